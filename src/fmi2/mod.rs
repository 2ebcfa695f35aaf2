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
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetDebugLogging(
                c: Component,
                on: Boolean,
                n: usize,
                cats: *const FmiString,
            ) -> Status {
                unsafe { rt::set_debug_logging::<M>(c, on, n, cats) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Instantiate(
                name: FmiString,
                ty: std::ffi::c_int,
                guid: FmiString,
                resources: FmiString,
                functions: *const CallbackFunctions,
                visible: Boolean,
                logging_on: Boolean,
            ) -> Component {
                unsafe {
                    rt::instantiate_c::<M>(
                        name, ty, guid, resources, functions, visible, logging_on,
                    )
                }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2FreeInstance(c: Component) {
                unsafe { rt::free_instance::<M>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetupExperiment(
                c: Component,
                tol_defined: Boolean,
                tol: Real,
                start: Real,
                stop_defined: Boolean,
                stop: Real,
            ) -> Status {
                unsafe { rt::setup_experiment::<M>(c, tol_defined, tol, start, stop_defined, stop) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Component) -> Status {
                unsafe { rt::enter_initialization_mode::<M>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Component) -> Status {
                unsafe { rt::exit_initialization_mode::<M>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Terminate(c: Component) -> Status {
                unsafe { rt::terminate::<M>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Reset(c: Component) -> Status {
                unsafe { rt::reset::<M>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetReal(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *mut Real,
            ) -> Status {
                unsafe { rt::get_real::<M>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetInteger(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *mut Integer,
            ) -> Status {
                unsafe { rt::get_integer::<M>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetBoolean(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *mut Boolean,
            ) -> Status {
                unsafe { rt::get_boolean::<M>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetString(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *mut FmiString,
            ) -> Status {
                unsafe { rt::get_string::<M>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetReal(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *const Real,
            ) -> Status {
                unsafe { rt::set_real::<M>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetInteger(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *const Integer,
            ) -> Status {
                unsafe { rt::set_integer::<M>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetBoolean(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *const Boolean,
            ) -> Status {
                unsafe { rt::set_boolean::<M>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetString(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *const FmiString,
            ) -> Status {
                unsafe { rt::set_string::<M>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetFMUstate(c: Component, s: *mut FMUstate) -> Status {
                unsafe { rt::get_fmu_state::<M>(c, s) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetFMUstate(c: Component, s: FMUstate) -> Status {
                unsafe { rt::set_fmu_state::<M>(c, s) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2FreeFMUstate(c: Component, s: *mut FMUstate) -> Status {
                unsafe { rt::free_fmu_state::<M>(c, s) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
                c: Component,
                s: FMUstate,
                size: *mut usize,
            ) -> Status {
                unsafe { rt::serialized_fmu_state_size::<M>(c, s, size) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SerializeFMUstate(
                c: Component,
                s: FMUstate,
                bytes: *mut Byte,
                size: usize,
            ) -> Status {
                unsafe { rt::serialize_fmu_state::<M>(c, s, bytes, size) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
                c: Component,
                bytes: *const Byte,
                size: usize,
                s: *mut FMUstate,
            ) -> Status {
                unsafe { rt::deserialize_fmu_state::<M>(c, bytes, size, s) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
                c: Component,
                _unknown: *const ValueReference,
                _nu: usize,
                _known: *const ValueReference,
                _nk: usize,
                _dv_known: *const Real,
                _dv_unknown: *mut Real,
            ) -> Status {
                unsafe {
                    rt::unsupported::<M>(
                        c,
                        Call::GetDirectionalDerivative,
                        "providesDirectionalDerivative is false",
                    )
                }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                order: *const Integer,
                v: *const Real,
            ) -> Status {
                unsafe { rt::set_real_input_derivatives::<M>(c, vr, n, order, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
                c: Component,
                _vr: *const ValueReference,
                _n: usize,
                _order: *const Integer,
                _v: *mut Real,
            ) -> Status {
                unsafe {
                    rt::unsupported::<M>(
                        c,
                        Call::GetRealOutputDerivatives,
                        "maxOutputDerivativeOrder is 0",
                    )
                }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2DoStep(
                c: Component,
                t: Real,
                h: Real,
                no_prior: Boolean,
            ) -> Status {
                unsafe { rt::do_step::<M>(c, t, h, no_prior) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2CancelStep(c: Component) -> Status {
                unsafe {
                    rt::unsupported::<M>(c, Call::CancelStep, "canRunAsynchronuously is false")
                }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetStatus(
                c: Component,
                _kind: std::ffi::c_int,
                _v: *mut Status,
            ) -> Status {
                unsafe {
                    rt::unsupported::<M>(
                        c,
                        Call::GetStatus,
                        "steps are synchronous; no status is pending",
                    )
                }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetRealStatus(
                c: Component,
                kind: std::ffi::c_int,
                v: *mut Real,
            ) -> Status {
                unsafe { rt::get_real_status::<M>(c, kind, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetIntegerStatus(
                c: Component,
                _kind: std::ffi::c_int,
                _v: *mut Integer,
            ) -> Status {
                unsafe {
                    rt::unsupported::<M>(
                        c,
                        Call::GetIntegerStatus,
                        "no integer status is defined in FMI 2.0",
                    )
                }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetBooleanStatus(
                c: Component,
                kind: std::ffi::c_int,
                v: *mut Boolean,
            ) -> Status {
                unsafe { rt::get_boolean_status::<M>(c, kind, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetStringStatus(
                c: Component,
                _kind: std::ffi::c_int,
                _v: *mut FmiString,
            ) -> Status {
                unsafe {
                    rt::unsupported::<M>(c, Call::GetStringStatus, "no status message is pending")
                }
            }

            // ---- Model Exchange (runtime::me); refused on a Co-Simulation instance
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2EnterEventMode(c: Component) -> Status {
                unsafe { rt::me::enter_event_mode::<M>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2NewDiscreteStates(
                c: Component,
                info: *mut rt::me::EventInfo,
            ) -> Status {
                unsafe { rt::me::new_discrete_states::<M>(c, info) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2EnterContinuousTimeMode(c: Component) -> Status {
                unsafe { rt::me::enter_continuous_time_mode::<M>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2CompletedIntegratorStep(
                c: Component,
                no_set_prior: Boolean,
                enter_event_mode: *mut Boolean,
                terminate: *mut Boolean,
            ) -> Status {
                unsafe {
                    rt::me::completed_integrator_step::<M>(
                        c,
                        no_set_prior,
                        enter_event_mode,
                        terminate,
                    )
                }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetTime(c: Component, t: Real) -> Status {
                unsafe { rt::me::set_time::<M>(c, t) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetContinuousStates(
                c: Component,
                x: *const Real,
                nx: usize,
            ) -> Status {
                unsafe { rt::me::set_continuous_states::<M>(c, x, nx) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetDerivatives(
                c: Component,
                dx: *mut Real,
                nx: usize,
            ) -> Status {
                unsafe { rt::me::get_derivatives::<M>(c, dx, nx) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetEventIndicators(
                c: Component,
                z: *mut Real,
                ni: usize,
            ) -> Status {
                unsafe { rt::me::get_event_indicators::<M>(c, z, ni) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetContinuousStates(
                c: Component,
                x: *mut Real,
                nx: usize,
            ) -> Status {
                unsafe { rt::me::get_continuous_states::<M>(c, x, nx) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetNominalsOfContinuousStates(
                c: Component,
                x: *mut Real,
                nx: usize,
            ) -> Status {
                unsafe { rt::me::get_nominals::<M>(c, x, nx) }
            }
        }
    };
}
