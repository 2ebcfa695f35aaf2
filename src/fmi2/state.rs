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
        pub const fn $mask(states: &[$name]) -> $repr {
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
    pub const ALL_STATES;
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
/// Where a value may be set (and an input derivative).
const SETTABLE: u16 = mask(&[Instantiated, InitializationMode, StepComplete]);
/// Where a step has been taken: its status can be asked.
const STEPPED: u16 = mask(&[StepComplete, StepFailed, StepCanceled, Terminated]);

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
    // Model Exchange (its event and continuous-time modes run in the state StepComplete, told
    // apart by the runtime's `me` module)
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

/// To which interface a call belongs, and in which of its states it is legal (as masks).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Legal {
    /// A function of both interfaces: legal in these Co-Simulation and these Model Exchange
    /// states.
    Both(u16, u8),
    /// A Co-Simulation function: legal in these states, never on a Model Exchange instance.
    Cs(u16),
    /// A Model Exchange function: legal in these states, never on a Co-Simulation instance.
    Me(u8),
}

impl Legal {
    /// The Co-Simulation mask and the Model Exchange mask.
    pub const fn masks(self) -> (u16, u8) {
        match self {
            Legal::Both(cs, me) => (cs, me),
            Legal::Cs(cs) => (cs, 0),
            Legal::Me(me) => (0, me),
        }
    }
}

/// The table: in which states of each interface each call is legal: Co-Simulation (FMI 2.0
/// section 4.2.4) and Model Exchange (section 3.2.3), as the Reference FMUs' `MASK_` tables.
pub const LEGAL: &[(Call, Legal)] = {
    use Legal::{Both, Cs, Me};
    use MeState::{
        ContinuousTimeMode as Ct, Error as Er, EventMode as Ev, InitializationMode as In,
        Instantiated as Is, Terminated as Te,
    };
    const ME_ANY: u8 = me_mask(&[Is, In, Ev, Ct, Te, Er]);
    const ME_READ: u8 = me_mask(&[In, Ev, Ct, Te, Er]);
    &[
        (Call::SetDebugLogging, Both(ANY, ME_ANY)),
        (
            Call::SetupExperiment,
            Both(mask(&[Instantiated]), me_mask(&[Is])),
        ),
        (
            Call::EnterInitializationMode,
            Both(mask(&[Instantiated]), me_mask(&[Is])),
        ),
        (
            Call::ExitInitializationMode,
            Both(mask(&[InitializationMode]), me_mask(&[In])),
        ),
        (
            Call::Terminate,
            Both(mask(&[StepComplete, StepFailed]), me_mask(&[Ev, Ct])),
        ),
        (Call::Reset, Both(ANY, ME_ANY)),
        (Call::FreeInstance, Both(ANY | Fatal as u16, ME_ANY)),
        (Call::GetReal, Both(AFTER_INIT_STARTED, ME_READ)),
        (Call::GetInteger, Both(AFTER_INIT_STARTED, ME_READ)),
        (Call::GetBoolean, Both(AFTER_INIT_STARTED, ME_READ)),
        (Call::GetString, Both(AFTER_INIT_STARTED, ME_READ)),
        (Call::SetReal, Both(SETTABLE, me_mask(&[Is, In, Ev, Ct]))),
        (Call::SetInteger, Both(SETTABLE, me_mask(&[Is, In, Ev]))),
        (Call::SetBoolean, Both(SETTABLE, me_mask(&[Is, In, Ev]))),
        (Call::SetString, Both(SETTABLE, me_mask(&[Is, In, Ev]))),
        (Call::GetFMUstate, Both(ANY, ME_ANY)),
        (Call::SetFMUstate, Both(ANY, ME_ANY)),
        (Call::FreeFMUstate, Both(ANY, ME_ANY)),
        (Call::SerializedFMUstateSize, Both(ANY, ME_ANY)),
        (Call::SerializeFMUstate, Both(ANY, ME_ANY)),
        (Call::DeSerializeFMUstate, Both(ANY, ME_ANY)),
        (
            Call::GetDirectionalDerivative,
            Both(AFTER_INIT_STARTED, ME_READ),
        ),
        (Call::SetRealInputDerivatives, Cs(SETTABLE)),
        (Call::GetRealOutputDerivatives, Cs(STEPPED | Error as u16)),
        (Call::DoStep, Cs(mask(&[StepComplete]))),
        (Call::CancelStep, Cs(0)),
        (Call::GetStatus, Cs(STEPPED)),
        (Call::GetRealStatus, Cs(STEPPED)),
        (Call::GetIntegerStatus, Cs(STEPPED)),
        (Call::GetBooleanStatus, Cs(STEPPED)),
        (Call::GetStringStatus, Cs(STEPPED)),
        (Call::EnterEventMode, Me(me_mask(&[Ev, Ct]))),
        (Call::NewDiscreteStates, Me(me_mask(&[Ev]))),
        (Call::EnterContinuousTimeMode, Me(me_mask(&[Ev]))),
        (Call::CompletedIntegratorStep, Me(me_mask(&[Ct]))),
        (Call::SetTime, Me(me_mask(&[Ev, Ct]))),
        (Call::SetContinuousStates, Me(me_mask(&[Ct]))),
        (Call::GetDerivatives, Me(me_mask(&[Ev, Ct, Te, Er]))),
        (Call::GetEventIndicators, Me(ME_READ)),
        (Call::GetContinuousStates, Me(ME_READ)),
        (
            Call::GetNominalsOfContinuousStates,
            Me(me_mask(&[Is, Ev, Ct, Te, Er])),
        ),
    ]
};

