//! The spec's reference values, the virtual-work identity, power balance, derivatives and the
//! β study of paper 002.

use super::*;
use crate::mechanisms::assert_printed;

const W100: f64 = 100.0 * TAU / 60.0;

/// No friction anywhere: guide and hinges.
fn frictionless(timing: Timing) -> Drive {
    let mut p = Params {
        timing,
        ..Params::default()
    };
    p.needles.guide_mu = 0.0;
    p.needles.joint_f = 0.0;
    p.drive().unwrap()
}

#[test]
fn reference_values_at_four_shaft_angles() {
    // timing, φ; s mm, v, a, ψ1 deg, α deg, ρ_p, Q_b, P_sh1, P_sh2, P_kr [f = 0], σ_H MPa, τ [f = 0]
    #[rustfmt::skip]
    let rows = [
        (Timing::Perforators, 0.5, [11.4693, 1.34321, 68.6558, 57.6393, -42.503, -0.11910, 23.5387, 23.5412, 20.4723, 39.0605, 37.9798, 75.215, 6.21031, 6.03848]),
        (Timing::Perforators, 1.0, [4.4829, -0.75873, 91.5989, 52.9549, 19.697, -0.03266, 30.4217, 30.3948, 25.7168, 37.3846, 38.2374, 64.637, -4.31001, -4.40832]),
        (Timing::Own, 1.3, [5.6667, 0.64784, 35.5093, 53.7505, -29.670, -0.21883, 13.5948, 13.6051, 11.8444, 18.9990, 18.5362, 53.847, 1.72406, 1.68206]),
        (Timing::Own, 1.45, [17.2993, 0.86526, -9.6724, 61.5372, -27.594, 0.10349, 28.7824, 28.7836, 25.0292, 39.5556, 38.6478, 86.856, 4.86808, 4.75636]),
    ];
    for (timing, phi, r) in rows {
        let (d, d0) = (Drive::default_with(timing), frictionless(timing));
        let k = d.kinematics(phi, W100, 0.0);
        let f = d.forces(&k, 0.0, true);
        let f0 = d0.forces(&d0.kinematics(phi, W100, 0.0), 0.0, true);
        let got = [
            (1000.0 * k.s, 4),
            (k.v, 5),
            (k.a, 4),
            (k.psi1.to_degrees(), 4),
            (k.alpha.to_degrees(), 3),
            (k.rho_p, 5),
            (f.q_b, 4),
            (f.p_sh1, 4),
            (f.p_sh2, 4),
            (f.p_kr, 4),
            (f0.p_kr, 4),
            (f.sigma_h / 1e6, 3),
            (f.tau, 5),
            (f0.tau, 5),
        ];
        for (i, ((x, decimals), reference)) in got.into_iter().zip(r).enumerate() {
            if timing == Timing::Own && phi == 1.45 && i >= 6 {
                // The spec prints Q_T = 57.484 N here; its own profile gives 57.4832 N
                // (s/S = 17.2993168/30, Q·(s/S − 0.55)/0.1 = 215.7463·0.2664389), see
                // `reference_geometry_and_the_angles_of_the_force_chain`. Every force of the
                // row scales with Q_b, 2e-5 below the spec's: they agree to 5e-5.
                assert!(
                    (x / reference - 1.0).abs() <= 5e-5,
                    "column {i}: {x} vs {reference}"
                );
            } else {
                assert_printed(x, reference, decimals);
            }
        }
    }
}

