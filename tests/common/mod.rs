//! A small FMI 2.0 host for the integration tests and benchmarks: loads a built FMU binary
//! with libloading and calls it through the C ABI, recording what it logs.
#![allow(dead_code)]

pub mod c_logger;
pub mod elastic;
pub mod fmi3;
#[cfg(target_os = "linux")]
pub mod heap;
pub mod me;
pub mod ode;
pub mod probe;
pub mod series;

use bindery_fmu::catalog::Entry;
use bindery_fmu::fmi2::types::*;
use bindery_fmu::model::{Causality, VarType};
use libloading::{Library, Symbol};
use std::ffi::{CStr, CString, c_char, c_void};
use std::fmt::Debug;
use std::path::PathBuf;
use std::sync::Mutex;

/// The runtime's Co-Simulation states a bindery FMU can be in (either FMI version; FMI 3.0's
/// Event Mode is a mode beside them). StepCanceled needs an asynchronous step and Fatal is never
/// entered: neither is reachable.
pub const REACHABLE_STATES: [bindery_fmu::fmi2::state::State; 6] = {
    use bindery_fmu::fmi2::state::State;
    [
        State::Instantiated,
        State::InitializationMode,
        State::StepComplete,
        State::StepFailed,
        State::Terminated,
        State::Error,
    ]
};

/// Every FMI 2.0 common and co-simulation function.
pub const FMI2_CS_FUNCTIONS: &[&str] = &[
    "fmi2GetTypesPlatform",
    "fmi2GetVersion",
    "fmi2SetDebugLogging",
    "fmi2Instantiate",
    "fmi2FreeInstance",
    "fmi2SetupExperiment",
    "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode",
    "fmi2Terminate",
    "fmi2Reset",
    "fmi2GetReal",
    "fmi2GetInteger",
    "fmi2GetBoolean",
    "fmi2GetString",
    "fmi2SetReal",
    "fmi2SetInteger",
    "fmi2SetBoolean",
    "fmi2SetString",
    "fmi2GetFMUstate",
    "fmi2SetFMUstate",
    "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize",
    "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative",
    "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives",
    "fmi2DoStep",
    "fmi2CancelStep",
    "fmi2GetStatus",
    "fmi2GetRealStatus",
    "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
];

/// Path of a built FMU binary: `target/{release,debug}/lib<id>.so`, newest first.
/// The test command builds them first (`cargo run --release -- build`).
pub fn binary_path(id: &str) -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target"));
    let candidates: Vec<PathBuf> = ["release", "debug"]
        .iter()
        .map(|p| target.join(p).join(format!("lib{id}.so")))
        .filter(|p| p.exists())
        .collect();
    candidates
        .into_iter()
        .max_by_key(|p| std::fs::metadata(p).and_then(|m| m.modified()).ok())
        .unwrap_or_else(|| panic!("lib{id}.so not built: run `cargo run --release -- build` first"))
}

/// One logged message: (status, category, message as the FMU sent it).
pub type LogLine = (Status, String, String);

static LOGS: Mutex<Vec<(usize, LogLine)>> = Mutex::new(Vec::new());

fn record(env: usize, status: Status, _: Option<&str>, category: Option<&str>, text: Option<&str>) {
    let s = |x: Option<&str>| x.unwrap_or_default().to_string();
    LOGS.lock()
        .unwrap()
        .push((env, (status, s(category), s(text))));
}

/// The logger the tests hand to the FMU: a real C-variadic function ([`c_logger`]) that
/// formats the message as a host does; the lines are kept per environment ([`logs_of`]).
pub fn logger() -> CallbackLogger {
    c_logger::logger(record)
}

static NEXT_ENV: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(1);

/// A loaded FMU binary.
pub struct Fmu {
    pub lib: Library,
    pub guid: String,
}

impl Fmu {
    pub fn load(id: &str, guid: &str) -> Fmu {
        // SAFETY: loading our own FMU binary, which has no library constructors.
        let lib = unsafe { Library::new(binary_path(id)) }.expect("load FMU binary");
        Fmu {
            lib,
            guid: guid.into(),
        }
    }

