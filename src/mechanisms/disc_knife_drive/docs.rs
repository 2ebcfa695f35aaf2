//! The DiscKnifeDrive FMU's `documentation/`: what the mechanism is, every variable, paper 004's
//! Fig. 2 redrawn from [`super::physics`], the series form's error and the shaft torque.

use super::model::DiscKnifeDrive;
use super::physics::Params;
use crate::catalog::{Documentation, variables_of};
use crate::docs::{Figure, Series, icon_png};
use crate::md::ModelInfo;
use std::f64::consts::TAU;

const INTRO: &str = r#"<p>Flow lines trim the spines of book and magazine blocks without stopping the
block: disc knives on a holder remove the spine in thin layers over several knife cycles, which
lowers the cutting load. Paper 004 drives the holder by a <b>combined crank-slider drive</b>: crank 3
(l<sub>1</sub>) turns with the shaft (angle &phi;) and moves slider 5 (hinge C) through rod 4
(l<sub>2</sub> = &lambda;<sub>2</sub>l<sub>1</sub>, &lambda;<sub>2</sub> = 2); knife holder 6 (CD, length
l<sub>4</sub>) is hinged to slider 5 at C and to slider 7 at D, which slides on the support line EQ at
the angle &alpha; from the vertical through Q. The knives cut at S, l<sub>S</sub>&middot;l<sub>4</sub>
from C. The block is fed at V along &minus;y; each crank turn gives a working stroke (C moving to +x,
<code>knife.working</code>) and an idle stroke.</p>
<p>Positions: x<sub>C</sub> exactly (<code>kinematics.series</code> = true uses the paper's series form
(1)); the holder angle from eq. (5), cos(&beta; + &alpha;) = ((x<sub>Q</sub> &minus; x<sub>C</sub>)cos &alpha;
&minus; (y<sub>Q</sub> &minus; e) sin &alpha;)/l<sub>4</sub>, &beta; = &minus;&alpha; + b&middot;arccos(&hellip;) on
the branch b = <code>assembly.branch</code>; D and S by eqs. (6), (8). Velocities and accelerations are
exact (dual-number differentiation of the position code, chain rule on the shaft inputs). A parameter
set whose holder cannot reach EQ somewhere on the turn is refused at initialization, naming the crank
angles where it fails.</p>
<p>Forces (level <code>kinetostatic</code>): one planar Newton&ndash;Euler system per instant for holder,
slider 5 and slider 7 (unknowns: rod force P, compression positive; the hinge forces at C and D; the
normal forces of both guides), with the inertia of every mass (holder at S, sliders at C and D, rod half
at the crank pin and half at C, crank), the weights (<code>gravity.g</code> along &minus;y, default 0:
horizontal plane), Coulomb friction in both guides by the sign of the sliding velocity and the cutting
force <code>cut.F</code> at S against the velocity of S relative to the block. Shaft torque = crank
torque.</p>
<p><b>Self-locking.</b> Where the holder CD lies within the friction angle of EQ's normal,
|tan(&beta; + &alpha;)| &lt; <code>support.mu</code>, Coulomb friction locks slider 7: the force system has
no unique solution. With the spec's defaults (&alpha; = 45&deg;, &mu; = 0.1) this is the case for
174.63&deg; &lt; &phi; &lt; 185.37&deg;; the FMU flags it (<code>sliders.locked</code>, one warning per
entry), computes the forces there without friction, and the forces rise steeply as the crank leaves
the zone in the working stroke (wedge effect). At &alpha; = 55&deg; and 70&deg; nothing locks.</p>
<p><b>Series form.</b> The paper's x<sub>C</sub> = l<sub>1</sub>(&lambda;<sub>2</sub> + cos &phi; &minus;
sin&sup2;&phi;/(2&lambda;<sub>2</sub>)) overestimates x<sub>C</sub> by at most
l<sub>1</sub>&lambda;<sub>2</sub>(1 &minus; 1/(2&lambda;<sub>2</sub>&sup2;) &minus; &radic;(1 &minus;
1/&lambda;<sub>2</sub>&sup2;)) = 0.341 mm at &phi; = 90&deg; and 270&deg; (l<sub>1</sub> = 19 mm,
&lambda;<sub>2</sub> = 2); the knife point S moves by up to 0.346 mm.</p>
<p><b>Elastodynamic level</b> (<code>model.fidelity</code> = elastodynamic, dynamics.md): rod 4 is an
axial spring (<code>elastic.k</code>, default 2e8 N/m: a steel shank of 60 mm&sup2; over 38 mm,
EA/l<sub>2</sub> = 3.3e8 N/m, in series with two pin bearings of 1e9 N/m, an assumption) with damping
ratio <code>elastic.zeta</code> between the crank pin and slider 5. Slider 5's position x is the one
compliant degree of freedom; holder, knives and slider 7 follow it by the exact kinematics, and the
same 7&times;7 Newton&ndash;Euler system as the kinetostatic level, with the slider's acceleration as
the unknown instead of the rod force, gives its equation of motion: the reduced mass
m<sub>5</sub> + m<sub>7</sub>|dD/dx|&sup2; + m<sub>h</sub>|dS/dx|&sup2; + J<sub>h</sub>(d&beta;/dx)&sup2;
(from 0.85 kg at the outer dead centre to 35 kg at the inner one, near the holder's own dead point),
the normal forces and Coulomb friction of both guides. Friction and cutting force are directed by the
rigid motion. The natural frequency of the default rod, &radic;(k&middot;cos&sup2;&nu;/M)/2&pi;, runs from 2.4 kHz at
the outer dead centre down to 0.38 kHz at the inner one. Outputs: <code>slider.x_kin</code> (rigid reference), <code>elastic.deflection</code>
(rod shortening), <code>elastic.F</code> (dynamic rod force; <code>rod.F</code> and the shaft torque use
it), <code>rod.F_kin</code> (kinetostatic rod force on the rigid motion), <code>dyn.factor</code>
(K<sub>d</sub>: peak dynamic over peak kinetostatic rod force per turn), the energy-balance residual and
solver statistics; the integrator (<code>solver.*</code>) locates the crank dead centres (which are
also the start and end of the working stroke), the reversal of slider 7, the jamming window and a
reversal of the shaft. The same right-hand side is offered through Model Exchange.</p>
<p>The jamming window is treated as at the kinetostatic level (friction dropped, flagged); to keep the
motion continuous the friction fades out over the last 5 % of the jamming indicator before it (the
determinant ratio of the force system, 1 without friction), which caps the wedge's force
amplification at 20&times; where the rigid model's is unbounded. So with the defaults K<sub>d</sub> is
small (a finite dynamic peak of some 13 kN over the rigid wedge's 4.4e6 N): the rigid model jams. On a
jam-free set (<code>support.mu</code> = 0) the default rod gives K<sub>d</sub> = 1.68 at 300 rpm: the
cutting force switching on at the inner dead centre is a step load that rings the rod. A rod soft
enough for slider 5 to overrun the inner dead centre into the holder's own dead point (e.g. 1e6 N/m,
or the default rod at 20&times; the nominal speed) makes the step a Discard that says so.</p>
<p>Not in the paper: l<sub>1</sub>, l<sub>4</sub> and Q are the spec's assumptions, chosen to reproduce
the trend of its Fig. 2 (y-range of S: 16.4, 10.4, 5.9 mm at &alpha; = 45&deg;, 55&deg;, 70&deg;), not its
printed 23 and 6 mm.</p>"#;

/// S over one crank turn in mm, `n` samples.
fn path_of_s(p: &Params, n: usize) -> Vec<(f64, f64)> {
    (0..=n)
        .map(|j| {
            let s = p.kinematics(TAU * j as f64 / n as f64, 1.0, 0.0).s * 1e3;
            (s.x, s.y)
        })
        .collect()
}

/// `f(φ)` over one crank turn, φ in degrees.
fn turn(n: usize, f: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    (0..=n)
        .map(|j| {
            let phi = TAU * j as f64 / n as f64;
            (phi.to_degrees(), f(phi))
        })
        .collect()
}

fn alpha(deg: f64) -> Params {
    Params {
        support_alpha: deg.to_radians(),
        ..Params::default()
    }
}

/// The documentation's figures, from the default parameters.
pub fn figures() -> Vec<Figure> {
    let p = Params::default();
    let n = 720;
    let angles = [45.0, 55.0, 70.0];
    let range = |a: f64| {
        let pts = path_of_s(&alpha(a), 3600);
        let (lo, hi) = pts.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &(_, y)| {
            (lo.min(y), hi.max(y))
        });
        hi - lo
    };
    vec![
        Figure {
            file: "fig2_path_of_S.png".into(),
            title: "Fig. 2: path of the knife point S".into(),
            x_label: "x of S, mm".into(),
            y_label: "y of S, mm".into(),
            series: angles
                .iter()
                .map(|&a| Series::new(format!("alpha = {a} deg"), path_of_s(&alpha(a), n)))
                .collect(),
            caption: "Path of S over one crank turn for three angles of the support line EQ (paper 004, Fig. 2, redrawn with the spec's defaults): the steeper EQ stands, the more S moves across the feed; its y-range is 16.4, 10.4 and 5.9 mm at 45, 55 and 70 deg, and x runs from 27.4 to 62.8 mm at 45 deg.".into(),
            equal_axes: true,
        },
        Figure {
            file: "fig2_y_range.png".into(),
            title: "y-range of S against the angle of EQ".into(),
            x_label: "support.alpha, deg".into(),
            y_label: "max - min of y of S, mm".into(),
            series: vec![Series::new(
                "y-range of S",
                (40..=75).map(|a| (a as f64, range(a as f64))).collect(),
            )],
            caption: "Range of y of S over a crank turn as EQ is set from 40 to 75 deg (the dependence paper 004's Fig. 2 shows).".into(),
            equal_axes: false,
        },
        Figure {
            file: "coordinates_of_S.png".into(),
            title: "Coordinates of S over a crank turn".into(),
            x_label: "crank angle phi, deg".into(),
            y_label: "mm".into(),
            series: angles
                .iter()
                .flat_map(|&a| {
                    let q = alpha(a);
                    [
                        Series::new(
                            format!("x, alpha = {a} deg"),
                            turn(n, |f| q.kinematics(f, 1.0, 0.0).s.x * 1e3),
                        ),
                        Series::new(
                            format!("y, alpha = {a} deg"),
                            turn(n, |f| q.kinematics(f, 1.0, 0.0).s.y * 1e3),
                        ),
                    ]
                })
                .collect(),
            caption: "x and y of S against the crank angle; the working stroke (C moving to +x) is 180..360 deg.".into(),
            equal_axes: false,
        },
        {
            let ps = Params { series: true, ..p };
            Figure {
                file: "series_error.png".into(),
                title: "Error of the series form (1)".into(),
                x_label: "crank angle phi, deg".into(),
                y_label: "series - exact, mm".into(),
                series: vec![
                    Series::new(
                        "x_C",
                        turn(n, |f| {
                            (ps.kinematics(f, 1.0, 0.0).x_c - p.kinematics(f, 1.0, 0.0).x_c) * 1e3
                        }),
                    ),
                    Series::new(
                        "|S|, distance",
                        turn(n, |f| {
                            (ps.kinematics(f, 1.0, 0.0).s - p.kinematics(f, 1.0, 0.0).s).norm()
                                * 1e3
                        }),
                    ),
                ],
                caption: "The paper's series form against the exact slider position (defaults): x_C is overestimated by up to 0.341 mm at 90 and 270 deg (analytic bound), S is off by up to 0.346 mm.".into(),
                equal_axes: false,
            }
        },
        {
            let w = p.drive_n;
            let tau = |q: Params| {
                move |f: f64| {
                    let k = q.kinematics(f, w, 0.0);
                    q.kinetostatics(&k).shaft_tau
                }
            };
            let no_friction = Params {
                guide_mu: 0.0,
                support_mu: 0.0,
                ..p
            };
            Figure {
                file: "shaft_tau.png".into(),
                title: "Shaft torque at 300 rpm".into(),
                x_label: "crank angle phi, deg".into(),
                y_label: "shaft.tau, N.m".into(),
                series: vec![
                    Series::new("alpha = 45 deg, no friction", turn(n, tau(no_friction))),
                    Series::new("alpha = 55 deg, mu = 0.1", turn(n, tau(alpha(55.0)))),
                    Series::new("alpha = 70 deg, mu = 0.1", turn(n, tau(alpha(70.0)))),
                ],
                caption: "Torque at the shaft over a turn at 300 rpm with the 150 N cutting force in the working stroke (180..360 deg). The defaults with friction (alpha = 45 deg, mu = 0.1) self-lock near 180 deg: see the next figure.".into(),
                equal_axes: false,
            }
        },
        {
            let w = p.drive_n;
            Figure {
                file: "shaft_tau_locking.png".into(),
                title: "Self-locking with the defaults (alpha = 45 deg, mu = 0.1)".into(),
                x_label: "crank angle phi, deg".into(),
                y_label: "shaft.tau, N.m".into(),
                series: vec![Series::new(
                    "shaft.tau",
                    (0..=1000)
                        .map(|j| {
                            let f = (170.0 + 30.0 * j as f64 / 1000.0).to_radians();
                            let k = p.kinematics(f, w, 0.0);
                            (f.to_degrees(), p.kinetostatics(&k).shaft_tau.min(50.0))
                        })
                        .collect(),
                )],
                caption: "Between 174.63 and 185.37 deg slider 7 self-locks (sliders.locked; forces without friction there). Leaving that zone in the working stroke, the Coulomb solution needs a steeply rising torque (the wedge effect; drawn clipped at 50 N.m).".into(),
                equal_axes: false,
            }
        },
    ]
}

