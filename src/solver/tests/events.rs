//! Events: contacts located and energy kept, functions resting at zero, a pair of crossings
//! inside one step, confirmation near a root.

use super::*;

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
