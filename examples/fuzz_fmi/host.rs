//! The fuzzer's host: the FMI functions of a binary ([`Api`]), a shadow of each instance's
//! state, random and hostile calls ([`Fuzzer`]) and the invariants checked after each
//! ([`Report`]); what chooses is an [`Rng`]. Used by the seeded smoke run (`main.rs`) and by the
//! coverage-guided targets (`fuzz/`), which include this file.
#![allow(clippy::type_complexity, dead_code)]

use bindery_fmu::catalog;
use bindery_fmu::fmi2::runtime::me::EventInfo;
use bindery_fmu::fmi2::state::{Call, MeState, State, allowed, me_allowed};
use bindery_fmu::fmi2::types::CallbackFunctions;
use bindery_fmu::model::{Causality, VarType, shaft};
use libloading::Library;
use std::cell::RefCell;
use std::ffi::{CStr, CString, c_char, c_int, c_void};

pub type Comp = *mut c_void;
type St = *mut c_void;

/// The FMI 2.0 functions of one binary, with C `int` for every enum a host passes in.
pub struct Api {
    _lib: Library,
    id: &'static str,
    guid: CString,
    /// (value reference, type, causality) of every variable.
    vars: Vec<(u32, VarType, Causality)>,
    /// Safe ranges of the parameters that set an elastodynamic step's work ([`BUDGET`]), by
    /// value reference, with the declared bounds (values outside them are refused).
    budget: Vec<(u32, f64, f64, f64, f64)>,
    /// Model Exchange: number of continuous states (0: none) and of event indicators.
    nx: usize,
    nz: usize,
    /// (value reference of model.fidelity, its elastodynamic item) where the level exists.
    elastodynamic: Option<(u32, c_int)>,
    instantiate: unsafe extern "C" fn(
        *const c_char,
        c_int,
        *const c_char,
        *const c_char,
        *const CallbackFunctions,
        c_int,
        c_int,
    ) -> Comp,
    free_instance: unsafe extern "C" fn(Comp),
    set_debug_logging: unsafe extern "C" fn(Comp, c_int, usize, *const *const c_char) -> c_int,
    setup: unsafe extern "C" fn(Comp, c_int, f64, f64, c_int, f64) -> c_int,
    enter: unsafe extern "C" fn(Comp) -> c_int,
    exit: unsafe extern "C" fn(Comp) -> c_int,
    terminate: unsafe extern "C" fn(Comp) -> c_int,
    reset: unsafe extern "C" fn(Comp) -> c_int,
    get_real: unsafe extern "C" fn(Comp, *const u32, usize, *mut f64) -> c_int,
    get_integer: unsafe extern "C" fn(Comp, *const u32, usize, *mut c_int) -> c_int,
    get_boolean: unsafe extern "C" fn(Comp, *const u32, usize, *mut c_int) -> c_int,
    get_string: unsafe extern "C" fn(Comp, *const u32, usize, *mut *const c_char) -> c_int,
    set_real: unsafe extern "C" fn(Comp, *const u32, usize, *const f64) -> c_int,
    set_integer: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int) -> c_int,
    set_boolean: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int) -> c_int,
    set_string: unsafe extern "C" fn(Comp, *const u32, usize, *const *const c_char) -> c_int,
    get_state: unsafe extern "C" fn(Comp, *mut St) -> c_int,
    set_state: unsafe extern "C" fn(Comp, St) -> c_int,
    free_state: unsafe extern "C" fn(Comp, *mut St) -> c_int,
    state_size: unsafe extern "C" fn(Comp, St, *mut usize) -> c_int,
    serialize: unsafe extern "C" fn(Comp, St, *mut c_char, usize) -> c_int,
    deserialize: unsafe extern "C" fn(Comp, *const c_char, usize, *mut St) -> c_int,
    directional: unsafe extern "C" fn(
        Comp,
        *const u32,
        usize,
        *const u32,
        usize,
        *const f64,
        *mut f64,
    ) -> c_int,
    set_input_der: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int, *const f64) -> c_int,
    get_output_der: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int, *mut f64) -> c_int,
    do_step: unsafe extern "C" fn(Comp, f64, f64, c_int) -> c_int,
    cancel_step: unsafe extern "C" fn(Comp) -> c_int,
    get_status: unsafe extern "C" fn(Comp, c_int, *mut c_int) -> c_int,
    get_real_status: unsafe extern "C" fn(Comp, c_int, *mut f64) -> c_int,
    get_integer_status: unsafe extern "C" fn(Comp, c_int, *mut c_int) -> c_int,
    get_boolean_status: unsafe extern "C" fn(Comp, c_int, *mut c_int) -> c_int,
    get_string_status: unsafe extern "C" fn(Comp, c_int, *mut *const c_char) -> c_int,
    me: Option<MeApi>,
}

/// The Model Exchange functions of a binary that provides them.
pub struct MeApi {
    enter_event_mode: unsafe extern "C" fn(Comp) -> c_int,
    new_discrete_states: unsafe extern "C" fn(Comp, *mut EventInfo) -> c_int,
    enter_continuous_time_mode: unsafe extern "C" fn(Comp) -> c_int,
    completed_integrator_step: unsafe extern "C" fn(Comp, c_int, *mut c_int, *mut c_int) -> c_int,
    set_time: unsafe extern "C" fn(Comp, f64) -> c_int,
    set_continuous_states: unsafe extern "C" fn(Comp, *const f64, usize) -> c_int,
    get_derivatives: unsafe extern "C" fn(Comp, *mut f64, usize) -> c_int,
    get_event_indicators: unsafe extern "C" fn(Comp, *mut f64, usize) -> c_int,
    get_continuous_states: unsafe extern "C" fn(Comp, *mut f64, usize) -> c_int,
    get_nominals: unsafe extern "C" fn(Comp, *mut f64, usize) -> c_int,
}