    /// The built binary of a catalog entry, with the entry's GUID.
    pub fn of(e: &Entry) -> Fmu {
        Fmu::load(e.identifier, &(e.describe)().1)
    }

    /// Asserts that the binary exports every function of `names`.
    pub fn assert_exports(&self, names: &[&str]) {
        for name in names {
            // SAFETY: only looks the symbol up.
            assert!(
                unsafe { self.lib.get::<*const ()>(name.as_bytes()) }.is_ok(),
                "{name} missing"
            );
        }
    }

    /// A function of the binary.
    pub fn sym<T>(&self, name: &str) -> Symbol<'_, T> {
        // SAFETY: the caller names the type of an FMI 2.0 function.
        unsafe { self.lib.get(name.as_bytes()) }.unwrap_or_else(|e| panic!("{name}: {e}"))
    }

    pub fn callbacks(&self, env: usize) -> CallbackFunctions {
        CallbackFunctions {
            logger: logger(),
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: env as *mut c_void,
        }
    }

    /// Raw fmi2Instantiate.
    pub fn instantiate_raw(
        &self,
        name: *const c_char,
        ty: FmuType,
        guid: *const c_char,
        res: *const c_char,
        f: *const CallbackFunctions,
    ) -> Component {
        let inst: Symbol<
            unsafe extern "C" fn(
                FmiString,
                FmuType,
                FmiString,
                FmiString,
                *const CallbackFunctions,
                Boolean,
                Boolean,
            ) -> Component,
        > = self.sym("fmi2Instantiate");
        unsafe { inst(name, ty, guid, res, f, FALSE, FALSE) }
    }

    /// A co-simulation instance with the right GUID and a recording logger.
    pub fn slave(&self, name: &str) -> Slave<'_> {
        self.instance(name, FmuType::CoSimulation)
    }

    /// A co-simulation instance set up from t = 0 without a stop time and initialized at the
    /// start values.
    pub fn initialized(&self, name: &str) -> Slave<'_> {
        self.started(name, &Start::default())
    }

    /// A co-simulation instance set up as `start` says, its variables set (before
    /// initialization), and initialized; every call asserted fmi2OK (see [`Slave::ok`]), a set
    /// naming the value reference and the value.
    pub fn started(&self, name: &str, start: &Start) -> Slave<'_> {
        let s = self.slave(name);
        s.ok(s.setup(start.time, start.stop), "fmi2SetupExperiment");
        for &(vr, x) in start.reals {
            s.ok(
                s.set_real(&[vr], &[x]),
                &format!("fmi2SetReal vr {vr} = {x}"),
            );
        }
        for &(vr, x) in start.integers {
            s.ok(
                s.set_integer(&[vr], &[x]),
                &format!("fmi2SetInteger vr {vr} = {x}"),
            );
        }
        s.ok(s.init(), "initialization");
        s
    }

    /// fmi2Instantiate with `guid` and the resource location `resources`, logging under an
    /// environment of its own: the component (NULL if refused) and that environment (for
    /// [`logs_of`]).
    pub fn instantiate_at(
        &self,
        name: &CStr,
        ty: FmuType,
        guid: &str,
        resources: &CStr,
    ) -> (Component, usize) {
        let env = NEXT_ENV.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        let f = self.callbacks(env);
        let g = CString::new(guid).unwrap();
        let c = self.instantiate_raw(name.as_ptr(), ty, g.as_ptr(), resources.as_ptr(), &f);
        (c, env)
    }

    /// A Model Exchange instance (for the FMUs that provide it).
    pub fn me_instance(&self, name: &str) -> Slave<'_> {
        self.instance(name, FmuType::ModelExchange)
    }

    /// An instance of either kind with the right GUID and a recording logger.
    pub fn instance(&self, name: &str, ty: FmuType) -> Slave<'_> {
        let env = NEXT_ENV.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        let f = self.callbacks(env);
        let n = CString::new(name).unwrap();
        let g = CString::new(self.guid.clone()).unwrap();
        let c = self.instantiate_raw(n.as_ptr(), ty, g.as_ptr(), std::ptr::null(), &f);
        assert!(!c.is_null(), "instantiate failed: {:?}", logs_of(env));
        Slave { fmu: self, c, env }
    }
}

