//! The Co-Simulation calls: input derivatives, `fmi2DoStep`, the step's status.

use super::*;

/// `fmi2SetRealInputDerivatives` (`canInterpolateInputs`, [`Model::CAN_INTERPOLATE_INPUTS`]):
/// time derivatives of Real inputs at the current communication point, for the next
/// `fmi2DoStep` only: the model's step uses those it declares it uses
/// ([`Model::unused_input_derivative`]); when that step is done they expire, unless the host
/// sets derivatives anew. Setting an input's value does not cancel its derivatives (a host may
/// set them in either order at one point). FMU states and `fmi2Reset` include them. Those the
/// model does not use are stored and ignored with its reason and
/// `fmi2Warning`. Refused, changing nothing: a model without the capability, a Model Exchange
/// instance, anything but a Real input, order 0 or above [`MAX_INPUT_DERIVATIVE_ORDER`], a
/// non-finite value. (On a Model Exchange instance [`entry`] refuses it: a Co-Simulation
/// function.)
///
/// # Safety
/// As [`entry`]; arrays hold `n` elements.
pub unsafe fn set_real_input_derivatives<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    order: *const Integer,
    value: *const Real,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, Call::SetRealInputDerivatives, |inst| {
            if !M::CAN_INTERPOLATE_INPUTS {
                return Err(
                    "not supported: canInterpolateInputs is false (this FMU holds its inputs over a step)"
                        .into(),
                );
            }
            if let Some(t) = &inst.scene
                && !t.info.can_interpolate_inputs
            {
                return Err(format!(
                    "not supported: canInterpolateInputs is false for {} (its scene holds its inputs over a step)",
                    t.identifier
                ));
            }
            let vrs = slice(vr, n, "vr")?;
            let orders = slice(order, n, "order")?;
            let vals = slice(value, n, "value")?;
            for ((&vr, &o), &x) in vrs.iter().zip(orders).zip(vals) {
                if !inst.listed(vr) {
                    return Err(inst.unlisted(vr));
                }
                let o = u32::try_from(o).map_err(|_| {
                    format!(
                        "order {o} refused: this FMU takes orders 1..={MAX_INPUT_DERIVATIVE_ORDER}"
                    )
                })?;
                Instance::<M>::check_input_derivative(vr, o, x)?;
            }
            let (mut unused, mut why) = (Vec::new(), "");
            for ((&vr, &o), &x) in vrs.iter().zip(orders).zip(vals) {
                inst.values.set_input_derivative(vr, o as u32, x);
                if let Some(w) = M::unused_input_derivative(vr, o as u32) {
                    unused.push(format!(
                        "{} of order {o}",
                        Instance::<M>::table()[vr as usize].name
                    ));
                    why = w;
                }
            }
            inst.dirty = true;
            if unused.is_empty() {
                return Ok(Status::Ok);
            }
            inst.logger.emit(
                Status::Warning,
                "logStatusWarning",
                &format!(
                    "fmi2SetRealInputDerivatives: the derivative of {} is kept but not used: {why}",
                    unused.join(", ")
                ),
            );
            Ok(Status::Warning)
        })
    }
}

/// `fmi2DoStep`: checks the communication point, `h > 0` and the stop time, then
/// [`Model::step`]: the model's own step and its inputs moved to `t + h` as the step moved them
/// (at every fidelity level). The outputs at the new time are computed when read. A step the
/// model refuses is `fmi2Discard` with its reason.
///
/// # Safety
/// As [`entry`].
pub unsafe fn do_step<M: Model>(c: Component, t: f64, h: f64, _no_prior: Boolean) -> Status {
    // SAFETY: as entry.
    unsafe { entry::<M, _>(c, Call::DoStep, |inst| inst.do_step(t, h, "fmi2DoStep")) }
}

impl<M: Model> Instance<M> {
    /// One communication step from `t` to `t + h` (`fmi2DoStep`, `fmi3DoStep`: `call` names it
    /// in the message of a step the model refuses).
    pub fn do_step(&mut self, t: f64, h: f64, call: &str) -> Outcome {
        if !(t.is_finite() && h.is_finite()) {
            return Err(format!(
                "currentCommunicationPoint = {t}, communicationStepSize = {h}: not finite"
            ));
        }
        if h <= 0.0 {
            return Err(format!("communicationStepSize = {h} must be > 0"));
        }
        if !(t + h).is_finite() {
            return Err(format!(
                "communicationStepSize = {h} from {t}: the end of the step is not finite"
            ));
        }
        let tol = 1e-9 * self.time.abs().max(1.0);
        if (t - self.time).abs() > tol {
            return Err(format!(
                "currentCommunicationPoint = {t} differs from the FMU's time {}",
                self.time
            ));
        }
        if let Some(stop) = self.stop_time
            && t + h > stop + 1e-9 * stop.abs().max(1.0)
        {
            return Err(format!("step to {} passes the stop time {stop}", t + h));
        }
        // the host's communication point names the FMU's time (to rounding): what was set
        // at the FMU's time was set at t
        if self.values.inputs_at == self.time {
            self.values.inputs_at = t;
        }
        self.time = t;
        self.prepared()?;
        let model = self.model.as_mut().expect("prepared");
        if let Err(why) = model.step(&mut self.values, t, h, &mut self.logger) {
            self.state = State::StepFailed;
            self.logger.emit(
                Status::Discard,
                "logStatusDiscard",
                &format!("{call} from t = {t}: {why}"),
            );
            return Ok(Status::Discard);
        }
        self.time = t + h;
        self.dirty = true;
        // input derivatives apply to the step they were set for (FMI 2.0: "with respect to
        // the beginning of a communication time step"); the next step starts from the
        // inputs as Model::step left them at t + h, unless the host sets them
        self.values.clear_input_derivatives();
        Ok(Status::Ok)
    }
}

