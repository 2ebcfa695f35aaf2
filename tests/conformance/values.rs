//! Bad values and states: parameters out of their bounds, values that break the mechanism,
//! tampered FMU states, the status calls after a Discard, every number of a saved state checked.

use super::*;

/// Every bounded parameter, set just outside its bounds, is refused in
/// `fmi2ExitInitializationMode` with a log line naming it; the host corrects it and goes on.
/// (The mechanism-specific assembly conditions are in each FMU's own C-ABI test.)
#[test]
fn out_of_bounds_parameters_are_refused_naming_them() {
    let _shared = shared();
    let mut checked = 0;
    for e in catalog::all() {
        let f = Fmu::of(&e);
        for (vr, v) in vars(&e) {
            if v.causality != Causality::Parameter {
                continue;
            }
            let mut bad = vec![];
            if let Some(lo) = v.min {
                bad.push(lo - 1.0 - lo.abs());
            }
            if let Some(hi) = v.max {
                bad.push(hi + 1.0 + hi.abs());
            }
            for x in bad {
                let s = f.slave("bounds");
                assert_eq!(s.call0("fmi2EnterInitializationMode"), Status::Ok);
                let set = match v.ty {
                    VarType::Real => s.set_real(&[vr], &[x]),
                    VarType::Integer => s.set_integer(&[vr], &[x as i32]),
                    _ => continue,
                };
                assert_eq!(set, Status::Ok, "{} = {x}: {:?}", v.name, s.logs());
                assert_eq!(s.call0("fmi2ExitInitializationMode"), Status::Error);
                let err = s.last_error();
                assert!(
                    err.contains(v.name) && err.contains("must be"),
                    "{} {} = {x}: {err}",
                    e.identifier,
                    v.name
                );
                let start = v.start.unwrap();
                let back = match v.ty {
                    VarType::Real => s.set_real(&[vr], &[start]),
                    _ => s.set_integer(&[vr], &[start as i32]),
                };
                assert_eq!(back, Status::Ok);
                assert_eq!(s.call0("fmi2ExitInitializationMode"), Status::Ok);
                checked += 1;
            }
            // masses are never negative
            if v.unit == Some("kg") {
                assert!(
                    v.min.is_some_and(|m| m >= 0.0),
                    "{} {}: a mass needs min >= 0",
                    e.identifier,
                    v.name
                );
            }
            // an enumeration value that is no item is refused at once
            if let VarType::Enumeration(t) = v.ty {
                let s = f.slave("enum");
                let bad = t.items.len() as i32 + 1;
                assert_eq!(s.set_integer(&[vr], &[bad]), Status::Error);
                assert!(s.last_error().contains(v.name));
                assert_eq!(s.set_integer(&[vr], &[0]), Status::Error);
            }
        }
    }
    assert!(checked > 10, "{checked}");
}

