use super::*;

/// m·x'' + c·x' + k·x = F·sin(Ω t), with the analytic solution from rest.
struct Osc {
    k: f64,
    c: f64,
    m: f64,
}

impl OdeSystem for Osc {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = (-self.k * y[0] - self.c * y[1]) / self.m;
    }
    fn jacobian(&self, _t: f64, _y: &[f64], j: &mut [f64]) {
        j.copy_from_slice(&[0.0, 1.0, -self.k / self.m, -self.c / self.m]);
    }
}

fn exact(o: &Osc, t: f64) -> f64 {
    // x(0) = 1, v(0) = 0, underdamped
    let w0 = (o.k / o.m).sqrt();
    let z = o.c / (2.0 * (o.k * o.m).sqrt());
    let wd = w0 * (1.0 - z * z).sqrt();
    (-z * w0 * t).exp() * ((wd * t).cos() + z * w0 / wd * (wd * t).sin())
}

fn run(method: Method, o: &Osc, t1: f64, rtol: f64, max_step: f64) -> Result<f64, String> {
    let mut it = Integrator::new(Settings {
        method,
        rtol,
        atol: rtol * 1e-3,
        max_step,
        max_steps: 200_000,
    });
    let mut y = [1.0, 0.0];
    // several communication steps, as fmi2DoStep calls them
    let n = 10;
    for i in 0..n {
        let a = t1 * i as f64 / n as f64;
        let b = t1 * (i + 1) as f64 / n as f64;
        it.integrate(o, a, b, &mut y)?;
    }
    Ok(y[0])
}

/// Radau IIA at `rtol` (`atol` the same), no step limit.
fn radau_at(rtol: f64) -> Integrator {
    Integrator::new(Settings {
        method: Method::Radau5,
        rtol,
        atol: rtol,
        max_step: 0.0,
        max_steps: 100_000,
    })
}

/// `calls` calls of 1 ms from t = 0, as `fmi2DoStep` makes them: the work of them all.
fn in_ms_calls(it: &mut Integrator, sys: &dyn OdeSystem, y: &mut [f64], calls: usize) -> Stats {
    let mut total = Stats::default();
    for i in 0..calls {
        let (a, b) = (i as f64 * 1e-3, (i + 1) as f64 * 1e-3);
        total.add(&it.integrate(sys, a, b, y).unwrap());
    }
    total
}

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

/// A call's work is bounded by its budget, which grows with the span: a request that cannot fit
/// is refused before a step (the fewest steps `max_step` allows, or `auto`'s measured rate), one
/// that turns out not to fit when a tenth of its budget is spent; the state is not advanced.
#[test]
fn a_call_does_at_most_its_work_budget_and_refuses_early_what_cannot_fit() {
    assert_eq!(work_budget(1e-3), WORK_BASE + WORK_RATE * 1e-3);
    assert_eq!(work_budget(1e3), WORK_MAX);
    let o = Osc {
        k: 1e12,
        c: 2e6,
        m: 1.0,
    };
    // rk4 with a step of 1e-9 s over 1 s: 4e9 right-hand sides at the least
    let mut it = Integrator::new(Settings {
        method: Method::Rk4,
        max_step: 1e-9,
        ..Settings::default()
    });
    let mut y = [1.0, 0.0];
    let e = it.integrate(&o, 0.0, 1.0, &mut y).unwrap_err();
    assert!(
        e.contains("needs about 4.000e9") && e.contains("communication steps of at most"),
        "{e}"
    );
    assert!(it.mem.stats.work() <= 1.0, "refused before a step");
    assert_eq!(y, [1.0, 0.0]);
    // dopri5 on the stiff oscillator over 5 s (a budget of WORK_MAX): its stability-bound steps
    // would need some 9e6; refused once a tenth of the budget is spent, naming the method
    let mut it = Integrator::new(Settings {
        method: Method::Dopri5,
        ..Settings::default()
    });
    let e = it.integrate(&o, 0.0, 5.0, &mut y).unwrap_err();
    let budget = work_budget(5.0);
    let work = it.mem.stats.work();
    assert!(e.contains("does not fit") && e.contains("stiff"), "{e}");
    assert!(
        (0.1 * budget..0.1 * budget + 100.0).contains(&work),
        "{work}"
    );
    // radau5 does the same call well inside it
    let mut it = Integrator::new(Settings {
        method: Method::Radau5,
        ..Settings::default()
    });
    let mut y = [1.0, 0.0];
    it.integrate(&o, 0.0, 5.0, &mut y).unwrap();
    assert!(
        it.mem.stats.work() < 0.05 * budget,
        "{}",
        it.mem.stats.work()
    );
}

