//! Tests of `physics.rs`.

use super::*;
use crate::mechanisms::assert_printed;
use approx::assert_abs_diff_eq;
use proptest::prelude::*;
use std::f64::consts::FRAC_PI_2;

fn params() -> Params {
    Params::default()
}

fn with_alpha(deg: f64) -> Params {
    Params {
        support_alpha: deg.to_radians(),
        ..params()
    }
}

/// `n` crank angles over one turn, offset from the dead centres.
fn turn(n: usize) -> impl Iterator<Item = f64> {
    (0..n).map(move |j| TAU * (j as f64 + 0.37) / n as f64)
}

/// Parameter sets the derivative and balance tests run on: the defaults, the other branch,
/// the paper's other support angles, an offset crank, the series form, and a heavy holder
/// with inertia, gravity and S off the middle.
fn cases() -> Vec<Params> {
    let p = params();
    vec![
        p,
        Params { branch: -1, ..p },
        with_alpha(55.0),
        with_alpha(70.0),
        Params {
            crank_e: 0.004,
            support_alpha: 60f64.to_radians(),
            ..p
        },
        Params { series: true, ..p },
        Params {
            holder_j: 3e-4,
            gravity_g: 9.80665,
            holder_ls: 0.3,
            support_alpha: 50f64.to_radians(),
            ..p
        },
    ]
}

#[test]
fn defaults_are_the_spec_table() {
    let p = params();
    assert_eq!((p.crank_l1, p.rod_lambda2, p.crank_e), (0.019, 2.0, 0.0));
    assert_eq!((p.holder_l4, p.holder_ls), (0.022, 0.5));
    assert_abs_diff_eq!(p.support_alpha.to_degrees(), 45.0, epsilon = 1e-12);
    assert_eq!((p.support_xq, p.support_yq), (0.060, 0.010));
    assert_eq!((p.branch, p.series), (1, false));
    assert_eq!(
        (p.holder_m, p.slider5_m, p.slider7_m, p.rod_m, p.crank_j),
        (0.8, 0.3, 0.2, 0.15, 2e-4)
    );
    assert_eq!(
        (p.guide_mu, p.support_mu, p.cut_f, p.feed_v),
        (0.1, 0.1, 150.0, 0.2)
    );
    assert_abs_diff_eq!(p.drive_n * 30.0 / PI, 300.0, epsilon = 1e-12);
    assert_abs_diff_eq!(p.rod_l2(), 0.038, epsilon = 1e-17);
    assert_eq!(p.stroke(), 0.038);
    assert_eq!(p.validate(), Ok(()));
}

/// disc-knife-drive.md, "Reference (defaults, exact)", to the digits printed.
#[test]
fn spec_reference_values() {
    let p = params();
    for (phi, x_c, beta, sx, sy) in [
        (0.0, 57.000, 58.002, 62.829, 9.329),
        (FRAC_PI_2, 32.909, 11.679, 43.681, 2.227),
        (PI, 19.000, -40.122, 27.411, -7.089),
    ] {
        let k = p.kinematics(phi, p.drive_n, 0.0);
        assert_printed(k.x_c * 1e3, x_c, 3);
        assert_printed(k.beta.to_degrees(), beta, 3);
        assert_printed(k.s.x * 1e3, sx, 3);
        assert_printed(k.s.y * 1e3, sy, 3);
    }
    // Series form at φ = π/2: x_C = 33.250 mm.
    let ps = Params {
        series: true,
        ..params()
    };
    assert_printed(ps.kinematics(FRAC_PI_2, 1.0, 0.0).x_c * 1e3, 33.250, 3);
    // The series form agrees with the exact one at the dead centres.
    for phi in [0.0, PI] {
        assert_abs_diff_eq!(
            ps.kinematics(phi, 1.0, 0.0).s.x,
            p.kinematics(phi, 1.0, 0.0).s.x,
            epsilon = 1e-15
        );
    }
}

