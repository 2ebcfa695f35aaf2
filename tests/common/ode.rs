//! The hand-written integrators (`src/solver/`) against a maintained library,
//! `differential-equations`: one of our 3-state ODE systems handed to the library, the
//! library's Radau5 and ours sampled on the same grid, and the largest difference of the two.

pub use bindery_fmu::solver::library::Library;
use bindery_fmu::solver::{Integrator, Method, OdeSystem, Settings};
use differential_equations::prelude::*;

/// The library's Radau5 (rtol 1e-10, the given `atol`) on `lib` from `y0` at t = 0 to `stop`,
/// output at the points `i * dt` of the grid: (i, first state). `what` names the case if the
/// library fails; a missing grid point (but the last) fails too.
pub fn library_on_grid(
    lib: &Library,
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

/// Our Radau5 and Auto against the library's Radau5 on every stiff case of a 3-state system
/// started at t = 0 (stiffness `k` 1e8, 1e10, 1e12 N/m × damping ratio `zeta` 0, 0.01, 1, made
/// by `system(k, zeta)`): both sampled every `dt` to `stop` (the library at rtol 1e-10 and
/// `lib_atol`, ours with `settings(method)`), the first state within `tol` (m) of the library's
/// at every point. A failure names k, zeta, the method and the difference.
pub fn assert_agrees_with_library<S: OdeSystem>(
    system: impl Fn(f64, f64) -> S,
    initial_state: impl Fn(&S) -> [f64; 3],
    settings: impl Fn(Method) -> Settings,
    (stop, dt): (f64, f64),
    lib_atol: f64,
    tol: f64,
) {
    let n = (stop / dt).round() as usize;
    for k in [1e8, 1e10, 1e12] {
        for zeta in [0.0, 0.01, 1.0] {
            let y0 = initial_state(&system(k, zeta));
            let sys = system(k, zeta);
            let lib = Library(&sys);
            let what = format!("k = {k}, zeta = {zeta}");
            let lib_x = library_on_grid(&lib, y0, stop, dt, lib_atol, &what);
            for method in [Method::Radau5, Method::Auto] {
                let o = system(k, zeta);
                let x = ours_on_grid(&o, settings(method), initial_state(&o), 0.0, dt, n);
                let d = max_diff_at(&x, &lib_x);
                assert!(d < tol, "{what}, {method:?}: {d:e} m");
            }
        }
    }
}