/// A ball on a unilateral spring (contact when x < 0): an event at each landing and lift-off.
struct Bounce;
impl OdeSystem for Bounce {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = -9.81 + if y[0] < 0.0 { -1e6 * y[0] } else { 0.0 };
    }
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0];
    }
}

#[test]
fn contact_events_are_located_and_energy_is_kept() {
    // elastic contact: the ball returns to its drop height
    for m in [Method::Auto, Method::Dopri5, Method::Radau5] {
        let mut it = Integrator::new(Settings {
            method: m,
            rtol: 1e-9,
            atol: 1e-12,
            max_step: 1e-2,
            max_steps: 1_000_000,
        });
        let mut y = [1.0, 0.0];
        let mut peak: f64 = 0.0;
        let mut t = 0.0;
        while t < 1.8 {
            it.integrate(&Bounce, t, t + 1e-3, &mut y).unwrap();
            t += 1e-3;
            if t > 0.5 {
                peak = peak.max(y[0]);
            }
        }
        assert!((peak - 1.0).abs() < 1e-4, "{m:?}: {peak}");
        assert!(it.mem.stats.events >= 2, "{m:?}: {:?}", it.mem.stats);
    }
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

/// A rigid speed with dwells: in turn k (t ∈ [k, k + 1)) a lobe of sign (−1)^k for half the
/// turn, then a rest at exactly zero. The events it records (time, before, after).
struct Dwells {
    seen: std::cell::RefCell<Vec<(f64, f64, f64)>>,
}

impl OdeSystem for Dwells {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, _t: f64, _y: &[f64], dy: &mut [f64]) {
        dy[0] = 1.0;
    }
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, t: f64, _y: &[f64], g: &mut [f64]) {
        let k = t.floor();
        let s = t - k;
        let sign = if k as i64 % 2 == 0 { 1.0 } else { -1.0 };
        g[0] = if s < 0.5 {
            sign * (std::f64::consts::TAU * s).sin()
        } else {
            0.0
        };
    }
    fn on_event(&self, t: f64, _y: &[f64], before: &[f64], after: &[f64]) {
        self.seen.borrow_mut().push((t, before[0], after[0]));
    }
}

#[test]
fn an_event_function_resting_at_zero_holds_its_sign() {
    let mut g = [0.0, -0.0, 2.0, 0.0, 0.0];
    hold_signs(&mut g, &[-1.0, -HELD, -3.0, 5.0]);
    assert_eq!(g, [-HELD, -HELD, 2.0, HELD, HELD]);
    const { assert!(HELD * HELD > 0.0 && HELD * HELD < f64::MIN_POSITIVE * 1.0001) };
    // through the integrator, in communication steps: an event where a lobe comes to rest
    // (t = 0.5, 1.5, ..., held at the lobe's sign) and where the next lobe leaves the rest to the
    // other side (t = 1, 2, ...: a change of sign from the held one, as a Model Exchange host
    // sees it), the held sign carried from one communication step to the next; none at the start
    let sys = Dwells {
        seen: Default::default(),
    };
    let mut it = Integrator::new(Settings::default());
    let mut y = [0.0];
    let h = 0.01;
    for j in 0..475 {
        let t = j as f64 * h;
        it.integrate(&sys, t, t + h, &mut y).unwrap();
    }
    let seen = sys.seen.borrow();
    assert_eq!(seen.len(), 9, "{seen:?}");
    for (j, &(t, before, after)) in seen.iter().enumerate() {
        // the system sees its own values (a held zero is zero again)
        let k = j / 2;
        let lobe = if k % 2 == 0 { 1.0 } else { -1.0 };
        if j % 2 == 0 {
            assert!((t - (k as f64 + 0.5)).abs() < 1e-9, "{seen:?}");
            assert!(before * lobe > 0.0 && after == 0.0, "{seen:?}");
        } else {
            assert!((t - (k as f64 + 1.0)).abs() < 1e-9, "{seen:?}");
            assert!(before == 0.0 && after * lobe < 0.0, "{seen:?}");
        }
    }
    assert_eq!(it.mem.stats.events, 9);
}

/// Van der Pol's oscillator, y1'' = μ((1 − y1²)y1' − y1): stiff on its slow branches, not in
/// its fast jumps, so `auto` switches both ways.
struct VanDerPol {
    mu: f64,
}

