//! The Perforators FMU's `documentation/`: the mechanism, every variable, and figures redrawn
//! from [`super::physics`] (papers 000 and 002).

use super::model::Perforators;
use super::physics::{Mode, Params};
use crate::docs::{
    Documentation, Figure, Question, Series, Sweep, model_page, number, over_turn, sweep,
};
use std::f64::consts::PI;

const WHAT: &str = r#"<p>Before a signature is sewn, perforators (a bar of needles) pierce holes in its
fold from inside the saddle. Paper 000 drives them from the translating sewing table: as the table
travels from loading to sewing, a roller on a lever climbs a fixed ramp; over the first half of the
travel the needles rise, piercing on the way, over the second half they withdraw. A tension spring
keeps the roller on the ramp, which can only push: too fast for the spring, and the roller lifts
off.</p>
<p>Drive it through <code>shaft.phi</code>, <code>shaft.w</code>, <code>shaft.a</code> (the main
shaft) or let it run alone (<code>drive.mode</code>); it gives the needles' motion, the ramp contact
force and its margin, the force on the table (<code>table.F</code>, to wire into
<code>SewingTable.table.F_ext</code>) and the perforators' share of the shaft torque.</p>"#;

/// How the drive is modelled; `liftoff` is the lift-off speed at the defaults, rpm.
fn notes(liftoff: f64) -> String {
    format!(
        r#"<p>Fixed ramp 7, roller 8 on two-arm lever 9 pivoted on the table, rod 10, carriage 11
with perforators 12, tension spring 13. The return passes the ramp again with an empty saddle. The
linkage is synthesized by the paper's "reverse" method (eqs. 2-4: &nu; = 28.79&deg;,
&gamma;<sub>&Sigma;</sub> = 28.93&deg;, S<sub>&Sigma;</sub> = 0.7023). Eq. (3) assumes the rod lies on
the carriage line at the top; the exact linkage then moves the carriage 1.0228 units (+2.3 %,
<code>synth.stroke_error</code>). <code>synth.mode</code> = <code>exact</code> (default) builds the
ramp for the swing 28.27&deg; that gives exactly the 30 mm stroke. The ramp is synthesized from the
needle motion law over the table position (<code>law.rise</code>, <code>law.fall</code>,
<code>travel.rise_fraction</code>).</p>
<p>Level <code>kinetostatic</code> (default): piercing load 22 kgf = 215.75 N (paper 002, 12 needles,
16-page signature), carriage inertia including the table's acceleration, guide and hinge friction,
the spring, the ramp contact force and its Hertz stress, and <code>table.F</code>.
<code>shaft.tau</code> is the perforators' share of the main shaft torque through the table cam.
When the spring is too weak for the speed, <code>roller.lost_contact</code> turns true and a warning
names the shaft angle; <code>roller.F_margin</code> is the smallest contact force over the last
turn. With the defaults that happens above {} rpm. Both watch the shaft's path over each step,
sampled every 0.25&deg;: in Co-Simulation each communication step, in Model Exchange the span
between the host's completed integrator steps, so the two interfaces report the same margin.</p>
<p>Level <code>elastodynamic</code>: the lever's rotation is a degree of freedom, its inertia
<code>lever.J</code> plus the carriage reduced to it, held on the ramp by the spring through a
<b>unilateral</b> contact: Hertz line contact K&middot;&delta;<sup>10/9</sup> (<code>contact.law</code> =
<code>hertz</code>, K from the roller width and moduli by Palmgren's formula,
<code>contact.K_hertz</code>) or a linear <code>contact.k</code>, with damping <code>contact.c</code>,
never pulling. The table moves rigidly with the shaft. Above the lift-off speed the roller leaves the
ramp near the top of the rise and lands again: <code>contact.liftoffs</code> counts the flights,
<code>contact.F_impact</code> is the largest landing force, <code>dyn.factor</code> the peak dynamic
over the peak kinetostatic contact force per turn. The peaks are taken at the accepted integration
steps: the FMU's own inside <code>fmi2DoStep</code>, the host's completed steps in Model Exchange. A
landing's compression lasts a fraction of a millisecond: a host completing a step every millisecond
sees 12.9&nbsp;kN of the 16.7&nbsp;kN impact at 130&nbsp;rpm, one completing a step every
20&nbsp;&micro;s 16.71&nbsp;kN. The equation of motion is integrated inside
<code>fmi2DoStep</code> by <code>solver.method</code>, with contact opening and closing, the
cyclogram's phase boundaries and the piercing load's corners located as events; the same
right-hand side is the Model Exchange interface. A spring far too weak for the speed throws the
lever past the rod's dead centre: the step is discarded with a message naming the lever angle.</p>"#,
        number(liftoff, 5)
    )
}

