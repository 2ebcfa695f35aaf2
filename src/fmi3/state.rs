//! The FMI 3.0 state machine as a declarative table of which call is legal in which state (FMI
//! 3.0 standard, sections 3.2.2 and 4.2.2; the `MASK_` table of the Reference FMUs). An FMI 3.0
//! instance lives in the states of the shared runtime ([`crate::fmi2::state::State`]), named
//! the FMI 3.0 way in messages: `StepComplete` is Step Mode, `StepFailed` Step Discarded.

use crate::fmi2::runtime::{Api, Instance};
use crate::fmi2::state::State::{self, *};
use crate::model::Model;

/// The mask of some states.
const fn mask(states: &[State]) -> u16 {
    let mut m = 0;
    let mut i = 0;
    while i < states.len() {
        m |= states[i] as u16;
        i += 1;
    }
    m
}

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

/// Every state but Fatal.
const ANY: u16 = mask(&[
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
]) | EVENT_MODE;
/// Where values can be read: from initialization on (and in Error, for diagnosis).
const READ: u16 = mask(&[
    InitializationMode,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
]) | EVENT_MODE;
/// Where values can be set.
const SET: u16 = mask(&[Instantiated, InitializationMode, StepComplete, Terminated]) | EVENT_MODE;

/// In which states of a Co-Simulation instance each call is legal (0: never, on this FMU's
/// Co-Simulation interface: Model Exchange, configuration and clocks are not offered, and their
/// calls are refused with the reason).
pub const LEGAL: &[(Call, u16)] = {
    use Call as C;
    &[
        (C::SetDebugLogging, ANY),
        (C::FreeInstance, ANY | Fatal as u16),
        (C::EnterInitializationMode, mask(&[Instantiated])),
        (C::ExitInitializationMode, mask(&[InitializationMode])),
        (C::EnterEventMode, STEP),
        (C::Terminate, STEP | EVENT_MODE | StepFailed as u16),
        (C::Reset, ANY),
        (C::GetFloat32, READ),
        (C::GetFloat64, READ),
        (C::GetInt8, READ),
        (C::GetUInt8, READ),
        (C::GetInt16, READ),
        (C::GetUInt16, READ),
        (C::GetInt32, READ),
        (C::GetUInt32, READ),
        (C::GetInt64, READ),
        (C::GetUInt64, READ),
        (C::GetBoolean, READ),
        (C::GetString, READ),
        (C::GetBinary, READ),
        (C::GetClock, ANY),
        (C::SetFloat32, SET),
        (C::SetFloat64, SET),
        (C::SetInt8, SET),
        (C::SetUInt8, SET),
        (C::SetInt16, SET),
        (C::SetUInt16, SET),
        (C::SetInt32, SET),
        (C::SetUInt32, SET),
        (C::SetInt64, SET),
        (C::SetUInt64, SET),
        (C::SetBoolean, SET),
        (C::SetString, SET),
        (C::SetBinary, SET),
        (C::SetClock, ANY),
        (C::GetNumberOfVariableDependencies, ANY),
        (C::GetVariableDependencies, ANY),
        (C::GetFMUState, ANY),
        (C::SetFMUState, ANY),
        (C::FreeFMUState, ANY),
        (C::SerializedFMUStateSize, ANY),
        (C::SerializeFMUState, ANY),
        (C::DeserializeFMUState, ANY),
        (
            C::GetDirectionalDerivative,
            mask(&[InitializationMode, StepComplete, Terminated]) | EVENT_MODE,
        ),
        (
            C::GetAdjointDerivative,
            mask(&[InitializationMode, StepComplete, Terminated]) | EVENT_MODE,
        ),
        (
            C::EnterConfigurationMode,
            mask(&[Instantiated, StepComplete]) | EVENT_MODE,
        ),
        (C::ExitConfigurationMode, 0),
        (C::GetIntervalDecimal, ANY),
        (C::GetIntervalFraction, ANY),
        (C::GetShiftDecimal, ANY),
        (C::GetShiftFraction, ANY),
        (C::SetIntervalDecimal, ANY),
        (C::SetIntervalFraction, ANY),
        (C::SetShiftDecimal, ANY),
        (C::SetShiftFraction, ANY),
        (C::EvaluateDiscreteStates, EVENT_MODE),
        (C::UpdateDiscreteStates, EVENT_MODE),
        (C::EnterContinuousTimeMode, 0),
        (C::CompletedIntegratorStep, 0),
        (C::SetTime, 0),
        (C::SetContinuousStates, 0),
        (C::GetContinuousStateDerivatives, 0),
        (C::GetEventIndicators, 0),
        (C::GetContinuousStates, 0),
        (C::GetNominalsOfContinuousStates, 0),
        (C::GetNumberOfEventIndicators, 0),
        (C::GetNumberOfContinuousStates, 0),
        (C::EnterStepMode, EVENT_MODE),
        (
            C::GetOutputDerivatives,
            STEP | mask(&[StepFailed, Terminated]),
        ),
        (C::DoStep, STEP),
        (C::ActivateModelPartition, 0),
    ]
};

/// [`LEGAL`] indexed by the call, built at compile time.
const BY_CALL: [u16; LEGAL.len()] = {
    let mut t = [0; LEGAL.len()];
    let mut i = 0;
    while i < LEGAL.len() {
        t[LEGAL[i].0 as usize] = LEGAL[i].1;
        i += 1;
    }
    t
};

/// Is `call` legal in the state with these bits ([`bits`])?
#[inline]
pub fn allowed_in(call: Call, bits: u16) -> bool {
    BY_CALL.get(call as usize).is_some_and(|&m| m & bits != 0)
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
        allowed_in(self, bits(inst))
    }
    #[inline(never)]
    fn refusal<M: Model>(self, inst: &Instance<M>) -> Option<String> {
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
                c if BY_CALL[c as usize] == 0 => {
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
        for (i, (c, _)) in LEGAL.iter().enumerate() {
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
