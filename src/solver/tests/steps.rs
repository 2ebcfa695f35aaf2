//! Steps and their work: the work budget, the integrator's memory replayed bit for bit, shared
//! factorizations, `auto`'s stability checks across calls, steps cut at a call's end.

use super::*;

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
