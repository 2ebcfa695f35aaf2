//! The hand-written integrators (`src/solver/`) against a maintained library,
//! `differential-equations`: one of our 3-state ODE systems handed to the library, the
//! library's Radau5 and ours sampled on the same grid, and the largest difference of the two.

use bindery_fmu::solver::{Integrator, OdeSystem, Settings};
use differential_equations::prelude::*;

/// One of our 3-state [`OdeSystem`]s as a `differential-equations` ODE, with our analytic
/// Jacobian (row-major, as [`OdeSystem::jacobian`] gives it).
pub struct Library<S>(pub S);

impl<S: OdeSystem> ODE<f64, [f64; 3]> for Library<S> {
    fn diff(&self, t: f64, y: &[f64; 3], dydt: &mut [f64; 3]) {
        self.0.rhs(t, y, dydt);
    }
    fn jacobian(&self, t: f64, y: &[f64; 3], j: &mut Matrix<f64>) {
        let mut a = [0.0; 9];
        self.0.jacobian(t, y, &mut a);
        for r in 0..3 {
            for c in 0..3 {
                j[(r, c)] = a[r * 3 + c];
            }
        }
    }
}

/// The library's Radau5 (rtol 1e-10, the given `atol`) on `lib` from `y0` at t = 0 to `stop`,
/// output at the points `i * dt` of the grid: (i, first state). `what` names the case if the
/// library fails; a missing grid point (but the last) fails too.
pub fn library_on_grid<S: OdeSystem>(
    lib: &Library<S>,
    y0: [f64; 3],
    stop: f64,
    dt: f64,
    atol: f64,
    what: &str,
) -> Vec<(usize, f64)> {
    let n = (stop / dt).round() as usize;
    let t_eval: Vec<f64> = (0..=n).map(|i| i as f64 * dt).collect();
    let reference = IVP::ode(lib, 0.0, stop, y0)
        .t_eval(&t_eval)
        .method(ImplicitRungeKutta::radau5().rtol(1e-10).atol(atol))
        .solve()
        .unwrap_or_else(|e| panic!("library radau5 {what}: {e:?}"));
    let x: Vec<(usize, f64)> = reference
        .iter()
        .map(|(t, y)| ((t / dt).round() as usize, y[0]))
        .collect();
    assert!(x.len() + 1 >= t_eval.len(), "{what}: {} points", x.len());
    x
}

/// `o` integrated by one [`Integrator`] with `settings`, from `y` at `t0` over `n` intervals of
/// `dt`: the first state at `t0` and at the end of every interval.
pub fn ours_on_grid(
    o: &dyn OdeSystem,
    settings: Settings,
    mut y: [f64; 3],
    t0: f64,
    dt: f64,
    n: usize,
) -> Vec<f64> {
    let mut it = Integrator::new(settings);
    let mut out = vec![y[0]];
    for i in 0..n {
        let (a, b) = (t0 + i as f64 * dt, t0 + (i + 1) as f64 * dt);
        it.integrate(o, a, b, &mut y).unwrap();
        out.push(y[0]);
    }
    out
}

/// The largest difference of our samples `x` (indexed by grid point) from the library's
/// `(grid point, value)` samples.
pub fn max_diff_at(x: &[f64], library: &[(usize, f64)]) -> f64 {
    library
        .iter()
        .map(|&(i, b)| (x[i] - b).abs())
        .fold(0.0, f64::max)
}