/// The fuzzer's budget: accepted values of these parameters are drawn from these ranges, so
/// one elastodynamic `fmi2DoStep` stays in milliseconds (a call's work budget,
/// `solver::work_budget`, lets a max_step of 1e-9 s be refused at once but rtol = 1e-14 spend
/// up to 2e6 right-hand sides, a second or two, which is legal and tested by
/// tests/elastodynamic.rs, only slow). Refused values (NaN, out of the declared bounds) are
/// still sent as drawn.
const BUDGET: &[(&str, f64, f64)] = &[
    ("solver.max_step", 1e-4, 0.1),
    ("solver.rtol", 1e-8, 1.0),
    ("solver.atol", 1e-12, 1.0),
    ("elastic.k", 1.0, 1e9),
    // 20x the nominal speed of the fastest machine (dynamics.md's extreme)
    ("drive.n", -200.0, 200.0),
];

/// On an instance at the elastodynamic level, also the shaft inputs (rad/s, rad/s2) and the
/// communication step (s) are held to these: radau5 on a 1e9 N/m chain at 200 rad/s takes
/// ~0.1 s per 0.05 s of simulated time.
const ELASTIC_W: f64 = 200.0;
const ELASTIC_A: f64 = 1e4;
const ELASTIC_H: f64 = 0.05;

impl Api {
    /// The FMI functions of the binary `lib<id>.so` in `dir`.
    pub fn load(dir: &std::path::Path, e: &catalog::Entry) -> Api {
        let path = dir.join(format!("lib{}.so", e.identifier));
        // SAFETY: our own FMU binary; it has no library constructors.
        let lib = unsafe { Library::new(&path) }.unwrap_or_else(|err| {
            panic!(
                "{}: {err} (build it first: cargo run --release -- build)",
                path.display()
            )
        });
        Api::of(lib, e)
    }

    /// The FMI functions of `e` in `lib` (a loaded binary, or the program itself where it
    /// exports them: the coverage-guided fuzz targets).
    pub fn of(lib: Library, e: &catalog::Entry) -> Api {
        macro_rules! f {
            ($name:literal) => {
                // SAFETY: the symbol is the FMI 2.0 function of that name, of the declared type.
                *unsafe { lib.get($name.as_bytes()) }
                    .unwrap_or_else(|err| panic!("{}: {err}", $name))
            };
        }
        let vars = (e.variables)();
        let nx = vars.iter().filter(|(_, v)| v.derivative.is_some()).count();
        let me = (nx > 0).then(|| MeApi {
            enter_event_mode: f!("fmi2EnterEventMode"),
            new_discrete_states: f!("fmi2NewDiscreteStates"),
            enter_continuous_time_mode: f!("fmi2EnterContinuousTimeMode"),
            completed_integrator_step: f!("fmi2CompletedIntegratorStep"),
            set_time: f!("fmi2SetTime"),
            set_continuous_states: f!("fmi2SetContinuousStates"),
            get_derivatives: f!("fmi2GetDerivatives"),
            get_event_indicators: f!("fmi2GetEventIndicators"),
            get_continuous_states: f!("fmi2GetContinuousStates"),
            get_nominals: f!("fmi2GetNominalsOfContinuousStates"),
        });
        Api {
            id: e.identifier,
            guid: CString::new((e.describe)().1).unwrap(),
            budget: vars
                .iter()
                .filter_map(|(vr, v)| {
                    BUDGET.iter().find(|b| b.0 == v.name).map(|b| {
                        let (lo, hi) = (v.min.unwrap_or(f64::MIN), v.max.unwrap_or(f64::MAX));
                        (*vr, b.1, b.2, lo, hi)
                    })
                })
                .collect(),
            nx,
            nz: (e.info)().event_indicators as usize,
            elastodynamic: vars
                .iter()
                .any(|(_, v)| v.name == "elastic.k")
                .then_some((bindery_fmu::model::shaft::FIDELITY, 3)),
            me,
            vars: vars
                .iter()
                .map(|(vr, v)| (*vr, v.ty, v.causality))
                .collect(),
            instantiate: f!("fmi2Instantiate"),
            free_instance: f!("fmi2FreeInstance"),
            set_debug_logging: f!("fmi2SetDebugLogging"),
            setup: f!("fmi2SetupExperiment"),
            enter: f!("fmi2EnterInitializationMode"),
            exit: f!("fmi2ExitInitializationMode"),
            terminate: f!("fmi2Terminate"),
            reset: f!("fmi2Reset"),
            get_real: f!("fmi2GetReal"),
            get_integer: f!("fmi2GetInteger"),
            get_boolean: f!("fmi2GetBoolean"),
            get_string: f!("fmi2GetString"),
            set_real: f!("fmi2SetReal"),
            set_integer: f!("fmi2SetInteger"),
            set_boolean: f!("fmi2SetBoolean"),
            set_string: f!("fmi2SetString"),
            get_state: f!("fmi2GetFMUstate"),
            set_state: f!("fmi2SetFMUstate"),
            free_state: f!("fmi2FreeFMUstate"),
            state_size: f!("fmi2SerializedFMUstateSize"),
            serialize: f!("fmi2SerializeFMUstate"),
            deserialize: f!("fmi2DeSerializeFMUstate"),
            directional: f!("fmi2GetDirectionalDerivative"),
            set_input_der: f!("fmi2SetRealInputDerivatives"),
            get_output_der: f!("fmi2GetRealOutputDerivatives"),
            do_step: f!("fmi2DoStep"),
            cancel_step: f!("fmi2CancelStep"),
            get_status: f!("fmi2GetStatus"),
            get_real_status: f!("fmi2GetRealStatus"),
            get_integer_status: f!("fmi2GetIntegerStatus"),
            get_boolean_status: f!("fmi2GetBooleanStatus"),
            get_string_status: f!("fmi2GetStringStatus"),
            _lib: lib,
        }
    }
}

// ---- the logger: counts what each call logged -------------------------------------------------

#[derive(Default)]
pub struct LogTally {
    errors: usize,
    pub lines: usize,
    panics: Vec<String>,
}

