//! FMI 2.0 conformance and robustness of every FMU of the catalog, through the C ABI (issue 7):
//! the call-sequence matrix (every function in every reachable state), bad arguments, bad
//! values, FMU-state and reset replay, parallel instances, instantiate/free cycles.
//!
//! The matrix is a table of rows (FMI function, [`Call`], how to call it with valid arguments)
//! crossed with the states of the co-simulation state machine; the expected outcome comes from
//! the runtime's own table (`fmi2::state::allowed`). Model Exchange rows and states are added
//! to [`ROWS`] and [`STATES`] (with a way to reach each state in [`drive_to`]) when the FMUs
//! provide it.

mod common;

use bindery_fmu::catalog::{self, Entry};
use bindery_fmu::fmi2::runtime::me::EventInfo;
use bindery_fmu::fmi2::state::{Call, ME_STATES, MeState, State, allowed, me_allowed};
use bindery_fmu::fmi2::types::*;
use bindery_fmu::model::{Causality, Var, VarType, Variability};
use common::series::bits;
use common::*;
use libloading::Symbol;
use std::ffi::{c_char, c_int};

/// The leak test measures the process's memory: it runs alone (write lock) while the other
/// tests of this file, which allocate (and log) a lot, share the read lock.
static ALONE: std::sync::RwLock<()> = std::sync::RwLock::new(());

fn shared() -> std::sync::RwLockReadGuard<'static, ()> {
    ALONE.read().unwrap_or_else(|e| e.into_inner())
}

fn vars(e: &Entry) -> Vec<(u32, &'static Var)> {
    (e.variables)()
}

fn first(e: &Entry, pred: impl Fn(&Var) -> bool) -> Option<u32> {
    vars(e).into_iter().find(|(_, v)| pred(v)).map(|(vr, _)| vr)
}

/// The first three Real inputs: `shaft.phi`, `shaft.w`, `shaft.a` of a mechanism; the loads
/// `load.tau`, `load1.J_red`, `load1.tau0` of a drive (MainShaft).
fn drive_inputs(e: &Entry) -> [u32; 3] {
    let ins: Vec<u32> = vars(e)
        .into_iter()
        .filter(|(_, v)| v.causality == Causality::Input && v.ty == VarType::Real)
        .map(|(vr, _)| vr)
        .take(3)
        .collect();
    [ins[0], ins[1], ins[2]]
}

/// A mechanism, driven through the shaft connector (not the drive that turns it).
fn is_mechanism(e: &Entry) -> bool {
    first(e, |v| {
        v.name == "shaft.phi" && v.causality == Causality::Input
    })
    .is_some()
}

/// Every state of the co-simulation state machine that a bindery FMU can be in.
const STATES: [State; 6] = REACHABLE_STATES;

/// The serialized state of `probe`, an initialized instance, with its state code replaced:
/// how a host gets an instance into StepFailed or Error without a failing model (the runtime
/// restores the state a saved FMU state was taken in).
fn bytes_in_state(probe: &Slave, state: State) -> Vec<u8> {
    let mut bytes = probe.state_bytes();
    assert_eq!(
        u16::from_le_bytes([bytes[24], bytes[25]]),
        State::StepComplete.code()
    );
    bytes[24..26].copy_from_slice(&state.code().to_le_bytes());
    bytes
}

/// Drives a fresh instance into `state` by legal calls.
fn drive_to(s: &Slave, state: State) {
    let ok = |st: Status, what: &str| s.ok(st, what);
    match state {
        State::Instantiated => {}
        State::InitializationMode => ok(s.call0("fmi2EnterInitializationMode"), "enter"),
        State::StepComplete => ok(s.init(), "init"),
        State::Terminated => {
            ok(s.init(), "init");
            ok(s.call0("fmi2Terminate"), "terminate");
        }
        State::StepFailed | State::Error => {
            s.restore_bytes(&bytes_in_state(&s.fmu.initialized("probe"), state))
        }
        other => panic!("no way to reach {other:?}"),
    }
}

