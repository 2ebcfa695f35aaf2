//! FMI 2.0 Model Exchange on the same runtime: the host integrates the model's continuous
//! states with its own solver (e.g. FMPy with CVode) through states, derivatives and event
//! indicators ([`Dynamics::STATES`], [`Dynamics::me_derivatives`], ...). A submodule of the runtime:
//! it uses the same instance and entry wrapper; [`entry`] checks each call against the Model
//! Exchange column of `state::LEGAL`, whose event and continuous-time modes both run in the
//! runtime's state `StepComplete`, told apart by [`Mode`].

use super::*;

/// Which Model Exchange mode an instance is in, after initialization.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Mode {
    #[default]
    Event,
    ContinuousTime,
}

/// The Model Exchange side of an instance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeMode {
    /// Instantiated as Model Exchange.
    pub is_me: bool,
    pub mode: Mode,
}

/// `fmi2EventInfo`, declared with the other C types.
pub use crate::fmi2::types::EventInfo;

fn count(n: usize, what: &str, expected: usize) -> Result<(), String> {
    if n != expected {
        return Err(format!("{what} = {n}; this FMU has {expected}"));
    }
    Ok(())
}

/// `name = value, ...` of the continuous states `x`, for the messages.
fn named_states<M: Model>(x: &[f64]) -> String {
    crate::model::state_names::<M::Var>()
        .iter()
        .zip(x)
        .map(|(n, v)| format!("{n} = {v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A function of the states returned non-finite values: where the model has no finite value
/// at the states the host set (a Newton iterate far off the motion, a lever outside the
/// linkage), `fmi2Discard` (FMI 2.0: "a function is outside of its domain": the host should
/// retry with a smaller step), logged with the states and the first value named. `Ok` if all
/// are finite.
fn discard_non_finite<M: Model>(
    inst: &mut Instance<M>,
    call: impl Api,
    values: &[f64],
    name: impl Fn(usize) -> String,
) -> Status {
    let Some(i) = values.iter().position(|v| !v.is_finite()) else {
        return Status::Ok;
    };
    let mut x = vec![0.0; M::STATES];
    let model = inst.model.as_mut().expect("prepared");
    model.me_states(&inst.values, inst.time, &mut x);
    let msg = format!(
        "{}{call:?}: {} = {} at t = {} is not finite: the model has no finite value at the states {} (outside its domain); a smaller step is needed",
        call.prefix(),
        name(i),
        values[i],
        inst.time,
        named_states::<M>(&x)
    );
    inst.logger.emit(Status::Discard, "logStatusDiscard", &msg);
    Status::Discard
}

/// `fmi2EnterEventMode`.
///
/// # Safety
/// As [`entry`].
pub unsafe fn enter_event_mode<M: Model, C: Api>(c: Component, call: C) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            inst.me.mode = Mode::Event;
            Ok(Status::Ok)
        })
    }
}

/// `fmi2NewDiscreteStates`: the model switches its discrete modes at the event.
///
/// # Safety
/// As [`entry`]; `info` points to an `fmi2EventInfo`.
pub unsafe fn new_discrete_states<M: Model>(c: Component, info: *mut EventInfo) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, Call::NewDiscreteStates, |inst| {
            if info.is_null() {
                return Err("fmi2EventInfo pointer is NULL".into());
            }
            inst.me_event()?;
            // no new discrete states, no termination, no state change, no time event
            *info = EventInfo::default();
            Ok(Status::Ok)
        })
    }
}

/// `fmi2EnterContinuousTimeMode`.
///
/// # Safety
/// As [`entry`].
pub unsafe fn enter_continuous_time_mode<M: Model, C: Api>(c: Component, call: C) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            inst.me.mode = Mode::ContinuousTime;
            Ok(Status::Ok)
        })
    }
}

/// `fmi2CompletedIntegratorStep` and `fmi3CompletedIntegratorStep` (`call`; `B` the version's
/// Boolean): never asks for an event or the end.
///
/// # Safety
/// As [`entry`]; the two flags point to a Boolean each.
pub unsafe fn completed_integrator_step<M: Model, B: From<bool>>(
    c: Component,
    call: impl Api,
    _no_set_prior: B,
    enter_event_mode: *mut B,
    terminate: *mut B,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            if enter_event_mode.is_null() || terminate.is_null() {
                return Err("a result pointer is NULL".into());
            }
            inst.completed_step()?;
            *enter_event_mode = B::from(false);
            *terminate = B::from(false);
            Ok(Status::Ok)
        })
    }
}

/// `fmi2SetTime`.
///
/// # Safety
/// As [`entry`].
pub unsafe fn set_time<M: Model, C: Api>(c: Component, call: C, t: Real) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            if !t.is_finite() {
                return Err(format!("time {t} is not finite"));
            }
            inst.time = t;
            inst.dirty = true;
            Ok(Status::Ok)
        })
    }
}

