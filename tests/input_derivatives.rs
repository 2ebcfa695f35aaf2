//! `canInterpolateInputs` (`interface.md`; `dynamics.md`: "the shaft angle is extrapolated from
//! shaft.phi, shaft.w, shaft.a (or the input derivatives a host set)"), through the C ABI: a
//! host that sets only `shaft.phi` at coarse communication points and its time derivatives
//! with `fmi2SetRealInputDerivatives` gets the same trajectory as one that sets `shaft.w` and
//! `shaft.a`, and a different one when it sets neither. Run for every FMU of the catalog that
//! declares the capability, at each of its levels: every level moves the shaft over a step
//! along that path and ends the step where it leads.

mod common;

use bindery_fmu::catalog::{self, Entry};
use bindery_fmu::fmi2::types::*;
use common::series::bits;
use common::*;

/// How the host tells the FMU about the shaft between communication points.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Host {
    /// `shaft.phi`, `shaft.w`, `shaft.a` at every point.
    Values,
    /// `shaft.phi` and its derivatives of order 1 and 2.
    PhiDerivatives,
    /// `shaft.phi` with its derivative of order 1, and `shaft.w`'s of order 1.
    PhiAndWDerivatives,
    /// `shaft.phi` only.
    PhiOnly,
}

/// The shaft's motion the host imposes: a run-up at constant acceleration from the nominal
/// speed, `phi(t) = w0*t + alpha*t^2/2`.
const ALPHA: f64 = 12.0;

/// The run-up's acceleration for one FMU: Perforators' roller lifts off above 113.6 rpm and is
/// thrown off its linkage near 160 rpm (a Discard), so its run-up over the 2 s stays below
/// 140 rpm.
fn alpha(e: &Entry) -> f64 {
    if e.identifier == "Perforators" {
        2.0
    } else {
        ALPHA
    }
}

/// Parameters changed from their defaults for this run-up: DiscKnifeDrive's default support
/// friction self-locks slider 7 near 180 deg (see `sliders.locked`); without it the forces
/// compared stay regular.
const RUN_UP_PARAMETERS: &[(&str, &str, f64)] = &[("DiscKnifeDrive", "support.mu", 0.0)];

/// Every Real output at every communication point.
fn run(f: &Fmu, e: &Entry, level: i32, host: Host, h: f64, n: usize) -> Vec<Vec<f64>> {
    let s = f.slave("interp");
    assert_eq!(s.setup(0.0, None), Status::Ok);
    let fid = vr_of(e, "model.fidelity");
    assert_eq!(s.set_integer(&[fid], &[level]), Status::Ok);
    for (_, name, x) in RUN_UP_PARAMETERS.iter().filter(|p| p.0 == e.identifier) {
        assert_eq!(s.set_real(&[vr_of(e, name)], &[*x]), Status::Ok);
    }
    assert_eq!(s.call0("fmi2EnterInitializationMode"), Status::Ok);
    let (phi, w, a) = (
        vr_of(e, "shaft.phi"),
        vr_of(e, "shaft.w"),
        vr_of(e, "shaft.a"),
    );
    let w0 = s.get_real(&[w]).1[0];
    let alpha = alpha(e);
    let at = |t: f64| (w0 * t + 0.5 * alpha * t * t, w0 + alpha * t);
    if host == Host::Values {
        assert_eq!(s.set_real(&[a], &[alpha]), Status::Ok);
    }
    assert_eq!(s.call0("fmi2ExitInitializationMode"), Status::Ok);
    // every Real output: positions, forces, the elastodynamic ones (whatever the FMU names them)
    let outs: Vec<u32> = real_outputs_of(e);
    let mut rows = vec![];
    for i in 0..n {
        let t = i as f64 * h;
        let (p, wt) = at(t);
        let ok = |st: Status, what: &str| s.ok(st, what);
        match host {
            Host::Values => ok(s.set_real(&[phi, w, a], &[p, wt, alpha]), "values"),
            Host::PhiDerivatives => {
                ok(s.set_real(&[phi], &[p]), "phi");
                ok(
                    s.set_input_derivatives(&[phi, phi], &[1, 2], &[wt, alpha]),
                    "derivatives",
                );
            }
            Host::PhiAndWDerivatives => {
                // derivatives first, then the value: the order does not matter
                ok(
                    s.set_input_derivatives(&[phi, w], &[1, 1], &[wt, alpha]),
                    "derivatives",
                );
                ok(s.set_real(&[phi], &[p]), "phi");
            }
            Host::PhiOnly => ok(s.set_real(&[phi], &[p]), "phi"),
        }
        let st = s.do_step(t, h);
        if host == Host::PhiOnly && st == Status::Discard {
            // a host that sets the angle alone jerks the rigid path at every communication
            // point; a mechanism may refuse the step that follows (with a reason): the run
            // ends there, as wrong as it gets
            eprintln!("{} {host:?}: {:?}", e.identifier, s.logs().last());
            rows.push(vec![f64::NAN; outs.len()]);
            return rows;
        }
        assert_eq!(st, Status::Ok, "{} {host:?}: {:?}", e.identifier, s.logs());
        let (st, y) = s.get_real(&outs);
        assert_eq!(st, Status::Ok);
        rows.push(y);
    }
    rows
}

