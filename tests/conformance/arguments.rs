//! Bad arguments: NULL pointers, sizes, unknown or wrong-type value references, non-finite
//! values, invalid `fmuType`s; each refused with a reason, changing nothing.

use super::*;

/// Bad arguments to the Model Exchange functions: NULL arrays and result pointers, nx and nz
/// that are not the FMU's, non-finite states and times, parameters set in continuous-time
/// mode. Each is `fmi2Error` with a reason naming it, changes nothing, and the run goes on.
#[test]
fn model_exchange_bad_arguments_are_refused_with_a_reason() {
    let _shared = shared();
    type Arr = unsafe extern "C" fn(Component, *mut Real, usize) -> Status;
    type SetX = unsafe extern "C" fn(Component, *const Real, usize) -> Status;
    for e in catalog::all() {
        let nx = n_states(&e);
        if nx == 0 {
            continue;
        }
        let nz = n_indicators(&e);
        let f = Fmu::of(&e);
        let s = f.me_instance("me-bad");
        // a mechanism's states are those of its elastodynamic level (a drive such as
        // MainShaft has no levels)
        if let Some(fid) = first(&e, |v| v.name == "model.fidelity") {
            assert_eq!(s.set_integer(&[fid], &[3]), Status::Ok);
        }
        drive_me_to(&s, MeState::ContinuousTimeMode);
        let expect = |st: Status, text: &str, what: &str| {
            s.assert_refused(st, text, &format!("{} {what}", e.identifier))
        };
        let mut x = vec![0.0; nx + 1];
        // SAFETY: the FMI functions with the arrays and pointers described, NULL where said.
        unsafe {
            // the first read starts the elastodynamic states (from the inputs at the time)
            assert_eq!(
                f.sym::<Arr>("fmi2GetContinuousStates")(s.c, x.as_mut_ptr(), nx),
                Status::Ok
            );
            assert!(x[..nx].iter().all(|v| v.is_finite()), "{x:?}");
        }
        let before = s.state_bytes();
        // SAFETY: as above.
        unsafe {
            for g in [
                "fmi2GetDerivatives",
                "fmi2GetContinuousStates",
                "fmi2GetNominalsOfContinuousStates",
            ] {
                expect(f.sym::<Arr>(g)(s.c, std::ptr::null_mut(), nx), "NULL", g);
                for n in [0, nx - 1, nx + 1, usize::MAX] {
                    expect(
                        f.sym::<Arr>(g)(s.c, x.as_mut_ptr(), n),
                        &format!("nx = {n}; this FMU has {nx}"),
                        g,
                    );
                }
            }
            let mut z = vec![0.0; nz + 1];
            let gi = f.sym::<Arr>("fmi2GetEventIndicators");
            if nz > 0 {
                expect(gi(s.c, std::ptr::null_mut(), nz), "NULL", "indicators");
            }
            // (an FMU may have states and no event indicators: then only nz + 1 is wrong)
            let wrong_nz: Vec<usize> = if nz > 0 {
                vec![0, nz - 1, nz + 1]
            } else {
                vec![1]
            };
            for n in wrong_nz {
                expect(
                    gi(s.c, z.as_mut_ptr(), n),
                    &format!("ni = {n}; this FMU has {nz}"),
                    "indicators",
                );
            }
            let set = f.sym::<SetX>("fmi2SetContinuousStates");
            expect(set(s.c, std::ptr::null(), nx), "NULL", "set states");
            expect(set(s.c, x.as_ptr(), nx + 1), "nx = ", "set states");
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut y = x[..nx].to_vec();
                y[nx - 1] = bad;
                expect(set(s.c, y.as_ptr(), nx), "not finite", "set states");
            }
            let st = f.sym::<unsafe extern "C" fn(Component, Real) -> Status>("fmi2SetTime");
            for bad in [f64::NAN, f64::INFINITY] {
                expect(st(s.c, bad), "not finite", "set time");
            }
            let cis = f.sym::<unsafe extern "C" fn(
                Component,
                Boolean,
                *mut Boolean,
                *mut Boolean,
            ) -> Status>("fmi2CompletedIntegratorStep");
            let mut b = FALSE;
            expect(
                cis(s.c, TRUE, std::ptr::null_mut(), &mut b),
                "NULL",
                "completed step",
            );
            expect(
                cis(s.c, TRUE, &mut b, std::ptr::null_mut()),
                "NULL",
                "completed step",
            );
            // a parameter in continuous-time mode (only continuous inputs may change)
            let param = first(&e, |v| {
                v.causality == Causality::Parameter && v.ty == VarType::Real
            })
            .expect("a Real parameter");
            expect(s.set_real(&[param], &[1.0]), "cannot be set", "parameter");
            assert_eq!(
                s.state_bytes(),
                before,
                "{}: a refused call changed the state",
                e.identifier
            );
            // in event mode: NewDiscreteStates(NULL)
            assert_eq!(s.call0("fmi2EnterEventMode"), Status::Ok);
            expect(
                f.sym::<unsafe extern "C" fn(Component, *mut EventInfo) -> Status>(
                    "fmi2NewDiscreteStates",
                )(s.c, std::ptr::null_mut()),
                "NULL",
                "new discrete states",
            );
            // the run goes on
            assert_eq!(s.call0("fmi2EnterContinuousTimeMode"), Status::Ok);
            assert_eq!(st(s.c, 1e-3), Status::Ok);
            assert_eq!(set(s.c, x.as_ptr(), nx), Status::Ok);
            let mut dx = vec![f64::NAN; nx];
            assert_eq!(
                f.sym::<Arr>("fmi2GetDerivatives")(s.c, dx.as_mut_ptr(), nx),
                Status::Ok
            );
            assert!(dx.iter().all(|v| v.is_finite()), "{dx:?}");
        }
        // a Model Exchange state in continuous-time mode restores its mode; a Co-Simulation
        // instance refuses it
        let mut st: FMUstate = std::ptr::null_mut();
        assert_eq!(s.get_state(&mut st), Status::Ok);
        let (_, bytes) = s.serialize(st);
        assert_eq!(*bytes.last().unwrap(), 1, "continuous-time mode is saved");
        assert_eq!(s.call0("fmi2EnterEventMode"), Status::Ok);
        assert_eq!(s.set_state(st), Status::Ok);
        let mut dummy = vec![0.0; nx];
        // SAFETY: as above.
        unsafe {
            // legal in continuous-time mode only: the mode came back with the state
            assert_eq!(
                f.sym::<SetX>("fmi2SetContinuousStates")(s.c, dummy.as_mut_ptr(), nx),
                Status::Ok
            );
        }
        assert_eq!(s.free_state(&mut st), Status::Ok);
        let cs = f.slave("cs");
        let mut st2: FMUstate = std::ptr::null_mut();
        assert_eq!(cs.deserialize(&bytes, &mut st2), Status::Ok);
        assert_eq!(cs.set_state(st2), Status::Error);
        assert!(
            cs.last_error().contains("continuous-time mode"),
            "{}",
            cs.last_error()
        );
        assert_eq!(cs.free_state(&mut st2), Status::Ok);
    }
}

