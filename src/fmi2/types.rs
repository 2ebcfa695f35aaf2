//! The FMI 2.0 C types (`fmi2TypesPlatform.h`, `fmi2FunctionTypes.h`), written by hand.

use std::ffi::{c_char, c_int, c_uint, c_void};

pub type Component = *mut c_void;
pub type ComponentEnvironment = *mut c_void;
pub type FMUstate = *mut c_void;
pub type ValueReference = c_uint;
pub type Real = f64;
pub type Integer = c_int;
pub type Boolean = c_int;
pub type Char = c_char;
pub type FmiString = *const c_char;
pub type Byte = c_char;

pub const TRUE: Boolean = 1;
pub const FALSE: Boolean = 0;

/// `fmi2Status`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
    Pending = 5,
}

/// `fmi2Type`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FmuType {
    ModelExchange = 0,
    CoSimulation = 1,
}

impl FmuType {
    /// The `fmi2Type` a C host passed as an `int`; `None` for a value that is none (such a value
    /// must never be read as this enum: that would be undefined behaviour).
    pub fn from_c(v: c_int) -> Option<FmuType> {
        match v {
            0 => Some(FmuType::ModelExchange),
            1 => Some(FmuType::CoSimulation),
            _ => None,
        }
    }
}

/// `fmi2StatusKind` (the runtime takes it as a C `int`: a host may pass any value).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StatusKind {
    DoStepStatus = 0,
    PendingStatus = 1,
    LastSuccessfulTime = 2,
    Terminated = 3,
}

/// `fmi2CallbackLogger`: variadic; the message is a printf format, so `%` is escaped.
pub type CallbackLogger = Option<
    unsafe extern "C" fn(ComponentEnvironment, FmiString, Status, FmiString, FmiString, ...),
>;
/// `fmi3LogMessageCallback` (FMI 3.0: not variadic, no instance name), for the instances
/// FMI 3.0 creates over the same runtime (`crate::fmi3`).
pub type LogMessage3 =
    Option<unsafe extern "C" fn(ComponentEnvironment, Status, FmiString, FmiString)>;
pub type CallbackAllocateMemory = Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>;
pub type CallbackFreeMemory = Option<unsafe extern "C" fn(*mut c_void)>;
pub type StepFinished = Option<unsafe extern "C" fn(ComponentEnvironment, Status)>;

/// `fmi2CallbackFunctions`.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct CallbackFunctions {
    pub logger: CallbackLogger,
    pub allocate_memory: CallbackAllocateMemory,
    pub free_memory: CallbackFreeMemory,
    pub step_finished: StepFinished,
    pub component_environment: ComponentEnvironment,
}

/// `fmi2EventInfo` (Model Exchange).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct EventInfo {
    pub new_discrete_states_needed: Boolean,
    pub terminate_simulation: Boolean,
    pub nominals_of_continuous_states_changed: Boolean,
    pub values_of_continuous_states_changed: Boolean,
    pub next_event_time_defined: Boolean,
    pub next_event_time: Real,
}

/// `fmi2TypesPlatform`.
pub const TYPES_PLATFORM: &std::ffi::CStr = c"default";
/// `fmi2Version`.
pub const VERSION: &std::ffi::CStr = c"2.0";