/// How [`Fmu::started`] starts a co-simulation instance: the experiment's start and stop time,
/// and the variables set before initialization (parameters, the level `model.fidelity`, the
/// `drive.mode`, ...). The default: from t = 0, no stop time, every variable at its start.
#[derive(Clone, Copy, Debug, Default)]
pub struct Start<'a> {
    pub time: f64,
    pub stop: Option<f64>,
    /// Real variables: (value reference, value).
    pub reals: &'a [(u32, f64)],
    /// Integer and Enumeration variables: (value reference, value).
    pub integers: &'a [(u32, i32)],
}

/// Messages logged for one environment.
pub fn logs_of(env: usize) -> Vec<LogLine> {
    LOGS.lock()
        .unwrap()
        .iter()
        .filter(|(e, _)| *e == env)
        .map(|(_, l)| l.clone())
        .collect()
}

/// An instance.
pub struct Slave<'a> {
    pub fmu: &'a Fmu,
    pub c: Component,
    pub env: usize,
}

impl Slave<'_> {
    pub fn logs(&self) -> Vec<LogLine> {
        logs_of(self.env)
    }
    pub fn last_error(&self) -> String {
        self.logs()
            .iter()
            .rev()
            .find(|l| l.0 == Status::Error)
            .map(|l| l.2.clone())
            .unwrap_or_default()
    }
    /// Asserts that a call returned fmi2OK; the message names the call (`what`) and shows the
    /// instance's log.
    pub fn ok(&self, st: Status, what: &str) {
        assert_eq!(st, Status::Ok, "{what}: {:?}", self.logs());
    }
    /// Asserts that a call was refused: fmi2Error with a logged error containing `text`;
    /// `what` names the call (and the FMU) in the messages.
    pub fn assert_refused(&self, st: Status, text: &str, what: &str) {
        assert_eq!(st, Status::Error, "{what}");
        assert!(
            self.last_error().contains(text),
            "{what}: {:?}",
            self.last_error()
        );
    }
    /// Enters initialization mode (asserted fmi2OK) and tries to leave it, which must be
    /// refused with fmi2Error: the error it logged.
    pub fn initialization_refusal(&self) -> String {
        self.ok(
            self.call0("fmi2EnterInitializationMode"),
            "fmi2EnterInitializationMode",
        );
        assert_eq!(
            self.call0("fmi2ExitInitializationMode"),
            Status::Error,
            "fmi2ExitInitializationMode accepted: {:?}",
            self.logs()
        );
        self.last_error()
    }
    pub fn call0(&self, name: &str) -> Status {
        let f: Symbol<unsafe extern "C" fn(Component) -> Status> = self.fmu.sym(name);
        unsafe { f(self.c) }
    }
    pub fn setup(&self, start: f64, stop: Option<f64>) -> Status {
        let f: Symbol<
            unsafe extern "C" fn(Component, Boolean, Real, Real, Boolean, Real) -> Status,
        > = self.fmu.sym("fmi2SetupExperiment");
        unsafe {
            f(
                self.c,
                FALSE,
                0.0,
                start,
                stop.is_some() as Boolean,
                stop.unwrap_or(0.0),
            )
        }
    }
    pub fn init(&self) -> Status {
        self.call0("fmi2EnterInitializationMode")
            .max(self.call0("fmi2ExitInitializationMode"))
    }
    /// fmi2SetupExperiment(`start`, `stop`) then fmi2EnterInitializationMode and
    /// fmi2ExitInitializationMode, each asserted fmi2OK (see [`Slave::ok`]).
    pub fn setup_and_init(&self, start: f64, stop: Option<f64>) {
        self.ok(self.setup(start, stop), "fmi2SetupExperiment");
        self.ok(self.init(), "initialization");
    }
    pub fn get_real(&self, vrs: &[u32]) -> (Status, Vec<f64>) {
        let f: Symbol<unsafe extern "C" fn(Component, *const u32, usize, *mut Real) -> Status> =
            self.fmu.sym("fmi2GetReal");
        let mut out = vec![f64::NAN; vrs.len()];
        let s = unsafe { f(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) };
        (s, out)
    }
    pub fn set_real(&self, vrs: &[u32], vals: &[f64]) -> Status {
        let f: Symbol<unsafe extern "C" fn(Component, *const u32, usize, *const Real) -> Status> =
            self.fmu.sym("fmi2SetReal");
        unsafe { f(self.c, vrs.as_ptr(), vrs.len(), vals.as_ptr()) }
    }
    pub fn get_integer(&self, vrs: &[u32]) -> (Status, Vec<i32>) {
        let f: Symbol<unsafe extern "C" fn(Component, *const u32, usize, *mut Integer) -> Status> =
            self.fmu.sym("fmi2GetInteger");
        let mut out = vec![0; vrs.len()];
        let s = unsafe { f(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) };
        (s, out)
    }
    pub fn set_integer(&self, vrs: &[u32], vals: &[i32]) -> Status {
        let f: Symbol<
            unsafe extern "C" fn(Component, *const u32, usize, *const Integer) -> Status,
        > = self.fmu.sym("fmi2SetInteger");
        unsafe { f(self.c, vrs.as_ptr(), vrs.len(), vals.as_ptr()) }
    }
    pub fn get_boolean(&self, vrs: &[u32]) -> (Status, Vec<bool>) {
        let f: Symbol<unsafe extern "C" fn(Component, *const u32, usize, *mut Boolean) -> Status> =
            self.fmu.sym("fmi2GetBoolean");
        let mut out = vec![0; vrs.len()];
        let s = unsafe { f(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) };
        (s, out.into_iter().map(|b| b != 0).collect())
    }
    /// `fmi2SetRealInputDerivatives`.
    pub fn set_input_derivatives(&self, vrs: &[u32], orders: &[i32], vals: &[f64]) -> Status {
        assert!(vrs.len() == orders.len() && vrs.len() == vals.len());
        let f: Symbol<
            unsafe extern "C" fn(
                Component,
                *const u32,
                usize,
                *const Integer,
                *const Real,
            ) -> Status,
        > = self.fmu.sym("fmi2SetRealInputDerivatives");
        unsafe {
            f(
                self.c,
                vrs.as_ptr(),
                vrs.len(),
                orders.as_ptr(),
                vals.as_ptr(),
            )
        }
    }
    pub fn do_step(&self, t: f64, h: f64) -> Status {
        let f: Symbol<unsafe extern "C" fn(Component, Real, Real, Boolean) -> Status> =
            self.fmu.sym("fmi2DoStep");
        unsafe { f(self.c, t, h, TRUE) }
    }
    pub fn get_state(&self, s: &mut FMUstate) -> Status {
        let f: Symbol<unsafe extern "C" fn(Component, *mut FMUstate) -> Status> =
            self.fmu.sym("fmi2GetFMUstate");
        unsafe { f(self.c, s) }
    }
    pub fn set_state(&self, s: FMUstate) -> Status {
        let f: Symbol<unsafe extern "C" fn(Component, FMUstate) -> Status> =
            self.fmu.sym("fmi2SetFMUstate");
        unsafe { f(self.c, s) }
    }
    pub fn free_state(&self, s: &mut FMUstate) -> Status {
        let f: Symbol<unsafe extern "C" fn(Component, *mut FMUstate) -> Status> =
            self.fmu.sym("fmi2FreeFMUstate");
        unsafe { f(self.c, s) }
    }
    pub fn serialize(&self, s: FMUstate) -> (Status, Vec<u8>) {
        let size_f: Symbol<unsafe extern "C" fn(Component, FMUstate, *mut usize) -> Status> =
            self.fmu.sym("fmi2SerializedFMUstateSize");
        let ser: Symbol<unsafe extern "C" fn(Component, FMUstate, *mut Byte, usize) -> Status> =
            self.fmu.sym("fmi2SerializeFMUstate");
        let mut n = 0usize;
        let st = unsafe { size_f(self.c, s, &mut n) };
        if st != Status::Ok {
            return (st, vec![]);
        }
        let mut buf = vec![0u8; n];
        let st = unsafe { ser(self.c, s, buf.as_mut_ptr() as *mut Byte, n) };
        (st, buf)
    }
    /// fmi2GetFMUstate then fmi2SerializeFMUstate, both asserted fmi2OK: the state and its
    /// bytes.
    pub fn save_state(&self) -> (FMUstate, Vec<u8>) {
        let mut st: FMUstate = std::ptr::null_mut();
        self.ok(self.get_state(&mut st), "fmi2GetFMUstate");
        let (ok, bytes) = self.serialize(st);
        self.ok(ok, "fmi2SerializeFMUstate");
        (st, bytes)
    }
    /// The instance's state now, serialized (the FMU state taken is freed again).
    pub fn state_bytes(&self) -> Vec<u8> {
        let (mut st, bytes) = self.save_state();
        self.ok(self.free_state(&mut st), "fmi2FreeFMUstate");
        bytes
    }
    /// fmi2DeSerializeFMUstate asserted fmi2OK: the FMU state of `bytes`.
    pub fn deserialized(&self, bytes: &[u8]) -> FMUstate {
        let mut st: FMUstate = std::ptr::null_mut();
        self.ok(self.deserialize(bytes, &mut st), "fmi2DeSerializeFMUstate");
        st
    }
    /// Sets the instance to the serialized state `bytes` (deserialized, set and freed, each
    /// asserted fmi2OK).
    pub fn restore_bytes(&self, bytes: &[u8]) {
        let mut st = self.deserialized(bytes);
        self.ok(self.set_state(st), "fmi2SetFMUstate");
        self.ok(self.free_state(&mut st), "fmi2FreeFMUstate");
    }
    pub fn deserialize(&self, bytes: &[u8], s: &mut FMUstate) -> Status {
        let f: Symbol<
            unsafe extern "C" fn(Component, *const Byte, usize, *mut FMUstate) -> Status,
        > = self.fmu.sym("fmi2DeSerializeFMUstate");
        unsafe { f(self.c, bytes.as_ptr() as *const Byte, bytes.len(), s) }
    }
}

