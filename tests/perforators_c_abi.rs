//! Drives the built Perforators binary through the FMI 2.0 C ABI: outputs equal the Rust model
//! bit for bit (incl. the per-cycle state), bad parameters refused naming them, lift-off logged,
//! FMU state round-trips including the model's internal state.

mod common;

use bindery_fmu::fmi2::types::*;
use bindery_fmu::md;
use bindery_fmu::mechanisms::perforators::model::{Perforators, V};
use bindery_fmu::model::Dynamics;
use bindery_fmu::model::{Model, NoLog, Values, VarSet};
use common::series::row_bits;
use common::*;
use std::f64::consts::PI;

const W: f64 = 100.0 * PI / 30.0;
const H: f64 = 0.002;

fn fmu() -> Fmu {
    Fmu::load("Perforators", &md::describe::<Perforators>().1)
}

/// An instance started at `time` with a spring preload of 0.5 N m (spring.M0): too weak to
/// keep the roller on the ramp at the nominal speed.
fn weak_spring<'a>(f: &'a Fmu, name: &str, time: f64) -> Slave<'a> {
    let start = Start {
        time,
        reals: &[(V::spring_M0.vr(), 0.5)],
        ..Start::default()
    };
    f.started(name, &start)
}

const OUTPUTS: [V; 10] = [
    V::perforators_s,
    V::perforators_v,
    V::perforators_a,
    V::lever_gamma,
    V::roller_F,
    V::roller_F_margin,
    V::roller_sigma_H,
    V::table_F,
    V::ramp_rho,
    V::shaft_tau,
];

/// Every output of [`OUTPUTS`] and, last, `roller.lost_contact` (0 or 1) per sample.
fn run(s: &Slave, t0: f64, n: usize) -> Vec<Vec<f64>> {
    let reals: Vec<u32> = OUTPUTS.iter().map(|v| v.vr()).collect();
    let p = Probe {
        inputs: &[V::shaft_phi.vr(), V::shaft_w.vr()],
        reals: &reals,
        flags: &[V::roller_lost_contact.vr()],
    };
    sample_run(s, &p, t0, n, H, |t| vec![W * t, W])
}

/// Whether a sample of [`run`] has the roller off the ramp.
fn lost_contact(row: &[f64]) -> bool {
    row[OUTPUTS.len()] == 1.0
}

#[test]
fn outputs_match_the_model_computed_in_rust() {
    let f = fmu();
    let s = f.initialized("run");
    let rows = run(&s, 0.0, 700);
    let mut v = Values::<V>::start();
    let mut m = Perforators::prepare(&v).unwrap();
    let mut t = 0.0;
    for row in &rows {
        v[V::shaft_phi] = W * t;
        v[V::shaft_w] = W;
        v.inputs_at = t; // the inputs the host set at t
        m.evaluate(&mut v, t, &mut NoLog);
        assert_row_is_the_models(t, &OUTPUTS, row, |o| v[o]);
        m.do_step(&mut v, t, H, &mut NoLog).unwrap();
        t += H;
    }
}

#[test]
fn calculated_parameters_are_the_papers() {
    let f = fmu();
    for (mode, gamma_sum) in [(1, 28.93), (2, 28.27)] {
        let s = f.started(
            "synth",
            &Start {
                integers: &[(V::synth_mode.vr(), mode)],
                ..Start::default()
            },
        );
        let vrs = [
            V::synth_nu,
            V::synth_gamma_sum,
            V::synth_S_sum,
            V::synth_stroke_error,
            V::synth_gamma_paper,
        ];
        let (_, y) = s.get_real(&vrs.iter().map(|v| v.vr()).collect::<Vec<_>>());
        assert!(
            (y[0].to_degrees() - 28.79).abs() <= 0.005,
            "{}",
            y[0].to_degrees()
        );
        assert!(
            (y[1].to_degrees() - gamma_sum).abs() <= 0.005,
            "{}",
            y[1].to_degrees()
        );
        assert!((y[2] - 0.7023).abs() <= 0.00005);
        assert!((100.0 * y[3] - 2.3).abs() <= 0.05);
        assert!((y[4].to_degrees() - 28.93).abs() <= 0.005);
    }
}

#[test]
fn bad_parameters_are_refused_naming_them() {
    let f = fmu();
    for (v, bad, name) in [
        (V::synth_lambda1, 0.3, "synth.lambda1"),
        (V::pierce_s_out, 0.5, "pierce.s_out"),
        (V::roller_r, 0.2, "roller.r"),
    ] {
        let s = f.slave("refuse");
        assert_eq!(s.setup(0.0, None), Status::Ok);
        assert_eq!(s.set_real(&[v.vr()], &[bad]), Status::Ok);
        let e = s.initialization_refusal();
        assert!(e.contains(name) && e.contains(&bad.to_string()), "{e}");
    }
}

#[test]
fn lift_off_is_logged_as_a_warning_not_an_error() {
    let f = fmu();
    let s = weak_spring(&f, "weak", 0.0);
    let rows = run(&s, 0.0, 500);
    assert!(rows.iter().any(|r| lost_contact(r)));
    let warn: Vec<_> = s
        .logs()
        .into_iter()
        .filter(|l| l.0 == Status::Warning)
        .collect();
    assert!(
        !warn.is_empty() && warn[0].2.contains("shaft angle"),
        "{warn:?}"
    );
    assert!(rows.last().unwrap()[5] < 0.0, "F_margin");
}

#[test]
fn fmu_state_round_trips_with_the_cycle_state() {
    let f = fmu();
    let s = weak_spring(&f, "state", 0.0);
    // past a full turn, so F_margin comes from the saved per-cycle state
    let _ = run(&s, 0.0, 400);
    let t1 = 400.0 * H;
    // the outputs and the lift-off flag, bit for bit
    let other = f.slave("other");
    let replay = assert_state_replays(&s, &other, "Perforators", |s| row_bits(&run(s, t1, 200)));
    // a fresh instance at the same time without the cycle state differs in F_margin
    let fresh = weak_spring(&f, "fresh", t1);
    let cold = run(&fresh, t1, 1);
    // (index 5: F_margin of the first sample)
    assert_ne!(cold[0][5].to_bits(), replay.run[5]);
    replay.free(&s, &other);
}
