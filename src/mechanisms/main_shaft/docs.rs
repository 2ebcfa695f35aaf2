//! The MainShaft FMU's `documentation/`: what it is, every variable, the motor's torque–speed
//! characteristic and a start-up, drawn from [`super::physics`].

use super::model::MainShaft;
use super::physics::{Load, Params};
use crate::docs::{Documentation, Figure, Question, Series, Sweep, defaults, model_page, number};

const WHAT: &str = r#"<p>The drive of a bookbinding machine's <b>main shaft</b>: an induction motor, a gear
pair of ratio <code>gear.i</code> to the main shaft, a flywheel <code>fly.J</code> and the bearings'
friction. It drives what the mechanism FMUs are driven by: connect its <code>shaft.phi</code>,
<code>shaft.w</code>, <code>shaft.a</code> to their shaft inputs, and each mechanism's
<code>shaft.tau0</code> and <code>shaft.J_red</code> back to an input pair <code>load1..3.tau0</code>,
<code>load1..3.J_red</code>. The papers give no drive data: every motor and flywheel value is an
assumption, visible as a parameter.</p>"#;

const NOTES: &str = r#"<p>The motor's torque&ndash;speed characteristic follows <b>Kloss's formula</b>
M = 2M<sub>k</sub>/(s/s<sub>k</sub> + s<sub>k</sub>/s) from its rated power, rated speed, rated slip and
breakdown-torque ratio. The mechanisms' torque is <code>shaft.tau0 + shaft.J_red*shaft.a</code>, so
the shaft's acceleration is solved with their inertia on the left-hand side:</p>
<p>(fly.J + i&sup2;&middot;motor.J + &Sigma;J<sub>red</sub>)&middot;&epsilon; = i&middot;M(i&omega;)
&minus; M<sub>f</sub>(&omega;) &minus; load.tau &minus; &Sigma;&tau;<sub>0</sub></p>
<p>which stays stable whatever the mechanisms' inertia. Feeding a mechanism's whole torque
<code>shaft.tau</code> to <code>load.tau</code> instead (plain torque coupling) lets its inertia
torque act one communication step late: that loop has the gain &minus;J<sub>red</sub>/J and
diverges, at any step size, once the mechanisms' reduced inertia exceeds the drive's.</p>
<p>&phi; and &omega; are states, integrated inside <code>fmi2DoStep</code> with the project's
solvers (<code>solver.method</code>); the same binary offers Model Exchange.</p>"#;

/// The characteristic and a start-up under half the rated load with the default parameters,
/// and the start-up time to 95 % of the running speed, s.
pub fn figures() -> (Vec<Figure>, f64) {
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
    let mut t95 = f64::NAN;
    for k in 0..=30_000 {
        if t95.is_nan() && p.steady_speed(load.tau).is_some_and(|run| w >= 0.95 * run) {
            t95 = k as f64 * h;
        }
        if k % 100 == 0 {
            start.push((k as f64 * h, w * rpm));
        }
        w += h * p.point(w, &load).map_or(0.0, |pt| pt.eps);
    }
    let figures = vec![
        Figure::lines(
            "motor_characteristic.png",
            "Motor torque-speed characteristic (Kloss's formula)",
            "motor speed, rpm",
            "motor torque, N.m",
            vec![Series::new("motor.tau", characteristic)],
            format!(
                "Torque of the default {} kW, {} rpm motor from standstill to the synchronous {} rpm: breakdown torque {} times the rated torque.",
                number(m.p_rated / 1e3, 3),
                number(m.w_rated * rpm, 4),
                number(m.w_sync() * rpm, 4),
                number(m.lambda, 3)
            ),
        ),
        Figure::lines(
            "startup.png",
            "Start-up under half the rated load",
            "time, s",
            "shaft.w, rpm",
            vec![Series::new("shaft.w", start)],
            format!(
                "Main-shaft speed from rest with the default flywheel and a constant load of half the motor's rated torque at the main shaft: 95 % of the running speed after {} s.",
                number(t95, 3)
            ),
        ),
    ];
    (figures, t95)
}

/// The questions a designer brings, answered at the defaults; `t95` the start-up time, s.
fn questions(s: &Sweep, t95: f64) -> Vec<Question> {
    vec![
        Question::new(
            "At what speed does the main shaft run?",
            &["shaft.n_sync", "shaft.w"],
            format!(
                "below the synchronous {} by the motor's slip under load (gear.i = {})",
                s.value("shaft.n_sync"),
                s.value("gear.i")
            ),
        ),
        Question::new(
            "Which torque can the motor give?",
            &["motor.tau_rated", "motor.tau_break", "motor.tau"],
            format!(
                "rated {}, breakdown {} at the motor shaft ({} rated power)",
                s.value("motor.tau_rated"),
                s.value("motor.tau_break"),
                s.value("motor.P_rated")
            ),
        ),
        Question::new(
            "How much inertia does the drive add at the main shaft?",
            &["drive.J"],
            format!("{} (flywheel fly.J = {} plus the rotor through the gear)", s.value("drive.J"), s.value("fly.J")),
        ),
        Question::new(
            "How long does it take to start?",
            &["shaft.w"],
            format!("{} s to 95 % of the running speed under half the rated load (figure)", number(t95, 3)),
        ),
        Question::new(
            "How fast does the speed fluctuate with the mechanisms coupled?",
            &["shaft.w", "shaft.tau_load"],
            "it depends on the mechanisms coupled: couple them as above (the project's `machines` command computes it for its two machines)".to_string(),
        ),
    ]
}

/// `documentation/` files (index.html first) and the icon.
pub fn documentation() -> Result<Documentation, String> {
    let s = defaults::<MainShaft>()?;
    let (figs, t95) = figures();
    model_page::<MainShaft>(WHAT, figs, &questions(&s, t95), NOTES, &s, "Main shaft")
}
