//! Per-step time of each example scene's tailored FMU against the full FMU of its mechanism at
//! the same parameters, level and drive (`scenes.md`): `fmi2SetReal` of the inputs the scene
//! lists + `fmi2DoStep` + reading the scene's outputs, through the C ABI of the built binary.
//! Also prints the number of variables of each. Needs the built binaries:
//! `cargo run --release -- build`, then `cargo bench --bench scenes`.

#[path = "../tests/common/mod.rs"]
mod common;

use bindery_fmu::catalog;
use bindery_fmu::fmi2::types::*;
use bindery_fmu::model::{Causality, VarType};
use bindery_fmu::scene::{RESOURCE_NAME, Scene, Tailored};
use common::{Fmu, Slave};
use divan::{Bencher, black_box};
use std::ffi::CString;
use std::path::Path;

/// The example scenes (`scenes/<name>.toml`).
const SCENES: &[&str] = &[
    "disc-knife-path",
    "disc-rod-dynamics",
    "disc-spine-cut",
    "geneva-chain-dynamics",
    "geneva-cut-forces",
    "geneva-side-knife-kinematics",
    "perforators-liftoff-dynamics",
    "perforators-needle-stroke",
    "perforators-ramp-contact",
    "sewing-cam-force",
    "sewing-follower-vibration",
    "sewing-table-travel",
];

const H: f64 = 1e-3;

fn main() {
    eprintln!(
        "{:<32} {:>18} {:>14}",
        "scene", "variables (tailored", "full)"
    );
    for name in SCENES {
        let (_, entry, t) = load(name);
        eprintln!(
            "{name:<32} {:>18} {:>14}",
            t.variables.len(),
            (entry.variables)().len()
        );
    }
    divan::main();
}

fn load(name: &str) -> (String, catalog::Entry, Tailored) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(format!("{name}.toml"));
    let text = std::fs::read_to_string(&path).expect("scene file");
    let scene = Scene::parse(&text).expect("scene");
    let (entry, t) = catalog::tailor(&scene).expect("tailored");
    (text, entry, t)
}

/// One instance (`tailored`: with the scene in its resources), initialized, and what a step
/// sets and reads.
struct Run<'a> {
    slave: Slave<'a>,
    inputs: Vec<u32>,
    reals: Vec<u32>,
    ints: Vec<u32>,
    bools: Vec<u32>,
}

fn run<'a>(fmu: &'a Fmu, text: &str, t: &Tailored, tailored: bool) -> Run<'a> {
    let slave = if tailored {
        let dir = std::env::temp_dir().join(format!(
            "bindery-bench-{}-{}",
            std::process::id(),
            t.identifier
        ));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join(RESOURCE_NAME), text).unwrap();
        let uri = CString::new(format!("file://{}/", dir.display())).unwrap();
        let f = fmu.callbacks(7);
        let g = CString::new(t.guid.clone()).unwrap();
        let c = fmu.instantiate_raw(
            c"bench".as_ptr(),
            FmuType::CoSimulation,
            g.as_ptr(),
            uri.as_ptr(),
            &f,
        );
        assert!(!c.is_null(), "tailored FMU refused");
        Slave { fmu, c, env: 7 }
    } else {
        let s = fmu.slave("bench");
        let table: Vec<_> = (catalog::all()
            .into_iter()
            .find(|e| e.identifier == t.scene.mechanism)
            .unwrap()
            .variables)();
        for (vr, v) in table {
            let x = t.start[vr as usize];
            if v.causality == Causality::Parameter && v.start != Some(x) {
                let st = match v.ty {
                    VarType::Real => s.set_real(&[vr], &[x]),
                    _ => s.set_integer(&[vr], &[x as i32]),
                };
                assert_eq!(st, Status::Ok, "{}", v.name);
            }
        }
        s
    };
    assert_eq!(slave.setup(0.0, None), Status::Ok);
    assert_eq!(slave.init(), Status::Ok);
    let pick = |f: &dyn Fn(&bindery_fmu::model::Var) -> bool| -> Vec<u32> {
        t.variables
            .iter()
            .filter(|(_, v)| f(v))
            .map(|(vr, _)| *vr)
            .collect()
    };
    Run {
        slave,
        inputs: pick(&|v| v.causality == Causality::Input),
        reals: pick(&|v| v.causality == Causality::Output && v.ty == VarType::Real),
        ints: pick(&|v| v.causality == Causality::Output && v.ty == VarType::Integer),
        bools: pick(&|v| v.causality == Causality::Output && v.ty == VarType::Boolean),
    }
}

fn bench_step(b: Bencher, name: &str, tailored: bool) {
    let (text, entry, t) = load(name);
    let fmu = Fmu::load(entry.identifier, &(entry.describe)().1);
    let r = run(&fmu, &text, &t, tailored);
    let mut time = 0.0;
    let mut out = vec![0.0; r.reals.len()];
    let mut ints = vec![0i32; r.ints.len()];
    let mut bools = vec![0 as Boolean; r.bools.len()];
    let set: libloading::Symbol<
        unsafe extern "C" fn(Component, *const u32, usize, *const Real) -> Status,
    > = fmu.sym("fmi2SetReal");
    let step: libloading::Symbol<unsafe extern "C" fn(Component, Real, Real, Boolean) -> Status> =
        fmu.sym("fmi2DoStep");
    let get: libloading::Symbol<
        unsafe extern "C" fn(Component, *const u32, usize, *mut Real) -> Status,
    > = fmu.sym("fmi2GetReal");
    let get_int: libloading::Symbol<
        unsafe extern "C" fn(Component, *const u32, usize, *mut Integer) -> Status,
    > = fmu.sym("fmi2GetInteger");
    let get_bool: libloading::Symbol<
        unsafe extern "C" fn(Component, *const u32, usize, *mut Boolean) -> Status,
    > = fmu.sym("fmi2GetBoolean");
    let c = r.slave.c;
    let mut vals = vec![0.0; r.inputs.len()];
    b.bench_local(|| unsafe {
        for (x, vr) in vals.iter_mut().zip(&r.inputs) {
            *x = match *vr {
                0 => 0.4 + 11.0 * time,
                1 => 11.0,
                _ => 0.0,
            };
        }
        set(c, r.inputs.as_ptr(), r.inputs.len(), vals.as_ptr());
        assert_eq!(step(c, time, H, TRUE), Status::Ok);
        time += H;
        get(c, r.reals.as_ptr(), r.reals.len(), out.as_mut_ptr());
        get_int(c, r.ints.as_ptr(), r.ints.len(), ints.as_mut_ptr());
        get_bool(c, r.bools.as_ptr(), r.bools.len(), bools.as_mut_ptr());
        black_box((&out, &ints, &bools));
    });
}

#[divan::bench(args = SCENES, sample_count = 300, sample_size = 20)]
fn full(b: Bencher, name: &str) {
    bench_step(b, name, false);
}

#[divan::bench(args = SCENES, sample_count = 300, sample_size = 20)]
fn tailored(b: Bencher, name: &str) {
    bench_step(b, name, true);
}
