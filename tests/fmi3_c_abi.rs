//! The FMI 3.0 interface of every FMU of the catalog, through the C ABI: the binary exports
//! every FMI 3.0 function; its outputs equal the FMI 2.0 interface's bit for bit over the
//! cross-check inputs at every level; an FMU state replays bit for bit; the call-sequence matrix
//! (every function in every reachable state) follows `fmi3::state`; NULL, freed and foreign
//! handles, bad arguments, wrong types and a tampered serialized state are refused with the
//! reason and change nothing; instantiation asks what this interface offers.

mod common;

use bindery_fmu::catalog::{self, Entry};
use bindery_fmu::fmi2::state::{ME_STATES, MeState, State};
use bindery_fmu::fmi3::state::{Call, EVENT_MODE, allowed_in, me_allowed};
use bindery_fmu::fmi3::types::*;
use bindery_fmu::model::{Causality, Var, VarType};
use common::Fmu;
use common::fmi3::*;
use libloading::Symbol;
use std::ptr::{null, null_mut};

/// Every FMI 3.0 function (`fmi3Functions.h`).
const FMI3_FUNCTIONS: &[&str] = &[
    "fmi3GetVersion",
    "fmi3SetDebugLogging",
    "fmi3InstantiateModelExchange",
    "fmi3InstantiateCoSimulation",
    "fmi3InstantiateScheduledExecution",
    "fmi3FreeInstance",
    "fmi3EnterInitializationMode",
    "fmi3ExitInitializationMode",
    "fmi3EnterEventMode",
    "fmi3Terminate",
    "fmi3Reset",
    "fmi3GetFloat32",
    "fmi3GetFloat64",
    "fmi3GetInt8",
    "fmi3GetUInt8",
    "fmi3GetInt16",
    "fmi3GetUInt16",
    "fmi3GetInt32",
    "fmi3GetUInt32",
    "fmi3GetInt64",
    "fmi3GetUInt64",
    "fmi3GetBoolean",
    "fmi3GetString",
    "fmi3GetBinary",
    "fmi3GetClock",
    "fmi3SetFloat32",
    "fmi3SetFloat64",
    "fmi3SetInt8",
    "fmi3SetUInt8",
    "fmi3SetInt16",
    "fmi3SetUInt16",
    "fmi3SetInt32",
    "fmi3SetUInt32",
    "fmi3SetInt64",
    "fmi3SetUInt64",
    "fmi3SetBoolean",
    "fmi3SetString",
    "fmi3SetBinary",
    "fmi3SetClock",
    "fmi3GetNumberOfVariableDependencies",
    "fmi3GetVariableDependencies",
    "fmi3GetFMUState",
    "fmi3SetFMUState",
    "fmi3FreeFMUState",
    "fmi3SerializedFMUStateSize",
    "fmi3SerializeFMUState",
    "fmi3DeserializeFMUState",
    "fmi3GetDirectionalDerivative",
    "fmi3GetAdjointDerivative",
    "fmi3EnterConfigurationMode",
    "fmi3ExitConfigurationMode",
    "fmi3GetIntervalDecimal",
    "fmi3GetIntervalFraction",
    "fmi3GetShiftDecimal",
    "fmi3GetShiftFraction",
    "fmi3SetIntervalDecimal",
    "fmi3SetIntervalFraction",
    "fmi3SetShiftDecimal",
    "fmi3SetShiftFraction",
    "fmi3EvaluateDiscreteStates",
    "fmi3UpdateDiscreteStates",
    "fmi3EnterContinuousTimeMode",
    "fmi3CompletedIntegratorStep",
    "fmi3SetTime",
    "fmi3SetContinuousStates",
    "fmi3GetContinuousStateDerivatives",
    "fmi3GetEventIndicators",
    "fmi3GetContinuousStates",
    "fmi3GetNominalsOfContinuousStates",
    "fmi3GetNumberOfEventIndicators",
    "fmi3GetNumberOfContinuousStates",
    "fmi3EnterStepMode",
    "fmi3GetOutputDerivatives",
    "fmi3DoStep",
    "fmi3ActivateModelPartition",
];

fn vars(e: &Entry) -> Vec<(u32, &'static Var)> {
    (e.variables)()
}

