//! The FMI 3.0 C ABI over the same runtime as FMI 2.0 ([`crate::fmi2::runtime`]: one instance
//! type, one entry wrapper, one FMU state): its C types, its state-machine table and its calls.
//! Every FMU binary exports both versions' symbols ([`crate::export_fmu!`]), so the FMI 2.0 and
//! the FMI 3.0 FMU of a model carry the same library and give the same numbers. Nothing here
//! knows a mechanism.
pub mod calls;
pub mod state;
pub mod types;

/// Exports the FMI 3.0 functions for one model type; part of [`crate::export_fmu!`].
#[doc(hidden)]
#[macro_export]
macro_rules! __export_fmi3 {
    ($model:ty) => {
        mod __fmi3_exports {
            #![allow(non_snake_case, clippy::missing_safety_doc, clippy::too_many_arguments)]
            use super::*;
            use $crate::fmi2::runtime as shared;
            use $crate::fmi3::calls as rt;
            use $crate::fmi3::state::Call;
            use $crate::fmi3::types::*;
            type M = $model;

            #[unsafe(no_mangle)]
            pub extern "C" fn fmi3GetVersion() -> FmiString {
                VERSION.as_ptr()
            }
            $crate::__fmi2_forward! { M;
                fmi3SetDebugLogging(c: Instance, on: Boolean, n: usize, cats: *const FmiString)
                    -> Status => rt::set_debug_logging;
                fmi3InstantiateCoSimulation(
                    name: FmiString,
                    token: FmiString,
                    resources: FmiString,
                    visible: Boolean,
                    logging_on: Boolean,
                    event_mode_used: Boolean,
                    early_return_allowed: Boolean,
                    required: *const ValueReference,
                    n_required: usize,
                    env: InstanceEnvironment,
                    log: LogMessageCallback,
                    update: IntermediateUpdateCallback,
                ) -> Instance => rt::instantiate_co_simulation;
                fmi3FreeInstance(c: Instance) => rt::free_instance;
                fmi3DoStep(
                    c: Instance,
                    t: Float64,
                    h: Float64,
                    no_prior: Boolean,
                    event: *mut Boolean,
                    terminate: *mut Boolean,
                    early: *mut Boolean,
                    last: *mut Float64,
                ) -> Status => rt::do_step;
                fmi3UpdateDiscreteStates(
                    c: Instance,
                    update: *mut Boolean,
                    terminate: *mut Boolean,
                    nominals_changed: *mut Boolean,
                    values_changed: *mut Boolean,
                    next_defined: *mut Boolean,
                    next: *mut Float64,
                ) -> Status => rt::update_discrete_states;
                fmi3GetBinary(
                    c: Instance,
                    vr: *const ValueReference,
                    n: usize,
                    sizes: *mut usize,
                    v: *mut Binary,
                    nv: usize,
                ) -> Status => rt::get_binary;
                fmi3SetBinary(
                    c: Instance,
                    vr: *const ValueReference,
                    n: usize,
                    sizes: *const usize,
                    v: *const Binary,
                    nv: usize,
                ) -> Status => rt::set_binary;
            }
            $crate::__fmi2_forward! { M;
                fmi3InstantiateModelExchange(
                    name: FmiString,
                    token: FmiString,
                    resources: FmiString,
                    visible: Boolean,
                    logging_on: Boolean,
                    env: InstanceEnvironment,
                    log: LogMessageCallback,
                ) -> Instance => rt::instantiate_model_exchange;
            }
            // the calls that are one method of the shared runtime's instance
            $crate::__fmi2_forward! { M; method:
                fmi3EnterInitializationMode(
                    c: Instance,
                    tol_defined: Boolean,
                    tol: Float64,
                    start: Float64,
                    stop_defined: Boolean,
                    stop: Float64,
                ) => experiment_and_initialization[EnterInitializationMode];
                fmi3ExitInitializationMode(c: Instance)
                    => exit_initialization_mode[ExitInitializationMode];
                fmi3Terminate(c: Instance) => terminate[Terminate];
                fmi3Reset(c: Instance) => reset[Reset];
                fmi3EnterEventMode(c: Instance) => enter_event_mode[EnterEventMode];
                fmi3EnterStepMode(c: Instance) => enter_continuous_time_mode[EnterStepMode];
                fmi3EnterContinuousTimeMode(c: Instance)
                    => enter_continuous_time_mode[EnterContinuousTimeMode];
            }
            // Model Exchange: the shared runtime's calls, as the FMI 3.0 calls they serve
            $crate::__fmi2_forward! { M; me(Boolean):
                fmi3CompletedIntegratorStep[CompletedIntegratorStep],
                fmi3SetTime[SetTime],
                fmi3SetContinuousStates[SetContinuousStates],
                fmi3GetContinuousStateDerivatives[GetContinuousStateDerivatives],
                fmi3GetEventIndicators[GetEventIndicators],
                fmi3GetContinuousStates[GetContinuousStates],
                fmi3GetNominalsOfContinuousStates[GetNominalsOfContinuousStates],
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3GetNumberOfContinuousStates(
                c: Instance,
                n: *mut usize,
            ) -> Status {
                unsafe { rt::number_of::<M>(c, Call::GetNumberOfContinuousStates, n) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3GetNumberOfEventIndicators(
                c: Instance,
                n: *mut usize,
            ) -> Status {
                unsafe { rt::number_of::<M>(c, Call::GetNumberOfEventIndicators, n) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
                name: FmiString,
                _token: FmiString,
                _resources: FmiString,
                _visible: Boolean,
                _logging_on: Boolean,
                env: InstanceEnvironment,
                log: LogMessageCallback,
                _clock_update: ClockUpdateCallback,
                _lock: PreemptionCallback,
                _unlock: PreemptionCallback,
            ) -> Instance {
                unsafe { rt::instantiate_scheduled_execution::<M>(name, env, log) }
            }

            // the FMU-state calls: the shared runtime's, as the FMI 3.0 calls they serve
            $crate::__fmi2_forward! { M; fmu_state:
                fmi3GetFMUState[GetFMUState],
                fmi3SetFMUState[SetFMUState],
                fmi3FreeFMUState[FreeFMUState],
                fmi3SerializedFMUStateSize[SerializedFMUStateSize],
                fmi3SerializeFMUState[SerializeFMUState],
                fmi3DeserializeFMUState[DeserializeFMUState],
            }

            // the typed get and set calls: (instance, value references, nvr, values, nValues)
            $crate::__fmi3_forward! { M; typed:
                fmi3GetFloat32(*mut Float32) => rt::get_float32;
                fmi3GetFloat64(*mut Float64) => rt::get_float64;
                fmi3GetInt8(*mut Int8) => rt::get_int8;
                fmi3GetUInt8(*mut UInt8) => rt::get_uint8;
                fmi3GetInt16(*mut Int16) => rt::get_int16;
                fmi3GetUInt16(*mut UInt16) => rt::get_uint16;
                fmi3GetInt32(*mut Int32) => rt::get_int32;
                fmi3GetUInt32(*mut UInt32) => rt::get_uint32;
                fmi3GetInt64(*mut Int64) => rt::get_int64;
                fmi3GetUInt64(*mut UInt64) => rt::get_uint64;
                fmi3GetBoolean(*mut Boolean) => rt::get_boolean;
                fmi3GetString(*mut FmiString) => rt::get_string;
                fmi3SetFloat32(*const Float32) => rt::set_float32;
                fmi3SetFloat64(*const Float64) => rt::set_float64;
                fmi3SetInt8(*const Int8) => rt::set_int8;
                fmi3SetUInt8(*const UInt8) => rt::set_uint8;
                fmi3SetInt16(*const Int16) => rt::set_int16;
                fmi3SetUInt16(*const UInt16) => rt::set_uint16;
                fmi3SetInt32(*const Int32) => rt::set_int32;
                fmi3SetUInt32(*const UInt32) => rt::set_uint32;
                fmi3SetInt64(*const Int64) => rt::set_int64;
                fmi3SetUInt64(*const UInt64) => rt::set_uint64;
                fmi3SetBoolean(*const Boolean) => rt::set_boolean;
                fmi3SetString(*const FmiString) => rt::set_string;
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3GetClock(
                c: Instance,
                vr: *const ValueReference,
                n: usize,
                v: *mut Clock,
            ) -> Status {
                unsafe { rt::clock::<M>(c, Call::GetClock, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3SetClock(
                c: Instance,
                vr: *const ValueReference,
                n: usize,
                v: *const Clock,
            ) -> Status {
                unsafe { rt::clock::<M>(c, Call::SetClock, vr, n, v as *mut Clock) }
            }

            // what this FMU's FMI 3.0 interface does not offer: refused with the reason
            $crate::__fmi2_unsupported! { M;
                fmi3GetNumberOfVariableDependencies(_vr: ValueReference, _n: *mut usize)
                    = GetNumberOfVariableDependencies,
                    "the dependencies are in modelDescription.xml's ModelStructure";
                fmi3GetVariableDependencies(
                    _dependent: ValueReference,
                    _element_of_dependent: *mut usize,
                    _independents: *mut ValueReference,
                    _element_of_independents: *mut usize,
                    _kinds: *mut DependencyKind,
                    _n: usize,
                ) = GetVariableDependencies,
                    "the dependencies are in modelDescription.xml's ModelStructure";
                fmi3EnterConfigurationMode() = EnterConfigurationMode,
                    "this FMU has no structural parameters";
                fmi3ExitConfigurationMode() = ExitConfigurationMode,
                    "this FMU has no structural parameters";
                fmi3EvaluateDiscreteStates() = EvaluateDiscreteStates,
                    "providesEvaluateDiscreteStates is false";
                fmi3GetOutputDerivatives(
                    _vr: *const ValueReference,
                    _n: usize,
                    _orders: *const Int32,
                    _v: *mut Float64,
                    _nv: usize,
                ) = GetOutputDerivatives, "maxOutputDerivativeOrder is 0";
                fmi3ActivateModelPartition(_clock: ValueReference, _t: Float64)
                    = ActivateModelPartition, "Scheduled Execution is not offered";
            }
            // the partial derivatives: directional, and adjoint from as many directions
            $crate::__fmi2_forward! { M; alike (
                c: Instance,
                unknowns: *const ValueReference,
                n_unknowns: usize,
                knowns: *const ValueReference,
                n_knowns: usize,
                seed: *const Float64,
                n_seed: usize,
                sensitivity: *mut Float64,
                n_sensitivity: usize,
            ) -> Status:
                fmi3GetDirectionalDerivative => rt::partial_derivative(false);
                fmi3GetAdjointDerivative => rt::partial_derivative(true);
            }
            // the clock calls: this FMU has no clocks
            $crate::__fmi2_unsupported! { M;
                fmi3GetIntervalDecimal(
                    _vr: *const ValueReference,
                    _n: usize,
                    _intervals: *mut Float64,
                    _qualifiers: *mut IntervalQualifier,
                ) = GetIntervalDecimal, "this FMU has no clocks";
                fmi3GetIntervalFraction(
                    _vr: *const ValueReference,
                    _n: usize,
                    _counters: *mut UInt64,
                    _resolutions: *mut UInt64,
                    _qualifiers: *mut IntervalQualifier,
                ) = GetIntervalFraction, "this FMU has no clocks";
                fmi3GetShiftDecimal(_vr: *const ValueReference, _n: usize, _shifts: *mut Float64)
                    = GetShiftDecimal, "this FMU has no clocks";
                fmi3GetShiftFraction(
                    _vr: *const ValueReference,
                    _n: usize,
                    _counters: *mut UInt64,
                    _resolutions: *mut UInt64,
                ) = GetShiftFraction, "this FMU has no clocks";
            }
            $crate::__fmi2_unsupported! { M; alike (
                _vr: *const ValueReference,
                _n: usize,
                _values: *const Float64,
            ):
                fmi3SetIntervalDecimal = SetIntervalDecimal, "this FMU has no clocks";
                fmi3SetShiftDecimal = SetShiftDecimal, "this FMU has no clocks";
            }
            $crate::__fmi2_unsupported! { M; alike (
                _vr: *const ValueReference,
                _n: usize,
                _counters: *const UInt64,
                _resolutions: *const UInt64,
            ):
                fmi3SetIntervalFraction = SetIntervalFraction, "this FMU has no clocks";
                fmi3SetShiftFraction = SetShiftFraction, "this FMU has no clocks";
            }
        }
    };
}

/// For [`crate::__export_fmi3!`]: FMI 3.0's typed get/set calls (named with their value array's
/// type, with `nValues`) as `extern "C"` functions passing their arguments on to the runtime
/// function after `=>`, for the model `$m`. Every other FMI 3.0 call is made by
/// [`crate::__fmi2_forward!`] (its plain list, `method:`, `fmu_state:` and `me(..):`) or
/// [`crate::__fmi2_unsupported!`], with FMI 3.0's `Call` in scope.
#[doc(hidden)]
#[macro_export]
macro_rules! __fmi3_forward {
    ($m:ty; typed: $($name:ident($value:ty) => $($f:ident)::+;)*) => {
        $crate::__fmi2_forward! { $m; $(
            $name(
                c: $crate::fmi3::types::Instance,
                vr: *const $crate::fmi3::types::ValueReference,
                n: usize,
                v: $value,
                nv: usize,
            ) -> $crate::fmi3::types::Status => $($f)::+;
        )* }
    };
}