type Row = (&'static str, Call);

/// Every FMI 2.0 function that takes an instance, with its call.
const ROWS: &[Row] = &[
    ("fmi2SetDebugLogging", Call::SetDebugLogging),
    ("fmi2SetupExperiment", Call::SetupExperiment),
    ("fmi2EnterInitializationMode", Call::EnterInitializationMode),
    ("fmi2ExitInitializationMode", Call::ExitInitializationMode),
    ("fmi2Terminate", Call::Terminate),
    ("fmi2Reset", Call::Reset),
    ("fmi2FreeInstance", Call::FreeInstance),
    ("fmi2GetReal", Call::GetReal),
    ("fmi2GetInteger", Call::GetInteger),
    ("fmi2GetBoolean", Call::GetBoolean),
    ("fmi2GetString", Call::GetString),
    ("fmi2SetReal", Call::SetReal),
    ("fmi2SetInteger", Call::SetInteger),
    ("fmi2SetBoolean", Call::SetBoolean),
    ("fmi2SetString", Call::SetString),
    ("fmi2GetFMUstate", Call::GetFMUstate),
    ("fmi2SetFMUstate", Call::SetFMUstate),
    ("fmi2FreeFMUstate", Call::FreeFMUstate),
    ("fmi2SerializedFMUstateSize", Call::SerializedFMUstateSize),
    ("fmi2SerializeFMUstate", Call::SerializeFMUstate),
    ("fmi2DeSerializeFMUstate", Call::DeSerializeFMUstate),
    (
        "fmi2GetDirectionalDerivative",
        Call::GetDirectionalDerivative,
    ),
    ("fmi2SetRealInputDerivatives", Call::SetRealInputDerivatives),
    (
        "fmi2GetRealOutputDerivatives",
        Call::GetRealOutputDerivatives,
    ),
    ("fmi2DoStep", Call::DoStep),
    ("fmi2CancelStep", Call::CancelStep),
    ("fmi2GetStatus", Call::GetStatus),
    ("fmi2GetRealStatus", Call::GetRealStatus),
    ("fmi2GetIntegerStatus", Call::GetIntegerStatus),
    ("fmi2GetBooleanStatus", Call::GetBooleanStatus),
    ("fmi2GetStringStatus", Call::GetStringStatus),
];

/// Every Model Exchange function.
const ME_ROWS: &[Row] = &[
    ("fmi2EnterEventMode", Call::EnterEventMode),
    ("fmi2NewDiscreteStates", Call::NewDiscreteStates),
    ("fmi2EnterContinuousTimeMode", Call::EnterContinuousTimeMode),
    ("fmi2CompletedIntegratorStep", Call::CompletedIntegratorStep),
    ("fmi2SetTime", Call::SetTime),
    ("fmi2SetContinuousStates", Call::SetContinuousStates),
    ("fmi2GetDerivatives", Call::GetDerivatives),
    ("fmi2GetEventIndicators", Call::GetEventIndicators),
    ("fmi2GetContinuousStates", Call::GetContinuousStates),
    (
        "fmi2GetNominalsOfContinuousStates",
        Call::GetNominalsOfContinuousStates,
    ),
];

/// Every row, common, Co-Simulation and Model Exchange.
fn all_rows() -> impl Iterator<Item = &'static Row> {
    ROWS.iter().chain(ME_ROWS)
}

/// The FMU's number of continuous states (0: no Model Exchange interface).
/// The FMU's number of event indicators.
fn n_indicators(e: &Entry) -> usize {
    (e.info)().event_indicators as usize
}

/// Calls whose capability flag is false: refused with "not supported" in every state.
/// (`fmi2SetRealInputDerivatives` works where `canInterpolateInputs` is true,
/// `fmi2GetDirectionalDerivative` where `providesDirectionalDerivative` is.)
fn unsupported(call: Call, e: &Entry) -> bool {
    (call == Call::SetRealInputDerivatives && !(e.info)().can_interpolate_inputs)
        || (call == Call::GetDirectionalDerivative && !(e.info)().partials)
        || matches!(
            call,
            Call::GetRealOutputDerivatives
                | Call::CancelStep
                | Call::GetStatus
                | Call::GetIntegerStatus
                | Call::GetStringStatus
        )
}

