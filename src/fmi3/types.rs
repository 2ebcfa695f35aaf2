//! The FMI 3.0 C types (`fmi3PlatformTypes.h`, `fmi3FunctionTypes.h`) the runtime takes, written
//! by hand. An instance, its FMU state and its status are those of the FMI 2.0 runtime it
//! shares ([`crate::fmi2::types`]): `fmi3Status` has the same values as `fmi2Status`.

use std::ffi::{c_char, c_void};

pub use crate::fmi2::types::{Component as Instance, FMUstate as FMUState, Status};

pub type InstanceEnvironment = *mut c_void;
pub type ValueReference = u32;
pub type Float32 = f32;
pub type Float64 = f64;
pub type Int8 = i8;
pub type UInt8 = u8;
pub type Int16 = i16;
pub type UInt16 = u16;
pub type Int32 = i32;
pub type UInt32 = u32;
pub type Int64 = i64;
pub type UInt64 = u64;
/// `fmi3Boolean` is C's `bool`: one byte. Taken as a byte, so that a host's byte other than 0
/// or 1 is read as true rather than being undefined behaviour.
pub type Boolean = u8;
pub type FmiString = *const c_char;
pub type Byte = u8;
pub type Binary = *const u8;
/// `fmi3Clock` is C's `bool`, taken as a byte as [`Boolean`].
pub type Clock = u8;
/// `fmi3IntervalQualifier` (an enum: a C `int`).
pub type IntervalQualifier = std::ffi::c_int;
/// `fmi3DependencyKind` (an enum: a C `int`).
pub type DependencyKind = std::ffi::c_int;

pub const TRUE: Boolean = 1;
pub const FALSE: Boolean = 0;

/// `fmi3LogMessageCallback`.
pub use crate::fmi2::types::LogMessage3 as LogMessageCallback;

/// `fmi3IntermediateUpdateCallback` (the FMU never calls it: `providesIntermediateUpdate` is
/// false).
pub type IntermediateUpdateCallback = Option<
    unsafe extern "C" fn(
        InstanceEnvironment,
        Float64,
        Boolean,
        Boolean,
        Boolean,
        Boolean,
        *mut Boolean,
        *mut Float64,
    ),
>;
/// `fmi3ClockUpdateCallback` (Scheduled Execution, not offered).
pub type ClockUpdateCallback = Option<unsafe extern "C" fn(InstanceEnvironment)>;
/// `fmi3LockPreemptionCallback` and `fmi3UnlockPreemptionCallback` (Scheduled Execution).
pub type PreemptionCallback = Option<unsafe extern "C" fn()>;

/// `fmi3Version`.
pub const VERSION: &std::ffi::CStr = c"3.0";