thread_local! {
    pub static TALLY: RefCell<LogTally> = RefCell::new(LogTally::default());
}

/// The tests' variadic C logger (`tests/c_host/logger.c`), which formats the message as a host
/// does.
use crate::c_logger;

fn record(
    _: usize,
    status: bindery_fmu::fmi2::types::Status,
    name: Option<&str>,
    cat: Option<&str>,
    msg: Option<&str>,
) {
    let (Some(_), Some(_), Some(m)) = (name, cat, msg) else {
        panic!("logger got a NULL string");
    };
    TALLY.with(|t| {
        let mut t = t.borrow_mut();
        t.lines += 1;
        if status == bindery_fmu::fmi2::types::Status::Error {
            t.errors += 1;
        }
        if m.contains("panic") {
            t.panics.push(m.to_string());
        }
    });
}

pub fn callbacks(logger: bool) -> CallbackFunctions {
    CallbackFunctions {
        logger: if logger {
            c_logger::logger(record)
        } else {
            None
        },
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    }
}

// ---- randomness ------------------------------------------------------------------------------

/// Where the fuzzer's choices come from: a seeded generator (the smoke run), or the bytes of a
/// coverage-guided fuzzer's input, eight a draw (zeros once they run out: [`Rng::exhausted`]).
pub enum Rng {
    Seeded(u64),
    /// A seeded generator that keeps what it drew as bytes: an input that [`Rng::Bytes`]
    /// replays as the same choices (a seed of a fuzz target's corpus).
    Recording(u64, Vec<u8>),
    Bytes {
        data: Vec<u8>,
        at: usize,
    },
}

impl Rng {
    /// The generator of `seed`.
    pub fn seeded(seed: u64) -> Rng {
        Rng::Seeded(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1)
    }
    /// Every byte of the input drawn.
    pub fn exhausted(&self) -> bool {
        matches!(self, Rng::Bytes { data, at } if *at >= data.len())
    }
    pub fn next(&mut self) -> u64 {
        let xorshift = |x: &mut u64| {
            // xorshift64*
            *x ^= *x >> 12;
            *x ^= *x << 25;
            *x ^= *x >> 27;
            x.wrapping_mul(0x2545_f491_4f6c_dd1d)
        };
        match self {
            Rng::Seeded(x) => xorshift(x),
            Rng::Recording(x, out) => {
                let v = xorshift(x);
                out.extend_from_slice(&v.to_le_bytes());
                v
            }
            Rng::Bytes { data, at } => {
                let mut b = [0u8; 8];
                let end = (*at + 8).min(data.len());
                if *at < end {
                    b[..end - *at].copy_from_slice(&data[*at..end]);
                }
                *at = (*at + 8).min(data.len().max(*at));
                u64::from_le_bytes(b)
            }
        }
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn chance(&mut self, percent: u64) -> bool {
        self.next() % 100 < percent
    }
    fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.below(xs.len())]
    }
    fn real(&mut self) -> f64 {
        const SPECIAL: [f64; 18] = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            std::f64::consts::PI,
            1e9,
            -1e9,
            1e300,
            -1e300,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e-12,
            1e4,
        ];
        match self.below(4) {
            0 => self.pick(&SPECIAL),
            1 => f64::from_bits(self.next()),
            _ => (self.next() as f64 / u64::MAX as f64 - 0.5) * 20.0,
        }
    }
    fn int(&mut self) -> c_int {
        match self.below(3) {
            0 => self.pick(&[0, 1, 2, 3, 4, -1, 5, 7, 12, c_int::MIN, c_int::MAX]),
            1 => self.next() as c_int,
            _ => self.below(8) as c_int,
        }
    }
}

// ---- the shadow host -------------------------------------------------------------------------

pub struct Inst {
    pub api: usize,
    pub c: Comp,
    state: State,
    /// Set to the elastodynamic level at instantiation.
    elastic: bool,
    /// A Model Exchange instance, and whether it is in continuous-time mode (else event mode).
    me: bool,
    ct: bool,
    /// FMU states this instance handed out and not freed, with the state (and mode) each holds.
    fmu_states: Vec<(St, State, bool)>,
    /// The last serialized state bytes (mutated into new ones).
    bytes: Vec<u8>,
}

#[derive(Default)]
pub struct Report {
    /// The slowest call (seconds, which).
    pub slowest: (f64, String),
    /// Completed `fmi2DoStep`s of instances set to the elastodynamic level, and their time.
    pub elastic_steps: (u64, f64),
    pub execs: u64,
    pub instantiated: u64,
    pub statuses: [u64; 6],
    pub findings: Vec<String>,
}

impl Report {
    fn finding(&mut self, what: String) {
        if self.findings.len() < 50 {
            eprintln!("FINDING: {what}");
        }
        self.findings.push(what);
    }
}

const CATEGORIES: [&CStr; 8] = [
    c"logEvents",
    c"logStatusWarning",
    c"logStatusDiscard",
    c"logStatusError",
    c"logStatusFatal",
    c"logAll",
    c"noSuchCategory",
    c"",
];

/// The Model Exchange state of a shadow (state, continuous-time mode).
fn me_state(state: State, ct: bool) -> Option<MeState> {
    Some(match state {
        State::Instantiated => MeState::Instantiated,
        State::InitializationMode => MeState::InitializationMode,
        State::StepComplete if ct => MeState::ContinuousTimeMode,
        State::StepComplete => MeState::EventMode,
        State::Terminated => MeState::Terminated,
        State::Error => MeState::Error,
        _ => return None,
    })
}

fn state_of_bytes(b: &[u8]) -> Option<State> {
    let code = u16::from_le_bytes(b.get(24..26)?.try_into().ok()?);
    State::from_code(code)
}

pub struct Fuzzer {
    pub apis: Vec<Api>,
    pub rng: Rng,
    pub live: Vec<Inst>,
    pub report: Report,
    /// The most instances alive at once.
    pub max_live: usize,
}

