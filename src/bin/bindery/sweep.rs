//! `bindery sweep FILE`: a design sweep (sweeps/README.md). Every run is native, in this process,
//! spread over threads (every core by default), its row written as it finishes; an interrupted
//! sweep resumes where it stopped. With `--dask ADDRESS` the runs go to a Dask cluster, whose
//! workers run this same binary (`--rows`), and the rows come back here to the same store.

use crate::progress::Progress;
use bindery_fmu::catalog;
use bindery_fmu::sweep::{Plan, Row, file, store::Store};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;

#[derive(clap::Args)]
pub struct Options {
    /// The sweep file (TOML; sweeps/README.md), or - for standard input
    pub file: PathBuf,
    /// Results folder (default: <file name without .toml>-results in the current folder)
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Threads (default: every core)
    #[arg(long)]
    pub threads: Option<usize>,
    /// Also write runs.csv
    #[arg(long)]
    pub csv: bool,
    /// Start over: delete the results of an earlier run in the folder
    #[arg(long)]
    pub fresh: bool,
    /// Run on the Dask cluster whose scheduler is at ADDRESS (e.g. tcp://10.0.0.5:8786)
    #[arg(long, value_name = "ADDRESS")]
    pub dask: Option<String>,
    /// Runs per Dask task (default: about 8 tasks per worker)
    #[arg(long, value_name = "N")]
    pub chunk: Option<usize>,
    /// Do not draw the plots
    #[arg(long)]
    pub no_plot: bool,
    /// Worker mode: compute these runs (e.g. 0-99,120) and print their rows on standard
    /// output; nothing is written
    #[arg(long, hide = true, value_name = "RUNS")]
    pub rows: Option<String>,
    /// The scene file, instead of the path the sweep file names (worker mode)
    #[arg(long, hide = true, value_name = "FILE")]
    pub scene_file: Option<PathBuf>,
}

/// The sweep file's plan: its model's runner, its scene read relative to the sweep file.
pub fn plan(file: &Path, scene_file: Option<&Path>) -> Result<Plan, String> {
    let text = if file == Path::new("-") {
        std::io::read_to_string(std::io::stdin()).map_err(|e| format!("standard input: {e}"))?
    } else {
        std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?
    };
    let shown = file.display();
    let (model, scene) = match file::target_of(&text).map_err(|e| format!("{shown}: {e}"))? {
        file::Target::Machine(name) => {
            let all = bindery_fmu::ssp::machines();
            let names: Vec<&str> = all.iter().map(|m| m.name).collect();
            let Some(m) = all.into_iter().find(|m| m.name == name) else {
                return Err(format!(
                    "{shown}: `machine`: unknown machine {name:?}; {}",
                    bindery_fmu::scene::nearest(&name, &names)
                ));
            };
            return bindery_fmu::machines::sweep::parse(&text, m)
                .map_err(|e| format!("{shown}: {e}"));
        }
        file::Target::Model(m) => (Some(m), None),
        file::Target::Scene(s) => (None, Some(s)),
    };
    let scene_text = match (scene, scene_file) {
        (Some(_), Some(f)) => {
            Some(std::fs::read_to_string(f).map_err(|e| format!("{}: {e}", f.display()))?)
        }
        (Some(s), None) => {
            let p = file.parent().unwrap_or(Path::new(".")).join(&s);
            Some(
                std::fs::read_to_string(&p)
                    .map_err(|e| format!("{shown}: scene {s:?}: {}: {e}", p.display()))?,
            )
        }
        (None, _) => None,
    };
    let model = match (&model, &scene_text) {
        (Some(m), _) => m.clone(),
        (None, Some(t)) => {
            bindery_fmu::scene::Scene::parse(t)
                .map_err(|e| format!("{shown}: the scene: {e}"))?
                .mechanism
        }
        (None, None) => unreachable!("target_of names one"),
    };
    let all = catalog::all();
    let Some(entry) = all.iter().find(|e| e.identifier == model) else {
        let known: Vec<&str> = all.iter().map(|e| e.identifier).collect();
        return Err(format!(
            "{shown}: `model`: unknown model {model:?}; {}",
            bindery_fmu::scene::nearest(&model, &known)
        ));
    };
    (entry.sweep)(&text, scene_text.as_deref()).map_err(|e| format!("{shown}: {e}"))
}

/// `0-99,120`: the runs, each below `runs`.
fn parse_runs(text: &str, runs: usize) -> Result<Vec<usize>, String> {
    let mut out = Vec::new();
    for part in text.split(',').filter(|p| !p.is_empty()) {
        let (a, b) = part.split_once('-').unwrap_or((part, part));
        let (a, b): (usize, usize) = (
            a.trim()
                .parse()
                .map_err(|_| format!("--rows {text:?}: {a:?} is not a run"))?,
            b.trim()
                .parse()
                .map_err(|_| format!("--rows {text:?}: {b:?} is not a run"))?,
        );
        if a > b || b >= runs {
            return Err(format!(
                "--rows {text:?}: the sweep has runs 0 to {}",
                runs - 1
            ));
        }
        out.extend(a..=b);
    }
    Ok(out)
}

