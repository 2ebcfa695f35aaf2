//! `bindery report`: error against wall time of the elastodynamic level (`dynamics.md`, "Error
//! against run time"). For every mechanism in [`CASES`], at a non-stiff and a stiff chain, every
//! internal method over a ladder of tolerances (rk4: of steps), `auto` also over a ladder of
//! communication steps, all in this process (the median of repeated runs, every run of a case
//! timed in rounds with the others: [`crate::timing::timed_in_rounds`]) on the plain Rust
//! models, against a Dormand–Prince reference at rtol 1e-11; and the baseline, FMPy + CVode on
//! the Model Exchange interface of the built FMU, with the FMU's own `auto` through the same
//! FMPy loop for a like-for-like ratio, measured in the same run by `scripts/work_precision.py`.
//! Writes `report.md` and one work-precision plot per case (log10 axes), as PNG and SVG.

use crate::place::{folder, root};
use crate::progress::Progress;
use bindery_fmu::docs::{Figure, Series, render_png, render_svg};
use bindery_fmu::mechanisms::disc_knife_drive::DiscKnifeDrive;
use bindery_fmu::mechanisms::geneva_knife_drive::GenevaKnifeDrive;
use bindery_fmu::mechanisms::perforators::Perforators;
use bindery_fmu::mechanisms::sewing_table::SewingTable;
use bindery_fmu::model::{Model, NoLog, Values, VarSet};
use std::fmt::Write as _;
use std::io::BufRead;
use std::path::{Path, PathBuf};

/// One mechanism at one chain stiffness, described by its variables' names, so a mechanism
/// joins the report with one entry here and one arm in [`simulate`].
#[derive(Clone, Copy)]
pub(crate) struct Case {
    /// modelIdentifier.
    pub(crate) mech: &'static str,
    pub(crate) label: &'static str,
    /// The stiffness parameter and its value, N/m.
    k_name: &'static str,
    pub(crate) k: f64,
    /// The main outputs: a position (m) and the dynamic force (N).
    x: &'static str,
    f: &'static str,
    /// Shaft speed, rpm; simulated time, s.
    rpm: f64,
    pub(crate) stop: f64,
    /// Other parameters of the case (name, value).
    extra: &'static [(&'static str, f64)],
}

/// A chain with the stiffness `elastic.k = k`, its position output `x`, at `rpm` for `stop` s.
const fn case(
    mech: &'static str,
    x: &'static str,
    rpm: f64,
    stop: f64,
    label: &'static str,
    k: f64,
) -> Case {
    Case {
        mech,
        label,
        k_name: "elastic.k",
        k,
        x,
        f: "elastic.F",
        rpm,
        stop,
        extra: &[],
    }
}

/// Perforators' ramp contact with the linear law, so its stiffness is one number,
/// `contact.k = k`.
const fn contact(label: &'static str, k: f64) -> Case {
    Case {
        k_name: "contact.k",
        extra: &[("contact.law", 2.0)],
        ..case("Perforators", "lever.gamma", 100.0, 0.3, label, k)
    }
}

#[rustfmt::skip]
const CASES: [Case; 8] = [
    case("GenevaKnifeDrive", "knife.s", 30.0, 0.5, "non-stiff (k = 5e7 N/m)", 5e7),
    case("GenevaKnifeDrive", "knife.s", 30.0, 0.5, "stiff (k = 1e12 N/m)", 1e12),
    case("SewingTable", "table.x", 100.0, 0.6, "non-stiff (k = 1e7 N/m)", 1e7),
    case("SewingTable", "table.x", 100.0, 0.6, "stiff (k = 1e12 N/m)", 1e12),
    contact("non-stiff (linear contact, k = 1e8 N/m)", 1e8),
    // (at 1e12 N/m neither dopri5 nor radau5 reaches rtol 1e-11 for a reference within the
    // step budget: the contact rings, opening and closing, every few microseconds)
    contact("stiff (linear contact, k = 1e10 N/m)", 1e10),
    case("DiscKnifeDrive", "slider.x", 300.0, 0.2, "non-stiff (rod k = 2e8 N/m)", 2e8),
    case("DiscKnifeDrive", "slider.x", 300.0, 0.2, "stiff (rod k = 1e12 N/m)", 1e12),
];

/// One run: the position and chain force on the 1 ms output grid.
type Trace = (Vec<f64>, Vec<f64>);

