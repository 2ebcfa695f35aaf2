//! Tests of `elastic.rs`.

use super::super::friction::solve7_for;
use super::*;
use crate::solver::chain::assert_jacobian_at;
use approx::assert_abs_diff_eq;
use std::f64::consts::{PI, TAU};

fn ode(p: &Params, k: f64, zeta: f64, w: f64) -> RodOde<'_> {
    RodOde::new(
        p,
        RodOde::spring(p, k, zeta),
        ShaftPath::new(0.0, 0.0, w, 0.0),
        dead_point_threshold(p),
        crate::solver::chain::Peaks::new(0.0),
    )
}

/// Without friction the swapped solve is Lagrange's equation of the one-DoF chain:
/// `M(x)·ẍ + ½·M'(x)·ẋ² = P·ĉ_x + F_cut·S'` (no weights, holder.J ≠ 0).
#[test]
fn frictionless_solve_is_lagrange() {
    let p = Params {
        guide_mu: 0.0,
        support_mu: 0.0,
        holder_j: 3e-4,
        ..Params::default()
    };
    let o = ode(&p, 2e8, 0.05, p.drive_n);
    for j in 0..40 {
        let t = 0.2 * (j as f64 + 0.3) / 40.0;
        let r = o.rigid(t);
        for (dx, xd) in [(0.0, r.kin.v_c), (2e-6, 0.3), (-1e-5, -0.7)] {
            let x = r.kin.x_c + dx;
            let ev = o.eval(&r, x, xd);
            let h = 1e-7;
            let dm = (reduced_mass(&p, x + h) - reduced_mass(&p, x - h)) / (2.0 * h);
            let (_, _, s) = p.holder(Dual2::new(x, 1.0, 0.0));
            let q = ev.force * ev.rod_dir[0] + r.load.x * s[0].v1 + r.load.y * s[1].v1;
            let inertia = reduced_mass(&p, x) * ev.xdd;
            let lhs = inertia + 0.5 * dm * xd * xd;
            let scale = 1.0 + q.abs() + inertia.abs();
            assert_abs_diff_eq!(lhs, q, epsilon = 1e-6 * scale);
            assert!(!ev.locked);
        }
    }
}

/// The Jacobian on dual numbers agrees with central differences of the right-hand side.
#[test]
fn jacobian_is_the_derivative_of_the_rhs() {
    let p = Params::default();
    let o = ode(&p, 2e8, 0.05, p.drive_n);
    for j in 0..60 {
        let t = 0.2 * (j as f64 + 0.41) / 60.0;
        let r = o.rigid(t);
        let y = [r.kin.x_c - 3e-7, r.kin.v_c + 0.01, 0.0];
        assert_jacobian_at(&o, t, y, [1e-9, 1e-6]);
    }
}

/// On the rigid motion with the kinetostatic rod force in the spring, the swapped solve
/// returns the rigid acceleration (the two levels are one system), friction included.
#[test]
fn rigid_state_reproduces_the_kinetostatic_level() {
    let p = Params::default();
    let k = 1e12;
    let o = ode(&p, k, 0.0, p.drive_n);
    let (mut checked, mut fading) = (0, 0);
    for j in 0..360 {
        let t = 0.2 * (j as f64 + 0.37) / 360.0;
        let r = o.rigid(t);
        let f = p.kinetostatics(&r.kin);
        // shorten the rod by P/k: x with |C − B| = l2 − P/k
        let ry = p.crank_e - r.kin.b.y;
        let x = r.kin.b.x + ((r.l_kin - f.rod_f / k).powi(2) - ry * ry).sqrt();
        let ev = o.eval(&r, x, r.kin.v_c);
        if f.rod_f.abs() > 1e4 {
            continue; // the wedge: P/k no longer small against rounding of x
        }
        let g = o.lock_indicator(x, ev.rod_dir);
        if g > 0.0 && g < WEDGE_BAND {
            fading += 1;
            continue; // the friction fades here (module docs): not the kinetostatic level's
        }
        assert_eq!(ev.locked, f.locked, "phi {}", r.kin.phi.to_degrees());
        assert_abs_diff_eq!(ev.force, f.rod_f, epsilon = 1e-3 * (1.0 + f.rod_f.abs()));
        assert_abs_diff_eq!(ev.xdd, r.kin.a_c, epsilon = 1e-3 * (1.0 + r.kin.a_c.abs()));
        assert_abs_diff_eq!(
            ev.z[6],
            f.support_n,
            epsilon = 1e-2 * (1.0 + f.support_n.abs())
        );
        checked += 1;
    }
    assert!(checked > 300 && fading > 0, "{checked} {fading}");
}

