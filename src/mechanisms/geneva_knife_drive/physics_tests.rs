//! Tests of `physics.rs`.

use super::*;
use crate::mechanisms::assert_printed;
use approx::assert_abs_diff_eq;
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_4, TAU};

const W: f64 = PI; // ω of the spec's reference table

fn params() -> Params {
    Params::default()
}

/// `p`, asserted valid (`Params::validate`).
#[track_caller]
fn valid(p: Params) -> Params {
    assert_eq!(p.validate(), Ok(()));
    p
}

#[test]
fn defaults_are_the_spec_table() {
    let p = params();
    assert_eq!(p.geneva_z, 4);
    assert_eq!(p.gear_i, 4);
    assert_eq!((p.geneva_r1, p.crank_r, p.rod_l), (0.08, 0.07, 0.35));
    assert_eq!((p.knife_m, p.rod_m), (12.0, 3.0));
    assert_eq!((p.crank_j, p.cross_j, p.driver_j), (0.05, 0.08, 0.03));
    assert_eq!((p.gear_eta, p.guide_mu, p.cut_f_max), (0.98, 0.1, 15000.0));
    assert_eq!(
        (p.cut_s_start, p.cut_s_full, p.cut_s_end),
        (0.070, 0.075, 0.135)
    );
    assert_abs_diff_eq!(p.drive_n * 30.0 / PI, 30.0, epsilon = 1e-12); // 30 rpm
    assert_printed(p.lambda(), 1.414, 3); // paper 003: λ = 1.414
    assert_abs_diff_eq!(p.a(), 0.08 * 2f64.sqrt(), epsilon = 1e-16);
    assert_abs_diff_eq!(p.lambda2(), 5.0, epsilon = 1e-14); // paper 003: λ2 = 5
    assert_eq!(p.stroke(), 0.14);
    assert_eq!(p.slider_mass(), 13.5);
    assert_eq!(p.validate(), Ok(()));
}

/// The spec's reference table (defaults, ω = π rad/s, ε = 0), to the digits printed.
///
/// Three cells of the spec do not reproduce; see `reference_values_from_geometry` for an
/// independent computation. The spec prints γ(0.3) = 0.063307, s(0.3) = 0.0026729 and
/// s(1.2) = 0.0074104; the closed forms (and the geometry) give 0.0633145, 0.0026727 and
/// 0.0074099. Every other cell, including v and a at those angles, matches.
#[test]
fn spec_reference_table() {
    let p = params();
    let k = p.kinematics(0.0, W, 0.0);
    assert_eq!((k.gamma, k.s), (0.0, 0.0));
    assert_abs_diff_eq!(k.v, 0.0, epsilon = 1e-15);
    assert_abs_diff_eq!(k.a, 0.0, epsilon = 1e-12);

    let k = p.kinematics(0.3, W, 0.0);
    assert_printed(k.gamma, 0.063315, 6); // spec prints 0.063307 (discrepancy)
    assert_printed(k.s, 0.0026727, 7); // spec prints 0.0026729 (discrepancy)
    assert_printed(k.v, 0.13247, 5);
    assert_printed(k.a, 5.4010, 4);

    let k = p.kinematics(FRAC_PI_4, W, 0.0);
    assert_abs_diff_eq!(k.gamma, FRAC_PI_4, epsilon = 1e-15);
    assert_printed(k.s, 0.14, 2);
    assert_abs_diff_eq!(k.s, 0.14, epsilon = 1e-15);
    assert_abs_diff_eq!(k.v, 0.0, epsilon = 1e-14);
    assert_printed(k.a, -51.542, 3);

    let k = p.kinematics(1.2, W, 0.0);
    assert_printed(k.gamma, 1.46462, 5);
    assert_printed(k.s, 0.0074099, 7); // spec prints 0.0074104 (discrepancy)
    assert_printed(k.v, -0.30696, 5);
    assert_printed(k.a, 10.458, 3);

    let k = p.kinematics(3.0, W, 0.0);
    assert!(k.dwell && !k.engaged);
    assert_eq!((k.gamma, k.s, k.v, k.a), (PI / 2.0, 0.0, 0.0, 0.0));
}