impl OdeSystem for VanDerPol {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = self.mu * ((1.0 - y[0] * y[0]) * y[1]) - y[0];
    }
    fn jacobian(&self, _t: f64, y: &[f64], j: &mut [f64]) {
        j.copy_from_slice(&[
            0.0,
            1.0,
            -2.0 * self.mu * y[0] * y[1] - 1.0,
            self.mu * (1.0 - y[0] * y[0]),
        ]);
    }
}

/// The integrator's whole memory is one value: an integrator restored from it at any
/// communication step replays the rest of the run bit for bit, under every method, `auto`
/// switching between them included. Restoring only part of it (the step size and the mode, as
/// before `Memory`) does not.
#[test]
fn a_restored_integrator_replays_every_step_bit_for_bit() {
    let sys = VanDerPol { mu: 200.0 };
    // a run over two periods (about 650), communication steps short enough to end inside
    // the runs of steps that `auto`'s switch counters count
    let (n, h) = (2600, 0.25);
    let window = 40;
    for method in [Method::Auto, Method::Dopri5, Method::Radau5, Method::Rk4] {
        let settings = Settings {
            method,
            rtol: 1e-6,
            atol: 1e-9,
            max_step: if method == Method::Rk4 { 1e-3 } else { 1.0 },
            max_steps: 2_000_000,
        };
        let (n, h) = if method == Method::Rk4 {
            (20, 0.05)
        } else {
            (n, h)
        };
        let mut it = Integrator::new(settings);
        let mut y = [2.0, 0.0];
        let mut saved = vec![(it.save(), y)];
        for k in 0..n {
            it.integrate(&sys, k as f64 * h, (k + 1) as f64 * h, &mut y)
                .unwrap();
            saved.push((it.save(), y));
        }
        if method == Method::Auto {
            assert!(it.mem.stats.switches >= 4, "{:?}", it.mem.stats);
        }
        // every save where a switch counter runs, and a sample of the others
        let counting: Vec<usize> = (0..n)
            .filter(|&k| saved[k].0.stiff_count > 0 || saved[k].0.nonstiff_count > 0)
            .collect();
        if method == Method::Auto {
            assert!(!counting.is_empty());
        }
        let replay = |from: usize, memory: Memory| {
            let mut it = Integrator::new(settings);
            it.restore(memory);
            let mut y = saved[from].1;
            let mut out = vec![];
            for k in from..(from + window).min(n) {
                it.integrate(&sys, k as f64 * h, (k + 1) as f64 * h, &mut y)
                    .unwrap();
                out.push((it.save(), y));
            }
            out
        };
        let bits = |v: &[(Memory, [f64; 2])]| -> Vec<Vec<u64>> {
            v.iter()
                .map(|(m, y)| {
                    m.to_numbers()
                        .iter()
                        .chain(y)
                        .map(|x| x.to_bits())
                        .collect()
                })
                .collect()
        };
        let mut partial_diverged = 0;
        for from in (0..n).step_by(13).chain(counting) {
            let memory = saved[from].0;
            let end = (from + window).min(n);
            assert_eq!(
                bits(&replay(from, memory)),
                bits(&saved[from + 1..=end]),
                "{method:?} from step {from}"
            );
            let part = Memory {
                h_next: memory.h_next,
                stiff: memory.stiff,
                stats: memory.stats,
                ..Memory::default()
            };
            let states = |v: &[(Memory, [f64; 2])]| -> Vec<[u64; 2]> {
                v.iter().map(|(_, y)| y.map(f64::to_bits)).collect()
            };
            if states(&replay(from, part)) != states(&saved[from + 1..=end]) {
                partial_diverged += 1;
            }
        }
        if method == Method::Auto {
            assert!(
                partial_diverged > 0,
                "the switch counters matter under auto"
            );
        }
    }
}

/// y' = 1 from 0 with the event function (y − 0.5)² − 0.05²: two crossings, at t = 0.45 and
/// 0.55, inside any step longer than 0.1 that spans them. The events it records.
struct Pair {
    seen: std::cell::RefCell<Vec<f64>>,
}

impl OdeSystem for Pair {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, _t: f64, _y: &[f64], dy: &mut [f64]) {
        dy[0] = 1.0;
    }
    fn jacobian(&self, _t: f64, _y: &[f64], j: &mut [f64]) {
        j[0] = 0.0;
    }
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = (y[0] - 0.5).powi(2) - 0.05f64.powi(2);
    }
    fn on_event(&self, t: f64, _y: &[f64], _before: &[f64], _after: &[f64]) {
        self.seen.borrow_mut().push(t);
    }
}