/// The rod force over the second of two shaft turns at 300 rpm on the elastodynamic level:
/// `(φ in degrees, dynamic P, kinetostatic P)`, every 0.25 ms.
fn rod_force_turn(p: &Params) -> Result<Vec<(f64, f64, f64)>, String> {
    use super::elastic::{RodOde, dead_point_threshold};
    use crate::solver::{Integrator, Settings, ShaftPath};
    let w = p.drive_n;
    let o = RodOde {
        p,
        k: 2e8,
        c: RodOde::damping(p, 2e8, 0.05),
        path: ShaftPath::new(0.0, 0.0, w, 0.0),
        c_dead: dead_point_threshold(p),
        peaks: std::cell::Cell::new((0.0, 0.0, 0.0)),
        k_d: std::cell::Cell::new(f64::NAN),
    };
    let mut y = o.initial_state(0.0);
    let mut it = Integrator::new(Settings::default());
    let (dt, turn) = (2.5e-4, TAU / w);
    let n = (2.0 * turn / dt).round() as usize;
    let mut out = Vec::new();
    for i in 0..n {
        let t = (i + 1) as f64 * dt;
        it.integrate(&o, i as f64 * dt, t, &mut y)?;
        if t >= turn {
            let pt = o.point(t, &y);
            let rigid = p.kinetostatics(&pt.rigid.kin).rod_f;
            out.push((pt.rigid.kin.phi.to_degrees(), pt.eval.force, rigid));
        }
    }
    Ok(out)
}

