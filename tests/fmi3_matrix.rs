//! The FMI 3.0 call-sequence matrix of the catalog's FMUs, through the C ABI: every FMI 3.0
//! function in every reachable state of a Co-Simulation instance (Event Mode included) and of a
//! Model Exchange instance, refused as "not allowed in state ..." exactly where `fmi3::state`
//! says; and Model Exchange through FMI 3.0 equal to FMI 2.0's bit for bit.

mod common;

use bindery_fmu::catalog::{self};
use bindery_fmu::fmi2::state::{ME_STATES, MeState, State};
use bindery_fmu::fmi3::state::{Call, EVENT_MODE, allowed_in, me_allowed};
use bindery_fmu::fmi3::types::*;
use bindery_fmu::model::VarType;
use common::Fmu;
use common::fmi3::*;
use libloading::Symbol;
use std::ptr::{null, null_mut};

type Invoke = fn(&Inst3) -> Status;

/// Calls an FMI 3.0 function with the given argument types and values after the instance.
macro_rules! call {
    ($name:literal $(, $t:ty = $v:expr)*) => {
        {
            fn invoke(i: &Inst3) -> Status {
                let f: Symbol<unsafe extern "C" fn(Instance $(, $t)*) -> Status> =
                    i.fmu.sym($name);
                unsafe { f(i.c $(, $v)*) }
            }
            invoke as Invoke
        }
    };
}