/// A valid call of `call` on instance `c` (NULL included: every function must refuse it).
/// `fmu_state` is an FMU state of this instance (or NULL), `bytes` a serialized one.
fn invoke(
    f: &Fmu,
    e: &Entry,
    c: Component,
    call: Call,
    fmu_state: &mut FMUstate,
    bytes: &[u8],
) -> Status {
    type F0 = unsafe extern "C" fn(Component) -> Status;
    type Arr = unsafe extern "C" fn(Component, *mut Real, usize) -> Status;
    type Get<T> = unsafe extern "C" fn(Component, *const u32, usize, *mut T) -> Status;
    type Set<T> = unsafe extern "C" fn(Component, *const u32, usize, *const T) -> Status;
    // shaft.phi, shaft.tau, drive.mode of a mechanism
    let input = [drive_inputs(e)[0]];
    let real = [first(e, |v| {
        v.causality == Causality::Output && v.ty == VarType::Real
    })
    .expect("a Real output")];
    let int = [first(e, |v| {
        v.ty.is_integer_like() && v.causality == Causality::Parameter
    })
    .expect("an Integer or Enumeration parameter")];
    let boolean: Vec<u32> = first(e, |v| v.ty == VarType::Boolean).into_iter().collect();
    let bool_param: Vec<u32> = first(e, |v| {
        v.ty == VarType::Boolean && v.causality == Causality::Parameter
    })
    .into_iter()
    .collect();
    let name = all_rows().find(|r| r.1 == call).expect("a row").0;
    let nx = n_states(e);
    let nz = n_indicators(e);
    // SAFETY: each symbol is the FMI 2.0 function of that name, called with valid arguments.
    unsafe {
        match call {
            Call::SetDebugLogging => {
                let g: Symbol<
                    unsafe extern "C" fn(Component, Boolean, usize, *const FmiString) -> Status,
                > = f.sym(name);
                let cats = [c"logEvents".as_ptr()];
                g(c, TRUE, 1, cats.as_ptr())
            }
            Call::SetupExperiment => {
                let g: Symbol<
                    unsafe extern "C" fn(Component, Boolean, Real, Real, Boolean, Real) -> Status,
                > = f.sym(name);
                g(c, FALSE, 0.0, 0.0, TRUE, 10.0)
            }
            Call::EnterInitializationMode
            | Call::ExitInitializationMode
            | Call::Terminate
            | Call::Reset
            | Call::CancelStep => f.sym::<F0>(name)(c),
            Call::FreeInstance => {
                f.sym::<unsafe extern "C" fn(Component)>(name)(c);
                Status::Ok
            }
            Call::GetReal => {
                let mut out = [0.0];
                f.sym::<Get<Real>>(name)(c, real.as_ptr(), 1, out.as_mut_ptr())
            }
            Call::GetInteger => {
                let mut out = [0];
                f.sym::<Get<Integer>>(name)(c, int.as_ptr(), 1, out.as_mut_ptr())
            }
            Call::GetBoolean => {
                let mut out = [0; 1];
                f.sym::<Get<Boolean>>(name)(c, boolean.as_ptr(), boolean.len(), out.as_mut_ptr())
            }
            Call::GetString => {
                f.sym::<Get<FmiString>>(name)(c, std::ptr::null(), 0, std::ptr::null_mut())
            }
            Call::SetReal => f.sym::<Set<Real>>(name)(c, input.as_ptr(), 1, [0.25].as_ptr()),
            Call::SetInteger => {
                // an integer-typed variable settable in every phase: none is (drive.mode is
                // fixed), so nvr = 0, which is valid in every state that allows the call
                f.sym::<Set<Integer>>(name)(c, std::ptr::null(), 0, std::ptr::null())
            }
            Call::SetBoolean => {
                // tunable Boolean parameters do not exist either: nvr = 0 after initialization
                let n = if bool_param.is_empty() { 0 } else { 1 };
                let running = {
                    let mut out = [0.0];
                    // is the instance past initialization? (GetReal legal and Ok)
                    f.sym::<Get<Real>>("fmi2GetReal")(c, real.as_ptr(), 1, out.as_mut_ptr())
                        == Status::Ok
                };
                let n = if running { 0 } else { n };
                f.sym::<Set<Boolean>>(name)(c, bool_param.as_ptr(), n, [TRUE].as_ptr())
            }
            Call::SetString => {
                f.sym::<Set<FmiString>>(name)(c, std::ptr::null(), 0, std::ptr::null())
            }
            Call::GetFMUstate => f
                .sym::<unsafe extern "C" fn(Component, *mut FMUstate) -> Status>(name)(
                c, fmu_state,
            ),
            Call::SetFMUstate => {
                f.sym::<unsafe extern "C" fn(Component, FMUstate) -> Status>(name)(c, *fmu_state)
            }
            Call::FreeFMUstate => f
                .sym::<unsafe extern "C" fn(Component, *mut FMUstate) -> Status>(name)(
                c, fmu_state,
            ),
            Call::SerializedFMUstateSize => {
                let mut n = 0usize;
                f.sym::<unsafe extern "C" fn(Component, FMUstate, *mut usize) -> Status>(name)(
                    c, *fmu_state, &mut n,
                )
            }
            Call::SerializeFMUstate => {
                let mut buf = vec![0u8; bytes.len()];
                f.sym::<unsafe extern "C" fn(Component, FMUstate, *mut Byte, usize) -> Status>(name)(
                    c,
                    *fmu_state,
                    buf.as_mut_ptr() as *mut c_char,
                    buf.len(),
                )
            }
            Call::DeSerializeFMUstate => {
                let mut st: FMUstate = std::ptr::null_mut();
                let s = f.sym::<unsafe extern "C" fn(
                    Component,
                    *const Byte,
                    usize,
                    *mut FMUstate,
                ) -> Status>(name)(
                    c, bytes.as_ptr() as *const c_char, bytes.len(), &mut st
                );
                if !st.is_null() {
                    let free: Symbol<unsafe extern "C" fn(Component, *mut FMUstate) -> Status> =
                        f.sym("fmi2FreeFMUstate");
                    assert_eq!(free(c, &mut st), Status::Ok);
                }
                s
            }
            Call::GetDirectionalDerivative => {
                let mut out = [0.0];
                f.sym::<unsafe extern "C" fn(
                    Component,
                    *const u32,
                    usize,
                    *const u32,
                    usize,
                    *const Real,
                    *mut Real,
                ) -> Status>(name)(
                    c,
                    real.as_ptr(),
                    1,
                    input.as_ptr(),
                    1,
                    [1.0].as_ptr(),
                    out.as_mut_ptr(),
                )
            }
            Call::SetRealInputDerivatives => f.sym::<unsafe extern "C" fn(
                Component,
                *const u32,
                usize,
                *const Integer,
                *const Real,
            ) -> Status>(name)(
                c, input.as_ptr(), 1, [1].as_ptr(), [1.0].as_ptr()
            ),
            Call::GetRealOutputDerivatives => {
                let mut out = [0.0];
                f.sym::<unsafe extern "C" fn(
                    Component,
                    *const u32,
                    usize,
                    *const Integer,
                    *mut Real,
                ) -> Status>(name)(
                    c, real.as_ptr(), 1, [1].as_ptr(), out.as_mut_ptr()
                )
            }
            Call::DoStep => {
                let mut t = 0.0;
                let _ = f.sym::<unsafe extern "C" fn(Component, c_int, *mut Real) -> Status>(
                    "fmi2GetRealStatus",
                )(c, 2, &mut t);
                f.sym::<unsafe extern "C" fn(Component, Real, Real, Boolean) -> Status>(name)(
                    c, t, 0.01, TRUE,
                )
            }
            Call::GetStatus | Call::GetIntegerStatus => {
                let mut v = 0;
                f.sym::<unsafe extern "C" fn(Component, c_int, *mut c_int) -> Status>(name)(
                    c, 0, &mut v,
                )
            }
            Call::GetRealStatus => {
                let mut v = 0.0;
                f.sym::<unsafe extern "C" fn(Component, c_int, *mut Real) -> Status>(name)(
                    c, 2, &mut v,
                )
            }
            Call::GetBooleanStatus => {
                let mut v = 0;
                f.sym::<unsafe extern "C" fn(Component, c_int, *mut Boolean) -> Status>(name)(
                    c, 3, &mut v,
                )
            }
            Call::GetStringStatus => {
                let mut v: FmiString = std::ptr::null();
                f.sym::<unsafe extern "C" fn(Component, c_int, *mut FmiString) -> Status>(name)(
                    c, 0, &mut v,
                )
            }
            Call::EnterEventMode | Call::EnterContinuousTimeMode => f.sym::<F0>(name)(c),
            Call::NewDiscreteStates => {
                let mut info = EventInfo {
                    new_discrete_states_needed: TRUE,
                    terminate_simulation: TRUE,
                    nominals_of_continuous_states_changed: TRUE,
                    values_of_continuous_states_changed: TRUE,
                    next_event_time_defined: TRUE,
                    next_event_time: 0.0,
                };
                f.sym::<unsafe extern "C" fn(Component, *mut EventInfo) -> Status>(name)(
                    c, &mut info,
                )
            }
            Call::CompletedIntegratorStep => {
                let (mut enter, mut term) = (TRUE, TRUE);
                let s = f.sym::<unsafe extern "C" fn(
                    Component,
                    Boolean,
                    *mut Boolean,
                    *mut Boolean,
                ) -> Status>(name)(c, TRUE, &mut enter, &mut term);
                if s == Status::Ok {
                    assert_eq!((enter, term), (FALSE, FALSE));
                }
                s
            }
            Call::SetTime => f.sym::<unsafe extern "C" fn(Component, Real) -> Status>(name)(c, 0.0),
            Call::SetContinuousStates => {
                // (the matrix runs at the default level: no elastodynamic states, all 0)
                let x = vec![0.0; nx];
                f.sym::<unsafe extern "C" fn(Component, *const Real, usize) -> Status>(name)(
                    c,
                    x.as_ptr(),
                    nx,
                )
            }
            Call::GetDerivatives
            | Call::GetContinuousStates
            | Call::GetNominalsOfContinuousStates => {
                let mut x = vec![f64::NAN; nx];
                let s = f.sym::<Arr>(name)(c, x.as_mut_ptr(), nx);
                if s == Status::Ok {
                    assert!(x.iter().all(|v| v.is_finite()), "{name}: {x:?}");
                }
                s
            }
            Call::GetEventIndicators => {
                let mut z = vec![f64::NAN; nz];
                let s = f.sym::<Arr>(name)(c, z.as_mut_ptr(), nz);
                if s == Status::Ok {
                    assert!(z.iter().all(|v| v.is_finite()), "{name}: {z:?}");
                }
                s
            }
        }
    }
}