fn vr_of(e: &Entry, name: &str) -> Option<u32> {
    vars(e)
        .into_iter()
        .find(|(_, v)| v.name == name)
        .map(|(vr, _)| vr)
}

/// The value references of every variable of one type.
fn of_type(e: &Entry, pred: impl Fn(VarType) -> bool) -> Vec<u32> {
    (vars(e).into_iter())
        .filter(|(_, v)| pred(v.ty))
        .map(|(vr, _)| vr)
        .collect()
}

/// The cross-check inputs of a model (`fmus/<id>/<id>_in.csv`): the input value references and
/// the rows (time, then the inputs).
fn cross_check_inputs(e: &Entry) -> (Vec<u32>, Vec<Vec<f64>>) {
    let path = format!(
        "{}/fmus/{id}/{id}_in.csv",
        env!("CARGO_MANIFEST_DIR"),
        id = e.identifier
    );
    let text = std::fs::read_to_string(&path).unwrap_or_else(|err| panic!("{path}: {err}"));
    let mut lines = text.lines();
    let names: Vec<String> = (lines.next().unwrap().split(','))
        .map(|n| n.trim_matches('"').to_string())
        .collect();
    let vrs = (names[1..].iter())
        .map(|n| vr_of(e, n).unwrap_or_else(|| panic!("{n} in {path}")))
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (vrs, rows)
}

/// The levels a model has (`model.fidelity`'s items), or none.
fn levels(e: &Entry) -> Vec<Option<i32>> {
    match vr_of(e, "model.fidelity") {
        Some(_) => vec![Some(1), Some(2), Some(3)],
        None => vec![None],
    }
}

/// Every variable's value as bits, through the FMI 2.0 interface.
fn bits2(s: &common::Slave, e: &Entry) -> Vec<u64> {
    let reals = s.get_real(&of_type(e, |t| t == VarType::Real));
    let ints = s.get_integer(&of_type(e, VarType::is_integer_like));
    let bools = s.get_boolean(&of_type(e, |t| t == VarType::Boolean));
    assert_eq!(
        (reals.0, ints.0, bools.0),
        (Status::Ok, Status::Ok, Status::Ok)
    );
    (reals.1.iter().map(|x| x.to_bits()))
        .chain(ints.1.iter().map(|&i| i as u64))
        .chain(bools.1.iter().map(|&b| b as u64))
        .collect()
}

/// The same through the FMI 3.0 interface (Integer variables by `fmi3GetInt32`, Enumerations
/// by `fmi3GetInt64`, in the value references' order as in [`bits2`]).
fn bits3(i: &Inst3, e: &Entry) -> Vec<u64> {
    let reals = i.get::<f64>("fmi3GetFloat64", &of_type(e, |t| t == VarType::Real));
    let all_ints = of_type(e, VarType::is_integer_like);
    let bools = i.get::<u8>("fmi3GetBoolean", &of_type(e, |t| t == VarType::Boolean));
    assert_eq!(
        (reals.0, bools.0),
        (Status::Ok, Status::Ok),
        "{:?}",
        i.logs()
    );
    let ints = all_ints.iter().map(|&vr| {
        let enumeration = matches!(vars(e)[vr as usize].1.ty, VarType::Enumeration(_));
        if enumeration {
            let (s, v) = i.get::<i64>("fmi3GetInt64", &[vr]);
            assert_eq!(s, Status::Ok);
            v[0] as i32 as u64
        } else {
            let (s, v) = i.get::<i32>("fmi3GetInt32", &[vr]);
            assert_eq!(s, Status::Ok);
            v[0] as u64
        }
    });
    let ints: Vec<u64> = ints.collect();
    (reals.1.iter().map(|x| x.to_bits()))
        .chain(ints)
        .chain(bools.1.iter().map(|&b| (b != 0) as u64))
        .collect()
}

/// An FMI 3.0 instance at this level, initialized from t = 0.
fn started3<'a>(f3: &'a Fmu3, e: &Entry, level: Option<i32>) -> Inst3<'a> {
    let i = f3.instance("fmi3");
    if let Some(l) = level {
        let vr = vr_of(e, "model.fidelity").unwrap();
        i.ok(i.set("fmi3SetInt64", &[vr], &[l as i64]), "fidelity");
    }
    i.ok(i.init(), "initialization");
    i
}

