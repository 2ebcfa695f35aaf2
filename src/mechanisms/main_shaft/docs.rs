//! The MainShaft FMU's `documentation/`: what it is, every variable, the motor's torque–speed
//! characteristic and a start-up, drawn from [`super::physics`].

use super::model::MainShaft;
use super::physics::{Load, Params};
use crate::catalog::{Documentation, variables_of};
use crate::docs::{Figure, Series, icon_png};
use crate::md::ModelInfo;

const INTRO: &str = r#"<p>The drive of a bookbinding machine's <b>main shaft</b>: an induction motor
(torque&ndash;speed characteristic by <b>Kloss's formula</b> M = 2M<sub>k</sub>/(s/s<sub>k</sub> +
s<sub>k</sub>/s) from its rated power, rated speed, rated slip and breakdown-torque ratio), a gear
pair of ratio <code>gear.i</code> to the main shaft, a flywheel <code>fly.J</code> and the
bearings' Coulomb and viscous friction. The papers give no drive data: every motor and flywheel
value is an assumption, visible as a parameter.</p>
<p>It drives what the mechanism FMUs are driven by: its outputs <code>shaft.phi</code>,
<code>shaft.w</code>, <code>shaft.a</code> go to their shaft inputs. Each mechanism returns its
torque at zero shaft acceleration <code>shaft.tau0</code> and its reduced moment of inertia
<code>shaft.J_red</code> (its torque is <code>shaft.tau0 + shaft.J_red*shaft.a</code>) to the input
pair <code>load1..3.tau0</code>, <code>load1..3.J_red</code>; the shaft's acceleration is then
solved with the mechanisms' inertia on the left-hand side:</p>
<p>(fly.J + i&sup2;&middot;motor.J + &Sigma;J<sub>red</sub>)&middot;&epsilon; = i&middot;M(i&omega;)
&minus; M<sub>f</sub>(&omega;) &minus; load.tau &minus; &Sigma;&tau;<sub>0</sub></p>
<p>which stays stable whatever the mechanisms' inertia. Feeding a mechanism's whole torque
<code>shaft.tau</code> to <code>load.tau</code> instead (plain torque coupling) lets its inertia
torque act one communication step late: that loop has the gain &minus;J<sub>red</sub>/J and
diverges, at any step size, once the mechanisms' reduced inertia exceeds the drive's.</p>
<p>&phi; and &omega; are states, integrated inside <code>fmi2DoStep</code> with the project's
solvers (<code>solver.method</code>); the same binary offers Model Exchange.</p>"#;

/// The characteristic and a no-load start-up with the default parameters.
pub fn figures() -> Vec<Figure> {
    let p = Params::default();
    let m = p.motor;
    let rpm = 30.0 / std::f64::consts::PI;
    let n = 400;
    let characteristic = (0..=n)
        .map(|k| {
            let w = m.w_sync() * k as f64 / n as f64;
            (w * rpm, m.torque(w))
        })
        .collect();
    // start-up with a constant load of half the rated torque at the shaft (explicit Euler on a
    // fine grid: a picture, not a reference)
    let load = Load {
        tau: 0.5 * p.gear_i * m.tau_rated(),
        ..Load::default()
    };
    let (mut w, h) = (0.0, 1e-4);
    let mut start = Vec::new();
    for k in 0..=30_000 {
        if k % 100 == 0 {
            start.push((k as f64 * h, w * rpm));
        }
        w += h * p.point(w, &load).map_or(0.0, |pt| pt.eps);
    }
    vec![
        Figure {
            file: "motor_characteristic.png".into(),
            title: "Motor torque-speed characteristic (Kloss's formula)".into(),
            x_label: "motor speed, rpm".into(),
            y_label: "motor torque, N.m".into(),
            series: vec![Series::new("motor.tau", characteristic)],
            caption: "Torque of the default 1.1 kW, 1400 rpm motor from standstill to the synchronous 1500 rpm: breakdown torque 2.2 times the rated torque.".into(),
            equal_axes: false,
        },
        Figure {
            file: "startup.png".into(),
            title: "Start-up under half the rated load".into(),
            x_label: "time, s".into(),
            y_label: "shaft.w, rpm".into(),
            series: vec![Series::new("shaft.w", start)],
            caption: "Main-shaft speed from rest with the default flywheel and a constant load of half the motor's rated torque at the main shaft.".into(),
            equal_axes: false,
        },
    ]
}

/// `documentation/` files (index.html first) and the icon.
pub fn documentation() -> Result<Documentation, String> {
    let vars = variables_of::<MainShaft>();
    let files =
        crate::docs::documentation(&ModelInfo::of::<MainShaft>(), &vars, INTRO, &figures())?;
    Ok((files, icon_png("Main shaft")?))
}
