//! Accuracy: convergence on problems with known solutions, the error estimates against the
//! true error, the dense outputs inside a step, the spectral radius.

use super::*;

#[test]
fn every_method_converges_on_a_damped_oscillator() {
    let o = Osc {
        k: 100.0,
        c: 0.5,
        m: 1.0,
    };
    let x = exact(&o, 2.0);
    for m in [Method::Auto, Method::Dopri5, Method::Radau5] {
        let e6 = (run(m, &o, 2.0, 1e-6, 1.0).unwrap() - x).abs();
        let e10 = (run(m, &o, 2.0, 1e-10, 1.0).unwrap() - x).abs();
        assert!(e6 < 1e-4, "{m:?} {e6}");
        assert!(e10 < 1e-8, "{m:?} {e10}");
        assert!(e10 < e6, "{m:?}");
    }
    let e = (run(Method::Rk4, &o, 2.0, 1e-6, 1e-3).unwrap() - x).abs();
    assert!(e < 1e-7, "rk4 {e}");
}

#[test]
fn stiff_oscillator_implicit_and_auto_are_accurate_explicit_is_refused_fast() {
    // ω = 1e6 rad/s, critically damped fast mode over 10 ms: 1e4 periods
    let o = Osc {
        k: 1e12,
        c: 2e6,
        m: 1.0,
    };
    for m in [Method::Radau5, Method::Auto] {
        let x = run(m, &o, 1e-2, 1e-6, 1.0).unwrap();
        assert!(x.abs() < 1e-9, "{m:?} {x}");
    }
    let e = run(Method::Rk4, &o, 1e-2, 1e-6, 1e-3).unwrap_err();
    assert!(e.contains("unstable"), "{e}");
    let mut it = Integrator::new(Settings {
        method: Method::Dopri5,
        max_steps: 20_000,
        ..Settings::default()
    });
    let mut y = [1.0, 0.0];
    let e = it.integrate(&o, 0.0, 1.0, &mut y).unwrap_err();
    assert!(e.contains("budget"), "{e}");
}

/// y' = −λ·(y − cos t) − sin t, y(0) = 1: the solution cos t whatever λ (Prothero–Robinson), a
/// stiff problem for large λ whose true local error is known.
struct Prothero {
    lambda: f64,
}

impl OdeSystem for Prothero {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = -self.lambda * (y[0] - t.cos()) - t.sin();
    }
    fn jacobian(&self, _t: f64, _y: &[f64], j: &mut [f64]) {
        j[0] = -self.lambda;
    }
}

/// One attempt of `method` over `h` from the exact state at `t0`: the error estimate and the true
/// local error in the same norm (`exact`: the solution at a time).
fn estimate_and_truth(
    method: Stepper,
    sys: &dyn OdeSystem,
    exact: &dyn Fn(f64) -> Vec<f64>,
    t0: f64,
    h: f64,
) -> (f64, f64) {
    let mut it = Integrator::new(Settings::default());
    let n = sys.dim();
    let y0 = exact(t0);
    let mut f0 = vec![0.0; n];
    sys.rhs(t0, &y0, &mut f0);
    let (mut y1, mut f1) = (vec![0.0; n], vec![0.0; n]);
    let mut st = Stats::default();
    let at = Start {
        sys,
        t: t0,
        y: &y0,
        f0: &f0,
    };
    let est = it
        .attempt(method, at, h, &mut y1, &mut f1, &mut st)
        .map_err(|e| e.reason)
        .unwrap()
        .err;
    let e: Vec<f64> = y1.iter().zip(exact(t0 + h)).map(|(a, b)| a - b).collect();
    let truth = match method {
        Stepper::Radau => it.radau_norm(&e, &y0),
        _ => it.norm(&e, &y0, &y1),
    };
    (est, truth)
}

/// The error estimates against the true local error over a ladder of step sizes, with the
/// factors stated in the solver's documentation:
/// - non-stiff (an oscillator): both estimates never below the true error (a step they accept
///   is at least as accurate as they say) and above it by at most 10³ (Dormand–Prince) and 10⁵
///   (Radau IIA), since each estimates an embedded solution of lower order; they grow with the
///   step as that order says, h⁵ and h⁴ (slopes within ±0.5);
/// - stiff (Prothero–Robinson, λ = 1e4, Radau IIA only): the estimate within a factor of 4 of
///   the true error either way.
#[test]
fn error_estimates_bound_the_true_error_within_a_stated_factor() {
    let osc = Osc {
        k: 1.0,
        c: 0.0,
        m: 1.0,
    };
    let osc_exact = |t: f64| vec![t.cos(), -t.sin()];
    let pr = Prothero { lambda: 1e4 };
    let pr_exact = |t: f64| vec![t.cos()];
    let ladder = [0.02, 0.05, 0.1, 0.2, 0.4];
    for (method, ratio_max, order) in [(Stepper::Dopri, 1e3, 5.0), (Stepper::Radau, 1e5, 4.0)] {
        let runs: Vec<(f64, f64)> = ladder
            .iter()
            .map(|&h| estimate_and_truth(method, &osc, &osc_exact, 0.3, h))
            .collect();
        for (h, (est, truth)) in ladder.iter().zip(&runs) {
            let r = est / truth;
            assert!(
                (1.0..=ratio_max).contains(&r),
                "{method:?} h {h}: estimate {est:e}, true {truth:e}"
            );
        }
        for k in 1..ladder.len() {
            let slope = (runs[k].0 / runs[k - 1].0).ln() / (ladder[k] / ladder[k - 1]).ln();
            assert!(
                (slope - order).abs() <= 0.5,
                "{method:?}: slope {slope} at h {}",
                ladder[k]
            );
        }
    }
    for h in [1e-3, 3e-3, 1e-2, 3e-2, 0.1] {
        let (est, truth) = estimate_and_truth(Stepper::Radau, &pr, &pr_exact, 0.3, h);
        let r = est / truth;
        assert!(
            (0.25..=4.0).contains(&r),
            "stiff h {h}: estimate {est:e}, true {truth:e}"
        );
    }
}

