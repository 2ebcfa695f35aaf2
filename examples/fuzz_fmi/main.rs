//! Call-sequence fuzzer for the FMU binaries, through the C ABI (issue 7).
//!
//! A seeded random host: it loads every FMU of the catalog with libloading, keeps a few live
//! instances, and makes random FMI 2.0 calls with random and hostile arguments (NULL arrays,
//! unknown value references, wrong types, NaN/Inf/huge values, invalid enum integers, mutated
//! serialized states, FMU states of other instances, calls out of the state machine), Co-Simulation
//! and, for the FMUs that provide it, Model Exchange instances (every ME function, wrong nx/nz,
//! NULL result pointers), and `fmi2SetRealInputDerivatives`. It never passes dangling pointers:
//! that is undefined behaviour of the host, not a bug of the FMU.
//!
//! A third of the instances of an FMU with an elastodynamic level start at that level. The
//! values that set the work of one elastodynamic step are held to a budget ([`BUDGET`],
//! [`ELASTIC_H`]): accepted values are drawn from safe ranges, refused ones are still sent. A run
//! of 1e7 calls then takes ~10 min of one core (about 60 µs per call).
//!
//! After every call it checks:
//! * the status is an `fmi2Status` (0..=4);
//! * a call the state machine forbids (the shadow state, `fmi2::state::allowed`, or
//!   `me_allowed` for a Model Exchange instance) is `fmi2Error`;
//! * every `fmi2Error` of a live instance comes with an error log line;
//! * no log line reports a panic caught at the FMI boundary (a caught panic is still a bug);
//! * `fmi2Instantiate` succeeds exactly for valid arguments.
//!
//! A crash, a sanitizer report or any finding fails the run (exit status 1).
//!
//! ```sh
//! cargo run --release --example fuzz_fmi -- --execs 200000 --seed 1
//! # the coverage-guided targets' seed corpora (fuzz/corpus: FUZZING.md), and their replay
//! cargo run --release --example fuzz_fmi -- --record fuzz/corpus --seed 1 --execs 3
//! cargo run --release --example fuzz_fmi -- --replay fuzz/corpus
//! # under AddressSanitizer (FMU binaries built with it, gcc's runtime preloaded; on a stable
//! # toolchain RUSTC_BOOTSTRAP=1 admits the -Z option):
//! RUSTC_BOOTSTRAP=1 RUSTFLAGS=-Zsanitizer=address cargo build --release --target x86_64-unknown-linux-gnu \
//!     --target-dir target/asan -p geneva-knife-drive-fmu ...
//! LD_PRELOAD=$(gcc -print-file-name=libasan.so) target/release/examples/fuzz_fmi \
//!     --lib-dir target/asan/x86_64-unknown-linux-gnu/release --execs 10000000
//! # the leak check: a million instantiate/free cycles, then LeakSanitizer at exit (after the
//! # binaries are unloaded: what they kept for their lifetime is freed by then, see
//! # bindery_fmu::lifetime)
//! LD_PRELOAD=$(gcc -print-file-name=libasan.so) target/release/examples/fuzz_fmi \
//!     --lib-dir target/asan/x86_64-unknown-linux-gnu/release --cycles 1000000
//! ```
#![allow(clippy::type_complexity)]

#[path = "../../tests/common/c_logger.rs"]
mod c_logger;
mod host;

use bindery_fmu::catalog;
use host::*;
use std::path::PathBuf;

