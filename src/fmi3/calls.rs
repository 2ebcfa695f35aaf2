//! The FMI 3.0 calls over the shared runtime ([`crate::fmi2::runtime`]): instantiation,
//! initialization with the experiment, the typed get and set calls, `fmi3DoStep`. The FMU-state,
//! mode and Model Exchange calls are the runtime's instance methods, exported as the FMI 3.0
//! calls they serve. Each is one [`entry`] with this version's [`Call`], so the state machine
//! of [`super::state`] decides what is legal.

use super::state::Call;
use super::types::*;
use crate::fmi2::runtime::{
    Kind, Logger, c_str, create, entry, get, instantiating, scalars, set, slice, slice_mut,
};
use crate::model::{Model, VarType};
use std::borrow::Cow;
use std::path::PathBuf;

/// What an `fmi3Instantiate*` call asks for, besides the model.
struct Request {
    /// `CoSimulation` or `ModelExchange`: names the call in messages.
    kind: &'static str,
    /// Why this interface refuses, if it does (`None`: go ahead).
    refusal: Option<String>,
    model_exchange: bool,
    event_mode_used: bool,
    early_return: bool,
}

/// One instantiation through FMI 3.0: the host's strings read, its logger made, the request's
/// refusal or the runtime's ([`create`]) logged, panics caught.
///
/// # Safety
/// Pointer arguments must be NULL or valid per the FMI 3.0 standard.
unsafe fn instantiate<M: Model>(
    (instance_name, token, resource_path): (FmiString, FmiString, FmiString),
    logging_on: Boolean,
    (env, log): (InstanceEnvironment, LogMessageCallback),
    request: Request,
) -> Instance {
    let call = format!("fmi3Instantiate{}", request.kind);
    instantiating::<M>(&call, || {
        // SAFETY: NULL or valid C strings, per the standard.
        let (name, token, resources) =
            unsafe { (c_str(instance_name), c_str(token), c_str(resource_path)) };
        let name = name.unwrap_or("");
        let logger = Logger::fmi3(
            log,
            env,
            if name.is_empty() { M::IDENTIFIER } else { name },
            logging_on != FALSE,
        );
        let refused = |logger: Logger, why: String| {
            logger.emit(
                Status::Error,
                "logStatusError",
                &format!("{call}: {why}; refused"),
            );
            std::ptr::null_mut()
        };
        if name.is_empty() {
            return refused(logger, "instanceName is NULL or empty".into());
        }
        if let Some(why) = request.refusal {
            return refused(logger, why);
        }
        // FMI 3.0 passes a native path to the resources folder (FMI 2.0 a URI)
        let resources = resources.filter(|r| !r.is_empty()).map(PathBuf::from);
        match create::<M>(logger, request.model_exchange, token, resources) {
            Ok(c) => {
                // SAFETY: create returned a live instance of M.
                let inst = unsafe { &mut *(c as *mut crate::fmi2::runtime::Instance<M>) };
                inst.event_mode_used = request.event_mode_used;
                inst.early_return = request.early_return;
                c
            }
            Err((logger, why)) => refused(logger, why.replace("GUID", "instantiationToken")),
        }
    })
}

/// `fmi3InstantiateCoSimulation`: a Co-Simulation instance, with Event Mode if the host uses it
/// (`eventModeUsed`) and steps that return early at the mechanism's events if it allows them
/// (`earlyReturnAllowed`); intermediate variables are refused (`providesIntermediateUpdate`
/// is false).
///
/// # Safety
/// Pointer arguments must be NULL or valid per the FMI 3.0 standard.
#[allow(clippy::too_many_arguments)]
pub unsafe fn instantiate_co_simulation<M: Model>(
    instance_name: FmiString,
    token: FmiString,
    resource_path: FmiString,
    _visible: Boolean,
    logging_on: Boolean,
    event_mode_used: Boolean,
    early_return_allowed: Boolean,
    _required_intermediate: *const ValueReference,
    n_required_intermediate: usize,
    env: InstanceEnvironment,
    log: LogMessageCallback,
    _intermediate_update: IntermediateUpdateCallback,
) -> Instance {
    let request = Request {
        kind: "CoSimulation",
        refusal: (n_required_intermediate > 0).then(|| {
            format!(
                "{n_required_intermediate} required intermediate variables; providesIntermediateUpdate is false"
            )
        }),
        model_exchange: false,
        event_mode_used: event_mode_used != FALSE,
        early_return: early_return_allowed != FALSE,
    };
    let strings = (instance_name, token, resource_path);
    // SAFETY: as this function.
    unsafe { instantiate::<M>(strings, logging_on, (env, log), request) }
}