#[test]
fn every_fmu_exports_every_fmi3_function() {
    for e in catalog::all() {
        let f = Fmu::of(&e);
        f.assert_exports(FMI3_FUNCTIONS);
        let v: Symbol<unsafe extern "C" fn() -> FmiString> = f.sym("fmi3GetVersion");
        let version = unsafe { std::ffi::CStr::from_ptr(v()) };
        assert_eq!(version.to_str().unwrap(), "3.0");
    }
}

/// Every variable (outputs, states, calculated parameters) after every step of the cross-check
/// input, at every level: the FMI 3.0 interface gives the FMI 2.0 interface's bits.
#[test]
fn fmi3_equals_fmi2_bit_for_bit_at_every_level() {
    for e in catalog::all() {
        let (f2, f3) = (Fmu::of(&e), Fmu3::of(&e));
        let (inputs, rows) = cross_check_inputs(&e);
        for level in levels(&e) {
            let fid = level.map(|l| (vr_of(&e, "model.fidelity").unwrap(), l));
            let s2 = f2.slave("fmi2");
            s2.ok(s2.setup(0.0, None), "fmi2SetupExperiment");
            if let Some((vr, l)) = fid {
                s2.ok(s2.set_integer(&[vr], &[l]), "fidelity");
            }
            let i3 = f3.instance("fmi3");
            if let Some((vr, l)) = fid {
                i3.ok(i3.set("fmi3SetInt64", &[vr], &[i64::from(l)]), "fidelity");
            }
            if s2.init() != Status::Ok {
                // a level the model does not have: both refuse it, for the same reason
                let why = s2.last_error().replace("fmi2", "fmi3");
                assert_eq!(i3.init(), Status::Error, "{}", e.identifier);
                assert_eq!(i3.last_error(), why);
                continue;
            }
            i3.ok(i3.init(), "initialization");
            let what = format!("{} at level {level:?}", e.identifier);
            for k in 0..rows.len() - 1 {
                let (t, h) = (rows[k][0], rows[k + 1][0] - rows[k][0]);
                s2.ok(s2.set_real(&inputs, &rows[k][1..]), "fmi2SetReal");
                i3.ok(
                    i3.set("fmi3SetFloat64", &inputs, &rows[k][1..]),
                    "fmi3SetFloat64",
                );
                if k == 0 {
                    assert_eq!(bits2(&s2, &e), bits3(&i3, &e), "{what} at the start");
                }
                let st2 = s2.do_step(t, h);
                let (st3, flags, last) = i3.do_step(t, h);
                assert_eq!(st2, st3, "{what}: step {k}");
                assert_eq!(flags, [false; 3], "{what}: step {k}");
                assert_eq!(last, t + h, "{what}: lastSuccessfulTime");
                assert_eq!(bits2(&s2, &e), bits3(&i3, &e), "{what} after step {k}");
            }
        }
    }
}

/// An FMU state taken through FMI 3.0 (kept, and serialized and read back) replays the steps
/// after it bit for bit, at the elastodynamic level under `auto`.
#[test]
fn an_fmi3_fmu_state_replays_bit_for_bit() {
    for e in catalog::all() {
        let f3 = Fmu3::of(&e);
        let (inputs, rows) = cross_check_inputs(&e);
        let level = levels(&e).into_iter().rev().find(|&l| {
            let probe = f3.instance("probe");
            if let Some(l) = l {
                let vr = vr_of(&e, "model.fidelity").unwrap();
                probe.set("fmi3SetInt64", &[vr], &[i64::from(l)]);
            }
            probe.init() == Status::Ok
        });
        let i = started3(&f3, &e, level.flatten());
        let run = |from: usize, n: usize| -> Vec<Vec<u64>> {
            (from..from + n)
                .map(|k| {
                    let (t, h) = (rows[k][0], rows[k + 1][0] - rows[k][0]);
                    i.ok(i.set("fmi3SetFloat64", &inputs, &rows[k][1..]), "set");
                    i.ok(i.do_step(t, h).0, "step");
                    bits3(&i, &e)
                })
                .collect()
        };
        run(0, 100);
        let mut kept: FMUState = std::ptr::null_mut();
        i.ok(i.get_state(&mut kept), "fmi3GetFMUState");
        let bytes = i.state_bytes();
        let first = run(100, 100);
        i.ok(i.set_state(kept), "fmi3SetFMUState");
        assert_eq!(run(100, 100), first, "{}: a kept state", e.identifier);
        i.restore_bytes(&bytes);
        assert_eq!(run(100, 100), first, "{}: a serialized state", e.identifier);
        i.ok(i.free_state(&mut kept), "fmi3FreeFMUState");
    }
}

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

