//! `bindery scene`: exports the FMU tailored to each scene file (`scenes.md`) into
//! `out/scenes/<modelIdentifier>.fmu`. The binary is the mechanism's own cdylib; the scene rides
//! in `resources/scene.toml`, and the binary reads it at `fmi2Instantiate`.

use bindery_fmu::catalog;
use bindery_fmu::package::Binaries;
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

/// A scene named on the command line: a file (against the current folder), or the name of a
/// scene in the checkout's `scenes/` (`geneva-cut-forces`); else an error listing those names.
pub fn resolve(arg: &Path, root: Option<&Path>) -> Result<PathBuf, String> {
    if arg.is_file() {
        return Ok(arg.to_path_buf());
    }
    let dir = root.map(|r| r.join("scenes"));
    let plain = arg.components().count() == 1 && arg.extension().is_none();
    if let Some(dir) = &dir {
        let named = dir.join(arg).with_extension("toml");
        if plain && named.is_file() {
            return Ok(named);
        }
    }
    let names: Vec<String> = dir
        .and_then(|d| scene_files(&d).ok())
        .unwrap_or_default()
        .iter()
        .filter_map(|f| f.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .collect();
    Err(format!(
        "{}: no such scene file{}",
        arg.display(),
        if names.is_empty() {
            String::new()
        } else {
            format!(
                ", and no scene of that name in scenes/; valid names: {}",
                names.join(", ")
            )
        }
    ))
}

/// The `.fmu` of one scene file (bytes) and its modelIdentifier; `binaries` gives a
/// mechanism's cdylib for every platform built, `date` the `generationDateAndTime`.
pub fn export(
    path: &Path,
    binaries: &dyn Fn(&str) -> Result<Binaries, String>,
    date: &str,
    fmi: bindery_fmu::package::Fmi,
) -> Result<(String, Vec<u8>), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    // the mechanism's cross-check inputs, for the reference results inside the FMU
    let scene =
        bindery_fmu::scene::Scene::parse(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let inputs_path = crate::place::root()?
        .join("fmus")
        .join(&scene.mechanism)
        .join(format!("{}_in.csv", scene.mechanism));
    let inputs = std::fs::read_to_string(&inputs_path)
        .map_err(|e| format!("{}: {e}", inputs_path.display()))?;
    catalog::scene_fmu_of(&text, binaries, date, fmi, Some(&inputs))
        .map_err(|e| format!("{}: {e}", path.display()))
}