/// `fmi3InstantiateModelExchange`: a Model Exchange instance of a model with continuous
/// states (those of its elastodynamic level, MainShaft's); a model without is refused, naming
/// its Co-Simulation interface.
///
/// # Safety
/// Pointer arguments must be NULL or valid per the FMI 3.0 standard.
pub unsafe fn instantiate_model_exchange<M: Model>(
    instance_name: FmiString,
    token: FmiString,
    resource_path: FmiString,
    _visible: Boolean,
    logging_on: Boolean,
    env: InstanceEnvironment,
    log: LogMessageCallback,
) -> Instance {
    let request = Request {
        kind: "ModelExchange",
        refusal: (M::STATES == 0)
            .then(|| "this FMU has no continuous states and provides Co-Simulation only".into()),
        model_exchange: true,
        event_mode_used: false,
        early_return: false,
    };
    let strings = (instance_name, token, resource_path);
    // SAFETY: as this function.
    unsafe { instantiate::<M>(strings, logging_on, (env, log), request) }
}

/// `fmi3InstantiateScheduledExecution`: not offered (no clocks); refused with the reason.
///
/// # Safety
/// As [`instantiate_co_simulation`].
pub unsafe fn instantiate_scheduled_execution<M: Model>(
    instance_name: FmiString,
    env: InstanceEnvironment,
    log: LogMessageCallback,
) -> Instance {
    // SAFETY: NULL or a valid C string.
    let name = unsafe { c_str(instance_name) }.unwrap_or(M::IDENTIFIER);
    Logger::fmi3(log, env, name, false).emit(
        Status::Error,
        "logStatusError",
        "fmi3InstantiateScheduledExecution: Scheduled Execution is not offered (no clocks); refused",
    );
    std::ptr::null_mut()
}

/// `fmi3SetDebugLogging`.
///
/// # Safety
/// As [`entry`]; `categories` holds `n` C strings.
pub unsafe fn set_debug_logging<M: Model>(
    c: Instance,
    on: Boolean,
    n: usize,
    categories: *const FmiString,
) -> Status {
    // SAFETY: as this function.
    unsafe {
        crate::fmi2::runtime::set_debug_logging_as::<M, _>(
            c,
            Call::SetDebugLogging,
            on != FALSE,
            n,
            categories,
        )
    }
}

/// `fmi3FreeInstance`.
///
/// # Safety
/// As [`entry`].
pub unsafe fn free_instance<M: Model>(c: Instance) {
    // SAFETY: as this function.
    unsafe { crate::fmi2::runtime::free_instance_as::<M, _>(c, Call::FreeInstance) }
}

/// `fmi3DoStep`: the step of the shared runtime ([`crate::fmi2::runtime::Instance::do_step`]);
/// if the host allows early return, the step ends at the first event inside it
/// (`earlyReturn`, `lastSuccessfulTime` the event's time, and `eventHandlingNeeded` if the host
/// uses Event Mode). The simulation never ends by itself. `lastSuccessfulTime` is the FMU's
/// time after the call (the step's end, the event, or the start of a discarded step).
///
/// # Safety
/// As [`entry`]; the out-pointers are NULL or valid.
#[allow(clippy::too_many_arguments)]
pub unsafe fn do_step<M: Model>(
    c: Instance,
    t: Float64,
    h: Float64,
    _no_set_prior: Boolean,
    event_handling_needed: *mut Boolean,
    terminate_simulation: *mut Boolean,
    early_return: *mut Boolean,
    last_successful_time: *mut Float64,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, Call::DoStep, |inst| {
            let (status, event) = if inst.early_return {
                inst.do_step_to_event(t, h, "fmi3DoStep")?
            } else {
                (inst.do_step(t, h, "fmi3DoStep")?, None)
            };
            let flags = [
                (
                    event_handling_needed,
                    event.is_some() && inst.event_mode_used,
                ),
                (terminate_simulation, false),
                (early_return, event.is_some()),
            ];
            for (p, value) in flags {
                if let Some(f) = p.as_mut() {
                    *f = Boolean::from(value);
                }
            }
            if let Some(last) = last_successful_time.as_mut() {
                *last = inst.time;
            }
            if let Some(te) = event {
                inst.logger.emit(
                    Status::Ok,
                    "logEvents",
                    &format!("fmi3DoStep: returns early at the event at t = {te}"),
                );
            }
            Ok(status)
        })
    }
}

