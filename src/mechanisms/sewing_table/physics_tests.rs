//! Tests of `physics.rs`.

use super::*;
use crate::mechanisms::assert_printed;
use approx::assert_abs_diff_eq;
use std::f64::consts::TAU;

const W100: f64 = 100.0 * PI / 30.0;

#[test]
fn paper_synthesis_numbers() {
    let s = Params::default().synthesis();
    assert_printed(s.alpha1.to_degrees(), 5.22, 2);
    assert_printed(s.a1a2, 3.82, 2);
    assert_printed(s.k1, 10.83, 2);
    assert_printed(s.k2, 9.95, 2);
    assert_printed(s.alpha3.to_degrees(), 64.78, 2);
    assert_printed(s.k0, 0.88, 2);
    assert_printed(s.l2, 3.72, 2);
    // table.stroke = l2·unit = 0.11152 m
    assert_printed(Params::default().stroke(), 0.11152, 5);
}

#[test]
fn rocking_saddle_geometry_against_the_synthesis() {
    // Independent: the saddle's end positions on the circle. The chord is A1A2 (3.82); the
    // paper's k0 = k1 - k2 is not the saddle's true height difference (1.003), so its
    // l2 = 3.72 is not the saddle's true horizontal travel (3.686) either: the paper's choice,
    // kept as the translating table's travel.
    let p = Params::default();
    let end = p.rocking(p.forward + 0.1, 0.0, 0.0);
    let chord = (end.x.powi(2) + end.y.powi(2)).sqrt() / p.unit;
    assert_abs_diff_eq!(chord, p.synthesis().a1a2, epsilon = 1e-12);
    assert_printed(end.x / p.unit, 3.686, 3);
    assert_printed(end.y / p.unit, 1.003, 3);
    let start = p.rocking(p.forward + p.dwell_sew + p.ret + 0.1, 0.0, 0.0);
    assert_eq!((start.x, start.y), (0.0, 0.0));
}

#[test]
fn spec_reference_values_at_100_rpm() {
    let p = Params::default();
    let k = p.kinematics(0.5, W100, 0.0);
    assert_printed(k.c.x, 0.024560, 6);
    assert_printed(k.v, 1.29297, 5);
    assert_printed(k.a, 30.4377, 4);
    assert_eq!(k.c.phase, Phase::Forward);
    let k = p.kinematics(1.0, W100, 0.0);
    assert_printed(k.c.x, 0.094756, 6);
    assert_printed(k.v, 1.07433, 5);
    assert_printed(k.a, -35.5847, 4);
}

#[test]
fn half_travel_at_41_degrees() {
    let p = Params::default();
    let c = p.cyclogram();
    assert_abs_diff_eq!(c.forward_angle_at(0.5).to_degrees(), 41.0, epsilon = 1e-9);
    assert_abs_diff_eq!(
        p.kinematics(41f64.to_radians(), 1.0, 0.0).c.x,
        p.stroke() / 2.0,
        epsilon = 1e-15
    );
}

#[test]
fn velocities_and_accelerations_match_finite_differences() {
    for kind in [Kind::Translating, Kind::Rocking] {
        let p = Params {
            kind,
            law_return: MotionLaw::Poly345,
            ..Params::default()
        };
        let (w, eps) = (W100, 3.0);
        // a shaft with constant acceleration: phi(t) = phi + w t + eps t²/2
        for k in 0..360 {
            let phi = TAU * (k as f64 + 0.3) / 360.0;
            let h = 1e-6;
            let at = |t: f64| (phi + w * t + 0.5 * eps * t * t, w + eps * t);
            let x = |t: f64| {
                let (f, ww) = at(t);
                let k = p.kinematics(f, ww, eps);
                let r = p.rocking(f, ww, eps);
                (k.c.x, k.v, r.beta, r.w, r.x)
            };
            let k0 = p.kinematics(phi, w, eps);
            let r0 = p.rocking(phi, w, eps);
            let (a, b) = (x(-h), x(h));
            assert_abs_diff_eq!(k0.v, (b.0 - a.0) / (2.0 * h), epsilon = 1e-6);
            assert_abs_diff_eq!(k0.a, (b.1 - a.1) / (2.0 * h), epsilon = 1e-4);
            assert_abs_diff_eq!(r0.w, (b.2 - a.2) / (2.0 * h), epsilon = 1e-6);
            assert_abs_diff_eq!(r0.a, (b.3 - a.3) / (2.0 * h), epsilon = 1e-4);
            assert_abs_diff_eq!(r0.dx_dbeta * r0.w, (b.4 - a.4) / (2.0 * h), epsilon = 1e-6);
        }
    }
}