/// Every variable of `e` through every setter of another type on `s`: refused naming the type,
/// the value read back unchanged.
fn wrong_type_setters_refused(f: &Fmu, s: &Slave, e: &catalog::Entry, when: &str) {
    type Set<T> = unsafe extern "C" fn(Component, *const u32, usize, *const T) -> Status;
    let set_boolean: Symbol<Set<Boolean>> = f.sym("fmi2SetBoolean");
    let set_string: Symbol<Set<FmiString>> = f.sym("fmi2SetString");
    let text = std::ffi::CString::new("x").unwrap();
    let read = |vr: u32, ty: VarType| -> f64 {
        let (st, x) = match ty {
            VarType::Real => s.get_real(&[vr]),
            VarType::Boolean => {
                let (st, b) = s.get_boolean(&[vr]);
                (st, vec![f64::from(u8::from(b[0]))])
            }
            _ => {
                let (st, i) = s.get_integer(&[vr]);
                (st, vec![f64::from(i[0])])
            }
        };
        assert_eq!(st, Status::Ok, "{} vr {vr}: read back", e.identifier);
        x[0]
    };
    for (vr, v) in vars(e) {
        let before = read(vr, v.ty);
        let what = format!("{} {} {when}", e.identifier, v.name);
        for ty in ["Real", "Integer", "Boolean", "String"] {
            let right = match ty {
                "Real" => v.ty == VarType::Real,
                "Integer" => v.ty.is_integer_like(),
                "Boolean" => v.ty == VarType::Boolean,
                _ => false,
            };
            if right {
                continue;
            }
            // SAFETY: one value reference and one value
            let st = unsafe {
                match ty {
                    "Real" => s.set_real(&[vr], &[1.0]),
                    "Integer" => s.set_integer(&[vr], &[1]),
                    "Boolean" => set_boolean(s.c, [vr].as_ptr(), 1, [TRUE].as_ptr()),
                    _ => set_string(s.c, [vr].as_ptr(), 1, [text.as_ptr()].as_ptr()),
                }
            };
            assert_eq!(st, Status::Error, "{what}: fmi2Set{ty}");
            let err = s.last_error();
            assert!(
                err.contains(&format!("is not of type {ty}")),
                "{what}: {err}"
            );
        }
        assert_eq!(
            read(vr, v.ty).to_bits(),
            before.to_bits(),
            "{what}: value kept"
        );
    }
}