/// The largest difference between two runs, relative to each output's range in `b`, the
/// output where it is, and how many outputs differ by more than 1 % of their range.
fn max_rel_diff(e: &Entry, a: &[Vec<f64>], b: &[Vec<f64>]) -> (f64, &'static str, usize) {
    let names: Vec<&'static str> = real_output_names_of(e);
    let mut worst = (0.0, "", 0);
    for (j, name) in names.iter().enumerate() {
        // the energy-balance residual is the integration's own error, not a quantity of the
        // motion: two runs whose inputs differ by rounding take other steps (and `auto` may
        // change method at another step), so its value differs on its own tiny range; the
        // motion's outputs still say whether a shaft angle is off
        if *name == "elastic.E_residual" {
            continue;
        }
        let scale = b.iter().fold(0.0f64, |m, r| m.max(r[j].abs())).max(1e-9);
        let mut off = 0.0f64;
        for (ra, rb) in a.iter().zip(b) {
            off = off.max((ra[j] - rb[j]).abs() / scale);
        }
        if off > worst.0 {
            (worst.0, worst.1) = (off, *name);
        }
        if off > 1e-2 {
            worst.2 += 1;
        }
    }
    worst
}

#[test]
fn shaft_phi_with_its_derivatives_drives_as_well_as_shaft_w_and_shaft_a() {
    let mut tested = 0;
    for e in catalog::all() {
        if !(e.info)().can_interpolate_inputs {
            continue;
        }
        let f = Fmu::of(&e);
        let (h, n) = (0.05, 40);
        for level in levels(&e) {
            let reference = run(&f, &e, level, Host::Values, h, n);
            for host in [Host::PhiDerivatives, Host::PhiAndWDerivatives] {
                // the same path inside every step: the same run to rounding (the outputs that
                // use shaft.w read the FMU's extrapolated value instead of the host's)
                let (d, name, _) = max_rel_diff(&e, &run(&f, &e, level, host, h, n), &reference);
                assert!(
                    d <= 1e-9,
                    "{} level {level} {host:?}: {name} differs by {d:e} of its range",
                    e.identifier
                );
            }
            let phi_only = run(&f, &e, level, Host::PhiOnly, h, n);
            if phi_only.len() < n {
                // refused with a reason (above): different enough
                tested += 1;
                continue;
            }
            let (d, name, n_off) = max_rel_diff(&e, &phi_only, &reference);
            eprintln!(
                "{} level {level}: shaft.phi alone at h = {h} s: {n_off} outputs off by more than 1 % of their range (worst {name}, {d:.3e})",
                e.identifier
            );
            // without derivatives shaft.w stays at its start value: the step ends elsewhere,
            // and positions, velocities and forces go wrong, not only one output
            assert!(
                n_off >= 5,
                "{} level {level}: without derivatives the run should differ: {n_off} outputs, worst {name} {d:e}",
                e.identifier
            );
            tested += 1;
        }
    }
    assert_eq!(
        tested, 14,
        "four mechanisms at three levels, LegacyNeedleDrive at two"
    );
}