#[test]
fn power_balance_without_friction() {
    // tau*w = d/dt(m v²/2 + J w²/2) − F_ext·v, at constant and accelerating shaft
    for kind in [Kind::Translating, Kind::Rocking] {
        let p = Params {
            guide_f: 0.0,
            kind,
            ..Params::default()
        };
        for (w, eps, f_ext) in [(W100, 0.0, 0.0), (W100, 5.0, 0.0), (W100, 5.0, -37.0)] {
            for k in 0..360 {
                let phi = TAU * (k as f64 + 0.5) / 360.0;
                let (tau, power_kin) = match kind {
                    Kind::Translating => {
                        let km = p.kinematics(phi, w, eps);
                        let f = p.forces(&km, eps, f_ext);
                        (f.tau, p.table_m * km.v * km.a - f_ext * km.v)
                    }
                    Kind::Rocking => {
                        let r = p.rocking(phi, w, eps);
                        (
                            p.rocking_tau(&r, eps, f_ext),
                            p.rocking_j * r.w * r.a - f_ext * r.dx_dbeta * r.w,
                        )
                    }
                };
                let lhs = tau * w;
                let rhs = power_kin + p.cam_j * w * eps;
                assert_abs_diff_eq!(lhs, rhs, epsilon = 1e-9 * (1.0 + rhs.abs()));
            }
        }
    }
}

#[test]
fn friction_is_dissipative_and_solved_exactly() {
    let p = Params {
        guide_f: 0.05,
        ..Params::default()
    };
    let q = Params { guide_f: 0.0, ..p };
    for k in 0..360 {
        let phi = TAU * (k as f64 + 0.5) / 360.0;
        let km = p.kinematics(phi, W100, 0.0);
        let f = p.forces(&km, 0.0, 12.0);
        // the equation of the spec holds with N from the solved force
        let n = p.table_m * STANDARD_GRAVITY + (f.cam_f * km.theta.sin()).abs();
        assert_abs_diff_eq!(f.guide_n, n, epsilon = 1e-12 * n);
        assert_abs_diff_eq!(
            f.f_x,
            p.table_m * km.a + p.guide_f * n * sgn(km.v) + 0.0 - 12.0,
            epsilon = 1e-9 * (1.0 + f.f_x.abs())
        );
        assert_abs_diff_eq!(f.f_friction, -p.guide_f * n * sgn(km.v), epsilon = 1e-12);
        // friction only adds power drawn
        let f0 = q.forces(&km, 0.0, 12.0);
        assert!(f.tau * W100 >= f0.tau * W100 - 1e-12);
    }
}

#[test]
fn flank_and_hertz_stress() {
    let p = Params::default();
    for k in 0..720 {
        let phi = TAU * (k as f64 + 0.5) / 720.0;
        let km = p.kinematics(phi, W100, 0.0);
        let f = p.forces(&km, 0.0, 0.0);
        let rp = km.rho_pitch.abs();
        assert!(
            (f.rho_flank.abs() - (rp - p.roller.r)).abs() < 1e-12
                || (f.rho_flank.abs() - (rp + p.roller.r)).abs() < 1e-12
        );
        // independent σH of eq. 8
        let inv = 1.0 / p.roller.r + 1.0 / f.rho_flank;
        let expected = 0.418 * ((f.cam_f.abs() / p.roller.b) * 2.1e11 * inv).sqrt();
        assert_abs_diff_eq!(f.sigma_h, expected, epsilon = 1e-9 * expected.max(1.0));
        // in the dwells: pitch circle R0 + x
        if matches!(km.c.phase, Phase::DwellFar | Phase::DwellNear) {
            assert_abs_diff_eq!(km.rho_pitch, p.cam_r0 + km.c.x, epsilon = 1e-12);
            assert_eq!(km.theta, 0.0);
        }
    }
    // accelerating: the cam pushes +x on the inner flank; decelerating: the outer one
    let acc = p.forces(&p.kinematics(0.5, W100, 0.0), 0.0, 0.0);
    assert!(acc.f_x > 0.0 && acc.cam_f > 0.0);
    let dec = p.forces(&p.kinematics(1.0, W100, 0.0), 0.0, 0.0);
    assert!(dec.f_x < 0.0 && dec.cam_f < 0.0);
}