/// Independent of the closed forms: the cross angle from the roller's position
/// (driver centre at the origin, cross centre at (a, 0)), and the knife position from the
/// rod's length (crank pin at r2·(cos θ, sin θ), slider on the x axis at distance l from it,
/// solved by bisection, not by the square-root formula).
#[test]
fn reference_values_from_geometry() {
    let p = params();
    let (r1, a, r2, l) = (p.geneva_r1, p.a(), p.crank_r, p.rod_l);
    let phi_e = FRAC_PI_4;
    for (psi, gamma_ref, s_ref) in [(0.3, 0.0633145, 0.0026727), (1.2, 1.4646156, 0.0074099)] {
        let u: f64 = phi_e - psi;
        let (x, y) = (r1 * u.cos(), r1 * u.sin());
        // The slot through the roller turns by γ from its entry direction at angle π/4.
        let gamma = FRAC_PI_4 - y.atan2(a - x);
        assert_abs_diff_eq!(gamma, gamma_ref, epsilon = 5e-8);
        let theta = 4.0 * gamma;
        let (px, py) = (r2 * theta.cos(), r2 * theta.sin());
        let (mut lo, mut hi) = (px, px + l);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if (mid - px).powi(2) + py * py < l * l {
                lo = mid
            } else {
                hi = mid
            }
        }
        let s = (r2 + l) - 0.5 * (lo + hi);
        assert_abs_diff_eq!(s, s_ref, epsilon = 5e-11 + 5e-8);
        let k = p.kinematics(psi, W, 0.0);
        assert_abs_diff_eq!(k.gamma, gamma, epsilon = 1e-14);
        assert_abs_diff_eq!(k.s, s, epsilon = 1e-12);
    }
    // The spec's printed γ(0.3) = 0.063307 is 7.5e-6 rad away: 100× the printed precision.
    let k = p.kinematics(0.3, W, 0.0);
    assert!((k.gamma - 0.063307).abs() > 7e-6);
}

/// Paper 003's errata: its S factor would double the stroke; its V2 lacks the gear ratio i.
#[test]
fn paper_errata_are_not_copied() {
    let p = params();
    // The knife's lowest point is at ψ = φe (θ = π): s = 2·r2, not 4·r2.
    let k = p.kinematics(FRAC_PI_4, W, 0.0);
    assert_abs_diff_eq!(k.s, p.stroke(), epsilon = 1e-15);
    let invariant = 6.0 - (4.0 * k.gamma).cos() - 5.0 * k.nu.cos();
    assert_abs_diff_eq!(invariant * p.crank_r, k.s, epsilon = 1e-15);
    // v = r2·V1·i·γ'·ω with the paper's velocity invariant V1 = sin θ + cos θ·tan ν.
    for psi in [0.1, 0.3, 0.7, 1.2, 1.5] {
        let k = p.kinematics(psi, W, 0.0);
        let th = 4.0 * k.gamma;
        let v1 = th.sin() + th.cos() * (th.sin() / 5.0).asin().tan();
        assert_abs_diff_eq!(k.v, p.crank_r * v1 * 4.0 * k.gamma_d * W, epsilon = 1e-14);
    }
}