/// Independent of eqs. 1 and 5: C from the rod length by bisection, D as the intersection of
/// the circle of radius l4 about C with the line EQ (a quadratic in the line parameter).
#[test]
fn reference_values_from_geometry() {
    for p in [params(), with_alpha(55.0), with_alpha(70.0)] {
        let (l1, l2, l4) = (p.crank_l1, p.rod_l2(), p.holder_l4);
        let q = Vec2::new(p.support_xq, p.support_yq);
        let u = p.support_dir();
        for phi in turn(97) {
            let b = Vec2::new(l1 * phi.cos(), l1 * phi.sin());
            let (mut lo, mut hi) = (b.x, b.x + l2);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if (mid - b.x).powi(2) + b.y * b.y < l2 * l2 {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            let c = Vec2::new(0.5 * (lo + hi), 0.0);
            // |Q + t·u − C| = l4: t² + 2t·u·(Q − C) + |Q − C|² − l4² = 0.
            let w = q - c;
            let (bb, cc) = (u.dot(&w), w.norm_squared() - l4 * l4);
            let disc = bb * bb - cc;
            assert!(disc > 0.0);
            let k = p.kinematics(phi, 1.0, 0.0);
            assert_abs_diff_eq!(k.x_c, c.x, epsilon = 1e-15);
            // One of the two intersections is branch +1's D.
            let roots = [-bb + disc.sqrt(), -bb - disc.sqrt()].map(|t| q + u * t);
            let hit = roots
                .iter()
                .map(|r| (r - k.d).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(hit < 1e-15, "phi = {phi}: D off by {hit}");
            let s = c + (k.d - c) * p.holder_ls;
            assert_abs_diff_eq!(k.s.x, s.x, epsilon = 1e-15);
            assert_abs_diff_eq!(k.s.y, s.y, epsilon = 1e-15);
            // The other branch takes the other root.
            let k2 = Params { branch: -1, ..p }.kinematics(phi, 1.0, 0.0);
            let other = roots
                .iter()
                .map(|r| (r - k2.d).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(other < 1e-15 && (k2.d - k.d).norm() > 1e-6);
        }
    }
}

/// Every constraint holds on the whole turn: rod length, holder length, D on EQ, S on CD.
/// With an offset guide (e ≠ 0) too, where the spec's K (without e) would miss EQ.
#[test]
fn support_point_stays_on_eq_with_eccentricity() {
    for p in cases() {
        let n = p.support_normal();
        let q = Vec2::new(p.support_xq, p.support_yq);
        for phi in turn(360) {
            let k = p.kinematics(phi, 1.0, 0.0);
            let c = Vec2::new(k.x_c, p.crank_e);
            if !p.series {
                assert_abs_diff_eq!((c - k.b).norm(), p.rod_l2(), epsilon = 1e-15);
            }
            assert_abs_diff_eq!((k.d - c).norm(), p.holder_l4, epsilon = 1e-15);
            assert_abs_diff_eq!((k.d - q).dot(&n), 0.0, epsilon = 1e-15);
            assert_abs_diff_eq!(cross(k.d - c, k.s - c), 0.0, epsilon = 1e-18);
            assert_abs_diff_eq!((k.s - c).norm(), p.holder_ls * p.holder_l4, epsilon = 1e-15);
        }
    }
    // The spec's K = (x_Q − tan α·y_Q − x_C)/l4 omits e: with e = 4 mm it misses EQ by mm.
    let p = cases()[4];
    let k = p.kinematics(1.0, 1.0, 0.0);
    let spec_k = (p.support_xq - p.support_alpha.tan() * p.support_yq - k.x_c) / p.holder_l4;
    let beta = -p.support_alpha + (p.support_alpha.cos() * spec_k).acos();
    let d = Vec2::new(
        k.x_c + p.holder_l4 * beta.cos(),
        p.crank_e + p.holder_l4 * beta.sin(),
    );
    let miss = (d - Vec2::new(p.support_xq, p.support_yq)).dot(&p.support_normal());
    assert!(miss.abs() > 1e-3, "{miss}");
}

/// Paper 004's Fig. 2 trend with the spec's defaults: the y-range of S shrinks from α = 45°
/// through 55° to 70° (spec: 16.4, 10.4, 5.9 mm), x of S spans 27.4–62.8 mm at 45°.
#[test]
fn fig2_trend() {
    let range = |p: Params| {
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for j in 0..=72_000 {
            let s = p.kinematics(TAU * j as f64 / 72_000.0, 1.0, 0.0).s * 1e3;
            (x0, x1, y0, y1) = (x0.min(s.x), x1.max(s.x), y0.min(s.y), y1.max(s.y));
        }
        (x0, x1, y1 - y0)
    };
    let (x0, x1, y45) = range(with_alpha(45.0));
    let (_, _, y55) = range(with_alpha(55.0));
    let (_, _, y70) = range(with_alpha(70.0));
    assert_printed(y45, 16.4, 1);
    assert_printed(y55, 10.4, 1);
    assert_printed(y70, 5.9, 1);
    assert!(y45 > y55 && y55 > y70);
    assert_printed(x0, 27.4, 1);
    assert_printed(x1, 62.8, 1);
    // The paper's own numbers (23 mm at 45°, within 6 mm at 70°, x from 24 to 62 mm) come
    // from its unpublished l1, l4, Q: the trend, not the values, is reproduced.
    assert!(y45 < 23.0 && y70 < 6.0);
    // The y-range shrinks monotonically over the paper's whole range of α.
    let ys: Vec<f64> = (45..=70)
        .step_by(5)
        .map(|a| range(with_alpha(a as f64)).2)
        .collect();
    assert!(ys.windows(2).all(|w| w[1] < w[0]), "{ys:?}");
}

/// β' from its closed form: c' = −cos α·x_C'/l4, β' = −b·c'/√(1 − c²).
#[test]
fn dual_numbers_agree_with_the_closed_form() {
    for p in cases() {
        for phi in turn(100) {
            let k = p.kinematics(phi, 1.0, 0.0);
            let dc = -p.support_alpha.cos() * k.x_c_d / p.holder_l4;
            let dbeta = -f64::from(p.branch) * dc / (1.0 - k.c * k.c).sqrt();
            assert_abs_diff_eq!(k.beta_d, dbeta, epsilon = 1e-12 * (1.0 + dbeta.abs()));
            let ddc = -p.support_alpha.cos() * k.x_c_dd / p.holder_l4;
            let s = 1.0 - k.c * k.c;
            let ddbeta = -f64::from(p.branch) * (ddc / s.sqrt() + k.c * dc * dc / (s * s.sqrt()));
            assert_abs_diff_eq!(k.beta_dd, ddbeta, epsilon = 1e-11 * (1.0 + ddbeta.abs()));
        }
    }
}

#[test]
fn angle_derivatives_match_finite_differences() {
    let h = 1e-5;
    for p in cases() {
        for phi in turn(360) {
            let (k, kp, km) = (
                p.kinematics(phi, 1.0, 0.0),
                p.kinematics(phi + h, 1.0, 0.0),
                p.kinematics(phi - h, 1.0, 0.0),
            );
            let fd = |a: f64, b: f64| (a - b) / (2.0 * h);
            let tol = 1e-8 * (1.0 + k.beta_dd.abs());
            assert_abs_diff_eq!(k.x_c_d, fd(kp.x_c, km.x_c), epsilon = 1e-11);
            assert_abs_diff_eq!(k.x_c_dd, fd(kp.x_c_d, km.x_c_d), epsilon = 1e-11);
            assert_abs_diff_eq!(k.beta_d, fd(kp.beta, km.beta), epsilon = tol);
            assert_abs_diff_eq!(k.beta_dd, fd(kp.beta_d, km.beta_d), epsilon = tol);
            for (q, d1, d2, qp, qm, d1p, d1m) in [
                (k.s, k.s_d, k.s_dd, kp.s, km.s, kp.s_d, km.s_d),
                (k.d, k.d_d, k.d_dd, kp.d, km.d, kp.d_d, km.d_d),
            ] {
                let _ = q;
                for i in 0..2 {
                    let t = 1e-10 + 1e-8 * d2[i].abs();
                    assert_abs_diff_eq!(d1[i], fd(qp[i], qm[i]), epsilon = t);
                    assert_abs_diff_eq!(d2[i], fd(d1p[i], d1m[i]), epsilon = t);
                }
            }
            // Second derivatives straight from positions, too.
            let h2 = 1e-4;
            let (sp, sm) = (
                p.kinematics(phi + h2, 1.0, 0.0),
                p.kinematics(phi - h2, 1.0, 0.0),
            );
            let fd2 = (sp.s - 2.0 * k.s + sm.s) / (h2 * h2);
            assert_abs_diff_eq!(k.s_dd.x, fd2.x, epsilon = 1e-6);
            assert_abs_diff_eq!(k.s_dd.y, fd2.y, epsilon = 1e-6);
        }
    }
}

/// v and a from the chain rule against differences in time, for φ(t) = φ0 + ω·t + ε·t²/2.
#[test]
fn time_derivatives_match_finite_differences() {
    let h = 1e-7;
    for p in cases() {
        for (w, eps) in [(31.4, 0.0), (-20.0, 150.0), (5.0, -800.0)] {
            for phi0 in turn(90) {
                let at = |t: f64| p.kinematics(phi0 + w * t + 0.5 * eps * t * t, w + eps * t, eps);
                let (k, kp, km) = (at(0.0), at(h), at(-h));
                let fd = |a: Vec2, b: Vec2| (a - b) / (2.0 * h);
                let scale = 1e-7 * (1.0 + w * w + eps.abs());
                let v = fd(kp.s, km.s);
                let a = fd(kp.v_s, km.v_s);
                assert_abs_diff_eq!(k.v_s.x, v.x, epsilon = scale * 1e-2);
                assert_abs_diff_eq!(k.v_s.y, v.y, epsilon = scale * 1e-2);
                assert_abs_diff_eq!(k.a_s.x, a.x, epsilon = scale);
                assert_abs_diff_eq!(k.a_s.y, a.y, epsilon = scale);
                let vd = fd(kp.d, km.d);
                let ad = fd(kp.v_d, km.v_d);
                assert_abs_diff_eq!((k.v_d - vd).norm(), 0.0, epsilon = scale * 1e-2);
                assert_abs_diff_eq!((k.a_d - ad).norm(), 0.0, epsilon = scale);
                assert_abs_diff_eq!(k.v_c, (kp.x_c - km.x_c) / (2.0 * h), epsilon = scale * 1e-2);
                assert_abs_diff_eq!(k.a_c, (kp.v_c - km.v_c) / (2.0 * h), epsilon = scale);
                assert_abs_diff_eq!(k.beta_w, (kp.beta - km.beta) / (2.0 * h), epsilon = scale);
                assert_abs_diff_eq!(
                    k.beta_eps,
                    (kp.beta_w - km.beta_w) / (2.0 * h),
                    epsilon = 100.0 * scale
                );
            }
        }
    }
}

/// Working stroke: C moves to +x, for ω > 0 (e = 0) the half turn π < φ < 2π.
#[test]
fn working_stroke_is_c_moving_to_plus_x() {
    let p = params();
    for phi in turn(720) {
        let k = p.kinematics(phi, 10.0, 0.0);
        assert_eq!(k.working, phi > PI, "phi = {phi}");
        assert_eq!(p.kinematics(phi, -10.0, 0.0).working, phi < PI);
        assert!(!p.kinematics(phi, 0.0, 0.0).working);
        let f = p.cut_force(&k);
        if k.working {
            // Magnitude cut.F, opposite to the velocity relative to the block (fed along −y).
            let v_rel = Vec2::new(k.v_s.x, k.v_s.y + p.feed_v);
            assert_abs_diff_eq!(f.norm(), p.cut_f, epsilon = 1e-12);
            assert_abs_diff_eq!(f.dot(&v_rel), -p.cut_f * v_rel.norm(), epsilon = 1e-9);
        } else {
            assert_eq!(f, Vec2::zeros());
        }
    }
    // Half of the turn each, at constant speed.
    let n = 10_000;
    let working = (0..n)
        .filter(|&j| {
            p.kinematics(TAU * (j as f64 + 0.5) / n as f64, 1.0, 0.0)
                .working
        })
        .count();
    assert_eq!(working, n / 2);
}

/// The [`cases`] of a rigid linkage (the series form is none: the rod's length varies).
fn rigid_cases() -> impl Iterator<Item = Params> {
    cases().into_iter().filter(|p| !p.series)
}

/// The rigid cases under gravity with the friction coefficients `guide_mu` and `support_mu`.
fn heavy_rigid_cases(guide_mu: f64, support_mu: f64) -> impl Iterator<Item = Params> {
    rigid_cases().map(move |p| Params {
        guide_mu,
        support_mu,
        gravity_g: 9.80665,
        ..p
    })
}

/// Statics (ω = ε = 0) by virtual work, independent of the Newton–Euler system: with a load F
/// at S and the weights, `τ = −F·S' + g·(rod.m/2·y_B' + m7·y_D' + m_h·y_S')`, the primes by
/// central differences of positions. And every body balances with the forces reported.
#[test]
fn static_equilibrium_by_virtual_work() {
    let h = 1e-6;
    for p in heavy_rigid_cases(0.0, 0.0) {
        for (j, phi) in turn(180).enumerate() {
            let load = Vec2::new(40.0 * (j as f64).cos() - 100.0, 70.0 * (j as f64).sin());
            let k = p.kinematics(phi, 0.0, 0.0);
            let f = p.kinetostatics_with_load(&k, load);
            let (kp, km) = (
                p.kinematics(phi + h, 0.0, 0.0),
                p.kinematics(phi - h, 0.0, 0.0),
            );
            let d = |a: f64, b: f64| (a - b) / (2.0 * h);
            let g = p.gravity_g;
            let tau = -(load.x * d(kp.s.x, km.s.x) + load.y * d(kp.s.y, km.s.y))
                + g * (0.5 * p.rod_m * d(kp.b.y, km.b.y)
                    + p.slider7_m * d(kp.d.y, km.d.y)
                    + p.holder_m * d(kp.s.y, km.s.y));
            let scale = 1e-7 * (1.0 + f.rod_f.abs() * p.crank_l1);
            assert_abs_diff_eq!(f.shaft_tau, tau, epsilon = scale);
            assert_eq!(f.shaft_p, 0.0);
            // Body balances with the reported forces (ω = ε = 0: no inertia).
            let c = Vec2::new(k.x_c, p.crank_e);
            let holder = f.pin_c + f.pin_d + load - Vec2::new(0.0, p.holder_m * g);
            assert_abs_diff_eq!(holder.norm(), 0.0, epsilon = 1e-9);
            let moment = cross(c - k.s, f.pin_c) + cross(k.d - k.s, f.pin_d);
            assert_abs_diff_eq!(moment, 0.0, epsilon = 1e-11);
            let s5 = k.rod_dir * f.rod_f - f.pin_c + Vec2::new(0.0, f.guide_n - p.mass_c() * g);
            assert_abs_diff_eq!(s5.norm(), 0.0, epsilon = 1e-9);
            let s7 = -f.pin_d + p.support_normal() * f.support_n - Vec2::new(0.0, p.slider7_m * g);
            assert_abs_diff_eq!(s7.norm(), 0.0, epsilon = 1e-9);
        }
    }
}

/// Energy over time, states from a shaft φ(t) = φ0 + ω·t + ε·t²/2.
fn energy(p: &Params, phi0: f64, w: f64, eps: f64, t: f64) -> f64 {
    let k = p.kinematics(phi0 + w * t + 0.5 * eps * t * t, w + eps * t, eps);
    p.kinetic_energy(&k) + p.potential_energy(&k)
}

/// Without friction: shaft power = rate of kinetic and potential energy − power of the
/// cutting force, dE/dt by central differences in time (not from the accelerations).
#[test]
fn power_balance_without_friction() {
    let h = 1e-6;
    for p in heavy_rigid_cases(0.0, 0.0) {
        let p = Params {
            holder_j: 2e-4,
            ..p
        };
        for (w, eps) in [(p.drive_n, 0.0), (-25.0, 300.0), (12.0, -900.0)] {
            for phi in turn(240) {
                let k = p.kinematics(phi, w, eps);
                let f = p.kinetostatics(&k);
                let de = (energy(&p, phi, w, eps, h) - energy(&p, phi, w, eps, -h)) / (2.0 * h);
                let cut_power = f.cut.dot(&k.v_s);
                let scale = 1e-6 * (1.0 + f.shaft_p.abs() + de.abs());
                assert_abs_diff_eq!(f.shaft_p, de - cut_power, epsilon = scale);
                assert_eq!((f.guide_friction, f.support_friction), (0.0, 0.0));
            }
        }
    }
}

/// With friction: the balance is closed by the friction losses μ·|N|·|v| of both guides,
/// which are ≥ 0, and each friction force opposes its slider's velocity.
#[test]
fn friction_dissipates() {
    let h = 1e-6;
    for p in heavy_rigid_cases(0.15, 0.2) {
        assert_eq!(p.validate(), Ok(()));
        for (w, eps) in [(p.drive_n, 0.0), (-25.0, 300.0)] {
            for phi in turn(240) {
                let k = p.kinematics(phi, w, eps);
                let f = p.kinetostatics(&k);
                let v7 = k.v_d.dot(&p.support_dir());
                // Self-locking of slider 7 exactly where CD is within the friction angle of
                // EQ's normal (slider 5 cannot lock here: μ5·tan ν_max = 0.087 < 1).
                let t = (k.beta + p.support_alpha).tan().abs();
                if (t - p.support_mu).abs() > 1e-9 {
                    assert_eq!(f.locked, t < p.support_mu, "phi = {phi}");
                }
                let (m5, m7) = if f.locked {
                    (0.0, 0.0)
                } else {
                    (p.guide_mu, p.support_mu)
                };
                let loss = m5 * f.guide_n.abs() * k.v_c.abs() + m7 * f.support_n.abs() * v7.abs();
                assert!(loss >= 0.0);
                assert_abs_diff_eq!(
                    f.guide_friction.abs(),
                    m5 * f.guide_n.abs(),
                    epsilon = 1e-12
                );
                assert_abs_diff_eq!(
                    f.support_friction.abs(),
                    m7 * f.support_n.abs(),
                    epsilon = 1e-12
                );
                assert!(f.guide_friction * k.v_c <= 0.0);
                assert!(f.support_friction * v7 <= 0.0);
                let de = (energy(&p, phi, w, eps, h) - energy(&p, phi, w, eps, -h)) / (2.0 * h);
                let scale = 1e-6 * (1.0 + f.shaft_p.abs() + de.abs());
                assert_abs_diff_eq!(f.shaft_p, de - f.cut.dot(&k.v_s) + loss, epsilon = scale);
                // The friction forces enter the slider balances.
                let s5 = k.rod_dir * f.rod_f - f.pin_c
                    + Vec2::new(f.guide_friction, f.guide_n - p.mass_c() * p.gravity_g)
                    - Vec2::new(p.mass_c() * k.a_c, 0.0);
                assert_abs_diff_eq!(s5.norm(), 0.0, epsilon = 1e-8);
            }
        }
    }
}

/// Default drive at 300 rpm: the knives' cutting force dominates the working stroke.
#[test]
fn cutting_load_needs_torque_in_the_working_stroke() {
    let p = params();
    let w = p.drive_n;
    let mean = |working: bool| {
        let (mut sum, mut n) = (0.0, 0);
        for phi in turn(3600) {
            let k = p.kinematics(phi, w, 0.0);
            if k.working == working {
                sum += p.kinetostatics(&k).shaft_p;
                n += 1;
            }
        }
        sum / n as f64
    };
    // Over a turn at constant speed the kinetic energy returns: the mean power is the cutting
    // and friction work; the working half draws more than the idle half.
    assert!(mean(true) > mean(false));
    let cut_work: f64 = turn(3600)
        .map(|phi| {
            let k = p.kinematics(phi, w, 0.0);
            -p.cut_force(&k).dot(&k.v_s) / 3600.0
        })
        .sum();
    assert!(cut_work > 0.0);
    assert!(0.5 * (mean(true) + mean(false)) > cut_work);
}

/// Paper 004's series form (1) against the exact x_C: the error is the truncation of
/// √(1 − u), u = sin²φ/λ2², after its linear term; that remainder grows with u, so the
/// largest error is at sin²φ = 1: `l1·λ2·(1 − 1/(2λ2²) − √(1 − 1/λ2²))` = 0.34103 mm
/// (λ2 = 2, l1 = 19 mm), the spec's 33.250 − 32.909 mm at φ = π/2.
#[test]
fn series_form_error() {
    let p = params();
    let ps = Params { series: true, ..p };
    let l2 = p.rod_lambda2;
    let bound = p.crank_l1 * l2 * (1.0 - 1.0 / (2.0 * l2 * l2) - (1.0 - 1.0 / (l2 * l2)).sqrt());
    let (mut max_x, mut at) = (0.0f64, 0.0);
    let mut max_s = 0.0f64;
    let mut slope = 0.0f64; // max |dS/dx_C| over the turn (exact kinematics)
    for j in 0..=36_000 {
        let phi = TAU * j as f64 / 36_000.0;
        let (k, ks) = (p.kinematics(phi, 1.0, 0.0), ps.kinematics(phi, 1.0, 0.0));
        let dx = ks.x_c - k.x_c;
        assert!(dx >= -1e-17, "the series form overestimates x_C: {dx}");
        if dx > max_x {
            (max_x, at) = (dx, phi);
        }
        max_s = max_s.max((ks.s - k.s).norm());
        if k.x_c_d.abs() > 1e-6 {
            slope = slope.max(k.s_d.norm() / k.x_c_d.abs());
        }
    }
    assert_abs_diff_eq!(max_x, bound, epsilon = 1e-15);
    assert_printed(max_x * 1e3, 0.341, 3);
    assert_abs_diff_eq!(at, FRAC_PI_2, epsilon = 1e-12);
    // S moves with x_C alone: |ΔS| ≤ max|dS/dx_C|·|Δx_C| (mean value theorem).
    assert!(
        max_s <= slope * max_x * (1.0 + 1e-9),
        "{max_s} vs {}",
        slope * max_x
    );
    assert!(max_s > max_x, "the holder amplifies the error: {max_s}");
    // Recorded for the documentation and the report: 0.346 mm at S (this computation).
    assert_printed(max_s * 1e3, 0.346, 3);
}

#[test]
fn refuses_what_cannot_assemble_naming_the_crank_angle() {
    // Q 15 mm further out: the holder cannot reach EQ with the slider near the crank.
    let p = Params {
        support_xq: 0.075,
        ..params()
    };
    let f = p.assembly_failure().expect("fails");
    assert!(f.worst > 1.0);
    // |c| reaches 1 exactly at the ends of the interval, and exceeds it in between.
    for phi in [f.from, f.to] {
        assert_abs_diff_eq!(p.abs_c(phi), 1.0, epsilon = 1e-9);
    }
    assert!(p.abs_c(0.5 * (f.from + f.to)) > 1.0);
    assert!(p.abs_c(f.from - 1e-3) < 1.0 && p.abs_c(f.to + 1e-3) < 1.0);
    // Independent: x_C where c = −1 ((x_Q − x_C)·cos α − y_Q·sin α = −l4... here c = +1 side)
    let (sa, ca) = p.support_alpha.sin_cos();
    let x_crit_hi = p.support_xq - (p.holder_l4 + p.support_yq * sa) / ca; // c = +1
    let x_crit_lo = p.support_xq + (p.holder_l4 - p.support_yq * sa) / ca; // c = −1
    let x_from = p.kinematics(f.from, 1.0, 0.0).x_c;
    assert!(
        (x_from - x_crit_hi).abs() < 1e-9 || (x_from - x_crit_lo).abs() < 1e-9,
        "{x_from} {x_crit_hi} {x_crit_lo}"
    );
    // Symmetric about φ = π for e = 0 (x_C is even in φ).
    assert_abs_diff_eq!(f.from + f.to, TAU, epsilon = 1e-9);
    let e = p.validate().unwrap_err();
    assert_eq!(e.param, "holder.l4");
    let msg = e.to_string();
    let deg = format!("{:.4} deg", f.from.to_degrees());
    assert!(msg.contains(&deg) && msg.contains("support.alpha"), "{msg}");

    // An interval through φ = 0: Q close to A, failing with the slider far out.
    let p = Params {
        support_xq: 0.030,
        ..params()
    };
    let f = p.assembly_failure().expect("fails");
    assert!(f.from < 0.0 && f.to > 0.0, "{f:?}");
    assert_abs_diff_eq!(f.from, -f.to, epsilon = 1e-9);
    assert_abs_diff_eq!(p.abs_c(f.to), 1.0, epsilon = 1e-9);
    // Nowhere: every angle.
    let p = Params {
        support_xq: 0.2,
        ..params()
    };
    let f = p.assembly_failure().unwrap();
    assert_eq!((f.from, f.to), (0.0, TAU));
    assert!(
        p.validate()
            .unwrap_err()
            .to_string()
            .contains("from 0.0000 deg to 360.0000 deg")
    );
    // Defaults and the paper's angles assemble.
    for a in [45.0, 50.0, 55.0, 60.0, 65.0, 70.0] {
        assert_eq!(with_alpha(a).assembly_failure(), None, "{a}");
    }
}

#[test]
fn validate_refuses_bad_parameters() {
    let p = params();
    let name = |q: Params| q.validate().unwrap_err().param;
    assert_eq!(name(Params { crank_l1: 0.0, ..p }), "crank.l1");
    assert_eq!(
        name(Params {
            rod_lambda2: 1.0,
            ..p
        }),
        "rod.lambda2"
    );
    assert_eq!(name(Params { crank_e: 0.02, ..p }), "rod.lambda2");
    assert_eq!(
        name(Params {
            series: true,
            crank_e: 0.001,
            ..p
        }),
        "crank.e"
    );
    assert_eq!(
        name(Params {
            holder_l4: -0.01,
            ..p
        }),
        "holder.l4"
    );
    assert_eq!(
        name(Params {
            holder_ls: 1.5,
            ..p
        }),
        "holder.lS"
    );
    assert_eq!(
        name(Params {
            support_alpha: 2.0,
            ..p
        }),
        "support.alpha"
    );
    assert_eq!(name(Params { branch: 0, ..p }), "assembly.branch");
    assert_eq!(name(Params { rod_m: -1.0, ..p }), "rod.m");
    assert_eq!(
        name(Params {
            support_mu: f64::NAN,
            ..p
        }),
        "support.mu"
    );
    assert_eq!(
        name(Params {
            feed_v: f64::INFINITY,
            ..p
        }),
        "feed.V"
    );
    // Friction does not refuse a parameter set: self-locking is flagged while running.
    assert_eq!(
        Params {
            support_mu: 5.0,
            ..p
        }
        .validate(),
        Ok(())
    );
    assert_eq!(Params { branch: -1, ..p }.validate(), Ok(()));
}

/// The friction solution agrees with its assumed signs everywhere on the turn.
#[test]
fn friction_signs_are_consistent() {
    let p = params();
    let mut locked = 0;
    for phi in turn(3600) {
        for w in [p.drive_n, -p.drive_n] {
            let k = p.kinematics(phi, w, 0.0);
            let f = p.kinetostatics(&k);
            let (s5, s7) = p.slip_signs(&k, sgn(w));
            let (m5, m7) = if f.locked {
                (0.0, 0.0)
            } else {
                (p.guide_mu, p.support_mu)
            };
            assert_eq!(f.guide_friction, -m5 * f.guide_n.abs() * s5);
            assert_eq!(f.support_friction, -m7 * f.support_n.abs() * s7);
            locked += usize::from(f.locked);
            // Reconstruct the slider 7 balance with |N7| in the friction force.
            let s7b =
                -f.pin_d + p.support_normal() * f.support_n + p.support_dir() * f.support_friction
                    - k.a_d * p.slider7_m;
            assert_abs_diff_eq!(s7b.norm(), 0.0, epsilon = 1e-9);
        }
    }
    // The spec's defaults self-lock slider 7 for 174.63° < φ < 185.37° (module docs), in both
    // directions of rotation: where |tan(β + α)| < support.mu.
    let zone = |phi: f64| {
        (p.kinematics(phi, 1.0, 0.0).beta + p.support_alpha)
            .tan()
            .abs()
            - p.support_mu
    };
    let expected = turn(3600).filter(|&phi| zone(phi) < 0.0).count();
    assert!(expected > 100);
    assert_eq!(locked, 2 * expected);
    assert!(zone(174.63f64.to_radians()) > 0.0 && zone(174.64f64.to_radians()) < 0.0);
    assert!(zone(185.36f64.to_radians()) < 0.0 && zone(185.37f64.to_radians()) > 0.0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]
    #[test]
    fn outputs_are_finite_and_periodic(
        phi in -50.0f64..50.0,
        w in -100.0f64..100.0,
        eps in -1e3f64..1e3,
        alpha in 45.0f64..70.0,
        turns in -3i32..3,
    ) {
        let p = with_alpha(alpha);
        let k = p.kinematics(phi, w, eps);
        let f = p.kinetostatics(&k);
        for x in [k.x_c, k.v_c, k.a_c, k.beta, k.beta_w, k.beta_eps, k.s.x, k.s.y, k.a_s.x,
                  k.a_s.y, f.rod_f, f.guide_n, f.support_n, f.shaft_tau, f.pin_c.x, f.pin_d.y] {
            prop_assert!(x.is_finite());
        }
        let k2 = p.kinematics(phi + TAU * f64::from(turns), w, eps);
        prop_assert!((k2.s - k.s).norm() < 1e-14);
        prop_assert!((k2.beta - k.beta).abs() < 1e-12);
    }
}

/// The structured solve ([`Params::solve_system`]) is Gaussian elimination with partial
/// pivoting of the module docs' frictionless 7×7 matrix ([`Params::system_matrix`],
/// `super::friction::solve7_for`): over a turn of every case, for the kinetostatic level's
/// first column (the rod's direction) and an elastic one (inertia coefficients), for several
/// right-hand sides at once, within 1e-12 of the solution's scale (the holder's dead point,
/// where both are singular, left out); and on dual numbers its derivative is the
/// elimination's.
#[test]
fn the_structured_solve_is_the_elimination() {
    use super::super::friction::solve7_for;
    use num_dual::Dual64;
    let bs = [
        [3.0, -20.0, 7.0, 40.0, -5.0, 11.0, 0.7],
        [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.6, -0.8, 0.0, 0.0, 0.0],
        [-2.0, 5.0, 0.1, 0.0, 30.0, -7.0, -0.4],
    ];
    let (mut worst, mut worst_dual, mut solved): (f64, f64, usize) = (0.0, 0.0, 0);
    for p in cases() {
        for phi in turn(720) {
            let k = p.kinematics(phi, p.drive_n, 0.0);
            let (beta, d, s) = p.holder(Dual64::new(k.x_c, 1.0));
            let c = [k.x_c, p.crank_e];
            let (dr, sr) = ([d[0].re, d[1].re], [s[0].re, s[1].re]);
            let rod = [k.rod_dir.x, k.rod_dir.y, 0.0, 0.0, 0.0, 0.0, 0.0];
            let inertia = [
                -p.mass_c(),
                0.0,
                -p.slider7_m * d[0].eps,
                -p.slider7_m * d[1].eps,
                -p.holder_m * s[0].eps,
                -p.holder_m * s[1].eps,
                -p.holder_j / p.holder_l4 * beta.eps,
            ];
            for col0 in [rod, inertia] {
                let a = p.system_matrix(col0, c, dr, sr, 0.0, 0.0);
                let (direct, ours) = match (solve7_for(a, bs), p.solve_system(col0, c, dr, sr, bs))
                {
                    (Some(direct), Some(ours)) => (direct, ours),
                    // singular for both: the holder's dead point
                    (None, None) => continue,
                    (direct, ours) => panic!(
                        "at {phi}: the elimination solves {}, the structured solve {}",
                        direct.is_some(),
                        ours.is_some()
                    ),
                };
                solved += 1;
                for (u, v) in ours.iter().zip(&direct) {
                    let scale = v.iter().fold(1.0f64, |m, z| m.max(z.abs()));
                    for (x, y) in u.iter().zip(v) {
                        worst = worst.max((x - y).abs() / scale);
                    }
                }
                // on dual numbers along x: the matrix's entries and the first column move
                let dual = |v: &[f64; 7], e: &[f64; 7]| -> [Dual64; 7] {
                    std::array::from_fn(|i| Dual64::new(v[i], e[i]))
                };
                let col0_d = dual(&col0, &[0.3, -0.1, 0.2, 0.0, 1.0, -0.5, 0.05]);
                let (cd, dd, sd) = (
                    [Dual64::new(k.x_c, 1.0), Dual64::from(p.crank_e)],
                    [d[0], d[1]],
                    [s[0], s[1]],
                );
                let z = Dual64::from(0.0);
                let bd = bs.map(|b| b.map(Dual64::from));
                let a = p.system_matrix(col0_d, cd, dd, sd, z, z);
                let (Some(direct), Some(ours)) =
                    (solve7_for(a, bd), p.solve_system(col0_d, cd, dd, sd, bd))
                else {
                    panic!("at {phi}: solved on f64, not on dual numbers");
                };
                for (u, v) in ours.iter().zip(&direct) {
                    let scale = v
                        .iter()
                        .fold(1.0f64, |m, z| m.max(z.re.abs() + z.eps.abs()));
                    for (x, y) in u.iter().zip(v) {
                        worst_dual = worst_dual.max((x.eps - y.eps).abs() / scale);
                    }
                }
            }
        }
    }
    println!("{solved} systems, worst {worst:e}, derivatives {worst_dual:e}");
    assert!(solved > 5000, "{solved} systems solved");
    assert!(worst < 1e-12, "off by {worst:e} of the solution");
    assert!(worst_dual < 1e-10, "derivatives off by {worst_dual:e}");
}
