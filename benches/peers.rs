//! The native host of the peer benchmark (`bench/run`, BENCHMARKS.md): GenevaKnifeDrive, its
//! PythonFMU peer and the C floor, each loaded from its unpacked `.fmu` through the C ABI (the
//! host of `tests/common`), and the bare Rust call of the same mechanism, per communication step:
//! `fmi2SetReal` of the shaft angle, `fmi2DoStep`, `fmi2GetReal` of 19 Real values (the first 19
//! Real outputs by value reference, `shaft.tau` … `crank.tau`; the floor's three outputs are read
//! cyclically to the same count, so the host does the same work with every FMU). Not a test: `cargo test` never runs it.
//!
//! ```sh
//! cargo bench --bench peers -- --dir out/bench/unpacked --json out/bench/native.json
//! cargo bench --bench peers -- --dir out/bench/unpacked --heap --json out/bench/heap.json
//! ```
//!
//! Timing: the configurations are measured in interleaved rounds (one sample of each per
//! round), so a burst of load on this shared machine hits them alike; a sample is `m` steps
//! (calibrated to about 2 ms), the figure is the median over the rounds.
//!
//! Heap (`--heap`, run with `PYTHONMALLOC=malloc` so Python's objects are malloc'd too): the
//! live bytes glibc's `mallinfo2` counts, before and after 16 more instances are instantiated,
//! initialized and stepped once (after a first one has paid for one-time set-up: the variable
//! table, the Python interpreter), divided by 16. For ours also the same instances made
//! in-process through `bindery_fmu::fmi2::runtime` with a counting global allocator.

#[path = "../tests/common/mod.rs"]
mod common;

use bindery_fmu::fmi2::runtime;
use bindery_fmu::fmi2::state::Call;
use bindery_fmu::fmi2::types::*;
use bindery_fmu::mechanics::geneva::Geneva;
use bindery_fmu::mechanisms::geneva_knife_drive::GenevaKnifeDrive;
use bindery_fmu::mechanisms::geneva_knife_drive::physics::Params;
use bindery_fmu::model::shaft;
use common::{Fmu, Slave};
use std::alloc::{GlobalAlloc, Layout, System};
use std::ffi::CString;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicIsize, Ordering};
use std::time::Instant;

// ---- counting global allocator (heap of the in-process runtime) -----------------------------