#[test]
fn undercut_is_refused_naming_angle_and_smallest_r0() {
    let p = Params::default();
    assert!(p.validate().is_ok());
    assert!(p.undercut(p.cam_r0).is_none());
    let r0_min = p.smallest_r0();
    let small = Params {
        cam_r0: 0.5 * r0_min,
        ..p
    };
    let e = small.validate().unwrap_err();
    assert_eq!(e.param, "cam.R0");
    assert!(
        e.condition.contains("undercut") && e.condition.contains("shaft angle"),
        "{e}"
    );
    assert!(e.condition.contains(&format!("{r0_min:.4}")), "{e}");
    // the reported radius works, a bit smaller does not
    assert!(
        Params {
            cam_r0: r0_min,
            ..p
        }
        .undercut(r0_min)
        .is_none()
    );
    assert!(p.undercut(r0_min - 2e-4).is_some());
    // the angle named lies in a travel phase where the pitch curve is tightest
    let (phi, _) = small.undercut(small.cam_r0).unwrap();
    let ph = small.cyclogram().at(phi).phase;
    assert!(matches!(ph, Phase::Forward | Phase::Return), "{ph:?}");
}

/// A fuzzed huge base radius once made the bisection spin for ever (the float spacing at
/// 1e20 is far above its 1e-7 m tolerance); it must end, finite.
#[test]
fn smallest_r0_terminates_for_huge_and_tiny_radii() {
    let p = Params::default();
    for r0 in [1e20, 1e300, 1e-300, 0.0] {
        let r = Params { cam_r0: r0, ..p }.smallest_r0();
        assert!(r.is_finite() || r0 >= 1e300, "{r0}: {r}");
    }
}

#[test]
fn other_refusals() {
    let p = Params::default();
    for (wrong, param) in [
        (Params { l1: 12.0, ..p }, "synth.l1"),
        (Params { alpha2: 1.6, ..p }, "synth.alpha2"),
        (Params { cam_e: 0.2, ..p }, "cam.e"),
        (Params { guide_f: 5.0, ..p }, "guide.f"),
        (
            Params {
                dwell_sew: 3.5,
                ..p
            },
            "cycle.dwell_sew",
        ),
    ] {
        assert_eq!(wrong.validate().unwrap_err().param, param);
    }
    // the rocking table has no slot cam to undercut
    assert!(
        Params {
            cam_r0: 0.02,
            kind: Kind::Rocking,
            ..p
        }
        .validate()
        .is_ok()
    );
}

#[test]
fn rocking_inertia_torque_is_larger() {
    // what the paper's redesign removes: the rocking table's peak inertia torque at the shaft
    // against the translating table's, same cyclogram and mass
    let p = Params {
        guide_f: 0.0,
        ..Params::default()
    };
    let (mut tr, mut ro) = (0.0f64, 0.0f64);
    for k in 0..3600 {
        let phi = TAU * k as f64 / 3600.0;
        tr = tr.max(p.forces(&p.kinematics(phi, W100, 0.0), 0.0, 0.0).tau.abs());
        ro = ro.max(p.rocking_tau(&p.rocking(phi, W100, 0.0), 0.0, 0.0).abs());
    }
    assert!(tr > 0.0 && ro > 0.0);
    // same travel and mass at radius R·unit: the swing's torque exceeds the slide's by (R·unit·α2/stroke)²
    let ratio = (p.r * p.unit * p.alpha2 / p.stroke()).powi(2);
    assert_abs_diff_eq!(ro / tr, ratio, epsilon = 1e-3 * ratio);
}
