//! `bindery`: builds and packages the FMUs, and keeps `modelDescription/` current.
//!
//! - `bindery build`: compiles every FMU's cdylib for every platform whose toolchain is here
//!   (`platforms`; the others are named with the command that installs them) and writes
//!   `out/fmus/<id>.fmu`.
//! - `bindery describe`: writes `modelDescription/<id>.xml`; `--check` fails if one is stale.
//! - `bindery ssp`: the two machines as SSP 1.0 files of the built FMUs, `out/ssp/<machine>.ssp`.
//! - `bindery scene [FILE...]`: exports the FMU tailored to each scene (default: every
//!   `scenes/*.toml`) into `out/scenes/`.
//! - `bindery sweep FILE`: a design sweep, every run native, on every core or a Dask cluster.
//!
//! The checkout is the folder at or above the current one holding `Cargo.toml` and
//! `modelDescription/` (or `--root`); relative `--out` paths are relative to the current folder.
// The subcommands' doc comments are clap's help text, where `<id>` and `<machine>` are
// placeholders of a path, not HTML.
#![allow(rustdoc::invalid_html_tags)]

#[path = "bindery/anchors.rs"]
mod anchors;
#[path = "bindery/dask.rs"]
mod dask;
#[path = "bindery/liftoff.rs"]
mod liftoff;
#[path = "bindery/machines.rs"]
mod machines;
#[path = "bindery/needles.rs"]
mod needles;
#[path = "bindery/params.rs"]
mod params;
#[path = "bindery/place.rs"]
mod place;
#[path = "bindery/platforms.rs"]
mod platforms;
#[path = "bindery/progress.rs"]
mod progress;
#[path = "bindery/report.rs"]
mod report;
#[path = "bindery/scene.rs"]
mod scene;
#[path = "bindery/sweep.rs"]
mod sweep;
#[path = "bindery/timing.rs"]
mod timing;

use bindery_fmu::catalog::{self, Entry};
use bindery_fmu::package::{self, Binaries, Fmi, FmuContents};
use clap::{Parser, Subcommand};
use place::{folder, root};
use progress::Progress;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