#[test]
fn reference_geometry_and_the_angles_of_the_force_chain() {
    let d = Drive::default_with(Timing::Perforators);
    assert_printed(d.psi_low.to_degrees(), 49.9332, 4);
    assert_printed(d.psi_high.to_degrees(), 70.0906, 4);
    assert_printed(d.r0, 0.117390, 6);
    let theta_c = |s: f64| {
        let c = d.pose(s).unwrap().c;
        (c[1] - d.p.o3[1]).atan2(c[0] - d.p.o3[0]).to_degrees()
    };
    assert_printed(theta_c(0.0), -14.4597, 4);
    assert_printed(theta_c(d.stroke), 14.4955, 4);
    let k_top = d.pose(d.stroke).unwrap().k;
    assert_printed(k_top[0].hypot(k_top[1]), 0.142578, 6);
    assert_printed(d.pose(Dual64::new(0.0, 1.0)).unwrap().psi1.eps, 11.79343, 5);
    let k = d.kinematics(0.5, W100, 0.0);
    let f = d.forces(&k, 0.0, true);
    for (x, r) in [(f.p_c, 23.7393), (f.p_b, 20.4364), (f.p_a, 20.4550)] {
        assert_printed(x, r, 4);
    }
    for (x, r) in [
        (k.cos_alpha_sh, 0.999999),
        (k.sin_gamma, 0.998328),
        (k.sin_mu, 0.998274),
        (k.sin_delta_psi, 0.999156),
    ] {
        assert_printed(x, r, 6);
    }
    let o = Drive::default_with(Timing::Own);
    // The spec prints 57.484 N; its profile, rising: Q·(s/S − s_in)/(mid − s_in) with s =
    // 17.2993168 mm, S = 30 mm, s_in = 0.55, mid = 0.65, Q = 22 kgf gives 57.4832 N.
    let k = o.kinematics(1.45, W100, 0.0);
    let by_hand = 22.0 * STANDARD_GRAVITY * (k.s / 0.030 - 0.55) / 0.1;
    assert_printed(o.stroke, 0.030, 12);
    assert!((o.pierce_load(&k) - by_hand).abs() <= 1e-9);
    assert_printed(o.pierce_load(&k), 57.4832, 4);
    // the smallest |ρ_p| over a turn, mm
    for (dr, r) in [(&d, 16.79), (&o, 43.85)] {
        let least = (0..36_000)
            .map(|i| {
                dr.kinematics(TAU * i as f64 / 36_000.0, 1.0, 0.0)
                    .rho_p
                    .abs()
            })
            .fold(f64::INFINITY, f64::min);
        assert_printed(1000.0 * least, r, 2);
    }
}

/// Shaft angles over a turn, off the phase boundaries.
fn turn(n: usize) -> impl Iterator<Item = f64> {
    (0..n).map(move |i| TAU * (i as f64 + 0.37) / n as f64)
}

#[test]
fn frictionless_cam_force_is_virtual_work_and_power_balances() {
    for timing in [Timing::Perforators, Timing::Own] {
        let d = frictionless(timing);
        for phi in turn(720) {
            let k = d.kinematics(phi, W100, 0.0);
            if k.psi1_s.abs() < 1e-9 {
                continue;
            }
            let f = d.forces(&k, 0.0, false);
            // (7) = Q_b/(L·cos α·dψ1/ds)
            let reference = f.q_b / (d.l * k.alpha.cos() * k.psi1_s.abs());
            assert!(
                (f.p_kr - reference).abs() <= 1e-12 * reference.abs().max(1e-3),
                "{timing:?} phi {phi}: {} vs {reference}",
                f.p_kr
            );
            // τ·ω = n·Q_b·v
            let (p_shaft, p_bar) = (f.tau * W100, d.p.n * f.q_b * k.v);
            assert!(
                (p_shaft - p_bar).abs() <= 1e-9 * p_bar.abs().max(1.0),
                "{timing:?} phi {phi}: {p_shaft} vs {p_bar}"
            );
        }
    }
}

#[test]
fn friction_only_dissipates() {
    for timing in [Timing::Perforators, Timing::Own] {
        let d = Drive::default_with(timing);
        let mut lost = 0.0;
        for phi in turn(1440) {
            let k = d.kinematics(phi, W100, 0.0);
            let f = d.forces(&k, 0.0, false);
            let loss = f.tau * W100 - d.p.n * f.q_b * k.v;
            assert!(
                loss >= -1e-9,
                "{timing:?} phi {phi}: friction gives power {loss}"
            );
            lost += loss;
        }
        assert!(lost > 0.0, "{timing:?}: friction dissipates over a turn");
    }
}

