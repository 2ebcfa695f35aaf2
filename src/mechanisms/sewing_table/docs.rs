//! The SewingTable FMU's `documentation/`: what the mechanism is, every variable, and figures
//! redrawn from [`super::physics`] (paper 000).

use super::model::SewingTable;
use super::physics::{Kind, Params};
use crate::docs::{
    Documentation, Figure, Question, Series, Sweep, model_page, number, over_turn as turn, sweep,
};
use std::f64::consts::PI;

const WHAT: &str = r#"<p>A thread-sewing machine sews book blocks signature by signature. Its table takes a
half-open signature on its saddle at the loading position, carries it to the sewing position under
the sewing carriage, dwells while it is sewn, and returns. This FMU is the <b>translating table</b>
that paper 000 puts in place of the machine's rocking table: a slot cam on the main shaft moves the
table through a roller and pusher, in a cyclogram of forward travel, dwell at sewing, return and
dwell at loading.</p>
<p>Drive it through <code>shaft.phi</code>, <code>shaft.w</code>, <code>shaft.a</code> or let it run
alone (<code>drive.mode</code>); it gives the table's motion, the cam's pressure angle, contact force
and Hertz stress, and the torque the main shaft needs. The perforators ride on this table: wire
<code>Perforators.table.F</code> into <code>table.F_ext</code>.</p>"#;

const NOTES: &str = r#"<p>Slot cam 1 on the main shaft, roller 2, pusher 3 fixed to table 4 with saddle 4',
running on rollers 5, 5' in guides 6. The table's travel l<sub>2</sub> = 3.72 relative units
(0.11152 m with the 30 mm unit) follows from the rocking table's geometry (calculated parameters
<code>synth.*</code>). The motion laws <code>law.forward</code>, <code>law.return</code> are cycloidal by
default: the smooth stop at the sewing position.</p>
<p>Level <code>kinetostatic</code> (default) adds inertia, guide friction, the external force
<code>table.F_ext</code>, the slot cam's pressure angle, contact force, loaded-flank curvature and Hertz
stress, and the shaft torque. A cam whose convex flank would be undercut is refused at initialization,
naming the angle and the smallest <code>cam.R0</code> (also given as <code>cam.R0_min</code>).
<code>table.kind</code> = <code>rocking</code> computes the rocking table it replaces with the same
cyclogram; the outputs <code>rocking.*</code> are always given for comparison. Level
<code>elastodynamic</code> ties the table to its rigid motion through the follower chain's stiffness
<code>elastic.k</code>, with optional play in the cam slot <code>cam.clearance</code>: the roller leaves
a flank, crosses the play and impacts the other (<code>contact.liftoffs</code>,
<code>contact.F_impact</code>); its equation of motion is integrated inside <code>fmi2DoStep</code> and
offered to Model Exchange hosts.</p>
<p>On the synthesis: the paper's k<sub>0</sub> = k<sub>1</sub> &minus; k<sub>2</sub> subtracts the saddle's
height at loading from the distance of the chord A<sub>1</sub>A<sub>2</sub> to the axis; the saddle's
true end-to-end displacement on its circle is 3.686 horizontally and 1.003 vertically (chord 3.82).
The FMU keeps the paper's l<sub>2</sub> = 3.72 as the translating table's travel.</p>"#;

fn fig(file: &str, title: &str, y: &str, series: Vec<Series>, caption: &str) -> Figure {
    Figure::lines(file, title, "shaft angle phi, deg", y, series, caption)
}

