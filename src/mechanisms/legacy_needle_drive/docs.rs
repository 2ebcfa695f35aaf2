//! The LegacyNeedleDrive FMU's `documentation/`: the mechanism, every variable, and figures drawn
//! from [`super::physics`] (paper 002), with the Perforators beside it at equal needle motion.

use super::compare::{legacy_turn, new_turn};
use super::model::LegacyNeedleDrive;
use super::physics::{Drive, Params, Timing};
use crate::docs::{
    Documentation, Figure, Question, Series, Sweep, model_page, number, over_turn, sweep,
};
use crate::mechanisms::perforators::physics::Params as PerforatorsParams;
use std::f64::consts::PI;

const WHAT: &str = r#"<p>The needle drive of the existing thread-sewing automat (NSh-6), the drive the
Perforators' ramp and lever replace. Two cams on the main shaft each drive the needle bar through
three contours: the cam moves the roller of a rocker (the cam-rocker pair), the rocker is one bell
crank with the crank of a four-bar, whose rocker is one bell crank with the arm of a rocker-slider,
whose rod lifts the bar of needles along its guide. Paper 002 carries the load of the needles
through every link with the friction in its hinges, finds the cam-roller contact the most loaded
place of the drive, and shows that a longer rocker arm (&beta; = L<sub>rocker</sub>/l<sub>k</sub>
from 0.48 to 1) lowers its contact stress 1.83-fold.</p>
<p>Drive it through <code>shaft.phi</code>, <code>shaft.w</code>, <code>shaft.a</code> or let it run
alone (<code>drive.mode</code>); it gives the needles' motion, the force in every link, the
cam-roller force and its Hertz stress, and the drive's share of the shaft torque. Its needle,
table and load parameters are the Perforators' (same names, meanings and defaults): set both alike
and their needles move alike, so the two drives can be compared at equal needle motion.</p>"#;

const NOTES: &str = r#"<p>The bar's displacement is the independent variable: the cam is made for the
needle law (<code>needle.timing</code>: <code>perforators</code>, the Perforators' needle curve over
the table's forward travel and at rest for the rest of the turn; or <code>own</code>, paper 002's
cycloidal rise and harmonic fall at the <code>needle.*</code> angles). From the bar the chain is
closed back to the roller by two circle intersections (<code>kpm.branch</code>,
<code>fb.branch</code>), exactly, with the derivatives by dual numbers: the rocker's angle
<code>rocker.psi</code>, the cam's pressure angle <code>cam.theta</code> and the curvature radius of
its pitch curve <code>cam.rho</code> follow.</p>
<p>Level <code>kinetostatic</code> (default): the load of one branch (<code>load.Q</code>: piercing
load, friction and spring loads, the bar's weight and its inertia times <code>load.Kd</code>, over
<code>legacy.branches</code>) is carried through the rod, the two bell cranks and the coupler to the
roller (paper 002, eqs. 2-7), with the guide's friction and each hinge's friction as a relative arm
f&middot;r/&ell; that lowers the efficiency of its link; the cam-roller force <code>roller.F</code>
and its Hertz stress on the loaded flank (eq. 8). The shaft torque is what the roller's force
needs on the rocker, with every branch: without friction it equals the bar's power over the shaft
speed exactly (virtual work), with friction it is larger. A groove cam
(<code>cam.closure</code> = <code>groove</code>, default) pushes with either flank; with
<code>spring</code> the cam can only push, and where it would have to pull
<code>roller.lost_contact</code> turns true and a warning names the shaft angle, once per turn.</p>
<p>The paper prints one size of the drive, &beta; = 0.48; every other size is an assumption, chosen
so that at mid-stroke both bell cranks are horizontal and both rods vertical, and visible as a
parameter. The table's motion is left out (the needles pierce while the table rests). There is no
elastodynamic level: the paper gives no compliance of the links.</p>"#;

const RPM: f64 = PI / 30.0;

/// The chain at bar position `s`: the links as one polyline, mm.
fn chain_at(d: &Drive, s: f64) -> Vec<(f64, f64)> {
    let q = d.pose(s).expect("the defaults assemble");
    let mm = |p: [f64; 2]| (1000.0 * p[0], 1000.0 * p[1]);
    let nan = (f64::NAN, f64::NAN);
    vec![
        mm([0.0, 0.0]),
        mm(q.k),
        nan,
        mm(q.k),
        mm(d.o2),
        mm(q.a),
        mm(q.b),
        mm(d.p.o3),
        mm(q.c),
        mm(q.d),
        nan,
        mm([q.d[0], q.d[1] - 0.03]),
        mm([q.d[0], q.d[1] + 0.03]),
    ]
}

/// The largest σ_H in the run-up of the rise over β, `own` timing, 100 rpm, MPa.
pub fn beta_study() -> Vec<(f64, f64)> {
    (0..=20)
        .map(|i| {
            let beta = 0.4 + 0.05 * i as f64;
            let d = Params {
                timing: Timing::Own,
                beta,
                ..Params::default()
            }
            .drive();
            let s = d.map_or(f64::NAN, |d| d.run_up_stress(100.0 * RPM, 4000));
            (beta, 1e-6 * s)
        })
        .collect()
}