/// A typed `fmi2Get*Status` of a synchronous slave: it answers one status `kind`, `known`,
/// with `read`; any other kind is refused.
///
/// # Safety
/// As [`entry`]; `value` points to one element.
unsafe fn typed_status<M: Model, T>(
    c: Component,
    call: Call,
    known: StatusKind,
    kind: std::ffi::c_int,
    value: *mut T,
    read: impl FnOnce(&Instance<M>) -> T,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            if value.is_null() {
                return Err("value is NULL".into());
            }
            if kind != known as i32 {
                return Err(format!(
                    "fmi2{call:?} answers fmi2{known:?} ({}) only, not {kind}",
                    known as i32
                ));
            }
            *value = read(inst);
            Ok(Status::Ok)
        })
    }
}

/// `fmi2GetStatus` and the typed variants: only what a synchronous slave can answer.
///
/// # Safety
/// As [`entry`]; `value` points to one element.
pub unsafe fn get_real_status<M: Model>(
    c: Component,
    kind: std::ffi::c_int,
    value: *mut Real,
) -> Status {
    let known = StatusKind::LastSuccessfulTime;
    // SAFETY: as this function.
    unsafe { typed_status::<M, _>(c, Call::GetRealStatus, known, kind, value, |i| i.time) }
}

/// `fmi2GetBooleanStatus`: `fmi2Terminated` is always false (the slave never ends a run itself).
///
/// # Safety
/// As [`entry`]; `value` points to one element.
pub unsafe fn get_boolean_status<M: Model>(
    c: Component,
    kind: std::ffi::c_int,
    value: *mut Boolean,
) -> Status {
    let known = StatusKind::Terminated;
    // SAFETY: as this function.
    unsafe { typed_status::<M, _>(c, Call::GetBooleanStatus, known, kind, value, |_| FALSE) }
}

impl<M: Model> Instance<M> {
    /// The value references of the discrete outputs this FMU lists whose change is an event
    /// ([`crate::model::Var::event`]).
    fn event_outputs(&self) -> Vec<usize> {
        (Self::table().iter().enumerate())
            .filter(|&(i, v)| v.event && self.access.get(i).is_some_and(|&a| a != 0))
            .map(|(i, _)| i)
            .collect()
    }

    /// A step from `t` that returns early at the first event inside it (FMI 3.0's
    /// `earlyReturnAllowed`): the step to `t + h`; if an event output then differs from its
    /// value at `t`, the shortest step after which it differs, found by bisection (each trial
    /// from the state at `t`, without logging) to adjacent floating-point times, is the step
    /// taken. Returns the status and the event's time if the step ended there. A change and a
    /// change back inside one step are not seen (a shorter step sees them).
    pub fn do_step_to_event(
        &mut self,
        t: f64,
        h: f64,
        call: &str,
    ) -> Result<(Status, Option<f64>), String> {
        let events = self.event_outputs();
        if events.is_empty() {
            return Ok((self.do_step(t, h, call)?, None));
        }
        self.refresh()?;
        let read = |inst: &Self| -> Vec<f64> {
            let raw = inst.values.raw();
            events.iter().map(|&i| raw[i]).collect()
        };
        let before = read(self);
        let saved = (
            self.values.clone(),
            self.model.as_ref().map(M::save_state),
            self.time,
            self.state,
        );
        let status = self.do_step(t, h, call)?;
        if status != Status::Ok {
            return Ok((status, None));
        }
        self.refresh()?;
        if read(self) == before {
            return Ok((status, None));
        }
        let muted = std::mem::replace(&mut self.logger.sink, logger::Sink::Fmi2(None));
        let (mut lo, mut hi) = (0.0_f64, h);
        // the logger is muted for the trials and given back even if one panics (the entry
        // wrapper reports the panic through it)
        let trials = catch_unwind(AssertUnwindSafe(|| -> Result<(), String> {
            loop {
                let mid = lo + 0.5 * (hi - lo);
                if !(t + lo < t + mid && t + mid < t + hi) {
                    return Ok(());
                }
                self.put_back(&saved)?;
                // a shorter step refused: the event is taken where it was found
                if !matches!(self.do_step(t, mid, call), Ok(Status::Ok)) || self.refresh().is_err()
                {
                    return Ok(());
                }
                if read(self) != before {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
        }));
        self.logger.sink = muted;
        trials.unwrap_or_else(|p| std::panic::resume_unwind(p))?;
        self.put_back(&saved)?;
        let status = self.do_step(t, hi, call)?;
        Ok((status, (hi < h).then_some(t + hi)))
    }

    /// Back to what [`Instance::do_step_to_event`] saved.
    fn put_back(&mut self, saved: &(Values<M::Var>, Option<Vec<f64>>, f64, State)) -> Outcome {
        let (values, model_state, time, state) = saved;
        self.values = values.clone();
        if let (Some(m), Some(s)) = (self.model.as_mut(), model_state) {
            m.restore_state(s)?;
        }
        (self.time, self.state, self.dirty) = (*time, *state, true);
        Ok(Status::Ok)
    }
}
