//! The generic FMI 2.0 co-simulation runtime: one instance type over any [`Model`], one entry
//! wrapper ([`entry`]) that checks the component, the state machine and catches panics, and
//! the implementation of every call. It knows no mechanism: what it knows of a model is the
//! [`Model`] trait and the variable table.
//!
//! The `extern "C"` symbols themselves are generated per FMU by [`crate::export_fmu!`], each a
//! one-line call into this module.
//!
//! This file: the instance, its access table and the entry wrapper. Beside it: `lifecycle.rs`
//! (instantiation to termination), `getset.rs` (get and set), `logger.rs` (the host's logger),
//! `snapshot.rs` (an FMU state and its serialized form), `fmu_state.rs` (the FMU-state calls),
//! `cs.rs` (the Co-Simulation calls), `me.rs` (the Model Exchange calls), `runtime_tests.rs`.

use super::state::{Call, MeState, State, allowed, me_allowed};
use super::types::*;
use crate::md;
use crate::model::{
    Log, MAX_INPUT_DERIVATIVE_ORDER, Model, SetPhase, Severity, Values, Var, VarSet, VarType,
    check_bounds,
};
use std::ffi::{CStr, CString};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;

#[path = "cs.rs"]
mod cs;
#[path = "fmu_state.rs"]
mod fmu_state;
#[path = "getset.rs"]
mod getset;
#[path = "lifecycle.rs"]
mod lifecycle;
#[path = "logger.rs"]
mod logger;
#[path = "me.rs"]
pub mod me;
#[path = "partials.rs"]
mod partials;
#[path = "snapshot.rs"]
mod snapshot;

pub use cs::*;
pub use getset::*;
pub use lifecycle::*;
pub use logger::Logger;
use logger::category_bit;
use snapshot::Snapshot;

const MAGIC: u64 = 0x4249_4e44_4552_5932; // "BINDERY2"
const STATE_MAGIC: &[u8; 8] = b"BNDRYST4";

/// What a host may do with a variable, as bits of one word per value reference: the per-value
/// checks of `fmi2Get*`/`fmi2Set*` are one load and a mask (the variable table holds the same
/// facts, for the messages of refused calls).
pub mod access {
    use crate::model::{Causality, SetPhase, Var, VarType};

    /// The bits of one variable.
    pub type Bits = u16;
    /// Read and written by `fmi2GetReal`/`fmi2SetReal`.
    pub const REAL: Bits = 1;
    /// By the Integer calls (Integer and Enumeration variables).
    pub const INTEGER: Bits = 2;
    /// By the Boolean calls.
    pub const BOOLEAN: Bits = 4;
    /// Settable before `fmi2EnterInitializationMode`.
    pub const SET_INSTANTIATED: Bits = 8;
    /// Settable in initialization mode.
    pub const SET_INITIALIZATION: Bits = 16;
    /// Settable after initialization (Co-Simulation, Model Exchange in event mode).
    pub const SET_RUNNING: Bits = 32;
    /// An Enumeration: a set value must be one of its items (checked on the slow path).
    pub const ENUMERATION: Bits = 64;
    /// A parameter: setting it re-prepares the model.
    pub const PARAMETER: Bits = 128;
    /// Settable in Model Exchange's continuous-time mode (an input).
    pub const SET_CONTINUOUS_TIME: Bits = 256;
    /// By the String calls: no variable has it (the models have no String variables), so
    /// every String call takes the slow path, which refuses it naming the variable's type.
    pub const STRING: Bits = 512;
    /// By FMI 3.0's Int32 calls (Integer variables).
    pub const INT32: Bits = 1024;
    /// By FMI 3.0's Int64 calls (Enumeration variables: FMI 3.0 gets and sets them as Int64).
    pub const INT64: Bits = 2048;

    /// The bits of one declared variable.
    pub fn of(v: &Var) -> Bits {
        let mut a = match v.ty {
            VarType::Real => REAL,
            VarType::Integer => INTEGER | INT32,
            VarType::Boolean => BOOLEAN,
            VarType::Enumeration(_) => INTEGER | ENUMERATION | INT64,
        };
        for phase in SetPhase::ALL {
            if v.settable(phase) {
                a |= settable_bit(phase);
            }
        }
        if v.causality == Causality::Parameter {
            a |= PARAMETER;
        }
        a
    }

