//! The FMI 3.0 interface of every FMU of the catalog, through the C ABI: the binary exports
//! every FMI 3.0 function; its outputs equal the FMI 2.0 interface's bit for bit over the
//! cross-check inputs at every level; an FMU state replays bit for bit; NULL, freed and foreign
//! handles, bad arguments, wrong types and a tampered serialized state are refused with the
//! reason and change nothing; instantiation asks what this interface offers. The call-sequence
//! matrix is in `fmi3_matrix.rs`, the events in `fmi3_events.rs`.

mod common;

use bindery_fmu::catalog::{self};
use bindery_fmu::fmi2::state::State;
use bindery_fmu::fmi3::types::*;
use bindery_fmu::model::{Causality, VarType};
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
    // Model Exchange: the models with continuous states; one without is refused, saying why
    for e in catalog::all() {
        let g = Fmu3::of(&e);
        let (c, env) = g.instantiate_me("me");
        let has_states = vars(&e).iter().any(|(_, v)| v.derivative.is_some());
        assert_eq!(!c.is_null(), has_states, "{}", e.identifier);
        if c.is_null() {
            let why = logs_of(env).iter().map(|l| l.2.clone()).collect::<Vec<_>>();
            assert!(
                why.iter().any(|w| w.contains("no continuous states")),
                "{}: {why:?}",
                e.identifier
            );
        } else {
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