#[derive(Parser)]
#[command(
    name = "bindery",
    about = "Bookbinding mechanisms as FMI 2.0 co-simulation FMUs"
)]
struct Cli {
    /// The checkout to work in (default: the folder at or above the current one that holds
    /// Cargo.toml and modelDescription/)
    #[arg(long, global = true)]
    root: Option<PathBuf>,
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Build every FMU (or those named) into out/fmus/, with binaries for every platform whose
    /// toolchain is installed (linux64, aarch64-linux, win64, darwin64); a platform skipped is
    /// named with the command that installs its toolchain
    Build {
        /// Only these modelIdentifiers
        models: Vec<String>,
        /// Output folder (default: out/fmus in the checkout)
        #[arg(long)]
        out: Option<PathBuf>,
        /// Fail instead of skipping a platform whose toolchain is missing
        #[arg(long)]
        require_all: bool,
    },
    /// Write each FMU's documentation/ folder (index.html and figures) unpacked, to read or to
    /// pick a figure from
    Docs {
        /// Output folder, one subfolder per FMU (default: out/docs in the checkout)
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// The lowest main-shaft speed at which the Perforators' spring lets the roller lift off
    /// the ramp (kinetostatic model, bisection on the speed), for the default parameters or
    /// those set
    #[command(
        after_help = "Values are in the parameter's display unit where it has one (rpm for \
        rad/s, deg for rad, mm for m, MPa for Pa), else in SI; a unit may follow the number \
        (--set synth.gamma0=0.1rad). Examples:\n  bindery liftoff --m0 8 --kt 25\n  \
        bindery liftoff --set perf.m=1.2 --set roller.r=12"
    )]
    Liftoff {
        /// Search from this speed, rpm
        #[arg(long, default_value_t = 100.0, allow_negative_numbers = true)]
        from: f64,
        /// Up to this speed, rpm
        #[arg(long, default_value_t = 2000.0, allow_negative_numbers = true)]
        to: f64,
        /// Spring moment spring.M0 in the lowest position, N.m (same as --set spring.M0=...)
        #[arg(long, allow_negative_numbers = true)]
        m0: Option<f64>,
        /// Spring rate spring.kt, N.m/rad (same as --set spring.kt=...)
        #[arg(long, allow_negative_numbers = true)]
        kt: Option<f64>,
        /// Any parameter of the Perforators FMU, NAME=VALUE (repeatable)
        #[arg(long = "set", value_name = "NAME=VALUE")]
        set: Vec<String>,
    },
    /// The legacy needle drive (LegacyNeedleDrive, paper 002) against the Perforators at equal
    /// needle motion over one shaft turn (kinetostatic): peak roller force, peak Hertz stress,
    /// shaft torque, and paper 002's beta study: out/needles/needles.md and PNG plots
    #[command(
        after_help = "A parameter the two FMUs share (cycle.*, law.*, travel.rise_fraction, \
        synth.unit, pierce.*, perf.m, guide.mu, joint.*) is set on both. Examples:\n  \
        bindery needles --rpm 120\n  bindery needles --set kmk.beta=1 --set cam.closure=spring"
    )]
    Needles {
        /// Shaft speed, rpm
        #[arg(long, default_value_t = 100.0)]
        rpm: f64,
        /// Any parameter of the LegacyNeedleDrive FMU, NAME=VALUE (repeatable)
        #[arg(long = "set", value_name = "NAME=VALUE")]
        set: Vec<String>,
        /// Output folder (default: out/needles in the checkout)
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Error against wall time of the elastodynamic level: every solver method over a ladder of
    /// tolerances and communication steps, against FMPy + CVode on Model Exchange (needs .venv
    /// and the built FMUs for that line): out/report/report.md and work-precision PNGs
    Report {
        /// Output folder (default: out/report in the checkout)
        #[arg(long)]
        out: Option<PathBuf>,
        /// Leave out the FMPy baseline
        #[arg(long)]
        no_fmpy: bool,
        /// Only these mechanisms (modelIdentifiers, comma-separated)
        #[arg(long, value_delimiter = ',')]
        only: Vec<String>,
    },
    /// The two machines (thread-sewing machine, three-knife trimmer) as SSP 1.0 files of the FMUs
    /// built into out/fmus/ (run `build` first): out/ssp/<machine>.ssp
    Ssp {
        /// Folder of the built FMUs (default: out/fmus in the checkout)
        #[arg(long)]
        fmus: Option<PathBuf>,
        /// Output folder (default: out/ssp in the checkout)
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// What a machine designer asks of the two machines: speed fluctuation, the flywheel for
    /// delta <= 1/40, motor torque, start-up time: out/machines/machines.md and PNG plots
    Machines {
        /// Output folder (default: out/machines in the checkout)
        #[arg(long)]
        out: Option<PathBuf>,
        #[command(flatten)]
        options: machines::Options,
    },
    /// Export the FMU tailored to each scene (scenes/README.md) into
    /// out/scenes/<modelIdentifier>.fmu
    Scene {
        /// Scene files (TOML) or names of scenes in scenes/ (e.g. geneva-cut-forces); none:
        /// every scenes/*.toml
        files: Vec<PathBuf>,
        /// Output folder (default: out/scenes in the checkout)
        #[arg(long)]
        out: Option<PathBuf>,
        /// Fail instead of skipping a platform whose toolchain is missing
        #[arg(long)]
        require_all: bool,
    },
    /// Run a design sweep (sweeps/README.md): every run native, on every core (or a Dask
    /// cluster), results as Parquet in a folder, plots of the metrics; resumes when interrupted
    Sweep(sweep::Options),
    /// Write modelDescription/<id>.xml for every FMU
    Describe {
        /// Do not write; fail if a committed file differs from the generated one
        #[arg(long)]
        check: bool,
    },
}

fn target_dir() -> Result<PathBuf, String> {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(dir) => Ok(place::absolute(Path::new(&dir))),
        None => Ok(root()?.join("target")),
    }
}

