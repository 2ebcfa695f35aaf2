//! Drives the built LegacyNeedleDrive binary through the FMI 2.0 C ABI: outputs equal the Rust
//! model bit for bit, the spec's reference values at the nominal speed, refusals (the
//! elastodynamic level, an undercut cam, a loop that does not assemble) naming the level, the
//! shaft angle or the loop, a spring-closed cam's lift-off flagged and warned once per turn, and
//! the FMU state round-tripping with the watch's state.

mod common;

use bindery_fmu::fmi2::types::*;
use bindery_fmu::md;
use bindery_fmu::mechanisms::legacy_needle_drive::model::{LegacyNeedleDrive, V};
use bindery_fmu::model::Dynamics;
use bindery_fmu::model::{Model, NoLog, Values, VarSet};
use common::series::row_bits;
use common::*;
use std::f64::consts::PI;

const W: f64 = 100.0 * PI / 30.0;
const H: f64 = 0.002;

fn fmu() -> Fmu {
    Fmu::load("LegacyNeedleDrive", &md::describe::<LegacyNeedleDrive>().1)
}

/// A spring-closed cam (`cam.closure = spring`), started at `time`.
fn spring_closed<'a>(f: &'a Fmu, name: &str, time: f64) -> Slave<'a> {
    let start = Start {
        time,
        integers: &[(V::cam_closure.vr(), 2)],
        ..Start::default()
    };
    f.started(name, &start)
}

const OUTPUTS: [V; 10] = [
    V::perforators_s,
    V::perforators_v,
    V::perforators_a,
    V::rocker_psi,
    V::cam_theta,
    V::cam_rho,
    V::roller_F,
    V::roller_F_margin,
    V::roller_sigma_H,
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

#[test]
fn outputs_match_the_model_computed_in_rust() {
    let f = fmu();
    let s = spring_closed(&f, "run", 0.0);
    let rows = run(&s, 0.0, 700);
    let mut v = Values::<V>::start();
    v[V::cam_closure] = 2.0;
    let mut m = LegacyNeedleDrive::prepare(&v).unwrap();
    let mut t = 0.0;
    for row in &rows {
        v[V::shaft_phi] = W * t;
        v[V::shaft_w] = W;
        v.inputs_at = t;
        m.evaluate(&mut v, t, &mut NoLog);
        assert_row_is_the_models(t, &OUTPUTS, row, |o| v[o]);
        m.do_step(&mut v, t, H, &mut NoLog).unwrap();
        t += H;
    }
}

#[test]
fn the_reference_values_at_the_nominal_speed() {
    let f = fmu();
    let s = f.initialized("reference");
    // shaft.phi = 0.5 rad at 100 rpm, the spec's first row (perforators timing, friction on)
    let vrs: Vec<u32> = [
        V::perforators_s,
        V::roller_F,
        V::roller_sigma_H,
        V::shaft_tau,
    ]
    .iter()
    .map(|v| v.vr())
    .collect();
    assert_eq!(
        s.set_real(&[V::shaft_phi.vr(), V::shaft_w.vr()], &[0.5, W]),
        Status::Ok
    );
    let (_, y) = s.get_real(&vrs);
    for (x, reference, tol) in [
        (1000.0 * y[0], 11.4693, 5e-5),
        (y[1], 39.0605, 5e-5),
        (y[2] / 1e6, 75.215, 5e-4),
        (y[3], 6.21031, 5e-6),
    ] {
        assert!((x - reference).abs() <= tol, "{x} vs {reference}");
    }
}

#[test]
fn refusals_name_the_level_the_shaft_angle_or_the_loop() {
    let f = fmu();
    let s = f.slave("elastic");
    assert_eq!(s.setup(0.0, None), Status::Ok);
    assert_eq!(s.set_integer(&[V::model_fidelity.vr()], &[3]), Status::Ok);
    let e = s.initialization_refusal();
    assert!(
        e.contains("model.fidelity") && e.contains("kinematic and kinetostatic levels only"),
        "{e}"
    );
    for (v, bad, words) in [
        (V::roller_r, 0.03, "undercut at shaft angle"),
        (V::kpm_l, 0.02, "rocker-slider"),
        (V::fb_c, 0.05, "four-bar"),
        (V::kmk_beta, 0.0, "kmk.beta"),
    ] {
        let s = f.slave("refuse");
        assert_eq!(s.setup(0.0, None), Status::Ok);
        assert_eq!(s.set_real(&[v.vr()], &[bad]), Status::Ok);
        let e = s.initialization_refusal();
        assert!(e.contains(words), "{e}");
    }
    // an integer inside the declared bounds but not a branch
    let s = f.slave("branch");
    assert_eq!(s.setup(0.0, None), Status::Ok);
    assert_eq!(s.set_integer(&[V::fb_branch.vr()], &[0]), Status::Ok);
    let e = s.initialization_refusal();
    assert!(e.contains("fb.branch") && e.contains("+1 or -1"), "{e}");
}

#[test]
fn a_spring_closed_cam_lifts_off_flagged_and_warned_once_per_turn() {
    let f = fmu();
    let s = spring_closed(&f, "spring", 0.0);
    // 1.6 s at 100 rpm: two turns complete, the third lifted off but not over
    let rows = run(&s, 0.0, 800);
    assert!(rows.iter().any(|r| r[OUTPUTS.len()] == 1.0));
    assert!(
        rows.last().unwrap()[7] < 0.0,
        "F_margin: the cam would pull"
    );
    let warn: Vec<_> = s
        .logs()
        .into_iter()
        .filter(|l| l.0 == Status::Warning && l.2.contains("roller lifts off the cam"))
        .collect();
    // once for each completed turn (turns 0 and 1, each counting its two lift-offs; the third
    // is reported when it is over, or at termination)
    assert_eq!(warn.len(), 2, "{warn:?}");
    assert!(
        warn[0].2.contains("2 times in the shaft turn 0") && warn[0].2.contains("shaft angle"),
        "{warn:?}"
    );
    // a groove cam never lifts off
    let g = f.initialized("groove");
    let rows = run(&g, 0.0, 900);
    assert!(rows.iter().all(|r| r[OUTPUTS.len()] == 0.0));
    assert!(rows.last().unwrap()[7] >= 0.0);
}

#[test]
fn fmu_state_round_trips_with_the_watch() {
    let f = fmu();
    let s = spring_closed(&f, "state", 0.0);
    // past a full turn, so F_margin comes from the saved watch
    let _ = run(&s, 0.0, 400);
    let t1 = 400.0 * H;
    let other = f.slave("other");
    let replay = assert_state_replays(&s, &other, "LegacyNeedleDrive", |s| {
        row_bits(&run(s, t1, 200))
    });
    let fresh = spring_closed(&f, "fresh", t1);
    let cold = run(&fresh, t1, 1);
    assert_ne!(cold[0][7].to_bits(), replay.run[7]);
    replay.free(&s, &other);
}
