//! `canInterpolateInputs` (`interface.md`; `dynamics.md`: "the shaft angle is extrapolated from
//! shaft.phi, shaft.w, shaft.a (or the input derivatives a host set)"), through the C ABI: a
//! host that sets only `shaft.phi` at coarse communication points and its time derivatives
//! with `fmi2SetRealInputDerivatives` gets the same trajectory as one that sets `shaft.w` and
//! `shaft.a`, and a different one when it sets neither. Run for every FMU of the catalog that
//! declares the capability, at its elastodynamic level.

mod common;

use bindery_fmu::catalog::{self, Entry};
use bindery_fmu::fmi2::types::*;
use common::*;

fn vr_of(e: &Entry, name: &str) -> u32 {
    (e.variables)()
        .into_iter()
        .find(|(_, v)| v.name == name)
        .unwrap_or_else(|| panic!("{}: no variable {name}", e.identifier))
        .0
}

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

/// The main position output and the dynamic force at every communication point.
fn run(f: &Fmu, e: &Entry, host: Host, h: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
    let s = f.slave("interp");
    assert_eq!(s.setup(0.0, None), Status::Ok);
    let fid = vr_of(e, "model.fidelity");
    assert_eq!(s.set_integer(&[fid], &[3]), Status::Ok);
    assert_eq!(s.call0("fmi2EnterInitializationMode"), Status::Ok);
    let (phi, w, a) = (
        vr_of(e, "shaft.phi"),
        vr_of(e, "shaft.w"),
        vr_of(e, "shaft.a"),
    );
    let w0 = s.get_real(&[w]).1[0];
    let at = |t: f64| (w0 * t + 0.5 * ALPHA * t * t, w0 + ALPHA * t);
    if host == Host::Values {
        assert_eq!(s.set_real(&[a], &[ALPHA]), Status::Ok);
    }
    assert_eq!(s.call0("fmi2ExitInitializationMode"), Status::Ok);
    let pos = (e.variables)()
        .into_iter()
        .find(|(_, v)| {
            v.name.ends_with(".x") && v.name.starts_with("table")
                || v.name == "knife.s"
                || v.name == "perforator.s"
        })
        .map(|(vr, _)| vr)
        .expect("a position output");
    let force = vr_of(e, "elastic.F");
    let (mut xs, mut fs) = (vec![], vec![]);
    for i in 0..n {
        let t = i as f64 * h;
        let (p, wt) = at(t);
        let ok = |st: Status, what: &str| assert_eq!(st, Status::Ok, "{what}: {:?}", s.logs());
        match host {
            Host::Values => ok(s.set_real(&[phi, w, a], &[p, wt, ALPHA]), "values"),
            Host::PhiDerivatives => {
                ok(s.set_real(&[phi], &[p]), "phi");
                ok(
                    s.set_input_derivatives(&[phi, phi], &[1, 2], &[wt, ALPHA]),
                    "derivatives",
                );
            }
            Host::PhiAndWDerivatives => {
                // derivatives first, then the value: the order does not matter
                ok(
                    s.set_input_derivatives(&[phi, w], &[1, 1], &[wt, ALPHA]),
                    "derivatives",
                );
                ok(s.set_real(&[phi], &[p]), "phi");
            }
            Host::PhiOnly => ok(s.set_real(&[phi], &[p]), "phi"),
        }
        assert_eq!(s.do_step(t, h), Status::Ok, "{:?}", s.logs());
        let (st, y) = s.get_real(&[pos, force]);
        assert_eq!(st, Status::Ok);
        xs.push(y[0]);
        fs.push(y[1]);
    }
    (xs, fs)
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn shaft_phi_with_its_derivatives_drives_as_well_as_shaft_w_and_shaft_a() {
    let mut tested = 0;
    for e in catalog::all() {
        if !(e.info)().can_interpolate_inputs {
            continue;
        }
        let f = Fmu::load(e.identifier, &(e.describe)().1);
        let (h, n) = (0.05, 40);
        let (x_ref, f_ref) = run(&f, &e, Host::Values, h, n);
        let scale = x_ref.iter().fold(0.0f64, |m, x| m.max(x.abs())).max(1e-3);
        let f_scale = f_ref.iter().fold(0.0f64, |m, x| m.max(x.abs())).max(1.0);
        for host in [Host::PhiDerivatives, Host::PhiAndWDerivatives] {
            let (x, fo) = run(&f, &e, host, h, n);
            // the same path inside every step: the state is the same to rounding
            let dx = max_diff(&x, &x_ref);
            let df = max_diff(&fo, &f_ref);
            assert!(
                dx <= 1e-12 * scale && df <= 1e-9 * f_scale,
                "{} {host:?}: position differs by {dx:e}, force by {df:e}",
                e.identifier
            );
        }
        let (x, fo) = run(&f, &e, Host::PhiOnly, h, n);
        let dx = max_diff(&x, &x_ref);
        let df = max_diff(&fo, &f_ref);
        eprintln!(
            "{}: shaft.phi alone at h = {h} s: position off by {dx:e} m, force by {df:e} N",
            e.identifier
        );
        assert!(
            dx > 1e-6 * scale || df > 1e-3 * f_scale,
            "{}: without derivatives (shaft.w stays at its start) the run should differ: {dx:e}, {df:e}",
            e.identifier
        );
        tested += 1;
    }
    assert!(tested >= 1, "no FMU declares canInterpolateInputs");
}

/// Derivatives apply to one step: the step after falls back to `shaft.w`/`shaft.a`, which the
/// FMU left at the values extrapolated to the end of the step; FMU states carry them.
#[test]
fn derivatives_expire_after_the_step_and_travel_with_fmu_states() {
    for e in catalog::all() {
        if !(e.info)().can_interpolate_inputs {
            continue;
        }
        let f = Fmu::load(e.identifier, &(e.describe)().1);
        let s = f.slave("expire");
        assert_eq!(s.setup(0.0, None), Status::Ok);
        assert_eq!(
            s.set_integer(&[vr_of(&e, "model.fidelity")], &[3]),
            Status::Ok
        );
        assert_eq!(s.init(), Status::Ok);
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
        let out = |s: &Slave| s.get_real(&[vr_of(&e, "elastic.F")]).1[0];
        let f1 = out(&s);
        assert_eq!(s.set_state(st), Status::Ok);
        assert_eq!(s.do_step(0.0, 0.01), Status::Ok);
        assert_eq!(out(&s).to_bits(), f1.to_bits());
        // also through the serialized bytes
        let mut st3: FMUstate = std::ptr::null_mut();
        assert_eq!(s.deserialize(&bytes, &mut st3), Status::Ok);
        assert_eq!(s.set_state(st3), Status::Ok);
        assert_eq!(s.do_step(0.0, 0.01), Status::Ok);
        assert_eq!(out(&s).to_bits(), f1.to_bits());
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
