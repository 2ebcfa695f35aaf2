//! Drives the built SewingTable binary through the FMI 2.0 C ABI: outputs equal the Rust model
//! bit for bit (with the extra input table.F_ext), bad parameters refused naming them, FMU state.

mod common;

use bindery_fmu::fmi2::types::*;
use bindery_fmu::md;
use bindery_fmu::mechanisms::sewing_table::model::{SewingTable, V};
use bindery_fmu::model::{Model, NoLog, Values, VarSet};
use common::series::row_bits;
use common::*;
use std::f64::consts::PI;

const W: f64 = 100.0 * PI / 30.0;

fn fmu() -> Fmu {
    Fmu::load("SewingTable", &md::describe::<SewingTable>().1)
}

const OUTPUTS: [V; 10] = [
    V::table_x,
    V::table_v,
    V::table_a,
    V::cam_theta,
    V::cam_rho,
    V::cam_F,
    V::cam_sigma_H,
    V::table_F_friction,
    V::shaft_tau,
    V::rocking_x,
];

fn f_ext(t: f64) -> f64 {
    -150.0 * (7.0 * t).sin()
}

fn run(s: &Slave, t0: f64, n: usize, h: f64) -> Vec<Vec<f64>> {
    let reals: Vec<u32> = OUTPUTS.iter().map(|v| v.vr()).collect();
    let p = Probe {
        inputs: &[V::shaft_phi.vr(), V::shaft_w.vr(), V::table_F_ext.vr()],
        reals: &reals,
        flags: &[],
    };
    sample_run(s, &p, t0, n, h, |t| vec![W * t, W, f_ext(t)])
}

#[test]
fn outputs_match_the_model_computed_in_rust() {
    let f = fmu();
    let s = f.initialized("run");
    let rows = run(&s, 0.0, 300, 0.002);
    let mut m = SewingTable::prepare(&Values::start()).unwrap();
    let mut t = 0.0;
    for row in &rows {
        let mut v = Values::<V>::start();
        v[V::shaft_phi] = W * t;
        v.inputs_at = t; // the inputs the host set at t
        v[V::table_F_ext] = f_ext(t);
        m.evaluate(&mut v, t, &mut NoLog);
        assert_row_is_the_models(t, &OUTPUTS, row, |o| v[o]);
        t += 0.002;
    }
    let (_, phase) = s.get_integer(&[V::table_phase.vr()]);
    assert!((0..=3).contains(&phase[0]));
}

#[test]
fn calculated_parameters_are_the_papers() {
    let f = fmu();
    let s = f.initialized("synth");
    let names = [
        V::synth_alpha1,
        V::synth_A1A2,
        V::synth_k1,
        V::synth_k2,
        V::synth_alpha3,
        V::synth_k0,
        V::synth_l2,
        V::table_stroke,
    ];
    let (_, y) = s.get_real(&names.iter().map(|v| v.vr()).collect::<Vec<_>>());
    let printed = [
        (5.22, 2, true),
        (3.82, 2, false),
        (10.83, 2, false),
        (9.95, 2, false),
        (64.78, 2, true),
        (0.88, 2, false),
        (3.72, 2, false),
        (0.11152, 5, false),
    ];
    for (i, &(p, d, deg)) in printed.iter().enumerate() {
        let x = if deg { y[i].to_degrees() } else { y[i] };
        assert!(
            (x - p).abs() <= 0.5 * 10f64.powi(-d) + 1e-12,
            "{:?} = {x}, paper {p}",
            names[i]
        );
    }
}

#[test]
fn bad_parameters_are_refused_naming_them() {
    let f = fmu();
    // an undercut cam: named with the angle and the smallest cam.R0
    let s = f.slave("undercut");
    assert_eq!(s.setup(0.0, None), Status::Ok);
    assert_eq!(s.set_real(&[V::cam_R0.vr()], &[0.02]), Status::Ok);
    let e = s.initialization_refusal();
    assert!(
        e.contains("cam.R0")
            && e.contains("0.02")
            && e.contains("undercut")
            && e.contains("shaft angle"),
        "{e}"
    );
    // corrected, it goes on
    assert_eq!(s.set_real(&[V::cam_R0.vr()], &[0.1]), Status::Ok);
    assert_eq!(s.call0("fmi2ExitInitializationMode"), Status::Ok);
    // phases that leave no loading dwell
    let s = f.slave("cycle");
    assert_eq!(s.setup(0.0, None), Status::Ok);
    assert_eq!(s.set_real(&[V::cycle_dwell_sew.vr()], &[3.5]), Status::Ok);
    assert_eq!(s.init(), Status::Error);
    assert!(
        s.last_error().contains("cycle.dwell_sew") && s.last_error().contains("cycle.dwell_load"),
        "{}",
        s.last_error()
    );
    // an enumeration value that is no law
    assert_eq!(s.set_integer(&[V::law_forward.vr()], &[9]), Status::Error);
    assert!(s.last_error().contains("law.forward"));
}

#[test]
fn fmu_state_round_trips() {
    let f = fmu();
    let s = f.initialized("state");
    let _ = run(&s, 0.0, 37, 0.002);
    let other = f.slave("other");
    assert_state_replays(&s, &other, "SewingTable", |s| {
        row_bits(&run(s, 0.074, 80, 0.002))
    })
    .free(&s, &other);
}