impl Fuzzer {
    /// Frees every live instance (the FMU states they hold go with them).
    pub fn free_all(&mut self) {
        for inst in self.live.drain(..) {
            // SAFETY: a live instance of this binary.
            unsafe { (self.apis[inst.api].free_instance)(inst.c) };
        }
    }

    fn vrs(&mut self, api: usize, want: fn(VarType) -> bool) -> Vec<u32> {
        let n = self.rng.below(6);
        let vars = &self.apis[api].vars;
        let typed: Vec<u32> = vars.iter().filter(|v| want(v.1)).map(|v| v.0).collect();
        (0..n)
            .map(|_| match self.rng.below(10) {
                0 => self
                    .rng
                    .pick(&[u32::MAX, vars.len() as u32, vars.len() as u32 + 1, 1 << 31]),
                1 | 2 => self.rng.below(vars.len()) as u32,
                _ if !typed.is_empty() => self.rng.pick(&typed),
                _ => self.rng.below(vars.len()) as u32,
            })
            .collect()
    }

    /// Makes one call on instance `k` (or instantiates/frees) and checks the invariants.
    pub fn step(&mut self) {
        if self.live.is_empty() || self.rng.chance(2) {
            self.instantiate();
            return;
        }
        let k = self.rng.below(self.live.len());
        if self.rng.chance(1) {
            let inst = self.live.swap_remove(k);
            // SAFETY: a live instance of this binary.
            unsafe { (self.apis[inst.api].free_instance)(inst.c) };
            self.report.execs += 1;
            return;
        }
        let before = TALLY.with(|t| {
            let t = t.borrow();
            (t.errors, t.panics.len())
        });
        let (state, me, ct) = (self.live[k].state, self.live[k].me, self.live[k].ct);
        let t_call = std::time::Instant::now();
        let (call, status) = self.call(k);
        let took = t_call.elapsed().as_secs_f64();
        if call == Call::DoStep && status == 0 && self.live[k].elastic {
            self.report.elastic_steps.0 += 1;
            self.report.elastic_steps.1 += took;
        }
        if took > self.report.slowest.0 {
            self.report.slowest = (
                took,
                format!("{} fmi2{call:?}", self.apis[self.live[k].api].id),
            );
        }
        self.report.execs += 1;
        let (errors, panics) = TALLY.with(|t| {
            let t = t.borrow();
            (t.errors, t.panics.len())
        });
        let inst = &mut self.live[k];
        let id = self.apis[inst.api].id;
        if !(0..=4).contains(&status) {
            self.report
                .finding(format!("{id}: fmi2{call:?} returned status {status}"));
            return;
        }
        self.report.statuses[status as usize] += 1;
        if panics > before.1 {
            let msg = TALLY.with(|t| t.borrow().panics.last().cloned().unwrap_or_default());
            self.report
                .finding(format!("{id}: fmi2{call:?} in {state:?}: {msg}"));
            inst.state = State::Error;
        }
        let legal = if me {
            me_state(state, ct).is_some_and(|s| me_allowed(call, s))
        } else {
            allowed(call, state)
        };
        if !legal && status != 3 {
            self.report.finding(format!(
                "{id}: fmi2{call:?} in state {state:?} (ME {me}, continuous-time {ct}) returned {status}, not fmi2Error"
            ));
        }
        if status == 3 && errors == before.0 {
            self.report.finding(format!(
                "{id}: fmi2{call:?} in state {state:?} returned fmi2Error without a log line"
            ));
        }
    }

    fn instantiate(&mut self) {
        if self.live.len() >= self.max_live {
            let inst = self.live.swap_remove(self.rng.below(self.max_live));
            // SAFETY: a live instance of this binary.
            unsafe { (self.apis[inst.api].free_instance)(inst.c) };
        }
        let api = self.rng.below(self.apis.len());
        let a = &self.apis[api];
        let good_name = !self.rng.chance(10);
        let name = if good_name {
            c"fuzz".as_ptr()
        } else {
            self.rng.pick(&[std::ptr::null(), c"".as_ptr()])
        };
        let has_me = a.me.is_some();
        let ty = if self.rng.chance(90) {
            // Model Exchange where the FMU provides it, a third of the time
            if has_me && self.rng.chance(33) { 0 } else { 1 }
        } else {
            self.rng.pick(&[0, 2, -1, 1000, c_int::MIN])
        };
        let good_type = ty == 1 || ty == 0 && has_me;
        let good_guid = !self.rng.chance(10);
        let wrong = CString::new(format!("{{{}-%s%n}}", self.rng.next())).unwrap();
        let guid = if good_guid {
            a.guid.as_ptr()
        } else {
            self.rng.pick(&[std::ptr::null(), wrong.as_ptr()])
        };
        let res = self.rng.pick(&[
            std::ptr::null(),
            c"file:///tmp/x%20y/".as_ptr(),
            c"http://x".as_ptr(),
            c"file:".as_ptr(),
        ]);
        let good_cb = !self.rng.chance(1);
        let cb = callbacks(good_cb || self.rng.chance(50));
        let cbp: *const CallbackFunctions = if good_cb || self.rng.chance(50) {
            &cb
        } else {
            std::ptr::null()
        };
        let logging = self.rng.int();
        // SAFETY: every pointer is NULL or valid for the call.
        let c = unsafe { (a.instantiate)(name, ty, guid, res, cbp, self.rng.int(), logging) };
        self.report.execs += 1;
        let valid = good_name && good_type && good_guid && !cbp.is_null() && cb.logger.is_some();
        if valid == c.is_null() {
            self.report.finding(format!(
                "{}: fmi2Instantiate(name ok {good_name}, type {ty}, guid ok {good_guid}, callbacks ok {}) returned {c:?}",
                a.id,
                !cbp.is_null() && cb.logger.is_some()
            ));
        }
        let elastic = !c.is_null() && a.elastodynamic.is_some() && self.rng.chance(30);
        if elastic {
            // often at the elastodynamic level (integrator, events, ME states) to fuzz it
            let (vr, level) = a.elastodynamic.expect("checked");
            // SAFETY: a live instance; one value reference and value.
            let s = unsafe { (a.set_integer)(c, &vr, 1, &level) };
            self.report.execs += 1;
            if s != 0 {
                self.report
                    .finding(format!("{}: model.fidelity = elastodynamic refused", a.id));
            }
        }
        if !c.is_null() {
            self.report.instantiated += 1;
            self.live.push(Inst {
                api,
                c,
                state: State::Instantiated,
                me: ty == 0,
                ct: false,
                elastic,
                fmu_states: Vec::new(),
                bytes: Vec::new(),
            });
        }
    }

