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

            // the calls that are one method of the instance
            $crate::__fmi2_forward! { M; method:
                fmi2SetupExperiment(
                    c: Component,
                    tol_defined: Boolean,
                    tol: Real,
                    start: Real,
                    stop_defined: Boolean,
                    stop: Real,
                ) => experiment[SetupExperiment];
                fmi2EnterInitializationMode(c: Component)
                    => enter_initialization_mode[EnterInitializationMode];
                fmi2ExitInitializationMode(c: Component)
                    => exit_initialization_mode[ExitInitializationMode];
                fmi2GetDirectionalDerivative(
                    c: Component,
                    unknown: *const ValueReference,
                    nu: usize,
                    known: *const ValueReference,
                    nk: usize,
                    dv_known: *const Real,
                    dv_unknown: *mut Real,
                ) => directional_derivative[GetDirectionalDerivative];
                fmi2Terminate(c: Component) => terminate[Terminate];
                fmi2Reset(c: Component) => reset[Reset];
                fmi2EnterEventMode(c: Component) => enter_event_mode[EnterEventMode];
                fmi2EnterContinuousTimeMode(c: Component)
                    => enter_continuous_time_mode[EnterContinuousTimeMode];
            }

            // the FMU-state calls
            $crate::__fmi2_forward! { M; fmu_state:
                fmi2GetFMUstate[GetFMUstate],
                fmi2SetFMUstate[SetFMUstate],
                fmi2FreeFMUstate[FreeFMUstate],
                fmi2SerializedFMUstateSize[SerializedFMUstateSize],
                fmi2SerializeFMUstate[SerializeFMUstate],
                fmi2DeSerializeFMUstate[DeSerializeFMUstate],
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
            $crate::__fmi2_forward! { M; method:
                fmi2NewDiscreteStates(c: Component, info: *mut rt::me::EventInfo)
                    => new_discrete_states[NewDiscreteStates];
            }
            $crate::__fmi2_forward! { M; me(Boolean):
                fmi2CompletedIntegratorStep[CompletedIntegratorStep],
                fmi2SetTime[SetTime],
                fmi2SetContinuousStates[SetContinuousStates],
                fmi2GetDerivatives[GetDerivatives],
                fmi2GetEventIndicators[GetEventIndicators],
                fmi2GetContinuousStates[GetContinuousStates],
                fmi2GetNominalsOfContinuousStates[GetNominalsOfContinuousStates],
            }
        }
    };
}

/// For [`crate::export_fmu!`]: `extern "C"` functions, each passing its arguments on, in
/// order, to the runtime function named after `=>`, for the model `$m`. After `get_set:`, the
/// calls of the get/set signature, named with the type of their value array only. After
/// `method:`, calls that are one [`runtime::Instance`] method (`method[Call]`), run through the
/// entry wrapper as `Call::Call` of the version whose `Call` the invoking module imports, with
/// the arguments after the component, after leading arguments of its own where the call names
/// them (`method[Call](lead, ..)`: the call itself, say). After `alike (signature) -> R:`, calls
/// of one signature, each passing leading arguments of its own before the call's.
#[doc(hidden)]
#[macro_export]
macro_rules! __fmi2_forward {
    ($m:ty; method: $(
        $name:ident($c:ident: $ct:ty $(, $arg:ident: $t:ty)* $(,)?)
            => $method:ident[$call:ident] $(($($lead:expr),*))?;
    )*) => {$(
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name($c: $ct $(, $arg: $t)*) -> $crate::fmi2::types::Status {
            unsafe {
                $crate::fmi2::runtime::entry::<$m, _>($c, Call::$call, |i| {
                    i.$method($($($lead,)*)? $($arg),*)
                })
            }
        }
    )*};
    // the FMU-state calls, the same in FMI 2.0 and FMI 3.0 but for their names
    ($m:ty; fmu_state:
        $get:ident[$cget:ident], $set:ident[$cset:ident], $free:ident[$cfree:ident],
        $size:ident[$csize:ident], $ser:ident[$cser:ident], $de:ident[$cde:ident] $(,)?
    ) => {
        $crate::__fmi2_forward! { $m; method:
            $get(c: $crate::fmi2::types::Component, s: *mut $crate::fmi2::types::FMUstate) => get_fmu_state[$cget];
            $set(c: $crate::fmi2::types::Component, s: $crate::fmi2::types::FMUstate) => set_fmu_state[$cset];
            $free(c: $crate::fmi2::types::Component, s: *mut $crate::fmi2::types::FMUstate) => free_fmu_state[$cfree];
            $size(c: $crate::fmi2::types::Component, s: $crate::fmi2::types::FMUstate, size: *mut usize)
                => serialized_fmu_state_size[$csize];
            $ser(c: $crate::fmi2::types::Component, s: $crate::fmi2::types::FMUstate, bytes: *mut $crate::fmi2::types::Byte, size: usize)
                => serialize_fmu_state[$cser];
            $de(c: $crate::fmi2::types::Component, bytes: *const $crate::fmi2::types::Byte, size: usize, s: *mut $crate::fmi2::types::FMUstate)
                => deserialize_fmu_state[$cde];
        }
    };
    // the Model Exchange calls of the continuous-time mode, the same in FMI 2.0 and FMI 3.0
    // but for their names and the Boolean
    ($m:ty; me($boolean:ty):
        $completed:ident[$ccompleted:ident], $time:ident[$ctime:ident],
        $set_x:ident[$cset_x:ident], $der:ident[$cder:ident], $ind:ident[$cind:ident],
        $get_x:ident[$cget_x:ident], $nominals:ident[$cnominals:ident] $(,)?
    ) => {
        $crate::__fmi2_forward! { $m; method:
            $completed(c: $crate::fmi2::types::Component, no_prior: $boolean, event: *mut $boolean, end: *mut $boolean)
                => completed_integrator_step[$ccompleted];
            $time(c: $crate::fmi2::types::Component, t: f64) => set_time[$ctime];
            $set_x(c: $crate::fmi2::types::Component, x: *const f64, n: usize) => set_continuous_states[$cset_x];
            $get_x(c: $crate::fmi2::types::Component, x: *mut f64, n: usize) => get_continuous_states[$cget_x];
            $nominals(c: $crate::fmi2::types::Component, x: *mut f64, n: usize) => get_nominals[$cnominals];
            $der(c: $crate::fmi2::types::Component, dx: *mut f64, n: usize)
                => get_derivatives[$cder](Call::$cder);
            $ind(c: $crate::fmi2::types::Component, z: *mut f64, n: usize)
                => get_event_indicators[$cind](Call::$cind);
        }
    };
    ($m:ty; alike $args:tt -> $ret:ty: $(
        $name:ident => $($f:ident)::+($($lead:expr),*);
    )*) => {$(
        $crate::__fmi2_forward! { $m; one $name $args -> $ret => $($f)::+($($lead),*) }
    )*};
    ($m:ty; one $name:ident ($($arg:ident: $t:ty),* $(,)?) -> $ret:ty
        => $($f:ident)::+($($lead:expr),*)) => {
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name($($arg: $t),*) -> $ret {
            unsafe { $($f)::+::<$m>($($lead,)* $($arg),*) }
        }
    };
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
    // calls of one signature (`alike (arguments)`), each refused with its reason
    ($m:ty; alike $args:tt: $($name:ident = $call:ident, $why:literal;)*) => {
        $crate::__fmi2_unsupported! { $m; $($name $args = $call, $why;)* }
    };
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
