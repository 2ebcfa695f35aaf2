//! `bindery scene`: exports the FMU tailored to each scene file (`scenes.md`) into
//! `out/scenes/<modelIdentifier>.fmu`. The binary is the mechanism's own cdylib; the scene rides
//! in `resources/scene.toml`, and the binary reads it at `fmi2Instantiate`.

use bindery_fmu::catalog;
use std::path::{Path, PathBuf};

/// Every `*.toml` in `dir`, sorted.
pub fn scene_files(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(format!("no *.toml scene in {}", dir.display()));
    }
    Ok(files)
}

/// The `.fmu` of one scene file (bytes) and its modelIdentifier; `binary` gives a
/// mechanism's cdylib.
pub fn export(
    path: &Path,
    binary: &dyn Fn(&str) -> Result<Vec<u8>, String>,
) -> Result<(String, Vec<u8>), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    catalog::scene_fmu(&text, binary).map_err(|e| format!("{}: {e}", path.display()))
}