    /// The bit that says a variable may be set in this phase.
    #[inline]
    pub fn settable_bit(phase: SetPhase) -> Bits {
        match phase {
            SetPhase::Instantiated => SET_INSTANTIATED,
            SetPhase::Initialization => SET_INITIALIZATION,
            SetPhase::Running => SET_RUNNING,
            SetPhase::ContinuousTime => SET_CONTINUOUS_TIME,
        }
    }
}

/// The [`access`] bits of every variable of `M`; 0 for those a tailored FMU leaves out, so the
/// per-call checks refuse them without looking at the scene.
fn access_table<M: Model>(scene: Option<&crate::scene::Tailored>) -> Box<[access::Bits]> {
    <M::Var as VarSet>::table()
        .iter()
        .enumerate()
        .map(|(i, v)| match scene {
            Some(t) if !t.exposed.get(i).copied().unwrap_or(false) => 0,
            _ => access::of(v),
        })
        .collect()
}

/// One FMU instance.
pub struct Instance<M: Model> {
    magic: u64,
    guid_hash: u128,
    pub logger: Logger,
    pub state: State,
    pub values: Values<M::Var>,
    model: Option<M>,
    /// Outputs are stale (an input, parameter or the time changed since the last evaluation).
    dirty: bool,
    /// Parameters changed since the model was prepared.
    params_changed: bool,
    pub time: f64,
    start_time: f64,
    stop_time: Option<f64>,
    /// Where the FMU's `resources/` folder is, if the host said.
    pub resources: Option<PathBuf>,
    /// FMU states handed out and not yet freed (so a foreign pointer is refused, not followed).
    snapshots: Vec<*mut Snapshot>,
    /// Model Exchange: instantiated as such, and its mode. An FMI 3.0 Co-Simulation instance
    /// with event mode ([`Instance::event_mode_used`]) keeps its Event Mode (`me::Mode::Event`)
    /// and Step Mode (`ContinuousTime`) here too.
    pub me: me::MeMode,
    /// FMI 3.0 Co-Simulation: the host uses Event Mode (`eventModeUsed`).
    pub event_mode_used: bool,
    /// FMI 3.0 Co-Simulation: a step may return early at the first event
    /// (`earlyReturnAllowed`): where a discrete output marked as an event changes.
    pub early_return: bool,
    /// Per value reference, what a host may do with it ([`access`]; 0: not visible).
    access: Box<[access::Bits]>,
    /// The scene this FMU is tailored to (`resources/scene.toml`), if any: its variables are
    /// the only ones a host may address, its start values and stages are the instance's.
    pub scene: Option<std::sync::Arc<crate::scene::Tailored>>,
}

type Outcome = Result<Status, String>;

impl<M: Model> Instance<M> {
    fn new(
        logger: Logger,
        resources: Option<PathBuf>,
        guid: &str,
        scene: Option<std::sync::Arc<crate::scene::Tailored>>,
    ) -> Self {
        Instance {
            magic: MAGIC,
            guid_hash: md::fnv1a_128(guid.as_bytes()),
            logger,
            state: State::Instantiated,
            values: start_values::<M>(scene.as_deref()),
            model: None,
            dirty: true,
            params_changed: true,
            time: 0.0,
            start_time: 0.0,
            stop_time: None,
            resources,
            snapshots: Vec::new(),
            me: me::MeMode::default(),
            event_mode_used: false,
            early_return: false,
            access: access_table::<M>(scene.as_deref()),
            scene,
        }
    }

    /// Is this value reference one this FMU lists? (All of the model's, unless tailored.)
    #[inline]
    fn listed(&self, vr: ValueReference) -> bool {
        match &self.scene {
            None => true,
            Some(t) => t.exposed.get(vr as usize).copied().unwrap_or(false),
        }
    }

    /// The refusal of a value reference this FMU does not list.
    #[cold]
    fn unlisted(&self, vr: ValueReference) -> String {
        match &self.scene {
            Some(t) if (vr as usize) < t.exposed.len() => format!(
                "unknown value reference {vr}: {} is left out of {} (scene {:?})",
                Self::table()[vr as usize].name,
                t.identifier,
                t.scene.name
            ),
            _ => format!("unknown value reference {vr}"),
        }
    }

