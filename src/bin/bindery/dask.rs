//! `bindery sweep --dask ADDRESS`: the runs as tasks on an existing Dask `distributed` cluster.
//!
//! Dask speaks Python, so a small driver (`dask_driver.py`, carried in this binary and written
//! to a temporary folder) connects to the scheduler with the Python found as `BINDERY_PYTHON`
//! (default `python3`, which must have `distributed`). Each task runs this same binary on a
//! worker in its worker mode (`bindery sweep FILE --rows RUNS`: the native runner, rows as exact
//! text), so the results equal the embedded run's bit for bit. The binary must be at the same
//! path on the workers (a shared or identical install), or at `BINDERY_WORKER_BINARY` there.
//! The rows come back through the driver's standard output and go to the same store as an
//! embedded run's, so an interrupted Dask sweep resumes like any other.

use bindery_fmu::sweep::{Plan, Row};
use std::collections::BTreeSet;
use std::io::BufRead;
use std::path::Path;
use std::process::{Command, Stdio};

const DRIVER: &str = include_str!("dask_driver.py");

/// `runs` as chunks of about `size` runs each, each written as ranges (`0-99,120`).
fn chunks(runs: &[usize], size: usize) -> Vec<String> {
    runs.chunks(size.max(1))
        .map(|c| {
            let mut parts: Vec<String> = Vec::new();
            let mut i = 0;
            while i < c.len() {
                let mut j = i;
                while j + 1 < c.len() && c[j + 1] == c[j] + 1 {
                    j += 1;
                }
                parts.push(if i == j {
                    c[i].to_string()
                } else {
                    format!("{}-{}", c[i], c[j])
                });
                i = j + 1;
            }
            parts.join(",")
        })
        .collect()
}

pub fn run(
    file: &Path,
    plan: &Plan,
    todo: &[usize],
    address: &str,
    chunk: Option<usize>,
    take: &mut dyn FnMut(Row) -> Result<(), String>,
) -> Result<(), String> {
    if todo.is_empty() {
        return Ok(());
    }
    let dir = std::env::temp_dir().join(format!("bindery-dask-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let write = |name: &str, text: &str| -> Result<String, String> {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))?;
        Ok(p.display().to_string())
    };
    let driver = write("dask_driver.py", DRIVER)?;
    let sweep = write("sweep.toml", &plan.text)?;
    let scene = match &plan.scene {
        Some(s) => write("scene.toml", s)?,
        None => "-".into(),
    };
    // about 64 tasks, at least 1 run each, unless --chunk says otherwise
    let size = chunk.unwrap_or_else(|| todo.len().div_ceil(64));
    let list = write("chunks.txt", &(chunks(todo, size).join("\n") + "\n"))?;
    let exe = std::env::current_exe().map_err(|e| format!("this binary's path: {e}"))?;
    let python = std::env::var("BINDERY_PYTHON").unwrap_or_else(|_| "python3".into());
    let mut child = Command::new(&python)
        .arg(&driver)
        .arg(address)
        .arg(&exe)
        .arg(&sweep)
        .arg(&scene)
        .arg(&list)
        .stdout(Stdio::piped())
        .spawn()
        .map_err(|e| {
            format!("{python}: {e} (set BINDERY_PYTHON to a Python with Dask's distributed)")
        })?;
    let wanted: BTreeSet<usize> = todo.iter().copied().collect();
    let mut seen = BTreeSet::new();
    let stdout = child.stdout.take().expect("piped");
    let mut result = Ok(());
    for line in std::io::BufReader::new(stdout).lines() {
        let line = line.map_err(|e| format!("the Dask driver's output: {e}"))?;
        let Some(row) = Row::from_line(&line) else {
            result = Err(format!(
                "{}: the Dask driver sent a line that is not a row: {line:?}",
                file.display()
            ));
            break;
        };
        if !wanted.contains(&row.run) || !seen.insert(row.run) {
            // a run not asked for, or a second time: not stored
            result = Err(format!(
                "the Dask driver sent run {} twice or unasked",
                row.run
            ));
            break;
        }
        if let Err(e) = take(row) {
            result = Err(e);
            break;
        }
    }
    if result.is_err() {
        let _ = child.kill();
    }
    let status = child.wait().map_err(|e| format!("the Dask driver: {e}"))?;
    let _ = std::fs::remove_dir_all(&dir);
    result?;
    if !status.success() {
        return Err(format!(
            "the Dask driver failed ({status}); its message is above"
        ));
    }
    if seen.len() != wanted.len() {
        return Err(format!(
            "the Dask cluster returned {} of {} runs",
            seen.len(),
            wanted.len()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn chunks_are_written_as_ranges() {
        assert_eq!(super::chunks(&[0, 1, 2, 5, 7, 8], 4), vec!["0-2,5", "7-8"]);
        assert_eq!(super::chunks(&[3], 10), vec!["3"]);
    }
}