#[test]
fn derivatives_match_finite_differences() {
    for timing in [Timing::Perforators, Timing::Own] {
        let d = Drive::default_with(timing);
        let h = 1e-5;
        for phi in turn(97) {
            let k = d.kinematics(phi, 1.0, 0.0);
            let (m, p) = (
                d.kinematics(phi - h, 1.0, 0.0),
                d.kinematics(phi + h, 1.0, 0.0),
            );
            let scale = |x: f64| 1e-6 * (1.0 + x.abs());
            for (x, lo, hi) in [(k.s_d, m.s, p.s), (k.psi1_d, m.psi1, p.psi1)] {
                let d1 = (hi - lo) / (2.0 * h);
                assert!((x - d1).abs() <= scale(x), "{timing:?} {phi}: {x} vs {d1}");
            }
            let dd_psi = (p.psi1_d - m.psi1_d) / (2.0 * h);
            assert!((k.psi1_dd - dd_psi).abs() <= 1e-5 * (1.0 + dd_psi.abs()));
            let dd_s = (p.s_d - m.s_d) / (2.0 * h);
            assert!((k.s_dd - dd_s).abs() <= 1e-5 * (1.0 + dd_s.abs()));
            // dψ1/ds against the chain's ψ1 at neighbouring bar positions
            if k.s > 1e-4 && k.s < d.stroke - 1e-4 {
                let hs = 1e-7;
                let ds =
                    (d.pose(k.s + hs).unwrap().psi1 - d.pose(k.s - hs).unwrap().psi1) / (2.0 * hs);
                assert!(
                    (k.psi1_s - ds).abs() <= 1e-6 * ds.abs(),
                    "{ds} vs {}",
                    k.psi1_s
                );
            }
            // ρ_p: the curvature radius of the pitch curve K_cam(φ) from its differences
            let (a, b, c) = (
                d.pitch_point(phi - 1e-4),
                d.pitch_point(phi),
                d.pitch_point(phi + 1e-4),
            );
            let d1 = [(c[0] - a[0]) / 2e-4, (c[1] - a[1]) / 2e-4];
            let d2 = [
                (c[0] - 2.0 * b[0] + a[0]) / 1e-8,
                (c[1] - 2.0 * b[1] + a[1]) / 1e-8,
            ];
            let rho = d1[0].hypot(d1[1]).powi(3) / cross((d1[0], d1[1]), (d2[0], d2[1]));
            assert!(
                (k.rho_p.abs() - rho.abs()).abs() <= 1e-4 * rho.abs(),
                "{timing:?} phi {phi}: rho_p {} vs {rho}",
                k.rho_p
            );
        }
    }
}

#[test]
fn the_needle_curve_is_the_perforators_one() {
    let d = Drive::default_with(Timing::Perforators);
    let perforators = crate::mechanisms::perforators::physics::Params::default()
        .drive()
        .unwrap();
    for i in 0..=820 {
        let phi = (i as f64 / 10.0).to_radians();
        let (a, b) = (
            d.kinematics(phi, W100, 0.0),
            perforators.kinematics(phi, W100, 0.0),
        );
        assert!((a.s - b.s).abs() <= 1e-12, "phi {phi}: {} vs {}", a.s, b.s);
    }
}

/// Largest σ_H over the run-up of the rise (ψ1'' > 0), `own` timing, `kmk.beta = beta`, and
/// ψ1 over the rise.
fn run_up_stress(beta: f64) -> (f64, Vec<f64>) {
    let d = Params {
        timing: Timing::Own,
        beta,
        ..Params::default()
    }
    .drive()
    .unwrap();
    let psi = (0..=200)
        .map(|i| {
            d.kinematics(d.own.phi0 + d.own.forward * i as f64 / 200.0, W100, 0.0)
                .psi1
        })
        .collect();
    (d.run_up_stress(W100, 20_000), psi)
}

