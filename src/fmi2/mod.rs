//! The FMI 2.0 C ABI: hand-written C types, the state machine table, the generic runtime and
//! the [`crate::export_fmu!`] macro that makes a cdylib export one model. Nothing here knows a
//! mechanism.
pub mod runtime;
pub mod state;
pub mod types;
pub mod uri;

/// Exports every FMI 2.0 common and co-simulation function for one model type. A cdylib that
/// is an FMU is this one line: `bindery_fmu::export_fmu!(bindery_fmu::mechanisms::X::Model);`
#[macro_export]
macro_rules! export_fmu {
    ($model:ty) => {
        $crate::__export_fmi3!($model);
        mod __fmi2_exports {
            #![allow(non_snake_case, clippy::missing_safety_doc)]
            use super::*;
            use $crate::fmi2::runtime as rt;
            use $crate::fmi2::state::Call;
            use $crate::fmi2::types::*;
            type M = $model;

            /// Frees the library's caches when the loader unloads it ([`$crate::lifetime`]).
            #[cfg(target_os = "linux")]
            #[used]
            #[unsafe(link_section = ".fini_array")]
            static RELEASE_AT_UNLOAD: unsafe extern "C" fn() = $crate::lifetime::release_at_unload;

            /// Windows calls a DLL's `DllMain` with `DLL_PROCESS_DETACH` when `FreeLibrary`
            /// unloads it (`reserved` null) and at process exit (`reserved` not null, other
            /// threads already gone: nothing to free then). Frees the library's caches at the
            /// former ([`$crate::lifetime`]).
            #[cfg(windows)]
            #[unsafe(no_mangle)]
            pub unsafe extern "system" fn DllMain(
                _module: *mut std::ffi::c_void,
                reason: u32,
                reserved: *mut std::ffi::c_void,
            ) -> i32 {
                const DLL_PROCESS_DETACH: u32 = 0;
                if reason == DLL_PROCESS_DETACH && reserved.is_null() {
                    // SAFETY: the DLL is being unloaded: none of its code runs afterwards.
                    unsafe { $crate::lifetime::release_at_unload() };
                }
                1
            }

            #[unsafe(no_mangle)]
            pub extern "C" fn fmi2GetTypesPlatform() -> FmiString {
                TYPES_PLATFORM.as_ptr()
            }
            #[unsafe(no_mangle)]
            pub extern "C" fn fmi2GetVersion() -> FmiString {
                VERSION.as_ptr()
            }
            $crate::__fmi2_forward! { M;
                fmi2SetDebugLogging(c: Component, on: Boolean, n: usize, cats: *const FmiString)
                    -> Status => rt::set_debug_logging;
                fmi2Instantiate(
                    name: FmiString,
                    ty: std::ffi::c_int,
                    guid: FmiString,
                    resources: FmiString,
                    functions: *const CallbackFunctions,
                    visible: Boolean,
                    logging_on: Boolean,
                ) -> Component => rt::instantiate_c;
                fmi2FreeInstance(c: Component) => rt::free_instance;
                fmi2SetupExperiment(
                    c: Component,
                    tol_defined: Boolean,
                    tol: Real,
                    start: Real,
                    stop_defined: Boolean,
                    stop: Real,
                ) -> Status => rt::setup_experiment;
                fmi2EnterInitializationMode(c: Component)
                    -> Status => rt::enter_initialization_mode;
                fmi2ExitInitializationMode(c: Component) -> Status => rt::exit_initialization_mode;
                fmi2Terminate(c: Component) -> Status => rt::terminate;
                fmi2Reset(c: Component) -> Status => rt::reset;
                fmi2SetRealInputDerivatives(
                    c: Component,
                    vr: *const ValueReference,
                    n: usize,
                    order: *const Integer,
                    v: *const Real,
                ) -> Status => rt::set_real_input_derivatives;
                fmi2DoStep(c: Component, t: Real, h: Real, no_prior: Boolean)
                    -> Status => rt::do_step;
                fmi2GetRealStatus(c: Component, kind: std::ffi::c_int, v: *mut Real)
                    -> Status => rt::get_real_status;
                fmi2GetBooleanStatus(c: Component, kind: std::ffi::c_int, v: *mut Boolean)
                    -> Status => rt::get_boolean_status;
            }

            // the FMU-state calls, each told which call it is
            $crate::__fmi2_forward! { M; with_call:
                fmi2GetFMUstate(c: Component, s: *mut FMUstate) -> Status
                    => rt::get_fmu_state[GetFMUstate];
                fmi2SetFMUstate(c: Component, s: FMUstate) -> Status
                    => rt::set_fmu_state[SetFMUstate];
                fmi2FreeFMUstate(c: Component, s: *mut FMUstate) -> Status
                    => rt::free_fmu_state[FreeFMUstate];
                fmi2SerializedFMUstateSize(c: Component, s: FMUstate, size: *mut usize)
                    -> Status => rt::serialized_fmu_state_size[SerializedFMUstateSize];
                fmi2SerializeFMUstate(c: Component, s: FMUstate, bytes: *mut Byte, size: usize)
                    -> Status => rt::serialize_fmu_state[SerializeFMUstate];
                fmi2DeSerializeFMUstate(
                    c: Component,
                    bytes: *const Byte,
                    size: usize,
                    s: *mut FMUstate,
                ) -> Status => rt::deserialize_fmu_state[DeSerializeFMUstate];
            }

            // the get and set calls, each (component, value references, n, values)
            $crate::__fmi2_forward! { M; get_set:
                fmi2GetReal(*mut Real) => rt::get_real;
                fmi2GetInteger(*mut Integer) => rt::get_integer;
                fmi2GetBoolean(*mut Boolean) => rt::get_boolean;
                fmi2GetString(*mut FmiString) => rt::get_string;
                fmi2SetReal(*const Real) => rt::set_real;
                fmi2SetInteger(*const Integer) => rt::set_integer;
                fmi2SetBoolean(*const Boolean) => rt::set_boolean;
                fmi2SetString(*const FmiString) => rt::set_string;
            }

            // the calls whose capability flag is false: logged and refused (rt::unsupported)
            $crate::__fmi2_unsupported! { M;
                fmi2GetDirectionalDerivative(
                    _unknown: *const ValueReference,
                    _nu: usize,
                    _known: *const ValueReference,
                    _nk: usize,
                    _dv_known: *const Real,
                    _dv_unknown: *mut Real,
                ) = GetDirectionalDerivative, "providesDirectionalDerivative is false";
                fmi2GetRealOutputDerivatives(
                    _vr: *const ValueReference,
                    _n: usize,
                    _order: *const Integer,
                    _v: *mut Real,
                ) = GetRealOutputDerivatives, "maxOutputDerivativeOrder is 0";
                fmi2CancelStep() = CancelStep, "canRunAsynchronuously is false";
                fmi2GetStatus(_kind: std::ffi::c_int, _v: *mut Status)
                    = GetStatus, "steps are synchronous; no status is pending";
                fmi2GetIntegerStatus(_kind: std::ffi::c_int, _v: *mut Integer)
                    = GetIntegerStatus, "no integer status is defined in FMI 2.0";
                fmi2GetStringStatus(_kind: std::ffi::c_int, _v: *mut FmiString)
                    = GetStringStatus, "no status message is pending";
            }

            // ---- Model Exchange (runtime::me); refused on a Co-Simulation instance
            $crate::__fmi2_forward! { M;
                fmi2NewDiscreteStates(c: Component, info: *mut rt::me::EventInfo)
                    -> Status => rt::me::new_discrete_states;
            }
            $crate::__fmi2_forward! { M; with_call:
                fmi2EnterEventMode(c: Component) -> Status => rt::me::enter_event_mode[EnterEventMode];
                fmi2EnterContinuousTimeMode(c: Component)
                    -> Status => rt::me::enter_continuous_time_mode[EnterContinuousTimeMode];
                fmi2CompletedIntegratorStep(
                    c: Component,
                    no_set_prior: Boolean,
                    enter_event_mode: *mut Boolean,
                    terminate: *mut Boolean,
                ) -> Status => rt::me::completed_integrator_step[CompletedIntegratorStep];
                fmi2SetTime(c: Component, t: Real) -> Status => rt::me::set_time[SetTime];
                fmi2SetContinuousStates(c: Component, x: *const Real, nx: usize)
                    -> Status => rt::me::set_continuous_states[SetContinuousStates];
                fmi2GetDerivatives(c: Component, dx: *mut Real, nx: usize)
                    -> Status => rt::me::get_derivatives[GetDerivatives];
                fmi2GetEventIndicators(c: Component, z: *mut Real, ni: usize)
                    -> Status => rt::me::get_event_indicators[GetEventIndicators];
                fmi2GetContinuousStates(c: Component, x: *mut Real, nx: usize)
                    -> Status => rt::me::get_continuous_states[GetContinuousStates];
                fmi2GetNominalsOfContinuousStates(c: Component, x: *mut Real, nx: usize)
                    -> Status => rt::me::get_nominals[GetNominalsOfContinuousStates];
            }
        }
    };
}