/// Figures with the default parameters at 100 rpm.
pub fn figures() -> Vec<Figure> {
    let (d, own) = (
        Drive::default_with(Timing::Perforators),
        Drive::default_with(Timing::Own),
    );
    let perforators = PerforatorsParams::default()
        .drive()
        .expect("the defaults assemble");
    let w = 100.0 * RPM;
    let n = 720;
    let (turn_d, turn_own) = (legacy_turn(&d, w, n), legacy_turn(&own, w, n));
    let mpa =
        |t: &[(f64, f64)]| -> Vec<(f64, f64)> { t.iter().map(|p| (p.0, 1e-6 * p.1)).collect() };
    vec![
        Figure {
            equal_axes: true,
            ..Figure::lines(
                "chain.png",
                "The three contours, needles lowest and highest",
                "x, mm",
                "y, mm",
                vec![
                    Series::new("needles lowest", chain_at(&d, 0.0)),
                    Series::new("needles highest", chain_at(&d, d.stroke)),
                ],
                "Cam shaft O1 at the origin, roller K on the rocker O2K (the cam-rocker pair), crank O2A of the four-bar O2A-AB-BO3, arm O3C of the rocker-slider, rod CD to the needle bar on its vertical guide (the default sizes).",
            )
        },
        Figure::lines(
            "needle_motion.png",
            "Needle motion over a turn",
            "shaft angle phi, deg",
            "perforators.s, mm",
            vec![
                Series::new(
                    "needle.timing = perforators",
                    over_turn(n, |phi| 1000.0 * d.kinematics(phi, w, 0.0).s),
                ),
                Series::new(
                    "needle.timing = own",
                    over_turn(n, |phi| 1000.0 * own.kinematics(phi, w, 0.0).s),
                ),
                Series::new(
                    "Perforators (new drive)",
                    over_turn(n, |phi| 1000.0 * perforators.kinematics(phi, w, 0.0).s),
                ),
            ],
            "With the perforators timing the legacy cam moves the needles as the Perforators' ramp does on the forward travel (the ramp lifts them once more, idle, on the return); the own timing is paper 002's cycloidal rise and harmonic fall.",
        ),
        Figure::lines(
            "cam_force.png",
            "Cam-roller force and Hertz stress at 100 rpm",
            "shaft angle phi, deg",
            "roller.F, N / roller.sigma_H, MPa",
            vec![
                Series::new("roller.F, perforators timing", turn_d.roller_f.clone()),
                Series::new("roller.sigma_H, perforators timing", mpa(&turn_d.sigma_h)),
                Series::new("roller.F, own timing", turn_own.roller_f.clone()),
                Series::new("roller.sigma_H, own timing", mpa(&turn_own.sigma_h)),
            ],
            "The force of one branch's cam on its roller (paper 002, eq. 7) and the Hertz stress on the loaded flank (eq. 8), groove cam, with the piercing load while the needles rise.",
        ),
        Figure::lines(
            "torque.png",
            "Shaft torque: legacy against new drive at 100 rpm",
            "shaft angle phi, deg",
            "shaft.tau, N.m",
            vec![
                Series::new("LegacyNeedleDrive (both branches)", turn_d.tau.clone()),
                Series::new("Perforators", new_turn(&perforators, w, n).tau),
            ],
            "The needle drives' share of the main-shaft torque at equal needle motion and piercing load.",
        ),
        Figure::lines(
            "beta_study.png",
            "Paper 002's study: a longer rocker arm lowers the contact stress",
            "kmk.beta = L_rocker / l_k",
            "largest roller.sigma_H in the run-up, MPa",
            vec![Series::new("own timing, 100 rpm", beta_study())],
            format!(
                "The largest Hertz stress cam-roller over the run-up of the rise (where the rocker accelerates), the rocker's swing held: raising beta from the NSh-6's 0.48 to 1 lowers it {}-fold here (the paper: 1.83 with its unknown sizes).",
                number(beta_ratio(), 3)
            ),
        ),
    ]
}

/// The questions a designer brings, answered at the defaults.
fn questions(s: &Sweep) -> Vec<Question> {
    vec![
        Question::new(
            "How do the needles move?",
            &["perforators.s", "perforators.v", "perforators.a"],
            format!(
                "stroke {}; velocity peaks at {}, acceleration at {}",
                s.value("perforators.stroke"),
                s.peak("perforators.v"),
                s.peak("perforators.a")
            ),
        ),
        Question::new(
            "Which force and stress does the cam carry?",
            &["roller.F", "roller.sigma_H"],
            format!(
                "cam-roller force {}, Hertz stress {} (one branch)",
                s.peak("roller.F"),
                s.peak("roller.sigma_H")
            ),
        ),
        Question::new(
            "How well does each contour transmit the force?",
            &["rod.alpha", "fb.mu", "fb.delta_psi", "cam.theta"],
            format!(
                "pressure angle of the cam {}, of the rocker-slider {}; transmission angle of the four-bar {}",
                s.peak("cam.theta"),
                s.peak("rod.alpha"),
                s.peak("fb.mu")
            ),
        ),
        Question::new(
            "Which share of the main-shaft torque?",
            &["shaft.tau"],
            format!("peak {}, RMS {}", s.peak("shaft.tau"), s.rms("shaft.tau")),
        ),
        Question::new(
            "How much does a longer rocker arm help?",
            &["kmk.beta", "roller.sigma_H"],
            format!(
                "from beta = 0.48 to 1 the largest stress in the run-up falls {}-fold (figure)",
                number(beta_ratio(), 3)
            ),
        ),
    ]
}

/// The β study's ratio 0.48 → 1.
pub fn beta_ratio() -> f64 {
    let at = |beta: f64| {
        Params {
            timing: Timing::Own,
            beta,
            ..Params::default()
        }
        .drive()
        .map_or(f64::NAN, |d| d.run_up_stress(100.0 * RPM, 4000))
    };
    at(0.48) / at(1.0)
}

/// `documentation/` files (index.html first) and the icon.
pub fn documentation() -> Result<Documentation, String> {
    let s = sweep::<LegacyNeedleDrive>()?;
    model_page::<LegacyNeedleDrive>(WHAT, figures(), &questions(&s), NOTES, &s, "Legacy needles")
}
