//! The FMI 3.0 state machine as a declarative table of which call is legal in which state (FMI
//! 3.0 standard, sections 3.2.2 and 4.2.2; the `MASK_` table of the Reference FMUs). An FMI 3.0
//! instance lives in the states of the shared runtime ([`crate::fmi2::state::State`]), named
//! the FMI 3.0 way in messages: `StepComplete` is Step Mode, `StepFailed` Step Discarded.

use crate::fmi2::runtime::{Api, Instance};
use crate::fmi2::state::MeState::{
    self, ContinuousTimeMode as Ct, Error as Er, EventMode as Ev, InitializationMode as In,
    Instantiated as Is, Terminated as Te,
};
use crate::fmi2::state::State::{self, *};
use crate::fmi2::state::{mask, me_mask};
use crate::model::Model;

/// Every FMI 3.0 function that takes an instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Call {
    SetDebugLogging,
    FreeInstance,
    EnterInitializationMode,
    ExitInitializationMode,
    EnterEventMode,
    Terminate,
    Reset,
    GetFloat32,
    GetFloat64,
    GetInt8,
    GetUInt8,
    GetInt16,
    GetUInt16,
    GetInt32,
    GetUInt32,
    GetInt64,
    GetUInt64,
    GetBoolean,
    GetString,
    GetBinary,
    GetClock,
    SetFloat32,
    SetFloat64,
    SetInt8,
    SetUInt8,
    SetInt16,
    SetUInt16,
    SetInt32,
    SetUInt32,
    SetInt64,
    SetUInt64,
    SetBoolean,
    SetString,
    SetBinary,
    SetClock,
    GetNumberOfVariableDependencies,
    GetVariableDependencies,
    GetFMUState,
    SetFMUState,
    FreeFMUState,
    SerializedFMUStateSize,
    SerializeFMUState,
    DeserializeFMUState,
    GetDirectionalDerivative,
    GetAdjointDerivative,
    EnterConfigurationMode,
    ExitConfigurationMode,
    GetIntervalDecimal,
    GetIntervalFraction,
    GetShiftDecimal,
    GetShiftFraction,
    SetIntervalDecimal,
    SetIntervalFraction,
    SetShiftDecimal,
    SetShiftFraction,
    EvaluateDiscreteStates,
    UpdateDiscreteStates,
    EnterContinuousTimeMode,
    CompletedIntegratorStep,
    SetTime,
    SetContinuousStates,
    GetContinuousStateDerivatives,
    GetEventIndicators,
    GetContinuousStates,
    GetNominalsOfContinuousStates,
    GetNumberOfEventIndicators,
    GetNumberOfContinuousStates,
    EnterStepMode,
    GetOutputDerivatives,
    DoStep,
    ActivateModelPartition,
}

/// Event Mode of a Co-Simulation instance that uses it (`eventModeUsed`): the runtime's
/// `StepComplete` with its mode at `Event` ([`bits`]); a bit of its own in the masks.
pub const EVENT_MODE: u16 = 1 << 8;
/// Step Mode: the runtime's `StepComplete` (outside Event Mode).
const STEP: u16 = StepComplete as u16;

/// Where values can be read: from initialization on (and in Error, for diagnosis).
const READ: u16 = mask(&[
    InitializationMode,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
]) | EVENT_MODE;
/// Every state but Fatal.
const ANY: u16 = READ | Instantiated as u16;
/// Where values can be set.
const SET: u16 = mask(&[Instantiated, InitializationMode, StepComplete, Terminated]) | EVENT_MODE;

/// Model Exchange states, as the runtime's `MeState` bits.
const ME_ANY: u8 = me_mask(&[Is, In, Ev, Ct, Te, Er]);
const ME_READ: u8 = me_mask(&[In, Ev, Ct, Te, Er]);
const ME_SET: u8 = me_mask(&[Is, In, Ev, Ct]);
const ME_SET_DISCRETE: u8 = me_mask(&[Is, In, Ev]);