fn simulate(c: &Case, method: i32, tol: f64, dt: f64) -> Result<Trace, String> {
    match c.mech {
        "GenevaKnifeDrive" => run::<GenevaKnifeDrive>(c, method, tol, dt),
        "SewingTable" => run::<SewingTable>(c, method, tol, dt),
        "Perforators" => run::<Perforators>(c, method, tol, dt),
        "DiscKnifeDrive" => run::<DiscKnifeDrive>(c, method, tol, dt),
        m => Err(format!("no report case for {m}")),
    }
}

/// The unit of a case's position output (m; rad for the Perforators' lever angle).
fn unit_of(c: &Case) -> &'static str {
    bindery_fmu::catalog::all()
        .iter()
        .find(|e| e.identifier == c.mech)
        .and_then(|e| (e.variables)().into_iter().find(|(_, v)| v.name == c.x))
        .and_then(|(_, v)| v.unit)
        .unwrap_or("")
}

/// The value reference of a variable of `M`, by name.
fn vr<M: Model>(name: &str) -> Result<usize, String> {
    <M::Var as VarSet>::table()
        .iter()
        .position(|v| v.name == name)
        .ok_or_else(|| format!("{} has no variable {name}", M::IDENTIFIER))
}

/// The variables of `M` for case `c` at its elastodynamic level, at a constant speed, with the
/// solver `method` at tolerance `tol` (rk4: its step).
pub(crate) fn case_values<M: Model>(
    c: &Case,
    method: i32,
    tol: f64,
) -> Result<Values<M::Var>, String> {
    let mut v = Values::<M::Var>::start();
    let mut set = |name: &str, x: f64| -> Result<(), String> {
        v.raw_mut()[vr::<M>(name)?] = x;
        Ok(())
    };
    set("model.fidelity", 3.0)?;
    set("drive.mode", 2.0)?;
    set("drive.n", c.rpm * std::f64::consts::PI / 30.0)?;
    set(c.k_name, c.k)?;
    for &(name, x) in c.extra {
        set(name, x)?;
    }
    set("solver.method", method as f64)?;
    if method == 4 {
        set("solver.max_step", tol)?;
    } else {
        set("solver.rtol", tol)?;
        set("solver.atol", (tol * 1e-3).min(3.0 / c.k))?;
    }
    Ok(v)
}

/// The elastodynamic level of `M` at a constant speed, sampled on a 1 ms grid.
fn run<M: Model>(c: &Case, method: i32, tol: f64, dt: f64) -> Result<Trace, String> {
    let grid = 1e-3;
    let per = (grid / dt).round().max(1.0) as usize;
    let dt = grid / per as f64;
    let n = (c.stop / grid).round() as usize;
    let (mut xs, mut fs) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let mut v = case_values::<M>(c, method, tol)?;
    let (ix, iff) = (vr::<M>(c.x)?, vr::<M>(c.f)?);
    let mut m = M::prepare(&v).map_err(|e| e.to_string())?;
    let mut t = 0.0;
    for i in 0..n {
        for j in 0..per {
            m.step(&mut v, t, dt, &mut NoLog)?;
            t = (i * per + j + 1) as f64 * dt;
        }
        m.evaluate(&mut v, t, &mut NoLog);
        xs.push(v.raw()[ix]);
        fs.push(v.raw()[iff]);
    }
    Ok((xs, fs))
}

/// A run's errors against the reference: the largest of the position on the grid (m), of the
/// peak force (relative), and the largest of the force on the grid over the reference's peak
/// force (NaN where the run has no force: FMPy's lines, the anchors).
#[derive(Clone, Copy)]
struct Errors {
    x: f64,
    peak_f: f64,
    f: f64,
}

impl Errors {
    fn of_position(x: f64) -> Errors {
        Errors {
            x,
            peak_f: f64::NAN,
            f: f64::NAN,
        }
    }
}

fn errors(a: &Trace, r: &Trace) -> Errors {
    let largest = |u: &[f64], v: &[f64]| {
        u.iter()
            .zip(v)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max)
    };
    let pa = a.1.iter().map(|x| x.abs()).fold(0.0, f64::max);
    let pr = r.1.iter().map(|x| x.abs()).fold(0.0, f64::max).max(1e-300);
    Errors {
        x: largest(&a.0, &r.0),
        peak_f: (pa - pr).abs() / pr,
        f: largest(&a.1, &r.1) / pr,
    }
}