impl Drop for Slave<'_> {
    fn drop(&mut self) {
        let f: Symbol<unsafe extern "C" fn(Component)> = self.fmu.sym("fmi2FreeInstance");
        unsafe { f(self.c) }
    }
}

/// The value reference of the variable `name` of a catalog entry (panics naming both if there
/// is none).
pub fn vr_of(e: &Entry, name: &str) -> u32 {
    (e.variables)()
        .into_iter()
        .find(|(_, v)| v.name == name)
        .unwrap_or_else(|| panic!("{}: no variable {name}", e.identifier))
        .0
}

/// The value references of every Real output of a catalog entry, in order.
pub fn real_outputs_of(e: &Entry) -> Vec<u32> {
    (e.variables)()
        .into_iter()
        .filter(|(_, v)| v.causality == Causality::Output && v.ty == VarType::Real)
        .map(|(vr, _)| vr)
        .collect()
}

/// The names of every Real output of a catalog entry, in the order of [`real_outputs_of`].
pub fn real_output_names_of(e: &Entry) -> Vec<&'static str> {
    (e.variables)()
        .into_iter()
        .filter(|(_, v)| v.causality == Causality::Output && v.ty == VarType::Real)
        .map(|(_, v)| v.name)
        .collect()
}

/// What a run through the C ABI sets and reads at every communication point.
pub struct Probe<'a> {
    /// The Real inputs set before each step.
    pub inputs: &'a [u32],
    /// The Real outputs read before each step.
    pub reals: &'a [u32],
    /// The Boolean outputs read after them, as 0.0 or 1.0 at the end of the row.
    pub flags: &'a [u32],
}

