//! The FMI 2.0 co-simulation state machine, as a declarative table of which call is legal in
//! which state (FMI 2.0 standard, section 4.2.4, and the "MASK_" table of the Reference FMUs).

/// States of a co-simulation slave. Each is one bit, so a set of states is a mask.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u16)]
pub enum State {
    Instantiated = 1 << 0,
    InitializationMode = 1 << 1,
    StepComplete = 1 << 2,
    StepFailed = 1 << 3,
    StepCanceled = 1 << 4,
    Terminated = 1 << 5,
    Error = 1 << 6,
    Fatal = 1 << 7,
}

impl State {
    /// Stable number for serialized states.
    pub fn code(self) -> u16 {
        self as u16
    }
    /// Inverse of [`State::code`].
    pub fn from_code(c: u16) -> Option<State> {
        ALL_STATES.iter().copied().find(|s| s.code() == c)
    }
}

const ALL_STATES: [State; 8] = [
    State::Instantiated,
    State::InitializationMode,
    State::StepComplete,
    State::StepFailed,
    State::StepCanceled,
    State::Terminated,
    State::Error,
    State::Fatal,
];

use State::*;

const fn mask(states: &[State]) -> u16 {
    let mut m = 0;
    let mut i = 0;
    while i < states.len() {
        m |= states[i] as u16;
        i += 1;
    }
    m
}

/// Every state an instance can be in (for calls legal anywhere but Fatal).
const ANY: u16 = mask(&[
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    StepCanceled,
    Terminated,
    Error,
]);
const AFTER_INIT_STARTED: u16 = mask(&[
    InitializationMode,
    StepComplete,
    StepFailed,
    StepCanceled,
    Terminated,
    Error,
]);

/// Every FMI 2.0 common and co-simulation function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Call {
    SetDebugLogging,
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    FreeInstance,
    GetReal,
    GetInteger,
    GetBoolean,
    GetString,
    SetReal,
    SetInteger,
    SetBoolean,
    SetString,
    GetFMUstate,
    SetFMUstate,
    FreeFMUstate,
    SerializedFMUstateSize,
    SerializeFMUstate,
    DeSerializeFMUstate,
    GetDirectionalDerivative,
    SetRealInputDerivatives,
    GetRealOutputDerivatives,
    DoStep,
    CancelStep,
    GetStatus,
    GetRealStatus,
    GetIntegerStatus,
    GetBooleanStatus,
    GetStringStatus,
    // Model Exchange (its event and continuous-time modes run in the state StepComplete; the
    // runtime's `me` module tells them apart)
    EnterEventMode,
    NewDiscreteStates,
    EnterContinuousTimeMode,
    CompletedIntegratorStep,
    SetTime,
    SetContinuousStates,
    GetDerivatives,
    GetEventIndicators,
    GetContinuousStates,
    GetNominalsOfContinuousStates,
}

