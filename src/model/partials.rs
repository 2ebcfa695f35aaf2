//! Exact partial derivatives (FMI's directional derivatives) from dual numbers: the runtime
//! seeds a direction over the knowns (inputs; in Model Exchange also the continuous states),
//! the model computes its outputs and state derivatives as [`Dual64`]s along it
//! ([`super::Model::partials`]), and the dual parts are the directional derivative. The same
//! generic functions compute the plain `f64` values, so the derivative is that of the formula
//! the FMU evaluates, not of a second copy of it.

use super::{Values, VarSet};
pub use crate::mechanics::Scalar;
pub use num_dual::{Dual64, DualNum};

/// Where [`super::Model::partials`] puts each unknown: `put(variable, value with its
/// derivative)`.
pub type Put<'p, V> = &'p mut dyn FnMut(V, Dual64);

/// Puts the derivative 0 for each of `vars`: outputs a model holds at its level (a constant
/// there), or its Model Exchange state derivatives where it has no chain.
pub fn put_zero<V>(put: Put<'_, V>, vars: impl IntoIterator<Item = V>) {
    for var in vars {
        put(var, Dual64::from(0.0));
    }
}

/// The instance's values with a direction over the knowns: each known's seed, 0 elsewhere.
pub struct Seeded<'a, V: VarSet> {
    values: &'a Values<V>,
    /// Per value reference.
    seed: &'a [f64],
}

impl<'a, V: VarSet> Seeded<'a, V> {
    /// `seed` has one entry per variable (value reference).
    pub fn new(values: &'a Values<V>, seed: &'a [f64]) -> Self {
        debug_assert_eq!(seed.len(), V::table().len());
        Seeded { values, seed }
    }

    /// The variable's value now, with its seed as the dual part.
    pub fn get(&self, v: V) -> Dual64 {
        Dual64::new(self.values[v], self.seed(v))
    }

    /// The variable of value reference `vr` now, with its seed ([`Seeded::get`] by value
    /// reference, as [`super::shaft::state_of`] reads the shaft inputs).
    pub fn get_vr(&self, vr: u32) -> Dual64 {
        Dual64::new(self.values.raw()[vr as usize], self.seed[vr as usize])
    }

    /// The variable's seed (0 unless it is a known of the call).
    pub fn seed(&self, v: V) -> f64 {
        self.seed[v.vr() as usize]
    }

    /// A value the model holds itself (a continuous state `x` of the variable `v`), with `v`'s
    /// seed.
    pub fn own(&self, v: V, x: f64) -> Dual64 {
        Dual64::new(x, self.seed(v))
    }

    /// The model's own values `x` (continuous states) of the variables `vars`, each with its
    /// seed ([`Seeded::own`] for each).
    pub fn own_all<const N: usize>(&self, vars: [V; N], x: [f64; N]) -> [Dual64; N] {
        std::array::from_fn(|i| self.own(vars[i], x[i]))
    }

    /// The shaft's state at `time` from the seeded inputs ([`super::shaft::state_of`]).
    pub fn shaft(&self, time: f64) -> super::shaft::ShaftState<Dual64> {
        super::shaft::state_of(self.values, time, |vr| self.get_vr(vr))
    }

    /// The values without seeds (parameters, held inputs).
    pub fn values(&self) -> &Values<V> {
        self.values
    }
}

/// For the models' unit tests: their exact partial derivatives against central differences of
/// their own `evaluate`, written once.
#[cfg(test)]
pub mod check {
    use super::{Seeded, Values, VarSet};
    use crate::model::{Causality, Model, NoLog, VarType, Variability, shaft};

    /// For the mechanisms' mass checks: `v` is accepted at the rigid levels and refused at the
    /// elastodynamic one, naming `param` with its value; the refusal.
    pub fn refused_only_elastodynamic<M: Model>(
        v: &mut Values<M::Var>,
        param: &str,
    ) -> crate::model::ParamError {
        assert!(M::prepare(v).is_ok(), "the rigid levels need no mass");
        v.raw_mut()[shaft::FIDELITY as usize] = 3.0;
        let e = M::prepare(v)
            .err()
            .expect("refused at the elastodynamic level");
        let value = M::Var::table()
            .iter()
            .position(|d| d.name == param)
            .map(|i| v.raw()[i]);
        assert_eq!((e.param, Some(e.value)), (param, value));
        assert!(e.condition.contains("needs a mass"), "{}", e.condition);
        e
    }

    /// The unknowns of a partial derivative: the continuous Real outputs, and with
    /// `derivatives` the state derivatives (Model Exchange), as value references.
    pub fn unknowns<V: VarSet>(derivatives: bool) -> Vec<usize> {
        V::table()
            .iter()
            .enumerate()
            .filter(|(_, var)| {
                (var.causality == Causality::Output
                    && matches!(var.ty, VarType::Real)
                    && var.variability == Variability::Continuous)
                    || (derivatives && var.derivative.is_some())
            })
            .map(|(vr, _)| vr)
            .collect()
    }

    /// The step of a central difference along a known of value `x`: 1e-6 of the value, at
    /// least 1e-6 (the models' checks take it where a known has no scale of its own).
    pub fn relative_step<V>(_: V, x: f64) -> f64 {
        1e-6 * x.abs().max(1.0)
    }