    fn own_state(&mut self, k: usize) -> St {
        let inst = &self.live[k];
        match self.rng.below(10) {
            0 => std::ptr::null_mut(),
            // an FMU state of another live instance: must be refused, never followed
            1 => {
                let j = self.rng.below(self.live.len());
                self.live[j]
                    .fmu_states
                    .first()
                    .map(|s| s.0)
                    .unwrap_or(std::ptr::null_mut())
            }
            _ if !inst.fmu_states.is_empty() => {
                inst.fmu_states[self.rng.below(inst.fmu_states.len())].0
            }
            _ => std::ptr::null_mut(),
        }
    }

    fn mutate(&mut self, mut b: Vec<u8>) -> Vec<u8> {
        if b.is_empty() || self.rng.chance(20) {
            return b;
        }
        match self.rng.below(5) {
            0 => {
                let i = self.rng.below(b.len());
                b[i] ^= 1 << self.rng.below(8);
            }
            1 => b.truncate(self.rng.below(b.len())),
            2 => b.push(self.rng.next() as u8),
            3 if b.len() > 67 => {
                // overwrite one value (parameters, inputs, time) with a hostile number
                let i = 51 + 8 * self.rng.below((b.len() - 51) / 8);
                let x = self.rng.real().to_bits().to_le_bytes();
                b[i..i + 8].copy_from_slice(&x);
            }
            _ => {
                // another state code, time or stop time
                let i = self.rng.pick(&[24usize, 26, 34, 42, 50]);
                if i == 24 {
                    let code = self.rng.pick(&[1u16, 2, 4, 8, 16, 32, 64, 128, 3, 0xffff]);
                    b[24..26].copy_from_slice(&code.to_le_bytes());
                } else if i == 50 {
                    b[50] = self.rng.next() as u8;
                } else {
                    b[i..i + 8].copy_from_slice(&self.rng.real().to_bits().to_le_bytes());
                }
            }
        }
        b
    }