/// Steps `s` `n` times by `h` from `t0`. At each communication point `t`, before its step, sets
/// `p.inputs` to `inputs_at(t)` and reads a row: `p.reals` then `p.flags`. Every call is
/// asserted fmi2OK (naming the call, t and the log). The rows, one per communication point.
pub fn sample_run(
    s: &Slave,
    p: &Probe,
    t0: f64,
    n: usize,
    h: f64,
    inputs_at: impl Fn(f64) -> Vec<f64>,
) -> Vec<Vec<f64>> {
    let mut rows = Vec::with_capacity(n);
    let mut t = t0;
    for _ in 0..n {
        s.ok(
            s.set_real(p.inputs, &inputs_at(t)),
            &format!("fmi2SetReal at t = {t}"),
        );
        let (st, mut row) = s.get_real(p.reals);
        s.ok(st, &format!("fmi2GetReal at t = {t}"));
        if !p.flags.is_empty() {
            let (st, flags) = s.get_boolean(p.flags);
            s.ok(st, &format!("fmi2GetBoolean at t = {t}"));
            row.extend(flags.iter().map(|&b| f64::from(u8::from(b))));
        }
        rows.push(row);
        s.ok(s.do_step(t, h), &format!("fmi2DoStep at t = {t}"));
        t += h;
    }
    rows
}