    fn table() -> &'static [Var] {
        <M::Var as VarSet>::table()
    }

    /// The Model Exchange state of an instance (None for the Co-Simulation-only states a
    /// Model Exchange instance is never in).
    pub fn me_state(&self) -> Option<MeState> {
        Some(match self.state {
            State::Instantiated => MeState::Instantiated,
            State::InitializationMode => MeState::InitializationMode,
            State::StepComplete => match self.me.mode {
                me::Mode::Event => MeState::EventMode,
                me::Mode::ContinuousTime => MeState::ContinuousTimeMode,
            },
            State::Terminated => MeState::Terminated,
            State::Error => MeState::Error,
            State::StepFailed | State::StepCanceled | State::Fatal => return None,
        })
    }

    /// Makes sure the model is prepared for the current parameters.
    #[inline]
    fn prepared(&mut self) -> Result<&mut M, String> {
        if self.params_changed || self.model.is_none() {
            self.prepare_now()?;
        }
        Ok(self.model.as_mut().expect("prepared above"))
    }

    /// The slow path of [`Instance::prepared`], out of the per-step code.
    #[cold]
    #[inline(never)]
    fn prepare_now(&mut self) -> Result<(), String> {
        check_bounds(&self.values).map_err(|e| e.to_string())?;
        let model = M::prepare(&self.values).map_err(|e| e.to_string())?;
        model.calculated_parameters(&mut self.values);
        self.model = Some(model);
        self.params_changed = false;
        self.dirty = true;
        Ok(())
    }

    /// Makes sure the outputs are current (lazy outputs).
    #[inline]
    fn refresh(&mut self) -> Result<(), String> {
        self.prepared()?;
        if self.dirty {
            let model = self.model.as_mut().expect("prepared above");
            model.evaluate(&mut self.values, self.time, &mut self.logger);
            self.dirty = false;
        }
        Ok(())
    }

    fn set_phase(&self) -> SetPhase {
        match self.state {
            State::Instantiated => SetPhase::Instantiated,
            State::InitializationMode => SetPhase::Initialization,
            State::StepComplete if self.me.is_me && self.me.mode == me::Mode::ContinuousTime => {
                SetPhase::ContinuousTime
            }
            _ => SetPhase::Running,
        }
    }

    /// Validates every (vr, value) first, then applies them all: a refused call changes nothing.
    /// The common case (every value of the right type, settable now, finite, no enumeration)
    /// costs one byte load and a mask per value ([`access`]); anything else takes the slow path
    /// that names the culprit.
    fn set_values(&mut self, vrs: &[ValueReference], vals: &[f64], kind: Kind) -> Outcome {
        let phase = self.set_phase();
        let need = kind.bit | access::settable_bit(phase);
        let fast = vrs.iter().zip(vals).all(|(&vr, &x)| {
            let a = self.access.get(vr as usize).copied().unwrap_or(0);
            a & need == need && a & access::ENUMERATION == 0 && x.is_finite()
        });
        if !fast {
            self.check_set(vrs, vals, kind, phase)?;
        }
        let table = Self::table();
        let raw = self.values.raw_mut();
        let mut input_set = false;
        for (&vr, &x) in vrs.iter().zip(vals) {
            let slot = &mut raw[vr as usize];
            if *slot != x {
                *slot = x;
                self.dirty = true;
                if self.access[vr as usize] & access::PARAMETER != 0 {
                    self.params_changed = true;
                }
            }
            input_set |= table[vr as usize].causality == crate::model::Causality::Input;
        }
        // an input is the value at the instant it is set (the model may move it on from there)
        if input_set && self.values.inputs_at != self.time {
            self.values.inputs_at = self.time;
            self.dirty = true;
        }
        Ok(Status::Ok)
    }

    /// The slow path of [`Instance::set_values`]: the first refused value, named.
    #[cold]
    #[inline(never)]
    fn check_set(
        &self,
        vrs: &[ValueReference],
        vals: &[f64],
        kind: Kind,
        phase: SetPhase,
    ) -> Result<(), String> {
        let table = Self::table();
        for (&vr, &x) in vrs.iter().zip(vals) {
            let v = table
                .get(vr as usize)
                .filter(|_| self.listed(vr))
                .ok_or_else(|| self.unlisted(vr))?;
            if !(kind.ok)(v.ty) {
                return Err(format!("{} (vr {vr}) is not of type {}", v.name, kind.name));
            }
            if !v.settable(phase) {
                return Err(format!(
                    "{} cannot be set {}",
                    v.name,
                    match phase {
                        SetPhase::Running =>
                            "after initialization (it is not an input or tunable parameter)",
                        SetPhase::ContinuousTime =>
                            "in continuous-time mode (only continuous inputs; a tunable parameter in event mode)",
                        _ => "(it is not a parameter or an input)",
                    }
                ));
            }
            if !x.is_finite() {
                return Err(format!(
                    "{} = {x} refused: not a finite number; the previous value {} is kept",
                    v.name,
                    self.values.raw()[vr as usize]
                ));
            }
            if let VarType::Enumeration(t) = v.ty
                && t.item(x as i32).is_none()
            {
                return Err(format!(
                    "{} = {x} refused: not an item of {} (1..={})",
                    v.name,
                    t.name,
                    t.items.len()
                ));
            }
        }
        Ok(())
    }

    /// Brings the outputs up to date (lazy outputs), then writes the value of each vr, converted
    /// by `conv`, to `out`, checking in the same pass that it is a variable of this type (one
    /// byte load and a mask, [`access`]). A vr refused ends the call with the slow path's
    /// message naming it; `out` is then undefined, as FMI 2.0 has it for a call that returns
    /// `fmi2Error`.
    fn read_values<T>(
        &mut self,
        vrs: &[ValueReference],
        out: &mut [T],
        kind: Kind,
        conv: impl Fn(f64) -> T,
    ) -> Outcome {
        self.refresh()?;
        let (access, raw, bit) = (&self.access[..], self.values.raw(), kind.bit);
        let fast = out.iter_mut().zip(vrs).all(|(o, &vr)| {
            let i = vr as usize;
            let ok = i < raw.len() && access.get(i).is_some_and(|a| a & bit != 0);
            if ok {
                *o = conv(raw[i]);
            }
            ok
        });
        if !fast {
            self.check_get(vrs, kind)?;
            // the access table and the slow check agree, so this is not reached; were it, the
            // values are read as the slow check allows rather than left unwritten
            for (o, &vr) in out.iter_mut().zip(vrs) {
                let x = raw.get(vr as usize).copied();
                *o = conv(x.ok_or_else(|| format!("unknown value reference {vr}"))?);
            }
        }
        Ok(Status::Ok)
    }

    /// The slow path of [`Instance::read_values`]: the first vr refused, named.
    #[cold]
    #[inline(never)]
    fn check_get(&self, vrs: &[ValueReference], kind: Kind) -> Result<(), String> {
        let table = Self::table();
        for &vr in vrs {
            match table.get(vr as usize) {
                Some(_) if !self.listed(vr) => return Err(self.unlisted(vr)),
                Some(v) if (kind.ok)(v.ty) => {}
                Some(v) => {
                    return Err(format!("{} (vr {vr}) is not of type {}", v.name, kind.name));
                }
                None => return Err(format!("unknown value reference {vr}")),
            }
        }
        Ok(())
    }

    /// Is `(vr, order, x)` an input derivative `fmi2SetRealInputDerivatives` accepts?
    fn check_input_derivative(vr: u32, order: u32, x: f64) -> Result<(), String> {
        let v = Self::table()
            .get(vr as usize)
            .ok_or_else(|| format!("unknown value reference {vr}"))?;
        if !(v.ty == VarType::Real && v.causality == crate::model::Causality::Input) {
            return Err(format!(
                "{} (vr {vr}) is not a Real input; only inputs have input derivatives",
                v.name
            ));
        }
        if !(1..=MAX_INPUT_DERIVATIVE_ORDER).contains(&order) {
            return Err(format!(
                "order {order} of the derivative of {} refused: this FMU takes orders 1..={MAX_INPUT_DERIVATIVE_ORDER}",
                v.name
            ));
        }
        if !x.is_finite() {
            return Err(format!(
                "derivative of order {order} of {} = {x} refused: not a finite number",
                v.name
            ));
        }
        Ok(())
    }

    fn snapshot(&self) -> Snapshot {
        Snapshot {
            state: self.state,
            time: self.time,
            start_time: self.start_time,
            stop_time: self.stop_time,
            values: self.values.raw().to_vec(),
            model_state: self.model.as_ref().map(M::save_state).unwrap_or_default(),
            input_derivatives: self.values.input_derivatives().to_vec(),
            continuous_time: (self.me.is_me || self.event_mode_used)
                && self.state == State::StepComplete
                && self.me.mode == me::Mode::ContinuousTime,
            inputs_at: self.values.inputs_at,
        }
    }

    fn restore(&mut self, s: &Snapshot) -> Outcome {
        if s.values.len() != self.values.raw().len() {
            return Err("FMU state does not belong to this FMU".into());
        }
        // A serialized state is data a host may have stored and altered: it is held to what
        // fmi2Set* and fmi2ExitInitializationMode accept, so no model runs on refused values.
        if !(s.time.is_finite()
            && s.start_time.is_finite()
            && s.stop_time.is_none_or(f64::is_finite))
        {
            return Err(format!(
                "FMU state refused: time = {}, start time = {}, stop time = {:?} must be finite",
                s.time, s.start_time, s.stop_time
            ));
        }
        if s.state == State::Fatal {
            return Err("FMU state refused: an instance never leaves state Fatal".into());
        }
        if self.me.is_me && matches!(s.state, State::StepFailed | State::StepCanceled) {
            return Err(format!(
                "FMU state refused: {:?} is a Co-Simulation state; this instance is Model Exchange",
                s.state
            ));
        }
        if s.continuous_time
            && !((self.me.is_me || self.event_mode_used) && s.state == State::StepComplete)
        {
            return Err(
                "FMU state refused: continuous-time mode belongs to an initialized Model Exchange instance"
                    .into(),
            );
        }
        for (v, &x) in Self::table().iter().zip(&s.values) {
            if matches!(
                v.causality,
                crate::model::Causality::Input | crate::model::Causality::Parameter
            ) && !x.is_finite()
            {
                return Err(format!("FMU state refused: {} = {x} is not finite", v.name));
            }
        }
        let mut values = start_values::<M>(self.scene.as_deref());
        values.raw_mut().copy_from_slice(&s.values);
        values.inputs_at = s.inputs_at;
        for &(vr, order, x) in &s.input_derivatives {
            Self::check_input_derivative(vr, order, x)
                .map_err(|e| format!("FMU state refused: {e}"))?;
            values.set_input_derivative(vr, order, x);
        }
        if !matches!(s.state, State::Instantiated | State::InitializationMode) {
            check_bounds(&values).map_err(|e| format!("FMU state refused: {e}"))?;
        }
        // Before initialization ends the model is prepared afresh (fmi2ExitInitializationMode
        // always re-prepares it), so a state saved then carries no model state to restore.
        let model = if matches!(s.state, State::Instantiated | State::InitializationMode) {
            None
        } else {
            match M::prepare(&values) {
                Ok(mut m) => {
                    m.restore_state(&s.model_state)?;
                    m.calculated_parameters(&mut values);
                    Some(m)
                }
                Err(e) if s.state == State::InitializationMode => {
                    let _ = e;
                    None
                }
                Err(e) => return Err(format!("FMU state cannot be restored: {e}")),
            }
        };
        self.values = values;
        self.params_changed = model.is_none();
        self.model = model;
        self.state = s.state;
        self.me.mode = if s.continuous_time {
            me::Mode::ContinuousTime
        } else {
            me::Mode::Event
        };
        self.time = s.time;
        self.start_time = s.start_time;
        self.stop_time = s.stop_time;
        self.dirty = true;
        Ok(Status::Ok)
    }

    fn own_snapshot(&self, p: FMUstate) -> Result<*mut Snapshot, String> {
        let p = p as *mut Snapshot;
        if p.is_null() {
            return Err("FMU state is NULL".into());
        }
        if !self.snapshots.contains(&p) {
            return Err("FMU state was not created by this instance (or was already freed)".into());
        }
        Ok(p)
    }

    /// Puts `snap` where `*state` says: a new FMU state of this instance if it is NULL, else
    /// over the one of this instance it points to (`fmi2GetFMUstate`, `fmi2DeSerializeFMUstate`).
    ///
    /// # Safety
    /// `state` is a valid pointer to an `FMUstate`.
    unsafe fn store_snapshot(&mut self, state: *mut FMUstate, snap: Snapshot) -> Outcome {
        // SAFETY: as this function.
        if unsafe { (*state).is_null() } {
            let p = Box::into_raw(Box::new(snap));
            self.snapshots.push(p);
            // SAFETY: as this function.
            unsafe { *state = p as FMUstate };
        } else {
            // SAFETY: as this function; own_snapshot checked it is one of ours.
            let p = self.own_snapshot(unsafe { *state })?;
            // SAFETY: a live snapshot of this instance.
            unsafe { *p = snap };
        }
        Ok(Status::Ok)
    }
}

