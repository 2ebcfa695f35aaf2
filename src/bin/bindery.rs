//! `bindery`: builds and packages the FMUs, and keeps `modelDescription/` current.
//!
//! - `bindery build`: compiles every FMU's cdylib (release) and writes `out/fmus/<id>.fmu`.
//! - `bindery describe`: writes `modelDescription/<id>.xml`; `--check` fails if one is stale.
//! - `bindery ssp`: the two machines as SSP 1.0 files of the built FMUs, `out/ssp/<machine>.ssp`.
//! - `bindery scene [FILE...]`: exports the FMU tailored to each scene (default: every
//!   `scenes/*.toml`) into `out/scenes/`.

#[path = "bindery/machines.rs"]
mod machines;
#[path = "bindery/report.rs"]
mod report;
#[path = "bindery/scene.rs"]
mod scene;

use bindery_fmu::catalog::{self, Entry};
use bindery_fmu::package::FmuContents;
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

#[derive(Parser)]
#[command(
    name = "bindery",
    about = "Bookbinding mechanisms as FMI 2.0 co-simulation FMUs"
)]
struct Cli {
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Build every FMU (or those named) into out/fmus/
    Build {
        /// Only these modelIdentifiers
        models: Vec<String>,
        /// Output folder
        #[arg(long, default_value = "out/fmus")]
        out: PathBuf,
    },
    /// Write each FMU's documentation/ folder (index.html and figures) unpacked, to read or to
    /// pick a figure from
    Docs {
        /// Output folder; one subfolder per FMU
        #[arg(long, default_value = "out/docs")]
        out: PathBuf,
    },
    /// The lowest main-shaft speed at which the Perforators' spring lets the roller lift off
    /// the ramp (default parameters, bisection on the speed with the Rust model)
    Liftoff {
        /// Search from this speed, rpm (no lift-off there)
        #[arg(long, default_value_t = 100.0)]
        from: f64,
        /// Up to this speed, rpm
        #[arg(long, default_value_t = 2000.0)]
        to: f64,
        /// Spring moment spring.M0 in the lowest position, N.m
        #[arg(long, default_value_t = 6.0)]
        m0: f64,
        /// Spring rate spring.kt, N.m/rad
        #[arg(long, default_value_t = 20.0)]
        kt: f64,
    },
    /// Error against wall time of the elastodynamic level: every solver method over a ladder of
    /// tolerances and communication steps, against FMPy + CVode on Model Exchange (needs .venv
    /// and the built FMUs for that line): out/report/report.md and work-precision PNGs
    Report {
        /// Output folder
        #[arg(long, default_value = "out/report")]
        out: PathBuf,
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
        /// Folder of the built FMUs
        #[arg(long, default_value = "out/fmus")]
        fmus: PathBuf,
        /// Output folder
        #[arg(long, default_value = "out/ssp")]
        out: PathBuf,
    },
    /// What a machine designer asks of the two machines: speed fluctuation, the flywheel for
    /// delta <= 1/40, motor torque, start-up time: out/machines/machines.md and PNG plots
    Machines {
        /// Output folder
        #[arg(long, default_value = "out/machines")]
        out: PathBuf,
    },
    /// Export the FMU tailored to each scene file (scenes.md) into out/scenes/<modelIdentifier>.fmu
    Scene {
        /// Scene files (TOML); none: every scenes/*.toml
        files: Vec<PathBuf>,
        /// Output folder
        #[arg(long, default_value = "out/scenes")]
        out: PathBuf,
    },
    /// Write modelDescription/<id>.xml for every FMU
    Describe {
        /// Do not write; fail if a committed file differs from the generated one
        #[arg(long)]
        check: bool,
    },
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("target"))
}

fn selected(models: &[String]) -> Result<Vec<Entry>, String> {
    let all = catalog::all();
    if let Some(bad) = models
        .iter()
        .find(|m| !all.iter().any(|e| e.identifier == m.as_str()))
    {
        let known: Vec<_> = all.iter().map(|e| e.identifier).collect();
        return Err(format!(
            "unknown model {bad:?}; known: {}",
            known.join(", ")
        ));
    }
    Ok(all
        .into_iter()
        .filter(|e| models.is_empty() || models.iter().any(|m| m == e.identifier))
        .collect())
}

/// Compiles the FMU binaries of these entries (release).
fn compile(entries: &[Entry]) -> Result<(), String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.current_dir(root())
        .args(["build", "--release", "--lib"]);
    for e in entries {
        cmd.args(["-p", e.package]);
    }
    eprintln!("compiling {} FMU binaries (release)...", entries.len());
    let status = cmd.status().map_err(|e| format!("cannot run cargo: {e}"))?;
    if !status.success() {
        return Err("cargo build of the FMU binaries failed".into());
    }
    Ok(())
}

/// The built binary of a modelIdentifier.
fn binary_of(identifier: &str) -> Result<Vec<u8>, String> {
    let so = target_dir()
        .join("release")
        .join(format!("lib{identifier}.so"));
    std::fs::read(&so).map_err(|err| format!("{}: {err}", so.display()))
}

fn build(models: &[String], out: &Path) -> Result<(), String> {
    let entries = selected(models)?;
    compile(&entries)?;
    let out = if out.is_absolute() {
        out.to_path_buf()
    } else {
        root().join(out)
    };
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let bar = ProgressBar::new(entries.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}").map_err(|e| e.to_string())?,
    );
    for e in &entries {
        bar.set_message(e.identifier);
        let binary = binary_of(e.identifier)?;
        let (model_description, _guid) = (e.describe)();
        let (documentation, icon) = (e.documentation)()?;
        let fmu = FmuContents {
            identifier: e.identifier.into(),
            model_description,
            binary,
            documentation,
            icon,
            resources: vec![],
        };
        let path = out.join(format!("{}.fmu", e.identifier));
        std::fs::write(&path, fmu.to_zip()?).map_err(|err| format!("{}: {err}", path.display()))?;
        bar.inc(1);
        bar.println(format!("wrote {}", path.display()));
    }
    bar.finish_and_clear();
    if let Err(stale) = check_descriptions(&entries, true) {
        eprintln!(
            "warning: {stale}; run `cargo run --release -- describe` and commit modelDescription/"
        );
    }
    Ok(())
}

