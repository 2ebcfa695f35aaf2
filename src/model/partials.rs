//! Exact partial derivatives (FMI's directional derivatives) from dual numbers: the runtime
//! seeds a direction over the knowns (inputs; in Model Exchange also the continuous states),
//! the model computes its outputs and state derivatives as [`Dual64`]s along it
//! ([`super::Model::partials`]), and the dual parts are the directional derivative. The same
//! generic functions compute the plain `f64` values, so the derivative is that of the formula
//! the FMU evaluates, not of a second copy of it.

use super::{Values, VarSet};
pub use crate::mechanics::Scalar;
pub use num_dual::{Dual64, DualNum};

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

    /// The values without seeds (parameters, held inputs).
    pub fn values(&self) -> &Values<V> {
        self.values
    }
}