    fn call(&mut self, k: usize) -> (Call, c_int) {
        let api = self.live[k].api;
        let c = self.live[k].c;
        let a: *const Api = &self.apis[api];
        // SAFETY: `apis` is not modified while the fuzzer runs.
        let a = unsafe { &*a };
        let null_arrays = self.rng.chance(5);
        macro_rules! arr {
            ($v:expr) => {
                if null_arrays {
                    std::ptr::null()
                } else {
                    $v.as_ptr()
                }
            };
        }
        macro_rules! arr_mut {
            ($v:expr) => {
                if null_arrays {
                    std::ptr::null_mut()
                } else {
                    $v.as_mut_ptr()
                }
            };
        }
        let state = self.live[k].state;
        let elastic = self.live[k].elastic;
        // SAFETY (all calls below): `c` is a live instance; every array holds its length or is
        // NULL; FMU states are NULL, this instance's, or another live instance's.
        unsafe {
            match self.rng.below(if a.me.is_some() { 36 } else { 31 }) {
                0 => {
                    let n = self.rng.below(4);
                    let cats: Vec<*const c_char> = (0..n)
                        .map(|_| {
                            if self.rng.chance(5) {
                                std::ptr::null()
                            } else {
                                self.rng.pick(&CATEGORIES).as_ptr()
                            }
                        })
                        .collect();
                    (
                        Call::SetDebugLogging,
                        (a.set_debug_logging)(c, self.rng.int(), n, arr!(cats)),
                    )
                }
                1 => {
                    let start = if self.rng.chance(70) {
                        0.0
                    } else {
                        self.rng.real()
                    };
                    let stop = if self.rng.chance(50) {
                        start + 10.0
                    } else {
                        self.rng.real()
                    };
                    let s = (a.setup)(
                        c,
                        self.rng.int(),
                        self.rng.real(),
                        start,
                        self.rng.int(),
                        stop,
                    );
                    (Call::SetupExperiment, s)
                }
                2 | 3 => {
                    let s = (a.enter)(c);
                    if s == 0 {
                        self.live[k].state = State::InitializationMode;
                    }
                    (Call::EnterInitializationMode, s)
                }
                4 | 5 => {
                    let s = (a.exit)(c);
                    if s == 0 {
                        self.live[k].state = State::StepComplete;
                        self.live[k].ct = false;
                    }
                    (Call::ExitInitializationMode, s)
                }
                6 => {
                    let s = (a.terminate)(c);
                    if s == 0 {
                        self.live[k].state = State::Terminated;
                    }
                    (Call::Terminate, s)
                }
                7 => {
                    let s = (a.reset)(c);
                    if s == 0 {
                        self.live[k].state = State::Instantiated;
                        self.live[k].ct = false;
                    }
                    (Call::Reset, s)
                }
                8 | 9 => {
                    let vrs = self.vrs(api, |t| t == VarType::Real);
                    let mut out = vec![0.0; vrs.len()];
                    (
                        Call::GetReal,
                        (a.get_real)(c, arr!(vrs), vrs.len(), arr_mut!(out)),
                    )
                }
                10 => {
                    let vrs = self.vrs(api, VarType::is_integer_like);
                    let mut out = vec![0; vrs.len()];
                    (
                        Call::GetInteger,
                        (a.get_integer)(c, arr!(vrs), vrs.len(), arr_mut!(out)),
                    )
                }
                11 => {
                    let vrs = self.vrs(api, |t| t == VarType::Boolean);
                    let mut out = vec![0; vrs.len()];
                    (
                        Call::GetBoolean,
                        (a.get_boolean)(c, arr!(vrs), vrs.len(), arr_mut!(out)),
                    )
                }
                12 => {
                    let vrs = self.vrs(api, |_| true);
                    let mut out = vec![std::ptr::null(); vrs.len()];
                    (
                        Call::GetString,
                        (a.get_string)(c, arr!(vrs), vrs.len(), arr_mut!(out)),
                    )
                }
                13..=15 => {
                    let vrs = self.vrs(api, |t| t == VarType::Real);
                    let vals: Vec<f64> = vrs
                        .iter()
                        .map(|&vr| {
                            let x = self.rng.real();
                            match a.budget.iter().find(|b| b.0 == vr) {
                                // an accepted value of a budget parameter: into its safe range
                                Some(&(_, lo, hi, min, max)) if x >= min && x <= max => {
                                    x.clamp(lo, hi)
                                }
                                _ if elastic && x.is_finite() && vr == shaft::W => {
                                    x.clamp(-ELASTIC_W, ELASTIC_W)
                                }
                                _ if elastic && x.is_finite() && vr == shaft::A => {
                                    x.clamp(-ELASTIC_A, ELASTIC_A)
                                }
                                _ => x,
                            }
                        })
                        .collect();
                    (
                        Call::SetReal,
                        (a.set_real)(c, arr!(vrs), vrs.len(), arr!(vals)),
                    )
                }
                16 => {
                    let vrs = self.vrs(api, VarType::is_integer_like);
                    let vals: Vec<c_int> = vrs.iter().map(|_| self.rng.int()).collect();
                    let s = (a.set_integer)(c, arr!(vrs), vrs.len(), arr!(vals));
                    if s == 0
                        && vrs
                            .iter()
                            .zip(&vals)
                            .any(|(&v, &x)| v == shaft::FIDELITY && x == 3)
                    {
                        // the elastodynamic level: from now on held to its budget
                        self.live[k].elastic = true;
                    }
                    (Call::SetInteger, s)
                }
                17 => {
                    let vrs = self.vrs(api, |t| t == VarType::Boolean);
                    let vals: Vec<c_int> = vrs.iter().map(|_| self.rng.int()).collect();
                    (
                        Call::SetBoolean,
                        (a.set_boolean)(c, arr!(vrs), vrs.len(), arr!(vals)),
                    )
                }
                18 => {
                    let vrs = self.vrs(api, |_| true);
                    let vals: Vec<*const c_char> = vrs.iter().map(|_| c"x".as_ptr()).collect();
                    (
                        Call::SetString,
                        (a.set_string)(c, arr!(vrs), vrs.len(), arr!(vals)),
                    )
                }
                19 => {
                    let mut st = if self.rng.chance(30) {
                        self.own_state(k)
                    } else {
                        std::ptr::null_mut()
                    };
                    let fresh = st.is_null();
                    let sp: *mut St = if self.rng.chance(3) {
                        std::ptr::null_mut()
                    } else {
                        &mut st
                    };
                    let s = (a.get_state)(c, sp);
                    if s == 0 {
                        let inst = &mut self.live[k];
                        let ct = inst.ct;
                        if fresh {
                            inst.fmu_states.push((st, state, ct));
                        } else if let Some(e) = inst.fmu_states.iter_mut().find(|e| e.0 == st) {
                            (e.1, e.2) = (state, ct);
                        }
                    }
                    (Call::GetFMUstate, s)
                }
                20 => {
                    let st = self.own_state(k);
                    let s = (a.set_state)(c, st);
                    if s == 0 {
                        let inst = &mut self.live[k];
                        match inst.fmu_states.iter().find(|e| e.0 == st) {
                            Some(e) => (inst.state, inst.ct) = (e.1, e.2),
                            None => self.report.finding(format!(
                                "{}: fmi2SetFMUstate accepted a foreign state",
                                a.id
                            )),
                        }
                    }
                    (Call::SetFMUstate, s)
                }
                21 => {
                    let orig = self.own_state(k);
                    let mut st = orig;
                    let s = (a.free_state)(c, &mut st);
                    if s == 0 && !st.is_null() {
                        self.report.finding(format!(
                            "{}: fmi2FreeFMUstate did not clear the pointer",
                            a.id
                        ));
                    }
                    if s == 0 {
                        self.live[k].fmu_states.retain(|e| e.0 != orig);
                    }
                    (Call::FreeFMUstate, s)
                }
                22 => {
                    let st = self.own_state(k);
                    let mut n = 0usize;
                    let np: *mut usize = if self.rng.chance(5) {
                        std::ptr::null_mut()
                    } else {
                        &mut n
                    };
                    (Call::SerializedFMUstateSize, (a.state_size)(c, st, np))
                }
                23 | 24 => {
                    let st = self.own_state(k);
                    let mut n = 0usize;
                    let s = (a.state_size)(c, st, &mut n);
                    if s != 0 {
                        return (Call::SerializedFMUstateSize, s);
                    }
                    let short = self.rng.chance(10);
                    let len = if short { n / 2 } else { n };
                    let mut buf = vec![0u8; len];
                    let bp: *mut c_char = if self.rng.chance(5) {
                        std::ptr::null_mut()
                    } else {
                        buf.as_mut_ptr() as *mut c_char
                    };
                    let s = (a.serialize)(c, st, bp, len);
                    if s == 0 {
                        self.live[k].bytes = buf;
                    }
                    (Call::SerializeFMUstate, s)
                }
                25 | 26 => {
                    // bytes of this instance, of another instance (maybe another FMU), mutated
                    let j = if self.rng.chance(20) {
                        self.rng.below(self.live.len())
                    } else {
                        k
                    };
                    let b = self.live[j].bytes.clone();
                    let b = self.mutate(b);
                    let mut st = if self.rng.chance(20) {
                        self.own_state(k)
                    } else {
                        std::ptr::null_mut()
                    };
                    let fresh = st.is_null();
                    let bp: *const c_char = if b.is_empty() && self.rng.chance(50) {
                        std::ptr::null()
                    } else {
                        b.as_ptr() as *const c_char
                    };
                    let s = (a.deserialize)(c, bp, b.len(), &mut st);
                    if s == 0 {
                        let code = state_of_bytes(&b).unwrap_or(State::Fatal);
                        // the last byte: continuous-time mode of a Model Exchange state
                        let ct = b.last() == Some(&1);
                        let inst = &mut self.live[k];
                        if fresh {
                            inst.fmu_states.push((st, code, ct));
                        } else if let Some(e) = inst.fmu_states.iter_mut().find(|e| e.0 == st) {
                            (e.1, e.2) = (code, ct);
                        }
                    }
                    (Call::DeSerializeFMUstate, s)
                }
                27 => {
                    let mut t = f64::NAN;
                    let s = (a.get_real_status)(c, 2, &mut t);
                    if s != 0 || self.rng.chance(10) {
                        t = self.rng.real();
                    }
                    let h = if self.rng.chance(80) {
                        self.rng.pick(&[1e-3, 0.01, 0.1, 0.37])
                    } else {
                        // hostile sizes; not 1e3..1e9 s, which an elastodynamic level integrates
                        // up to its work budget (a second or two each): legal, only slow
                        self.rng.pick(&[
                            0.0,
                            -0.0,
                            -1e-3,
                            f64::NAN,
                            f64::INFINITY,
                            f64::NEG_INFINITY,
                            5e-324,
                            1e-300,
                            10.0,
                            1e300,
                            f64::MAX,
                        ])
                    };
                    let h = if elastic && h > ELASTIC_H {
                        ELASTIC_H
                    } else {
                        h
                    };
                    let s = (a.do_step)(c, t, h, self.rng.int());
                    if s == 2 {
                        self.live[k].state = State::StepFailed;
                    }
                    (Call::DoStep, s)
                }
                28 => {
                    let vrs = self.vrs(api, |_| true);
                    let vals: Vec<f64> = vrs.iter().map(|_| self.rng.real()).collect();
                    let ord: Vec<c_int> = vrs.iter().map(|_| self.rng.int()).collect();
                    match self.rng.below(3) {
                        0 => {
                            let mut out = vec![0.0; vrs.len()];
                            (
                                Call::GetDirectionalDerivative,
                                (a.directional)(
                                    c,
                                    arr!(vrs),
                                    vrs.len(),
                                    arr!(vrs),
                                    vrs.len(),
                                    arr!(vals),
                                    arr_mut!(out),
                                ),
                            )
                        }
                        1 if self.rng.chance(50) => {
                            // valid ones: Real inputs, orders 1 and 2, finite values
                            let inputs: Vec<u32> = a
                                .vars
                                .iter()
                                .filter(|v| v.1 == VarType::Real && v.2 == Causality::Input)
                                .map(|v| v.0)
                                .collect();
                            let n = 1 + self.rng.below(3);
                            let vrs: Vec<u32> = (0..n).map(|_| self.rng.pick(&inputs)).collect();
                            let ord: Vec<c_int> =
                                vrs.iter().map(|_| 1 + self.rng.below(2) as c_int).collect();
                            let vals: Vec<f64> = vrs
                                .iter()
                                .map(|_| (self.rng.next() as f64 / u64::MAX as f64 - 0.5) * 40.0)
                                .collect();
                            (
                                Call::SetRealInputDerivatives,
                                (a.set_input_der)(c, arr!(vrs), n, arr!(ord), arr!(vals)),
                            )
                        }
                        1 => (
                            Call::SetRealInputDerivatives,
                            (a.set_input_der)(c, arr!(vrs), vrs.len(), arr!(ord), arr!(vals)),
                        ),
                        _ => {
                            let mut out = vec![0.0; vrs.len()];
                            (
                                Call::GetRealOutputDerivatives,
                                (a.get_output_der)(
                                    c,
                                    arr!(vrs),
                                    vrs.len(),
                                    arr!(ord),
                                    arr_mut!(out),
                                ),
                            )
                        }
                    }
                }
                29 => (Call::CancelStep, (a.cancel_step)(c)),
                31.. => self.me_call(k),
                _ => {
                    let kind = self.rng.int();
                    let np = self.rng.chance(5);
                    match self.rng.below(5) {
                        0 => {
                            let mut v = 0;
                            (
                                Call::GetStatus,
                                (a.get_status)(
                                    c,
                                    kind,
                                    if np { std::ptr::null_mut() } else { &mut v },
                                ),
                            )
                        }
                        1 => {
                            let mut v = 0.0;
                            (
                                Call::GetRealStatus,
                                (a.get_real_status)(
                                    c,
                                    kind,
                                    if np { std::ptr::null_mut() } else { &mut v },
                                ),
                            )
                        }
                        2 => {
                            let mut v = 0;
                            (
                                Call::GetIntegerStatus,
                                (a.get_integer_status)(
                                    c,
                                    kind,
                                    if np { std::ptr::null_mut() } else { &mut v },
                                ),
                            )
                        }
                        3 => {
                            let mut v = 0;
                            (
                                Call::GetBooleanStatus,
                                (a.get_boolean_status)(
                                    c,
                                    kind,
                                    if np { std::ptr::null_mut() } else { &mut v },
                                ),
                            )
                        }
                        _ => {
                            let mut v = std::ptr::null();
                            (
                                Call::GetStringStatus,
                                (a.get_string_status)(
                                    c,
                                    kind,
                                    if np { std::ptr::null_mut() } else { &mut v },
                                ),
                            )
                        }
                    }
                }
            }
        }
    }
}

