//! The README's finding: `bindery liftoff` finds the lowest main-shaft speed at which the default
//! spring lets the perforators' roller lift off the ramp; the FMU model, stepped through whole
//! turns, flags lift-off just above it and none just below.

mod common;

use bindery_fmu::mechanisms::perforators::model::{Perforators, V};
use bindery_fmu::model::Dynamics;
use bindery_fmu::model::{Model, Values};
use common::series::Warnings;
use std::f64::consts::PI;

/// Two turns at `rpm`, steps of 0.1 deg: (lift-off flagged at some step, warnings, F_margin).
fn two_turns(rpm: f64) -> (bool, usize, f64) {
    let mut v = Values::<V>::start();
    let mut m = Perforators::prepare(&v).unwrap();
    let w = rpm * PI / 30.0;
    let h = 0.1f64.to_radians() / w;
    let mut log = Warnings::default();
    let mut lost = false;
    let mut t = 0.0;
    for _ in 0..7200 {
        v[V::shaft_phi] = w * t;
        v[V::shaft_w] = w;
        m.do_step(&mut v, t, h, &mut log).unwrap();
        t += h;
        v[V::shaft_phi] = w * t;
        m.evaluate(&mut v, t, &mut log);
        lost |= v.flag(V::roller_lost_contact);
    }
    (lost, log.0.len(), v[V::roller_F_margin])
}

#[test]
fn lift_off_speed_found_by_the_cli() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_bindery"))
        .arg("liftoff")
        .output()
        .expect("run bindery liftoff");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let token = text
        .split("lifts off the ramp above ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .unwrap_or_else(|| panic!("no speed in {text:?}"));
    let rpm: f64 = token.parse().unwrap();
    // the README states this speed, as printed
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    assert!(
        readme.contains(&format!("{token} rpm")),
        "README does not state {token} rpm"
    );
    let (lost, warnings, margin) = two_turns(rpm + 0.5);
    assert!(
        lost && warnings >= 1 && margin < 0.0,
        "{rpm} + 0.5 rpm: {lost} {warnings} {margin}"
    );
    let (lost, warnings, margin) = two_turns(rpm - 0.5);
    assert!(
        !lost && warnings == 0 && margin > 0.0,
        "{rpm} - 0.5 rpm: {lost} {warnings} {margin}"
    );
}
