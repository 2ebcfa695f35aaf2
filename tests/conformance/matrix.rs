//! The call-sequence matrices: every FMI 2.0 function in every state of the Co-Simulation and
//! the Model Exchange state machine, for every FMU.

use super::*;

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