impl<M: Model> Drop for Instance<M> {
    fn drop(&mut self) {
        for p in self.snapshots.drain(..) {
            // SAFETY: every pointer in `snapshots` came from Box::into_raw and was not freed.
            drop(unsafe { Box::from_raw(p) });
        }
        self.magic = 0;
    }
}

/// A function of one FMI version's C API: how it is named in messages and where it is legal.
/// [`entry`] serves FMI 2.0 ([`Call`]) and FMI 3.0 (`crate::fmi3::state::Call`) alike.
pub trait Api: Copy + std::fmt::Debug {
    /// `fmi2` or `fmi3`: a call is named `{PREFIX}{call:?}`.
    const PREFIX: &'static str;
    /// [`Api::PREFIX`] of a value's type.
    fn prefix(&self) -> &'static str {
        Self::PREFIX
    }
    /// Is the call legal on this instance now? The inline fast path: `false` sends the call to
    /// [`Api::refusal`], which decides (and words the refusal).
    fn allowed_now<M: Model>(self, inst: &Instance<M>) -> bool;
    /// Why the call is illegal on this instance now (its interface's state machine), if it is.
    fn refusal<M: Model>(self, inst: &Instance<M>) -> Option<String>;
}

impl Api for Call {
    const PREFIX: &'static str = "fmi2";
    /// A co-simulation call legal in the instance's state is one table load and a mask;
    /// anything else (and every Model Exchange call) takes the out-of-line path.
    #[inline]
    fn allowed_now<M: Model>(self, inst: &Instance<M>) -> bool {
        !inst.me.is_me && allowed(self, inst.state)
    }
    fn refusal<M: Model>(self, inst: &Instance<M>) -> Option<String> {
        refusal(inst, self)
    }
}

