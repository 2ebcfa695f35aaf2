//! `bindery machines`: what a machine designer asks of the two machines (the systems of
//! `bindery ssp`, simulated here on the Rust models with the same master as FMPy's
//! `simulate_ssp`): the coefficient of speed fluctuation δ at nominal speed with the default
//! flywheel, the flywheel that brings δ below 1/40, peak and RMS motor torque, the start-up time
//! to 95 % of the running speed. Writes `machines.md` and PNG plots.

use crate::params::{self, Setting, shown};
use crate::place::folder;
use bindery_fmu::catalog::variables_of;
use bindery_fmu::docs::{Figure, Series, number, render_png};
use bindery_fmu::machines::{Trace, flywheel_for, simulate, startup_time, steady};
use bindery_fmu::mechanisms::main_shaft::MainShaft;
use bindery_fmu::model::VarSet;
use bindery_fmu::ssp::{Machine, machines as all_machines};
use std::fmt::Write as _;
use std::path::PathBuf;

/// What to change of the machines' drives (every value checked against the MainShaft FMU's
/// parameter bounds).
#[derive(clap::Args, Debug, Default)]
#[command(
    after_help = "--set takes any MainShaft parameter of the drive, in its display unit where it \
    has one (rpm for rad/s), else in SI, or with the unit after the number. Example:\n  \
    bindery machines --machine ThreadSewingMachine --rpm 120 --flywheel 4"
)]
pub struct Options {
    /// Only this machine (ThreadSewingMachine, ThreeKnifeTrimmer, ThreadSewingMachineLegacy)
    #[arg(long)]
    machine: Option<String>,
    /// Nominal main-shaft speed, rpm; the gear ratio becomes the motor's synchronous speed over
    /// it unless --gear is given
    #[arg(long, allow_negative_numbers = true)]
    rpm: Option<f64>,
    /// Flywheel and rotating parts at the main shaft fly.J, kg.m2
    #[arg(long, allow_negative_numbers = true)]
    flywheel: Option<f64>,
    /// Gear ratio gear.i, motor speed over main-shaft speed
    #[arg(long, allow_negative_numbers = true)]
    gear: Option<f64>,
    /// Rated motor power motor.P_rated, kW
    #[arg(long, allow_negative_numbers = true)]
    motor_kw: Option<f64>,
    /// Rated motor speed motor.n_rated, rpm
    #[arg(long, allow_negative_numbers = true)]
    motor_rpm: Option<f64>,
    /// Any parameter of the machine's MainShaft, NAME=VALUE (repeatable)
    #[arg(long = "set", value_name = "NAME=VALUE")]
    set: Vec<String>,
}

impl Options {
    /// The drive settings, checked against MainShaft's parameters.
    fn settings(&self) -> Result<Vec<Setting>, String> {
        let vars = variables_of::<MainShaft>();
        let mut texts: Vec<String> = Vec::new();
        texts.extend(self.flywheel.map(|x| format!("fly.J={x}")));
        texts.extend(self.gear.map(|x| format!("gear.i={x}")));
        texts.extend(self.motor_kw.map(|x| format!("motor.P_rated={}", x * 1e3)));
        texts.extend(self.motor_rpm.map(|x| format!("motor.n_rated={x}rpm")));
        texts.extend(self.set.iter().cloned());
        params::parse_all(
            "MainShaft",
            &vars,
            &texts,
            &["init.w", "init.phi"],
            "the runs set the start themselves (at speed, and from rest)",
        )
    }

    /// The machines to run, with the options applied to their drives.
    fn machines(&self) -> Result<Vec<Machine>, String> {
        if let Some(n) = self.rpm.filter(|n| !(n.is_finite() && *n > 0.0)) {
            return Err(format!("--rpm {n}: want a speed above 0 rpm"));
        }
        let all = all_machines();
        let names: Vec<&str> = all.iter().map(|m| m.name).collect();
        if let Some(name) = &self.machine
            && !names.contains(&name.as_str())
        {
            return Err(format!(
                "--machine: unknown machine {name:?}; valid: {}",
                names.join(", ")
            ));
        }
        let settings = self.settings()?;
        let mut out = Vec::new();
        for mut m in all {
            if self.machine.as_ref().is_some_and(|n| n != m.name) {
                continue;
            }
            apply(&mut m, &settings, self.rpm, self.gear.is_some());
            out.push(m);
        }
        Ok(out)
    }
}

/// A drive parameter's value in a machine (its own setting, else the FMU's start value).
fn drive_param(m: &Machine, name: &str) -> f64 {
    m.components[0]
        .params
        .iter()
        .find(|(p, _)| *p == name)
        .map(|p| p.1)
        .or_else(|| {
            <<MainShaft as bindery_fmu::model::Model>::Var as VarSet>::table()
                .iter()
                .find(|v| v.name == name)
                .and_then(|v| v.start)
        })
        .unwrap_or(f64::NAN)
}