/// For [`crate::export_fmu!`]: `extern "C"` functions, each passing its arguments on, in
/// order, to the runtime function named after `=>`, for the model `$m`. After `get_set:`, the
/// calls of the get/set signature, named with the type of their value array only; after
/// `with_call:`, calls whose runtime function is told which call it serves (`f[Call]`: the
/// component, then `Call::Call` of the version whose `Call` the invoking module imports, then
/// the other arguments).
#[doc(hidden)]
#[macro_export]
macro_rules! __fmi2_forward {
    ($m:ty; with_call: $(
        $name:ident($c:ident: $ct:ty $(, $arg:ident: $t:ty)* $(,)?) -> $ret:ty
            => $($f:ident)::+[$call:ident];
    )*) => {$(
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name($c: $ct $(, $arg: $t)*) -> $ret {
            unsafe { $($f)::+::<$m, _>($c, Call::$call $(, $arg)*) }
        }
    )*};
    ($m:ty; get_set: $($name:ident($value:ty) => $($f:ident)::+;)*) => {
        $crate::__fmi2_forward! { $m; $(
            $name(
                c: $crate::fmi2::types::Component,
                vr: *const $crate::fmi2::types::ValueReference,
                n: usize,
                v: $value,
            ) -> $crate::fmi2::types::Status => $($f)::+;
        )* }
    };
    ($m:ty; $(
        $name:ident($($arg:ident: $t:ty),* $(,)?) $(-> $ret:ty)? => $($f:ident)::+;
    )*) => {$(
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name($($arg: $t),*) $(-> $ret)? {
            unsafe { $($f)::+::<$m>($($arg),*) }
        }
    )*};
}

/// For [`crate::export_fmu!`]: `extern "C"` functions of calls the model does not support, each
/// taking the component and the listed (unused) arguments, and refusing the call with its
/// reason ([`crate::fmi2::runtime::unsupported`]); `Call` is the invoking module's (FMI 2.0's
/// or FMI 3.0's).
#[doc(hidden)]
#[macro_export]
macro_rules! __fmi2_unsupported {
    ($m:ty; $(
        $name:ident($($arg:ident: $t:ty),* $(,)?) = $call:ident, $why:literal;
    )*) => {$(
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            c: $crate::fmi2::types::Component,
            $($arg: $t),*
        ) -> $crate::fmi2::types::Status {
            unsafe {
                $crate::fmi2::runtime::unsupported::<$m>(c, Call::$call, $why)
            }
        }
    )*};
}
