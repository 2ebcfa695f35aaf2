//! Input derivatives, replay from FMU states and reset, parallel instances, instantiate/free
//! cycles without a leak, and freed or foreign handles refused.

use super::*;

/// `fmi2SetRealInputDerivatives`: refused where `canInterpolateInputs` is false ("not
/// supported") and on a Model Exchange instance; where it is true, every bad argument (not a
/// Real input, order 0 or above 2, a non-finite value, NULL arrays) is refused with a reason
/// and changes nothing, even when other entries of the same call are valid; derivatives a
/// state was saved with are checked when it is set again.
#[test]
fn input_derivative_calls_are_checked_and_atomic() {
    let _shared = shared();
    for e in catalog::all() {
        let f = Fmu::of(&e);
        let s = f.initialized("ider");
        let phi = vr_of(&e, "shaft.phi");
        if !(e.info)().can_interpolate_inputs {
            assert_eq!(s.set_input_derivatives(&[phi], &[1], &[1.0]), Status::Error);
            assert!(
                s.last_error().contains("not supported"),
                "{}",
                s.last_error()
            );
            continue;
        }
        assert_eq!(s.set_input_derivatives(&[phi], &[1], &[2.5]), Status::Ok);
        let before = s.state_bytes();
        let n = vars(&e).len() as u32;
        let output = vr_of(&e, "shaft.tau");
        let param = first(&e, |v| {
            v.causality == Causality::Parameter && v.ty == VarType::Real
        })
        .expect("a Real parameter");
        let int = vr_of(&e, "drive.mode");
        let cases: Vec<(u32, i32, f64, &str)> = vec![
            (output, 1, 1.0, "not a Real input"),
            (param, 1, 1.0, "not a Real input"),
            (int, 1, 1.0, "not a Real input"),
            (n, 1, 1.0, "unknown value reference"),
            (u32::MAX, 1, 1.0, "unknown value reference"),
            (phi, 0, 1.0, "orders 1..=2"),
            (phi, 3, 1.0, "orders 1..=2"),
            (phi, -1, 1.0, "orders 1..=2"),
            (phi, i32::MIN, 1.0, "orders 1..=2"),
            (phi, 1, f64::NAN, "not a finite number"),
            (phi, 2, f64::INFINITY, "not a finite number"),
        ];
        for (vr, order, x, why) in cases {
            // a valid entry first: the call is refused as a whole
            let st = s.set_input_derivatives(&[phi, vr], &[2, order], &[7.0, x]);
            let cell = format!("{} vr {vr} order {order} = {x}", e.identifier);
            assert_eq!(st, Status::Error, "{cell}");
            assert!(s.last_error().contains(why), "{cell}: {}", s.last_error());
            assert_eq!(
                s.state_bytes(),
                before,
                "{cell}: the refused call changed the state"
            );
        }
        // NULL arrays with n > 0
        let g: Symbol<
            unsafe extern "C" fn(
                Component,
                *const u32,
                usize,
                *const Integer,
                *const Real,
            ) -> Status,
        > = f.sym("fmi2SetRealInputDerivatives");
        // SAFETY: the FMI function with NULL arrays, which it must refuse.
        unsafe {
            assert_eq!(
                g(s.c, std::ptr::null(), 1, [1].as_ptr(), [1.0].as_ptr()),
                Status::Error
            );
            assert_eq!(
                g(s.c, [phi].as_ptr(), 1, std::ptr::null(), [1.0].as_ptr()),
                Status::Error
            );
            assert_eq!(
                g(s.c, [phi].as_ptr(), 1, [1].as_ptr(), std::ptr::null()),
                Status::Error
            );
            assert!(s.last_error().contains("NULL"), "{}", s.last_error());
            assert_eq!(
                g(s.c, std::ptr::null(), 0, std::ptr::null(), std::ptr::null()),
                Status::Ok
            );
        }
        assert_eq!(s.state_bytes(), before);
        // a derivative the path does not use is kept, with a warning saying so
        let a = vr_of(&e, "shaft.a");
        let n_logs = s.logs().len();
        assert_eq!(s.set_input_derivatives(&[a], &[1], &[1.0]), Status::Warning);
        assert!(
            s.logs()[n_logs..]
                .iter()
                .any(|l| l.0 == Status::Warning && l.2.contains("shaft.a of order 1")),
            "{:?}",
            &s.logs()[n_logs..]
        );
        // tampered derivatives in a serialized state: the last triple (vr, order, value)
        let bytes = s.state_bytes();
        let at = bytes.len() - 25; // before the Model Exchange mode byte
        for (k, x, why) in [
            (0, f64::from(output), "not a Real input"),
            (0, 0.5, "not a value reference"),
            (1, 3.0, "orders 1..=2"),
            (2, f64::NAN, "not a finite number"),
        ] {
            let mut b = bytes.clone();
            b[at + 8 * k..at + 8 * k + 8].copy_from_slice(&x.to_bits().to_le_bytes());
            refuse_tampered(&s, &b, why, &format!("{} tampered {k} = {x}", e.identifier));
            assert_eq!(s.state_bytes(), bytes);
        }
        // not on a Model Exchange instance (of an FMU that has one): the host integrates and
        // sets the inputs itself
        if n_states(&e) > 0 {
            let me = f.me_instance("ider-me");
            me.setup_and_init(0.0, None);
            assert_eq!(
                me.set_input_derivatives(&[phi], &[1], &[1.0]),
                Status::Error
            );
            assert!(
                me.last_error().contains("Model Exchange"),
                "{}",
                me.last_error()
            );
        }
        // the instance goes on, with its derivatives
        assert_eq!(s.do_step(0.0, 0.01), Status::Ok);
    }
}