struct Point {
    method: String,
    setting: String,
    err: Option<Errors>,
    secs: f64,
    note: String,
}

/// One rung of a case's ladders: its line in the tables, its setting, the solver method, its
/// tolerance (rk4: its step) and the communication step.
struct Rung {
    name: &'static str,
    setting: String,
    method: i32,
    tol: f64,
    dt: f64,
}

/// The points of case `c`'s `rungs`, all timed together in rounds
/// ([`crate::timing::timed_in_rounds`]), so that the machine's load falls on every method alike;
/// `done` is told of each point as it completes.
fn measure(
    c: &Case,
    rungs: &[Rung],
    reference: &Trace,
    bar: &Progress,
    done: &mut dyn FnMut(&Point),
) -> Vec<Point> {
    let point = |r: &Rung, secs: f64, run: &Result<Trace, String>| Point {
        method: r.name.into(),
        setting: r.setting.clone(),
        err: run.as_ref().ok().map(|tr| errors(tr, reference)),
        secs,
        note: run.as_ref().err().map_or(String::new(), |e| {
            format!("Discard: {}", e.chars().take(90).collect::<String>())
        }),
    };
    let timed = crate::timing::timed_in_rounds(
        rungs.len(),
        |i| {
            let r = &rungs[i];
            bar.doing(format!("{} {}: {}, {}", c.mech, c.label, r.name, r.setting));
            simulate(c, r.method, r.tol, r.dt)
        },
        |i, secs, run| done(&point(&rungs[i], secs, run)),
    );
    rungs
        .iter()
        .zip(&timed)
        .map(|(r, (secs, run))| point(r, *secs, run))
        .collect()
}

