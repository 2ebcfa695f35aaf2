//! The SewingTable FMU's `documentation/`: what the mechanism is, every variable, and figures
//! redrawn from [`super::physics`] (paper 000).

use super::model::SewingTable;
use super::physics::{Kind, Params};
use crate::catalog::{Documentation, variables_of};
use crate::docs::{Figure, Series, icon_png};
use crate::md::ModelInfo;
use std::f64::consts::PI;

const INTRO: &str = r#"<p>A thread-sewing machine (analogue: the BNSh-6A) sews book blocks signature by
signature. Its rocking table takes a half-open signature on its saddle at the loading position I,
carries it to the sewing position III under the sewing carriage, dwells while it is sewn, and returns.
Paper 000 replaces it by a <b>translating table</b>: slot cam 1 on the main shaft, roller 2, pusher 3
fixed to table 4 with saddle 4', running on rollers 5, 5' in guides 6. Its travel
l<sub>2</sub> = 3.72 relative units (0.11152 m with the 30 mm unit) follows from the rocking table's
geometry (calculated parameters <code>synth.*</code>).</p>
<p>One shaft turn: forward travel (<code>cycle.forward</code>, 82&deg;), dwell at sewing, return, dwell at
loading, with the laws <code>law.forward</code>, <code>law.return</code> (cycloidal by default: the
smooth stop at the sewing position). Level <code>kinetostatic</code> adds inertia, guide friction, the
external force <code>table.F_ext</code> (e.g. the perforators' reaction <code>Perforators.table.F</code>),
the slot cam's pressure angle, contact force, loaded-flank curvature and Hertz stress, and the shaft
torque. A cam whose convex flank would be undercut is refused at initialization, naming the angle and
the smallest <code>cam.R0</code> (also given as <code>cam.R0_min</code>).</p>
<p><code>table.kind</code> = <code>rocking</code> computes the rocking table it replaces, with the same
cyclogram applied to its swing; the outputs <code>rocking.*</code> (saddle path, inertia torque) are
always given for comparison.</p>
<p>Note on the synthesis: the paper's k<sub>0</sub> = k<sub>1</sub> &minus; k<sub>2</sub> subtracts the
saddle's height at loading from the distance of the chord A<sub>1</sub>A<sub>2</sub> to the axis; the
saddle's true end-to-end displacement on its circle is 3.686 horizontally and 1.003 vertically (chord
3.82). The FMU keeps the paper's l<sub>2</sub> = 3.72 as the translating table's travel.</p>"#;

fn turn(n: usize, f: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    (0..=n)
        .map(|k| {
            let phi = 2.0 * PI * k as f64 / n as f64;
            (phi.to_degrees(), f(phi))
        })
        .collect()
}

fn fig(file: &str, title: &str, y: &str, series: Vec<Series>, caption: &str) -> Figure {
    Figure {
        file: file.into(),
        title: title.into(),
        x_label: "shaft angle phi, deg".into(),
        y_label: y.into(),
        series,
        caption: caption.into(),
        equal_axes: false,
    }
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

/// `documentation/` files (index.html first) and the icon.
pub fn documentation() -> Result<Documentation, String> {
    let vars = variables_of::<SewingTable>();
    let files =
        crate::docs::documentation(&ModelInfo::of::<SewingTable>(), &vars, INTRO, &figures())?;
    Ok((files, icon_png("Sewing table")?))
}