/// Why `call` is illegal in the instance's state (its interface's state machine), if it is.
/// Out of line: [`entry`] decides a legal co-simulation call inline and comes here for Model
/// Exchange calls and refusals.
#[inline(never)]
fn refusal<M: Model>(inst: &Instance<M>, call: Call) -> Option<String> {
    if inst.me.is_me {
        let state = inst.me_state();
        let legal = state.is_some_and(|s| me_allowed(call, s));
        (!legal).then(|| {
            format!(
                "fmi2{call:?} is not allowed in state {}{}",
                state.map_or_else(|| format!("{:?}", inst.state), |s| format!("{s:?}")),
                if call.is_co_simulation() {
                    " (a Co-Simulation function; this instance is Model Exchange)"
                } else {
                    ""
                }
            )
        })
    } else {
        (!allowed(call, inst.state)).then(|| {
            format!(
                "fmi2{call:?} is not allowed in state {:?}{}",
                inst.state,
                if call.is_model_exchange() {
                    " (a Model Exchange function; this instance is Co-Simulation)"
                } else {
                    ""
                }
            )
        })
    }
}

pub(crate) fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// The live instances, by address and model: [`entry`] dereferences a handle only if it is
/// one of them, so a freed, foreign or made-up handle is refused without being read.
mod registry {
    use super::{Component, Model};
    use std::sync::Mutex;