fn selected(models: &[String]) -> Result<Vec<Entry>, String> {
    let all = catalog::all();
    if let Some(bad) = models
        .iter()
        .find(|m| !all.iter().any(|e| e.identifier == m.as_str()))
    {
        let known: Vec<_> = all.iter().map(|e| e.identifier).collect();
        return Err(format!(
            "unknown model {bad:?}; valid: {}",
            known.join(", ")
        ));
    }
    Ok(all
        .into_iter()
        .filter(|e| models.is_empty() || models.iter().any(|m| m == e.identifier))
        .collect())
}

/// Compiles the FMU binaries of these entries natively (release, `target/release/`: the ones the
/// Rust tests load), then for every platform whose toolchain is here (`platforms`).
fn compile(entries: &[Entry], require_all: bool) -> Result<platforms::Built, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.current_dir(root()?)
        .args(["build", "--release", "--lib"]);
    for e in entries {
        cmd.args(["-p", e.package]);
    }
    eprintln!("compiling {} FMU binaries (release)...", entries.len());
    let status = cmd.status().map_err(|e| format!("cannot run cargo: {e}"))?;
    if !status.success() {
        return Err("cargo build of the FMU binaries failed".into());
    }
    let packages: Vec<&str> = entries.iter().map(|e| e.package).collect();
    platforms::build(&root()?, &target_dir()?, &packages, require_all)
}

fn build(models: &[String], out: &Option<PathBuf>, require_all: bool) -> Result<(), String> {
    let entries = selected(models)?;
    let out = folder(out, "out/fmus")?;
    let built = compile(&entries, require_all)?;
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let bar = Progress::new(entries.len() as u64, "{bar:30} {pos}/{len} {msg}")?;
    let (date, source) = place::generation_date()?;
    bar.line(format!("generationDateAndTime {date} ({source})"));
    for e in &entries {
        bar.doing(e.identifier);
        let binaries = built.binaries_of(e.identifier)?;
        let (documentation, icon) = (e.documentation)()?;
        let extra = reference_files(e)?;
        // the same binary in both: it exports the FMI 2.0 and the FMI 3.0 functions
        for (fmi, describe, dir, terminals) in [
            (Fmi::V2, e.describe, out.clone(), None),
            (
                Fmi::V3,
                e.describe3,
                out.join("fmi3"),
                Some((e.terminals3)()),
            ),
        ] {
            let fmu = FmuContents {
                identifier: e.identifier.into(),
                model_description: bindery_fmu::md::stamp(&describe().0, &date),
                binaries: binaries.clone(),
                documentation: documentation.clone(),
                icon: icon.clone(),
                resources: vec![],
                fmi,
                terminals,
                extra: extra.clone(),
            };
            std::fs::create_dir_all(&dir).map_err(|err| format!("{}: {err}", dir.display()))?;
            let path = dir.join(format!("{}.fmu", e.identifier));
            let zip = fmu.to_zip()?;
            std::fs::write(&path, &zip).map_err(|err| format!("{}: {err}", path.display()))?;
            bar.line(format!("wrote {} ({} bytes)", path.display(), zip.len()));
        }
        bar.inc();
    }
    bar.finish();
    if let Err(stale) = check_descriptions(&entries, true) {
        eprintln!(
            "warning: {stale}; run `cargo run --release -- describe` and commit modelDescription/"
        );
    }
    Ok(())
}