/// What one cell of a call-sequence matrix expects.
struct Cell {
    /// The FMU, the interface, the function and the state, for the messages.
    label: String,
    /// The instance's state, as the runtime names it in its log.
    state: String,
    /// Whether the call is legal in that state.
    legal: bool,
    /// Whether a refused call is also checked to leave the serialized state as it was.
    check_unchanged: bool,
}

/// One cell of a call-sequence matrix: `row`'s function called on `s`, an instance already in
/// the cell's state (with an FMU state of it taken first where `save`). An illegal call is
/// `fmi2Error` with a log line saying so, a legal but unsupported one `fmi2Error` "not
/// supported", any other legal one `fmi2OK`; a NULL instance is refused by every function.
fn check_cell(f: &Fmu, e: &Entry, s: Slave, (name, call): Row, save: bool, cell: &Cell) {
    let mut st: FMUstate = std::ptr::null_mut();
    if save {
        assert_eq!(s.get_state(&mut st), Status::Ok);
    }
    let (_, bytes) = s.serialize(st);
    let n_logs = s.logs().len();
    let status = invoke(f, e, s.c, call, &mut st, &bytes);
    let new_logs: Vec<LogLine> = s.logs()[n_logs..].to_vec();
    let label = &cell.label;
    if !cell.legal {
        assert_eq!(status, Status::Error, "{label}");
        assert!(
            new_logs.iter().any(|l| l.0 == Status::Error
                && l.2
                    .contains(&format!("not allowed in state {}", cell.state))),
            "{label}: {new_logs:?}"
        );
        // nothing changed: the instance's state serializes as before
        if cell.check_unchanged && call != Call::FreeInstance {
            let mut now: FMUstate = std::ptr::null_mut();
            assert_eq!(s.get_state(&mut now), Status::Ok, "{label}");
            assert_eq!(s.serialize(now).1, bytes, "{label}: changed");
            assert_eq!(s.free_state(&mut now), Status::Ok);
        }
    } else if unsupported(call, e) {
        assert_eq!(status, Status::Error, "{label}");
        assert!(
            new_logs.iter().any(|l| l.2.contains("not supported")),
            "{label}: {new_logs:?}"
        );
    } else {
        assert_eq!(status, Status::Ok, "{label}: {new_logs:?}");
    }
    if call == Call::FreeInstance {
        std::mem::forget(s);
    } else if call != Call::FreeFMUstate && !st.is_null() {
        assert_eq!(s.free_state(&mut st), Status::Ok, "{label}");
    }
    // a NULL instance is refused by every function, in no state at all
    let mut none: FMUstate = std::ptr::null_mut();
    if call != Call::FreeInstance {
        assert_eq!(
            invoke(f, e, std::ptr::null_mut(), call, &mut none, &bytes),
            Status::Error,
            "{name}(NULL)"
        );
    }
}

