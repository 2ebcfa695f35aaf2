//! A small FMI 3.0 host for the integration tests: the same built binaries as the FMI 2.0
//! host ([`super::Fmu`]), called through their `fmi3*` functions, with a recording
//! `fmi3LogMessageCallback`.

use super::LogLine;
use bindery_fmu::catalog::Entry;
use bindery_fmu::fmi3::types::*;
use bindery_fmu::model::{Var, VarType};
use libloading::{Library, Symbol};
use std::ffi::{CStr, CString, c_char, c_void};
use std::sync::Mutex;

static LOGS: Mutex<Vec<(usize, LogLine)>> = Mutex::new(Vec::new());
static NEXT_ENV: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(1 << 20);

unsafe extern "C" fn record(env: *mut c_void, status: Status, cat: FmiString, msg: FmiString) {
    let s = |p: FmiString| {
        if p.is_null() {
            String::new()
        } else {
            // SAFETY: the FMU passes valid C strings.
            unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
        }
    };
    LOGS.lock()
        .unwrap()
        .push((env as usize, (status, s(cat), s(msg))));
}

/// Messages logged for one environment.
pub fn logs_of(env: usize) -> Vec<LogLine> {
    (LOGS.lock().unwrap().iter())
        .filter(|(e, _)| *e == env)
        .map(|(_, l)| l.clone())
        .collect()
}

/// A new logging environment.
pub fn new_env() -> usize {
    NEXT_ENV.fetch_add(1, std::sync::atomic::Ordering::SeqCst)
}

/// A loaded FMU binary, seen as an FMI 3.0 FMU.
pub struct Fmu3 {
    pub lib: Library,
    pub token: String,
}

type InstantiateCs = unsafe extern "C" fn(
    FmiString,
    FmiString,
    FmiString,
    Boolean,
    Boolean,
    Boolean,
    Boolean,
    *const ValueReference,
    usize,
    InstanceEnvironment,
    LogMessageCallback,
    IntermediateUpdateCallback,
) -> Instance;

impl Fmu3 {
    /// The built binary of a catalog entry, with its instantiation token.
    pub fn of(e: &Entry) -> Fmu3 {
        // SAFETY: loading our own FMU binary, which has no library constructors.
        let lib = unsafe { Library::new(super::binary_path(e.identifier)) }.expect("load");
        Fmu3 {
            lib,
            token: (e.describe3)().1,
        }
    }

    /// A function of the binary.
    pub fn sym<T>(&self, name: &str) -> Symbol<'_, T> {
        // SAFETY: the caller names the type of an FMI 3.0 function.
        unsafe { self.lib.get(name.as_bytes()) }.unwrap_or_else(|e| panic!("{name}: {e}"))
    }

    /// `fmi3InstantiateCoSimulation` with these arguments, logging under a new environment:
    /// the instance (NULL if refused) and the environment.
    pub fn instantiate_with(
        &self,
        name: &CStr,
        token: &CStr,
        (event_mode_used, early_return): (bool, bool),
        required: &[u32],
    ) -> (Instance, usize) {
        let env = new_env();
        let f: Symbol<InstantiateCs> = self.sym("fmi3InstantiateCoSimulation");
        let c = unsafe {
            f(
                name.as_ptr(),
                token.as_ptr(),
                std::ptr::null(),
                FALSE,
                FALSE,
                event_mode_used as Boolean,
                early_return as Boolean,
                required.as_ptr(),
                required.len(),
                env as *mut c_void,
                Some(record),
                None,
            )
        };
        (c, env)
    }

    /// A Co-Simulation instance with the right token and a recording logger.
    pub fn instance(&self, name: &str) -> Inst3<'_> {
        self.instance_with(name, false, false)
    }

    /// A Model Exchange instance with the right token and a recording logger.
    pub fn me_instance(&self, name: &str) -> Inst3<'_> {
        let (c, env) = self.instantiate_me(name);
        assert!(!c.is_null(), "instantiate refused: {:?}", logs_of(env));
        Inst3 { fmu: self, c, env }
    }

    /// `fmi3InstantiateModelExchange` with the right token, logging under a new environment: the
    /// instance (NULL if refused) and the environment.
    pub fn instantiate_me(&self, name: &str) -> (Instance, usize) {
        type Me = unsafe extern "C" fn(
            FmiString,
            FmiString,
            FmiString,
            Boolean,
            Boolean,
            InstanceEnvironment,
            LogMessageCallback,
        ) -> Instance;
        let env = new_env();
        let f: Symbol<Me> = self.sym("fmi3InstantiateModelExchange");
        let (n, t) = (cstr(name), cstr(&self.token));
        let c = unsafe {
            f(
                n.as_ptr(),
                t.as_ptr(),
                std::ptr::null(),
                FALSE,
                FALSE,
                env as *mut c_void,
                Some(record),
            )
        };
        (c, env)
    }

    /// A Co-Simulation instance using Event Mode or not, allowing early return or not.
    pub fn instance_with(&self, name: &str, event_mode: bool, early: bool) -> Inst3<'_> {
        let n = CString::new(name).unwrap();
        let t = CString::new(self.token.clone()).unwrap();
        let (c, env) = self.instantiate_with(&n, &t, (event_mode, early), &[]);
        assert!(!c.is_null(), "instantiate refused: {:?}", logs_of(env));
        Inst3 { fmu: self, c, env }
    }
}