/// NULL arrays with nvr > 0, unknown value references, wrong-type getters and setters, setting
/// what cannot be set after initialization, NULL FMU-state pointers: `fmi2Error` with a named log
/// line, and the instance goes on.
#[test]
fn bad_arguments_are_refused_with_a_reason() {
    let _shared = shared();
    type Get<T> = unsafe extern "C" fn(Component, *const u32, usize, *mut T) -> Status;
    type Set<T> = unsafe extern "C" fn(Component, *const u32, usize, *const T) -> Status;
    for e in catalog::all() {
        let f = Fmu::of(&e);
        let s = f.initialized("bad");
        let n = vars(&e).len() as u32;
        let expect = |st: Status, text: &str, what: &str| {
            s.assert_refused(st, text, &format!("{} {what}", e.identifier))
        };
        // SAFETY: the FMI functions with the arrays described; NULL where the test says.
        unsafe {
            let two = [0u32, 1];
            for g in [
                "fmi2GetReal",
                "fmi2GetInteger",
                "fmi2GetBoolean",
                "fmi2GetString",
            ] {
                let get: Symbol<Get<f64>> = f.sym(g);
                expect(
                    get(s.c, std::ptr::null(), 2, std::ptr::null_mut()),
                    "NULL",
                    g,
                );
                let mut out = [0.0f64; 2];
                expect(get(s.c, two.as_ptr(), 2, std::ptr::null_mut()), "NULL", g);
                for bad in [n, n + 1, u32::MAX] {
                    expect(
                        get(s.c, [bad].as_ptr(), 1, out.as_mut_ptr()),
                        &format!("unknown value reference {bad}"),
                        g,
                    );
                }
            }
            for g in [
                "fmi2SetReal",
                "fmi2SetInteger",
                "fmi2SetBoolean",
                "fmi2SetString",
            ] {
                let set: Symbol<Set<f64>> = f.sym(g);
                expect(set(s.c, std::ptr::null(), 2, std::ptr::null()), "NULL", g);
                expect(
                    set(s.c, [drive_inputs(&e)[0]].as_ptr(), 1, std::ptr::null()),
                    "NULL",
                    g,
                );
                let vals = [0.0f64; 1];
                for bad in [n, u32::MAX] {
                    expect(
                        set(s.c, [bad].as_ptr(), 1, vals.as_ptr()),
                        "unknown value reference",
                        g,
                    );
                }
            }
            // wrong-type getters: every variable through every getter of another type
            for (vr, v) in vars(&e) {
                let mut r = [0.0];
                let mut i = [0];
                if v.ty != VarType::Real {
                    expect(s.get_real(&[vr]).0, "is not of type Real", v.name);
                }
                if !v.ty.is_integer_like() {
                    expect(s.get_integer(&[vr]).0, "is not of type Integer", v.name);
                }
                if v.ty != VarType::Boolean {
                    expect(s.get_boolean(&[vr]).0, "is not of type Boolean", v.name);
                }
                let gs: Symbol<Get<FmiString>> = f.sym("fmi2GetString");
                let mut p: [FmiString; 1] = [std::ptr::null()];
                expect(
                    gs(s.c, [vr].as_ptr(), 1, p.as_mut_ptr()),
                    "is not of type String",
                    v.name,
                );
                let _ = (&mut r, &mut i);
            }
            // wrong-type setters: every variable through every setter of another type, its
            // value kept (fmi2SetString used to write 0 into any variable settable now)
            wrong_type_setters_refused(&f, &s, &e, "after initialization");
            // and where parameters are settable: drive.n through fmi2SetString was 0 after it
            let init = f.slave("init");
            init.ok(init.setup(0.0, None), "fmi2SetupExperiment");
            init.ok(
                init.call0("fmi2EnterInitializationMode"),
                "fmi2EnterInitializationMode",
            );
            wrong_type_setters_refused(&f, &init, &e, "in initialization mode");
            // after initialization only inputs (and tunable parameters) may be set
            for (vr, v) in vars(&e) {
                if v.causality == Causality::Input
                    || v.causality == Causality::Parameter && v.variability == Variability::Tunable
                {
                    continue;
                }
                let st = match v.ty {
                    VarType::Real => s.set_real(&[vr], &[1.0]),
                    VarType::Boolean => {
                        let set: Symbol<Set<Boolean>> = f.sym("fmi2SetBoolean");
                        set(s.c, [vr].as_ptr(), 1, [TRUE].as_ptr())
                    }
                    _ => s.set_integer(&[vr], &[1]),
                };
                expect(st, v.name, "set after initialization");
                assert!(
                    s.last_error().contains("cannot be set"),
                    "{}",
                    s.last_error()
                );
            }
            // FMU-state calls with NULL pointers
            let get: Symbol<unsafe extern "C" fn(Component, *mut FMUstate) -> Status> =
                f.sym("fmi2GetFMUstate");
            expect(get(s.c, std::ptr::null_mut()), "NULL", "GetFMUstate(NULL)");
            expect(
                s.set_state(std::ptr::null_mut()),
                "NULL",
                "SetFMUstate(NULL)",
            );
            let size: Symbol<unsafe extern "C" fn(Component, FMUstate, *mut usize) -> Status> =
                f.sym("fmi2SerializedFMUstateSize");
            let mut st: FMUstate = std::ptr::null_mut();
            assert_eq!(s.get_state(&mut st), Status::Ok);
            expect(size(s.c, st, std::ptr::null_mut()), "NULL", "size(NULL)");
            let ser: Symbol<unsafe extern "C" fn(Component, FMUstate, *mut Byte, usize) -> Status> =
                f.sym("fmi2SerializeFMUstate");
            expect(
                ser(s.c, st, std::ptr::null_mut(), 4096),
                "NULL",
                "serialize(NULL)",
            );
            expect(
                ser(s.c, st, [0 as c_char; 8].as_mut_ptr(), 8),
                "too small",
                "serialize(short)",
            );
            let de: Symbol<
                unsafe extern "C" fn(Component, *const Byte, usize, *mut FMUstate) -> Status,
            > = f.sym("fmi2DeSerializeFMUstate");
            let mut st2: FMUstate = std::ptr::null_mut();
            expect(
                de(s.c, std::ptr::null(), 16, &mut st2),
                "NULL",
                "deserialize(NULL)",
            );
            expect(
                de(s.c, [0 as c_char; 4].as_ptr(), 4, std::ptr::null_mut()),
                "NULL",
                "deserialize(.., NULL)",
            );
            // invalid enum values of a C host: fmi2StatusKind and fmi2Type
            let rs: Symbol<unsafe extern "C" fn(Component, c_int, *mut Real) -> Status> =
                f.sym("fmi2GetRealStatus");
            let mut t = 0.0;
            for kind in [-1, 0, 7, c_int::MAX] {
                expect(rs(s.c, kind, &mut t), "fmi2LastSuccessfulTime", "kind");
            }
            let bs: Symbol<unsafe extern "C" fn(Component, c_int, *mut Boolean) -> Status> =
                f.sym("fmi2GetBooleanStatus");
            let mut b = 0;
            expect(bs(s.c, 99, &mut b), "fmi2Terminated", "kind");
            assert_eq!(s.free_state(&mut st), Status::Ok);
            // the instance goes on
            assert_eq!(s.do_step(0.0, 0.01), Status::Ok);
            assert!(
                s.get_real(&real_outputs_of(&e))
                    .1
                    .iter()
                    .all(|x| x.is_finite())
            );
        }
        instantiate_refuses_invalid_fmu_types(&e, &f);
    }
}

