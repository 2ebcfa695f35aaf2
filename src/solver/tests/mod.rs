//! The integrators' tests, by concern; here the problems and runs they share.

use super::*;

mod accuracy;
mod events;
mod steps;

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