/// The reference results of an FMU (FMI-LS-REF, [`bindery_fmu::reference`]): its model run
/// over its cross-check experiment (`fmus/<Model>/<Model>_in.csv`, `_ref.opt`; the outputs of
/// `_ref.csv`), with the inputs and the manifest.
fn reference_files(e: &Entry) -> Result<Vec<(String, Vec<u8>)>, String> {
    let dir = root()?.join("fmus").join(e.identifier);
    let read = |ext: &str| {
        let p = dir.join(format!("{}{ext}", e.identifier));
        std::fs::read_to_string(&p).map_err(|err| format!("{}: {err}", p.display()))
    };
    let (input, opt, reference) = (read("_in.csv")?, read("_ref.opt")?, read("_ref.csv")?);
    let value = |key: &str| -> Result<f64, String> {
        (opt.lines())
            .find_map(|l| {
                l.strip_prefix(key)?
                    .trim_start_matches([',', ' '])
                    .parse()
                    .ok()
            })
            .ok_or_else(|| format!("{}_ref.opt: no {key}", e.identifier))
    };
    let (start, stop, step) = (value("StartTime")?, value("StopTime")?, value("StepSize")?);
    let outputs = bindery_fmu::reference::header(&reference)[1..].to_vec();
    let experiment = bindery_fmu::reference::Experiment {
        input_csv: &input,
        start,
        stop,
        step,
        outputs: &outputs,
        tailored: None,
    };
    let out = (e.reference)(&experiment).map_err(|err| format!("{}: {err}", e.identifier))?;
    Ok(bindery_fmu::reference::files(
        e.identifier,
        &experiment,
        out,
    ))
}

/// Exports every scene (all of `scenes/` when none is named): checks every file first, then
/// compiles the mechanisms' binaries and writes the FMUs.
fn scenes(files: &[PathBuf], out: &Option<PathBuf>, require_all: bool) -> Result<(), String> {
    let files = if files.is_empty() {
        scene::scene_files(&root()?.join("scenes"))?
    } else {
        files
            .iter()
            .map(|f| scene::resolve(f, root().ok().as_deref()))
            .collect::<Result<_, _>>()?
    };
    let mut mechanisms: Vec<String> = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).map_err(|e| format!("{}: {e}", f.display()))?;
        let s =
            bindery_fmu::scene::Scene::parse(&text).map_err(|e| format!("{}: {e}", f.display()))?;
        catalog::tailor(&s).map_err(|e| format!("{}: {e}", f.display()))?;
        if !mechanisms.contains(&s.mechanism) {
            mechanisms.push(s.mechanism);
        }
    }
    let out = folder(out, "out/scenes")?;
    let built = compile(&selected(&mechanisms)?, require_all)?;
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let (date, source) = place::generation_date()?;
    eprintln!("generationDateAndTime {date} ({source})");
    for f in &files {
        // FMI 2.0 in out/scenes/, FMI 3.0 in out/scenes/fmi3/: the same binary and scene
        for (fmi, dir) in [(Fmi::V2, out.clone()), (Fmi::V3, out.join("fmi3"))] {
            let (id, bytes) = scene::export(f, &|lib| built.binaries_of(lib), &date, fmi)?;
            std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            let path = dir.join(format!("{id}.fmu"));
            std::fs::write(&path, &bytes).map_err(|e| format!("{}: {e}", path.display()))?;
            eprintln!(
                "wrote {} ({} bytes, from {})",
                path.display(),
                bytes.len(),
                f.display()
            );
        }
    }
    Ok(())
}

fn docs(out: &Option<PathBuf>) -> Result<(), String> {
    let out = folder(out, "out/docs")?;
    for e in catalog::all() {
        let dir = out.join(e.identifier);
        std::fs::create_dir_all(&dir).map_err(|err| format!("{}: {err}", dir.display()))?;
        let (mut files, icon) = (e.documentation)()?;
        for (_, bytes) in files.iter_mut().filter(|(n, _)| n == "index.html") {
            let page = String::from_utf8_lossy(bytes)
                .replace(package::PLATFORMS_MARK, &package::platforms_all_html())
                .replace(package::VERSION_MARK, package::version_html(None));
            *bytes = page.into_bytes();
        }
        for (name, bytes) in files
            .iter()
            .chain(std::iter::once(&("model.png".to_string(), icon)))
        {
            std::fs::write(dir.join(name), bytes).map_err(|err| format!("{name}: {err}"))?;
        }
        eprintln!("wrote {} ({} files)", dir.display(), files.len() + 1);
    }
    Ok(())
}

