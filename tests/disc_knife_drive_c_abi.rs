//! Drives the built DiscKnifeDrive binary through the FMI 2.0 C ABI, as a host would: outputs
//! bit-identical to the Rust model, a holder that cannot assemble refused naming the crank angle,
//! the FMU state round trip, the constant-speed drive and the self-locking warning.

mod common;

use bindery_fmu::fmi2::types::*;
use bindery_fmu::md;
use bindery_fmu::mechanisms::disc_knife_drive::model::{DiscKnifeDrive, V};
use bindery_fmu::mechanisms::disc_knife_drive::physics::Params;
use bindery_fmu::model::{Model, NoLog, Values, VarSet};
use common::series::row_bits;
use common::*;
use std::f64::consts::{FRAC_PI_2, PI};

fn fmu() -> Fmu {
    Fmu::load("DiscKnifeDrive", &md::describe::<DiscKnifeDrive>().1)
}

fn vr(v: V) -> u32 {
    v.vr()
}

/// Every Real output of the model.
fn real_outputs() -> Vec<V> {
    use bindery_fmu::model::{Causality, VarType};
    let all = [
        V::shaft_tau,
        V::shaft_P,
        V::shaft_J_red,
        V::shaft_tau0,
        V::slider_x,
        V::slider_v,
        V::slider_a,
        V::holder_beta,
        V::holder_w,
        V::holder_eps,
        V::knife_x,
        V::knife_y,
        V::knife_vx,
        V::knife_vy,
        V::knife_ax,
        V::knife_ay,
        V::support_x,
        V::support_y,
        V::cut_Fx,
        V::cut_Fy,
        V::rod_F,
        V::guide_N,
        V::support_N,
        V::pinC_F,
        V::pinD_F,
        // the elastodynamic level's (at the rigid levels: their rigid values, 0 or 1)
        V::slider_x_kin,
        V::elastic_deflection,
        V::elastic_F,
        V::rod_F_kin,
        V::dyn_factor,
        V::elastic_E_residual,
    ];
    // The list is every Real output the model declares.
    let declared = V::table()
        .iter()
        .filter(|v| v.causality == Causality::Output && v.ty == VarType::Real)
        .count();
    assert_eq!(all.len(), declared);
    all.to_vec()
}

const W: f64 = 10.0 * PI; // 300 rpm

#[test]
fn exports_every_fmi2_cs_function() {
    fmu().assert_exports(FMI2_CS_FUNCTIONS);
}

/// Runs `n` steps of `h` with the shaft at speed W and acceleration `a` through the inputs,
/// returning every Real output and both flags per sample.
fn run(s: &Slave, t0: f64, n: usize, h: f64, a: f64) -> Vec<Vec<f64>> {
    let reals: Vec<u32> = real_outputs().iter().map(|&v| vr(v)).collect();
    let p = Probe {
        inputs: &[vr(V::shaft_phi), vr(V::shaft_w), vr(V::shaft_a)],
        reals: &reals,
        flags: &[vr(V::knife_working), vr(V::sliders_locked)],
    };
    sample_run(s, &p, t0, n, h, |t| vec![W * t, W, a])
}

#[test]
fn outputs_match_the_model_computed_in_rust() {
    let f = fmu();
    let s = f.slave("run");
    s.setup_and_init(0.0, Some(1.0));
    let (n, h, a) = (400, 1e-3, 25.0);
    let rows = run(&s, 0.0, n, h, a);
    let outs = real_outputs();
    let mut m = DiscKnifeDrive::prepare(&Values::start()).unwrap();
    let mut t = 0.0;
    let mut working = 0;
    for row in &rows {
        let mut v = Values::<V>::start();
        v[V::shaft_phi] = W * t;
        v.inputs_at = t; // the inputs the host set at t
        v[V::shaft_a] = a;
        m.evaluate(&mut v, t, &mut NoLog);
        assert_row_is_the_models(t, &outs, row, |o| v[o]);
        assert_eq!(row[outs.len()] == 1.0, v.flag(V::knife_working));
        assert_eq!(row[outs.len() + 1] == 1.0, v.flag(V::sliders_locked));
        working += usize::from(v.flag(V::knife_working));
        t += h;
    }
    // Two turns: half of the samples in the working stroke.
    assert!((working as f64 / n as f64 - 0.5).abs() < 0.01, "{working}");
    // The calculated parameters.
    let (_, c) = s.get_real(&[vr(V::rod_l2), vr(V::slider_stroke)]);
    assert_eq!(
        c,
        vec![Params::default().rod_l2(), Params::default().stroke()]
    );
}