/// The table: in which states each call is legal.
pub const LEGAL: &[(Call, u16)] = &[
    (Call::SetDebugLogging, ANY),
    (Call::SetupExperiment, mask(&[Instantiated])),
    (Call::EnterInitializationMode, mask(&[Instantiated])),
    (Call::ExitInitializationMode, mask(&[InitializationMode])),
    (Call::Terminate, mask(&[StepComplete, StepFailed])),
    (Call::Reset, ANY),
    (Call::FreeInstance, ANY | Fatal as u16),
    (Call::GetReal, AFTER_INIT_STARTED),
    (Call::GetInteger, AFTER_INIT_STARTED),
    (Call::GetBoolean, AFTER_INIT_STARTED),
    (Call::GetString, AFTER_INIT_STARTED),
    (
        Call::SetReal,
        mask(&[Instantiated, InitializationMode, StepComplete]),
    ),
    (
        Call::SetInteger,
        mask(&[Instantiated, InitializationMode, StepComplete]),
    ),
    (
        Call::SetBoolean,
        mask(&[Instantiated, InitializationMode, StepComplete]),
    ),
    (
        Call::SetString,
        mask(&[Instantiated, InitializationMode, StepComplete]),
    ),
    (Call::GetFMUstate, ANY),
    (Call::SetFMUstate, ANY),
    (Call::FreeFMUstate, ANY),
    (Call::SerializedFMUstateSize, ANY),
    (Call::SerializeFMUstate, ANY),
    (Call::DeSerializeFMUstate, ANY),
    (Call::GetDirectionalDerivative, AFTER_INIT_STARTED),
    (
        Call::SetRealInputDerivatives,
        mask(&[Instantiated, InitializationMode, StepComplete]),
    ),
    (
        Call::GetRealOutputDerivatives,
        mask(&[StepComplete, StepFailed, StepCanceled, Terminated, Error]),
    ),
    (Call::DoStep, mask(&[StepComplete])),
    (Call::CancelStep, 0),
    (
        Call::GetStatus,
        mask(&[StepComplete, StepFailed, StepCanceled, Terminated]),
    ),
    (
        Call::GetRealStatus,
        mask(&[StepComplete, StepFailed, StepCanceled, Terminated]),
    ),
    (
        Call::GetIntegerStatus,
        mask(&[StepComplete, StepFailed, StepCanceled, Terminated]),
    ),
    (
        Call::GetBooleanStatus,
        mask(&[StepComplete, StepFailed, StepCanceled, Terminated]),
    ),
    (
        Call::GetStringStatus,
        mask(&[StepComplete, StepFailed, StepCanceled, Terminated]),
    ),
    (Call::EnterEventMode, mask(&[StepComplete])),
    (Call::NewDiscreteStates, mask(&[StepComplete])),
    (Call::EnterContinuousTimeMode, mask(&[StepComplete])),
    (Call::CompletedIntegratorStep, mask(&[StepComplete])),
    (Call::SetTime, mask(&[StepComplete])),
    (Call::SetContinuousStates, mask(&[StepComplete])),
    (
        Call::GetDerivatives,
        mask(&[InitializationMode, StepComplete, Terminated, Error]),
    ),
    (
        Call::GetEventIndicators,
        mask(&[InitializationMode, StepComplete, Terminated, Error]),
    ),
    (
        Call::GetContinuousStates,
        mask(&[InitializationMode, StepComplete, Terminated, Error]),
    ),
    (
        Call::GetNominalsOfContinuousStates,
        mask(&[InitializationMode, StepComplete, Terminated, Error]),
    ),
];

/// [`LEGAL`] indexed by the call, built at compile time: a call's check is one load and a mask.
const BY_CALL: [u16; LEGAL.len()] = {
    let mut t = [0u16; LEGAL.len()];
    let mut i = 0;
    while i < LEGAL.len() {
        t[LEGAL[i].0 as usize] = LEGAL[i].1;
        i += 1;
    }
    t
};

/// Is `call` legal in `state`?
#[inline]
pub fn allowed(call: Call, state: State) -> bool {
    BY_CALL
        .get(call as usize)
        .is_some_and(|m| m & state as u16 != 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_call_has_one_entry() {
        for (i, (c, _)) in LEGAL.iter().enumerate() {
            assert_eq!(
                LEGAL.iter().filter(|(d, _)| d == c).count(),
                1,
                "{c:?} at {i}"
            );
        }
        assert_eq!(LEGAL.len(), 41);
        // the indexed copy holds the same rules
        for (c, m) in LEGAL {
            for s in ALL_STATES {
                assert_eq!(allowed(*c, s), m & s as u16 != 0, "{c:?} in {s:?}");
            }
        }
    }

    #[test]
    fn representative_rules() {
        assert!(allowed(Call::DoStep, StepComplete));
        assert!(!allowed(Call::DoStep, Instantiated));
        assert!(!allowed(Call::DoStep, InitializationMode));
        assert!(!allowed(Call::GetReal, Instantiated));
        assert!(allowed(Call::GetReal, Error));
        assert!(!allowed(Call::SetupExperiment, StepComplete));
        assert!(allowed(Call::FreeInstance, Fatal));
        assert!(!allowed(Call::Reset, Fatal));
        for s in ALL_STATES {
            assert_eq!(State::from_code(s.code()), Some(s));
        }
    }
}