/// Figures with the default parameters at the nominal 100 rpm.
pub fn figures() -> Vec<Figure> {
    let p = Params::default();
    let w = 100.0 * PI / 30.0;
    let k = |phi: f64| p.kinematics(phi, w, 0.0);
    let n = 720;
    let rocking = Params {
        kind: Kind::Rocking,
        ..p
    };
    vec![
        fig(
            "table_x.png",
            "Table position over one turn",
            "table.x, mm",
            vec![Series::new("table.x", turn(n, |f| 1000.0 * k(f).c.x))],
            "The cyclogram of the table (paper 000, Fig. 2 a): forward travel 82 deg, dwell at sewing 110 deg, return 90 deg, dwell at loading 78 deg.",
        ),
        fig(
            "table_v.png",
            "Table velocity at 100 rpm",
            "table.v, m/s",
            vec![Series::new("table.v", turn(n, |f| k(f).v))],
            "Velocity of the translating table, cycloidal laws.",
        ),
        fig(
            "table_a.png",
            "Table acceleration at 100 rpm",
            "table.a, m/s2",
            vec![Series::new("table.a", turn(n, |f| k(f).a))],
            "Acceleration: it fades smoothly to zero before the sewing position, which positions the saddle precisely (paper 000).",
        ),
        fig(
            "cam_theta_sigma.png",
            "Pressure angle of the slot cam",
            "cam.theta, deg",
            vec![Series::new(
                "cam.theta",
                turn(n, |f| k(f).theta.to_degrees()),
            )],
            "Pressure angle theta_p = atan(x'/(R0 + x)) with cam.R0 = 100 mm.",
        ),
        fig(
            "cam_sigma_H.png",
            "Hertz stress on the loaded flank at 100 rpm",
            "cam.sigma_H, MPa",
            vec![Series::new(
                "cam.sigma_H",
                turn(n, |f| 1e-6 * p.forces(&k(f), 0.0, 0.0).sigma_h),
            )],
            "Hertz stress (paper 002, eq. 8) on the loaded slot flank; the dwells carry only the friction load.",
        ),
        fig(
            "shaft_tau.png",
            "Shaft torque: translating and rocking table at 100 rpm",
            "shaft.tau, N.m",
            vec![
                Series::new("translating", turn(n, |f| p.forces(&k(f), 0.0, 0.0).tau)),
                Series::new(
                    "rocking",
                    turn(n, |f| {
                        rocking.rocking_tau(&rocking.rocking(f, w, 0.0), 0.0, 0.0)
                    }),
                ),
            ],
            "Shaft torque of the translating table and of the rocking table (rocking.J = 0.8712 kg.m2, assumption) with the same cyclogram.",
        ),
        Figure {
            x_label: "x, mm".into(),
            equal_axes: true,
            markers: false,
            ..fig(
                "rocking_saddle.png",
                "Saddle paths: rocking and translating table",
                "y, mm",
                vec![
                    Series::new(
                        "rocking saddle",
                        (0..=n)
                            .map(|i| {
                                let r = p.rocking(2.0 * PI * i as f64 / n as f64, w, 0.0);
                                (1000.0 * r.x, 1000.0 * r.y)
                            })
                            .collect(),
                    ),
                    Series::new(
                        "translating saddle",
                        vec![(0.0, 0.0), (1000.0 * p.stroke(), 0.0)],
                    ),
                ],
                "The rocking table's saddle moves on an arc of radius R = 330 mm, rising 30 mm; the translating table's saddle moves on a line.",
            )
        },
    ]
}

/// The questions a designer brings, answered at the defaults.
fn questions(s: &Sweep) -> Vec<Question> {
    vec![
        Question::new(
            "How far does the table travel, and when?",
            &["table.x", "table.phase"],
            format!(
                "travel {} ({}); shaft angles: forward {}, dwell at sewing {}, return {}, dwell at loading {}",
                s.value("table.stroke"),
                s.range("table.x"),
                s.value("cycle.forward"),
                s.value("cycle.dwell_sew"),
                s.value("cycle.return"),
                s.value("cycle.dwell_load")
            ),
        ),
        Question::new(
            "How fast does it move?",
            &["table.v", "table.a"],
            format!(
                "velocity peaks at {}, acceleration at {}",
                s.peak("table.v"),
                s.peak("table.a")
            ),
        ),
        Question::new(
            "How steep is the cam?",
            &["cam.theta"],
            format!("pressure angle up to {}", s.peak("cam.theta")),
        ),
        Question::new(
            "Which force and stress does the cam carry?",
            &["cam.F", "cam.sigma_H"],
            format!(
                "contact force {}, Hertz stress {}",
                s.peak("cam.F"),
                s.peak("cam.sigma_H")
            ),
        ),
        Question::new(
            "How small may the cam be?",
            &["cam.R0_min"],
            format!(
                "smallest base radius without undercut {} (cam.R0 = {})",
                s.value("cam.R0_min"),
                s.value("cam.R0")
            ),
        ),
        Question::new(
            "Which torque does the main shaft need?",
            &["shaft.tau"],
            format!("peak {}, RMS {}", s.peak("shaft.tau"), s.rms("shaft.tau")),
        ),
        Question::new(
            "And the rocking table it replaces?",
            &["rocking.M_inertia"],
            format!("inertia torque up to {}", s.peak("rocking.M_inertia")),
        ),
        Question::new(
            "How much does the follower chain's compliance raise the force?",
            &["dyn.factor", "elastic.F"],
            format!(
                "dynamic factor K_d = {} (elastodynamic level, elastic.k = {}); chain force {}",
                number(s.stat("dyn.factor").map_or(f64::NAN, |d| d.max), 3),
                s.value("elastic.k"),
                s.peak("elastic.F")
            ),
        ),
    ]
}

/// `documentation/` files (index.html first) and the icon.
pub fn documentation() -> Result<Documentation, String> {
    let s = sweep::<SewingTable>()?;
    model_page::<SewingTable>(WHAT, figures(), &questions(&s), NOTES, &s, "Sewing table")
}