#[test]
fn invariants_for_four_slots() {
    let p = params();
    let g = p.geneva();
    // Largest γ' = 1/(λ − 1) = 2.4142 at ψ = π/4.
    let k = p.kinematics(FRAC_PI_4, W, 0.0);
    assert_printed(k.gamma_d, 2.4142, 4);
    assert_abs_diff_eq!(k.gamma_d, 1.0 / (p.lambda() - 1.0), epsilon = 1e-14);
    let n = 10_000;
    let max = (0..=n)
        .map(|j| p.kinematics(TAU * j as f64 / n as f64, W, 0.0).gamma_d)
        .fold(0.0, f64::max);
    assert_abs_diff_eq!(max, k.gamma_d, epsilon = 1e-12);
    // γ'' jumps from 0 to λ·cos(π/Z)/(λ² − 1) = 1.0 at entry.
    assert_eq!(p.kinematics(-1e-9, W, 0.0).gamma_dd, 0.0);
    let entry = p.kinematics(0.0, W, 0.0).gamma_dd;
    assert_printed(entry, 1.0, 1);
    assert_abs_diff_eq!(
        entry,
        p.lambda() * (PI / 4.0).cos() / (p.lambda().powi(2) - 1.0),
        epsilon = 1e-14
    );
    // The knife dwells 3/4 of the driver turn, at the top.
    assert_abs_diff_eq!(g.dwell_fraction(), 0.75, epsilon = 1e-15);
    let n = 100_000;
    let mut dwell = 0;
    for j in 0..n {
        let k = p.kinematics(TAU * j as f64 / n as f64, W, 0.0);
        if k.dwell {
            dwell += 1;
            assert_eq!((k.s, k.v, k.a, k.theta), (0.0, 0.0, 0.0, 0.0));
        } else {
            assert!(k.s >= 0.0 && k.s <= p.stroke() + 1e-15);
        }
    }
    assert_abs_diff_eq!(dwell as f64 / n as f64, 0.75, epsilon = 2.0 / n as f64);
    // At exit the knife is back at the top.
    let k = p.kinematics(PI / 2.0, W, 0.0);
    assert!(k.engaged);
    assert_abs_diff_eq!(k.s, 0.0, epsilon = 1e-16);
}

/// With i = 8 the crank turns twice per index: two knife strokes per driver turn.
#[test]
fn gear_ratio_multiple_of_z() {
    let p = valid(Params {
        gear_i: 8,
        ..params()
    });
    let phi_e = FRAC_PI_4;
    // Bottom at θ = π: γ = π/8 and 3π/8; top in between at γ = π/4 (ψ = φe).
    assert_abs_diff_eq!(p.kinematics(phi_e, W, 0.0).s, 0.0, epsilon = 1e-15);
    let bottoms = (0..=20_000)
        .map(|j| p.kinematics(2.0 * phi_e * j as f64 / 20_000.0, W, 0.0).s)
        .collect::<Vec<_>>()
        .windows(3)
        .filter(|w| w[1] > w[0] && w[1] >= w[2] && w[1] > 0.139)
        .count();
    assert_eq!(bottoms, 2);
    // Six slots, i = 6: the knife still runs its stroke once per index.
    let p = valid(Params {
        geneva_z: 6,
        gear_i: 6,
        ..params()
    });
    let g = p.geneva();
    assert_abs_diff_eq!(
        p.kinematics(g.half_engagement(), W, 0.0).s,
        p.stroke(),
        epsilon = 1e-15
    );
    assert_abs_diff_eq!(g.dwell_fraction(), 0.5 + 1.0 / 6.0, epsilon = 1e-15);
}

/// Angles of one turn, away from the entry and exit of the roller (where γ'' jumps).
fn smooth_angles(p: &Params, n: usize, margin: f64) -> Vec<f64> {
    let exit = 2.0 * p.geneva().half_engagement();
    (0..n)
        .map(|j| TAU * (j as f64 + 0.37) / n as f64)
        .filter(|&psi| psi > margin && (psi - exit).abs() > margin && psi < TAU - margin)
        .collect()
}