/// Every function in every state, for every FMU: an illegal call is `fmi2Error` with a log line
/// saying so and changes nothing; a legal one does what it should; a NULL instance is refused.
#[test]
fn call_sequence_matrix() {
    let _shared = shared();
    let mut cells = 0;
    for e in catalog::all() {
        let f = Fmu::of(&e);
        assert_eq!(
            ROWS.len(),
            31,
            "every FMI 2.0 common and CS function taking an instance"
        );
        assert_eq!(ME_ROWS.len(), 10, "every FMI 2.0 Model Exchange function");
        for &state in &STATES {
            for &row in all_rows() {
                let (name, call) = row;
                let s = f.slave("matrix");
                drive_to(&s, state);
                let cell = Cell {
                    label: format!("{} {name} in {state:?}", e.identifier),
                    state: format!("{state:?}"),
                    legal: allowed(call, state),
                    check_unchanged: false,
                };
                check_cell(&f, &e, s, row, allowed(Call::GetFMUstate, state), &cell);
                cells += 1;
            }
        }
    }
    assert_eq!(
        cells,
        catalog::all().len() * STATES.len() * (ROWS.len() + ME_ROWS.len())
    );
    eprintln!("call-sequence matrix: {cells} cells");
}

/// Drives a fresh Model Exchange instance into `state` by legal calls.
fn drive_me_to(s: &Slave, state: MeState) {
    let ok = |st: Status, what: &str| s.ok(st, what);
    match state {
        MeState::Instantiated => {}
        MeState::InitializationMode => ok(s.call0("fmi2EnterInitializationMode"), "enter"),
        MeState::EventMode => ok(s.init(), "init"),
        MeState::ContinuousTimeMode => {
            ok(s.init(), "init");
            ok(
                s.call0("fmi2EnterContinuousTimeMode"),
                "continuous-time mode",
            );
        }
        MeState::Terminated => {
            ok(s.init(), "init");
            ok(s.call0("fmi2Terminate"), "terminate");
        }
        MeState::Error => {
            // as for Co-Simulation: a saved state with the state code replaced
            let probe = s.fmu.me_instance("probe");
            probe.ok(probe.init(), "probe init");
            s.restore_bytes(&bytes_in_state(&probe, State::Error));
        }
    }
}