/// The states an FMI 3.0 Co-Simulation instance of these FMUs can be in.
const STATES: [State; 6] = [
    State::Instantiated,
    State::InitializationMode,
    State::StepComplete,
    State::StepFailed,
    State::Terminated,
    State::Error,
];

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

/// Event Mode the FMI 3.0 way: after initialization an instance that uses it is in Event Mode
/// (no step there), leaves it with `fmi3EnterStepMode`, enters it again from Step Mode;
/// `fmi3UpdateDiscreteStates` asks for nothing more. An instance that does not use it is never
/// in Event Mode and says why.
#[test]
fn event_mode_the_fmi3_way() {
    let e = &catalog::all()[0];
    let f3 = Fmu3::of(e);
    let i = f3.instance_with("events", true, false);
    i.ok(i.init(), "init");
    i.assert_refused(
        i.do_step(0.0, 1e-3).0,
        "not allowed in state Event Mode",
        "step in Event Mode",
    );
    let (st, flags, _) = i.update_discrete_states();
    i.ok(st, "update");
    assert_eq!(flags, [false; 5]);
    i.ok(i.call0("fmi3EnterStepMode"), "step mode");
    i.ok(i.do_step(0.0, 1e-3).0, "step");
    i.ok(i.call0("fmi3EnterEventMode"), "event mode");
    // an FMU state taken in Event Mode comes back in Event Mode
    let bytes = i.state_bytes();
    i.ok(i.call0("fmi3EnterStepMode"), "step mode");
    i.restore_bytes(&bytes);
    i.assert_refused(
        i.do_step(1e-3, 1e-3).0,
        "Event Mode",
        "restored into Event Mode",
    );
    let plain = f3.instance("plain");
    plain.ok(plain.init(), "init");
    plain.assert_refused(
        plain.call0("fmi3EnterEventMode"),
        "eventModeUsed was false",
        "no event mode",
    );
    plain.assert_refused(
        plain.call0("fmi3EnterStepMode"),
        "eventModeUsed was false",
        "no event mode",
    );
}

/// The event outputs' bits of an instance (those marked as events).
fn event_bits(i: &Inst3, e: &Entry) -> Vec<u64> {
    let marked: Vec<(u32, VarType)> = (vars(e).into_iter())
        .filter(|(_, v)| v.event)
        .map(|(vr, v)| (vr, v.ty))
        .collect();
    (marked.iter())
        .map(|&(vr, ty)| match ty {
            VarType::Boolean => u64::from(i.get::<u8>("fmi3GetBoolean", &[vr]).1[0]),
            _ => i.get::<i32>("fmi3GetInt32", &[vr]).1[0] as u64,
        })
        .collect()
}