/// In which states of each interface each call is legal: (call, Co-Simulation states, Model
/// Exchange states); 0: never on that interface (configuration and clocks are not offered,
/// and their calls are refused with the reason).
pub const LEGAL: &[(Call, u16, u8)] = {
    use Call as C;
    const NEVER: u8 = 0;
    &[
        (C::SetDebugLogging, ANY, ME_ANY),
        (C::FreeInstance, ANY | Fatal as u16, ME_ANY),
        (
            C::EnterInitializationMode,
            mask(&[Instantiated]),
            me_mask(&[Is]),
        ),
        (
            C::ExitInitializationMode,
            mask(&[InitializationMode]),
            me_mask(&[In]),
        ),
        (C::EnterEventMode, STEP, me_mask(&[Ev, Ct])),
        (
            C::Terminate,
            STEP | EVENT_MODE | StepFailed as u16,
            me_mask(&[Ev, Ct]),
        ),
        (C::Reset, ANY, ME_ANY),
        (C::GetFloat32, READ, ME_READ),
        (C::GetFloat64, READ, ME_READ),
        (C::GetInt8, READ, ME_READ),
        (C::GetUInt8, READ, ME_READ),
        (C::GetInt16, READ, ME_READ),
        (C::GetUInt16, READ, ME_READ),
        (C::GetInt32, READ, ME_READ),
        (C::GetUInt32, READ, ME_READ),
        (C::GetInt64, READ, ME_READ),
        (C::GetUInt64, READ, ME_READ),
        (C::GetBoolean, READ, ME_READ),
        (C::GetString, READ, ME_READ),
        (C::GetBinary, READ, ME_READ),
        (C::GetClock, ANY, ME_ANY),
        (C::SetFloat32, SET, ME_SET),
        (C::SetFloat64, SET, ME_SET),
        (C::SetInt8, SET, ME_SET_DISCRETE),
        (C::SetUInt8, SET, ME_SET_DISCRETE),
        (C::SetInt16, SET, ME_SET_DISCRETE),
        (C::SetUInt16, SET, ME_SET_DISCRETE),
        (C::SetInt32, SET, ME_SET_DISCRETE),
        (C::SetUInt32, SET, ME_SET_DISCRETE),
        (C::SetInt64, SET, ME_SET_DISCRETE),
        (C::SetUInt64, SET, ME_SET_DISCRETE),
        (C::SetBoolean, SET, ME_SET_DISCRETE),
        (C::SetString, SET, ME_SET_DISCRETE),
        (C::SetBinary, SET, ME_SET_DISCRETE),
        (C::SetClock, ANY, ME_ANY),
        (C::GetNumberOfVariableDependencies, ANY, ME_ANY),
        (C::GetVariableDependencies, ANY, ME_ANY),
        (C::GetFMUState, ANY, ME_ANY),
        (C::SetFMUState, ANY, ME_ANY),
        (C::FreeFMUState, ANY, ME_ANY),
        (C::SerializedFMUStateSize, ANY, ME_ANY),
        (C::SerializeFMUState, ANY, ME_ANY),
        (C::DeserializeFMUState, ANY, ME_ANY),
        (
            C::GetDirectionalDerivative,
            mask(&[InitializationMode, StepComplete, Terminated]) | EVENT_MODE,
            me_mask(&[In, Ev, Ct, Te]),
        ),
        (
            C::GetAdjointDerivative,
            mask(&[InitializationMode, StepComplete, Terminated]) | EVENT_MODE,
            me_mask(&[In, Ev, Ct, Te]),
        ),
        (
            C::EnterConfigurationMode,
            mask(&[Instantiated, StepComplete]) | EVENT_MODE,
            me_mask(&[Is, Ev]),
        ),
        (C::ExitConfigurationMode, 0, NEVER),
        (C::GetIntervalDecimal, ANY, ME_ANY),
        (C::GetIntervalFraction, ANY, ME_ANY),
        (C::GetShiftDecimal, ANY, ME_ANY),
        (C::GetShiftFraction, ANY, ME_ANY),
        (C::SetIntervalDecimal, ANY, ME_ANY),
        (C::SetIntervalFraction, ANY, ME_ANY),
        (C::SetShiftDecimal, ANY, ME_ANY),
        (C::SetShiftFraction, ANY, ME_ANY),
        (C::EvaluateDiscreteStates, EVENT_MODE, me_mask(&[Ev])),
        (C::UpdateDiscreteStates, EVENT_MODE, me_mask(&[Ev])),
        (C::EnterContinuousTimeMode, 0, me_mask(&[Ev])),
        (C::CompletedIntegratorStep, 0, me_mask(&[Ct])),
        (C::SetTime, 0, me_mask(&[Ev, Ct])),
        (C::SetContinuousStates, 0, me_mask(&[Ct])),
        (
            C::GetContinuousStateDerivatives,
            0,
            me_mask(&[Ev, Ct, Te, Er]),
        ),
        (C::GetEventIndicators, 0, ME_READ),
        (C::GetContinuousStates, 0, ME_READ),
        (
            C::GetNominalsOfContinuousStates,
            0,
            me_mask(&[Is, Ev, Ct, Te, Er]),
        ),
        (C::GetNumberOfEventIndicators, 0, ME_ANY),
        (C::GetNumberOfContinuousStates, 0, ME_ANY),
        (C::EnterStepMode, EVENT_MODE, NEVER),
        (
            C::GetOutputDerivatives,
            STEP | mask(&[StepFailed, Terminated]),
            NEVER,
        ),
        (C::DoStep, STEP, NEVER),
        (C::ActivateModelPartition, 0, NEVER),
    ]
};

/// [`LEGAL`] indexed by the call, built at compile time.
const BY_CALL: [(u16, u8); LEGAL.len()] = {
    let mut t = [(0, 0); LEGAL.len()];
    let mut i = 0;
    while i < LEGAL.len() {
        t[LEGAL[i].0 as usize] = (LEGAL[i].1, LEGAL[i].2);
        i += 1;
    }
    t
};

/// Is `call` legal in the state with these bits ([`bits`])?
#[inline]
pub fn allowed_in(call: Call, bits: u16) -> bool {
    BY_CALL
        .get(call as usize)
        .is_some_and(|&(m, _)| m & bits != 0)
}