/// `fmuType` values that are no `fmi2Type` (a C host may pass any int) are refused with a log
/// line. Before issue 7 the binary read the int as a Rust enum: undefined behaviour, and in the
/// optimized build -1 and 1000 were accepted as Co-Simulation.
fn instantiate_refuses_invalid_fmu_types(e: &Entry, f: &Fmu) {
    type Inst = unsafe extern "C" fn(
        FmiString,
        c_int,
        FmiString,
        FmiString,
        *const CallbackFunctions,
        Boolean,
        Boolean,
    ) -> Component;
    let inst: Symbol<Inst> = f.sym("fmi2Instantiate");
    let env = 700_000 + e.identifier.len();
    let cb = f.callbacks(env);
    let guid = std::ffi::CString::new(f.guid.clone()).unwrap();
    for ty in [-1, 2, 1000, c_int::MIN, c_int::MAX] {
        // SAFETY: valid strings and callbacks.
        let c = unsafe {
            inst(
                c"x".as_ptr(),
                ty,
                guid.as_ptr(),
                std::ptr::null(),
                &cb,
                FALSE,
                FALSE,
            )
        };
        assert!(c.is_null(), "{} accepted fmuType {ty}", e.identifier);
        let last = logs_of(env).last().cloned().expect("a log line");
        assert!(
            last.0 == Status::Error && last.2.contains(&format!("fmuType {ty}")),
            "{last:?}"
        );
    }
}