/// NaN and ±Inf inputs are refused and the previous value is kept bit for bit; huge angles give
/// finite outputs; zero, negative, non-finite and overflowing steps are refused; tiny and huge
/// steps are taken, but one along which the shaft's angle would leave the finite numbers is
/// discarded with the state kept.
#[test]
fn bad_values_keep_the_instance_going() {
    let _shared = shared();
    for e in catalog::all() {
        let f = Fmu::of(&e);
        let outs = real_outputs_of(&e);
        let inputs: Vec<u32> = vars(&e)
            .into_iter()
            .filter(|(_, v)| v.causality == Causality::Input && v.ty == VarType::Real)
            .map(|(vr, _)| vr)
            .collect();
        let s = f.initialized("values");
        assert_eq!(s.set_real(&inputs, &vec![0.3; inputs.len()]), Status::Ok);
        let before = s.get_real(&outs).1;
        for &vr in &inputs {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                assert_eq!(s.set_real(&[vr], &[bad]), Status::Error);
                assert!(s.last_error().contains("kept"), "{}", s.last_error());
            }
        }
        assert_eq!(s.get_real(&inputs).1, vec![0.3; inputs.len()]);
        assert_eq!(bits(&s.get_real(&outs).1), bits(&before));
        // huge angles: the mechanism is 2*pi-periodic, the outputs stay finite
        let phi = vr_of(&e, "shaft.phi");
        let huges: &[f64] = if is_mechanism(&e) {
            &[1e9, -1e9, 1e15, -1e300]
        } else {
            &[] // a drive's angle is its output
        };
        for &huge in huges {
            assert_eq!(s.set_real(&[phi], &[huge]), Status::Ok);
            let y = s.get_real(&outs).1;
            assert!(
                y.iter().all(|x| x.is_finite()),
                "{} at shaft.phi = {huge}: {y:?}",
                e.identifier
            );
        }
        // 1e9 rad is the angle 1e9 mod 2*pi: the same outputs, to the precision of that angle
        if is_mechanism(&e) {
            let a = 1e9_f64;
            assert_eq!(s.set_real(&[phi], &[a]), Status::Ok);
            let y1 = s.get_real(&outs).1;
            assert_eq!(
                s.set_real(&[phi], &[a.rem_euclid(2.0 * std::f64::consts::PI)]),
                Status::Ok
            );
            let y2 = s.get_real(&outs).1;
            for (p, q) in y1.iter().zip(&y2) {
                assert!((p - q).abs() <= 1e-5 * (1.0 + q.abs()), "{p} vs {q}");
            }
        }
        // step sizes
        for h in [0.0, -1e-3, f64::NAN, f64::INFINITY, -f64::MAX] {
            assert_eq!(s.do_step(0.0, h), Status::Error, "h = {h}");
            assert!(s.last_error().contains("communicationStepSize"));
        }
        assert_eq!(s.do_step(0.0, 1e-300), Status::Ok);
        if !is_mechanism(&e) {
            // a drive integrates its states: a step of 1e300 s is beyond any work budget, it is
            // discarded with the state kept
            assert_eq!(s.do_step(1e-300, 1e300), Status::Discard);
            assert!(s.get_real(&outs).1.iter().all(|x| x.is_finite()));
            continue;
        }
        // the shaft accelerating at 0.3 rad/s2 for 1e300 s ends at an infinite angle: the step
        // is refused with the reason, before anything moved
        let mut before: FMUstate = std::ptr::null_mut();
        assert_eq!(s.get_state(&mut before), Status::Ok);
        let kept = s.get_real(&inputs).1;
        assert_eq!(s.do_step(1e-300, 1e300), Status::Discard);
        let why = s.logs().last().map(|l| l.2.clone()).unwrap_or_default();
        assert!(why.contains("leads to shaft.phi = inf"), "{why}");
        assert_eq!(s.get_real(&inputs).1, kept);
        assert_eq!(s.set_state(before), Status::Ok);
        assert_eq!(s.free_state(&mut before), Status::Ok);
        // at constant speed the angle stays finite: the step is taken
        assert_eq!(s.set_real(&[vr_of(&e, "shaft.a")], &[0.0]), Status::Ok);
        assert_eq!(s.do_step(1e-300, 1e300), Status::Ok);
        assert!(s.get_real(&outs).1.iter().all(|x| x.is_finite()));
        // a step whose end time overflows is refused, not taken to t = inf
        assert_eq!(s.do_step(1e300, f64::MAX), Status::Error);
        assert!(s.last_error().contains("not finite"), "{}", s.last_error());
        let mut t = 0.0;
        let rs: Symbol<unsafe extern "C" fn(Component, c_int, *mut Real) -> Status> =
            f.sym("fmi2GetRealStatus");
        // SAFETY: valid pointer.
        assert_eq!(unsafe { rs(s.c, 2, &mut t) }, Status::Ok);
        assert_eq!(t, 1e300);
        // constant-speed mode at a huge time: still finite outputs
        let constant_speed = Start {
            time: 1e12,
            integers: &[(vr_of(&e, "drive.mode"), 2)],
            ..Start::default()
        };
        let c = f.started("constant", &constant_speed);
        assert_eq!(c.do_step(1e12, 0.5), Status::Ok);
        assert!(c.get_real(&outs).1.iter().all(|x| x.is_finite()));
    }
}