/// The lowest main-shaft speed (rpm) at which the default spring lets the roller lift off.
pub fn liftoff_rpm() -> f64 {
    let rpm = PI / 30.0;
    Params::default()
        .drive()
        .ok()
        .and_then(|d| d.liftoff_speed(10.0 * rpm, 2000.0 * rpm, 1e-6, 7200))
        .map_or(f64::NAN, |w| w / rpm)
}

/// Figures with the default parameters at the nominal 100 rpm; `liftoff` is the lift-off
/// speed, rpm.
pub fn figures(liftoff: f64) -> Vec<Figure> {
    let d = Params::default().drive().expect("defaults assemble");
    let paper = Params {
        mode: Mode::Paper,
        ..Params::default()
    }
    .drive()
    .expect("defaults assemble");
    let w = 100.0 * PI / 30.0;
    let n = 720;
    let turn = |f: &dyn Fn(f64) -> f64| over_turn(n, f);
    let travel = |f: &dyn Fn(f64) -> (f64, f64)| -> Vec<(f64, f64)> {
        (0..=n).map(|k| f(d.cyc.h * k as f64 / n as f64)).collect()
    };
    let profile = |dd: &super::physics::Drive| -> Vec<(f64, f64)> {
        (0..=n)
            .map(|k| {
                let x = dd.cyc.h * k as f64 / n as f64;
                let (c, _, _) = dd.ramp(x);
                let (nrm, _, _) = dd.ramp_geometry(x);
                let r = dd.p.roller.r;
                (1000.0 * (c.0 - r * nrm.0), 1000.0 * (c.1 - r * nrm.1))
            })
            .collect()
    };
    vec![
        Figure::lines(
            "cyclogram.png",
            "Cyclogram: table and perforators",
            "shaft angle phi, deg",
            "displacement / stroke",
            vec![
                Series::new(
                    "table.x / table.stroke",
                    turn(&|f| d.kinematics(f, w, 0.0).x_t / d.cyc.h),
                ),
                Series::new(
                    "perforators.s / stroke",
                    turn(&|f| d.kinematics(f, w, 0.0).s / d.stroke),
                ),
            ],
            "Paper 000, Fig. 2 c: the perforators reach the top at half the forward travel, 41 deg of shaft angle, pierce on the way and withdraw before the sewing position; the return travel lifts them again (idle stroke).",
        ),
        Figure {
            equal_axes: true,
            markers: false,
            ..Figure::lines(
                "ramp_profile.png",
                "The synthesized ramp",
                "x (lever frame at loading), mm",
                "y, mm",
                vec![
                    Series::new(
                        "pitch curve (roller centre)",
                        travel(&|x| {
                            let (c, _, _) = d.ramp(x);
                            (1000.0 * c.0, 1000.0 * c.1)
                        }),
                    ),
                    Series::new("profile, synth.mode = exact", profile(&d)),
                    Series::new("profile, synth.mode = paper", profile(&paper)),
                ],
                "Ramp 7 in the frame of the lever pivot at the loading position: the roller centre's path and the profile (offset by roller.r) for both synthesis modes.",
            )
        },
        Figure::lines(
            "sigma_H.png",
            "Hertz stress roller - ramp over the travel at 100 rpm",
            "table position x_t, mm",
            "roller.sigma_H, MPa",
            vec![Series::new(
                "forward travel",
                (0..=n)
                    .map(|k| {
                        let phi = d.cyc.forward * k as f64 / n as f64;
                        let kk = d.kinematics(phi, w, 0.0);
                        (1000.0 * kk.x_t, 1e-6 * d.forces(&kk).sigma_h)
                    })
                    .collect(),
            )],
            "Hertz stress (paper 002, eq. 8) between roller and ramp on the forward travel, with the piercing load.",
        ),
        Figure::lines(
            "forces.png",
            "Contact force and table reaction at 100 rpm",
            "shaft angle phi, deg",
            "N",
            vec![
                Series::new(
                    "roller.F",
                    turn(&|f| d.forces(&d.kinematics(f, w, 0.0)).roller_f),
                ),
                Series::new(
                    "table.F",
                    turn(&|f| d.forces(&d.kinematics(f, w, 0.0)).table_f),
                ),
                Series::new("rod.F", turn(&|f| d.forces(&d.kinematics(f, w, 0.0)).rod_f)),
            ],
            "The ramp's contact force (must stay positive), the drive's force on the table and the rod force over one turn.",
        ),
        liftoff_figure(liftoff),
    ]
}