#[test]
fn raising_beta_lowers_the_contact_stress() {
    let table = [
        (0.40, 61.620),
        (0.48, 54.637),
        (0.60, 46.865),
        (0.80, 38.089),
        (1.00, 32.231),
        (1.20, 28.036),
        (1.40, 27.348),
    ];
    let runs: Vec<(f64, Vec<f64>)> = table.iter().map(|&(b, _)| run_up_stress(b)).collect();
    for ((beta, reference), (max, psi)) in table.iter().zip(&runs) {
        eprintln!("beta {beta}: {} MPa", max / 1e6);
        assert_printed(max / 1e6, *reference, 3);
        // ψ1(φ) is the same for every β
        assert!(
            psi.iter()
                .zip(&runs[0].1)
                .all(|(a, b)| (a - b).abs() <= 1e-12)
        );
    }
    // the maximum falls monotonically from 0.4 to 1.2
    for w in runs[..6].windows(2) {
        assert!(w[1].0 < w[0].0);
    }
    // 0.48 -> 1: the paper's 1.83-fold fall within 15 %
    let ratio = runs[1].0 / runs[4].0;
    assert!((ratio / 1.83 - 1.0).abs() <= 0.15, "ratio {ratio}");
    assert_printed(ratio, 1.6952, 4);
}

#[test]
fn refusals_name_the_loop_the_parameter_or_the_shaft_angle() {
    // what is changed, the parameter named, a word of the reason
    type Refusal = (fn(&mut Params), &'static str, &'static str);
    let refusals: [Refusal; 7] = [
        (|p| p.l_rod = 0.02, "kpm.l", "rocker-slider"),
        (|p| p.c = 0.05, "fb.c", "four-bar"),
        (|p| p.roller.r = 0.03, "roller.r", "shaft angle"),
        (|p| p.beta = 0.0, "kmk.beta", ""),
        (|p| p.n = 0.0, "legacy.branches", ""),
        (|p| p.fb_branch = 0.0, "fb.branch", ""),
        (|p| p.kpm_branch = 0.0, "kpm.branch", ""),
    ];
    for (edit, name, why) in refusals {
        let mut p = Params::default();
        edit(&mut p);
        let e = p.drive().unwrap_err();
        assert!(e.param == name && e.condition.contains(why), "{e}");
    }
}

#[test]
fn every_assembly_branch_closes_its_loops_and_balances_power() {
    let mut psi = Vec::new();
    for (fb, kpm) in [(1.0, -1.0), (-1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        let mut p = Params {
            fb_branch: fb,
            kpm_branch: kpm,
            ..Params::default()
        };
        p.needles.guide_mu = 0.0;
        p.needles.joint_f = 0.0;
        let d = p.drive().unwrap();
        let len = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
        let side = |p: [f64; 2], q: [f64; 2], x: [f64; 2]| {
            ((q[0] - p[0]) * (x[1] - p[1]) - (q[1] - p[1]) * (x[0] - p[0])).signum()
        };
        for i in 0..=20 {
            let q = d.pose(d.stroke * i as f64 / 20.0).unwrap();
            for (x, y, l) in [
                (q.c, p.o3, p.r_k),
                (q.c, q.d, p.l_rod),
                (q.a, d.o2, p.r),
                (q.a, q.b, p.c),
                (q.b, p.o3, p.b),
                (q.k, d.o2, d.l),
            ] {
                assert!((len(x, y) - l).abs() <= 1e-14, "branches {fb} {kpm}");
            }
            assert_eq!(side(p.o3, q.d, q.c), kpm);
            assert_eq!(side(d.o2, q.b, q.a), fb);
        }
        for phi in turn(90) {
            let k = d.kinematics(phi, W100, 0.0);
            let f = d.forces(&k, 0.0, false);
            let p_bar = d.p.n * f.q_b * k.v;
            assert!((f.tau * W100 - p_bar).abs() <= 1e-9 * p_bar.abs().max(1.0));
        }
        psi.push(d.psi_low);
    }
    // four different assemblies
    for i in 0..4 {
        for j in 0..i {
            assert!((psi[i] - psi[j]).abs() > 0.1, "{psi:?}");
        }
    }
}

#[test]
fn a_dead_point_within_the_stroke_is_refused_naming_the_loop() {
    // the pivot O3 moved so that the four-bar's coupler comes in line with its rocker
    let e = Params {
        o3: [-0.09, 0.27],
        ..Params::default()
    }
    .drive()
    .unwrap_err();
    assert!(
        e.param == "fb.b" && e.condition.contains("dead point") && e.condition.contains("four-bar"),
        "{e}"
    );
}
