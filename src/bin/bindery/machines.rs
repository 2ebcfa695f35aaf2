//! `bindery machines`: what a machine designer asks of the two machines (the systems of
//! `bindery ssp`, simulated here on the Rust models with the same master as FMPy's
//! `simulate_ssp`): the coefficient of speed fluctuation δ at nominal speed with the default
//! flywheel, the flywheel that brings δ below 1/40, peak and RMS motor torque, the start-up time
//! to 95 % of the running speed. Writes `machines.md` and PNG plots.

use bindery_fmu::docs::{Figure, Series, render_png};
use bindery_fmu::machines::{Trace, flywheel_for, simulate, startup_time, steady};
use bindery_fmu::ssp::{Machine, machines as all_machines};
use std::fmt::Write as _;
use std::path::Path;

/// Target coefficient of speed fluctuation.
const TARGET: f64 = 1.0 / 40.0;
const RPM: f64 = 30.0 / std::f64::consts::PI;

/// How a machine is run for the figures.
struct Setup {
    /// Length of a steady run from the nominal speed, s, and the turns δ is measured over.
    stop: f64,
    turns: f64,
    /// Start-up run (from rest) length, s, and its extra settings.
    startup_stop: f64,
    startup_set: Vec<(&'static str, &'static str, f64)>,
    /// Bisection bracket of the flywheel, kg·m².
    fly_hi: f64,
}

fn setup(m: &Machine) -> Setup {
    if m.name == "ThreeKnifeTrimmer" {
        Setup {
            stop: 20.0,
            turns: 4.0,
            startup_stop: 30.0,
            // idle start-up: no stack under the knives (the clutch engages at speed)
            startup_set: vec![
                ("side_left", "cut.F_max", 0.0),
                ("side_right", "cut.F_max", 0.0),
                ("front", "cut.F_max", 0.0),
                ("drive", "init.w", 0.0),
            ],
            fly_hi: 1e5,
        }
    } else {
        Setup {
            stop: 8.0,
            turns: 4.0,
            startup_stop: 6.0,
            startup_set: vec![],
            fly_hi: 1e3,
        }
    }
}

fn fly_default(m: &Machine) -> f64 {
    m.components[0]
        .params
        .iter()
        .find(|(p, _)| *p == "fly.J")
        .map_or(2.0, |p| p.1)
}

/// The last `turns` turns of a trace as (time from their start, rpm).
fn cycles(tr: &Trace, turns: f64) -> Vec<(f64, f64)> {
    let i0 = bindery_fmu::machines::last_turns_start(tr, turns);
    let t0 = tr.t[i0];
    (i0..tr.t.len())
        .map(|i| (tr.t[i] - t0, tr.w[i] * RPM))
        .collect()
}

pub fn machines(out: &Path) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut md = String::new();
    let mut rows = String::new();
    let mut figures = Vec::new();
    for m in all_machines() {
        let s = setup(&m);
        let j0 = fly_default(&m);
        let nominal = [("drive", "init.w", m.nominal_w)];
        eprintln!("{}: steady run", m.name);
        let run = simulate(&m, &nominal, s.stop, m.step)?;
        let st = steady(&run, s.turns);
        eprintln!("{}: flywheel for delta <= 1/40", m.name);
        let j40 = flywheel_for(&m, TARGET, 0.0, s.fly_hi, s.stop, m.step, s.turns)?;
        let run40 = match j40 {
            Some(j) => Some(simulate(
                &m,
                &[("drive", "init.w", m.nominal_w), ("drive", "fly.J", j)],
                s.stop,
                m.step,
            )?),
            None => None,
        };
        eprintln!("{}: start-up", m.name);
        let up = simulate(&m, &s.startup_set, s.startup_stop, m.step)?;
        let w_run = steady(&up, s.turns).w_mean;
        let t95 = startup_time(&up, 0.95, w_run);
        let i2 = (m.components[0].params.iter())
            .find(|(p, _)| *p == "gear.i")
            .map_or(15.0, |p| p.1);
        let _ = writeln!(
            rows,
            "| {} | {:.1} | {:.1} | {j0} | {:.4} (1/{:.0}) | {} | {:.1} | {:.1} | {} |",
            m.name,
            m.nominal_w * RPM,
            st.w_mean * RPM,
            st.delta,
            1.0 / st.delta,
            j40.map_or("not below 1e5".into(), |j| format!(
                "{j:.1} ({:.3} at the motor)",
                j / (i2 * i2)
            )),
            st.tau_peak,
            st.tau_rms,
            t95.map_or("not reached".into(), |t| format!("{t:.2}")),
        );
        let mut series = vec![Series::new(
            format!("fly.J = {j0} kg.m2"),
            cycles(&run, s.turns),
        )];
        if let (Some(r), Some(j)) = (&run40, j40) {
            series.push(Series::new(
                format!("fly.J = {j:.0} kg.m2 (delta = 1/40)"),
                cycles(r, s.turns),
            ));
        }
        figures.push(Figure {
            file: format!("{}_speed.png", m.name),
            title: format!("{}: main-shaft speed over {} turns", m.name, s.turns),
            x_label: "time, s".into(),
            y_label: "shaft speed, rpm".into(),
            series,
            caption: String::new(),
            equal_axes: false,
        });
        figures.push(Figure {
            file: format!("{}_startup.png", m.name),
            title: format!("{}: start-up from rest", m.name),
            x_label: "time, s".into(),
            y_label: "shaft speed, rpm".into(),
            series: vec![Series::new(
                "shaft.w",
                up.t.iter()
                    .zip(&up.w)
                    .step_by(10)
                    .map(|(t, w)| (*t, w * RPM))
                    .collect(),
            )],
            caption: String::new(),
            equal_axes: false,
        });
    }
    md += "| machine | nominal, rpm | running speed, rpm | fly.J, kg.m2 | delta | fly.J for delta <= 1/40, kg.m2 | peak motor torque, N.m | RMS motor torque, N.m | start-up to 95 %, s |\n";
    md += "| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    md += &rows;
    md += "\nMotor torque at the motor shaft over the steady turns; delta over the same turns; start-up from rest to 95 % of the running speed (trimmer: without the cutting load).\n\n";
    for f in &figures {
        std::fs::write(out.join(&f.file), render_png(f)?)
            .map_err(|e| format!("{}: {e}", f.file))?;
        let _ = writeln!(md, "![{}]({})\n", f.title, f.file);
    }
    let path = out.join("machines.md");
    std::fs::write(&path, &md).map_err(|e| format!("{}: {e}", path.display()))?;
    eprintln!("wrote {}\n{md}", path.display());
    Ok(())
}