/// FMPy's lines: JSON lines of scripts/work_precision.py on the case's FMU (Model Exchange
/// with CVode, and the FMU's own `auto` through the same host loop), each reported as it comes.
fn fmpy_baseline(root: &Path, c: &Case, bar: &Progress) -> Vec<Point> {
    let child = std::process::Command::new(root.join(".venv/bin/python"))
        .arg(root.join("scripts/work_precision.py"))
        .args([
            "--fmu",
            c.mech,
            "--x",
            c.x,
            "--k-name",
            c.k_name,
            "--k",
            &c.k.to_string(),
            "--rpm",
            &c.rpm.to_string(),
            "--stop",
            &c.stop.to_string(),
            "--set",
            &c.extra
                .iter()
                .map(|(n, x)| format!("{n}={x}"))
                .collect::<Vec<_>>()
                .join(","),
            "--only",
            "auto,fmpy-cvode-me",
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn();
    let Ok(mut child) = child else {
        bar.line(format!(
            "  FMPy baseline skipped: cannot run {}",
            root.join(".venv/bin/python").display()
        ));
        return vec![];
    };
    let mut pts = vec![];
    let lines = std::io::BufReader::new(child.stdout.take().expect("piped")).lines();
    for line in lines.map_while(Result::ok) {
        let get = |key: &str| -> Option<String> {
            let i = line.find(&format!("\"{key}\": "))? + key.len() + 4;
            let rest = &line[i..];
            let end = rest.find([',', '}']).unwrap_or(rest.len());
            Some(rest[..end].trim_matches('"').to_string())
        };
        let (Some(m), Some(tol)) = (get("method"), get("tol")) else {
            continue;
        };
        let err = get("error").and_then(|e| e.parse::<f64>().ok());
        let secs = get("seconds")
            .and_then(|e| e.parse::<f64>().ok())
            .unwrap_or(f64::NAN);
        let p = Point {
            method: format!(
                "FMPy: {}",
                if m == "auto" {
                    "CS auto"
                } else {
                    "CVode on ME"
                }
            ),
            setting: format!("rtol {tol}"),
            err: err.map(Errors::of_position),
            secs,
            note: if err.is_none() {
                "failed".into()
            } else {
                String::new()
            },
        };
        bar.line(format!("  {}", point_line(&p)));
        pts.push(p);
    }
    let _ = child.wait();
    pts
}

/// A run point as the progress log shows it.
fn point_line(p: &Point) -> String {
    let result = match p.err {
        Some(e) => format!("error {:.2e}, {:.4} s", e.x, p.secs),
        None => format!("no result ({})", p.note),
    };
    format!("{}, {}: {result}", p.method, p.setting)
}

/// The mechanisms `--only` names, each checked against the report's cases.
fn only_cases(only: &[String]) -> Result<Vec<Case>, String> {
    let mut valid: Vec<&str> = CASES.iter().map(|c| c.mech).collect();
    valid.dedup();
    if let Some(bad) = only.iter().find(|m| !valid.contains(&m.as_str())) {
        let why = if bindery_fmu::catalog::all()
            .iter()
            .any(|e| e.identifier == bad.as_str())
        {
            format!("{bad} has no elastodynamic level, so no report case")
        } else {
            format!("unknown mechanism {bad:?}")
        };
        return Err(format!("--only: {why}; valid: {}", valid.join(", ")));
    }
    Ok(CASES
        .into_iter()
        .filter(|c| only.is_empty() || only.iter().any(|m| m == c.mech))
        .collect())
}

/// Per method, its work-precision line: `(seconds, error)` of its runs, sorted by time.
type MethodLines = Vec<(String, Vec<(f64, f64)>)>;

/// The error at which methods are compared (`dynamics.md` benchmark: equal error 1e-6), m.
const TARGET: f64 = 1e-6;

/// Per method, its work-precision line (the runs with an error and a time, sorted by time).
fn method_lines(pts: &[Point]) -> MethodLines {
    let mut names: Vec<&str> = vec![];
    for p in pts {
        if !names.contains(&p.method.as_str()) && !p.method.contains("ladder") {
            names.push(&p.method);
        }
    }
    names
        .into_iter()
        .map(|n| {
            let mut run: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| p.method == n && p.secs.is_finite())
                .filter_map(|p| p.err.map(|e| (p.secs, e.x)))
                .collect();
            run.sort_by(|a, b| a.0.total_cmp(&b.0));
            (n.to_string(), run)
        })
        .collect()
}

/// The largest error a line reaches (its coarsest run).
fn coarsest(run: &[(f64, f64)]) -> f64 {
    run.iter().map(|r| r.1).fold(f64::NAN, f64::max)
}

/// Time of line `a` over time of line `b` at equal error: at [`TARGET`], or where one of them
/// has no run as coarse as that, at the coarsest error both reach (a line whose cheapest run is
/// already more accurate than the target is not slower there than that run, and a ratio taken
/// at that run's time would compare two errors). With the error compared at when it is not
/// [`TARGET`].
fn ratio_at_equal_error(a: &[(f64, f64)], b: &[(f64, f64)]) -> Option<(f64, f64)> {
    let e = TARGET.min(coarsest(a)).min(coarsest(b));
    Some((time_at(a, e)? / time_at(b, e)?, e))
}

/// The time at which a work-precision line `(seconds, error)` (sorted by time) first reaches
/// `target`, log–log interpolated.
fn time_at(run: &[(f64, f64)], target: f64) -> Option<f64> {
    let first = run.iter().position(|&(_, e)| e <= target)?;
    if first == 0 {
        return Some(run[0].0);
    }
    let ((t0, e0), (t1, e1)) = (run[first - 1], run[first]);
    let (l0, l1, lt) = (e0.max(1e-300).ln(), e1.max(1e-300).ln(), target.ln());
    let u = if l0 == l1 { 1.0 } else { (l0 - lt) / (l0 - l1) };
    Some((t0.ln() + u * (t1.ln() - t0.ln())).exp())
}

/// The benchmark figures of issue 5: at equal error, FMPy + CVode on the Model Exchange
/// interface against the FMU's own `auto` in the same FMPy loop, and `auto` against the best
/// fixed internal method.
fn summary_table(summary: &[(Case, MethodLines)]) -> String {
    let mut md = format!(
        "\n## At equal error ({TARGET:e} in position: m, rad for the Perforators' lever)\n\nWall time at which each method's error reaches {TARGET:e} m (log–log interpolation on its ladder; – where none does; ≤ where even its cheapest run is more accurate, so its time at {TARGET:e} is at most that run's). A ratio compares two lines at {TARGET:e}, or, where one of them has no run as coarse as that, at the coarsest error both reach, given in brackets; of several methods (best fixed, faster library) the one that does best against `auto`.\n\n| case | auto | dopri5 | radau5 | rk4 | library radau5 | library dopri5 | best fixed ÷ auto | auto, same ODE | faster library ÷ auto (same ODE) | FMPy: CS auto | FMPy: CVode on ME | CVode ÷ our CS (FMPy loop) |\n| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n"
    );
    for (c, lines) in summary {
        let line = |n: &str| {
            lines
                .iter()
                .find(|(m, _)| m == n)
                .map_or(&[][..], |(_, r)| &r[..])
        };
        let fmt = |n: &str| {
            let run = line(n);
            match time_at(run, TARGET) {
                Some(t) if coarsest(run) < TARGET => format!("≤ {t:.4} s"),
                Some(t) => format!("{t:.4} s"),
                None => "–".into(),
            }
        };
        // the smallest ratio of any of `over` to `under`, with the error it was taken at
        let ratio = |over: &[&str], under: &str| {
            over.iter()
                .filter_map(|n| ratio_at_equal_error(line(n), line(under)))
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map_or("–".into(), |(r, e)| {
                    if e < TARGET {
                        format!("{r:.2} ({e:.1e})")
                    } else {
                        format!("{r:.2}")
                    }
                })
        };
        let _ = writeln!(
            md,
            "| {} {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            c.mech,
            c.label,
            fmt("auto"),
            fmt("dopri5"),
            fmt("radau5"),
            fmt("rk4"),
            fmt("library radau5"),
            fmt("library dopri5"),
            ratio(&["dopri5", "radau5", "rk4"], "auto"),
            fmt("auto, same ODE"),
            ratio(&["library radau5", "library dopri5"], "auto, same ODE"),
            fmt("FMPy: CS auto"),
            fmt("FMPy: CVode on ME"),
            ratio(&["FMPy: CVode on ME"], "FMPy: CS auto")
        );
    }
    md
}

pub fn report(out: &Option<PathBuf>, with_fmpy: bool, only: &[String]) -> Result<(), String> {
    let cases = only_cases(only)?;
    let out = &folder(out, "out/report")?;
    let root = if with_fmpy { Some(root()?) } else { None };
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let tols = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8];
    let rk4_steps = [1e-4, 3e-5, 1e-5, 3e-6];
    let dts = [1e-4, 1e-3, 1e-2];
    let per_case = 3 * tols.len() + rk4_steps.len() + dts.len() + 2;
    let bar = Progress::new(
        (cases.len() * per_case) as u64,
        "{msg:40} [{bar:30}] {pos}/{len} {elapsed}",
    )?;
    // one line per finished run point: [done/all] what, its error and time
    let report_point = |c: &Case, p: &Point| {
        bar.inc();
        bar.line(format!(
            "[{}/{}] {} {}: {}",
            bar.done(),
            bar.len(),
            c.mech,
            c.label,
            point_line(p)
        ));
    };
    let mut md = String::from(
        "# Error against run time (elastodynamic level)\n\nGenerated by `cargo run --release -- report`. Error: largest |position − reference| on the 1 ms output grid (m), the relative error of the peak chain force, and the largest |force − reference| on the grid over the reference's peak force (a stiff chain's force needs a tighter tolerance than its position: the README's solver section); reference: dopri5 at rtol 1e-11. Time: median of at least 3 runs in this process, repeated until they took 0.1 s together (at most 51; plain Rust model, no FMI host), a case's runs timed in rounds (every method and setting once a round, forth and back), so that a change in the machine's load falls on all of them alike; the FMPy lines run through FMPy's host loop (Python per output step; instantiation timed, the model description read once before the timed runs, as a sweep over one FMU reads it), with the FMU's own `auto` through the same loop for the like-for-like ratio.\n\nrk4 has no error estimate, so its error need not fall with h: a step that ends on a located event (cut-through, where the 15 kN cutting force drops to 0; a contact opening) evaluates its last stage just past the jump or just before it, decided at roundoff level in the event bracketing, not by h. Where it falls past, the step loses F·h_last/(6m) of velocity and the chain rings with it (Geneva, k = 5e7 N/m: 1.8e-4 m/s at cut-through, 8.2e-8 m in the knife position at h = 1e-6, 3e-6 and 6e-6 s, against at most 2.6e-11 m at 2e-6, 4e-6, 5e-6 and 1e-5 s). The adaptive methods reject such a step. The reference is not the cause: dopri5 at rtol 1e-11 and 1e-12 differ by 3.3e-13 m there.\n",
    );
    let mut summary = vec![];
    for c in cases {
        bar.doing(format!("{} {}", c.mech, c.label));
        bar.line(format!(
            "{} {}: reference (dopri5, rtol 1e-11)",
            c.mech, c.label
        ));
        // Dormand–Prince resolves an undamped stiff ringing that Radau's error estimate filters;
        // where it cannot finish (its step budget on the stiffest contact), Radau IIA at rtol 1e-11
        let reference = match simulate(&c, 2, 1e-11, 1e-3) {
            Ok(r) => r,
            Err(dopri) => match simulate(&c, 3, 1e-11, 1e-3) {
                Ok(r) => {
                    let _ = write!(
                        md,
                        "\n({} {}: reference by radau5 at rtol 1e-11; dopri5 did not finish: {})\n",
                        c.mech,
                        c.label,
                        dopri.chars().take(120).collect::<String>()
                    );
                    r
                }
                Err(e) => {
                    let _ = write!(md, "\n## {} — {}\n\nNo reference: {e}\n", c.mech, c.label);
                    continue;
                }
            },
        };
        bar.inc();
        let mut rungs = vec![];
        for (method, name) in [(1, "auto"), (2, "dopri5"), (3, "radau5")] {
            for tol in tols {
                let setting = format!("rtol {tol:e}");
                rungs.push(Rung {
                    name,
                    setting,
                    method,
                    tol,
                    dt: 1e-3,
                });
            }
        }
        for h in rk4_steps {
            let setting = format!("h {h:e} s");
            rungs.push(Rung {
                name: "rk4",
                setting,
                method: 4,
                tol: h,
                dt: 1e-3,
            });
        }
        for dt in dts {
            let (name, setting) = ("auto, rtol 1e-6, comm. step ladder", format!("dt {dt:e} s"));
            rungs.push(Rung {
                name,
                setting,
                method: 1,
                tol: 1e-6,
                dt,
            });
        }
        let mut pts = measure(&c, &rungs, &reference, &bar, &mut |p| report_point(&c, p));
        if let Some(root) = &root {
            bar.doing(format!("{} {}: FMPy", c.mech, c.label));
            bar.line(format!(
                "{} {}: FMPy baseline (scripts/work_precision.py)",
                c.mech, c.label
            ));
            pts.extend(fmpy_baseline(root, &c, &bar));
        }
        // the anchors: the same chain ODE, ours and the library's, with their counts
        bar.doing(format!("{} {}: anchors", c.mech, c.label));
        let anchors = crate::anchors::anchors(&c, &tols, &mut |a| {
            bar.line(format!(
                "{} {}: same ODE, {} rtol {:e}: {} in {:.4} s",
                c.mech,
                c.label,
                a.method,
                a.rtol,
                a.err.map_or(a.note.clone(), |e| format!("error {e:.2e}")),
                a.secs
            ))
        })
        .unwrap_or_else(|e| {
            bar.line(format!("{} {}: no anchors: {e}", c.mech, c.label));
            vec![]
        });
        bar.inc();
        for a in anchors
            .iter()
            .filter(|a| a.method.starts_with("library") || a.method == "auto")
        {
            pts.push(Point {
                method: if a.method == "auto" {
                    "auto, same ODE".into()
                } else {
                    a.method.to_string()
                },
                setting: format!("rtol {:e}", a.rtol),
                err: a.err.map(Errors::of_position),
                secs: a.secs,
                note: a.note.clone(),
            });
        }
        // table
        let _ = write!(
            md,
            "\n## {} — {}\n\n| method | setting | position error (m) | peak force error | force error (of the peak) | time (s) | note |\n| --- | --- | --- | --- | --- | --- | --- |\n",
            c.mech, c.label
        );
        let num = |x: f64| {
            if x.is_nan() {
                "–".to_string()
            } else {
                format!("{x:.2e}")
            }
        };
        for p in &pts {
            let (e, pf, f) = p.err.map_or(("–".into(), "–".into(), "–".into()), |e| {
                (num(e.x), num(e.peak_f), num(e.f))
            });
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {:.4} | {} |",
                p.method, p.setting, e, pf, f, p.secs, p.note
            );
        }
        // plot: one line per method, log10 axes
        let mut names: Vec<&str> = vec![];
        for p in &pts {
            if !names.contains(&p.method.as_str()) {
                names.push(&p.method);
            }
        }
        let series = names
            .iter()
            .map(|n| {
                let v: Vec<(f64, f64)> = pts
                    .iter()
                    .filter(|p| p.method == *n)
                    .filter_map(|p| p.err.map(|e| (p.secs.log10(), e.x.max(1e-16).log10())))
                    .filter(|(a, b)| a.is_finite() && b.is_finite())
                    .collect();
                // in ladder order (tolerance or step), as work-precision plots join them
                Series::new(*n, v)
            })
            .collect();
        let stem = format!(
            "{}_{}",
            c.mech,
            if c.k > 1e9 { "stiff" } else { "nonstiff" }
        );
        let file = format!("{stem}.png");
        let fig = Figure {
            file: file.clone(),
            title: format!("{} {}: work-precision", c.mech, c.label),
            x_label: "log10 wall time [s]".into(),
            y_label: format!("log10 error of {} [{}]", c.x, unit_of(&c)),
            series,
            caption: String::new(),
            equal_axes: false,
            markers: true,
        };
        for (name, bytes) in [
            (file.clone(), render_png(&fig)?),
            (format!("{stem}.svg"), render_svg(&fig)?.into_bytes()),
        ] {
            let path = out.join(name);
            std::fs::write(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
            bar.line(format!("wrote {}", path.display()));
        }
        let _ = writeln!(md, "\n![{}]({file}) ([SVG]({stem}.svg))", fig.title);
        md.push_str(&crate::anchors::counts_table(&anchors));
        summary.push((c, method_lines(&pts)));
        // written after every case, so a long run leaves what it has
        let partial = md.clone() + &summary_table(&summary);
        std::fs::write(out.join("report.md"), partial).map_err(|e| e.to_string())?;
    }
    bar.finish();
    md.push_str(&summary_table(&summary));
    std::fs::write(out.join("report.md"), md).map_err(|e| e.to_string())?;
    eprintln!("wrote {}", out.join("report.md").display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{TARGET, ratio_at_equal_error, time_at};

    #[test]
    fn equal_error_time_is_interpolated_log_log_between_the_bracketing_runs() {
        // error ∝ time^-2: 1e-4 at 1 ms, 1e-8 at 100 ms → 1e-6 at 10 ms
        let run = [(1e-3, 1e-4), (1e-1, 1e-8)];
        let t = time_at(&run, 1e-6).unwrap();
        assert!((t / 1e-2 - 1.0).abs() < 1e-12, "{t}");
        // the first run already reaches it; none reaches it
        assert_eq!(time_at(&[(0.5, 1e-7)], 1e-6), Some(0.5));
        assert_eq!(time_at(&[(0.5, 1e-5), (1.0, 2e-6)], 1e-6), None);
        // a non-monotone ladder: the first run at or below the target counts
        let t = time_at(&[(1.0, 1e-5), (2.0, 3e-5), (4.0, 1e-7)], 1e-6).unwrap();
        assert!(t > 2.0 && t < 4.0, "{t}");
    }

    #[test]
    fn a_ratio_is_taken_at_an_error_both_lines_reach() {
        // both bracket the target: at the target, error ∝ time^-2 and ∝ time^-4
        let a = [(1e-3, 1e-4), (1e-1, 1e-8)];
        let b = [(1e-3, 1e-2), (1e-2, 1e-6), (1e-1, 1e-10)];
        let (r, e) = ratio_at_equal_error(&a, &b).unwrap();
        assert_eq!(e, TARGET);
        assert!((r - 1.0).abs() < 1e-9, "{r}");
        // `c`'s cheapest run is already at 1e-8, 100 times below the target, in 2 ms: against
        // `a` at 1e-8 (100 ms), not at 1e-6 (10 ms), which would compare 1e-8 with 1e-6
        let c = [(2e-3, 1e-8), (1e-2, 1e-10)];
        let (r, e) = ratio_at_equal_error(&a, &c).unwrap();
        assert_eq!(e, 1e-8);
        assert!((r - 50.0).abs() < 1e-9, "{r}");
        // a line with no run at all: no ratio
        assert_eq!(ratio_at_equal_error(&a, &[]), None);
    }
}