    /// Puts the shaft inputs `shaft.phi`, `shaft.w`, `shaft.a` ([`crate::model::shaft`]) of
    /// the point a check is taken at into `v`.
    pub fn set_shaft<V: VarSet>(v: &mut Values<V>, phi: f64, w: f64, a: f64) {
        for (vr, x) in [(shaft::PHI, phi), (shaft::W, w), (shaft::A, a)] {
            v.raw_mut()[vr as usize] = x;
        }
    }

    /// [`against_central_differences`] over a model's knowns and every unknown: the shaft
    /// inputs and the `more` inputs at their values in `base`, and with `states` (the
    /// elastodynamic level) the Model Exchange states, the variables its state derivatives are
    /// the derivatives of, at the values the model holds
    /// ([`crate::model::Dynamics::me_states`]), put in with
    /// [`crate::model::Dynamics::me_set_states`].
    #[allow(clippy::too_many_arguments)]
    pub fn inputs_and_states<M: Model>(
        m: &mut M,
        base: &Values<M::Var>,
        time: f64,
        more: &[M::Var],
        states: bool,
        step: impl Fn(M::Var, f64) -> f64,
        noise: f64,
        what: &str,
    ) {
        let all = M::Var::ALL;
        let inputs: Vec<_> = [shaft::PHI, shaft::W, shaft::A]
            .map(|vr| all[vr as usize])
            .into_iter()
            .chain(more.iter().copied())
            .collect();
        let states: Vec<_> = if states {
            let table = M::Var::table();
            table
                .iter()
                .filter_map(|v| v.derivative)
                .map(|s| all[s as usize])
                .collect()
        } else {
            vec![]
        };
        let mut held = vec![0.0; states.len()];
        if !states.is_empty() {
            m.me_states(base, time, &mut held);
        }
        let knowns: Vec<_> = inputs
            .iter()
            .map(|k| (*k, base[*k]))
            .chain(states.iter().copied().zip(held))
            .collect();
        let n = inputs.len();
        let set = |m: &mut M, v: &mut Values<M::Var>, x: &[f64]| {
            for (k, xi) in inputs.iter().zip(x) {
                v[*k] = *xi;
            }
            if !states.is_empty() {
                m.me_set_states(v, time, &x[n..]);
            }
        };
        let outs = unknowns::<M::Var>(true);
        against_central_differences(m, base, time, &knowns, &outs, set, step, noise, what);
    }

    /// The values `base` with the knowns' values `x` put in by `set`, evaluated at `time`:
    /// the unknowns `outs`.
    fn evaluate<M: Model, S: FnMut(&mut M, &mut Values<M::Var>, &[f64])>(
        m: &mut M,
        base: &Values<M::Var>,
        time: f64,
        outs: &[usize],
        set: &mut S,
        x: &[f64],
    ) -> Vec<f64> {
        let mut v = base.clone();
        set(m, &mut v, x);
        m.evaluate(&mut v, time, &mut NoLog);
        outs.iter().map(|o| v.raw()[*o]).collect()
    }

    /// At the point `base` (the instance's values) and `time`, for each known `(k, x0)`:
    /// the column [`Model::partials`] gives along `k` against the central difference of
    /// `evaluate` over `x0 ± step(k, x0)`, for every unknown in `outs`; `set(m, v, x)` puts
    /// the knowns' values `x` (in the order of `knowns`) into the values or the model (a
    /// state). Within 1e-6 of the column's scale plus the differences' rounding, `noise` of
    /// the value over the step (1e-14 is `f64`'s; a value that is a difference of nearly
    /// equal positions carries more). `what` names the point in a failure.
    #[allow(clippy::too_many_arguments)]
    pub fn against_central_differences<M: Model>(
        m: &mut M,
        base: &Values<M::Var>,
        time: f64,
        knowns: &[(M::Var, f64)],
        outs: &[usize],
        mut set: impl FnMut(&mut M, &mut Values<M::Var>, &[f64]),
        step: impl Fn(M::Var, f64) -> f64,
        noise: f64,
        what: &str,
    ) {
        let table = M::Var::table();
        let x0: Vec<f64> = knowns.iter().map(|(_, x)| *x).collect();
        for (i, (k, _)) in knowns.iter().enumerate() {
            let mut at = base.clone();
            set(m, &mut at, &x0);
            let mut seed = vec![0.0; table.len()];
            seed[k.vr() as usize] = 1.0;
            let mut exact = vec![f64::NAN; table.len()];
            m.partials(&Seeded::new(&at, &seed), time, &mut |o, x| {
                exact[o.vr() as usize] = x.eps
            })
            .unwrap();
            let h = step(*k, x0[i]);
            let (mut xp, mut xm) = (x0.clone(), x0.clone());
            xp[i] += h;
            xm[i] -= h;
            let yp = evaluate(m, base, time, outs, &mut set, &xp);
            let ym = evaluate(m, base, time, outs, &mut set, &xm);
            for (j, o) in outs.iter().enumerate() {
                let fd = (yp[j] - ym[j]) / (2.0 * h);
                let ex = exact[*o];
                assert!(
                    (ex - fd).abs()
                        <= 1e-6 * fd.abs().max(1.0) + noise * yp[j].abs().max(ym[j].abs()) / h,
                    "{what}: d {} / d {}: exact {ex}, central {fd}",
                    table[*o].name,
                    table[k.vr() as usize].name,
                );
            }
        }
    }
}