/// `fmi2SetContinuousStates`.
///
/// # Safety
/// As [`entry`]; `x` holds `nx` reals.
pub unsafe fn set_continuous_states<M: Model, C: Api>(
    c: Component,
    call: C,
    x: *const Real,
    nx: usize,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            count(nx, "nx", M::STATES)?;
            let x = slice(x, nx, "x")?;
            // refused before anything reads it: the model keeps its states
            if let Some(i) = x.iter().position(|v| !v.is_finite()) {
                return Err(format!(
                    "{} = {} is not finite; the states are kept ({})",
                    crate::model::state_names::<M::Var>()[i],
                    x[i],
                    named_states::<M>(&inst.me_states()?)
                ));
            }
            inst.prepared()?;
            let model = inst.model.as_mut().expect("prepared");
            model.me_set_states(&inst.values, inst.time, x);
            inst.dirty = true;
            Ok(Status::Ok)
        })
    }
}

/// `fmi2GetDerivatives`.
///
/// # Safety
/// As [`entry`]; `dx` holds `nx` reals.
pub unsafe fn get_derivatives<M: Model, C: Api>(
    c: Component,
    call: C,
    dx: *mut Real,
    nx: usize,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            count(nx, "nx", M::STATES)?;
            let dx = slice_mut(dx, nx, "derivatives")?;
            inst.prepared()?;
            let model = inst.model.as_mut().expect("prepared");
            model.me_derivatives(&inst.values, inst.time, dx);
            let names = crate::model::state_names::<M::Var>();
            Ok(discard_non_finite(inst, call, dx, |i| {
                format!("der({})", names[i])
            }))
        })
    }
}

/// `fmi2GetEventIndicators`.
///
/// # Safety
/// As [`entry`]; `z` holds `ni` reals.
pub unsafe fn get_event_indicators<M: Model, C: Api>(
    c: Component,
    call: C,
    z: *mut Real,
    ni: usize,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            count(ni, "ni", M::EVENT_INDICATORS)?;
            let z = slice_mut(z, ni, "eventIndicators")?;
            inst.prepared()?;
            let model = inst.model.as_mut().expect("prepared");
            model.me_event_indicators(&inst.values, inst.time, z);
            Ok(discard_non_finite(inst, call, z, |i| {
                format!("event indicator {i}")
            }))
        })
    }
}

/// `fmi2GetContinuousStates`.
///
/// # Safety
/// As [`entry`]; `x` holds `nx` reals.
pub unsafe fn get_continuous_states<M: Model, C: Api>(
    c: Component,
    call: C,
    x: *mut Real,
    nx: usize,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            count(nx, "nx", M::STATES)?;
            let x = slice_mut(x, nx, "x")?;
            x.copy_from_slice(&inst.me_states()?);
            Ok(Status::Ok)
        })
    }
}

/// `fmi2GetNominalsOfContinuousStates`: 1 for every state.
///
/// # Safety
/// As [`entry`]; `x` holds `nx` reals.
pub unsafe fn get_nominals<M: Model, C: Api>(
    c: Component,
    call: C,
    x: *mut Real,
    nx: usize,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |_| {
            count(nx, "nx", M::STATES)?;
            slice_mut(x, nx, "x_nominal")?.fill(1.0);
            Ok(Status::Ok)
        })
    }
}

impl<M: Model> Instance<M> {
    /// The model's event indicators now.
    pub fn event_indicators(&mut self) -> Result<Vec<f64>, String> {
        self.prepared()?;
        let mut z = vec![0.0; M::EVENT_INDICATORS];
        let model = self.model.as_mut().expect("prepared");
        model.me_event_indicators(&self.values, self.time, &mut z);
        Ok(z)
    }

    /// The model's event at this instant (FMI 2.0's `fmi2NewDiscreteStates`, FMI 3.0's
    /// `fmi3UpdateDiscreteStates`): it switches its discrete modes.
    pub fn me_event(&mut self) -> Outcome {
        self.prepared()?;
        let model = self.model.as_mut().expect("prepared");
        model.me_event(&self.values, self.time, &mut self.logger);
        self.dirty = true;
        Ok(Status::Ok)
    }

    /// A step of the host's integrator completed (`fmi2CompletedIntegratorStep`,
    /// `fmi3CompletedIntegratorStep`); never asks for an event or the end.
    pub fn completed_step(&mut self) -> Outcome {
        self.prepared()?;
        let model = self.model.as_mut().expect("prepared");
        model.me_completed_step(&self.values, self.time, &mut self.logger);
        Ok(Status::Ok)
    }

    /// The model's continuous states.
    fn me_states(&mut self) -> Result<Vec<f64>, String> {
        self.prepared()?;
        let mut x = vec![0.0; M::STATES];
        let model = self.model.as_mut().expect("prepared");
        model.me_states(&self.values, self.time, &mut x);
        Ok(x)
    }
}