/// With early return allowed, a step ends exactly at the first event inside it: at the
/// returned time an event output has its new value, a step from the same start ending a
/// nanosecond earlier still shows the old one; between events the steps are the host's.
/// SewingTable's events (early returns, or changes that fall on a step's end) are its
/// cyclogram's phase boundaries, at the angles its parameters give (82, 192, 282 and 360 deg
/// at the defaults), to 1e-9 deg.
#[test]
fn early_return_stops_exactly_at_each_event() {
    for e in catalog::all() {
        if !vars(&e).iter().any(|(_, v)| v.event) {
            continue;
        }
        let f3 = Fmu3::of(&e);
        let (inputs, rows) = cross_check_inputs(&e);
        let i = f3.instance_with("early", true, true);
        let probe = f3.instance_with("probe", true, false);
        // the Perforators' event is the roller lifting off its ramp (contact.liftoffs): at the
        // elastodynamic level above the lift-off speed (130 rpm: every turn)
        let liftoff = e.identifier == "Perforators";
        let rows = if liftoff {
            let w = 130.0 * std::f64::consts::PI / 30.0;
            let fid = vr_of(&e, "model.fidelity").unwrap();
            i.ok(i.set("fmi3SetInt64", &[fid], &[3i64]), "elastodynamic");
            probe.ok(probe.set("fmi3SetInt64", &[fid], &[3i64]), "elastodynamic");
            (0..=500)
                .map(|k| {
                    let t = k as f64 * 2e-3;
                    vec![t, w * t, w, 0.0]
                })
                .collect()
        } else {
            rows
        };
        i.ok(i.init(), "init");
        i.ok(i.call0("fmi3EnterStepMode"), "step mode");
        let input_at = |t: f64| -> Vec<f64> {
            // the cross-check rows, linear in between (constant speed: exact)
            let k = rows
                .iter()
                .rposition(|r| r[0] <= t)
                .unwrap()
                .min(rows.len() - 2);
            let f = (t - rows[k][0]) / (rows[k + 1][0] - rows[k][0]);
            (1..rows[k].len())
                .map(|j| rows[k][j] + f * (rows[k + 1][j] - rows[k][j]))
                .collect()
        };
        let (mut t, stop, h) = (0.0, rows[rows.len() - 1][0], rows[1][0] - rows[0][0]);
        let (mut events, mut changes, mut last_bits) = (vec![], vec![], None);
        // (which event output, rose) of the early returns
        let mut kinds = std::collections::BTreeSet::new();
        while t < stop - 1e-12 {
            let step = h.min(stop - t);
            i.ok(i.set("fmi3SetFloat64", &inputs, &input_at(t)), "inputs");
            let bytes = i.state_bytes();
            let before = event_bits(&i, &e);
            // the host's input at t may cross a boundary itself (it rounds to either side)
            if last_bits.as_ref().is_some_and(|b| *b != before) {
                changes.push(t);
            }
            let (st, [handling, terminate, early], last) = i.do_step(t, step);
            i.ok(st, "step");
            assert!(!terminate);
            assert_eq!(
                handling, early,
                "{}: eventHandlingNeeded with early return",
                e.identifier
            );
            if event_bits(&i, &e) != before {
                changes.push(last);
            }
            last_bits = Some(event_bits(&i, &e));
            if early {
                assert!(
                    last > t && last < t + step,
                    "{}: {last} in ({t}, {})",
                    e.identifier,
                    t + step
                );
                let after = event_bits(&i, &e);
                assert_ne!(
                    after, before,
                    "{} at {last}: no event output changed",
                    e.identifier
                );
                // a nanosecond earlier from the same start: nothing changed yet (rigid levels:
                // the event's time to a nanosecond; a lift-off: to the time the integrator
                // inside the step locates it, which moves with the step's end by its own error,
                // as the bisection's trials end at different times). Not where the host's input
                // put the step's start next to the event (a step of a few floating-point times).
                let delta = if liftoff { 1e-6 } else { 1e-9 };
                if last - t > 2.0 * delta {
                    probe.restore_bytes(&bytes);
                    probe.ok(probe.do_step(t, last - t - delta).0, "probe");
                    assert_eq!(
                        event_bits(&probe, &e),
                        before,
                        "{} just before {last}",
                        e.identifier
                    );
                }
                probe.restore_bytes(&bytes);
                probe.ok(probe.do_step(t, last - t).0, "probe");
                assert_eq!(event_bits(&probe, &e), after, "{} at {last}", e.identifier);
                events.push(last);
                for (j, (b, a)) in before.iter().zip(&after).enumerate() {
                    if b != a {
                        kinds.insert((j, a > b || (*a == 1 && *b > 1)));
                    }
                }
                i.ok(i.call0("fmi3EnterEventMode"), "event mode");
                i.ok(i.update_discrete_states().0, "update");
                i.ok(i.call0("fmi3EnterStepMode"), "step mode");
            } else {
                assert_eq!(last, t + step);
            }
            t = last;
        }
        let marked: Vec<&str> = (vars(&e).into_iter())
            .filter(|(_, v)| v.event)
            .map(|(_, v)| v.name)
            .collect();
        let seen = |name: &str, rose: bool| {
            let j = marked.iter().position(|n| *n == name).unwrap();
            kinds.contains(&(j, rose))
        };
        match e.identifier {
            // the cut's start and its cut-through, the roller entering and leaving the slots
            "GenevaKnifeDrive" => {
                for (name, rose) in [("knife.in_stack", true), ("knife.in_stack", false)] {
                    assert!(seen(name, rose), "Geneva: {name} rising {rose}: {kinds:?}");
                }
            }
            // a lift-off and a landing
            "Perforators" => {
                for (name, rose) in [("contact.open", true), ("contact.open", false)] {
                    assert!(
                        seen(name, rose),
                        "Perforators: {name} rising {rose}: {kinds:?}"
                    );
                }
            }
            _ => {}
        }
        assert!(
            !events.is_empty(),
            "{}: no event over the cross-check run",
            e.identifier
        );
        if e.identifier == "SewingTable" {
            let par = |n: &str| i.get::<f64>("fmi3GetFloat64", &[vr_of(&e, n).unwrap()]).1[0];
            let (phi0, fwd, sew, ret) = (
                par("cycle.phi0"),
                par("cycle.forward"),
                par("cycle.dwell_sew"),
                par("cycle.return"),
            );
            let w = rows[0][2];
            let turn = std::f64::consts::TAU;
            let mut expected = vec![];
            for k in 0..3 {
                for b in [fwd, fwd + sew, fwd + sew + ret, turn] {
                    let te = (phi0 + b + k as f64 * turn) / w;
                    if te > 1e-9 && te < stop + 1e-9 {
                        expected.push(te);
                    }
                }
            }
            expected.sort_by(f64::total_cmp);
            // a change at a step's end is no early return; and where the host's input at the
            // event's time rounds to the old side (the shaft angle interpolated from the input
            // file), the output changes back and again one floating-point time later: one event
            changes.dedup_by(|b, a| (*b - *a).abs() < 1e-12);
            assert_eq!(
                changes.len(),
                expected.len(),
                "{changes:?} against {expected:?}"
            );
            for (got, want) in changes.iter().zip(&expected) {
                let deg = (got - want).abs() * w.to_degrees();
                assert!(
                    deg < 1e-9,
                    "phase boundary at {got} s, expected {want} s ({deg} deg off)"
                );
            }
        }
    }
}

