//! ns per communication step of GenevaKnifeDrive through the C ABI (`fmi2SetReal` of the shaft
//! angle + `fmi2DoStep` + `fmi2GetReal` of every Real output), against the bare Rust call of the
//! same kinetostatic computation. Needs the built binary: `cargo run --release -- build`, then
//! `cargo bench --bench fmi_step`.

#[path = "../tests/common/mod.rs"]
mod common;

use bindery_fmu::md;
use bindery_fmu::mechanisms::geneva_knife_drive::model::{GenevaKnifeDrive, V};
use bindery_fmu::mechanisms::geneva_knife_drive::physics::Params;
use bindery_fmu::model::{Causality, VarSet, VarType};
use common::Fmu;
use divan::{Bencher, black_box};
use std::f64::consts::PI;

fn main() {
    divan::main();
}

const H: f64 = 1e-3;

/// Every Real output's value reference.
fn real_outputs() -> Vec<u32> {
    V::table()
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality == Causality::Output && v.ty == VarType::Real)
        .map(|(i, _)| i as u32)
        .collect()
}

#[divan::bench(sample_count = 2000, sample_size = 50)]
fn c_abi_step_and_get_all_outputs(b: Bencher) {
    let fmu = Fmu::load("GenevaKnifeDrive", &md::describe::<GenevaKnifeDrive>().1);
    let s = fmu.slave("bench");
    assert_eq!(s.setup(0.0, None), bindery_fmu::fmi2::types::Status::Ok);
    assert_eq!(s.init(), bindery_fmu::fmi2::types::Status::Ok);
    let vrs = real_outputs();
    let mut out = vec![0.0; vrs.len()];
    let set: libloading::Symbol<
        unsafe extern "C" fn(
            *mut std::ffi::c_void,
            *const u32,
            usize,
            *const f64,
        ) -> bindery_fmu::fmi2::types::Status,
    > = fmu.sym("fmi2SetReal");
    let step: libloading::Symbol<
        unsafe extern "C" fn(
            *mut std::ffi::c_void,
            f64,
            f64,
            i32,
        ) -> bindery_fmu::fmi2::types::Status,
    > = fmu.sym("fmi2DoStep");
    let get: libloading::Symbol<
        unsafe extern "C" fn(
            *mut std::ffi::c_void,
            *const u32,
            usize,
            *mut f64,
        ) -> bindery_fmu::fmi2::types::Status,
    > = fmu.sym("fmi2GetReal");
    let phi_vr = [V::shaft_phi.vr()];
    let mut t = 0.0;
    b.bench_local(|| unsafe {
        let phi = PI * t;
        set(s.c, phi_vr.as_ptr(), 1, &phi);
        step(s.c, t, H, 1);
        t += H;
        get(s.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr());
        black_box(&out);
    });
}

#[divan::bench(sample_count = 2000, sample_size = 50)]
fn bare_rust_kinetostatics(b: Bencher) {
    let p = Params::default();
    let mut t = 0.0;
    b.bench_local(|| {
        let k = p.kinematics(black_box(PI * t), PI, 0.0);
        let f = p.kinetostatics(&k, PI, 0.0);
        t += H;
        black_box((k, f));
    });
}