    static LIVE: Mutex<Vec<(usize, &'static str)>> = Mutex::new(Vec::new());

    fn live() -> std::sync::MutexGuard<'static, Vec<(usize, &'static str)>> {
        LIVE.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A new instance of `M`.
    pub fn add<M: Model>(c: Component) {
        live().push((c as usize, M::IDENTIFIER));
    }

    /// Is `c` a live instance of `M`?
    pub fn holds<M: Model>(c: Component) -> bool {
        let key = (c as usize, M::IDENTIFIER);
        !c.is_null() && live().contains(&key)
    }

    /// Forgets `c`; false if it was not a live instance of `M`.
    pub fn remove<M: Model>(c: Component) -> bool {
        let mut l = live();
        match l.iter().position(|&k| k == (c as usize, M::IDENTIFIER)) {
            Some(i) => {
                l.swap_remove(i);
                if l.is_empty() {
                    // no buffer outlives the last instance: a library unloaded then keeps none
                    *l = Vec::new();
                }
                true
            }
            None => false,
        }
    }
}

/// The one entry wrapper: checks the component pointer, the state machine, runs `f` with panics
/// caught, and logs any refusal with its reason.
///
/// # Safety
/// None for `c` itself: any pointer is refused unless it is a live instance of `M` (the
/// registry); `f` gets that instance.
pub unsafe fn entry<M: Model, C: Api>(
    c: Component,
    call: C,
    f: impl FnOnce(&mut Instance<M>) -> Outcome,
) -> Status {
    // a handle that is not a live instance of this model (NULL, freed, another model's, any
    // other pointer) is refused without being dereferenced
    if !registry::holds::<M>(c) {
        return Status::Error;
    }
    // SAFETY: a registered handle is a live Instance<M> (registry).
    let inst = unsafe { &mut *(c as *mut Instance<M>) };
    if inst.magic != MAGIC {
        return Status::Error;
    }
    // the common case, a call legal in the instance's state, is decided inline
    if !call.allowed_now(inst)
        && let Some(msg) = call.refusal(inst)
    {
        inst.logger.emit(Status::Error, "logStatusError", &msg);
        return Status::Error;
    }
    if inst.logger.on && inst.logger.enabled(Status::Ok, "logAll") {
        inst.logger
            .emit(Status::Ok, "logAll", &format!("{}{call:?}", C::PREFIX));
    }
    match catch_unwind(AssertUnwindSafe(|| f(inst))) {
        Ok(Ok(status)) => status,
        Ok(Err(msg)) => {
            inst.logger.emit(
                Status::Error,
                "logStatusError",
                &format!("{}{call:?}: {msg}", C::PREFIX),
            );
            Status::Error
        }
        Err(p) => {
            let msg = format!(
                "{}{call:?}: internal error (panic caught at the FMI boundary): {}",
                C::PREFIX,
                panic_text(&*p)
            );
            inst.state = State::Error;
            inst.logger.emit(Status::Error, "logStatusError", &msg);
            Status::Error
        }
    }
}

/// Builds a slice from a C array, refusing NULL when `n > 0`.
///
/// # Safety
/// `p` must point to `n` valid elements when non-NULL.
pub(crate) unsafe fn slice<'a, T>(p: *const T, n: usize, what: &str) -> Result<&'a [T], String> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(format!("{what} is NULL but nvr = {n}"));
    }
    // SAFETY: per the contract above.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// As [`fn@slice`], mutable.
///
/// # Safety
/// `p` must point to `n` valid elements when non-NULL.
pub(crate) unsafe fn slice_mut<'a, T>(
    p: *mut T,
    n: usize,
    what: &str,
) -> Result<&'a mut [T], String> {
    if n == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(format!("{what} is NULL but nvr = {n}"));
    }
    // SAFETY: per the contract above.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// # Safety
/// `s` must be NULL or a valid C string.
pub(crate) unsafe fn c_str<'a>(s: FmiString) -> Option<&'a str> {
    // SAFETY: per the contract above.
    (!s.is_null())
        .then(|| unsafe { CStr::from_ptr(s) }.to_str().ok())
        .flatten()
}

/// The start values of an instance: the model's, or those of the scene it is tailored to (with
/// the stages the scene's outputs need).
fn start_values<M: Model>(scene: Option<&crate::scene::Tailored>) -> Values<M::Var> {
    let mut v = Values::start();
    if let Some(t) = scene {
        v.raw_mut().copy_from_slice(&t.start);
        v.stages = t.stages;
    }
    v
}

pub use super::uri::resource_path;

#[cfg(test)]
#[path = "runtime_tests.rs"]
mod tests;