/// NULL, freed, made-up and another model's handles are refused without being followed.
#[test]
fn foreign_and_dead_handles_are_refused() {
    let all = catalog::all();
    let (a, b) = (Fmu3::of(&all[0]), Fmu3::of(&all[1]));
    let other = b.instance("other");
    other.ok(other.init(), "init");
    let freed = {
        let i = a.instance("freed");
        i.c
    };
    let mut x = 0u64;
    for h in [
        std::ptr::null_mut(),
        freed,
        other.c,
        &mut x as *mut u64 as Instance,
    ] {
        let fake = Inst3 {
            fmu: &a,
            c: h,
            env: 0,
        };
        assert_eq!(fake.do_step(0.0, 1e-3).0, Status::Error);
        assert_eq!(fake.get::<f64>("fmi3GetFloat64", &[0]).0, Status::Error);
        assert_eq!(fake.call0("fmi3Terminate"), Status::Error);
        std::mem::forget(fake);
        let free: Symbol<unsafe extern "C" fn(Instance)> = a.sym("fmi3FreeInstance");
        unsafe { free(h) };
    }
    // the other model's instance is untouched
    other.ok(other.do_step(0.0, 1e-3).0, "step");
}

/// Bad arguments and values: refused with the reason, nothing changed.
#[test]
fn bad_arguments_are_refused_and_change_nothing() {
    for e in catalog::all() {
        let f3 = Fmu3::of(&e);
        let i = f3.instance("bad");
        let real = of_type(&e, |t| t == VarType::Real)[0];
        let input = (vars(&e).into_iter())
            .find(|(_, v)| v.causality == Causality::Input && v.ty == VarType::Real)
            .unwrap()
            .0;
        i.ok(i.init(), "init");
        // nValues other than nvr
        type Get = unsafe extern "C" fn(Instance, *const u32, usize, *mut f64, usize) -> Status;
        let g: Symbol<Get> = f3.sym("fmi3GetFloat64");
        let mut out = [0.0; 2];
        let st = unsafe { g(i.c, &real, 1, out.as_mut_ptr(), 2) };
        i.assert_refused(st, "nValues = 2", "nValues");
        // the types the models do not have, and the wrong type
        for name in ["fmi3GetFloat32", "fmi3GetInt8", "fmi3GetUInt64"] {
            let st = match name {
                "fmi3GetFloat32" => i.get::<f32>(name, &[real]).0,
                "fmi3GetInt8" => i.get::<i8>(name, &[real]).0,
                _ => i.get::<u64>(name, &[real]).0,
            };
            i.assert_refused(st, "is not of type", name);
        }
        i.assert_refused(
            i.get::<i32>("fmi3GetInt32", &[real]).0,
            "is not of type Int32",
            "Int32",
        );
        i.assert_refused(
            i.get::<i64>("fmi3GetInt64", &[real]).0,
            "is not of type Int64",
            "Int64",
        );
        // a non-finite input is refused and the old value kept
        let old = i.get::<f64>("fmi3GetFloat64", &[input]).1[0];
        i.assert_refused(
            i.set("fmi3SetFloat64", &[input], &[f64::NAN]),
            "not a finite number",
            "NaN",
        );
        assert_eq!(
            i.get::<f64>("fmi3GetFloat64", &[input]).1[0].to_bits(),
            old.to_bits()
        );
        // an enumeration item that does not exist (any Int64, also beyond i32)
        if let Some(fid) = vr_of(&e, "solver.method") {
            let j = f3.instance("enum");
            let old = j.get::<i64>("fmi3GetInt64", &[fid]);
            assert_eq!(old.0, Status::Error, "no get before initialization");
            for bad in [0, 99, i64::from(i32::MAX) + 2, i64::MIN] {
                j.assert_refused(j.set("fmi3SetInt64", &[fid], &[bad]), "not an item", "item");
            }
            j.ok(j.init(), "init");
            let (_, v) = j.get::<i64>("fmi3GetInt64", &[fid]);
            let start = vars(&e)[fid as usize].1.start.unwrap() as i64;
            assert_eq!(v[0], start);
        }
        // a step at the wrong time, of no length
        i.assert_refused(i.do_step(1.0, 1e-3).0, "differs from the FMU's time", "t");
        i.assert_refused(i.do_step(0.0, 0.0).0, "must be > 0", "h");
        // NULL out-pointers of fmi3DoStep are not written
        type DoStep = unsafe extern "C" fn(
            Instance,
            f64,
            f64,
            Boolean,
            *mut u8,
            *mut u8,
            *mut u8,
            *mut f64,
        ) -> Status;
        let d: Symbol<DoStep> = f3.sym("fmi3DoStep");
        let null = std::ptr::null_mut();
        i.ok(
            unsafe { d(i.c, 0.0, 1e-3, TRUE, null, null, null, std::ptr::null_mut()) },
            "NULL outs",
        );
        // a Boolean byte other than 0 and 1 reads as true
        if let Some(b) = (vars(&e).into_iter())
            .find(|(_, v)| v.ty == VarType::Boolean && v.causality == Causality::Parameter)
        {
            let j = f3.instance("bool");
            j.ok(j.set("fmi3SetBoolean", &[b.0], &[2u8]), "byte 2");
            j.ok(j.enter_init(0.0, None), "enter");
            assert_eq!(j.get::<u8>("fmi3GetBoolean", &[b.0]).1, vec![1]);
        }
    }
}

