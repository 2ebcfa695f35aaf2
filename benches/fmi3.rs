//! Per-step cost of the FMI 3.0 interface against FMI 2.0 on the same binary: set the inputs
//! (`fmi2SetReal` / `fmi3SetFloat64`), `fmi2DoStep` / `fmi3DoStep` of 1 ms, read every Real
//! output, through the C ABI of the built binary, at each model's default level; and FMI 3.0
//! with early return allowed (the step watches the event outputs: one more evaluation per step,
//! a bisection where an event falls). Needs the built binaries: `cargo run --release -- build`,
//! then `cargo bench --bench fmi3`.

#[path = "../tests/common/mod.rs"]
mod common;

use bindery_fmu::catalog::{self, Entry};
use bindery_fmu::model::{Causality, VarType};
use common::Fmu;
use common::fmi3::Fmu3;
use divan::{Bencher, black_box};

const H: f64 = 1e-3;
const MODELS: &[&str] = &[
    "GenevaKnifeDrive",
    "SewingTable",
    "Perforators",
    "DiscKnifeDrive",
    "MainShaft",
    "LegacyNeedleDrive",
];

fn main() {
    divan::main();
}

fn entry(id: &str) -> Entry {
    catalog::all()
        .into_iter()
        .find(|e| e.identifier == id)
        .unwrap()
}

/// The Real inputs and outputs of a model, and the inputs' values at time `t` (a shaft at
/// 100 rpm for a mechanism; the start values otherwise).
fn io(e: &Entry) -> (Vec<u32>, Vec<u32>) {
    let vars = (e.variables)();
    let of = |c: Causality| -> Vec<u32> {
        (vars.iter())
            .filter(|(_, v)| v.causality == c && v.ty == VarType::Real)
            .map(|(vr, _)| *vr)
            .collect()
    };
    (of(Causality::Input), of(Causality::Output))
}

fn inputs_at(e: &Entry, inputs: &[u32], t: f64) -> Vec<f64> {
    let vars = (e.variables)();
    let w = 100.0 * std::f64::consts::PI / 30.0;
    (inputs.iter())
        .map(|&vr| match vars[vr as usize].1.name {
            "shaft.phi" => w * t,
            "shaft.w" => w,
            "shaft.a" => 0.0,
            _ => vars[vr as usize].1.start.unwrap_or(0.0),
        })
        .collect()
}

#[divan::bench(args = MODELS)]
fn fmi2_step(b: Bencher, id: &str) {
    let e = entry(id);
    let f = Fmu::of(&e);
    let s = f.initialized("bench");
    let (ins, outs) = io(&e);
    let mut t = 0.0;
    b.bench_local(|| {
        s.set_real(&ins, &inputs_at(&e, &ins, t));
        s.do_step(t, H);
        t += H;
        black_box(s.get_real(&outs));
    });
}

#[divan::bench(args = MODELS)]
fn fmi3_step(b: Bencher, id: &str) {
    fmi3_steps(b, id, false);
}

#[divan::bench(args = MODELS)]
fn fmi3_step_early_return(b: Bencher, id: &str) {
    fmi3_steps(b, id, true);
}

/// Steps of an FMI 3.0 instance, early return allowed or not.
fn fmi3_steps(b: Bencher, id: &str, early: bool) {
    let e = entry(id);
    let f = Fmu3::of(&e);
    let i = f.instance_with("bench", false, early);
    i.init();
    let (ins, outs) = io(&e);
    let mut t = 0.0;
    b.bench_local(|| {
        i.set("fmi3SetFloat64", &ins, &inputs_at(&e, &ins, t));
        let (_, _, last) = i.do_step(t, H);
        t = last;
        black_box(i.get::<f64>("fmi3GetFloat64", &outs));
    });
}