impl Fuzzer {
    /// One Model Exchange call on instance `k` (of a binary that provides them; on a
    /// Co-Simulation instance each is refused): random modes, times, states, wrong nx/nz,
    /// NULL arrays and pointers.
    fn me_call(&mut self, k: usize) -> (Call, c_int) {
        let a: *const Api = &self.apis[self.live[k].api];
        // SAFETY: `apis` is not modified while the fuzzer runs.
        let a = unsafe { &*a };
        let me = a.me.as_ref().expect("an FMU with Model Exchange");
        let c = self.live[k].c;
        let nx = match self.rng.below(10) {
            0 => 0,
            1 => a.nx + 1,
            2 => self.rng.pick(&[a.nx.saturating_sub(1), 1 << 20]),
            _ => a.nx,
        };
        let nz = match self.rng.below(10) {
            0 => 0,
            1 => a.nz + 1,
            _ => a.nz,
        };
        let null = self.rng.chance(5);
        // arrays as long as the counts (up to a cap: a huge count is refused before any read)
        let mut buf = vec![0.0f64; nx.max(nz).min(64)];
        let p = if null || nx.max(nz) > 64 {
            std::ptr::null_mut()
        } else {
            buf.as_mut_ptr()
        };
        // SAFETY: `c` is a live instance; `p` is NULL or holds max(nx, nz) reals.
        unsafe {
            match self.rng.below(10) {
                0 => {
                    let s = (me.enter_event_mode)(c);
                    if s == 0 {
                        self.live[k].ct = false;
                    }
                    (Call::EnterEventMode, s)
                }
                1 => {
                    let mut info = std::mem::zeroed::<EventInfo>();
                    let ip: *mut EventInfo = if null {
                        std::ptr::null_mut()
                    } else {
                        &mut info
                    };
                    (Call::NewDiscreteStates, (me.new_discrete_states)(c, ip))
                }
                2 => {
                    let s = (me.enter_continuous_time_mode)(c);
                    if s == 0 {
                        self.live[k].ct = true;
                    }
                    (Call::EnterContinuousTimeMode, s)
                }
                3 => {
                    let (mut e, mut t) = (0, 0);
                    let ep: *mut c_int = if null { std::ptr::null_mut() } else { &mut e };
                    (
                        Call::CompletedIntegratorStep,
                        (me.completed_integrator_step)(c, self.rng.int(), ep, &mut t),
                    )
                }
                4 => {
                    let t = if self.rng.chance(70) {
                        self.rng.below(1000) as f64 * 1e-3
                    } else {
                        self.rng.real()
                    };
                    (Call::SetTime, (me.set_time)(c, t))
                }
                5 => {
                    for x in buf.iter_mut() {
                        *x = if self.rng.chance(80) {
                            (self.rng.next() as f64 / u64::MAX as f64 - 0.5) * 1e-2
                        } else {
                            self.rng.real()
                        };
                    }
                    let p = if p.is_null() {
                        std::ptr::null()
                    } else {
                        buf.as_ptr()
                    };
                    (
                        Call::SetContinuousStates,
                        (me.set_continuous_states)(c, p, nx),
                    )
                }
                6 => (Call::GetDerivatives, (me.get_derivatives)(c, p, nx)),
                7 => (
                    Call::GetEventIndicators,
                    (me.get_event_indicators)(c, p, nz),
                ),
                8 => (
                    Call::GetContinuousStates,
                    (me.get_continuous_states)(c, p, nx),
                ),
                _ => (
                    Call::GetNominalsOfContinuousStates,
                    (me.get_nominals)(c, p, nx),
                ),
            }
        }
    }
}