/// A run of `n` steps of `h` from `t0`, reading every Real output after each: the shaft input
/// follows a fixed non-trivial law so that inputs matter.
fn run(s: &Slave, e: &Entry, t0: f64, n: usize, h: f64) -> Vec<u64> {
    let outs = real_outputs_of(e);
    let ins = drive_inputs(e);
    let mut out = Vec::with_capacity(n * outs.len());
    for k in 0..n {
        let t = t0 + k as f64 * h;
        let phi = 2.0 * t + 0.3 * (3.0 * t).sin();
        assert_eq!(
            s.set_real(
                &ins,
                &[phi, 2.0 + 0.9 * (3.0 * t).cos(), -2.7 * (3.0 * t).sin()]
            ),
            Status::Ok
        );
        assert_eq!(s.do_step(t, h), Status::Ok, "{:?}", s.logs());
        let (st, y) = s.get_real(&outs);
        assert_eq!(st, Status::Ok);
        out.extend(y.iter().map(|x| x.to_bits()));
    }
    out
}

/// For every FMU: FMU state get/set, serialize/deserialize (into another instance) and
/// fmi2Reset each replay the same run bit for bit.
#[test]
fn fmu_state_and_reset_replay_bit_identically() {
    let _shared = shared();
    for e in catalog::all() {
        let f = Fmu::of(&e);
        let s = f.initialized("replay");
        let first = run(&s, &e, 0.0, 40, 0.01);
        let other = f.slave("other");
        let replay = assert_state_replays(&s, &other, e.identifier, |s| run(s, &e, 0.4, 60, 0.01));
        // a state of another instance is refused, not followed
        assert_eq!(other.set_state(replay.saved), Status::Error);
        replay.free(&s, &other);
        // reset: the same run as a fresh instance
        assert_eq!(s.call0("fmi2Reset"), Status::Ok);
        s.setup_and_init(0.0, None);
        assert_eq!(run(&s, &e, 0.0, 40, 0.01), first, "{} reset", e.identifier);
    }
}