/// An FMI 3.0 instance; freed when dropped.
pub struct Inst3<'a> {
    pub fmu: &'a Fmu3,
    pub c: Instance,
    pub env: usize,
}

impl Drop for Inst3<'_> {
    fn drop(&mut self) {
        let f: Symbol<unsafe extern "C" fn(Instance)> = self.fmu.sym("fmi3FreeInstance");
        unsafe { f(self.c) }
    }
}

impl Inst3<'_> {
    pub fn logs(&self) -> Vec<LogLine> {
        logs_of(self.env)
    }
    pub fn last_error(&self) -> String {
        (self.logs().iter().rev())
            .find(|l| l.0 == Status::Error)
            .map(|l| l.2.clone())
            .unwrap_or_default()
    }
    pub fn ok(&self, st: Status, what: &str) {
        assert_eq!(st, Status::Ok, "{what}: {:?}", self.logs());
    }
    pub fn assert_refused(&self, st: Status, text: &str, what: &str) {
        assert_eq!(st, Status::Error, "{what}");
        let e = self.last_error();
        assert!(e.contains(text), "{what}: {e:?}");
    }
    pub fn call0(&self, name: &str) -> Status {
        let f: Symbol<unsafe extern "C" fn(Instance) -> Status> = self.fmu.sym(name);
        unsafe { f(self.c) }
    }
    pub fn enter_init(&self, start: f64, stop: Option<f64>) -> Status {
        let f: Symbol<
            unsafe extern "C" fn(Instance, Boolean, Float64, Float64, Boolean, Float64) -> Status,
        > = self.fmu.sym("fmi3EnterInitializationMode");
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
        self.enter_init(0.0, None)
            .max(self.call0("fmi3ExitInitializationMode"))
    }
    /// `fmi3UpdateDiscreteStates`: the status and its six results (the last as a time).
    pub fn update_discrete_states(&self) -> (Status, [bool; 5], f64) {
        type Update = unsafe extern "C" fn(
            Instance,
            *mut Boolean,
            *mut Boolean,
            *mut Boolean,
            *mut Boolean,
            *mut Boolean,
            *mut Float64,
        ) -> Status;
        let f: Symbol<Update> = self.fmu.sym("fmi3UpdateDiscreteStates");
        let mut b = [7u8; 5];
        let mut next = f64::NAN;
        let [p0, p1, p2, p3, p4] = b.each_mut().map(|x| x as *mut u8);
        let st = unsafe { f(self.c, p0, p1, p2, p3, p4, &mut next) };
        (st, b.map(|x| x != 0), next)
    }
    /// `fmi3DoStep`: the status and (eventHandlingNeeded, terminateSimulation, earlyReturn,
    /// lastSuccessfulTime).
    pub fn do_step(&self, t: f64, h: f64) -> (Status, [bool; 3], f64) {
        type DoStep = unsafe extern "C" fn(
            Instance,
            Float64,
            Float64,
            Boolean,
            *mut Boolean,
            *mut Boolean,
            *mut Boolean,
            *mut Float64,
        ) -> Status;
        let f: Symbol<DoStep> = self.fmu.sym("fmi3DoStep");
        let (mut e, mut term, mut early, mut last) = (7u8, 7u8, 7u8, f64::NAN);
        let st = unsafe { f(self.c, t, h, TRUE, &mut e, &mut term, &mut early, &mut last) };
        (st, [e != 0, term != 0, early != 0], last)
    }
    /// A typed get of `n` values (`fmi3Get<T>`).
    pub fn get<T: Copy + Default>(&self, name: &str, vrs: &[u32]) -> (Status, Vec<T>) {
        type Get<T> = unsafe extern "C" fn(Instance, *const u32, usize, *mut T, usize) -> Status;
        let f: Symbol<Get<T>> = self.fmu.sym(name);
        let mut out = vec![T::default(); vrs.len()];
        let s = unsafe { f(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), vrs.len()) };
        (s, out)
    }
    /// A typed set (`fmi3Set<T>`).
    pub fn set<T: Copy>(&self, name: &str, vrs: &[u32], vals: &[T]) -> Status {
        type Set<T> = unsafe extern "C" fn(Instance, *const u32, usize, *const T, usize) -> Status;
        let f: Symbol<Set<T>> = self.fmu.sym(name);
        unsafe { f(self.c, vrs.as_ptr(), vrs.len(), vals.as_ptr(), vals.len()) }
    }
    pub fn get_state(&self, s: &mut FMUState) -> Status {
        let f: Symbol<unsafe extern "C" fn(Instance, *mut FMUState) -> Status> =
            self.fmu.sym("fmi3GetFMUState");
        unsafe { f(self.c, s) }
    }
    pub fn set_state(&self, s: FMUState) -> Status {
        let f: Symbol<unsafe extern "C" fn(Instance, FMUState) -> Status> =
            self.fmu.sym("fmi3SetFMUState");
        unsafe { f(self.c, s) }
    }
    pub fn free_state(&self, s: &mut FMUState) -> Status {
        let f: Symbol<unsafe extern "C" fn(Instance, *mut FMUState) -> Status> =
            self.fmu.sym("fmi3FreeFMUState");
        unsafe { f(self.c, s) }
    }
    /// The serialized form of the instance's current state.
    pub fn state_bytes(&self) -> Vec<u8> {
        let mut s: FMUState = std::ptr::null_mut();
        self.ok(self.get_state(&mut s), "fmi3GetFMUState");
        let size_f: Symbol<unsafe extern "C" fn(Instance, FMUState, *mut usize) -> Status> =
            self.fmu.sym("fmi3SerializedFMUStateSize");
        let ser: Symbol<unsafe extern "C" fn(Instance, FMUState, *mut u8, usize) -> Status> =
            self.fmu.sym("fmi3SerializeFMUState");
        let mut n = 0usize;
        self.ok(unsafe { size_f(self.c, s, &mut n) }, "size");
        let mut b = vec![0u8; n];
        self.ok(unsafe { ser(self.c, s, b.as_mut_ptr(), n) }, "serialize");
        self.ok(self.free_state(&mut s), "free");
        b
    }
    /// Deserializes `bytes` into a new FMU state: the status and the state (NULL if refused).
    pub fn deserialize(&self, bytes: &[u8]) -> (Status, FMUState) {
        let de: Symbol<unsafe extern "C" fn(Instance, *const u8, usize, *mut FMUState) -> Status> =
            self.fmu.sym("fmi3DeserializeFMUState");
        let mut s: FMUState = std::ptr::null_mut();
        let st = unsafe { de(self.c, bytes.as_ptr(), bytes.len(), &mut s) };
        (st, s)
    }
    /// Restores the state serialized in `bytes` (asserted fmi3OK).
    pub fn restore_bytes(&self, bytes: &[u8]) {
        let (st, mut s) = self.deserialize(bytes);
        self.ok(st, "fmi3DeserializeFMUState");
        self.ok(self.set_state(s), "fmi3SetFMUState");
        self.ok(self.free_state(&mut s), "fmi3FreeFMUState");
    }
}