/// Every FMI 3.0 function that takes an instance, with its call and a call of it with valid
/// arguments (no values: a get or set of no variable; the FMU-state calls on a NULL state
/// where a state is read, which the call refuses, legal or not).
fn rows() -> Vec<(&'static str, Call, Invoke)> {
    vec![
        (
            "fmi3SetDebugLogging",
            Call::SetDebugLogging,
            call!("fmi3SetDebugLogging", Boolean = TRUE, usize = 0, *const FmiString = null()),
        ),
        (
            "fmi3EnterInitializationMode",
            Call::EnterInitializationMode,
            call!(
                "fmi3EnterInitializationMode",
                Boolean = FALSE,
                f64 = 0.0,
                f64 = 0.0,
                Boolean = FALSE,
                f64 = 0.0
            ),
        ),
        (
            "fmi3ExitInitializationMode",
            Call::ExitInitializationMode,
            call!("fmi3ExitInitializationMode"),
        ),
        (
            "fmi3EnterEventMode",
            Call::EnterEventMode,
            call!("fmi3EnterEventMode"),
        ),
        ("fmi3Terminate", Call::Terminate, call!("fmi3Terminate")),
        ("fmi3Reset", Call::Reset, call!("fmi3Reset")),
        (
            "fmi3GetFloat32",
            Call::GetFloat32,
            call!("fmi3GetFloat32", *const u32 = null(), usize = 0, *mut f32 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetFloat64",
            Call::GetFloat64,
            call!("fmi3GetFloat64", *const u32 = null(), usize = 0, *mut f64 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetInt8",
            Call::GetInt8,
            call!("fmi3GetInt8", *const u32 = null(), usize = 0, *mut i8 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetUInt8",
            Call::GetUInt8,
            call!("fmi3GetUInt8", *const u32 = null(), usize = 0, *mut u8 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetInt16",
            Call::GetInt16,
            call!("fmi3GetInt16", *const u32 = null(), usize = 0, *mut i16 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetUInt16",
            Call::GetUInt16,
            call!("fmi3GetUInt16", *const u32 = null(), usize = 0, *mut u16 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetInt32",
            Call::GetInt32,
            call!("fmi3GetInt32", *const u32 = null(), usize = 0, *mut i32 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetUInt32",
            Call::GetUInt32,
            call!("fmi3GetUInt32", *const u32 = null(), usize = 0, *mut u32 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetInt64",
            Call::GetInt64,
            call!("fmi3GetInt64", *const u32 = null(), usize = 0, *mut i64 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetUInt64",
            Call::GetUInt64,
            call!("fmi3GetUInt64", *const u32 = null(), usize = 0, *mut u64 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetBoolean",
            Call::GetBoolean,
            call!("fmi3GetBoolean", *const u32 = null(), usize = 0, *mut u8 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetString",
            Call::GetString,
            call!("fmi3GetString", *const u32 = null(), usize = 0, *mut FmiString = null_mut(), usize = 0),
        ),
        (
            "fmi3GetBinary",
            Call::GetBinary,
            call!("fmi3GetBinary", *const u32 = null(), usize = 0, *mut usize = null_mut(), *mut Binary = null_mut(), usize = 0),
        ),
        (
            "fmi3GetClock",
            Call::GetClock,
            call!("fmi3GetClock", *const u32 = null(), usize = 0, *mut u8 = null_mut()),
        ),
        (
            "fmi3SetFloat32",
            Call::SetFloat32,
            call!("fmi3SetFloat32", *const u32 = null(), usize = 0, *const f32 = null(), usize = 0),
        ),
        (
            "fmi3SetFloat64",
            Call::SetFloat64,
            call!("fmi3SetFloat64", *const u32 = null(), usize = 0, *const f64 = null(), usize = 0),
        ),
        (
            "fmi3SetInt8",
            Call::SetInt8,
            call!("fmi3SetInt8", *const u32 = null(), usize = 0, *const i8 = null(), usize = 0),
        ),
        (
            "fmi3SetUInt8",
            Call::SetUInt8,
            call!("fmi3SetUInt8", *const u32 = null(), usize = 0, *const u8 = null(), usize = 0),
        ),
        (
            "fmi3SetInt16",
            Call::SetInt16,
            call!("fmi3SetInt16", *const u32 = null(), usize = 0, *const i16 = null(), usize = 0),
        ),
        (
            "fmi3SetUInt16",
            Call::SetUInt16,
            call!("fmi3SetUInt16", *const u32 = null(), usize = 0, *const u16 = null(), usize = 0),
        ),
        (
            "fmi3SetInt32",
            Call::SetInt32,
            call!("fmi3SetInt32", *const u32 = null(), usize = 0, *const i32 = null(), usize = 0),
        ),
        (
            "fmi3SetUInt32",
            Call::SetUInt32,
            call!("fmi3SetUInt32", *const u32 = null(), usize = 0, *const u32 = null(), usize = 0),
        ),
        (
            "fmi3SetInt64",
            Call::SetInt64,
            call!("fmi3SetInt64", *const u32 = null(), usize = 0, *const i64 = null(), usize = 0),
        ),
        (
            "fmi3SetUInt64",
            Call::SetUInt64,
            call!("fmi3SetUInt64", *const u32 = null(), usize = 0, *const u64 = null(), usize = 0),
        ),
        (
            "fmi3SetBoolean",
            Call::SetBoolean,
            call!("fmi3SetBoolean", *const u32 = null(), usize = 0, *const u8 = null(), usize = 0),
        ),
        (
            "fmi3SetString",
            Call::SetString,
            call!("fmi3SetString", *const u32 = null(), usize = 0, *const FmiString = null(), usize = 0),
        ),
        (
            "fmi3SetBinary",
            Call::SetBinary,
            call!("fmi3SetBinary", *const u32 = null(), usize = 0, *const usize = null(), *const Binary = null(), usize = 0),
        ),
        (
            "fmi3SetClock",
            Call::SetClock,
            call!("fmi3SetClock", *const u32 = null(), usize = 0, *const u8 = null()),
        ),
        (
            "fmi3GetNumberOfVariableDependencies",
            Call::GetNumberOfVariableDependencies,
            call!("fmi3GetNumberOfVariableDependencies", u32 = 0, *mut usize = null_mut()),
        ),
        (
            "fmi3GetVariableDependencies",
            Call::GetVariableDependencies,
            call!("fmi3GetVariableDependencies", u32 = 0, *mut usize = null_mut(), *mut u32 = null_mut(), *mut usize = null_mut(), *mut DependencyKind = null_mut(), usize = 0),
        ),
        (
            "fmi3GetFMUState",
            Call::GetFMUState,
            call!("fmi3GetFMUState", *mut FMUState = null_mut()),
        ),
        (
            "fmi3SetFMUState",
            Call::SetFMUState,
            call!("fmi3SetFMUState", FMUState = null_mut()),
        ),
        (
            "fmi3FreeFMUState",
            Call::FreeFMUState,
            call!("fmi3FreeFMUState", *mut FMUState = null_mut()),
        ),
        (
            "fmi3SerializedFMUStateSize",
            Call::SerializedFMUStateSize,
            call!("fmi3SerializedFMUStateSize", FMUState = null_mut(), *mut usize = null_mut()),
        ),
        (
            "fmi3SerializeFMUState",
            Call::SerializeFMUState,
            call!("fmi3SerializeFMUState", FMUState = null_mut(), *mut u8 = null_mut(), usize = 0),
        ),
        (
            "fmi3DeserializeFMUState",
            Call::DeserializeFMUState,
            call!("fmi3DeserializeFMUState", *const u8 = null(), usize = 0, *mut FMUState = null_mut()),
        ),
        (
            "fmi3GetDirectionalDerivative",
            Call::GetDirectionalDerivative,
            call!("fmi3GetDirectionalDerivative", *const u32 = null(), usize = 0, *const u32 = null(), usize = 0, *const f64 = null(), usize = 0, *mut f64 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetAdjointDerivative",
            Call::GetAdjointDerivative,
            call!("fmi3GetAdjointDerivative", *const u32 = null(), usize = 0, *const u32 = null(), usize = 0, *const f64 = null(), usize = 0, *mut f64 = null_mut(), usize = 0),
        ),
        (
            "fmi3EnterConfigurationMode",
            Call::EnterConfigurationMode,
            call!("fmi3EnterConfigurationMode"),
        ),
        (
            "fmi3ExitConfigurationMode",
            Call::ExitConfigurationMode,
            call!("fmi3ExitConfigurationMode"),
        ),
        (
            "fmi3GetIntervalDecimal",
            Call::GetIntervalDecimal,
            call!("fmi3GetIntervalDecimal", *const u32 = null(), usize = 0, *mut f64 = null_mut(), *mut IntervalQualifier = null_mut()),
        ),
        (
            "fmi3GetIntervalFraction",
            Call::GetIntervalFraction,
            call!("fmi3GetIntervalFraction", *const u32 = null(), usize = 0, *mut u64 = null_mut(), *mut u64 = null_mut(), *mut IntervalQualifier = null_mut()),
        ),
        (
            "fmi3GetShiftDecimal",
            Call::GetShiftDecimal,
            call!("fmi3GetShiftDecimal", *const u32 = null(), usize = 0, *mut f64 = null_mut()),
        ),
        (
            "fmi3GetShiftFraction",
            Call::GetShiftFraction,
            call!("fmi3GetShiftFraction", *const u32 = null(), usize = 0, *mut u64 = null_mut(), *mut u64 = null_mut()),
        ),
        (
            "fmi3SetIntervalDecimal",
            Call::SetIntervalDecimal,
            call!("fmi3SetIntervalDecimal", *const u32 = null(), usize = 0, *const f64 = null()),
        ),
        (
            "fmi3SetIntervalFraction",
            Call::SetIntervalFraction,
            call!("fmi3SetIntervalFraction", *const u32 = null(), usize = 0, *const u64 = null(), *const u64 = null()),
        ),
        (
            "fmi3SetShiftDecimal",
            Call::SetShiftDecimal,
            call!("fmi3SetShiftDecimal", *const u32 = null(), usize = 0, *const f64 = null()),
        ),
        (
            "fmi3SetShiftFraction",
            Call::SetShiftFraction,
            call!("fmi3SetShiftFraction", *const u32 = null(), usize = 0, *const u64 = null(), *const u64 = null()),
        ),
        (
            "fmi3EvaluateDiscreteStates",
            Call::EvaluateDiscreteStates,
            call!("fmi3EvaluateDiscreteStates"),
        ),
        (
            "fmi3UpdateDiscreteStates",
            Call::UpdateDiscreteStates,
            call!("fmi3UpdateDiscreteStates", *mut u8 = null_mut(), *mut u8 = null_mut(), *mut u8 = null_mut(), *mut u8 = null_mut(), *mut u8 = null_mut(), *mut f64 = null_mut()),
        ),
        (
            "fmi3EnterContinuousTimeMode",
            Call::EnterContinuousTimeMode,
            call!("fmi3EnterContinuousTimeMode"),
        ),
        (
            "fmi3CompletedIntegratorStep",
            Call::CompletedIntegratorStep,
            call!("fmi3CompletedIntegratorStep", Boolean = TRUE, *mut u8 = null_mut(), *mut u8 = null_mut()),
        ),
        (
            "fmi3SetTime",
            Call::SetTime,
            call!("fmi3SetTime", f64 = 0.0),
        ),
        (
            "fmi3SetContinuousStates",
            Call::SetContinuousStates,
            call!("fmi3SetContinuousStates", *const f64 = null(), usize = 0),
        ),
        (
            "fmi3GetContinuousStateDerivatives",
            Call::GetContinuousStateDerivatives,
            call!("fmi3GetContinuousStateDerivatives", *mut f64 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetEventIndicators",
            Call::GetEventIndicators,
            call!("fmi3GetEventIndicators", *mut f64 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetContinuousStates",
            Call::GetContinuousStates,
            call!("fmi3GetContinuousStates", *mut f64 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetNominalsOfContinuousStates",
            Call::GetNominalsOfContinuousStates,
            call!("fmi3GetNominalsOfContinuousStates", *mut f64 = null_mut(), usize = 0),
        ),
        (
            "fmi3GetNumberOfEventIndicators",
            Call::GetNumberOfEventIndicators,
            call!("fmi3GetNumberOfEventIndicators", *mut usize = null_mut()),
        ),
        (
            "fmi3GetNumberOfContinuousStates",
            Call::GetNumberOfContinuousStates,
            call!("fmi3GetNumberOfContinuousStates", *mut usize = null_mut()),
        ),
        (
            "fmi3EnterStepMode",
            Call::EnterStepMode,
            call!("fmi3EnterStepMode"),
        ),
        (
            "fmi3GetOutputDerivatives",
            Call::GetOutputDerivatives,
            call!("fmi3GetOutputDerivatives", *const u32 = null(), usize = 0, *const i32 = null(), *mut f64 = null_mut(), usize = 0),
        ),
        (
            "fmi3DoStep",
            Call::DoStep,
            call!("fmi3DoStep", f64 = 0.0, f64 = 1e-3, Boolean = TRUE, *mut u8 = null_mut(), *mut u8 = null_mut(), *mut u8 = null_mut(), *mut f64 = null_mut()),
        ),
        (
            "fmi3ActivateModelPartition",
            Call::ActivateModelPartition,
            call!("fmi3ActivateModelPartition", u32 = 0, f64 = 0.0),
        ),
    ]
}

/// The states an FMI 3.0 Co-Simulation instance of these FMUs can be in: the runtime's, for
/// either version.
const STATES: [State; 6] = common::REACHABLE_STATES;

/// Drives a fresh instance into `state`: by legal calls, or (Step Discarded, Error) by
/// restoring a serialized state whose state code says so.
fn drive_to(i: &Inst3, state: State) {
    match state {
        State::Instantiated => {}
        State::InitializationMode => i.ok(i.enter_init(0.0, None), "enter"),
        State::StepComplete => i.ok(i.init(), "init"),
        State::Terminated => {
            i.ok(i.init(), "init");
            i.ok(i.call0("fmi3Terminate"), "terminate");
        }
        State::StepFailed | State::Error => {
            let probe = i.fmu.instance("probe");
            probe.ok(probe.init(), "init");
            let mut bytes = probe.state_bytes();
            bytes[24..26].copy_from_slice(&state.code().to_le_bytes());
            i.restore_bytes(&bytes);
        }
        other => panic!("no way to reach {other:?}"),
    }
}

/// Every FMI 3.0 function in every reachable state (Event Mode on an instance that uses it):
/// refused as "not allowed in state ..." exactly where the table says it is illegal (a legal
/// call may still be refused for its arguments or because the FMU does not offer it, with
/// another reason); never a crash.
#[test]
fn fmi3_call_sequence_matrix() {
    let e = &catalog::all()[0];
    let f3 = Fmu3::of(e);
    let mut checked = 0;
    let states: Vec<(Option<State>, u16)> = (STATES.iter())
        .map(|&s| (Some(s), s as u16))
        .chain([(None, EVENT_MODE)])
        .collect();
    for (name, call, invoke) in rows() {
        for &(state, bits) in &states {
            let i = match state {
                Some(state) => {
                    let i = f3.instance("matrix");
                    drive_to(&i, state);
                    i
                }
                None => {
                    let i = f3.instance_with("matrix", true, true);
                    i.ok(i.init(), "init into Event Mode");
                    i
                }
            };
            let before = i.logs().len();
            let st = invoke(&i);
            let logs = i.logs();
            let illegal = logs[before..]
                .iter()
                .any(|l| l.2.contains("is not allowed in state"));
            if allowed_in(call, bits) {
                assert!(!illegal, "{name} in {state:?}: {:?}", &logs[before..]);
            } else {
                assert_eq!(st, Status::Error, "{name} in {state:?}");
                assert!(illegal, "{name} in {state:?}: {:?}", &logs[before..]);
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 70 * states.len());
    assert_eq!(rows().len(), bindery_fmu::fmi3::state::LEGAL.len() - 1);
}

/// The Model Exchange column of the table: every FMI 3.0 function in every state of a Model
/// Exchange instance, refused as "not allowed" exactly where `fmi3::state` says.
#[test]
fn fmi3_model_exchange_call_sequence_matrix() {
    let e = &catalog::all()[0];
    let f3 = Fmu3::of(e);
    let mut checked = 0;
    for (name, call, invoke) in rows() {
        for state in ME_STATES {
            let i = f3.me_instance("me-matrix");
            match state {
                MeState::Instantiated => {}
                MeState::InitializationMode => i.ok(i.enter_init(0.0, None), "enter"),
                MeState::EventMode => i.ok(i.init(), "init"),
                MeState::ContinuousTimeMode => {
                    i.ok(i.init(), "init");
                    i.ok(i.call0("fmi3EnterContinuousTimeMode"), "ct");
                }
                MeState::Terminated => {
                    i.ok(i.init(), "init");
                    i.ok(i.call0("fmi3Terminate"), "terminate");
                }
                MeState::Error => {
                    let probe = f3.me_instance("probe");
                    probe.ok(probe.init(), "init");
                    let mut bytes = probe.state_bytes();
                    bytes[24..26].copy_from_slice(&State::Error.code().to_le_bytes());
                    i.restore_bytes(&bytes);
                }
            }
            let before = i.logs().len();
            let st = invoke(&i);
            let logs = i.logs();
            let illegal = (logs[before..].iter()).any(|l| l.2.contains("is not allowed in state"));
            if me_allowed(call, state) {
                assert!(!illegal, "{name} in {state:?}: {:?}", &logs[before..]);
            } else {
                assert_eq!(st, Status::Error, "{name} in {state:?}");
                assert!(illegal, "{name} in {state:?}: {:?}", &logs[before..]);
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 70 * ME_STATES.len());
}

/// Model Exchange through FMI 3.0 gives FMI 2.0's bits: the same calls (time, states,
/// derivatives, event indicators, completed steps, an event) on both interfaces of every model
/// with states, at its highest level.
#[test]
fn fmi3_model_exchange_equals_fmi2() {
    for e in catalog::all() {
        if !vars(&e).iter().any(|(_, v)| v.derivative.is_some()) {
            continue;
        }
        let (f2, f3) = (Fmu::of(&e), Fmu3::of(&e));
        let s2 = f2.me_instance("fmi2");
        let i3 = f3.me_instance("fmi3");
        s2.ok(s2.setup(0.0, None), "setup");
        if let Some(fid) = vr_of(&e, "model.fidelity") {
            s2.ok(s2.set_integer(&[fid], &[3]), "level");
            i3.ok(i3.set("fmi3SetInt64", &[fid], &[3i64]), "level");
        }
        s2.ok(s2.init(), "init");
        i3.ok(i3.init(), "init");
        let nx = vars(&e)
            .iter()
            .filter(|(_, v)| v.derivative.is_some())
            .count();
        let nz = {
            let mut n = 0usize;
            let f: Symbol<unsafe extern "C" fn(Instance, *mut usize) -> Status> =
                f3.sym("fmi3GetNumberOfEventIndicators");
            i3.ok(unsafe { f(i3.c, &mut n) }, "number of indicators");
            n
        };
        let arr2 = |name: &str, n: usize| s2.get_array(name, n);
        let arr3 = |name: &str, n: usize| -> Vec<f64> {
            let f: Symbol<unsafe extern "C" fn(Instance, *mut f64, usize) -> Status> = f3.sym(name);
            let mut v = vec![0.0; n];
            i3.ok(unsafe { f(i3.c, v.as_mut_ptr(), n) }, name);
            v
        };
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        s2.ok(s2.call0("fmi2EnterContinuousTimeMode"), "ct");
        i3.ok(i3.call0("fmi3EnterContinuousTimeMode"), "ct");
        // forward Euler below the stiffest chain's limit (DiscKnifeDrive's rod)
        let h = 5e-6;
        let mut t = 0.0;
        for _ in 0..200 {
            let x2 = arr2("fmi2GetContinuousStates", nx).1;
            let x3 = arr3("fmi3GetContinuousStates", nx);
            assert_eq!(bits(&x2), bits(&x3), "{} states at {t}", e.identifier);
            let d2 = arr2("fmi2GetDerivatives", nx).1;
            let d3 = arr3("fmi3GetContinuousStateDerivatives", nx);
            assert_eq!(bits(&d2), bits(&d3), "{} derivatives at {t}", e.identifier);
            let z2 = arr2("fmi2GetEventIndicators", nz).1;
            let z3 = arr3("fmi3GetEventIndicators", nz);
            assert_eq!(bits(&z2), bits(&z3), "{} indicators at {t}", e.identifier);
            // the event indicators are variables too (after time)
            let n = vars(&e).len() as u32;
            let zvrs: Vec<u32> = (0..nz as u32).map(|j| n + 1 + j).collect();
            let (st, zv) = i3.get::<f64>("fmi3GetFloat64", &zvrs);
            i3.ok(st, "indicators as variables");
            assert_eq!(bits(&zv), bits(&z3), "{}", e.identifier);
            assert_eq!(i3.get::<f64>("fmi3GetFloat64", &[n]).1, vec![t], "time");
            // forward Euler on both
            let x: Vec<f64> = x2.iter().zip(&d2).map(|(x, d)| x + h * d).collect();
            s2.ok(s2.set_time(t + h), "time");
            s2.ok(s2.set_states(&x), "states");
            s2.ok(s2.completed_step().0, "completed");
            let f: Symbol<unsafe extern "C" fn(Instance, f64) -> Status> = f3.sym("fmi3SetTime");
            i3.ok(unsafe { f(i3.c, t + h) }, "time");
            let f: Symbol<unsafe extern "C" fn(Instance, *const f64, usize) -> Status> =
                f3.sym("fmi3SetContinuousStates");
            i3.ok(unsafe { f(i3.c, x.as_ptr(), nx) }, "states");
            let f: Symbol<unsafe extern "C" fn(Instance, u8, *mut u8, *mut u8) -> Status> =
                f3.sym("fmi3CompletedIntegratorStep");
            let (mut ev, mut term) = (7u8, 7u8);
            i3.ok(unsafe { f(i3.c, TRUE, &mut ev, &mut term) }, "completed");
            assert_eq!((ev, term), (0, 0));
            let reals = of_type(&e, |t| t == VarType::Real);
            assert_eq!(
                bits(&s2.get_real(&reals).1),
                bits(&i3.get::<f64>("fmi3GetFloat64", &reals).1),
                "{} outputs at {}",
                e.identifier,
                t + h
            );
            t += h;
        }
        // an event on both
        s2.ok(s2.call0("fmi2EnterEventMode"), "event");
        i3.ok(i3.call0("fmi3EnterEventMode"), "event");
        s2.event_iteration();
        let (st, flags, _) = i3.update_discrete_states();
        i3.ok(st, "update");
        assert_eq!(flags, [false; 5]);
        let reals = of_type(&e, |t| t == VarType::Real);
        assert_eq!(
            bits(&s2.get_real(&reals).1),
            bits(&i3.get::<f64>("fmi3GetFloat64", &reals).1),
            "{} after the event",
            e.identifier
        );
    }
}
