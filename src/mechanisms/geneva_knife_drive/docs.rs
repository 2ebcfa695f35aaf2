//! The GenevaKnifeDrive FMU's `documentation/`: what the mechanism is, every variable, and the
//! paper's Figs. 2-7 (paper 003) redrawn from [`super::physics`].

use super::model::GenevaKnifeDrive;
use super::physics::Params;
use crate::docs::{
    Documentation, Figure, Question, Series, Sweep, model_page, number, over_turn as turn, sweep,
};
use std::f64::consts::PI;

const WHAT: &str = r#"<p>A three-knife trimmer cuts book blocks, brochures and magazines on three sides.
This FMU is the drive of one of its knives (paper 003): a <b>4-slot Geneva mechanism</b> on the
main shaft turns a gear pair and a crank, and a rod moves the knife slider. While the Geneva driver
turns through a quarter of its turn the crank turns once, so the knife makes its working stroke down
through the stack and its idle stroke back up; for the other three quarters the cross is locked and
the knife stands still at the top.</p>
<p>Drive it through <code>shaft.phi</code>, <code>shaft.w</code>, <code>shaft.a</code> (the main
shaft's angle, speed and acceleration) or let it run alone (<code>drive.mode</code>); it gives the
knife's motion, the forces in the chain and the torque the main shaft needs,
<code>shaft.tau</code>.</p>"#;

const NOTES: &str = r#"<p>Driver 1 on the main shaft (angle &phi;) carries a roller that enters the slots
of cross 2 and turns it by 90&deg;; gear 3, fixed to the cross, drives gear 4 with crank 5; rod 6
moves slider 7 with the knife housing in guides 8. The gear ratio <i>i</i> = 4 makes the crank turn
360&deg; while the driver turns 90&deg;.</p>
<p>Level <code>kinematic</code> gives positions, velocities and accelerations in closed form (exact);
<code>kinetostatic</code> (default) adds the cutting resistance, inertia, guide friction, gear losses
and the shaft torque; <code>elastodynamic</code> ties the knife to its rigid motion through the
drive chain's stiffness <code>elastic.k</code> and damping <code>elastic.zeta</code>: the knife sticks
at the cut front while the chain winds up, and cut-through is an event. Its equation of motion is
integrated inside <code>fmi2DoStep</code> (<code>solver.*</code>) and offered to Model Exchange
hosts as states.</p>
<p>Two errata of the paper are not copied: it multiplies the slider's displacement invariant
6 &minus; cos 4&gamma; &minus; 5 cos &nu; by S = 2r<sub>2</sub> (the factor is r<sub>2</sub>), and its
slider velocity leaves out the gear ratio (&theta;' = i&gamma;').</p>"#;

fn figure(
    file: &str,
    title: &str,
    y: &str,
    label: &str,
    points: Vec<(f64, f64)>,
    caption: &str,
) -> Figure {
    Figure::lines(
        file,
        title,
        "driver angle phi, deg",
        y,
        vec![Series::new(label, points)],
        caption,
    )
}

/// The paper's Figs. 2-7 over one driver turn, with the default parameters.
pub fn figures() -> Vec<Figure> {
    let p = Params::default();
    let k = |phi: f64| p.kinematics(phi, 1.0, 0.0);
    let n = 720;
    vec![
        figure(
            "fig2_gamma.png",
            "Fig. 2: cross angle",
            "gamma, rad",
            "gamma(phi)",
            // the left limit at 360 deg: gamma within the index that ends there, not the
            // next index's 0 (a vertical line at the wrap)
            turn(n, |f| k(f.min(2.0 * PI * (1.0 - 1e-12))).gamma),
            "Cross angle within its index over one driver turn (paper 003, Fig. 2).",
        ),
        figure(
            "fig3_gamma_d.png",
            "Fig. 3: cross velocity invariant",
            "gamma' = dgamma/dphi",
            "gamma'(phi)",
            turn(n, |f| k(f).gamma_d),
            "Analogue of the cross's angular velocity; its maximum 1/(lambda-1) = 2.4142 at phi = 45 deg (paper 003, Fig. 3).",
        ),
        figure(
            "fig4_gamma_dd.png",
            "Fig. 4: cross acceleration invariant",
            "gamma'' = d2gamma/dphi2",
            "gamma''(phi)",
            turn(n, |f| k(f).gamma_dd),
            "Analogue of the cross's angular acceleration; it jumps from 0 to 1.0 at entry and exit (paper 003, Fig. 4).",
        ),
        figure(
            "fig5_s.png",
            "Fig. 5: knife displacement invariant",
            "s/r2",
            "s/r2",
            turn(n, |f| k(f).s / p.crank_r),
            "Knife displacement from the top over r2 = the paper's 6 - cos(4 gamma) - 5 cos(nu), 0..2 (paper 003, Fig. 5).",
        ),
        figure(
            "fig6_v.png",
            "Fig. 6: knife velocity invariant",
            "(ds/dphi)/r2",
            "s'/r2",
            turn(n, |f| k(f).s_d / p.crank_r),
            "Knife velocity analogue ds/dphi over r2, with the gear ratio the paper leaves out (paper 003, Fig. 6).",
        ),
        figure(
            "fig7_a.png",
            "Fig. 7: knife acceleration invariant",
            "(d2s/dphi2)/r2",
            "s''/r2",
            turn(n, |f| k(f).s_dd / p.crank_r),
            "Knife acceleration analogue d2s/dphi2 over r2 (paper 003, Fig. 7).",
        ),
        {
            let w = p.drive_n;
            let f = |phi: f64| {
                p.kinetostatics(&p.kinematics(phi, w, 0.0), w, 0.0)
                    .shaft_tau
            };
            figure(
                "shaft_tau.png",
                "Shaft torque at 30 rpm",
                "shaft.tau, N.m",
                "shaft.tau",
                turn(n, f),
                "Torque at the main shaft over one turn at the nominal 30 rpm with the default cutting load (kinetostatic level).",
            )
        },
        {
            // The DefaultExperiment: two driver turns at the nominal 30 rpm.
            let w = p.drive_n;
            let points = (0..=2000).map(|k| {
                let t = 4.0 * k as f64 / 2000.0;
                (t, 1000.0 * p.kinematics(w * t, w, 0.0).s)
            });
            Figure {
                x_label: "time, s".into(),
                ..figure(
                    "knife_two_turns.png",
                    "Knife position over two driver turns (30 rpm)",
                    "knife.s, mm",
                    "knife.s",
                    points.collect(),
                    "Knife displacement from the top, down positive, over two driver turns at 30 rpm: a working and an idle stroke while the cross moves, then a dwell at the top for 3/4 of the turn.",
                )
            }
        },
    ]
}

/// The questions a designer brings, answered at the defaults.
fn questions(s: &Sweep) -> Vec<Question> {
    let dwell = s.stat("knife.dwell").map_or(f64::NAN, |d| d.true_fraction);
    let k_d = s.stat("dyn.factor").map_or(f64::NAN, |d| d.max);
    vec![
        Question::new(
            "How far does the knife travel, and how long does it stand still?",
            &["knife.s", "knife.dwell"],
            format!(
                "stroke {} ({}); at the top for {} % of the driver turn",
                s.value("knife.stroke"),
                s.range("knife.s"),
                number(100.0 * dwell, 3)
            ),
        ),
        Question::new(
            "How fast does the knife move?",
            &["knife.v", "knife.a"],
            format!(
                "up to {}; acceleration up to {}",
                s.peak("knife.v"),
                s.peak("knife.a")
            ),
        ),
        Question::new(
            "What force cuts the stack?",
            &["knife.F_cut"],
            format!(
                "the assumed cutting resistance cut.F_max = {}: {}",
                s.value("cut.F_max"),
                s.peak("knife.F_cut")
            ),
        ),
        Question::new(
            "The knife force in the chain: rod and Geneva slot",
            &["rod.F", "geneva.F"],
            format!(
                "rod.F peaks at {}, geneva.F at {}",
                s.peak("rod.F"),
                s.peak("geneva.F")
            ),
        ),
        Question::new(
            "Which load do the slider guides take?",
            &["guide.N"],
            s.peak("guide.N"),
        ),
        Question::new(
            "Which torque does the main shaft need?",
            &["shaft.tau"],
            format!("peak {}, RMS {}", s.peak("shaft.tau"), s.rms("shaft.tau")),
        ),
        Question::new(
            "What does a drive model need (implicit coupling)?",
            &["shaft.tau0", "shaft.J_red"],
            format!(
                "torque at zero shaft acceleration {}; reduced inertia {}",
                s.range("shaft.tau0"),
                s.range("shaft.J_red")
            ),
        ),
        Question::new(
            "How much does the chain's compliance raise the force?",
            &["dyn.factor", "elastic.F"],
            format!(
                "dynamic factor K_d = {} (elastodynamic level, elastic.k = {}); chain force {}",
                number(k_d, 3),
                s.value("elastic.k"),
                s.peak("elastic.F")
            ),
        ),
    ]
}

/// `documentation/` files (index.html first) and the icon.
pub fn documentation() -> Result<Documentation, String> {
    let s = sweep::<GenevaKnifeDrive>()?;
    let mut figs = figures();
    figs.rotate_right(1);
    model_page::<GenevaKnifeDrive>(WHAT, figs, &questions(&s), NOTES, &s, "Geneva")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fig2_has_no_wrap_around_line() {
        let fig = &figures()[0];
        assert_eq!(fig.file, "fig2_gamma.png");
        let pts = &fig.series[0].points;
        assert_eq!(pts.last().unwrap().0, 360.0);
        // the cross ends the turn locked at the end of its index, as it started it at 0
        assert!((pts.last().unwrap().1 - PI / 2.0).abs() < 1e-9);
        for w in pts.windows(2) {
            assert!((w[1].1 - w[0].1).abs() < 0.05, "a jump at {} deg", w[1].0);
        }
    }
}