/// A C string for a test.
pub fn cstr(s: &str) -> CString {
    CString::new(s).unwrap()
}

/// A pointer type the tests pass where any C string goes.
pub type Text = *const c_char;

// ---- what the FMI 3.0 tests share: the catalog's variables, the cross-check inputs, the
// values as bits through either interface

pub fn vars(e: &Entry) -> Vec<(u32, &'static Var)> {
    (e.variables)()
}

pub fn vr_of(e: &Entry, name: &str) -> Option<u32> {
    vars(e)
        .into_iter()
        .find(|(_, v)| v.name == name)
        .map(|(vr, _)| vr)
}

/// The value references of every variable of one type.
pub fn of_type(e: &Entry, pred: impl Fn(VarType) -> bool) -> Vec<u32> {
    (vars(e).into_iter())
        .filter(|(_, v)| pred(v.ty))
        .map(|(vr, _)| vr)
        .collect()
}

/// The cross-check inputs of a model (`fmus/<id>/<id>_in.csv`): the input value references and
/// the rows (time, then the inputs).
pub fn cross_check_inputs(e: &Entry) -> (Vec<u32>, Vec<Vec<f64>>) {
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
pub fn levels(e: &Entry) -> Vec<Option<i32>> {
    match vr_of(e, "model.fidelity") {
        Some(_) => vec![Some(1), Some(2), Some(3)],
        None => vec![None],
    }
}

/// Every variable's value as bits, through the FMI 2.0 interface.
pub fn bits2(s: &super::Slave, e: &Entry) -> Vec<u64> {
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
pub fn bits3(i: &Inst3, e: &Entry) -> Vec<u64> {
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
pub fn started3<'a>(f3: &'a Fmu3, e: &Entry, level: Option<i32>) -> Inst3<'a> {
    let i = f3.instance("fmi3");
    if let Some(l) = level {
        let vr = vr_of(e, "model.fidelity").unwrap();
        i.ok(i.set("fmi3SetInt64", &[vr], &[l as i64]), "fidelity");
    }
    i.ok(i.init(), "initialization");
    i
}