struct Counting;
static LIVE: AtomicIsize = AtomicIsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        LIVE.fetch_add(l.size() as isize, Ordering::Relaxed);
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        LIVE.fetch_sub(l.size() as isize, Ordering::Relaxed);
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn alloc_zeroed(&self, l: Layout) -> *mut u8 {
        LIVE.fetch_add(l.size() as isize, Ordering::Relaxed);
        unsafe { System.alloc_zeroed(l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        LIVE.fetch_add(new as isize - l.size() as isize, Ordering::Relaxed);
        unsafe { System.realloc(p, l, new) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

// ---- the model description, as much of it as a host needs ----------------------------------

struct Description {
    id: String,
    guid: String,
    /// (name, value reference, causality, type element)
    vars: Vec<(String, u32, String, String)>,
}

fn attr(tag: &str, name: &str) -> Option<String> {
    let key = format!(" {name}=\"");
    let at = tag.find(&key)? + key.len();
    Some(tag[at..at + tag[at..].find('"')?].to_string())
}

fn read_description(dir: &Path) -> Description {
    let xml = std::fs::read_to_string(dir.join("modelDescription.xml"))
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    let head = &xml[xml
        .find("<fmiModelDescription")
        .expect("fmiModelDescription")..];
    let guid = attr(&head[..head.find('>').unwrap()], "guid").expect("guid");
    let cs = &xml[xml.find("<CoSimulation").expect("CoSimulation")..];
    let id = attr(&cs[..cs.find('>').unwrap()], "modelIdentifier").expect("modelIdentifier");
    let mut vars = Vec::new();
    for chunk in xml.split("<ScalarVariable").skip(1) {
        let tag = &chunk[..chunk.find('>').unwrap()];
        let body = &chunk[chunk.find('>').unwrap() + 1..];
        let ty = ["Real", "Integer", "Boolean", "Enumeration", "String"]
            .into_iter()
            .find(|t| body.trim_start().starts_with(&format!("<{t}")))
            .unwrap_or("?");
        vars.push((
            attr(tag, "name").unwrap(),
            attr(tag, "valueReference").unwrap().parse().unwrap(),
            attr(tag, "causality").unwrap_or_else(|| "local".into()),
            ty.to_string(),
        ));
    }
    Description { id, guid, vars }
}

impl Description {
    fn vr(&self, name: &str) -> Option<u32> {
        self.vars.iter().find(|v| v.0 == name).map(|v| v.1)
    }
    fn real_outputs(&self) -> Vec<u32> {
        self.vars
            .iter()
            .filter(|v| v.2 == "output" && v.3 == "Real")
            .map(|v| v.1)
            .collect()
    }
}

/// Real values read per step from every FMU: GenevaKnifeDrive's Real outputs.
const N_READ: usize = 19;
const H: f64 = 1e-3;
const W: f64 = std::f64::consts::PI;

type SetReal = unsafe extern "C" fn(Component, *const u32, usize, *const f64) -> Status;
type GetReal = unsafe extern "C" fn(Component, *const u32, usize, *mut f64) -> Status;
type DoStep = unsafe extern "C" fn(Component, f64, f64, Boolean) -> Status;

/// An initialized instance of an unpacked FMU with its per-step loop.
struct Running<'a> {
    slave: Slave<'a>,
    set: SetReal,
    get: GetReal,
    step: DoStep,
    phi_vr: u32,
    read: Vec<u32>,
    out: Vec<f64>,
    t: f64,
}

impl Running<'_> {
    #[inline(never)]
    fn steps(&mut self, m: usize) {
        let c = self.slave.c;
        for _ in 0..m {
            let phi = W * self.t;
            // SAFETY: an initialized instance of this library; arrays of the stated lengths.
            unsafe {
                let s1 = (self.set)(c, &self.phi_vr, 1, &phi);
                let s2 = (self.step)(c, self.t, H, TRUE);
                let s3 = (self.get)(
                    c,
                    self.read.as_ptr(),
                    self.read.len(),
                    self.out.as_mut_ptr(),
                );
                debug_assert!(s1 == Status::Ok && s2 == Status::Ok && s3 == Status::Ok);
                if s1 as i32 + s2 as i32 + s3 as i32 != 0 {
                    panic!("step failed at t = {}: {:?}", self.t, self.slave.logs());
                }
            }
            self.t += H;
            black_box(&self.out);
        }
    }
}

fn load(dir: &Path) -> (Fmu, Description) {
    let d = read_description(dir);
    let so = dir.join("binaries/linux64").join(format!("{}.so", d.id));
    // SAFETY: an FMU binary; FMUs are made to be loaded by hosts.
    let lib = unsafe { libloading::Library::new(&so) }
        .unwrap_or_else(|e| panic!("{}: {e}", so.display()));
    (
        Fmu {
            lib,
            guid: d.guid.clone(),
        },
        d,
    )
}

static ENV: AtomicIsize = AtomicIsize::new(1_000_000);

/// Instantiates (with the FMU's resources folder), sets the level, initializes.
fn start<'a>(fmu: &'a Fmu, d: &Description, dir: &Path, level: Option<i32>) -> Running<'a> {
    let env = ENV.fetch_add(1, Ordering::Relaxed) as usize;
    let f = fmu.callbacks(env);
    let res = CString::new(format!(
        "file://{}",
        dir.canonicalize().unwrap().join("resources").display()
    ))
    .unwrap();
    let name = CString::new("bench").unwrap();
    let guid = CString::new(d.guid.clone()).unwrap();
    let c = fmu.instantiate_raw(
        name.as_ptr(),
        FmuType::CoSimulation,
        guid.as_ptr(),
        res.as_ptr(),
        &f,
    );
    assert!(!c.is_null(), "{}: fmi2Instantiate failed", d.id);
    let slave = Slave { fmu, c, env };
    if let (Some(level), Some(vr)) = (level, d.vr("model.fidelity")) {
        assert_eq!(slave.set_integer(&[vr], &[level]), Status::Ok, "{}", d.id);
    }
    assert_eq!(slave.setup(0.0, None), Status::Ok, "{}", d.id);
    assert_eq!(slave.init(), Status::Ok, "{}: {:?}", d.id, slave.logs());
    let outs = d.real_outputs();
    let read: Vec<u32> = outs.iter().copied().cycle().take(N_READ).collect();
    let phi_vr = d
        .vr("shaft.phi")
        .or_else(|| d.vr("u1"))
        .expect("an angle input");
    Running {
        set: *fmu.sym::<SetReal>("fmi2SetReal"),
        get: *fmu.sym::<GetReal>("fmi2GetReal"),
        step: *fmu.sym::<DoStep>("fmi2DoStep"),
        slave,
        phi_vr,
        out: vec![0.0; read.len()],
        read,
        t: 0.0,
    }
}