/// Both crossings of a pair inside one step are found, by every method: approaching one, the
/// step is limited by the function's rate (from the step before); a first step of a call that
/// spans the pair (no rate yet: a step of 1 from the start) sees it on the interpolant at its
/// middle.
#[test]
fn a_pair_of_crossings_inside_one_step_is_found() {
    for method in [Method::Auto, Method::Dopri5, Method::Radau5, Method::Rk4] {
        for first_step in [0.0, 1.0] {
            let sys = Pair {
                seen: Default::default(),
            };
            let mut it = Integrator::new(Settings {
                method,
                max_step: 1.0,
                ..Settings::default()
            });
            it.mem.h_next = first_step;
            let mut y = [0.0];
            it.integrate(&sys, 0.0, 1.0, &mut y).unwrap();
            let seen = sys.seen.borrow();
            assert_eq!(
                seen.len(),
                2,
                "{method:?}, first step {first_step}: {seen:?}"
            );
            assert!(
                (seen[0] - 0.45).abs() < 1e-9 && (seen[1] - 0.55).abs() < 1e-9,
                "{seen:?}"
            );
        }
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

/// y' = −λ·(y − cos ωt) − ω·sin ωt: the smooth solution cos ωt, stiff for large λ.
struct SmoothStiff {
    lambda: f64,
    omega: f64,
}

impl OdeSystem for SmoothStiff {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let w = self.omega;
        dy[0] = -self.lambda * (y[0] - (w * t).cos()) - w * (w * t).sin();
    }
    fn jacobian(&self, _t: f64, _y: &[f64], j: &mut [f64]) {
        j[0] = -self.lambda;
    }
}

#[test]
fn radau_steps_of_a_call_are_equal_and_share_their_factorization() {
    // calls of 1 ms, as fmi2DoStep makes them, with steps the error allows shorter than a call:
    // the call is taken in equal steps, so that they and the next calls' reuse one factorization
    // instead of a shortened last step needing its own and the next call's first another (with
    // that, these cases needed 0.6 to 1.2 factorizations per step; now 0.07 to 0.43)
    let sys = |omega| SmoothStiff { lambda: 1e4, omega };
    for (omega, rtol) in [
        (300.0, 1e-6),
        (1000.0, 1e-6),
        (2000.0, 1e-6),
        (1000.0, 1e-8),
        (2000.0, 1e-8),
        (2000.0, 1e-10),
    ] {
        let sys = sys(omega);
        let mut it = radau_at(rtol);
        let mut y = [1.0];
        let mut worst: f64 = 0.0;
        let mut total = Stats::default();
        for i in 0..1000 {
            let (a, b) = (i as f64 * 1e-3, (i + 1) as f64 * 1e-3);
            let st = it.integrate(&sys, a, b, &mut y).unwrap();
            total.add(&st);
            worst = worst.max((y[0] - (omega * b).cos()).abs());
        }
        assert!(total.steps > 1000, "steps shorter than a call: {total:?}");
        assert!(
            2 * total.decomps <= total.steps,
            "omega {omega}, rtol {rtol}: {total:?}"
        );
        assert!(worst < 100.0 * rtol, "error {worst:.2e} at rtol {rtol}");
    }
}

#[test]
fn an_event_is_confirmed_with_a_few_real_steps_near_its_root() {
    // Dormand-Prince makes six right-hand sides an attempt, plus one at each call's start and
    // after each event: what is left over the accepted and rejected steps are the attempts that
    // confirm the events. Regula falsi on the real steps' values, started at the interpolant's
    // root, needs 2.6 an event here (bisection from the step's start needed 9.3)
    let mut it = Integrator::new(Settings {
        method: Method::Dopri5,
        rtol: 1e-9,
        atol: 1e-12,
        max_step: 1e-2,
        max_steps: 1_000_000,
    });
    let (mut y, calls) = ([1.0, 0.0], 1800);
    for i in 0..calls {
        let t = i as f64 * 1e-3;
        it.integrate(&Bounce, t, t + 1e-3, &mut y).unwrap();
    }
    let st = it.mem.stats;
    assert_eq!(st.events, 4, "{st:?}");
    let confirming = st.rhs_evals - 6 * (st.steps + st.rejected) - calls - st.events;
    assert!(
        confirming <= 6 * 4 * st.events,
        "{} attempts for {} events: {st:?}",
        confirming as f64 / 6.0,
        st.events
    );
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

/// y' = −a(t)·y, stiff (a = 1e6 1/s) until `t_soft`, then soft (a = 1 1/s).
struct StiffThenSoft {
    t_soft: f64,
}

impl StiffThenSoft {
    fn a(&self, t: f64) -> f64 {
        if t < self.t_soft { 1e6 } else { 1.0 }
    }
}

impl OdeSystem for StiffThenSoft {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = -self.a(t) * y[0];
    }
    fn jacobian(&self, t: f64, _y: &[f64], j: &mut [f64]) {
        j[0] = -self.a(t);
    }
    /// The change of `a` is an event, so Radau IIA takes a new Jacobian there.
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, t: f64, _y: &[f64], g: &mut [f64]) {
        g[0] = t - self.t_soft;
    }
}