/// Asserts that a row of `outputs` sampled through the C ABI is the Rust model's, bit for bit:
/// `model(o)` is the model's value of output `o`. A mismatch names t, the output and both
/// values.
pub fn assert_row_is_the_models<V: Copy + Debug>(
    t: f64,
    outputs: &[V],
    row: &[f64],
    model: impl Fn(V) -> f64,
) {
    assert!(
        row.len() >= outputs.len(),
        "t = {t}: a row of {}",
        row.len()
    );
    for (&o, &x) in outputs.iter().zip(row) {
        let m = model(o);
        assert_eq!(x.to_bits(), m.to_bits(), "t = {t}, {o:?}: {x} vs {m}");
    }
}

/// A saved FMU state and its replays, from [`assert_state_replays`].
pub struct Replay<T> {
    /// The state `s` saved.
    pub saved: FMUstate,
    /// The state deserialized into `other`.
    pub copy: FMUstate,
    /// The serialized state.
    pub bytes: Vec<u8>,
    /// The run that continued from the saved state.
    pub run: T,
}

impl<T> Replay<T> {
    /// Frees both states (asserted fmi2OK, each pointer set to NULL): `s` and `other` as given
    /// to [`assert_state_replays`].
    pub fn free(mut self, s: &Slave, other: &Slave) {
        s.ok(s.free_state(&mut self.saved), "fmi2FreeFMUstate");
        other.ok(other.free_state(&mut self.copy), "fmi2FreeFMUstate");
        assert!(
            self.saved.is_null() && self.copy.is_null(),
            "freed states are NULL"
        );
    }
}

/// The FMU-state round trip a host relies on. `s` saves its state (get and serialize) and `run`
/// continues from it; set back to the saved state, `s` runs the same again; the bytes,
/// deserialized into `other`, serialize to the same bytes, and set there run the same again.
/// `what` names the case in the messages.
pub fn assert_state_replays<T: PartialEq + Debug>(
    s: &Slave,
    other: &Slave,
    what: &str,
    run: impl Fn(&Slave) -> T,
) -> Replay<T> {
    let (saved, bytes) = s.save_state();
    let first = run(s);
    s.ok(s.set_state(saved), "fmi2SetFMUstate");
    assert_eq!(run(s), first, "{what}: set state");
    let copy = other.deserialized(&bytes);
    assert_eq!(other.serialize(copy).1, bytes, "{what}: serialized again");
    other.ok(other.set_state(copy), "fmi2SetFMUstate");
    assert_eq!(run(other), first, "{what}: deserialized");
    Replay {
        saved,
        copy,
        bytes,
        run: first,
    }
}

/// The FMU's number of continuous states: 0 for one without Model Exchange.
#[allow(dead_code)]
pub fn n_states(e: &bindery_fmu::catalog::Entry) -> usize {
    (e.variables)()
        .iter()
        .filter(|(_, v)| v.derivative.is_some())
        .count()
}

/// The fidelity levels (`model.fidelity` items) a mechanism implements: kinematic and
/// kinetostatic, and elastodynamic where it has continuous states (the elastodynamic level is
/// the one with states); none for a model without levels (MainShaft).
#[allow(dead_code)]
pub fn levels(e: &bindery_fmu::catalog::Entry) -> Vec<i32> {
    let has_levels = (e.variables)()
        .iter()
        .any(|(_, v)| v.name == "model.fidelity");
    match (has_levels, n_states(e) > 0) {
        (false, _) => vec![],
        (true, false) => vec![1, 2],
        (true, true) => vec![1, 2, 3],
    }
}