/// `fmi3UpdateDiscreteStates`: Model Exchange: the model switches its discrete modes at the
/// event (as `fmi2NewDiscreteStates`); Co-Simulation: the mechanisms' discrete outputs follow
/// the shaft and the states at the event's time. Either way one pass: no further update, no
/// new event time, continuous states unchanged.
///
/// # Safety
/// As [`entry`]; the out-pointers are NULL or valid.
pub unsafe fn update_discrete_states<M: Model>(
    c: Instance,
    update_needed: *mut Boolean,
    terminate: *mut Boolean,
    nominals_changed: *mut Boolean,
    values_changed: *mut Boolean,
    next_time_defined: *mut Boolean,
    next_time: *mut Float64,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, Call::UpdateDiscreteStates, |inst| {
            if inst.me.is_me {
                inst.me_event()?;
            }
            for p in [
                update_needed,
                terminate,
                nominals_changed,
                values_changed,
                next_time_defined,
            ] {
                if let Some(f) = p.as_mut() {
                    *f = FALSE;
                }
            }
            if let Some(t) = next_time.as_mut() {
                *t = 0.0;
            }
            Ok(Status::Ok)
        })
    }
}

/// `fmi3GetNumberOfContinuousStates` and `fmi3GetNumberOfEventIndicators` (`call`).
///
/// # Safety
/// As [`entry`]; `n` points to a `size_t`.
pub unsafe fn number_of<M: Model>(c: Instance, call: Call, n: *mut usize) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |_| {
            let n = n.as_mut().ok_or("the result pointer is NULL")?;
            *n = match call {
                Call::GetNumberOfContinuousStates => M::STATES,
                _ => M::EVENT_INDICATORS,
            };
            Ok(Status::Ok)
        })
    }
}

/// `fmi3GetFloat64`: the model's Real variables, and the variables FMI 3.0 adds after them:
/// `time` (the instance's time) and, with Model Exchange, the event indicators.
///
/// # Safety
/// As [`entry`]; arrays hold `nvr` elements.
pub unsafe fn get_float64<M: Model>(
    c: Instance,
    vr: *const ValueReference,
    nvr: usize,
    values: *mut Float64,
    n_values: usize,
) -> Status {
    let n = <M::Var as crate::model::VarSet>::table().len();
    // SAFETY: as this function (a NULL array is refused by the call below).
    let model_only =
        unsafe { slice(vr, nvr, "vr") }.is_ok_and(|v| v.iter().all(|&r| (r as usize) < n));
    if model_only {
        // SAFETY: as this function.
        return unsafe { get_float64_of_model::<M>(c, vr, nvr, values, n_values) };
    }
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, Call::GetFloat64, |inst| {
            scalars(nvr, n_values)?;
            let vrs = slice(vr, nvr, "vr")?;
            let out = slice_mut(values, nvr, "values")?;
            let mut z: Option<Vec<f64>> = None;
            for (o, &r) in out.iter_mut().zip(vrs) {
                let r = r as usize;
                *o = if r < n {
                    let mut x = [0.0];
                    inst.read_reals(&[r as u32], &mut x)?;
                    x[0]
                } else if r == n {
                    inst.time
                } else if r - n - 1 < M::EVENT_INDICATORS && lists_indicators(inst) {
                    if z.is_none() {
                        z = Some(inst.event_indicators()?);
                    }
                    z.as_ref().expect("computed")[r - n - 1]
                } else {
                    return Err(format!("unknown value reference {r}"));
                };
            }
            Ok(Status::Ok)
        })
    }
}

/// Does this FMU list event-indicator variables? Those of Model Exchange: a model with
/// continuous states, and a tailored FMU that keeps them (as `md::xml3` writes it).
fn lists_indicators<M: Model>(inst: &crate::fmi2::runtime::Instance<M>) -> bool {
    M::STATES > 0
        && (inst.scene.as_ref())
            .is_none_or(|t| t.variables.iter().any(|(_, v)| v.derivative.is_some()))
}

/// The FMI 3.0 value types the models have, and those they do not (no variable has their
/// access bit, so a call of theirs is refused naming the variable's type).
pub mod kinds {
    use super::*;
    use crate::fmi2::runtime::access;

    pub const FLOAT64: Kind = Kind::new("Float64", access::REAL, |t| t == VarType::Real);
    pub const INT32: Kind = Kind::new("Int32", access::INT32, |t| t == VarType::Integer);
    pub const INT64: Kind = Kind::new("Int64", access::INT64, |t| {
        matches!(t, VarType::Enumeration(_))
    });
    pub const BOOLEAN: Kind = crate::fmi2::runtime::BOOLEAN;
    /// A type no variable has.
    pub const fn none(name: &'static str) -> Kind {
        Kind::new(name, access::STRING, |_| false)
    }
}