#[test]
fn a_holder_that_cannot_assemble_is_refused_naming_the_crank_angle() {
    let f = fmu();
    let s = f.slave("refuse");
    assert_eq!(s.setup(0.0, None), Status::Ok);
    // Q 15 mm further out: the holder cannot reach EQ while the slider is near the crank.
    assert_eq!(s.set_real(&[vr(V::support_xQ)], &[0.075]), Status::Ok);
    let e = s.initialization_refusal();
    let fail = Params {
        support_xq: 0.075,
        ..Params::default()
    }
    .assembly_failure()
    .unwrap();
    let from = format!("from {:.4} deg", fail.from.to_degrees());
    let to = format!("to {:.4} deg", fail.to.to_degrees());
    assert!(
        e.contains("holder.l4")
            && e.contains("crank angles")
            && e.contains(&from)
            && e.contains(&to),
        "{e}"
    );
    // Symmetric about the inner dead centre, 180 deg.
    assert!((fail.from + fail.to - 2.0 * PI).abs() < 1e-9 && fail.from > 1.0);
    // The host corrects it and goes on.
    assert_eq!(s.set_real(&[vr(V::support_xQ)], &[0.060]), Status::Ok);
    assert_eq!(s.call0("fmi2ExitInitializationMode"), Status::Ok);
    assert_eq!(s.do_step(0.0, 1e-3), Status::Ok);

    // An assembly branch that is neither +1 nor -1.
    let s = f.slave("branch");
    assert_eq!(s.setup(0.0, None), Status::Ok);
    assert_eq!(s.set_integer(&[vr(V::assembly_branch)], &[0]), Status::Ok);
    assert_eq!(s.init(), Status::Error);
    assert!(
        s.last_error().contains("assembly.branch"),
        "{}",
        s.last_error()
    );
}

#[test]
fn fmu_state_round_trips_bit_identically() {
    let f = fmu();
    let s = f.initialized("state");
    let _ = run(&s, 0.0, 37, 1e-3, 0.0);
    let t1 = 0.037;
    // Across the self-locking zone around 180 deg (t = 0.1 s at 300 rpm); set back, and
    // serialize -> deserialize into a second instance: the same continuation.
    let other = f.slave("other");
    let replay = assert_state_replays(&s, &other, "DiscKnifeDrive", |s| {
        let rows = run(s, t1, 120, 1e-3, 0.0);
        // (the last column: sliders.locked)
        assert!(rows.iter().any(|r| *r.last().unwrap() == 1.0));
        row_bits(&rows)
    });
    let bytes = &replay.bytes;
    let mut st3: FMUstate = std::ptr::null_mut();
    assert_eq!(
        other.deserialize(&bytes[..bytes.len() / 2], &mut st3),
        Status::Error
    );
    assert!(st3.is_null());
    replay.free(&s, &other);
}

#[test]
fn constant_speed_mode_reproduces_the_spec_reference() {
    let f = fmu();
    let constant_speed = Start {
        stop: Some(1.0),
        integers: &[(vr(V::drive_mode), 2)],
        ..Start::default()
    };
    let s = f.started("cs", &constant_speed);
    // φ = π/2 at 300 rpm: disc-knife-drive.md prints x_C = 32.909 mm, β = 11.679 deg,
    // S = (43.681, 2.227) mm.
    assert_eq!(s.do_step(0.0, FRAC_PI_2 / W), Status::Ok);
    let (_, y) = s.get_real(&[
        vr(V::slider_x),
        vr(V::holder_beta),
        vr(V::knife_x),
        vr(V::knife_y),
    ]);
    let printed = |x: f64, r: f64| (x - r).abs() <= 5e-4 * (1.0 + 1e-9);
    assert!(printed(y[0] * 1e3, 32.909), "{}", y[0]);
    assert!(printed(y[1].to_degrees(), 11.679), "{}", y[1]);
    assert!(printed(y[2] * 1e3, 43.681), "{}", y[2]);
    assert!(printed(y[3] * 1e3, 2.227), "{}", y[3]);
}

#[test]
fn self_locking_is_a_warning_not_an_error() {
    let f = fmu();
    let s = f.initialized("lock");
    let rows = run(&s, 0.0, 200, 1e-3, 0.0); // one turn
    let locked = rows.iter().filter(|r| *r.last().unwrap() == 1.0).count();
    assert!(locked > 0);
    let warnings: Vec<_> = s
        .logs()
        .into_iter()
        .filter(|l| l.0 == Status::Warning)
        .collect();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].2.contains("self-locks"), "{:?}", warnings[0]);
    // Without friction on EQ nothing locks and nothing is logged.
    let frictionless = Start {
        reals: &[(vr(V::support_mu), 0.0)],
        ..Start::default()
    };
    let s = f.started("free", &frictionless);
    let rows = run(&s, 0.0, 200, 1e-3, 0.0);
    assert!(rows.iter().all(|r| *r.last().unwrap() == 0.0));
    assert!(s.logs().iter().all(|l| l.0 != Status::Warning));
}