/// A saved FMU state whose bytes were tampered with (a parameter out of its bounds, a NaN
/// input, a non-finite time) is refused when set: the runtime never runs a model on values it
/// would have refused through fmi2Set*/fmi2ExitInitializationMode.
#[test]
fn tampered_fmu_states_are_refused() {
    let _shared = shared();
    for e in catalog::all() {
        let f = Fmu::of(&e);
        let s = f.initialized("tamper");
        assert_eq!(s.do_step(0.0, 0.1), Status::Ok);
        let outs = real_outputs_of(&e);
        let before = s.get_real(&outs).1;
        let mut st: FMUstate = std::ptr::null_mut();
        assert_eq!(s.get_state(&mut st), Status::Ok);
        let (_, bytes) = s.serialize(st);
        // magic, GUID hash, state code, times (time, start, stop, inputs set at), stop flag, length
        const VALUES: usize = 8 + 16 + 2 + 32 + 1 + 8;
        let mut cases: Vec<(usize, f64, String)> = vec![
            (26, f64::NAN, "time".into()),
            (26 + 24, f64::INFINITY, "input time".into()),
        ];
        for (vr, v) in vars(&e) {
            if v.causality == Causality::Input && v.ty == VarType::Real {
                cases.push((VALUES + 8 * vr as usize, f64::NAN, v.name.into()));
            }
            if v.causality == Causality::Parameter
                && let Some(lo) = v.min
            {
                cases.push((VALUES + 8 * vr as usize, lo - 1.0 - lo.abs(), v.name.into()));
            }
        }
        for (at, x, name) in cases {
            let mut b = bytes.clone();
            b[at..at + 8].copy_from_slice(&x.to_bits().to_le_bytes());
            refuse_tampered(
                &s,
                &b,
                &name,
                &format!("{} state with {name} = {x}", e.identifier),
            );
            // nothing of the instance changed
            let now = s.get_real(&outs);
            assert_eq!(now.0, Status::Ok);
            assert_eq!(bits(&now.1), bits(&before));
        }
        assert_eq!(s.free_state(&mut st), Status::Ok);
    }
}

/// A synchronous slave after a refused step, as FMI 2.0 (section 4.2.3) has it: `fmi2DoStep`
/// returns `fmi2Discard` with the reason; `fmi2GetRealStatus(fmi2LastSuccessfulTime)` is the end
/// of the last completed step and `fmi2GetBooleanStatus(fmi2Terminated)` false (the slave does
/// not end the run: the master may go back to a saved state and retry a shorter step);
/// `fmi2GetStatus(fmi2DoStepStatus)`, `fmi2GetStringStatus(fmi2PendingStatus)` and
/// `fmi2CancelStep` are refused, being for a step that returned `fmi2Pending`, which a slave
/// with `canRunAsynchronuously = false` never does; `fmi2DoStep` in stepFailed is refused; the
/// retry from the saved state completes.
#[test]
fn after_a_discard_the_status_calls_answer_as_a_synchronous_slave() {
    let _shared = shared();
    let e = catalog::all()
        .into_iter()
        .find(|e| e.identifier == "Perforators")
        .unwrap();
    let f = Fmu::of(&e);
    // the lift-off run: elastodynamic, 130 rpm
    let s = f.started(
        "status",
        &Start {
            integers: &[
                (vr_of(&e, "model.fidelity"), 3),
                (vr_of(&e, "drive.mode"), 2),
            ],
            reals: &[(vr_of(&e, "drive.n"), 130.0 * std::f64::consts::PI / 30.0)],
            ..Start::default()
        },
    );
    assert_eq!(s.do_step(0.0, 0.01), Status::Ok);
    let mut saved: FMUstate = std::ptr::null_mut();
    assert_eq!(s.get_state(&mut saved), Status::Ok);
    assert_eq!(s.do_step(0.01, 100.0), Status::Discard);
    let discarded = s.logs();
    assert!(
        discarded.iter().any(|l| l.2.contains("work budget")),
        "{discarded:?}"
    );
    // SAFETY: the FMI functions with one value each
    unsafe {
        let rs: Symbol<unsafe extern "C" fn(Component, c_int, *mut Real) -> Status> =
            f.sym("fmi2GetRealStatus");
        let mut t = f64::NAN;
        assert_eq!(
            rs(s.c, StatusKind::LastSuccessfulTime as c_int, &mut t),
            Status::Ok
        );
        assert_eq!(t, 0.01);
        let bs: Symbol<unsafe extern "C" fn(Component, c_int, *mut Boolean) -> Status> =
            f.sym("fmi2GetBooleanStatus");
        let mut b = TRUE;
        assert_eq!(bs(s.c, StatusKind::Terminated as c_int, &mut b), Status::Ok);
        assert_eq!(b, FALSE);
        let gs: Symbol<unsafe extern "C" fn(Component, c_int, *mut Status) -> Status> =
            f.sym("fmi2GetStatus");
        let mut st = Status::Ok;
        assert_eq!(
            gs(s.c, StatusKind::DoStepStatus as c_int, &mut st),
            Status::Error
        );
        let ss: Symbol<unsafe extern "C" fn(Component, c_int, *mut FmiString) -> Status> =
            f.sym("fmi2GetStringStatus");
        let mut text: FmiString = std::ptr::null();
        assert_eq!(
            ss(s.c, StatusKind::PendingStatus as c_int, &mut text),
            Status::Error
        );
    }
    assert_eq!(s.call0("fmi2CancelStep"), Status::Error);
    assert_eq!(
        s.do_step(0.01, 0.01),
        Status::Error,
        "no step in stepFailed"
    );
    assert_eq!(s.set_state(saved), Status::Ok);
    assert_eq!(s.do_step(0.01, 0.01), Status::Ok);
    assert_eq!(s.free_state(&mut saved), Status::Ok);
}