crate::__get_set_calls! {
    /// `fmi3GetFloat64` of the model's variables ([`get_float64`]).
    get_float64_of_model(*mut Float64, n_values) = get(GetFloat64, kinds::FLOAT64, |x| x);
    /// `fmi3GetInt32` (Integer variables).
    get_int32(*mut Int32, n_values) = get(GetInt32, kinds::INT32, |x| x as Int32);
    /// `fmi3GetInt64` (Enumeration variables).
    get_int64(*mut Int64, n_values) = get(GetInt64, kinds::INT64, |x| x as Int64);
    /// `fmi3GetBoolean`.
    get_boolean(*mut Boolean, n_values) = get(GetBoolean, kinds::BOOLEAN, |x| Boolean::from(x != 0.0));
    /// `fmi3GetFloat32`: no variable has this type.
    get_float32(*mut Float32, n_values) = get(GetFloat32, kinds::none("Float32"), |_| 0.0);
    /// `fmi3GetInt8`: no variable has this type.
    get_int8(*mut Int8, n_values) = get(GetInt8, kinds::none("Int8"), |_| 0);
    /// `fmi3GetUInt8`: no variable has this type.
    get_uint8(*mut UInt8, n_values) = get(GetUInt8, kinds::none("UInt8"), |_| 0);
    /// `fmi3GetInt16`: no variable has this type.
    get_int16(*mut Int16, n_values) = get(GetInt16, kinds::none("Int16"), |_| 0);
    /// `fmi3GetUInt16`: no variable has this type.
    get_uint16(*mut UInt16, n_values) = get(GetUInt16, kinds::none("UInt16"), |_| 0);
    /// `fmi3GetUInt32`: no variable has this type.
    get_uint32(*mut UInt32, n_values) = get(GetUInt32, kinds::none("UInt32"), |_| 0);
    /// `fmi3GetUInt64`: no variable has this type.
    get_uint64(*mut UInt64, n_values) = get(GetUInt64, kinds::none("UInt64"), |_| 0);
    /// `fmi3GetString`: no variable has this type.
    get_string(*mut FmiString, n_values) = get(GetString, kinds::none("String"), |_| std::ptr::null());
    /// `fmi3SetFloat64`: non-finite values are refused and the previous values kept.
    set_float64(*const Float64, n_values) = set(SetFloat64, kinds::FLOAT64, |v| v.into());
    /// `fmi3SetInt32` (Integer variables).
    set_int32(*const Int32, n_values) = set(SetInt32, kinds::INT32, |v| to_f64(v, |&x| x.into()));
    /// `fmi3SetInt64` (Enumeration variables; a value that is no item is refused).
    set_int64(*const Int64, n_values) = set(SetInt64, kinds::INT64, |v| to_f64(v, |&x| x as f64));
    /// `fmi3SetBoolean`.
    set_boolean(*const Boolean, n_values) = set(SetBoolean, kinds::BOOLEAN, |v| {
        to_f64(v, |&x| if x != FALSE { 1.0 } else { 0.0 })
    });
    /// `fmi3SetFloat32`: no variable has this type.
    set_float32(*const Float32, n_values) = set(SetFloat32, kinds::none("Float32"), zeros);
    /// `fmi3SetInt8`: no variable has this type.
    set_int8(*const Int8, n_values) = set(SetInt8, kinds::none("Int8"), zeros);
    /// `fmi3SetUInt8`: no variable has this type.
    set_uint8(*const UInt8, n_values) = set(SetUInt8, kinds::none("UInt8"), zeros);
    /// `fmi3SetInt16`: no variable has this type.
    set_int16(*const Int16, n_values) = set(SetInt16, kinds::none("Int16"), zeros);
    /// `fmi3SetUInt16`: no variable has this type.
    set_uint16(*const UInt16, n_values) = set(SetUInt16, kinds::none("UInt16"), zeros);
    /// `fmi3SetUInt32`: no variable has this type.
    set_uint32(*const UInt32, n_values) = set(SetUInt32, kinds::none("UInt32"), zeros);
    /// `fmi3SetUInt64`: no variable has this type.
    set_uint64(*const UInt64, n_values) = set(SetUInt64, kinds::none("UInt64"), zeros);
    /// `fmi3SetString`: no variable has this type.
    set_string(*const FmiString, n_values) = set(SetString, kinds::none("String"), zeros);
}