/// Exports every scene (all of `scenes/` when none is named): checks every file first, then
/// compiles the mechanisms' binaries and writes the FMUs.
fn scenes(files: &[PathBuf], out: &Path) -> Result<(), String> {
    let files = if files.is_empty() {
        scene::scene_files(&root().join("scenes"))?
    } else {
        files.to_vec()
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
    compile(&selected(&mechanisms)?)?;
    let out = if out.is_absolute() {
        out.to_path_buf()
    } else {
        root().join(out)
    };
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    for f in &files {
        let (id, bytes) = scene::export(f, &binary_of)?;
        let path = out.join(format!("{id}.fmu"));
        std::fs::write(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
        eprintln!("wrote {} ({})", path.display(), f.display());
    }
    Ok(())
}

fn docs(out: &Path) -> Result<(), String> {
    let out = if out.is_absolute() {
        out.to_path_buf()
    } else {
        root().join(out)
    };
    for e in catalog::all() {
        let dir = out.join(e.identifier);
        std::fs::create_dir_all(&dir).map_err(|err| format!("{}: {err}", dir.display()))?;
        let (files, icon) = (e.documentation)()?;
        for (name, bytes) in files
            .iter()
            .chain(std::iter::once(&("model.png".to_string(), icon)))
        {
            std::fs::write(dir.join(name), bytes).map_err(|err| format!("{name}: {err}"))?;
        }
        eprintln!("wrote {}", dir.display());
    }
    Ok(())
}

fn absolute(p: &Path) -> PathBuf {
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        root().join(p)
    }
}

/// Writes every machine's `.ssp`: the FMUs tailored to it, their binaries those of the built
/// FMUs in `fmus`.
fn ssp(fmus: &Path, out: &Path) -> Result<(), String> {
    let (fmus, out) = (absolute(fmus), absolute(out));
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let binary = |id: &str| -> Result<Vec<u8>, String> {
        let p = fmus.join(format!("{id}.fmu"));
        let bytes = std::fs::read(&p).map_err(|e| {
            format!(
                "{}: {e} (run `cargo run --release -- build` first)",
                p.display()
            )
        })?;
        let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes))
            .map_err(|e| format!("{}: {e}", p.display()))?;
        let mut so = zip
            .by_name(&format!("binaries/linux64/{id}.so"))
            .map_err(|e| format!("{}: binaries/linux64/{id}.so: {e}", p.display()))?;
        let mut b = Vec::new();
        std::io::Read::read_to_end(&mut so, &mut b).map_err(|e| format!("{}: {e}", p.display()))?;
        Ok(b)
    };
    for m in bindery_fmu::ssp::machines() {
        let bytes = bindery_fmu::ssp::package(&m, &binary)?;
        let path = out.join(format!("{}.ssp", m.name));
        std::fs::write(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// Compares (or writes) the committed descriptions.
fn check_descriptions(entries: &[Entry], check: bool) -> Result<(), String> {
    let mut stale = Vec::new();
    for e in entries {
        let path = root()
            .join("modelDescription")
            .join(format!("{}.xml", e.identifier));
        let (xml, _) = (e.describe)();
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
    if stale.is_empty() {
        Ok(())
    } else {
        Err(format!("stale model description(s): {}", stale.join(", ")))
    }
}

/// Samples per shaft turn of the lift-off search.
const LIFTOFF_SAMPLES: usize = 7200;

fn liftoff(from: f64, to: f64, m0: f64, kt: f64) -> Result<(), String> {
    use bindery_fmu::mechanisms::perforators::physics::Params;
    let rad = std::f64::consts::PI / 30.0;
    let p = Params {
        spring_m0: m0,
        spring_kt: kt,
        ..Params::default()
    };
    let d = p.drive().map_err(|e| e.to_string())?;
    match d.liftoff_speed(from * rad, to * rad, 1e-6, LIFTOFF_SAMPLES) {
        Some(w) => {
            let (f, phi) = d.min_contact_force(w, LIFTOFF_SAMPLES);
            let (f_below, _) = d.min_contact_force(w - 1e-4, LIFTOFF_SAMPLES);
            println!(
                "spring.M0 = {m0} N.m, spring.kt = {kt} N.m/rad: the roller lifts off the ramp above {:.2} rpm \
                 (first at shaft angle {:.2} deg, phase {:?}; smallest contact force {f:.4} N there, {f_below:.4} N just below)",
                w / rad,
                phi.to_degrees(),
                d.cyc.at(phi).phase
            );
            Ok(())
        }
        None => Err(format!(
            "no lift-off threshold between {from} and {to} rpm (it lifts off already at {from}, or not even at {to})"
        )),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Cmd::Build { models, out } => build(&models, &out),
        Cmd::Docs { out } => docs(&out),
        Cmd::Scene { files, out } => scenes(&files, &out),
        Cmd::Describe { check } => check_descriptions(&catalog::all(), check),
        Cmd::Liftoff { from, to, m0, kt } => liftoff(from, to, m0, kt),
        Cmd::Report { out, no_fmpy, only } => report::report(&root(), &out, !no_fmpy, &only),
        Cmd::Ssp { fmus, out } => ssp(&fmus, &out),
        Cmd::Machines { out } => machines::machines(&absolute(&out)),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
