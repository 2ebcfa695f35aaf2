//! FMI 2.0 Model Exchange on the same runtime: the host integrates the model's continuous
//! states with its own solver (e.g. FMPy with CVode) through states, derivatives and event
//! indicators ([`crate::model::Dynamics::STATES`], [`crate::model::Dynamics::me_derivatives`],
//! ...). A submodule of the runtime: it uses the same instance and entry wrapper; [`entry`]
//! checks each call against the Model Exchange column of `state::LEGAL`, whose event and
//! continuous-time modes both run in the runtime's state `StepComplete`, told apart by [`Mode`].

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

impl<M: Model> Instance<M> {
    /// A function of the states returned non-finite values: where the model has no finite
    /// value at the states the host set (a Newton iterate far off the motion, a lever outside
    /// the linkage), `fmi2Discard` (FMI 2.0: "a function is outside of its domain": the host
    /// should retry with a smaller step), logged with the states and the first value named.
    /// `Ok` if all are finite.
    fn discard_non_finite(
        &mut self,
        call: impl Api,
        values: &[f64],
        name: impl Fn(usize) -> String,
    ) -> Status {
        let Some(i) = values.iter().position(|v| !v.is_finite()) else {
            return Status::Ok;
        };
        // prepared: the values came from the model
        let x = self.me_states().unwrap_or_default();
        let msg = format!(
            "{}{call:?}: {} = {} at t = {} is not finite: the model has no finite value at the states {} (outside its domain); a smaller step is needed",
            call.prefix(),
            name(i),
            values[i],
            self.time,
            named_states::<M>(&x)
        );
        self.logger.emit(Status::Discard, "logStatusDiscard", &msg);
        Status::Discard
    }

    /// `fmi2NewDiscreteStates`: the model switches its discrete modes at the event.
    ///
    /// # Safety
    /// `info` points to an `fmi2EventInfo` (checked for NULL).
    pub unsafe fn new_discrete_states(&mut self, info: *mut EventInfo) -> Outcome {
        if info.is_null() {
            return Err("fmi2EventInfo pointer is NULL".into());
        }
        self.me_event()?;
        // no new discrete states, no termination, no state change, no time event
        // SAFETY: as this function.
        unsafe { *info = EventInfo::default() };
        Ok(Status::Ok)
    }

    /// `fmi2CompletedIntegratorStep` and `fmi3CompletedIntegratorStep` (`B` the version's
    /// Boolean): never asks for an event or the end.
    ///
    /// # Safety
    /// The two flags point to a Boolean each (checked for NULL).
    pub unsafe fn completed_integrator_step<B: From<bool>>(
        &mut self,
        _no_set_prior: B,
        enter_event_mode: *mut B,
        terminate: *mut B,
    ) -> Outcome {
        if enter_event_mode.is_null() || terminate.is_null() {
            return Err("a result pointer is NULL".into());
        }
        self.completed_step()?;
        // SAFETY: as this function.
        unsafe {
            *enter_event_mode = B::from(false);
            *terminate = B::from(false);
        }
        Ok(Status::Ok)
    }

    /// `fmi2SetTime`.
    pub fn set_time(&mut self, t: Real) -> Outcome {
        if !t.is_finite() {
            return Err(format!("time {t} is not finite"));
        }
        self.time = t;
        self.dirty = true;
        Ok(Status::Ok)
    }

