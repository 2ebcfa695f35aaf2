//! Where the CLI reads and writes: the checkout it runs in (found from the current folder, or
//! `--root`), never the folder it was compiled in; relative `--out` paths are relative to the
//! current folder, default outputs go under the checkout's `out/`.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

static ROOT: OnceLock<Result<PathBuf, String>> = OnceLock::new();

/// Is `dir` a bindery-fmu checkout (its `Cargo.toml` and `modelDescription/`)?
fn is_root(dir: &Path) -> bool {
    dir.join("Cargo.toml").is_file() && dir.join("modelDescription").is_dir()
}

/// Fixes the checkout: `--root` if given, else the nearest folder at or above the current one
/// that holds `Cargo.toml` and `modelDescription/`. Called once, before any command.
pub fn init(given: Option<PathBuf>) {
    let found = match given {
        Some(dir) => {
            let dir = absolute(&dir);
            if is_root(&dir) {
                Ok(dir)
            } else {
                Err(format!(
                    "--root {}: not a bindery-fmu checkout (no Cargo.toml and modelDescription/ there)",
                    dir.display()
                ))
            }
        }
        None => {
            let cwd = std::env::current_dir().unwrap_or_default();
            cwd.ancestors()
                .find(|d| is_root(d))
                .map(Path::to_path_buf)
                .ok_or_else(|| {
                    format!(
                        "{} is not inside a bindery-fmu checkout (no folder above it holds Cargo.toml and modelDescription/): run the command in the checkout or give --root",
                        cwd.display()
                    )
                })
        }
    };
    let _ = ROOT.set(found);
}

/// The checkout's root folder.
pub fn root() -> Result<PathBuf, String> {
    ROOT.get()
        .cloned()
        .unwrap_or_else(|| Err("the checkout was not looked for".into()))
}

/// `p` against the current folder.
pub fn absolute(p: &Path) -> PathBuf {
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        std::env::current_dir().unwrap_or_default().join(p)
    }
}

/// An output (or input) folder: as given, against the current folder; else `default` under the
/// checkout.
pub fn folder(given: &Option<PathBuf>, default: &str) -> Result<PathBuf, String> {
    match given {
        Some(p) => Ok(absolute(p)),
        None => Ok(root().map_err(|e| format!("{e}, or --out"))?.join(default)),
    }
}

/// `generationDateAndTime` of the FMUs built here, and where it comes from: `SOURCE_DATE_EPOCH`
/// (the reproducible-builds convention) if set, else the date of the checkout's commit
/// (`git log -1`), else [`bindery_fmu::md::VERSION_DATE`]. So a commit always builds the same
/// bytes.
pub fn generation_date() -> Result<(String, String), String> {
    use bindery_fmu::md::{VERSION_DATE, date_time};
    if let Some(s) = std::env::var_os("SOURCE_DATE_EPOCH") {
        let s = s.to_string_lossy().into_owned();
        let secs: i64 = s
            .trim()
            .parse()
            .map_err(|_| format!("SOURCE_DATE_EPOCH={s:?}: want seconds since 1970"))?;
        return Ok((date_time(secs), "SOURCE_DATE_EPOCH".into()));
    }
    let git = Command::new("git")
        .arg("-C")
        .arg(root()?)
        .args(["log", "-1", "--format=%ct %h"])
        .output();
    if let Ok(out) = git
        && out.status.success()
    {
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        if let Some((secs, hash)) = text.trim().split_once(' ')
            && let Ok(secs) = secs.parse::<i64>()
        {
            return Ok((date_time(secs), format!("the date of commit {hash}")));
        }
    }
    Ok((
        VERSION_DATE.to_string(),
        "no commit date at hand (no git, no SOURCE_DATE_EPOCH): the version's date".into(),
    ))
}