fn main() {
    let mut execs: u64 = 100_000;
    let mut seed: u64 = 1;
    let mut cycles: u64 = 0;
    let mut seconds = f64::INFINITY;
    let mut only: Option<String> = None;
    let mut dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/release");
    let mut record: Option<PathBuf> = None;
    let mut replay: Option<PathBuf> = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut val = || args.next().unwrap_or_else(|| panic!("{a} needs a value"));
        match a.as_str() {
            "--execs" => execs = val().replace('_', "").parse::<f64>().expect("--execs N") as u64,
            "--seed" => seed = val().parse().expect("--seed N"),
            "--lib-dir" => dir = PathBuf::from(val()),
            "--only" => only = Some(val()),
            "--seconds" => seconds = val().parse().expect("--seconds S"),
            "--cycles" => {
                cycles = val().replace('_', "").parse::<f64>().expect("--cycles N") as u64
            }
            "--record" => record = Some(PathBuf::from(val())),
            "--replay" => replay = Some(PathBuf::from(val())),
            _ => panic!(
                "usage: fuzz_fmi [--execs N] [--seed N] [--lib-dir DIR] [--only ID,ID] [--seconds S] [--cycles N] [--record DIR] [--replay DIR]"
            ),
        }
    }
    if let Some(corpus) = record {
        record_corpus(&dir, &corpus, only.as_deref(), seed, execs);
        return;
    }
    if let Some(corpus) = replay {
        replay_corpus(&dir, &corpus);
        return;
    }
    let apis: Vec<Api> = catalog::all()
        .iter()
        .filter(|e| {
            only.as_deref()
                .is_none_or(|o| o.split(',').any(|id| id == e.identifier))
        })
        .map(|e| Api::load(&dir, e))
        .collect();
    assert!(!apis.is_empty(), "--only names no FMU of the catalog");
    let mut f = Fuzzer {
        apis,
        rng: Rng::seeded(seed),
        live: Vec::new(),
        report: Report::default(),
        max_live: 6,
    };
    let t0 = std::time::Instant::now();
    if cycles > 0 {
        run_cycles(&f.apis, cycles);
        println!(
            "fuzz_fmi: {cycles} instantiate/initialize/get FMU state/free cycles in {:.1} s",
            t0.elapsed().as_secs_f64()
        );
        return;
    }
    // stops after --execs calls or --seconds of wall time, whichever comes first (a step of an
    // elastodynamic level with random solver parameters may take its whole step budget)
    while f.report.execs < execs
        && (!f.report.execs.is_multiple_of(256) || t0.elapsed().as_secs_f64() < seconds)
    {
        f.step();
    }
    f.free_all();
    let r = &f.report;
    let lines = TALLY.with(|t| t.borrow().lines);
    let secs = t0.elapsed().as_secs_f64();
    println!(
        "fuzz_fmi: {} FMI calls on {} FMUs from {} (seed {seed}) in {secs:.1} s ({:.0} calls/s; \
         slowest {:.3} s, {}; {} elastodynamic steps in {:.1} s): {} instances, \
         statuses ok/warning/discard/error/fatal = {:?}, {lines} log lines, {} findings",
        r.execs,
        f.apis.len(),
        dir.display(),
        r.execs as f64 / secs,
        r.slowest.0,
        r.slowest.1,
        r.elastic_steps.0,
        r.elastic_steps.1,
        r.instantiated,
        &r.statuses[..5],
        r.findings.len()
    );
    if !r.findings.is_empty() {
        std::process::exit(1);
    }
}

/// `--record DIR`: for each FMU (of `--only`), the inputs of the coverage-guided targets that
/// replay the seeded generator's calls, seeds `seed..seed + n` (`--execs` is `n` here), as
/// `DIR/<modelIdentifier>/seed-<k>`: the targets' seed corpora.
fn record_corpus(
    dir: &std::path::Path,
    corpus: &std::path::Path,
    only: Option<&str>,
    seed: u64,
    n: u64,
) {
    for e in catalog::all()
        .iter()
        .filter(|e| only.is_none_or(|o| o.split(',').any(|id| id == e.identifier)))
    {
        let out = corpus.join(e.identifier);
        std::fs::create_dir_all(&out).unwrap();
        for k in seed..seed + n {
            let bytes = record_input(Api::load(dir, e), k);
            std::fs::write(out.join(format!("seed-{k}")), &bytes).unwrap();
        }
        println!(
            "fuzz_fmi: {n} seed inputs of {} in {}",
            e.identifier,
            out.display()
        );
    }
}

/// `--replay DIR`: every input in `DIR/<modelIdentifier>/` (a target's corpus, or a crash it
/// saved) run as the coverage-guided target runs it, against the FMU binaries; a finding fails.
fn replay_corpus(dir: &std::path::Path, corpus: &std::path::Path) {
    let (mut inputs, mut findings) = (0, 0);
    for e in catalog::all() {
        let Ok(files) = std::fs::read_dir(corpus.join(e.identifier)) else {
            continue;
        };
        for f in files {
            let path = f.unwrap().path();
            let data = std::fs::read(&path).unwrap();
            let report = run_input(Api::load(dir, &e), &data);
            for x in &report.findings {
                eprintln!("{}: {x}", path.display());
            }
            findings += report.findings.len();
            inputs += 1;
        }
    }
    println!(
        "fuzz_fmi: {inputs} corpus inputs from {} replayed, {findings} findings",
        corpus.display()
    );
    assert!(inputs > 0, "no inputs in {}", corpus.display());
    if findings > 0 {
        std::process::exit(1);
    }
}