/// The elastodynamic contact force against the kinetostatic one over the forward travel at
/// 130 rpm, above the lift-off speed (the model itself, default contact).
fn liftoff_figure(liftoff: f64) -> Figure {
    use super::model::V;
    use crate::model::{Model, NoLog, Values};
    let rpm = 130.0;
    let mut v = Values::<V>::start();
    v[V::model_fidelity] = 3.0;
    v[V::drive_mode] = 2.0;
    v[V::drive_n] = rpm * PI / 30.0;
    let dt = 5e-5;
    let stop = 90f64.to_radians() / (rpm * PI / 30.0);
    let (mut dynamic, mut rigid) = (vec![], vec![]);
    if let Ok(mut m) = Perforators::prepare(&v) {
        m.evaluate(&mut v, 0.0, &mut NoLog);
        for i in 0..(stop / dt).round() as usize {
            let t = i as f64 * dt;
            if m.step(&mut v, t, dt, &mut NoLog).is_err() {
                break;
            }
            m.evaluate(&mut v, t + dt, &mut NoLog);
            let deg = (t + dt) * rpm * 6.0;
            dynamic.push((deg, v[V::elastic_F]));
            rigid.push((deg, v[V::roller_F_kin]));
        }
    }
    let dynamic_peak = dynamic.iter().map(|p| p.1).fold(0.0, f64::max);
    let quantity_n = |x: f64| format!("{} kN", number(x / 1e3, 3));
    Figure::lines(
        "liftoff.png",
        "Contact force at 130 rpm: elastodynamic against kinetostatic",
        "shaft angle phi, deg",
        "N",
        vec![
            Series::new("roller.F_kin (rigid, kinetostatic)", rigid),
            Series::new("elastic.F (elastodynamic, Hertz contact)", dynamic),
        ],
        format!(
            "Above the rigid lift-off speed ({} rpm) the kinetostatic force turns negative near the top of the rise (the ramp would have to pull); the elastic roller leaves the ramp there (force 0) and lands again with impacts of up to {} (contact.F_impact), far above the rigid force.",
            number(liftoff, 5),
            quantity_n(dynamic_peak)
        ),
    )
}

/// The questions a designer brings, answered at the defaults; `liftoff` in rpm.
fn questions(s: &Sweep, liftoff: f64) -> Vec<Question> {
    let margin = s.stat("roller.F").map_or(f64::NAN, |f| f.min);
    vec![
        Question::new(
            "How far do the needles travel?",
            &["perforators.s"],
            format!(
                "stroke {} ({})",
                s.value("perforators.stroke"),
                s.range("perforators.s")
            ),
        ),
        Question::new(
            "How fast?",
            &["perforators.v", "perforators.a"],
            format!(
                "velocity peaks at {}, acceleration at {}",
                s.peak("perforators.v"),
                s.peak("perforators.a")
            ),
        ),
        Question::new(
            "At what speed does the roller lift off the ramp?",
            &["roller.lost_contact", "roller.F_margin"],
            format!(
                "above {} rpm with spring.M0 = {}, spring.kt = {}; at {} rpm the smallest contact force is {} N ({} % margin in speed)",
                number(liftoff, 5),
                s.value("spring.M0"),
                s.value("spring.kt"),
                number(s.rpm, 4),
                number(margin, 3),
                number(100.0 * (liftoff / s.rpm - 1.0), 2)
            ),
        ),
        Question::new(
            "Which force and stress does the ramp carry?",
            &["roller.F", "roller.sigma_H"],
            format!(
                "contact force {}, Hertz stress {}",
                s.peak("roller.F"),
                s.peak("roller.sigma_H")
            ),
        ),
        Question::new(
            "Which load do the needles take?",
            &["pierce.Q_T", "rod.F"],
            format!(
                "piercing load {}, rod force {}",
                s.peak("pierce.Q_T"),
                s.peak("rod.F")
            ),
        ),
        Question::new(
            "Which force acts on the table (for SewingTable.table.F_ext)?",
            &["table.F"],
            s.peak("table.F"),
        ),
        Question::new(
            "Which share of the main-shaft torque?",
            &["shaft.tau"],
            format!("peak {}, RMS {}", s.peak("shaft.tau"), s.rms("shaft.tau")),
        ),
        Question::new(
            "Does it bounce on the ramp?",
            &["contact.liftoffs", "contact.F_impact", "dyn.factor"],
            format!(
                "at {} rpm: {} lift-offs a turn, dynamic factor K_d = {} (elastodynamic level); above {} rpm it lifts off and lands with impacts (figure below)",
                number(s.rpm, 4),
                number(
                    s.stat("contact.liftoffs")
                        .map_or(f64::NAN, |c| c.max - c.min),
                    3
                ),
                number(s.stat("dyn.factor").map_or(f64::NAN, |d| d.max), 3),
                number(liftoff, 5)
            ),
        ),
    ]
}

/// `documentation/` files (index.html first) and the icon.
pub fn documentation() -> Result<Documentation, String> {
    let s = sweep::<Perforators>()?;
    let liftoff = liftoff_rpm();
    let figs = figures(liftoff);
    model_page::<Perforators>(
        WHAT,
        figs,
        &questions(&s, liftoff),
        &notes(liftoff),
        &s,
        "Perforators",
    )
}