/// Velocities and accelerations against central differences in time along
/// φ(t) = φ0 + ω·t + ε·t²/2, ω(t) = ω + ε·t.
#[test]
fn time_derivatives_match_finite_differences() {
    let p = params();
    let h = 1e-6;
    for (w, eps) in [(PI, 0.0), (PI, 4.0), (-2.0, 7.5), (10.0, -30.0), (0.0, 3.0)] {
        for psi in smooth_angles(&p, 700, 1e-4) {
            let at = |t: f64| p.kinematics(psi + w * t + 0.5 * eps * t * t, w + eps * t, eps);
            let (k, kp, km) = (at(0.0), at(h), at(-h));
            let d = |fp: f64, fm: f64| (fp - fm) / (2.0 * h);
            let sc = w.abs().max(1.0).powi(2) + eps.abs();
            assert_abs_diff_eq!(k.v, d(kp.s, km.s), epsilon = 1e-7 * sc);
            assert_abs_diff_eq!(k.a, d(kp.v, km.v), epsilon = 1e-5 * sc);
            assert_abs_diff_eq!(k.cross_w, d(kp.gamma, km.gamma), epsilon = 1e-7 * sc);
            assert_abs_diff_eq!(k.cross_a, d(kp.cross_w, km.cross_w), epsilon = 1e-5 * sc);
            assert_abs_diff_eq!(k.nu_w, d(kp.nu, km.nu), epsilon = 1e-7 * sc);
            assert_abs_diff_eq!(k.nu_a, d(kp.nu_w, km.nu_w), epsilon = 1e-5 * sc);
            if k.engaged {
                // θ wraps at 2π: difference the unwrapped i·γ instead.
                assert_abs_diff_eq!(k.crank_w, 4.0 * d(kp.gamma, km.gamma), epsilon = 1e-6 * sc);
                assert_abs_diff_eq!(k.crank_a, d(kp.crank_w, km.crank_w), epsilon = 1e-5 * sc);
            }
            // ψ-derivatives are the ε = 0, ω = 1 velocities.
            let k1 = p.kinematics(psi, 1.0, 0.0);
            assert_abs_diff_eq!(k.s_d, k1.v, epsilon = 1e-15);
            assert_abs_diff_eq!(k.s_dd, k1.a, epsilon = 1e-13);
            assert_abs_diff_eq!(k.v, k.s_d * w, epsilon = 1e-13);
            assert_abs_diff_eq!(k.a, k.s_dd * w * w + k.s_d * eps, epsilon = 1e-11 * sc);
        }
    }
}

/// With μ = 0 and η = 1: τ·ω = d/dt(KE) + (F_cut − m_s·g)·v, dKE/dt by central differences
/// in time along the shaft's motion.
/// dKE/dt at the driver angle ψ, the driver turning at ω with ε: by central differences in time
/// (step `h`), not from the accelerations.
fn kinetic_energy_rate(p: &Params, psi: f64, w: f64, eps: f64, h: f64) -> f64 {
    let at = |t: f64| {
        let wt = w + eps * t;
        p.kinetic_energy(&p.kinematics(psi + w * t + 0.5 * eps * t * t, wt, eps), wt)
    };
    (at(h) - at(-h)) / (2.0 * h)
}

#[test]
fn power_balance_without_losses() {
    let p = Params {
        guide_mu: 0.0,
        gear_eta: 1.0,
        ..params()
    };
    let m_s = p.slider_mass();
    let h = 1e-6;
    for (w, eps) in [(PI, 0.0), (PI, 5.0), (3.0 * PI, -20.0), (-PI, 2.0)] {
        let angles = smooth_angles(&p, 2000, 1e-3);
        let balance = |psi: f64| {
            let dke = kinetic_energy_rate(&p, psi, w, eps, h);
            let k = p.kinematics(psi, w, eps);
            let f = p.kinetostatics(&k, w, eps);
            (
                f.shaft_tau * w,
                dke + (f.f_cut - m_s * STANDARD_GRAVITY) * k.v,
                f,
            )
        };
        let peak = angles
            .iter()
            .map(|&psi| balance(psi).0.abs())
            .fold(0.0, f64::max);
        assert!(peak > 100.0);
        let mut cutting = 0;
        for &psi in &angles {
            let (input, used, f) = balance(psi);
            assert!(
                (input - used).abs() <= 1e-8 * peak,
                "ψ = {psi}: τω = {input}, dKE/dt + load = {used}, peak {peak}"
            );
            assert_abs_diff_eq!(f.shaft_p, input, epsilon = 1e-9 * peak);
            if f.f_cut > 0.0 {
                cutting += 1;
            }
        }
        // The balance was checked while cutting too (w > 0 cuts on the way down; w < 0 on
        // the way back, which also descends).
        assert!(cutting > 0);
    }
}