/// The bare Rust call of the same computation, per step: what `GenevaKnifeDrive`'s `evaluate`
/// computes for the outputs a step reads (the Geneva pair built once, as the FMU does per
/// prepare), without FMI: the kinematics; at the kinetostatic level the forces and the torque
/// reduced to the shaft (`shaft.tau0`, `shaft.J_red`: one more kinetostatic evaluation,
/// `shaft::reduce_at`), since those are among the 19 values read.
struct Bare {
    p: Params,
    geneva: Geneva,
    kinetostatic: bool,
    t: f64,
}

impl Bare {
    fn new(p: Params, kinetostatic: bool) -> Self {
        Bare {
            geneva: p.geneva(),
            p,
            kinetostatic,
            t: 0.0,
        }
    }

    #[inline(never)]
    fn steps(&mut self, m: usize) {
        let (p, geneva) = (&self.p, &self.geneva);
        for _ in 0..m {
            let phi = black_box(W * self.t);
            let k = p.kinematics_of(geneva, phi, W, 0.0);
            if self.kinetostatic {
                let f = p.kinetostatics(&k, W, 0.0);
                let r = shaft::reduce_at(f.shaft_tau, 0.0, |a| {
                    p.kinetostatics(&p.at_shaft_accel(&k, W, a), W, a).shaft_tau
                });
                black_box((f, r));
            }
            black_box(&k);
            self.t += H;
        }
    }
}

enum Subject<'a> {
    Fmu(Running<'a>),
    Bare(Bare),
}