/// The elastodynamic level's figure: dynamic against kinetostatic rod force.
fn elastic_figure() -> Result<Figure, String> {
    let free = Params {
        support_mu: 0.0,
        ..Params::default()
    };
    let jam = rod_force_turn(&Params::default())?;
    let ok = rod_force_turn(&free)?;
    let clip = |x: f64| x.clamp(-2000.0, 2000.0);
    Ok(Figure {
        file: "rod_force_elastic.png".into(),
        title: "Rod force: compliant rod against rigid links, 300 rpm".into(),
        x_label: "crank angle phi, deg".into(),
        y_label: "rod force P, N (compression +)".into(),
        series: vec![
            Series::new("dynamic, support.mu = 0", ok.iter().map(|q| (q.0, q.1)).collect()),
            Series::new("kinetostatic, support.mu = 0", ok.iter().map(|q| (q.0, q.2)).collect()),
            Series::new("dynamic, defaults (clipped)", jam.iter().map(|q| (q.0, clip(q.1))).collect()),
            Series::new("kinetostatic, defaults (clipped)", jam.iter().map(|q| (q.0, clip(q.2))).collect()),
        ],
        caption: "Second turn of a run at 300 rpm with the default rod (2e8 N/m, zeta 0.05). Without support friction the dynamic force rings about the kinetostatic one after the cutting force steps on at 180 deg (K_d = 1.68). With the defaults, slider 7 self-locks from 174.63 to 185.37 deg and the rigid model wedges as it leaves that window (clipped at 2 kN; 4.4e6 N at 185.37 deg); the compliant rod's force stays finite (friction faded before the window, see above), but the wedge kicks the rod into a ring of up to 13 kN that its 5 % damping takes some 50 deg to calm (sampled every 0.25 ms).".into(),
        equal_axes: false,
    })
}

/// `documentation/` files (index.html first) and the icon.
pub fn documentation() -> Result<Documentation, String> {
    let vars = variables_of::<DiscKnifeDrive>();
    let mut figs = figures();
    figs.push(elastic_figure()?);
    let files =
        crate::docs::documentation(&ModelInfo::of::<DiscKnifeDrive>(), &vars, INTRO, &figs)?;
    Ok((files, icon_png("Disc")?))
}
