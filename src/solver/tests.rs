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
        assert!(it.stats.events >= 2, "{m:?}: {:?}", it.stats);
    }
}

#[test]
fn radau_error_estimate_tracks_the_true_error() {
    // y' = -y; one step of size h: estimate and true error within a factor of 100
    let o = Osc {
        k: 1.0,
        c: 0.0,
        m: 1.0,
    };
    let it = Integrator::new(Settings::default());
    let jac = [0.0, 1.0, -1.0, 0.0];
    let f0 = [0.0, -1.0];
    let mut y1 = [0.0; 2];
    let mut f1 = [0.0; 2];
    let mut st = Stats::default();
    let a = it
        .radau(
            &o,
            0.0,
            &[1.0, 0.0],
            &f0,
            &jac,
            0.2,
            &mut y1,
            &mut f1,
            &mut st,
        )
        .unwrap();
    let true_err = ((y1[0] - 0.2f64.cos()).powi(2) + (y1[1] + 0.2f64.sin()).powi(2)).sqrt();
    assert!(true_err < 1e-6, "{true_err}");
    assert!(a.err > 0.0 && a.err.is_finite());
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
    // (t = 0.5, 1.5, ..., held at the lobe's sign), none where the next one leaves it (the
    // integrator's test, as before holding) and none at the start
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
    assert_eq!(seen.len(), 5, "{seen:?}");
    for (k, &(t, before, after)) in seen.iter().enumerate() {
        assert!((t - (k as f64 + 0.5)).abs() < 1e-9, "{seen:?}");
        // the system sees its own values (a held zero is zero again)
        let lobe = if k % 2 == 0 { 1.0 } else { -1.0 };
        assert!(before * lobe > 0.0 && after == 0.0, "{seen:?}");
    }
    assert_eq!(it.stats.events, 5);
}
