//! `bindery needles`: the legacy three-contour needle drive (LegacyNeedleDrive, paper 002)
//! against the Perforators' ramp and lever (papers 000, 002) at equal needle motion, over one
//! shaft turn at constant speed (kinetostatic level): peak cam/ramp-roller force, peak Hertz
//! stress, the shaft torque, and paper 002's beta study. Writes out/needles/needles.md and PNGs.

use crate::params::{self, Setting, shown};
use crate::place::folder;
use bindery_fmu::catalog::variables_of;
use bindery_fmu::docs::{Figure, Series, number, render_png};
use bindery_fmu::mechanisms::legacy_needle_drive::compare::{Turn, legacy_turn, new_turn};
use bindery_fmu::mechanisms::legacy_needle_drive::docs::beta_study;
use bindery_fmu::mechanisms::legacy_needle_drive::model::{LegacyNeedleDrive, V};
use bindery_fmu::mechanisms::legacy_needle_drive::physics::Closure;
use bindery_fmu::mechanisms::perforators::Perforators;
use bindery_fmu::mechanisms::perforators::model::V as NewV;
use bindery_fmu::model::{Model, Values, VarSet};
use std::fmt::Write;
use std::path::PathBuf;

const RPM: f64 = std::f64::consts::PI / 30.0;

/// The parameters both drives share (same names, meanings and defaults): a setting of one of
/// them goes to both, so the needles move alike.
const SHARED: &[&str] = &[
    "cycle.forward",
    "cycle.phi0",
    "law.forward",
    "travel.rise_fraction",
    "law.rise",
    "law.fall",
    "synth.unit",
    "pierce.Q",
    "pierce.s_in",
    "pierce.s_out",
    "pierce.k_f",
    "perf.m",
    "guide.mu",
    "joint.f",
    "joint.r",
];