/// Derivatives apply to one step: the step after falls back to `shaft.w`/`shaft.a`, which the
/// FMU left at the values extrapolated to the end of the step; FMU states carry them.
#[test]
fn derivatives_expire_after_the_step_and_travel_with_fmu_states() {
    for e in catalog::all() {
        if !(e.info)().can_interpolate_inputs {
            continue;
        }
        let f = Fmu::of(&e);
        for level in levels(&e) {
            let at_level = Start {
                integers: &[(vr_of(&e, "model.fidelity"), level)],
                ..Start::default()
            };
            let s = f.started("expire", &at_level);
            let (phi, w, a) = (
                vr_of(&e, "shaft.phi"),
                vr_of(&e, "shaft.w"),
                vr_of(&e, "shaft.a"),
            );
            let w0 = s.get_real(&[w]).1[0];
            assert_eq!(
                s.set_input_derivatives(&[phi, phi], &[1, 2], &[2.0 * w0, 5.0]),
                Status::Ok
            );
            // saved with the derivatives, restored after a step that consumed them
            let mut st: FMUstate = std::ptr::null_mut();
            assert_eq!(s.get_state(&mut st), Status::Ok);
            let (_, bytes) = s.serialize(st);
            assert_eq!(s.do_step(0.0, 0.01), Status::Ok);
            let (_, after) = s.get_real(&[phi, w, a]);
            assert!(
                (after[0] - (2.0 * w0 * 0.01 + 0.5 * 5.0 * 1e-4)).abs() < 1e-12,
                "{}: the step followed the derivatives: {after:?}",
                e.identifier
            );
            assert!((after[1] - (2.0 * w0 + 0.05)).abs() < 1e-12 && after[2] == 5.0);
            let mut st2: FMUstate = std::ptr::null_mut();
            assert_eq!(s.get_state(&mut st2), Status::Ok);
            let (_, consumed) = s.serialize(st2);
            assert!(consumed.len() < bytes.len(), "expired after the step");
            // a restored state repeats the step exactly
            let outs: Vec<u32> = real_outputs_of(&e);
            let out = |s: &Slave| {
                let (st, y) = s.get_real(&outs);
                assert_eq!(st, Status::Ok);
                bits(&y)
            };
            let f1 = out(&s);
            assert_eq!(s.set_state(st), Status::Ok);
            assert_eq!(s.do_step(0.0, 0.01), Status::Ok);
            assert_eq!(out(&s), f1);
            // also through the serialized bytes
            let mut st3: FMUstate = std::ptr::null_mut();
            assert_eq!(s.deserialize(&bytes, &mut st3), Status::Ok);
            assert_eq!(s.set_state(st3), Status::Ok);
            assert_eq!(s.do_step(0.0, 0.01), Status::Ok);
            assert_eq!(out(&s), f1);
            // reset forgets them: a fresh run equals one that never set any
            assert_eq!(s.set_input_derivatives(&[phi], &[1], &[3.0]), Status::Ok);
            assert_eq!(s.call0("fmi2Reset"), Status::Ok);
            let mut st4: FMUstate = std::ptr::null_mut();
            assert_eq!(s.get_state(&mut st4), Status::Ok);
            let fresh = f.slave("fresh");
            let mut st5: FMUstate = std::ptr::null_mut();
            assert_eq!(fresh.get_state(&mut st5), Status::Ok);
            assert_eq!(s.serialize(st4).1, fresh.serialize(st5).1);
            for p in [&mut st, &mut st2, &mut st3, &mut st4] {
                assert_eq!(s.free_state(p), Status::Ok);
            }
            assert_eq!(fresh.free_state(&mut st5), Status::Ok);
        }
    }
}

/// A host that sets the shaft's inputs once leaves the angle to the FMU's own extrapolation from
/// step to step (`dynamics.md`). With the mechanism mounted at a phase `drive.phi0` on its shaft,
/// the extrapolated `shaft.phi` keeps the input's meaning, the shaft angle without that phase
/// ([`bindery_fmu::model::shaft::state`] adds it): after each step it reads `w*t`, and the run
/// is the run of a host that sets `shaft.phi` at every communication point.
#[test]
fn the_extrapolated_shaft_phi_leaves_drive_phi0_out() {
    let mut tested = 0;
    for e in catalog::all() {
        if !(e.info)().can_interpolate_inputs {
            continue;
        }
        let f = Fmu::of(&e);
        let phi = vr_of(&e, "shaft.phi");
        let mut reals = vec![(vr_of(&e, "drive.phi0"), 0.7)];
        for (_, name, x) in RUN_UP_PARAMETERS.iter().filter(|p| p.0 == e.identifier) {
            reals.push((vr_of(&e, name), *x));
        }
        for level in levels(&e) {
            let start = Start {
                reals: &reals,
                integers: &[(vr_of(&e, "model.fidelity"), level)],
                ..Start::default()
            };
            let outs = real_outputs_of(&e);
            let (h, n) = (0.01, 30);
            let run = |every_step: bool| {
                let s = f.started("phase", &start);
                let w0 = s.get_real(&[vr_of(&e, "shaft.w")]).1[0];
                let mut rows = vec![];
                for i in 0..n {
                    let t = i as f64 * h;
                    if every_step || i == 0 {
                        s.ok(s.set_real(&[phi], &[w0 * t]), "shaft.phi");
                    }
                    s.ok(
                        s.do_step(t, h),
                        &format!("{} step at t = {t}", e.identifier),
                    );
                    if !every_step {
                        let got = s.get_real(&[phi]).1[0];
                        let want = w0 * (t + h);
                        assert!(
                            (got - want).abs() <= 1e-9 * want.abs().max(1.0),
                            "{}: shaft.phi after the step to {} is {got}, the extrapolated angle \
                         without drive.phi0 is {want}",
                            e.identifier,
                            t + h
                        );
                    }
                    rows.push(s.get_real(&outs).1);
                }
                rows
            };
            let (every, once) = (run(true), run(false));
            // the same run: the angle differs by rounding (phi0 + w*t less phi0 in the one, w*t in
            // the other), which the adaptive solver may answer with other steps, so the compliant
            // chain's outputs agree to its tolerance (DiscKnifeDrive's stiff rod: 2e-4 of the force's
            // range; the energy residual, the integration's own error, is left out); a phase error
            // of drive.phi0 = 0.7 rad puts them off by tens of per cent
            let (worst, name, _) = max_rel_diff(&e, &once, &every);
            assert!(
                worst <= 1e-2,
                "{} level {level}: inputs set once vs at every point: {name} off by {worst:e} of its range",
                e.identifier
            );
            tested += 1;
        }
    }
    assert_eq!(
        tested, 14,
        "four mechanisms at three levels, LegacyNeedleDrive at two"
    );
}
