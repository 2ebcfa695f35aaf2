//! The elastodynamic test harness (the stiff and extreme matrix of every mechanism), written
//! once: a model at the elastodynamic level driven at constant speed, stepped on the plain Rust
//! API (the FMI runtime adds nothing to the numerics), with the history of one position and one
//! force, the energy-balance residual and the solver's steps; and a run held against its
//! reference (radau5 at a tight tolerance, sampled at the same instants).

use super::series::{assert_finite, max_abs_diff};
use bindery_fmu::model::{Log, Model, NoLog, Values, VarSet, shaft};
use std::fmt::Debug;

/// What every case of the matrix names besides the mechanism's own parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drive {
    /// Shaft speed, rpm (negative: reversed).
    pub rpm: f64,
    /// Communication step, s.
    pub dt: f64,
    /// Shaft angle at t = 0, rad.
    pub phi0: f64,
    /// `solver.method` (1 auto, 2 dopri5, 3 radau5, 4 rk4).
    pub method: i32,
    pub rtol: f64,
    pub atol: f64,
}

/// The value reference of the variable `name` of `V`.
pub fn vr_of<V: VarSet>(name: &str) -> usize {
    V::table()
        .iter()
        .position(|v| v.name == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
}

/// `values` at the elastodynamic level, driven at constant speed as `d` says, with its solver.
pub fn elastodynamic<V: VarSet>(mut values: Values<V>, d: &Drive) -> Values<V> {
    let raw = values.raw_mut();
    raw[shaft::FIDELITY as usize] = 3.0;
    raw[shaft::MODE as usize] = 2.0;
    raw[shaft::N as usize] = d.rpm * std::f64::consts::PI / 30.0;
    raw[shaft::PHI0 as usize] = d.phi0;
    for (name, x) in [
        ("solver.method", d.method as f64),
        ("solver.rtol", d.rtol),
        ("solver.atol", d.atol),
    ] {
        raw[vr_of::<V>(name)] = x;
    }
    values
}

/// A run: per step the position and the force, the largest |elastic.E_residual| and the energy
/// scale it is measured against, and the values after the last step.
#[derive(Debug)]
pub struct Run<V: VarSet> {
    pub x: Vec<f64>,
    pub f: Vec<f64>,
    pub residual: f64,
    /// The larger of its start value and the peak |force| times `stroke`.
    pub energy_scale: f64,
    pub values: Values<V>,
}

impl<V: VarSet> Run<V> {
    /// `solver.steps` at the end.
    pub fn steps(&self) -> f64 {
        self.values.raw()[vr_of::<V>("solver.steps")]
    }
}

/// What [`run`] records.
pub struct Record<V> {
    /// The position and the force recorded at every step.
    pub x: V,
    pub f: V,
    /// The distance the force works over in a stroke: energy scale = stroke × peak |force|.
    pub stroke: f64,
    /// The energy scale's floor.
    pub scale0: f64,
    /// Outputs that must be finite after every step (besides `x` and `f`).
    pub finite: Vec<V>,
}

/// `M` prepared from `values` (see [`elastodynamic`]) and stepped over `stop` in steps of `dt`,
/// evaluated after each; `each` sees the values after every step. An `Err` is the reason of a
/// refused preparation or step (a Discard).
pub fn run<M: Model>(
    mut v: Values<M::Var>,
    dt: f64,
    stop: f64,
    rec: &Record<M::Var>,
    log: &mut dyn Log,
    mut each: impl FnMut(&Values<M::Var>),
) -> Result<Run<M::Var>, String>
where
    M::Var: Debug,
{
    let mut m = M::prepare(&v).map_err(|e| e.to_string())?;
    let n = (stop / dt).round().max(1.0) as usize;
    let residual = vr_of::<M::Var>("elastic.E_residual");
    let mut r = Run {
        x: Vec::with_capacity(n),
        f: Vec::with_capacity(n),
        residual: 0.0,
        energy_scale: rec.scale0,
        values: v.clone(),
    };
    let mut finite = rec.finite.clone();
    finite.extend([rec.x, rec.f]);
    for i in 0..n {
        m.step(&mut v, i as f64 * dt, dt, log)?;
        m.evaluate(&mut v, (i + 1) as f64 * dt, &mut NoLog);
        assert_finite(&v, &finite, || format!("at step {i}"));
        let e = v.raw()[residual];
        assert!(e.is_finite(), "elastic.E_residual = {e} at step {i}");
        r.x.push(v[rec.x]);
        r.f.push(v[rec.f]);
        r.residual = r.residual.max(e.abs());
        r.energy_scale = r.energy_scale.max(v[rec.f].abs() * rec.stroke);
        each(&v);
    }
    r.values = v;
    Ok(r)
}

/// How close a run must be to its reference.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    /// Largest difference of the positions.
    pub x: f64,
    /// Of the peak forces, relative to the reference's (at least 1 N).
    pub f: f64,
    /// Largest energy-balance residual, relative to the energy scale.
    pub residual: f64,
}

/// Asserts that `r` is within `tol` of `reference`; `peak` is the force's peak (its magnitude,
/// or its largest value for a force that only pushes). `case` names the case in a failure.
pub fn assert_close<V: VarSet>(
    case: &dyn Debug,
    r: &Run<V>,
    reference: &Run<V>,
    tol: Tolerance,
    peak: fn(&[f64]) -> f64,
) {
    let dx = max_abs_diff(&r.x, &reference.x);
    assert!(
        dx <= tol.x,
        "{case:?}: position off the reference by {dx:e}"
    );
    let (pa, pb) = (peak(&r.f), peak(&reference.f));
    let df = (pa - pb).abs() / pb.max(1.0);
    assert!(
        df <= tol.f,
        "{case:?}: peak force off the reference by {df:e}"
    );
    assert!(
        r.residual <= tol.residual * r.energy_scale,
        "{case:?}: energy residual {} J of {} J",
        r.residual,
        r.energy_scale
    );
}