/// With friction and gear losses the shaft supplies at least what the balance needs:
/// losses ≥ 0, and with η = 1 they are exactly the guide friction power μ·|N|·|v|.
#[test]
fn losses_are_dissipative() {
    let m_s = params().slider_mass();
    let h = 1e-6;
    for p in [
        params(),
        Params {
            gear_eta: 1.0,
            ..params()
        },
        Params {
            guide_mu: 0.0,
            gear_eta: 0.9,
            ..params()
        },
    ] {
        for psi in smooth_angles(&p, 1500, 1e-3) {
            let (w, eps) = (PI, 1.0);
            let dke = kinetic_energy_rate(&p, psi, w, eps, h);
            let k = p.kinematics(psi, w, eps);
            let f = p.kinetostatics(&k, w, eps);
            let loss = f.shaft_tau * w - dke - (f.f_cut - m_s * STANDARD_GRAVITY) * k.v;
            assert!(loss >= -1e-4, "ψ = {psi}: loss {loss}");
            if p.gear_eta == 1.0 {
                let friction = p.guide_mu * f.guide_n.abs() * k.v.abs();
                assert_abs_diff_eq!(loss, friction, epsilon = 1e-4);
            }
        }
    }
}

/// The friction equation is solved with its own sign of P, on both branches.
#[test]
fn slider_equation_holds_on_both_branches() {
    let p = valid(Params {
        guide_mu: 0.3,
        ..params()
    });
    let m_s = p.slider_mass();
    let (mut pos, mut neg) = (0, 0);
    for (w, eps) in [(PI, 0.0), (3.0 * PI, 0.0), (-2.0 * PI, 10.0)] {
        for psi in smooth_angles(&p, 1000, 1e-4) {
            let k = p.kinematics(psi, w, eps);
            let f = p.kinetostatics(&k, w, eps);
            let sgn = if k.v > 0.0 {
                1.0
            } else if k.v < 0.0 {
                -1.0
            } else {
                0.0
            };
            let residual = f.rod_f * k.nu.cos() - p.guide_mu * (f.rod_f * k.nu.sin()).abs() * sgn
                + m_s * STANDARD_GRAVITY
                - f.f_cut
                - m_s * k.a;
            assert!(
                residual.abs() <= 1e-9 * (1.0 + f.rod_f.abs()),
                "ψ = {psi}: residual {residual}"
            );
            assert_abs_diff_eq!(f.f_inertia, -m_s * k.a, epsilon = 1e-12);
            assert_abs_diff_eq!(f.guide_n, f.rod_f * k.nu.sin(), epsilon = 1e-9);
            if f.rod_f > 0.0 { pos += 1 } else { neg += 1 }
        }
    }
    assert!(
        pos > 100 && neg > 100,
        "both signs of P exercised: {pos} / {neg}"
    );
}

#[test]
fn dwell_forces() {
    let p = params();
    let m_s = p.slider_mass();
    let k = p.kinematics(3.0, W, 2.0);
    let f = p.kinetostatics(&k, W, 2.0);
    // The rod holds the knife's weight; the cross is locked; the shaft feels only the driver.
    assert_abs_diff_eq!(f.rod_f, -m_s * STANDARD_GRAVITY, epsilon = 1e-12);
    assert_eq!(
        (f.f_cut, f.crank_tau, f.cross_tau, f.geneva_f),
        (0.0, 0.0, 0.0, 0.0)
    );
    assert_abs_diff_eq!(f.shaft_tau, p.driver_j * 2.0, epsilon = 1e-15);
    assert_abs_diff_eq!(f.shaft_p, p.driver_j * 2.0 * W, epsilon = 1e-15);
    // While engaged the flank force is the cross torque over ρ.
    let k = p.kinematics(0.5, W, 0.0);
    let f = p.kinetostatics(&k, W, 0.0);
    assert_abs_diff_eq!(f.geneva_f * k.rho, f.cross_tau, epsilon = 1e-9);
    assert_abs_diff_eq!(f.shaft_tau, f.cross_tau * k.gamma_d, epsilon = 1e-9);
}

