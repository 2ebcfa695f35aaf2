//! The DiscKnifeDrive FMU's `documentation/`: what the mechanism is, every variable, paper 004's
//! Fig. 2 redrawn from [`super::physics`], the series form's error and the shaft torque.

use super::model::DiscKnifeDrive;
use super::physics::Params;
use crate::docs::{
    Documentation, Figure, Question, Series, Sweep, model_page, number, over_turn as turn, sweep,
};
use crate::solver::chain::ChainOde;
use std::f64::consts::TAU;

const WHAT: &str = r#"<p>Flow lines trim the spines of book and magazine blocks without stopping the
block: disc knives on a holder remove the spine in thin layers over several knife cycles, which
lowers the cutting load. Paper 004 drives the holder by a <b>combined crank-slider drive</b>: a crank
on the shaft moves slider 5 through rod 4; the knife holder is hinged to slider 5 and to slider 7,
which slides on a support line inclined by <code>support.alpha</code>; the knives cut at point S.
Each crank turn gives a working stroke (<code>knife.working</code>) and an idle stroke.</p>
<p>Drive it through <code>shaft.phi</code>, <code>shaft.w</code>, <code>shaft.a</code> or let it run
alone (<code>drive.mode</code>); it gives the path and velocity of the knife point, the forces in
rod, guides and hinges, whether a slider self-locks, and the shaft torque.</p>"#;