/// A restored state is validated in full: every number of the model's own part (what it
/// integrates and tracks: chain states, integrator memory, peaks, counters, flags, warning
/// digests), at every fidelity level, set to -inf (no number a model keeps may be that) is
/// refused by `fmi2SetFMUstate`, and the instance keeps what it had.
#[test]
fn every_number_of_a_models_saved_state_is_checked() {
    let _shared = shared();
    let mut checked = 0;
    for e in catalog::all() {
        let f = Fmu::of(&e);
        let mut starts = vec![Start::default()];
        let fidelity = levels(&e)
            .into_iter()
            .map(|l| [(vr_of(&e, "model.fidelity"), l)])
            .collect::<Vec<_>>();
        starts.extend(fidelity.iter().map(|l| Start {
            integers: l,
            ..Start::default()
        }));
        for start in &starts {
            let s = f.started("model state", start);
            for k in 0..20 {
                assert_eq!(s.do_step(k as f64 * 0.005, 0.005), Status::Ok);
            }
            let outs = real_outputs_of(&e);
            let before = s.get_real(&outs).1;
            let bytes = s.state_bytes();
            // header (magic, GUID hash, state code, four times, stop flag), then the values
            // and the model's numbers, each with its count first
            let values = 8 + 16 + 2 + 32 + 1;
            let n = vars(&e).len();
            let model = values + 8 + 8 * n;
            let count = u64::from_le_bytes(bytes[model..model + 8].try_into().unwrap()) as usize;
            for i in 0..count {
                let at = model + 8 + 8 * i;
                let mut b = bytes.clone();
                b[at..at + 8].copy_from_slice(&f64::NEG_INFINITY.to_bits().to_le_bytes());
                let mut bad: FMUstate = std::ptr::null_mut();
                assert_eq!(s.deserialize(&b, &mut bad), Status::Ok);
                assert_eq!(
                    s.set_state(bad),
                    Status::Error,
                    "{} {:?}: model number {i} of {count} = -inf accepted",
                    e.identifier,
                    start.integers
                );
                assert!(
                    s.last_error().contains("refused")
                        || s.last_error().contains("expected")
                        || s.last_error().contains("not "),
                    "{}",
                    s.last_error()
                );
                assert_eq!(s.free_state(&mut bad), Status::Ok);
                let now = s.get_real(&outs);
                assert_eq!(now.0, Status::Ok);
                assert_eq!(bits(&now.1), bits(&before), "{} kept", e.identifier);
                checked += 1;
            }
            // the state as it was still restores
            s.restore_bytes(&bytes);
        }
    }
    assert!(checked > 500, "{checked} numbers checked");
}