/// Sets the drive's parameters; the nominal speed is `rpm` if given (with the gear ratio that
/// makes it the motor's synchronous speed, unless the gear is set), else the synchronous speed
/// through the gear whenever a setting changes either.
fn apply(m: &mut Machine, settings: &[Setting], rpm: Option<f64>, gear_given: bool) {
    let drive = &mut m.components[0];
    for s in settings {
        drive.params.retain(|(p, _)| *p != s.name);
        drive.params.push((s.name, s.value));
    }
    let n_sync = drive_param(m, "motor.n_rated") / (1.0 - drive_param(m, "motor.s_rated"));
    let moved = |n: &str| settings.iter().any(|s| s.name == n);
    if let Some(n) = rpm {
        m.nominal_w = n * std::f64::consts::PI / 30.0;
        if !gear_given {
            let drive = &mut m.components[0];
            drive.params.retain(|(p, _)| *p != "gear.i");
            drive.params.push(("gear.i", n_sync / m.nominal_w));
        }
    } else if moved("gear.i") || moved("motor.n_rated") || moved("motor.s_rated") {
        m.nominal_w = n_sync / drive_param(m, "gear.i");
    }
    for (p, x) in &mut m.components[0].params {
        if *p == "init.w" {
            *x = m.nominal_w;
        }
    }
}

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

/// A flywheel as the table and the legend both write it (one decimal: 5.5, 7959.0).
fn fly_text(j: f64) -> String {
    format!("{j:.1}")
}

/// The nominal speed of a machine as defined, rad/s.
fn default_nominal(name: &str) -> f64 {
    all_machines()
        .iter()
        .find(|m| m.name == name)
        .map_or(f64::NAN, |m| m.nominal_w)
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

pub fn machines(out: &Option<PathBuf>, options: &Options) -> Result<(), String> {
    let machines = options.machines()?;
    let out = &folder(out, "out/machines")?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut md = String::new();
    let mut rows = String::new();
    let mut figures = Vec::new();
    let table = <<MainShaft as bindery_fmu::model::Model>::Var as VarSet>::table();
    let settings = options.settings()?;
    if !settings.is_empty() || options.rpm.is_some() {
        let mut said: Vec<String> = settings
            .iter()
            .map(|s| format!("{} = {}", s.name, shown(&table[s.vr as usize], s.value)))
            .collect();
        said.extend(options.rpm.map(|n| format!("nominal speed {n} rpm")));
        let _ = writeln!(md, "Drive settings: {}.\n", said.join(", "));
    }
    for m in machines {
        let mut s = setup(&m);
        // as many turns as at the default speed
        let slower = (default_nominal(m.name) / m.nominal_w).max(1.0);
        s.stop *= slower;
        s.startup_stop *= slower;
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
            "| {} | {:.1} | {:.1} | {} | {:.4} (1/{:.0}) | {} | {:.1} | {:.1} | {} |",
            m.name,
            m.nominal_w * RPM,
            st.w_mean * RPM,
            number(j0, 4),
            st.delta,
            1.0 / st.delta,
            j40.map_or(format!("not below {}", number(s.fly_hi, 3)), |j| format!(
                "{} ({:.3} at the motor)",
                fly_text(j),
                j / (i2 * i2)
            )),
            st.tau_peak,
            st.tau_rms,
            t95.map_or("not reached".into(), |t| format!("{t:.2}")),
        );
        let mut series = vec![Series::new(
            format!("fly.J = {} kg.m2", number(j0, 4)),
            cycles(&run, s.turns),
        )];
        if let (Some(r), Some(j)) = (&run40, j40) {
            series.push(Series::new(
                format!("fly.J = {} kg.m2 (delta = 1/40)", fly_text(j)),
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
            markers: false,
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
            markers: false,
        });
    }
    md += "| machine | nominal, rpm | running speed, rpm | fly.J, kg.m2 | delta | fly.J for delta <= 1/40, kg.m2 | peak motor torque, N.m | RMS motor torque, N.m | start-up to 95 %, s |\n";
    md += "| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    md += &rows;
    md += "\nMotor torque at the motor shaft over the steady turns; delta over the same turns; start-up from rest to 95 % of the running speed (trimmer: without the cutting load).\n\n";
    for f in &figures {
        let path = out.join(&f.file);
        std::fs::write(&path, render_png(f)?).map_err(|e| format!("{}: {e}", path.display()))?;
        eprintln!("wrote {}", path.display());
        let _ = writeln!(md, "![{}]({})\n", f.title, f.file);
    }
    let path = out.join("machines.md");
    std::fs::write(&path, &md).map_err(|e| format!("{}: {e}", path.display()))?;
    eprintln!("wrote {}\n{md}", path.display());
    Ok(())
}