/// `auto` leaves the implicit method after three stability checks in a row, a check every 20
/// accepted steps counted over the calls: in calls of one step each it leaves 52 steps after
/// the stiffness ended (it left after 3 when each call's first step counted as the 0th, a check).
#[test]
fn auto_checks_stability_every_twenty_steps_across_calls() {
    let o = StiffThenSoft { t_soft: 0.01 };
    let dt = 1e-3;
    let mut it = Integrator::new(Settings {
        method: Method::Auto,
        rtol: 1e-6,
        atol: 1e-9,
        max_step: dt,
        max_steps: 200_000,
    });
    let mut y = [1.0];
    let mut soft_at = None;
    let mut explicit_again = None;
    for i in 0..400 {
        let t = i as f64 * dt;
        it.integrate(&o, t, t + dt, &mut y).unwrap();
        if it.mem.stiff && t >= o.t_soft && soft_at.is_none() {
            soft_at = Some(it.mem.stats.steps);
        }
        if soft_at.is_some() && !it.mem.stiff && explicit_again.is_none() {
            explicit_again = Some(it.mem.stats.steps);
        }
    }
    let (soft_at, back) = (
        soft_at.expect("implicit on the stiff stretch"),
        explicit_again,
    );
    let back = back.expect("explicit again on the soft stretch");
    // at least two checks 20 steps apart after the one that first found the step stable
    assert!(
        back - soft_at >= 40,
        "explicit again {} steps after the stiffness ended",
        back - soft_at
    );
}

#[test]
fn a_call_cut_short_at_its_end_does_not_grow_the_next_calls_first_step() {
    // calls of 1 ms whose last step is cut to the call's end: its error, tiny where the cut is
    // short, grew the step beyond what the error allows, and the next call's first attempt failed
    // (before: 249 rejected attempts in 607 steps at 4e6, rtol 1e-3; now none, and at most 8 %
    // in the other runs, the controller's own)
    for (k, rtol) in [(4e6, 1e-3), (4e6, 1e-6), (1e7, 1e-6), (1e8, 1e-8)] {
        let o = Osc { k, c: 0.0, m: 1.0 };
        let mut it = Integrator::new(Settings {
            method: Method::Dopri5,
            rtol,
            atol: rtol * 1e-3,
            max_step: 0.0,
            max_steps: 100_000,
        });
        let total = in_ms_calls(&mut it, &o, &mut [1.0, 0.0], 200);
        assert!(total.steps > 400, "steps shorter than a call: {total:?}");
        assert!(
            10 * total.rejected <= total.steps,
            "k {k}, rtol {rtol}: {total:?}"
        );
    }
}

#[test]
fn growing_steps_after_a_transient_share_their_factorizations() {
    // a stiff solution released off its slow manifold: the step grows from microseconds to the
    // call's length as the transient decays. A factorization is kept while the controller would
    // grow the step by at most a factor 2 (Hairer's QUOT2 for costly factorizations; with his
    // small-system 1.2 these cases made 0.35 to 0.43 factorizations per accepted step; now
    // 0.16 to 0.26)
    for (lambda, rtol, y0) in [
        (1e5, 1e-7, 3.0),
        (1e6, 1e-6, 2.0),
        (1e6, 1e-8, 2.0),
        (1e8, 1e-6, 1.5),
    ] {
        let sys = SmoothStiff {
            lambda,
            omega: 50.0,
        };
        let mut it = Integrator::new(Settings {
            method: Method::Radau5,
            rtol,
            atol: rtol,
            max_step: 0.0,
            max_steps: 100_000,
        });
        let mut y = [y0];
        let mut total = Stats::default();
        for i in 0..20 {
            let (a, b) = (i as f64 * 1e-3, (i + 1) as f64 * 1e-3);
            total.add(&it.integrate(&sys, a, b, &mut y).unwrap());
        }
        assert!(total.steps > 40, "lambda {lambda}: {total:?}");
        assert!(
            3 * total.decomps <= total.steps,
            "lambda {lambda}, rtol {rtol}: {total:?}"
        );
        assert!(
            (y[0] - (50.0f64 * 0.02).cos()).abs() < 100.0 * rtol,
            "{}",
            y[0]
        );
    }
}