fn to_f64<T>(v: &[T], f: impl Fn(&T) -> f64) -> Cow<'_, [f64]> {
    v.iter().map(f).collect()
}

fn zeros<T>(v: &[T]) -> Cow<'_, [f64]> {
    vec![0.0; v.len()].into()
}

/// `fmi3GetBinary`: no variable has this type.
///
/// # Safety
/// As [`entry`]; arrays hold `nvr` elements.
pub unsafe fn get_binary<M: Model>(
    c: Instance,
    vr: *const ValueReference,
    nvr: usize,
    _sizes: *mut usize,
    values: *mut Binary,
    n_values: usize,
) -> Status {
    // SAFETY: as this function.
    unsafe { get_typeless::<M, _>(c, Call::GetBinary, vr, nvr, values, n_values, "Binary") }
}

/// `fmi3SetBinary`: no variable has this type.
///
/// # Safety
/// As [`entry`]; arrays hold `nvr` elements.
pub unsafe fn set_binary<M: Model>(
    c: Instance,
    vr: *const ValueReference,
    nvr: usize,
    _sizes: *const usize,
    values: *const Binary,
    n_values: usize,
) -> Status {
    let v = values as *mut Binary;
    // SAFETY: as this function (the array is only checked, never written).
    unsafe { get_typeless::<M, _>(c, Call::SetBinary, vr, nvr, v, n_values, "Binary") }
}

/// `fmi3GetClock` and `fmi3SetClock`: this FMU has no clocks.
///
/// # Safety
/// As [`entry`]; arrays hold `nvr` elements.
pub unsafe fn clock<M: Model>(
    c: Instance,
    call: Call,
    vr: *const ValueReference,
    nvr: usize,
    values: *mut Clock,
) -> Status {
    // SAFETY: as this function.
    unsafe { get_typeless::<M, _>(c, call, vr, nvr, values, nvr, "Clock") }
}

/// A call on a type no variable has: the arrays checked, then every value reference refused
/// naming its variable's type (none at `nvr` = 0).
///
/// # Safety
/// As [`entry`]; arrays hold `nvr` elements.
unsafe fn get_typeless<M: Model, T>(
    c: Instance,
    call: Call,
    vr: *const ValueReference,
    nvr: usize,
    values: *mut T,
    n_values: usize,
    ty: &'static str,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            scalars(nvr, n_values)?;
            let vrs = slice(vr, nvr, "valueReferences")?;
            slice_mut(values, nvr, "values")?;
            inst.refuse_type(vrs, kinds::none(ty))
        })
    }
}

/// `fmi3GetDirectionalDerivative` (`adjoint` false) and `fmi3GetAdjointDerivative` (true): the
/// runtime's exact partial derivatives ([`crate::fmi2::runtime::Instance::partial_derivatives`]).
/// A directional derivative's seed has one value per known and its sensitivity one per
/// unknown; an adjoint's the other way round.
///
/// # Safety
/// As [`entry`]; the arrays hold the elements their counts say (checked for NULL).
#[allow(clippy::too_many_arguments)]
pub unsafe fn partial_derivative<M: Model>(
    adjoint: bool,
    c: Instance,
    unknowns: *const ValueReference,
    n_unknowns: usize,
    knowns: *const ValueReference,
    n_knowns: usize,
    seed: *const Float64,
    n_seed: usize,
    sensitivity: *mut Float64,
    n_sensitivity: usize,
) -> Status {
    let (call, n_in, n_out, what) = if adjoint {
        let what = ("nSeed = nUnknowns", "nSensitivity = nKnowns");
        (Call::GetAdjointDerivative, n_unknowns, n_knowns, what)
    } else {
        let what = ("nSeed = nKnowns", "nSensitivity = nUnknowns");
        (Call::GetDirectionalDerivative, n_knowns, n_unknowns, what)
    };
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            for (n, expected, rule) in [(n_seed, n_in, what.0), (n_sensitivity, n_out, what.1)] {
                if n != expected {
                    return Err(format!("{rule} is required; got {n} for {expected}"));
                }
            }
            let u = slice(unknowns, n_unknowns, "unknowns")?;
            let k = slice(knowns, n_knowns, "knowns")?;
            let s = slice(seed, n_seed, "seed")?;
            let o = slice_mut(sensitivity, n_sensitivity, "sensitivity")?;
            inst.partial_derivatives(adjoint, u, k, s, o)?;
            Ok(Status::Ok)
        })
    }
}