    /// `fmi2SetContinuousStates`.
    ///
    /// # Safety
    /// `x` holds `nx` reals.
    pub unsafe fn set_continuous_states(&mut self, x: *const Real, nx: usize) -> Outcome {
        count(nx, "nx", M::STATES)?;
        // SAFETY: as this function.
        let x = unsafe { slice(x, nx, "x")? };
        // refused before anything reads it: the model keeps its states
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(format!(
                "{} = {} is not finite; the states are kept ({})",
                crate::model::state_names::<M::Var>()[i],
                x[i],
                named_states::<M>(&self.me_states()?)
            ));
        }
        self.prepared()?;
        let model = self.model.as_mut().expect("prepared");
        model.me_set_states(&self.values, self.time, x);
        self.dirty = true;
        Ok(Status::Ok)
    }

    /// `fmi2GetDerivatives`.
    ///
    /// # Safety
    /// `dx` holds `nx` reals.
    pub unsafe fn get_derivatives(&mut self, call: impl Api, dx: *mut Real, nx: usize) -> Outcome {
        count(nx, "nx", M::STATES)?;
        // SAFETY: as this function.
        let dx = unsafe { slice_mut(dx, nx, "derivatives")? };
        self.model_fill(dx, M::me_derivatives)?;
        let names = crate::model::state_names::<M::Var>();
        Ok(self.discard_non_finite(call, dx, |i| format!("der({})", names[i])))
    }

    /// `fmi2GetEventIndicators`.
    ///
    /// # Safety
    /// `z` holds `ni` reals.
    pub unsafe fn get_event_indicators(
        &mut self,
        call: impl Api,
        z: *mut Real,
        ni: usize,
    ) -> Outcome {
        count(ni, "ni", M::EVENT_INDICATORS)?;
        // SAFETY: as this function.
        let z = unsafe { slice_mut(z, ni, "eventIndicators")? };
        self.model_fill(z, M::me_event_indicators)?;
        Ok(self.discard_non_finite(call, z, |i| format!("event indicator {i}")))
    }

    /// `fmi2GetContinuousStates`.
    ///
    /// # Safety
    /// `x` holds `nx` reals.
    pub unsafe fn get_continuous_states(&mut self, x: *mut Real, nx: usize) -> Outcome {
        count(nx, "nx", M::STATES)?;
        // SAFETY: as this function.
        self.model_fill(unsafe { slice_mut(x, nx, "x")? }, M::me_states)?;
        Ok(Status::Ok)
    }

    /// `fmi2GetNominalsOfContinuousStates`: 1 for every state.
    ///
    /// # Safety
    /// `x` holds `nx` reals.
    pub unsafe fn get_nominals(&mut self, x: *mut Real, nx: usize) -> Outcome {
        count(nx, "nx", M::STATES)?;
        // SAFETY: as this function.
        unsafe { slice_mut(x, nx, "x_nominal")? }.fill(1.0);
        Ok(Status::Ok)
    }

    /// Into Event Mode (FMI 2.0 and FMI 3.0 Model Exchange; FMI 3.0 Co-Simulation for a host
    /// that said at instantiation it uses Event Mode).
    pub fn enter_event_mode(&mut self) -> Outcome {
        if !(self.me.is_me || self.event_mode_used) {
            return Err("eventModeUsed was false at instantiation".into());
        }
        self.me.mode = Mode::Event;
        Ok(Status::Ok)
    }

    /// Out of Event Mode: Model Exchange's continuous-time mode, FMI 3.0 Co-Simulation's Step
    /// Mode.
    pub fn enter_continuous_time_mode(&mut self) -> Outcome {
        self.me.mode = Mode::ContinuousTime;
        Ok(Status::Ok)
    }

    /// The model's event indicators now.
    pub fn event_indicators(&mut self) -> Result<Vec<f64>, String> {
        let mut z = vec![0.0; M::EVENT_INDICATORS];
        self.model_fill(&mut z, M::me_event_indicators)?;
        Ok(z)
    }

    /// The prepared model's numbers `f` writes into `out` at the instance's values and time
    /// (its states, derivatives or event indicators).
    fn model_fill(
        &mut self,
        out: &mut [f64],
        f: impl FnOnce(&mut M, &Values<M::Var>, f64, &mut [f64]),
    ) -> Result<(), String> {
        self.prepared()?;
        f(
            self.model.as_mut().expect("prepared"),
            &self.values,
            self.time,
            out,
        );
        Ok(())
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
        let mut x = vec![0.0; M::STATES];
        self.model_fill(&mut x, M::me_states)?;
        Ok(x)
    }
}