/// A serialized state that is truncated, from another FMU or altered is refused, and the
/// instance goes on as before.
#[test]
fn a_tampered_serialized_state_is_refused() {
    let all = catalog::all();
    let (e, other) = (&all[0], &all[1]);
    let f3 = Fmu3::of(e);
    let i = f3.instance("tamper");
    i.ok(i.init(), "init");
    i.ok(i.do_step(0.0, 1e-3).0, "step");
    let good = i.state_bytes();
    let foreign = {
        let g = Fmu3::of(other);
        let j = g.instance("foreign");
        j.ok(j.init(), "init");
        j.state_bytes()
    };
    let mut cases: Vec<(Vec<u8>, &str)> = vec![
        (good[..good.len() / 2].to_vec(), "truncated"),
        (foreign, "GUID differs"),
    ];
    let mut tag = good.clone();
    tag[0] ^= 0xff;
    cases.push((tag, "not a serialized state"));
    let mut time = good.clone();
    time[26..34].copy_from_slice(&f64::NAN.to_bits().to_le_bytes());
    cases.push((time, "must be finite"));
    let mut fatal = good.clone();
    fatal[24..26].copy_from_slice(&State::Fatal.code().to_le_bytes());
    cases.push((fatal, "Fatal"));
    for (bytes, why) in cases {
        let (st, s) = i.deserialize(&bytes);
        let refused = st == Status::Error || {
            // read but refused when set
            let st = i.set_state(s);
            let mut s = s;
            i.free_state(&mut s);
            st == Status::Error
        };
        assert!(refused, "{why}: {:?}", i.logs());
        assert!(
            i.last_error().contains(why) || i.last_error().contains("refused"),
            "{why}: {}",
            i.last_error()
        );
        // the instance is where it was
        i.ok(i.do_step(1e-3, 1e-3).0, why);
        i.restore_bytes(&good);
    }
}