#[test]
fn gear_efficiency_by_power_flow() {
    let p = params();
    let ideal = Params {
        gear_eta: 1.0,
        ..params()
    };
    let mut seen = (false, false);
    for psi in smooth_angles(&p, 400, 1e-4)
        .into_iter()
        .filter(|&x| x < PI / 2.0)
    {
        let k = p.kinematics(psi, W, 0.0);
        let f = p.kinetostatics(&k, W, 0.0);
        let f1 = ideal.kinetostatics(&k, W, 0.0);
        let gear = f.cross_tau - p.cross_j * k.cross_a;
        let gear1 = f1.cross_tau - p.cross_j * k.cross_a;
        if f.crank_tau * k.crank_w > 0.0 {
            assert_abs_diff_eq!(gear, gear1 / 0.98, epsilon = 1e-9);
            seen.0 = true;
        } else if f.crank_tau * k.crank_w < 0.0 {
            assert_abs_diff_eq!(gear, gear1 * 0.98, epsilon = 1e-9);
            seen.1 = true;
        }
    }
    assert_eq!(seen, (true, true));
}

#[test]
fn cut_force_profile() {
    let p = params();
    assert_eq!(p.cut_force(0.069, 1.0), 0.0);
    assert_eq!(p.cut_force(0.070, 1.0), 0.0);
    assert_abs_diff_eq!(p.cut_force(0.0725, 1.0), 7500.0, epsilon = 1e-8);
    assert_eq!(p.cut_force(0.075, 1.0), 15000.0);
    assert_eq!(p.cut_force(0.1, 1.0), 15000.0);
    assert_eq!(p.cut_force(0.135, 1.0), 15000.0);
    assert_eq!(p.cut_force(0.1351, 1.0), 0.0);
    // Only while the knife descends.
    assert_eq!(p.cut_force(0.1, 0.0), 0.0);
    assert_eq!(p.cut_force(0.1, -1.0), 0.0);
    // A step when s_full = s_start.
    let q = valid(Params {
        cut_s_full: 0.070,
        ..params()
    });
    assert_eq!(q.cut_force(0.070, 1.0), 15000.0);
    // Over a turn the knife meets the stack on the way down only.
    let k = p.kinematics(0.65, W, 0.0);
    assert!(k.v > 0.0 && k.s > 0.075);
    assert_eq!(p.kinetostatics(&k, W, 0.0).f_cut, 15000.0);
    let k = p.kinematics(0.9, W, 0.0);
    assert!(k.v < 0.0 && k.s > 0.075);
    assert_eq!(p.kinetostatics(&k, W, 0.0).f_cut, 0.0);
}