/// Rows a worker thread hands over at once (fewer hand-overs for runs of microseconds).
const BATCH: usize = 64;

/// Runs `todo` of `plan` on `threads` threads, handing each row to `done` on this thread as it
/// finishes (in batches of up to [`BATCH`] rows, or what a thread has after 50 ms).
pub fn run_threads(
    plan: &Plan,
    todo: &[usize],
    threads: usize,
    mut done: impl FnMut(Row) -> Result<(), String>,
) -> Result<(), String> {
    let next = AtomicUsize::new(0);
    let (tx, rx) = mpsc::channel::<Vec<Row>>();
    std::thread::scope(|s| {
        for _ in 0..threads.max(1).min(todo.len().max(1)) {
            let tx = tx.clone();
            let next = &next;
            s.spawn(move || {
                let mut batch = Vec::with_capacity(BATCH);
                let mut since = std::time::Instant::now();
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&k) = todo.get(i) else { break };
                    batch.push(plan.run(k));
                    if batch.len() >= BATCH || since.elapsed().as_millis() >= 50 {
                        if tx.send(std::mem::take(&mut batch)).is_err() {
                            return;
                        }
                        since = std::time::Instant::now();
                    }
                }
                let _ = tx.send(batch);
            });
        }
        drop(tx);
        for row in rx.into_iter().flatten() {
            if let Err(e) = done(row) {
                // stop the workers: they find no more runs
                next.store(todo.len(), Ordering::Relaxed);
                return Err(e);
            }
        }
        Ok(())
    })
}

pub fn sweep(o: &Options) -> Result<(), String> {
    let plan = plan(&o.file, o.scene_file.as_deref())?;
    if let Some(rows) = &o.rows {
        // worker mode
        let todo = parse_runs(rows, plan.runs())?;
        let threads = o.threads.unwrap_or(1);
        let mut out = std::io::stdout().lock();
        return run_threads(&plan, &todo, threads, |r| {
            use std::io::Write;
            writeln!(out, "{}", r.to_line()).map_err(|e| format!("standard output: {e}"))
        });
    }
    let out = match &o.out {
        Some(d) => d.clone(),
        None => {
            let stem = o
                .file
                .file_stem()
                .and_then(|s| s.to_str())
                .filter(|s| *s != "-")
                .unwrap_or("sweep");
            PathBuf::from(format!("{stem}-results"))
        }
    };
    let (mut store, done) = Store::open(&out, &plan, o.fresh, o.csv)?;
    let todo: Vec<usize> = (0..plan.runs()).filter(|k| !done.contains(k)).collect();
    let threads = o
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    eprintln!(
        "{}: {} runs of {}{}; {} to do, {}",
        o.file.display(),
        plan.runs(),
        plan.model,
        plan.fidelity.map_or(String::new(), |f| format!(
            " ({})",
            bindery_fmu::scene::fidelity_name(f)
        )),
        todo.len(),
        match &o.dask {
            Some(a) => format!("on the Dask cluster at {a}"),
            None => format!("on {threads} thread{}", if threads == 1 { "" } else { "s" }),
        }
    );
    let bar = Progress::new(
        todo.len() as u64,
        "{bar:40} {pos}/{len} runs, {per_sec}, {elapsed} elapsed, ETA {eta} {msg}",
    )?;
    // without a terminal (a log, CI) no bar is drawn: a line every 10 s says how far it is
    let quiet_bar = !std::io::IsTerminal::is_terminal(&std::io::stderr());
    let started = std::time::Instant::now();
    let mut said = started;
    let total = todo.len();
    let mut done = 0usize;
    let mut take = |r: Row| -> Result<(), String> {
        store.push(r)?;
        bar.inc();
        done += 1;
        if quiet_bar && said.elapsed().as_secs() >= 10 {
            said = std::time::Instant::now();
            let rate = done as f64 / started.elapsed().as_secs_f64();
            eprintln!(
                "{done}/{total} runs, {rate:.1} runs/s, about {:.0} s to go",
                (total - done) as f64 / rate
            );
        }
        Ok(())
    };
    let result = match &o.dask {
        None => run_threads(&plan, &todo, threads, &mut take),
        Some(address) => crate::dask::run(&o.file, &plan, &todo, address, o.chunk, &mut take),
    };
    let flushed = store.flush();
    bar.finish();
    result?;
    flushed?;
    let rows = bindery_fmu::sweep::store::read(&out)?;
    eprintln!(
        "{} runs in {} ({} without metrics: their `error` says why)",
        rows.len(),
        out.display(),
        rows.iter().filter(|r| !r.error.is_empty()).count()
    );
    if !o.no_plot {
        for (file, bytes) in bindery_fmu::sweep::plot::figures(&plan, &rows)? {
            let p = out.join(&file);
            std::fs::write(&p, bytes).map_err(|e| format!("{}: {e}", p.display()))?;
            eprintln!("wrote {}", p.display());
        }
    }
    Ok(())
}