/// [`LEGAL`] indexed by the call, built at compile time: a call's check is one load and a mask.
const BY_CALL: [(u16, u8); LEGAL.len()] = {
    let mut t = [(0, 0); LEGAL.len()];
    let mut i = 0;
    while i < LEGAL.len() {
        t[LEGAL[i].0 as usize] = LEGAL[i].1.masks();
        i += 1;
    }
    t
};

/// Is `call` legal in `state` of a Co-Simulation instance? (Model Exchange calls never are.)
#[inline]
pub fn allowed(call: Call, state: State) -> bool {
    BY_CALL
        .get(call as usize)
        .is_some_and(|&(cs, _)| cs & state as u16 != 0)
}

/// Is `call` legal in `state` of a Model Exchange instance? (Co-Simulation calls never are.)
pub fn me_allowed(call: Call, state: MeState) -> bool {
    BY_CALL
        .get(call as usize)
        .is_some_and(|&(_, me)| me & state as u8 != 0)
}

impl Call {
    /// The call's row of [`LEGAL`].
    fn legal(self) -> Option<Legal> {
        LEGAL.iter().find(|(c, _)| *c == self).map(|&(_, l)| l)
    }

    /// A function of the Model Exchange interface only.
    pub fn is_model_exchange(self) -> bool {
        matches!(self.legal(), Some(Legal::Me(_)))
    }

    /// A function of the Co-Simulation interface only.
    pub fn is_co_simulation(self) -> bool {
        matches!(self.legal(), Some(Legal::Cs(_)))
    }
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
        for (c, l) in LEGAL {
            let (cs, me) = l.masks();
            for s in ALL_STATES {
                assert_eq!(allowed(*c, s), cs & s as u16 != 0, "{c:?} in {s:?}");
            }
            for s in ME_STATES {
                assert_eq!(me_allowed(*c, s), me & s as u8 != 0, "{c:?} in {s:?}");
            }
        }
    }

    #[test]
    fn each_interface_refuses_the_other_ones_calls() {
        let count = |f: fn(Call) -> bool| LEGAL.iter().filter(|(c, _)| f(*c)).count();
        assert_eq!(count(Call::is_model_exchange), 10);
        assert_eq!(count(Call::is_co_simulation), 9);
        for (c, _) in LEGAL {
            if c.is_co_simulation() {
                assert!(ME_STATES.iter().all(|&s| !me_allowed(*c, s)));
            }
            if c.is_model_exchange() {
                assert!(
                    ALL_STATES.iter().all(|&s| !allowed(*c, s)),
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