/// The jamming window of the defaults at the rigid geometry is the kinetostatic one.
#[test]
fn lock_indicator_marks_the_kinetostatic_window() {
    let p = Params::default();
    let o = ode(&p, 2e8, 0.05, 1.0);
    for deg in [170.0, 174.6, 174.65, 180.0, 185.35, 185.4, 200.0] {
        let phi: f64 = f64::to_radians(deg);
        let k = p.kinematics(phi, 1.0, 0.0);
        let g = o.lock_indicator(k.x_c, [k.rod_dir.x, k.rod_dir.y]);
        assert_eq!(g <= 0.0, p.kinetostatics(&k).locked, "{deg}");
    }
    let _ = (PI, TAU);
}

/// The system with friction solved by the rank-two update ([`with_friction`]) of the
/// frictionless solve ([`Params::solve_system`]) is the direct elimination of the full matrix,
/// for every sign combination of both friction factors, over a turn: with the kinetostatic
/// system's first column (the rod force's direction, whose determinant ratio is the jamming
/// indicator: the wedge included, where the update divides by a small ratio) and with an inertia
/// column as the elastic level's. Within 1e-11 of the solution's scale (measured: 1.5e-13, with
/// the ratio down to 8e-4).
#[test]
fn friction_by_the_rank_two_update_is_the_direct_solve() {
    let p = Params::default();
    let (m5, m7) = (p.mass_c(), p.slider7_m);
    let rhs = [3.0, -20.0, 7.0, 40.0, -5.0, 11.0, 0.7];
    let (mut worst, mut smallest_det): (f64, f64) = (0.0, f64::INFINITY);
    for j in 0..720 {
        let phi = TAU * (j as f64 + 0.3) / 720.0;
        let k = p.kinematics(phi, p.drive_n, 0.0);
        let (_, d, s) = p.holder(k.x_c);
        let c = [k.x_c, p.crank_e];
        let rod = [k.rod_dir.x, k.rod_dir.y, 0.0, 0.0, 0.0, 0.0, 0.0];
        let inertia = [-m5, 0.0, -m7 * 0.4, -m7 * 0.9, -1.0, 0.5, -0.2];
        for col0 in [rod, inertia] {
            // the frictionless solve as the models make it, the update on it, against the
            // elimination of the full matrix
            let [e0, w] = friction_columns(p.support_dir());
            let Some(solved) = p.solve_system(col0, c, d, s, [rhs, e0, w]) else {
                continue; // the holder's dead point
            };
            for (k5, k7) in sign_combinations(p.guide_mu, p.support_mu) {
                let a = p.system_matrix(col0, c, d, s, k5, k7);
                let Some([direct]) = solve7_for(a, [rhs]) else {
                    continue;
                };
                smallest_det = smallest_det.min(friction_det(&solved[1], &solved[2], k5, k7).abs());
                let updated = with_friction(&solved, k5, k7);
                let scale = direct.iter().fold(1.0f64, |m, z| m.max(z.abs()));
                for (u, v) in updated.iter().zip(direct) {
                    worst = worst.max((u - v).abs() / scale);
                }
            }
        }
    }
    println!("worst {worst:e}, smallest det ratio {smallest_det:e}");
    assert!(
        smallest_det < 0.05,
        "the wedge was not met: {smallest_det:e}"
    );
    assert!(
        worst < 1e-11,
        "the update is off by {worst:e} of the solution"
    );
}

/// The jamming indicator the right-hand side takes from its own elimination (Sherman–Morrison
/// on the swapped first column) is [`RodOde::lock_indicator`]'s, which the event functions
/// use, over a turn and through the window: within 1e-12.
#[test]
fn the_rhs_jamming_indicator_is_the_event_functions() {
    let p = Params::default();
    let o = ode(&p, 2e8, 0.05, p.drive_n);
    let (mut worst, mut near): (f64, usize) = (0.0, 0);
    for j in 0..3600 {
        let t = 0.2 * (j as f64 + 0.37) / 3600.0;
        let r = o.rigid(t);
        for (dx, xd) in [(0.0, r.kin.v_c), (3e-6, 0.2)] {
            let x = r.kin.x_c + dx;
            let ev = o.eval(&r, x, xd);
            let g = o.lock_indicator(x, ev.rod_dir);
            worst = worst.max((ev.lock_g - g).abs() / g.abs().max(1.0));
            near += usize::from(g.abs() < WEDGE_BAND);
        }
    }
    assert!(near > 0, "the window was not met");
    assert!(worst < 1e-12, "off by {worst:e}");
}