impl Subject<'_> {
    fn steps(&mut self, m: usize) {
        match self {
            Subject::Fmu(r) => r.steps(m),
            Subject::Bare(b) => b.steps(m),
        }
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

struct Args {
    dir: PathBuf,
    json: Option<PathBuf>,
    heap: bool,
    /// libpython to load with RTLD_GLOBAL first: PythonFMU's binary does not link it (it
    /// expects to be loaded into a Python process), so a native host has to.
    libpython: Option<PathBuf>,
    rounds: usize,
    sample_ns: f64,
    /// Measure only these (`ours,bare,...`), e.g. under callgrind.
    only: Option<Vec<String>>,
    /// Profile mode: exactly this many steps of each subject, no timing (for callgrind:
    /// instructions per step = collected / steps).
    fixed: Option<usize>,
}

fn args() -> Args {
    let mut a = Args {
        dir: PathBuf::from("out/bench/unpacked"),
        json: None,
        heap: false,
        libpython: None,
        rounds: 101,
        sample_ns: 2e6,
        only: None,
        fixed: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(x) = it.next() {
        match x.as_str() {
            "--dir" => a.dir = it.next().expect("--dir DIR").into(),
            "--json" => a.json = Some(it.next().expect("--json FILE").into()),
            "--heap" => a.heap = true,
            "--fixed" => a.fixed = Some(it.next().expect("--fixed N").parse().expect("steps")),
            "--only" => {
                a.only = Some(
                    it.next()
                        .expect("--only a,b")
                        .split(',')
                        .map(String::from)
                        .collect(),
                )
            }
            "--libpython" => a.libpython = Some(it.next().expect("--libpython FILE").into()),
            "--rounds" => a.rounds = it.next().expect("--rounds N").parse().expect("rounds"),
            "--sample-ms" => {
                a.sample_ns = it
                    .next()
                    .expect("--sample-ms X")
                    .parse::<f64>()
                    .expect("ms")
                    * 1e6
            }
            _ => {} // `cargo bench` passes --bench
        }
    }
    a
}

/// The three FMUs of the benchmark: (label, unpacked folder name).
const FMUS: [(&str, &str); 3] = [
    ("ours", "GenevaKnifeDrive"),
    ("pythonfmu", "GenevaKnifeDrivePy"),
    ("floor", "Floor"),
];
const LEVELS: [(&str, i32); 2] = [("kinematic", 1), ("kinetostatic", 2)];

fn main() {
    let a = args();
    if let Some(p) = &a.libpython {
        use libloading::os::unix::{Library, RTLD_GLOBAL, RTLD_NOW};
        // SAFETY: the Python runtime; kept loaded for the life of the process.
        let lib = unsafe { Library::open(Some(p), RTLD_NOW | RTLD_GLOBAL) }
            .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        std::mem::forget(lib);
    }
    let json = if a.heap { heap(&a) } else { timing(&a) };
    println!("{json}");
    if let Some(p) = &a.json {
        std::fs::write(p, format!("{json}\n")).expect("write json");
    }
}

fn timing(a: &Args) -> String {
    let loaded: Vec<(&str, PathBuf, Fmu, Description)> = FMUS
        .iter()
        .filter(|(label, _)| a.only.as_ref().is_none_or(|o| o.iter().any(|x| x == label)))
        .map(|(label, dir)| {
            let dir = a.dir.join(dir);
            let (fmu, d) = load(&dir);
            (*label, dir, fmu, d)
        })
        .collect();
    // (host label, level, subject)
    let mut subjects: Vec<(String, &str, Subject)> = Vec::new();
    for (level, code) in LEVELS {
        for (label, dir, fmu, d) in &loaded {
            if *label == "floor" && code == 1 {
                continue; // the floor has no levels: measured once, under kinetostatic
            }
            subjects.push((
                label.to_string(),
                level,
                Subject::Fmu(start(fmu, d, dir, Some(code))),
            ));
        }
        if a.only
            .as_ref()
            .is_some_and(|o| !o.iter().any(|x| x == "bare"))
        {
            continue;
        }
        subjects.push((
            "bare".into(),
            level,
            Subject::Bare(Bare::new(Params::default(), code == 2)),
        ));
    }
    if let Some(n) = a.fixed {
        for (label, level, s) in subjects.iter_mut() {
            s.steps(n);
            println!("{label} {level}: {n} steps");
        }
        return "[]".into();
    }
    // Calibrate: steps per sample so a sample lasts about `sample_ns`.
    let mut per_sample = Vec::new();
    for (_, _, s) in subjects.iter_mut() {
        s.steps(100); // warm up
        let mut m = 1usize;
        loop {
            let t0 = Instant::now();
            s.steps(m);
            let ns = t0.elapsed().as_nanos() as f64;
            if ns > a.sample_ns / 4.0 || m > 1 << 24 {
                per_sample.push(((m as f64 * a.sample_ns / ns).ceil() as usize).max(1));
                break;
            }
            m *= 2;
        }
    }
    let mut samples = vec![Vec::with_capacity(a.rounds); subjects.len()];
    for _ in 0..a.rounds {
        for (i, (_, _, s)) in subjects.iter_mut().enumerate() {
            let m = per_sample[i];
            let t0 = Instant::now();
            s.steps(m);
            samples[i].push(t0.elapsed().as_nanos() as f64 / m as f64);
        }
    }
    let mut rows = Vec::new();
    for (i, (label, level, _)) in subjects.iter().enumerate() {
        let mut v = samples[i].clone();
        let med = median(&mut v);
        let (lo, hi) = (v[v.len() / 10], v[v.len() * 9 / 10]);
        // Every round's figure, in round order: the report pairs them for per-round ratios.
        let rounds: Vec<String> = samples[i].iter().map(|x| format!("{x:.2}")).collect();
        rows.push(format!(
            "{{\"host\":\"native\",\"fmu\":\"{label}\",\"level\":\"{level}\",\"ns_per_step\":{med:.2},\"p10\":{lo:.2},\"p90\":{hi:.2},\"steps_per_sample\":{},\"samples\":{},\"rounds\":[{}]}}",
            per_sample[i],
            v.len(),
            rounds.join(",")
        ));
    }
    format!("[\n  {}\n]", rows.join(",\n  "))
}

fn heap(a: &Args) -> String {
    const N: usize = 16;
    let mut rows = Vec::new();
    for (label, dir) in FMUS {
        let dir = a.dir.join(dir);
        let (fmu, d) = load(&dir);
        let mut first = start(&fmu, &d, &dir, Some(2));
        first.steps(1);
        let mut more: Vec<Running> = Vec::with_capacity(N);
        // The host's own allocations (its per-instance vectors) go through malloc too: they are
        // counted by the counting allocator and taken off.
        let (before, host_before) = (common::heap::in_use(), LIVE.load(Ordering::Relaxed));
        for _ in 0..N {
            let mut r = start(&fmu, &d, &dir, Some(2));
            r.steps(1);
            more.push(r);
        }
        let (after, host_after) = (common::heap::in_use(), LIVE.load(Ordering::Relaxed));
        more.clear();
        drop(first);
        let fmu_bytes = (after - before) - (host_after - host_before);
        rows.push(format!(
            "{{\"fmu\":\"{label}\",\"method\":\"mallinfo2\",\"bytes_per_instance\":{}}}",
            fmu_bytes / N as isize
        ));
    }
    // Ours again, in-process: the same runtime code as the cdylib, under the counting allocator.
    let guid = CString::new(bindery_fmu::md::describe::<GenevaKnifeDrive>().1).unwrap();
    let f = CallbackFunctions {
        logger: common::logger(),
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    };
    let make = || {
        // SAFETY: valid arguments per FMI 2.0.
        unsafe {
            let c = runtime::instantiate::<GenevaKnifeDrive>(
                c"bench".as_ptr(),
                FmuType::CoSimulation,
                guid.as_ptr(),
                std::ptr::null(),
                &f,
                FALSE,
                FALSE,
            );
            assert!(!c.is_null());
            runtime::entry::<GenevaKnifeDrive, _>(c, Call::SetupExperiment, |i| {
                i.experiment(FALSE, 0.0, 0.0, FALSE, 0.0)
            });
            runtime::entry::<GenevaKnifeDrive, _>(c, Call::EnterInitializationMode, |i| {
                i.enter_initialization_mode()
            });
            runtime::entry::<GenevaKnifeDrive, _>(c, Call::ExitInitializationMode, |i| {
                i.exit_initialization_mode()
            });
            runtime::do_step::<GenevaKnifeDrive>(c, 0.0, H, TRUE);
            let mut x = [0.0];
            runtime::get_real::<GenevaKnifeDrive>(c, [3u32].as_ptr(), 1, x.as_mut_ptr());
            c
        }
    };
    let first = make();
    let before = LIVE.load(Ordering::Relaxed);
    let cs: Vec<Component> = (0..N).map(|_| make()).collect();
    let after = LIVE.load(Ordering::Relaxed);
    for c in cs.into_iter().chain([first]) {
        // SAFETY: instances made above.
        unsafe { runtime::free_instance::<GenevaKnifeDrive>(c) };
    }
    // the Vec of N pointers itself is host memory
    let host_vec = (N * std::mem::size_of::<Component>()) as isize;
    rows.push(format!(
        "{{\"fmu\":\"ours\",\"method\":\"counting allocator (in-process runtime)\",\"bytes_per_instance\":{}}}",
        (after - before - host_vec) / N as isize
    ));
    format!("[\n  {}\n]", rows.join(",\n  "))
}