/// Writes every machine's `.ssp`: the FMUs tailored to it, their binaries those of the built
/// FMUs in `fmus`.
fn ssp(fmus: &Option<PathBuf>, out: &Option<PathBuf>) -> Result<(), String> {
    let (fmus, out) = (folder(fmus, "out/fmus")?, folder(out, "out/ssp")?);
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let binaries = |id: &str| -> Result<Binaries, String> {
        let p = fmus.join(format!("{id}.fmu"));
        let bytes = std::fs::read(&p).map_err(|e| {
            format!(
                "{}: {e} (run `cargo run --release -- build` first)",
                p.display()
            )
        })?;
        package::binaries_in(&bytes, id).map_err(|e| format!("{}: {e}", p.display()))
    };
    // a mechanism's cross-check inputs, for the reference results inside each FMU
    let inputs = |id: &str| -> Result<String, String> {
        let p = place::root()?.join(format!("fmus/{id}/{id}_in.csv"));
        std::fs::read_to_string(&p).map_err(|e| format!("{}: {e}", p.display()))
    };
    let (date, _) = place::generation_date()?;
    for m in bindery_fmu::ssp::machines() {
        let bytes = bindery_fmu::ssp::package(&m, &binaries, &inputs, &date)?;
        let path = out.join(format!("{}.ssp", m.name));
        std::fs::write(&path, &bytes).map_err(|e| format!("{}: {e}", path.display()))?;
        eprintln!("wrote {} ({} bytes)", path.display(), bytes.len());
    }
    Ok(())
}

/// Compares (or writes) the committed descriptions.
fn check_descriptions(entries: &[Entry], check: bool) -> Result<(), String> {
    let mut stale = Vec::new();
    for e in entries {
        // FMI 2.0 in modelDescription/, FMI 3.0 in modelDescription/fmi3/
        for (dir, describe) in [("", e.describe), ("fmi3", e.describe3)] {
            let path = root()?
                .join("modelDescription")
                .join(dir)
                .join(format!("{}.xml", e.identifier));
            let (xml, _) = describe();
            if check {
                if std::fs::read_to_string(&path).ok().as_deref() != Some(xml.as_str()) {
                    stale.push(path.display().to_string());
                }
            } else {
                std::fs::create_dir_all(path.parent().unwrap()).map_err(|err| err.to_string())?;
                std::fs::write(&path, xml).map_err(|err| format!("{}: {err}", path.display()))?;
                eprintln!("wrote {}", path.display());
            }
        }
    }
    if stale.is_empty() {
        Ok(())
    } else {
        Err(format!("stale model description(s): {}", stale.join(", ")))
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    place::init(cli.root);
    let result = match cli.command {
        Cmd::Build {
            models,
            out,
            require_all,
        } => build(&models, &out, require_all),
        Cmd::Docs { out } => docs(&out),
        Cmd::Scene {
            files,
            out,
            require_all,
        } => scenes(&files, &out, require_all),
        Cmd::Describe { check } => check_descriptions(&catalog::all(), check),
        Cmd::Sweep(o) => sweep::sweep(&o),
        Cmd::Liftoff {
            from,
            to,
            m0,
            kt,
            set,
        } => liftoff::settings(m0, kt, &set).and_then(|s| liftoff::liftoff(from, to, &s)),
        Cmd::Needles { rpm, set, out } => needles::needles(rpm, &set, &out),
        Cmd::Report { out, no_fmpy, only } => report::report(&out, !no_fmpy, &only),
        Cmd::Ssp { fmus, out } => ssp(&fmus, &out),
        Cmd::Machines { out, options } => machines::machines(&out, &options),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