/// How the drive is modelled, with the numbers of the defaults.
fn notes(n: &Numbers) -> String {
    let jam_peak = format!("{} kN", number(n.jam_peak / 1e3, 3));
    let rigid_peak = format!("{:.2e} N", n.rigid_peak);
    format!(
        r#"<p>Crank 3 (l<sub>1</sub>) turns with the shaft (angle &phi;) and moves slider 5 (hinge C)
through rod 4 (l<sub>2</sub> = &lambda;<sub>2</sub>l<sub>1</sub>, &lambda;<sub>2</sub> = 2); knife holder 6 (CD,
length l<sub>4</sub>) is hinged to slider 5 at C and to slider 7 at D, which slides on the support line
EQ at the angle &alpha; from the vertical through Q. The knives cut at S, l<sub>S</sub>&middot;l<sub>4</sub>
from C. The block is fed at V along &minus;y.</p>
<p>Positions: x<sub>C</sub> exactly (<code>kinematics.series</code> = true uses the paper's series form
(1)); the holder angle from eq. (5), cos(&beta; + &alpha;) = ((x<sub>Q</sub> &minus; x<sub>C</sub>)cos &alpha;
&minus; (y<sub>Q</sub> &minus; e) sin &alpha;)/l<sub>4</sub>, &beta; = &minus;&alpha; + b&middot;arccos(&hellip;) on
the branch b = <code>assembly.branch</code>; D and S by eqs. (6), (8). Velocities and accelerations are
exact. A parameter set whose holder cannot reach EQ somewhere on the turn is refused at
initialization, naming the crank angles where it fails. The series form overestimates
x<sub>C</sub> by up to {series_c} mm and moves S by up to {series_s} mm with the defaults.</p>
<p>Forces (level <code>kinetostatic</code>, default): one planar Newton&ndash;Euler system per instant for
holder, slider 5 and slider 7 (unknowns: rod force P, compression positive; the hinge forces at C and
D; the normal forces of both guides), with the inertia of every mass, the weights
(<code>gravity.g</code>, default 0: horizontal plane), Coulomb friction in both guides and the cutting
force <code>cut.F</code> at S against the velocity of S relative to the block. Shaft torque = crank
torque.</p>
<p><b>Self-locking.</b> Where the holder CD lies within the friction angle of EQ's normal,
|tan(&beta; + &alpha;)| &lt; <code>support.mu</code>, Coulomb friction locks slider 7: the force system has
no unique solution. With the defaults (&alpha; = 45&deg;, &mu; = 0.1) this is the case for
{lock_from}&deg; &lt; &phi; &lt; {lock_to}&deg;; the FMU flags it (<code>sliders.locked</code>, one warning
per entry), computes the forces there without friction, and the forces rise steeply as the crank
leaves the zone in the working stroke (wedge effect). At &alpha; = 55&deg; and 70&deg; nothing locks.</p>
<p><b>Elastodynamic level</b>: rod 4 is an axial spring (<code>elastic.k</code>, default 2e8 N/m: a
steel shank of 60 mm&sup2; over 38 mm, EA/l<sub>2</sub> = 3.3e8 N/m, in series with two pin bearings of
1e9 N/m, an assumption) with damping ratio <code>elastic.zeta</code>. Slider 5's position is the one
compliant degree of freedom; holder, knives and slider 7 follow it by the exact kinematics, and the
same force system as the kinetostatic level gives its equation of motion (the reduced mass runs from
under 1 kg at the outer dead centre to some 35 kg at the inner one, near the holder's own dead point).
Outputs: <code>slider.x_kin</code> (rigid reference), <code>elastic.deflection</code>,
<code>elastic.F</code> (dynamic rod force; <code>rod.F</code> and the shaft torque use it),
<code>rod.F_kin</code>, <code>dyn.factor</code> (peak dynamic over peak kinetostatic rod force per
turn). The integrator locates the crank dead centres, the reversal of slider 7, the jamming window
and a reversal of the shaft; the same right-hand side is offered through Model Exchange.</p>
<p>The jamming window is treated as at the kinetostatic level (friction dropped, flagged); to keep
the motion continuous the friction fades out just before it, which caps the wedge's force
amplification at 20&times; where the rigid model's is unbounded. So with the defaults the dynamic
rod force stays finite ({jam_peak} at most over a turn at {rpm} rpm) where the rigid wedge reaches
{rigid_peak}. On a jam-free set (<code>support.mu</code> = 0) the default rod gives K<sub>d</sub> =
{k_d} at {rpm} rpm: the cutting force switching on at the inner dead centre is a step load that
rings the rod. A rod soft enough for slider 5 to overrun the inner dead centre into the holder's own
dead point makes the step a Discard that says so.</p>
<p>Not in the paper: l<sub>1</sub>, l<sub>4</sub> and Q are assumptions, chosen to reproduce the trend of
its Fig. 2 (the y-range of S: {y45}, {y55}, {y70} mm at &alpha; = 45&deg;, 55&deg;, 70&deg;), not its
printed 23 and 6 mm.</p>"#,
        series_c = number(n.series_c, 3),
        series_s = number(n.series_s, 3),
        lock_from = number(n.lock.0, 5),
        lock_to = number(n.lock.1, 5),
        k_d = number(n.k_d, 3),
        rpm = number(n.rpm, 4),
        y45 = number(n.y_range[0], 3),
        y55 = number(n.y_range[1], 3),
        y70 = number(n.y_range[2], 3),
    )
}

/// The numbers the page states, computed from the defaults.
struct Numbers {
    /// Largest error of the series form in x_C and in S, mm.
    series_c: f64,
    series_s: f64,
    /// The crank angles (deg) between which slider 7 self-locks.
    lock: (f64, f64),
    /// y-range of S at alpha = 45, 55, 70 deg, mm.
    y_range: [f64; 3],
    rpm: f64,
    /// Peak dynamic rod force with the defaults, and the rigid wedge's, N.
    jam_peak: f64,
    rigid_peak: f64,
    /// K_d without support friction.
    k_d: f64,
}

/// The crank angles (deg) between which slider 7 self-locks with `p`, to 1e-6 deg.
fn locking_window(p: &Params) -> (f64, f64) {
    let locked = |deg: f64| {
        let k = p.kinematics(deg.to_radians(), p.drive_n, 0.0);
        p.kinetostatics(&k).locked
    };
    let n = 3600;
    let grid: Vec<f64> = (0..n).map(|i| 360.0 * i as f64 / n as f64).collect();
    let Some(inside) = grid.iter().copied().find(|&d| locked(d)) else {
        return (f64::NAN, f64::NAN);
    };
    let edge = |mut out: f64, mut inn: f64| {
        while (out - inn).abs() > 1e-7 {
            let mid = 0.5 * (out + inn);
            if locked(mid) {
                inn = mid;
            } else {
                out = mid;
            }
        }
        0.5 * (out + inn)
    };
    let step = 360.0 / n as f64;
    let mut lo = inside;
    while locked(lo - step) {
        lo -= step;
    }
    let mut hi = inside;
    while locked(hi + step) {
        hi += step;
    }
    (edge(lo - step, lo), edge(hi + step, hi))
}

/// S over one crank turn in mm, `n` samples.
fn path_of_s(p: &Params, n: usize) -> Vec<(f64, f64)> {
    (0..=n)
        .map(|j| {
            let s = p.kinematics(TAU * j as f64 / n as f64, 1.0, 0.0).s * 1e3;
            (s.x, s.y)
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
    let path = |a: f64| path_of_s(&alpha(a), 3600);
    let x45 = path(45.0)
        .iter()
        .fold((f64::MAX, f64::MIN), |(lo, hi), &(x, _)| {
            (lo.min(x), hi.max(x))
        });
    vec![
        Figure {
            equal_axes: true,
            ..Figure::lines(
                "fig2_path_of_S.png",
                "Fig. 2: path of the knife point S",
                "x of S, mm",
                "y of S, mm",
                angles
                    .iter()
                    .map(|&a| Series::new(format!("alpha = {a} deg"), path_of_s(&alpha(a), n)))
                    .collect(),
                format!(
                    "Path of S over one crank turn (out in the working stroke, back along the same curve in the idle stroke) for three angles of the support line EQ (paper 004, Fig. 2, redrawn with the defaults): the steeper EQ stands, the more S moves across the feed; its y-range is {}, {} and {} mm at 45, 55 and 70 deg, and x runs from {} to {} mm at 45 deg.",
                    number(range(45.0), 3),
                    number(range(55.0), 3),
                    number(range(70.0), 3),
                    number(x45.0, 3),
                    number(x45.1, 3)
                ),
            )
        },
        Figure::lines(
            "fig2_y_range.png",
            "y-range of S against the angle of EQ",
            "support.alpha, deg",
            "max - min of y of S, mm",
            vec![Series::new(
                "y-range of S",
                (40..=75).map(|a| (a as f64, range(a as f64))).collect(),
            )],
            "Range of y of S over a crank turn as EQ is set from 40 to 75 deg (the dependence paper 004's Fig. 2 shows).",
        ),
        Figure::lines(
            "coordinates_of_S.png",
            "Coordinates of S over a crank turn",
            "crank angle phi, deg",
            "mm",
            angles
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
            "x and y of S against the crank angle; the working stroke (C moving to +x) is 180..360 deg.",
        ),
        {
            let ps = Params { series: true, ..p };
            Figure::lines(
                "series_error.png",
                "Error of the series form (1)",
                "crank angle phi, deg",
                "series - exact, mm",
                vec![
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
                format!(
                    "The paper's series form against the exact slider position (defaults): x_C is overestimated by up to {} mm at 90 and 270 deg, S is off by up to {} mm.",
                    number(series_error(&p).0, 3),
                    number(series_error(&p).1, 3)
                ),
            )
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
            Figure::lines(
                "shaft_tau.png",
                "Shaft torque at 300 rpm",
                "crank angle phi, deg",
                "shaft.tau, N.m",
                vec![
                    Series::new("alpha = 45 deg, no friction", turn(n, tau(no_friction))),
                    Series::new("alpha = 55 deg, mu = 0.1", turn(n, tau(alpha(55.0)))),
                    Series::new("alpha = 70 deg, mu = 0.1", turn(n, tau(alpha(70.0)))),
                ],
                "Torque at the shaft over a turn at 300 rpm with the 150 N cutting force in the working stroke (180..360 deg). The defaults with friction (alpha = 45 deg, mu = 0.1) self-lock near 180 deg: see the next figure.",
            )
        },
        {
            let w = p.drive_n;
            Figure::lines(
                "shaft_tau_locking.png",
                "Self-locking with the defaults (alpha = 45 deg, mu = 0.1)",
                "crank angle phi, deg",
                "shaft.tau, N.m",
                vec![Series::new(
                    "shaft.tau",
                    (0..=1000)
                        .map(|j| {
                            let f = (170.0 + 30.0 * j as f64 / 1000.0).to_radians();
                            let k = p.kinematics(f, w, 0.0);
                            let tau = p.kinetostatics(&k).shaft_tau;
                            (f.to_degrees(), if tau > 50.0 { f64::NAN } else { tau })
                        })
                        .collect(),
                )],
                format!(
                    "Between {} and {} deg slider 7 self-locks (sliders.locked; forces without friction there). Leaving that zone in the working stroke, the Coulomb solution needs a steeply rising torque (the wedge effect; drawn up to 50 N.m).",
                    number(locking_window(&p).0, 5),
                    number(locking_window(&p).1, 5)
                ),
            )
        },
    ]
}

/// The rod force over a window of the second of two shaft turns at the nominal speed on the
/// elastodynamic level: `(φ in degrees, dynamic P, kinetostatic P)`, every 10 µs (the rod rings
/// at 0.4 to 2.4 kHz: some 40 samples a period and more).
fn rod_force_window(
    p: &Params,
    from_deg: f64,
    to_deg: f64,
) -> Result<Vec<(f64, f64, f64)>, String> {
    use super::elastic::{RodOde, dead_point_threshold};
    use crate::solver::{Integrator, Settings, ShaftPath};
    let w = p.drive_n;
    let o = RodOde::new(
        p,
        RodOde::spring(p, 2e8, 0.05),
        ShaftPath::new(0.0, 0.0, w, 0.0),
        dead_point_threshold(p),
        crate::solver::chain::Peaks::new(0.0),
    );
    let mut y = o.initial_state(0.0);
    let mut it = Integrator::new(Settings::default());
    let turn = TAU / w;
    let (t_a, t_b) = (
        turn * (1.0 + from_deg / 360.0),
        turn * (1.0 + to_deg / 360.0),
    );
    let (coarse, fine) = (2.5e-4, 1e-5);
    let mut t = 0.0;
    while t < t_a {
        let t1 = (t + coarse).min(t_a);
        it.integrate(&o, t, t1, &mut y)?;
        t = t1;
    }
    let mut out = Vec::new();
    while t < t_b {
        let t1 = t + fine;
        it.integrate(&o, t, t1, &mut y)?;
        t = t1;
        let pt = o.point(t, &y);
        let rigid = p.kinetostatics(&pt.rigid.kin).rod_f;
        out.push(((w * t).to_degrees() - 360.0, pt.eval.force, rigid));
    }
    Ok(out)
}

/// Largest |x| of a column.
fn peak(v: &[(f64, f64, f64)], f: fn(&(f64, f64, f64)) -> f64) -> f64 {
    v.iter().map(|q| f(q).abs()).fold(0.0, f64::max)
}

/// The elastodynamic level's figures, dynamic against kinetostatic rod force: without support
/// friction, and with the defaults (self-locking); and the numbers the page states of them.
fn elastic_figures(p: &Params) -> Result<(Vec<Figure>, f64, f64, f64), String> {
    let free = Params {
        support_mu: 0.0,
        ..*p
    };
    let rpm = number(p.drive_n * 30.0 / std::f64::consts::PI, 4);
    let ok = rod_force_window(&free, 150.0, 300.0)?;
    let k_d = peak(&ok, |q| q.1) / peak(&ok, |q| q.2);
    let jam = rod_force_window(p, 165.0, 280.0)?;
    let (jam_peak, rigid_peak) = (peak(&jam, |q| q.1), peak(&jam, |q| q.2));
    let (lock_from, lock_to) = locking_window(p);
    // the rigid force off the scale of the dynamic one is left out, not clipped to a plateau
    let scale = 1.2 * jam_peak;
    let fig = |file: &str, title: String, series: Vec<Series>, caption: String| {
        Figure::lines(
            file,
            title,
            "crank angle phi, deg",
            "rod force P, N (compression +)",
            series,
            caption,
        )
    };
    Ok((
        vec![
            fig(
                "rod_force_elastic.png",
                format!("Rod force, compliant against rigid, support.mu = 0, {rpm} rpm"),
                vec![
                    Series::new(
                        "elastic.F (compliant rod)",
                        ok.iter().map(|q| (q.0, q.1)).collect(),
                    ),
                    Series::new(
                        "rod.F_kin (rigid links)",
                        ok.iter().map(|q| (q.0, q.2)).collect(),
                    ),
                ],
                format!(
                    "Without support friction nothing locks: the dynamic rod force rings about the kinetostatic one after the cutting force steps on at 180 deg, and the rod's 5 % damping calms it within the working stroke. Peak dynamic over peak kinetostatic force K_d = {}. Second turn of a run at {rpm} rpm with the default rod (2e8 N/m), sampled every 10 µs.",
                    number(k_d, 3)
                ),
            ),
            fig(
                "rod_force_locking.png",
                format!("Rod force with the defaults (self-locking), {rpm} rpm"),
                vec![
                    Series::new(
                        "elastic.F (compliant rod)",
                        jam.iter().map(|q| (q.0, q.1)).collect(),
                    ),
                    Series::new(
                        "rod.F_kin (rigid links)",
                        jam.iter()
                            .map(|q| (q.0, if q.2.abs() > scale { f64::NAN } else { q.2 }))
                            .collect(),
                    ),
                ],
                format!(
                    "With the defaults slider 7 self-locks from {} to {} deg. The rigid model wedges as it leaves that window: its force leaves the scale (up to {:.2e} N; the gap in its line). The compliant rod's force stays finite, up to {} kN, but the wedge kicks the rod into a ring that its 5 % damping takes tens of degrees to calm. Second turn at {rpm} rpm, sampled every 10 µs.",
                    number(lock_from, 5),
                    number(lock_to, 5),
                    rigid_peak,
                    number(jam_peak / 1e3, 3)
                ),
            ),
        ],
        k_d,
        jam_peak,
        rigid_peak,
    ))
}

/// Largest error of the series form against the exact slider position: in x_C and in S, mm.
fn series_error(p: &Params) -> (f64, f64) {
    let ps = Params { series: true, ..*p };
    (0..3600)
        .map(|j| TAU * j as f64 / 3600.0)
        .map(|f| {
            let (a, b) = (ps.kinematics(f, 1.0, 0.0), p.kinematics(f, 1.0, 0.0));
            ((a.x_c - b.x_c).abs() * 1e3, (a.s - b.s).norm() * 1e3)
        })
        .fold((0.0, 0.0), |(c, s), (dc, ds)| {
            (f64::max(c, dc), f64::max(s, ds))
        })
}

/// The questions a designer brings, answered at the defaults.
fn questions(s: &Sweep, n: &Numbers) -> Vec<Question> {
    let frac = |name: &str| s.stat(name).map_or(f64::NAN, |b| b.true_fraction);
    vec![
        Question::new(
            "Where does the knife point go?",
            &["knife.x", "knife.y"],
            format!("x {}, y {}", s.range("knife.x"), s.range("knife.y")),
        ),
        Question::new(
            "How long is the working stroke?",
            &["knife.working", "slider.x"],
            format!(
                "{} % of the turn; slider stroke {}",
                number(100.0 * frac("knife.working"), 3),
                s.value("slider.stroke")
            ),
        ),
        Question::new(
            "How fast does the knife point move?",
            &["knife.vx", "knife.vy"],
            format!(
                "vx peaks at {}, vy at {}",
                s.peak("knife.vx"),
                s.peak("knife.vy")
            ),
        ),
        Question::new(
            "Does a slider self-lock?",
            &["sliders.locked"],
            format!(
                "yes with the defaults: slider 7 between {} and {} deg ({} % of the turn); not at support.alpha = 55 or 70 deg",
                number(n.lock.0, 5),
                number(n.lock.1, 5),
                number(100.0 * frac("sliders.locked"), 2)
            ),
        ),
        Question::new(
            "Which force does the rod carry?",
            &["rod.F"],
            format!(
                "rigid links: {} on a 0.5 deg grid, without bound at the edge of the locking window (the wedge); compliant rod: {} kN",
                s.peak("rod.F"),
                number(n.jam_peak / 1e3, 3)
            ),
        ),
        Question::new(
            "Which cutting force acts at the knife point?",
            &["cut.Fx", "cut.Fy"],
            format!(
                "cut.F = {}: Fx {}, Fy {}",
                s.value("cut.F"),
                s.peak("cut.Fx"),
                s.peak("cut.Fy")
            ),
        ),
        Question::new(
            "Which torque does the shaft need?",
            &["shaft.tau"],
            format!(
                "peak {}, RMS {} (the wedge dominates)",
                s.peak("shaft.tau"),
                s.rms("shaft.tau")
            ),
        ),
        Question::new(
            "How much does the rod's compliance raise the force?",
            &["dyn.factor", "elastic.F"],
            format!(
                "without support friction K_d = {} at {} rpm; with the defaults the chain force stays finite at {} kN",
                number(n.k_d, 3),
                number(n.rpm, 4),
                number(n.jam_peak / 1e3, 3)
            ),
        ),
    ]
}

/// `documentation/` files (index.html first) and the icon.
pub fn documentation() -> Result<Documentation, String> {
    let p = Params::default();
    let s = sweep::<DiscKnifeDrive>()?;
    let mut figs = figures();
    let (elastic, k_d, jam_peak, rigid_peak) = elastic_figures(&p)?;
    figs.extend(elastic);
    let (series_c, series_s) = series_error(&p);
    let numbers = Numbers {
        series_c,
        series_s,
        lock: locking_window(&p),
        y_range: [45.0, 55.0, 70.0].map(|a| {
            let pts = path_of_s(&alpha(a), 3600);
            let (lo, hi) = pts.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &(_, y)| {
                (lo.min(y), hi.max(y))
            });
            hi - lo
        }),
        rpm: s.rpm,
        jam_peak,
        rigid_peak,
        k_d,
    };
    let notes = notes(&numbers);
    model_page::<DiscKnifeDrive>(WHAT, figs, &questions(&s, &numbers), &notes, &s, "Disc")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rod_force_is_sampled_finely_and_not_clipped() {
        let (figs, k_d, jam_peak, rigid_peak) = elastic_figures(&Params::default()).unwrap();
        // 10 µs at 300 rpm: 0.018 deg a sample; the rod rings at up to 2.4 kHz (0.75 deg)
        let dyn_pts = &figs[1].series[0].points;
        assert!(dyn_pts.windows(2).all(|w| w[1].0 - w[0].0 < 0.02));
        // the compliant rod's force is drawn whole: its peak is a point of the line
        assert!(dyn_pts.iter().any(|p| (p.1.abs() - jam_peak).abs() < 1e-9));
        // the rigid wedge leaves the scale as a gap, not a plateau
        let rigid = &figs[1].series[1].points;
        assert!(rigid.iter().any(|p| p.1.is_nan()));
        assert!(
            rigid
                .iter()
                .filter(|p| p.1.is_finite())
                .all(|p| p.1.abs() <= 1.2 * jam_peak)
        );
        assert!(rigid_peak > 100.0 * jam_peak, "{rigid_peak} {jam_peak}");
        assert!(k_d > 1.2 && k_d < 3.0, "{k_d}");
    }
}
