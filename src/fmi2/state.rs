//! The FMI 2.0 co-simulation state machine, as a declarative table of which call is legal in
//! which state (FMI 2.0 standard, section 4.2.4, and the "MASK_" table of the Reference FMUs).

/// A set of states of one bit each (so a set of them is a mask): the enum, the array of
/// all its states (`$all`) and the `const fn` (`$mask`) that makes a mask of some.
macro_rules! bit_states {
    (
        $(#[$doc:meta])*
        $vis:vis enum $name:ident: $repr:ident { $($state:ident = $bit:expr,)* }
        $(#[$all_doc:meta])*
        $all_vis:vis const $all:ident;
        fn $mask:ident;
    ) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        #[repr($repr)]
        $vis enum $name {
            $($state = $bit,)*
        }

        $(#[$all_doc])*
        $all_vis const $all: [$name; [$($name::$state),*].len()] = [$($name::$state),*];

        /// The mask of `states`.
        const fn $mask(states: &[$name]) -> $repr {
            let mut m = 0;
            let mut i = 0;
            while i < states.len() {
                m |= states[i] as $repr;
                i += 1;
            }
            m
        }
    };
}

bit_states! {
    /// States of a co-simulation slave. Each is one bit, so a set of states is a mask.
    pub enum State: u16 {
        Instantiated = 1 << 0,
        InitializationMode = 1 << 1,
        StepComplete = 1 << 2,
        StepFailed = 1 << 3,
        StepCanceled = 1 << 4,
        Terminated = 1 << 5,
        Error = 1 << 6,
        Fatal = 1 << 7,
    }
    const ALL_STATES;
    fn mask;
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

use State::*;

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
    // Model Exchange (legal per ME_LEGAL; its event and continuous-time modes run in the state
    // StepComplete, told apart by the runtime's `me` module)
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
    // Model Exchange calls: never on a Co-Simulation instance (their table is ME_LEGAL)
    (Call::EnterEventMode, 0),
    (Call::NewDiscreteStates, 0),
    (Call::EnterContinuousTimeMode, 0),
    (Call::CompletedIntegratorStep, 0),
    (Call::SetTime, 0),
    (Call::SetContinuousStates, 0),
    (Call::GetDerivatives, 0),
    (Call::GetEventIndicators, 0),
    (Call::GetContinuousStates, 0),
    (Call::GetNominalsOfContinuousStates, 0),
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

/// Is `call` legal in `state` of a Co-Simulation instance? (Model Exchange calls never are.)
#[inline]
pub fn allowed(call: Call, state: State) -> bool {
    BY_CALL
        .get(call as usize)
        .is_some_and(|m| m & state as u16 != 0)
}

impl Call {
    /// A function of the Model Exchange interface only.
    pub fn is_model_exchange(self) -> bool {
        matches!(
            self,
            Call::EnterEventMode
                | Call::NewDiscreteStates
                | Call::EnterContinuousTimeMode
                | Call::CompletedIntegratorStep
                | Call::SetTime
                | Call::SetContinuousStates
                | Call::GetDerivatives
                | Call::GetEventIndicators
                | Call::GetContinuousStates
                | Call::GetNominalsOfContinuousStates
        )
    }

    /// A function of the Co-Simulation interface only.
    pub fn is_co_simulation(self) -> bool {
        matches!(
            self,
            Call::SetRealInputDerivatives
                | Call::GetRealOutputDerivatives
                | Call::DoStep
                | Call::CancelStep
                | Call::GetStatus
                | Call::GetRealStatus
                | Call::GetIntegerStatus
                | Call::GetBooleanStatus
                | Call::GetStringStatus
        )
    }
}

bit_states! {
    /// States of a Model Exchange instance (FMI 2.0 standard, section 3.2.3). The runtime keeps
    /// one state variable for both interfaces: an initialized Model Exchange instance is in
    /// [`State::StepComplete`] with its mode (event or continuous-time) beside it.
    pub enum MeState: u8 {
        Instantiated = 1 << 0,
        InitializationMode = 1 << 1,
        EventMode = 1 << 2,
        ContinuousTimeMode = 1 << 3,
        Terminated = 1 << 4,
        Error = 1 << 5,
    }
    /// Every Model Exchange state, for tests that walk them all.
    pub const ME_STATES;
    fn me_mask;
}

/// The Model Exchange table: in which states each call is legal (FMI 2.0 section 3.2.3, as
/// the Reference FMUs' `MASK_` table). Co-Simulation calls are legal in none.
pub const ME_LEGAL: &[(Call, u8)] = {
    use MeState::{
        ContinuousTimeMode as Ct, Error as Er, EventMode as Ev, InitializationMode as In,
        Instantiated as Is, Terminated as Te,
    };
    const ALL: u8 = me_mask(&[Is, In, Ev, Ct, Te, Er]);
    const READ: u8 = me_mask(&[In, Ev, Ct, Te, Er]);
    &[
        (Call::SetDebugLogging, ALL),
        (Call::SetupExperiment, me_mask(&[Is])),
        (Call::EnterInitializationMode, me_mask(&[Is])),
        (Call::ExitInitializationMode, me_mask(&[In])),
        (Call::Terminate, me_mask(&[Ev, Ct])),
        (Call::Reset, ALL),
        (Call::FreeInstance, ALL),
        (Call::GetReal, READ),
        (Call::GetInteger, READ),
        (Call::GetBoolean, READ),
        (Call::GetString, READ),
        (Call::SetReal, me_mask(&[Is, In, Ev, Ct])),
        (Call::SetInteger, me_mask(&[Is, In, Ev])),
        (Call::SetBoolean, me_mask(&[Is, In, Ev])),
        (Call::SetString, me_mask(&[Is, In, Ev])),
        (Call::GetFMUstate, ALL),
        (Call::SetFMUstate, ALL),
        (Call::FreeFMUstate, ALL),
        (Call::SerializedFMUstateSize, ALL),
        (Call::SerializeFMUstate, ALL),
        (Call::DeSerializeFMUstate, ALL),
        (Call::GetDirectionalDerivative, READ),
        (Call::EnterEventMode, me_mask(&[Ev, Ct])),
        (Call::NewDiscreteStates, me_mask(&[Ev])),
        (Call::EnterContinuousTimeMode, me_mask(&[Ev])),
        (Call::CompletedIntegratorStep, me_mask(&[Ct])),
        (Call::SetTime, me_mask(&[Ev, Ct])),
        (Call::SetContinuousStates, me_mask(&[Ct])),
        (Call::GetEventIndicators, READ),
        (Call::GetContinuousStates, READ),
        (Call::GetDerivatives, me_mask(&[Ev, Ct, Te, Er])),
        (
            Call::GetNominalsOfContinuousStates,
            me_mask(&[Is, Ev, Ct, Te, Er]),
        ),
    ]
};

/// Is `call` legal in `state` of a Model Exchange instance?
pub fn me_allowed(call: Call, state: MeState) -> bool {
    ME_LEGAL
        .iter()
        .find(|(c, _)| *c == call)
        .is_some_and(|(_, m)| m & state as u8 != 0)
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
    fn model_exchange_table_covers_every_call_but_co_simulation() {
        for (c, _) in LEGAL {
            let n = ME_LEGAL.iter().filter(|(d, _)| d == c).count();
            assert_eq!(n, usize::from(!c.is_co_simulation()), "{c:?}");
            if c.is_co_simulation() {
                assert!(ME_STATES.iter().all(|&s| !me_allowed(*c, s)));
            }
            if c.is_model_exchange() {
                assert!(
                    [
                        Instantiated,
                        InitializationMode,
                        StepComplete,
                        Terminated,
                        Error
                    ]
                    .iter()
                    .all(|&s| !allowed(*c, s)),
                    "{c:?} on a Co-Simulation instance"
                );
            }
        }
        assert!(me_allowed(Call::SetReal, MeState::ContinuousTimeMode));
        assert!(!me_allowed(Call::SetInteger, MeState::ContinuousTimeMode));
        assert!(!me_allowed(Call::SetContinuousStates, MeState::EventMode));
        assert!(!me_allowed(
            Call::GetDerivatives,
            MeState::InitializationMode
        ));
        assert!(me_allowed(
            Call::GetNominalsOfContinuousStates,
            MeState::Instantiated
        ));
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