/// The Model Exchange state machine (FMI 2.0 section 3.2.3): every function, common,
/// Co-Simulation and Model Exchange, in every state of a Model Exchange instance, for every
/// FMU that provides Model Exchange (those with continuous states join by themselves): a legal
/// call does what it should, an illegal one is `fmi2Error` with a log line and changes nothing.
#[test]
fn model_exchange_call_sequence_matrix() {
    let _shared = shared();
    let mut cells = 0;
    let mut fmus = 0;
    for e in catalog::all() {
        if n_states(&e) == 0 {
            continue;
        }
        fmus += 1;
        let f = Fmu::of(&e);
        for &state in &ME_STATES {
            for &row in all_rows() {
                let (name, call) = row;
                let s = f.me_instance("me-matrix");
                drive_me_to(&s, state);
                let cell = Cell {
                    label: format!("{} ME {name} in {state:?}", e.identifier),
                    state: format!("{state:?}"),
                    legal: me_allowed(call, state),
                    check_unchanged: true,
                };
                check_cell(&f, &e, s, row, true, &cell);
                cells += 1;
            }
        }
    }
    assert!(fmus >= 1, "no FMU provides Model Exchange");
    assert_eq!(cells, fmus * ME_STATES.len() * (ROWS.len() + ME_ROWS.len()));
    eprintln!("Model Exchange call-sequence matrix: {fmus} FMUs, {cells} cells");
}

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
            let mut bad: FMUstate = std::ptr::null_mut();
            let de = s.deserialize(&b, &mut bad);
            if de == Status::Ok {
                assert_eq!(
                    s.set_state(bad),
                    Status::Error,
                    "{} state with {name} = {x} accepted",
                    e.identifier
                );
                assert!(s.last_error().contains(&name), "{name}: {}", s.last_error());
                assert_eq!(s.free_state(&mut bad), Status::Ok);
            }
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
            let mut bad: FMUstate = std::ptr::null_mut();
            let de = s.deserialize(&b, &mut bad);
            if de == Status::Ok {
                assert_eq!(
                    s.set_state(bad),
                    Status::Error,
                    "{} tampered {k} = {x}",
                    e.identifier
                );
                assert_eq!(s.free_state(&mut bad), Status::Ok);
            }
            assert!(
                s.last_error().contains(why),
                "{k} = {x}: {}",
                s.last_error()
            );
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