#[test]
fn validate_refuses() {
    let bad = |p: Params| p.validate().expect_err("should be refused");
    let e = bad(Params {
        geneva_z: 2,
        ..params()
    });
    assert_eq!(e.to_string(), "geneva.Z = 2: needs at least 3 slots");
    assert_eq!(
        bad(Params {
            geneva_z: 0,
            gear_i: 0,
            ..params()
        })
        .param,
        "geneva.Z"
    );
    let e = bad(Params {
        gear_i: 5,
        ..params()
    });
    assert_eq!(
        e.to_string(),
        "gear.i = 5: must be a whole multiple of geneva.Z = 4 so the crank makes whole turns per index"
    );
    assert_eq!(
        bad(Params {
            gear_i: 0,
            ..params()
        })
        .param,
        "gear.i"
    );
    assert_eq!(
        bad(Params {
            gear_i: 2,
            ..params()
        })
        .param,
        "gear.i"
    );
    assert_eq!(
        bad(Params {
            geneva_r1: 0.0,
            ..params()
        })
        .param,
        "geneva.r1"
    );
    assert_eq!(
        bad(Params {
            geneva_r1: -0.1,
            ..params()
        })
        .param,
        "geneva.r1"
    );
    assert_eq!(
        bad(Params {
            geneva_r1: f64::NAN,
            ..params()
        })
        .param,
        "geneva.r1"
    );
    assert_eq!(
        bad(Params {
            crank_r: 0.0,
            ..params()
        })
        .param,
        "crank.r"
    );
    assert_eq!(
        bad(Params {
            crank_r: -0.07,
            ..params()
        })
        .param,
        "crank.r"
    );
    let e = bad(Params {
        rod_l: 0.07,
        ..params()
    });
    assert_eq!(
        e.to_string(),
        "rod.l = 0.07: the rod must be longer than crank.r = 0.07 for the crank to turn"
    );
    assert_eq!(
        bad(Params {
            rod_l: 0.05,
            ..params()
        })
        .param,
        "rod.l"
    );
    assert_eq!(
        bad(Params {
            rod_l: f64::INFINITY,
            ..params()
        })
        .param,
        "rod.l"
    );
    for (name, p) in [
        (
            "knife.m",
            Params {
                knife_m: -1.0,
                ..params()
            },
        ),
        (
            "rod.m",
            Params {
                rod_m: -0.1,
                ..params()
            },
        ),
        (
            "crank.J",
            Params {
                crank_j: -1e-3,
                ..params()
            },
        ),
        (
            "cross.J",
            Params {
                cross_j: -1e-3,
                ..params()
            },
        ),
        (
            "driver.J",
            Params {
                driver_j: f64::NAN,
                ..params()
            },
        ),
        (
            "gear.eta",
            Params {
                gear_eta: 0.0,
                ..params()
            },
        ),
        (
            "gear.eta",
            Params {
                gear_eta: 1.01,
                ..params()
            },
        ),
        (
            "gear.eta",
            Params {
                gear_eta: -0.5,
                ..params()
            },
        ),
        (
            "guide.mu",
            Params {
                guide_mu: -0.1,
                ..params()
            },
        ),
        (
            "guide.mu",
            Params {
                guide_mu: 5.0,
                ..params()
            },
        ),
        (
            "cut.F_max",
            Params {
                cut_f_max: -1.0,
                ..params()
            },
        ),
        (
            "cut.s_start",
            Params {
                cut_s_start: -0.01,
                ..params()
            },
        ),
        (
            "cut.s_start",
            Params {
                cut_s_start: 0.15,
                cut_s_full: 0.15,
                cut_s_end: 0.15,
                ..params()
            },
        ),
        (
            "cut.s_full",
            Params {
                cut_s_full: 0.06,
                ..params()
            },
        ),
        (
            "cut.s_end",
            Params {
                cut_s_end: 0.074,
                ..params()
            },
        ),
        (
            "cut.s_end",
            Params {
                cut_s_end: 0.141,
                ..params()
            },
        ),
        (
            "drive.n",
            Params {
                drive_n: f64::NAN,
                ..params()
            },
        ),
    ] {
        let e = bad(p);
        assert_eq!(e.param, name, "{e}");
        assert!(!e.condition.is_empty());
    }
    // Zero masses and inertias, μ = 0, η = 1, F_max = 0, a window of zero width, a window
    // of the full stroke, three slots with i = 9 and a reversed nominal speed are fine.
    for p in [
        Params {
            knife_m: 0.0,
            rod_m: 0.0,
            crank_j: 0.0,
            cross_j: 0.0,
            driver_j: 0.0,
            ..params()
        },
        Params {
            guide_mu: 0.0,
            gear_eta: 1.0,
            cut_f_max: 0.0,
            ..params()
        },
        Params {
            cut_s_start: 0.1,
            cut_s_full: 0.1,
            cut_s_end: 0.1,
            ..params()
        },
        Params {
            cut_s_start: 0.0,
            cut_s_full: 0.0,
            cut_s_end: 0.14,
            ..params()
        },
        Params {
            geneva_z: 3,
            gear_i: 9,
            drive_n: -5.0,
            ..params()
        },
    ] {
        assert_eq!(p.validate(), Ok(()), "{p:?}");
    }
    // The jam limit: μ·tan ν_max < 1, tan ν_max = 1/√24 for λ2 = 5.
    let limit = 24f64.sqrt();
    assert_eq!(
        Params {
            guide_mu: limit * 0.999,
            ..params()
        }
        .validate(),
        Ok(())
    );
    assert_eq!(
        bad(Params {
            guide_mu: limit * 1.001,
            ..params()
        })
        .param,
        "guide.mu"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// The kinematics at one shaft acceleration carried to another by `at_shaft_accel`
    /// (what the torque split `shaft.tau0`/`shaft.J_red` evaluates) are the kinematics
    /// computed there from scratch, to the bit.
    #[test]
    fn at_shaft_accel_is_the_full_evaluation(
        phi in -20.0f64..20.0,
        w in -100.0f64..100.0,
        eps0 in -1e4f64..1e4,
        eps in -1e4f64..1e4,
    ) {
        let p = params();
        let g = p.geneva();
        let moved = p.at_shaft_accel(&p.kinematics_of(&g, phi, w, eps0), w, eps);
        prop_assert_eq!(moved, p.kinematics_of(&g, phi, w, eps));
    }

    /// Any angle, speed and acceleration: every output finite; ψ in one turn.
    #[test]
    fn outputs_are_finite(
        phi in prop_oneof![-1e9f64..1e9, -20.0f64..20.0, Just(1e9), Just(-1e9)],
        w in -100.0f64..100.0,
        eps in -1e4f64..1e4,
    ) {
        let p = params();
        let k = p.kinematics(phi, w, eps);
        let f = p.kinetostatics(&k, w, eps);
        prop_assert!((0.0..TAU).contains(&k.psi));
        prop_assert!((0.0..TAU).contains(&k.theta));
        prop_assert!(k.s >= 0.0 && k.s <= p.stroke() + 1e-15);
        prop_assert_eq!(k.dwell, !k.engaged);
        for x in [k.gamma, k.gamma_d, k.gamma_dd, k.cross_w, k.cross_a, k.crank_w, k.crank_a,
                  k.nu, k.nu_w, k.nu_a, k.s_d, k.s_dd, k.v, k.a, k.rho,
                  f.f_cut, f.f_inertia, f.rod_f, f.guide_n, f.crank_tau, f.cross_tau,
                  f.geneva_f, f.shaft_tau, f.shaft_p, p.kinetic_energy(&k, w)] {
            prop_assert!(x.is_finite());
        }
    }

    /// φ and φ + 2πk (|φ| up to ~1e9, both signs) give the same state, up to the rounding of
    /// φ itself (≈ |φ|·2.2e-16 rad).
    #[test]
    fn periodic_in_the_driver_angle(
        psi0 in 0.0f64..TAU,
        turns in prop_oneof![-160_000_000i64..160_000_000, -10i64..10],
        w in -10.0f64..10.0,
        eps in -50.0f64..50.0,
    ) {
        let p = params();
        let exit = 2.0 * p.geneva().half_engagement();
        // Stay clear of the instants where the state jumps (γ'' at entry and exit, γ at ψ = 0).
        prop_assume!(psi0 > 1e-5 && psi0 < TAU - 1e-5 && (psi0 - exit).abs() > 1e-5);
        let phi = psi0 + turns as f64 * TAU;
        let d_psi = 4.0 * phi.abs() * f64::EPSILON + 1e-15; // rounding of φ
        let (k0, k) = (p.kinematics(psi0, w, eps), p.kinematics(phi, w, eps));
        prop_assert!((k.psi - psi0).abs() <= d_psi + 1e-14, "ψ {} vs {}", k.psi, psi0);
        prop_assert_eq!(k.engaged, k0.engaged);
        let sc = w * w + eps.abs() + 1.0;
        // Bounds on the ψ-sensitivities of each output (|γ'| ≤ 2.42, |ds/dψ| ≤ 0.82 m, ...).
        prop_assert!((k.gamma - k0.gamma).abs() <= 3.0 * d_psi + 1e-13);
        prop_assert!((k.s - k0.s).abs() <= 1.0 * d_psi + 1e-13);
        prop_assert!((k.v - k0.v).abs() <= 20.0 * sc * d_psi + 1e-12 * sc);
        prop_assert!((k.a - k0.a).abs() <= 1e3 * sc * d_psi + 1e-10 * sc);
        prop_assert!((k.cross_a - k0.cross_a).abs() <= 1e2 * sc * d_psi + 1e-11 * sc);
    }
}