/// `--cycles N`: N instantiate, get FMU state, free cycles over the FMUs (every 100th also
/// initializes and steps; the FMU state is left for fmi2FreeInstance to free), for a leak
/// checker to look at.
pub fn run_cycles(apis: &[Api], n: u64) {
    let cb = callbacks(true);
    for k in 0..n {
        let a = &apis[(k % apis.len() as u64) as usize];
        // SAFETY: valid arguments; the instance is freed at the end of the cycle.
        unsafe {
            let c = (a.instantiate)(
                c"cycle".as_ptr(),
                1,
                a.guid.as_ptr(),
                std::ptr::null(),
                &cb,
                0,
                0,
            );
            assert!(!c.is_null());
            // preparing a model can take a millisecond: every 100th cycle initializes and steps
            if k % 100 == 0 {
                assert_eq!((a.enter)(c), 0);
                assert_eq!((a.exit)(c), 0);
                assert_eq!((a.do_step)(c, 0.0, 0.01, 1), 0);
            }
            let mut st: St = std::ptr::null_mut();
            assert_eq!((a.get_state)(c, &mut st), 0);
            (a.free_instance)(c);
        }
    }
}

/// The most FMI calls one input of a coverage-guided target makes.
pub const CALLS: u64 = 200;

/// One input of a coverage-guided target on the FMU `api`: up to [`CALLS`] calls on at most
/// three live instances, every choice drawn from `data`, then every instance freed; the report
/// (its findings) of the run.
pub fn run_input(api: Api, data: &[u8]) -> Report {
    let mut f = Fuzzer {
        apis: vec![api],
        rng: Rng::Bytes {
            data: data.to_vec(),
            at: 0,
        },
        live: Vec::new(),
        report: Report::default(),
        max_live: 3,
    };
    while f.report.execs < CALLS && !f.rng.exhausted() {
        f.step();
    }
    f.free_all();
    f.report
}

/// The input [`run_input`] replays as the calls of the seeded generator `seed` on `api`.
pub fn record_input(api: Api, seed: u64) -> Vec<u8> {
    let Rng::Seeded(x) = Rng::seeded(seed) else {
        unreachable!()
    };
    let mut f = Fuzzer {
        apis: vec![api],
        rng: Rng::Recording(x, Vec::new()),
        live: Vec::new(),
        report: Report::default(),
        max_live: 3,
    };
    while f.report.execs < CALLS {
        f.step();
    }
    f.free_all();
    match f.rng {
        Rng::Recording(_, out) => out,
        _ => unreachable!(),
    }
}