/// The interpolants events are located on, inside one step of the oscillator: Dormand–Prince's
/// continuous extension (order 4) and Radau IIA's collocation polynomial, each against the
/// exact solution and against the cubic Hermite of the step's ends, at a quarter, half and
/// three quarters of the step; at the ends each is the step's own state.
#[test]
fn the_methods_dense_outputs_follow_the_solution_inside_a_step() {
    let o = Osc {
        k: 100.0,
        c: 0.5,
        m: 1.0,
    };
    let y = [1.0, 0.0];
    let mut f0 = [0.0; 2];
    o.rhs(0.0, &y, &mut f0);
    for (stepper, h) in [(Stepper::Dopri, 0.05), (Stepper::Radau, 0.05)] {
        let mut it = Integrator::new(Settings::default());
        let (mut y1, mut f1) = ([0.0; 2], [0.0; 2]);
        let at = Start {
            sys: &o,
            t: 0.0,
            y: &y,
            f0: &f0,
        };
        let att = it
            .attempt(stepper, at, h, &mut y1, &mut f1, &mut Stats::default())
            .unwrap();
        let mut end = [0.0; 2];
        let ends = Ends {
            y: &y,
            f0: &f0,
            y1: &y1,
            f1: &f1,
            h,
        };
        att.interpolate(&ends, h, &mut end);
        assert!((end[0] - y1[0]).abs() < 1e-14, "{stepper:?} end");
        att.interpolate(&ends, 0.0, &mut end);
        assert!((end[0] - y[0]).abs() < 1e-14, "{stepper:?} start");
        for theta in [0.25, 0.5, 0.75] {
            let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
            att.interpolate(&ends, theta * h, &mut a);
            hermite(&ends, theta * h, &mut b);
            let x = exact(&o, theta * h);
            let (dense, cubic, at_end) = (
                (a[0] - x).abs(),
                (b[0] - x).abs(),
                (y1[0] - exact(&o, h)).abs(),
            );
            // measured: Dormand–Prince within 1.2 times the step's own error and 17 to 70
            // times closer than the Hermite; Radau IIA's polynomial (order 3 inside the step)
            // 1.8 to 4.5 times closer than the Hermite
            let ok = match stepper {
                Stepper::Dopri => dense < 2.0 * at_end && dense < cubic / 10.0,
                _ => dense < cubic / 1.5,
            };
            assert!(
                ok,
                "{stepper:?} theta {theta}: dense {dense:.3e}, hermite {cubic:.3e}, end {at_end:.3e}"
            );
        }
    }
}

/// The spectral radius in closed form (one or two rows, and a last column of zeros taken off)
/// agrees with the eigenvalues of nalgebra's Schur decomposition of the whole matrix: real and
/// complex pairs, a chain's Jacobian with its work column, stiff and soft.
#[test]
fn spectral_radius_agrees_with_the_eigenvalues() {
    let by_schur = |n: usize, a: &[f64]| {
        nalgebra::DMatrix::from_row_slice(n, n, a)
            .complex_eigenvalues()
            .iter()
            .map(|z| z.norm())
            .fold(0.0, f64::max)
    };
    // a small linear congruential sequence in [-1, 1), scaled over decades
    let mut s = 12345u64;
    let mut next = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    let (mut real, mut complex) = (0, 0);
    for case in 0..400 {
        let scale = 10f64.powi(case % 13 - 2);
        let (a, b, c, d) = (
            next(),
            next() * scale,
            next() * scale,
            next() * scale.sqrt(),
        );
        // [x, ẋ, W]: ẋ' = ẋ, ẍ = a·x + b·ẋ, Ẇ = c·x + d·ẋ, as a chain's Jacobian
        let chain = [0.0, 1.0, 0.0, -scale * scale * a.abs(), b, 0.0, c, d, 0.0];
        let two = [a * scale, b, c, d];
        let four: Vec<f64> = (0..16).map(|_| next() * scale).collect();
        for (n, m) in [(3, &chain[..]), (2, &two[..]), (4, &four[..])] {
            let (ours, schur) = (spectral_radius(n, m), by_schur(n, m));
            assert!(
                (ours - schur).abs() <= 1e-9 * schur.max(1e-300),
                "{n}x{n} {m:?}: {ours} against {schur}"
            );
        }
        let (ht, det) = (0.5 * (two[0] + two[3]), two[0] * two[3] - two[1] * two[2]);
        if ht * ht < det {
            complex += 1
        } else {
            real += 1
        }
    }
    // both branches of the 2×2 closed form were taken
    assert!(real > 50 && complex > 50, "{real} real, {complex} complex");
    assert_eq!(spectral_radius(3, &[f64::NAN; 9]), f64::INFINITY);
}