pub fn needles(rpm: f64, set: &[String], out: &Option<PathBuf>) -> Result<(), String> {
    if !(rpm > 0.0 && rpm.is_finite()) {
        return Err(format!("--rpm {rpm}: a speed > 0 is needed"));
    }
    let legacy_vars = variables_of::<LegacyNeedleDrive>();
    let settings = params::parse_all(
        "LegacyNeedleDrive",
        &legacy_vars,
        set,
        &["needle.timing", "drive.n", "drive.mode", "model.fidelity"],
        "the comparison sets it itself (the perforators timing, --rpm, kinetostatic)",
    )?;
    let mut v = Values::<V>::start();
    v[V::needle_timing] = 1.0;
    let mut new_v = Values::<NewV>::start();
    let new_table = <NewV as VarSet>::table();
    for s in &settings {
        v.raw_mut()[s.vr as usize] = s.value;
        if SHARED.contains(&s.name) {
            let vr = new_table
                .iter()
                .position(|x| x.name == s.name)
                .ok_or_else(|| format!("{}: not a Perforators parameter", s.name))?;
            new_v.raw_mut()[vr] = s.value;
        }
    }
    let legacy =
        LegacyNeedleDrive::prepare(&v).map_err(|e| format!("LegacyNeedleDrive refused: {e}"))?;
    let new = Perforators::prepare(&new_v).map_err(|e| format!("Perforators refused: {e}"))?;
    let w = rpm * RPM;
    let a = legacy_turn(legacy.drive(), w, 1440);
    let b = new_turn(new.drive(), w, 1440);
    let out = folder(out, "out/needles")?;
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;

    let table = <V as VarSet>::table();
    let with = settings_text(&settings, table);
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Needle drives at equal needle motion, {} rpm\n",
        number(rpm, 4)
    );
    let _ = writeln!(
        md,
        "LegacyNeedleDrive (paper 002: cam, rocker, four-bar, rocker-slider; two branches, groove cam \
         unless set) against the Perforators (paper 000: ramp, lever, rod, carriage), both with the \
         needle curve of the Perforators over the table's forward travel, kinetostatic level, {with}.\n"
    );
    // a row: what, unit, its scale, and the measure of a trace over the turn, legacy and new
    type Measure = fn(&[(f64, f64)]) -> f64;
    let row = |what, unit, scale, of: Measure, trace: fn(&Turn) -> &[(f64, f64)]| {
        (what, unit, scale, of(trace(&a)), of(trace(&b)))
    };
    let rows = [
        row("needle stroke", "mm", 1e3, Turn::peak, |t| &t.s),
        row(
            "peak roller force (one cam / the ramp)",
            "N",
            1.0,
            Turn::peak,
            |t| &t.roller_f,
        ),
        row("peak Hertz stress", "MPa", 1e-6, Turn::peak, |t| &t.sigma_h),
        row("peak shaft torque", "N.m", 1.0, Turn::peak, |t| &t.tau),
        row("RMS shaft torque", "N.m", 1.0, Turn::rms, |t| &t.tau),
        row("mean shaft power", "W", w, Turn::mean, |t| &t.tau),
    ];
    let _ = writeln!(md, "| over a turn | unit | legacy | new | legacy / new |");
    let _ = writeln!(md, "| --- | --- | --- | --- | --- |");
    for (what, unit, scale, x, y) in rows {
        let _ = writeln!(
            md,
            "| {what} | {unit} | {} | {} | {} |",
            number(scale * x, 4),
            number(scale * y, 4),
            number(x / y, 3)
        );
    }
    let pull = a
        .roller_f
        .iter()
        .copied()
        .fold((0.0, f64::INFINITY), |m, p| if p.1 < m.1 { p } else { m });
    if legacy.drive().p.closure == Closure::Spring && pull.1 < 0.0 {
        let _ = writeln!(
            md,
            "\nThe spring-closed legacy cam would have to pull the roller with {} N at shaft angle {} deg: \
             it lifts off (a groove, or a spring load load.P_spring, holds it on).",
            number(-pull.1, 4),
            number(pull.0, 4)
        );
    }
    let ratio = bindery_fmu::mechanisms::legacy_needle_drive::docs::beta_ratio();
    let _ = writeln!(
        md,
        "\nPaper 002's study (the own timing, 100 rpm, the rocker's swing held): raising \
         kmk.beta = L_rocker/l_k from 0.48 to 1 lowers the largest Hertz stress in the run-up \
         {}-fold (the paper: 1.83 with its unknown sizes).\n",
        number(ratio, 3)
    );
    // the two drives over one turn, legacy first
    let compare = |file: &str, what: &str, axis: &str, names: [&str; 2], traces, caption: &str| {
        let [ta, tb]: [Vec<(f64, f64)>; 2] = traces;
        Figure::lines(
            file,
            format!("{what} at {} rpm", number(rpm, 4)),
            "shaft angle phi, deg",
            axis,
            vec![Series::new(names[0], ta), Series::new(names[1], tb)],
            caption,
        )
    };
    let both = ["LegacyNeedleDrive", "Perforators"];
    let figures = [
        compare(
            "torque.png",
            "Shaft torque",
            "shaft.tau, N.m",
            both,
            [a.tau.clone(), b.tau.clone()],
            "The needle drives' share of the main-shaft torque over one turn.",
        ),
        compare(
            "roller_force.png",
            "Roller force",
            "roller.F, N",
            ["LegacyNeedleDrive (one cam)", "Perforators (ramp)"],
            [a.roller_f.clone(), b.roller_f.clone()],
            "The force on the roller of one legacy cam and on the Perforators' ramp roller.",
        ),
        compare(
            "sigma_H.png",
            "Hertz stress",
            "roller.sigma_H, MPa",
            both,
            [scaled(&a.sigma_h, 1e-6), scaled(&b.sigma_h, 1e-6)],
            "Hertz stress at the cam and at the ramp.",
        ),
        Figure::lines(
            "beta_study.png",
            "Paper 002's beta study",
            "kmk.beta = L_rocker / l_k",
            "largest roller.sigma_H in the run-up, MPa",
            vec![Series::new("own timing, 100 rpm", beta_study())],
            "The largest Hertz stress in the run-up of the rise over beta.",
        ),
    ];
    for f in &figures {
        let path = out.join(&f.file);
        std::fs::write(&path, render_png(f)?).map_err(|e| format!("{}: {e}", path.display()))?;
        let _ = writeln!(md, "![{}]({})\n", f.title, f.file);
    }
    let path = out.join("needles.md");
    std::fs::write(&path, &md).map_err(|e| format!("{}: {e}", path.display()))?;
    print!("{}", md.split("\n![").next().unwrap_or(&md));
    eprintln!("wrote {} and {} figures", path.display(), figures.len());
    Ok(())
}

fn scaled(trace: &[(f64, f64)], k: f64) -> Vec<(f64, f64)> {
    trace.iter().map(|p| (p.0, k * p.1)).collect()
}

fn settings_text(settings: &[Setting], table: &[bindery_fmu::model::Var]) -> String {
    if settings.is_empty() {
        "default parameters".to_string()
    } else {
        settings
            .iter()
            .map(|s| format!("{} = {}", s.name, shown(&table[s.vr as usize], s.value)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}