/// Instantiation asks what this interface offers: a wrong token, intermediate variables, no
/// name, Model Exchange of a model without continuous states and Scheduled Execution are
/// refused with the reason.
#[test]
fn instantiation_refuses_what_is_not_offered() {
    let e = &catalog::all()[0];
    let f3 = Fmu3::of(e);
    let token = cstr(&f3.token);
    let refused = |(c, env): (Instance, usize), why: &str| {
        assert!(c.is_null(), "{why}");
        let logs = logs_of(env);
        assert!(
            logs.iter()
                .any(|l| l.0 == Status::Error && l.2.contains(why)),
            "{why}: {logs:?}"
        );
    };
    refused(
        f3.instantiate_with(
            &cstr("x"),
            &cstr("{00000000-0000-0000-0000-000000000000}"),
            (false, false),
            &[],
        ),
        "instantiationToken",
    );
    refused(
        f3.instantiate_with(&cstr("x"), &token, (true, true), &[0, 1]),
        "providesIntermediateUpdate",
    );
    refused(
        f3.instantiate_with(&cstr(""), &token, (false, false), &[]),
        "instanceName",
    );
    // Model Exchange: the models with continuous states; one without is refused
    type Me = unsafe extern "C" fn(
        FmiString,
        FmiString,
        FmiString,
        Boolean,
        Boolean,
        InstanceEnvironment,
        LogMessageCallback,
    ) -> Instance;
    for e in catalog::all() {
        let g = Fmu3::of(&e);
        let f: Symbol<Me> = g.sym("fmi3InstantiateModelExchange");
        let t = cstr(&g.token);
        let c = unsafe {
            f(
                cstr("me").as_ptr(),
                t.as_ptr(),
                null(),
                FALSE,
                FALSE,
                null_mut(),
                None,
            )
        };
        let has_states = vars(&e).iter().any(|(_, v)| v.derivative.is_some());
        assert_eq!(!c.is_null(), has_states, "{}", e.identifier);
        if !c.is_null() {
            let free: Symbol<unsafe extern "C" fn(Instance)> = g.sym("fmi3FreeInstance");
            unsafe { free(c) };
        }
    }
    let se: Symbol<
        unsafe extern "C" fn(
            FmiString,
            FmiString,
            FmiString,
            Boolean,
            Boolean,
            InstanceEnvironment,
            LogMessageCallback,
            ClockUpdateCallback,
            PreemptionCallback,
            PreemptionCallback,
        ) -> Instance,
    > = f3.sym("fmi3InstantiateScheduledExecution");
    let c = unsafe {
        se(
            cstr("x").as_ptr(),
            token.as_ptr(),
            null(),
            FALSE,
            FALSE,
            null_mut(),
            None,
            None,
            None,
            None,
        )
    };
    assert!(c.is_null(), "Scheduled Execution");
}
