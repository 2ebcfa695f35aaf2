//! The current values of a model's variables ([`Values`]) and the check of its parameters
//! against their declared bounds ([`check_bounds`]).

use super::*;
use std::marker::PhantomData;
use std::ops::{Index, IndexMut};

/// The current values of a model's variables, indexed by its [`VarSet`].
/// Integer, Boolean and Enumeration values are held as exact `f64`.
#[derive(Clone, Debug, PartialEq)]
pub struct Values<V: VarSet> {
    data: Vec<f64>,
    /// The computation stages the outputs in use need ([`Stages::ALL`] in the full FMU; a
    /// scene's tailored FMU narrows it). [`Model::prepare`] and [`Model::evaluate`] skip what is
    /// not in it.
    pub stages: Stages,
    /// Time derivatives of Real inputs a host set with `fmi2SetRealInputDerivatives`, as
    /// `(value reference, order, value)`, for the next communication step only
    /// ([`shaft::path`] reads those of the shaft; see `interface.md`).
    input_derivatives: Vec<(u32, u32, f64)>,
    /// The time at which the host last set an input (the runtime records it; the start time
    /// until then). An input is the value at that instant: a model may move it on with time
    /// from there ([`shaft::state`]).
    pub inputs_at: f64,
    _v: PhantomData<V>,
}

impl<V: VarSet> Default for Values<V> {
    fn default() -> Self {
        Self::start()
    }
}

impl<V: VarSet> Values<V> {
    /// Every variable at its declared start value (0 where there is none).
    pub fn start() -> Self {
        Values {
            data: V::table().iter().map(|v| v.start.unwrap_or(0.0)).collect(),
            stages: Stages::ALL,
            input_derivatives: Vec::new(),
            inputs_at: 0.0,
            _v: PhantomData,
        }
    }
    /// Is anything that reads the results of these stages in use? (The full FMU: always.)
    #[inline]
    pub fn wants(&self, stages: Stages) -> bool {
        self.stages.intersects(stages)
    }
    /// An Integer or Enumeration value.
    pub fn int(&self, v: V) -> i32 {
        self.data[v.vr() as usize] as i32
    }
    /// The value of the variable named `name`: for the code shared by models that declare the
    /// same variables, each in its own enum ([`crate::solver::chain::solver_settings`], the
    /// needle and table parameters). Panics if the model declares no such variable.
    pub fn named(&self, name: &str) -> f64 {
        self.data[Self::index_of(name)]
    }
    /// Sets the variable named `name` (start values by name: the report's cases, benchmarks,
    /// tests). Panics if the model declares no such variable.
    pub fn set_named(&mut self, name: &str, x: f64) {
        self.data[Self::index_of(name)] = x;
    }
    /// The value reference of the variable named `name`. Panics if the model declares none.
    pub fn index_of(name: &str) -> usize {
        V::table()
            .iter()
            .position(|d| d.name == name)
            .unwrap_or_else(|| panic!("the model declares no {name}"))
    }
    /// A Boolean value.
    pub fn flag(&self, v: V) -> bool {
        self.data[v.vr() as usize] != 0.0
    }
    /// Sets a Boolean value.
    pub fn set_flag(&mut self, v: V, b: bool) {
        self.data[v.vr() as usize] = if b { 1.0 } else { 0.0 };
    }
    /// All values by value reference (for the runtime and state serialization).
    pub fn raw(&self) -> &[f64] {
        &self.data
    }
    /// All values by value reference, mutable.
    pub fn raw_mut(&mut self) -> &mut [f64] {
        &mut self.data
    }
    /// The derivative of order `order` of the input `vr` a host set for the next step, if any.
    pub fn input_derivative(&self, vr: u32, order: u32) -> Option<f64> {
        self.input_derivatives
            .iter()
            .find(|d| d.0 == vr && d.1 == order)
            .map(|d| d.2)
    }
    /// Sets (or replaces) the derivative of order `order` of the input `vr`. The runtime checks
    /// that `vr` is a Real input, `order` in `1..=`[`MAX_INPUT_DERIVATIVE_ORDER`] and `x` finite.
    pub fn set_input_derivative(&mut self, vr: u32, order: u32, x: f64) {
        match self
            .input_derivatives
            .iter_mut()
            .find(|d| d.0 == vr && d.1 == order)
        {
            Some(d) => d.2 = x,
            None => self.input_derivatives.push((vr, order, x)),
        }
    }
    /// Every input derivative set, as `(value reference, order, value)`, in the order set.
    pub fn input_derivatives(&self) -> &[(u32, u32, f64)] {
        &self.input_derivatives
    }
    /// Forgets the input derivatives (they applied to one communication step).
    pub fn clear_input_derivatives(&mut self) {
        self.input_derivatives.clear();
    }
}

/// Highest order of input derivative `fmi2SetRealInputDerivatives` accepts: the shaft angle is
/// extrapolated with a parabola, `phi(t0 + dt) = phi + phi'*dt + phi''*dt^2/2`
/// (`dynamics.md`). FMI 2.0 has no attribute for it in `modelDescription.xml`
/// (`fmi2ModelDescription.xsd` defines `maxOutputDerivativeOrder` only), so a higher order is
/// refused at the call with this number in the message.
pub const MAX_INPUT_DERIVATIVE_ORDER: u32 = 2;

impl<V: VarSet> Index<V> for Values<V> {
    type Output = f64;
    fn index(&self, v: V) -> &f64 {
        &self.data[v.vr() as usize]
    }
}

impl<V: VarSet> IndexMut<V> for Values<V> {
    fn index_mut(&mut self, v: V) -> &mut f64 {
        &mut self.data[v.vr() as usize]
    }
}

/// Checks every parameter against its declared `min`/`max` (and an Enumeration against its
/// items): the first violation, named.
pub fn check_bounds<V: VarSet>(values: &Values<V>) -> Result<(), ParamError> {
    for (v, &x) in V::table().iter().zip(values.raw()) {
        if v.causality != Causality::Parameter {
            continue;
        }
        let fail = |condition: String| {
            Err(ParamError {
                param: v.name,
                value: x,
                condition,
            })
        };
        if !x.is_finite() {
            return fail("must be finite".into());
        }
        if let Some(lo) = v.min
            && x < lo
        {
            return fail(format!(
                "{} must be at least {}",
                v.quantity(x),
                v.quantity(lo)
            ));
        }
        if let Some(hi) = v.max
            && x > hi
        {
            return fail(format!(
                "{} must be at most {}",
                v.quantity(x),
                v.quantity(hi)
            ));
        }
        if let VarType::Enumeration(t) = v.ty
            && t.item(x as i32).is_none()
        {
            return fail(format!(
                "is not an item of {} (1..={})",
                t.name,
                t.items.len()
            ));
        }
    }
    Ok(())
}