/// Instances driven in parallel threads give the same results, bit for bit, as the same runs
/// one after the other.
#[test]
fn parallel_instances_match_sequential_runs() {
    let _shared = shared();
    for e in catalog::all() {
        let f = Fmu::of(&e);
        let job = |k: usize| {
            // every other instance: another level of a mechanism, another integrator of a drive
            let (name, value) = if is_mechanism(&e) {
                ("model.fidelity", 1)
            } else {
                ("solver.method", 3)
            };
            let other = [(vr_of(&e, name), value)];
            let start = Start {
                time: 0.01 * k as f64,
                integers: if k % 2 == 1 { &other } else { &[] },
                ..Start::default()
            };
            let s = f.started("thread", &start);
            run(&s, &e, 0.01 * k as f64, 150, 0.007 + 0.001 * k as f64)
        };
        let sequential: Vec<Vec<u64>> = (0..8).map(job).collect();
        let parallel: Vec<Vec<u64>> = std::thread::scope(|sc| {
            let hs: Vec<_> = (0..8).map(|k| sc.spawn(move || job(k))).collect();
            hs.into_iter().map(|h| h.join().unwrap()).collect()
        });
        assert_eq!(sequential, parallel, "{}", e.identifier);
    }
}

fn rss_kib() -> usize {
    let s = std::fs::read_to_string("/proc/self/statm").unwrap_or_default();
    let pages: usize = s
        .split_whitespace()
        .nth(1)
        .and_then(|x| x.parse().ok())
        .unwrap_or(0);
    pages * 4
}

/// Instantiate/free cycles (with an FMU state left for FreeInstance to free) do not grow the
/// process. `examples/fuzz_fmi` and the report run a million cycles under LeakSanitizer.
#[test]
fn instantiate_free_cycles_do_not_leak() {
    let _alone = ALONE.write().unwrap_or_else(|e| e.into_inner());
    let cycles: usize = std::env::var("BINDERY_CYCLES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20_000);
    for e in catalog::all() {
        let f = Fmu::of(&e);
        // preparing a model can take a millisecond (syntheses): most cycles stop before it
        let cycle = |init: bool| {
            let s = f.slave("cycle");
            if init {
                assert_eq!(s.init(), Status::Ok);
                assert_eq!(s.do_step(0.0, 0.01), Status::Ok);
            }
            let mut st: FMUstate = std::ptr::null_mut();
            assert_eq!(s.get_state(&mut st), Status::Ok);
        };
        for k in 0..1000 {
            cycle(k % 10 == 0);
        }
        let before = rss_kib();
        for k in 0..cycles {
            cycle(k % 100 == 0);
        }
        let grown = rss_kib().saturating_sub(before);
        assert!(
            grown < 4096,
            "{}: {cycles} cycles grew the process by {grown} KiB",
            e.identifier
        );
    }
}

/// A handle that is not a live instance of the FMU is refused without being read: a freed one
/// (a second fmi2FreeInstance too), one of another FMU loaded in the same process, and pointers
/// into memory that holds no instance at all (which the old magic-number check had to read).
#[test]
fn freed_foreign_and_made_up_handles_are_refused_unread() {
    let _shared = shared();
    let all = catalog::all();
    let (a, b) = (Fmu::of(&all[0]), Fmu::of(&all[1]));
    let sa = a.initialized("a");
    let sb = b.initialized("b");
    let step: Symbol<unsafe extern "C" fn(Component, Real, Real, Boolean) -> Status> =
        a.sym("fmi2DoStep");
    let free: Symbol<unsafe extern "C" fn(Component)> = a.sym("fmi2FreeInstance");
    // SAFETY: the registry refuses every one of these handles before reading it.
    unsafe {
        assert_eq!(step(sa.c, 0.0, 1e-3, TRUE), Status::Ok, "a live instance");
        assert_eq!(
            step(sb.c, 0.0, 1e-3, TRUE),
            Status::Error,
            "another FMU's instance"
        );
        let junk = [0u8; 64];
        assert_eq!(
            step(junk.as_ptr() as Component, 0.0, 1e-3, TRUE),
            Status::Error
        );
        assert_eq!(
            step(8 as Component, 0.0, 1e-3, TRUE),
            Status::Error,
            "not even mapped"
        );
        let c = sa.c;
        free(c);
        assert_eq!(step(c, 1e-3, 1e-3, TRUE), Status::Error, "a freed instance");
        free(c); // a second free is ignored
        std::mem::forget(sa); // already freed
    }
}