/// Is `call` legal in `state` of a Model Exchange instance?
#[inline]
pub fn me_allowed(call: Call, state: MeState) -> bool {
    BY_CALL
        .get(call as usize)
        .is_some_and(|&(_, m)| m & state as u8 != 0)
}

/// Is `call` legal in `state` of a Co-Simulation instance outside Event Mode?
pub fn allowed(call: Call, state: State) -> bool {
    allowed_in(call, state as u16)
}

/// The instance's state as a bit of [`LEGAL`]'s masks: the runtime's, or [`EVENT_MODE`].
#[inline]
pub fn bits<M: Model>(inst: &Instance<M>) -> u16 {
    if inst.event_mode_used
        && inst.state == StepComplete
        && inst.me.mode == crate::fmi2::runtime::me::Mode::Event
    {
        EVENT_MODE
    } else {
        inst.state as u16
    }
}

/// A Model Exchange state as FMI 3.0 names it.
pub fn me_name(state: MeState) -> &'static str {
    match state {
        Is => "Instantiated",
        In => "Initialization Mode",
        Ev => "Event Mode",
        Ct => "Continuous-Time Mode",
        Te => "Terminated",
        Er => "Error",
    }
}

/// A state as FMI 3.0 names it.
pub fn name(bits: u16) -> &'static str {
    match bits {
        EVENT_MODE => "Event Mode",
        b if b == Instantiated as u16 => "Instantiated",
        b if b == InitializationMode as u16 => "Initialization Mode",
        STEP => "Step Mode",
        b if b == StepFailed as u16 => "Step Discarded",
        b if b == Terminated as u16 => "Terminated",
        b if b == Error as u16 => "Error",
        b if b == Fatal as u16 => "Fatal",
        _ => "Step Canceled",
    }
}

impl Api for Call {
    const PREFIX: &'static str = "fmi3";
    #[inline]
    fn allowed_now<M: Model>(self, inst: &Instance<M>) -> bool {
        if inst.me.is_me {
            inst.me_state().is_some_and(|s| me_allowed(self, s))
        } else {
            allowed_in(self, bits(inst))
        }
    }
    #[inline(never)]
    fn refusal<M: Model>(self, inst: &Instance<M>) -> Option<String> {
        if inst.me.is_me {
            let state = inst.me_state();
            return (!state.is_some_and(|s| me_allowed(self, s))).then(|| {
                let cs_only = BY_CALL[self as usize].1 == 0;
                format!(
                    "fmi3{self:?} is not allowed in state {}{}",
                    state.map_or("?", me_name),
                    if cs_only {
                        " (a Co-Simulation function; this instance is Model Exchange)"
                    } else {
                        ""
                    }
                )
            });
        }
        let b = bits(inst);
        (!allowed_in(self, b)).then(|| {
            let why = match self {
                Call::ExitConfigurationMode => " (this FMU has no structural parameters)",
                Call::EnterEventMode | Call::EnterStepMode | Call::UpdateDiscreteStates
                    if !inst.event_mode_used =>
                {
                    " (eventModeUsed was false at instantiation: never in Event Mode)"
                }
                Call::ActivateModelPartition => " (a Scheduled Execution function)",
                c if BY_CALL[c as usize].0 == 0 => {
                    " (a Model Exchange function; this instance is Co-Simulation)"
                }
                _ => "",
            };
            format!("fmi3{self:?} is not allowed in state {}{why}", name(b))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi2::state::ALL_STATES;

    #[test]
    fn every_call_has_one_entry_in_its_place() {
        for (i, (c, _, _)) in LEGAL.iter().enumerate() {
            assert_eq!(*c as usize, i, "{c:?} out of order");
        }
        assert_eq!(LEGAL.len(), Call::ActivateModelPartition as usize + 1);
    }

    #[test]
    fn representative_rules() {
        assert!(allowed(Call::DoStep, StepComplete));
        assert!(!allowed(Call::DoStep, StepFailed));
        assert!(!allowed(Call::DoStep, InitializationMode));
        assert!(allowed(Call::Terminate, StepFailed));
        assert!(!allowed(Call::GetFloat64, Instantiated));
        assert!(allowed(Call::SetFloat64, Instantiated));
        assert!(!allowed(Call::SetFloat64, StepFailed));
        assert!(allowed(Call::FreeInstance, Fatal));
        assert!(!allowed(Call::Reset, Fatal));
        for s in ALL_STATES {
            assert!(!allowed(Call::SetTime, s), "{s:?}");
            assert!(!allowed(Call::EnterStepMode, s), "{s:?}");
        }
        assert!(allowed_in(Call::EnterStepMode, EVENT_MODE));
        assert!(allowed_in(Call::UpdateDiscreteStates, EVENT_MODE));
        assert!(!allowed_in(Call::DoStep, EVENT_MODE));
        assert!(allowed_in(Call::GetFloat64, EVENT_MODE));
        assert!(allowed_in(Call::Terminate, EVENT_MODE));
    }
}
