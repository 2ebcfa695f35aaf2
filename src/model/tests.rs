//! Tests of `model.rs`.

use super::*;

crate::model_variables! {
    enum T (nominal_rpm = 60.0) {
        p = Var::parameter("a.p", 2.0, "m", "p").min(0.0),
        c = Var::calculated("a.c", "m", "c"),
        y = Var::output("a.y", "m", "y").depends(shaft::ON_PHI),
        f = Var::bool_output("a.f", "f"),
    }
}

/// A model of the variables `$var` that computes nothing of its own (`$name`, a unit struct):
/// what the trait's provided methods do alone.
macro_rules! empty_model {
    ($name:ident, $var:ty) => {
        struct $name;
        impl Model for $name {
            type Var = $var;
            const IDENTIFIER: &'static str = stringify!($name);
            const DESCRIPTION: &'static str = "";
            const EXPERIMENT: Experiment = Experiment::until(1.0, 0.1);
            fn prepare(_: &Values<$var>) -> Result<Self, ParamError> {
                Ok($name)
            }
            fn evaluate(&mut self, _: &mut Values<$var>, _: f64, _: &mut dyn Log) {}
        }
        impl Dynamics<$var> for $name {}
    };
}

#[test]
fn common_variables_come_first_and_vrs_follow_the_enum() {
    let t = T::table();
    assert_eq!(t.len(), shaft::COUNT + 4);
    assert_eq!(t[shaft::PHI as usize].name, "shaft.phi");
    assert_eq!(t[shaft::FIDELITY as usize].name, "model.fidelity");
    assert_eq!(t[T::p.vr() as usize].name, "a.p");
    assert_eq!(T::shaft_phi.vr(), shaft::PHI);
    assert_eq!(T::model_fidelity.vr(), shaft::FIDELITY);
    // start of the speed input is the nominal speed
    let v = Values::<T>::start();
    assert!((v[T::shaft_w] - 2.0 * std::f64::consts::PI).abs() < 1e-15);
    assert_eq!(v[T::p], 2.0);
    assert_eq!(v.int(T::drive_mode), 1);
    assert_eq!(shaft::fidelity(&v), shaft::Fidelity::Kinetostatic);
}

/// The start values with the shaft inputs `phi`, `w`, `a` set at time `at`.
fn shaft_at(phi: f64, w: f64, a: f64, at: f64) -> Values<T> {
    let mut v = Values::<T>::start();
    v[T::shaft_phi] = phi;
    v[T::shaft_w] = w;
    v[T::shaft_a] = a;
    v.inputs_at = at;
    v
}

#[test]
fn constant_speed_drive_ignores_inputs() {
    let mut v = shaft_at(5.0, 0.0, 0.0, 0.0);
    v[T::drive_mode] = 2.0;
    v[T::drive_phi0] = 1.0;
    let s = shaft::state(&v, 0.5);
    assert_eq!(s.phi, 1.0 + 0.5 * v[T::drive_n]);
    assert_eq!(s.a, 0.0);
}

#[test]
fn shaft_path_takes_the_input_derivatives_a_host_set() {
    let mut v = shaft_at(1.0, 2.0, 3.0, 10.0); // set at the step's start
    let at = |v: &Values<T>| {
        let p = shaft::path(v, 10.0);
        (p.w, p.a, p.absolute_phi(10.5))
    };
    assert_eq!(at(&v), (2.0, 3.0, 1.0 + 2.0 * 0.5 + 0.5 * 3.0 * 0.25));
    // phi' replaces shaft.w; shaft.w' replaces shaft.a; phi'' wins over shaft.w'
    v.set_input_derivative(shaft::PHI, 1, 5.0);
    assert_eq!(at(&v).0, 5.0);
    assert_eq!(at(&v).1, 3.0);
    v.set_input_derivative(shaft::W, 1, 7.0);
    assert_eq!(at(&v).1, 7.0);
    v.set_input_derivative(shaft::PHI, 2, -4.0);
    v.set_input_derivative(shaft::PHI, 2, -6.0);
    assert_eq!(v.input_derivatives().len(), 3, "set again replaces");
    let (w, a, phi) = at(&v);
    assert_eq!((w, a), (5.0, -6.0));
    assert!((phi - (1.0 + 5.0 * 0.5 - 0.5 * 6.0 * 0.25)).abs() < 1e-12);
    // the unused ones are stored but not read by the path
    assert!(!shaft::uses_input_derivative(shaft::A, 1));
    assert!(!shaft::uses_input_derivative(shaft::W, 2));
    // the constant-speed drive ignores the inputs and their derivatives
    v[T::drive_mode] = 2.0;
    let p = shaft::path(&v, 10.0);
    assert_eq!((p.w, p.a), (v[T::drive_n], 0.0));
    v.clear_input_derivatives();
    v[T::drive_mode] = 1.0;
    assert_eq!(at(&v).0, 2.0);
}

/// A step of an algebraic model: nothing of its own, yet the inputs end where the shaft's
/// path leads, with the host's input derivatives if it set any; a constant-speed drive and
/// a standalone model keep theirs.
#[test]
fn a_step_ends_with_the_inputs_at_its_end() {
    empty_model!(Algebraic, T);
    const { assert!(Algebraic::CAN_INTERPOLATE_INPUTS) };
    let mut v = shaft_at(1.0, 2.0, 3.0, 10.0);
    v[T::drive_phi0] = 0.25; // the mechanism's phase stays out of the input
    let mut m = Algebraic;
    m.step(&mut v, 10.0, 0.5, &mut NoLog).unwrap();
    let (phi, w, a) = (v[T::shaft_phi], v[T::shaft_w], v[T::shaft_a]);
    assert_eq!(
        v.inputs_at, 10.5,
        "the moved inputs are those of the step's end"
    );
    assert!(
        (phi - (1.0 + 2.0 * 0.5 + 0.5 * 3.0 * 0.25)).abs() < 1e-12,
        "{phi}"
    );
    assert_eq!((w, a), (2.0 + 3.0 * 0.5, 3.0));
    // phi' and phi'' a host set for the step
    v.set_input_derivative(shaft::PHI, 1, 4.0);
    v.set_input_derivative(shaft::PHI, 2, -2.0);
    m.step(&mut v, 10.5, 0.5, &mut NoLog).unwrap();
    assert!((v[T::shaft_phi] - (phi + 4.0 * 0.5 - 0.25)).abs() < 1e-12);
    assert_eq!((v[T::shaft_w], v[T::shaft_a]), (4.0 - 2.0 * 0.5, -2.0));
    // a path that leaves the finite numbers: refused before the step, the inputs kept
    v.clear_input_derivatives();
    let before = v.raw().to_vec();
    let why = m.step(&mut v, 11.0, 1e300, &mut NoLog).unwrap_err();
    assert!(why.contains("leads to shaft.phi = -inf"), "{why}");
    assert_eq!(v.raw(), &before[..]);
    // constant speed: the inputs are not the shaft, they stay
    v[T::drive_mode] = 2.0;
    m.step(&mut v, 11.0, 0.5, &mut NoLog).unwrap();
    assert_eq!(v.raw()[..3], before[..3]);
}

#[test]
fn phi0_phases_the_mechanism_on_its_shaft_in_input_mode() {
    let mut v = shaft_at(2.0, 3.0, 0.0, 7.0);
    v[T::drive_phi0] = 0.5;
    let s = shaft::state(&v, 7.0);
    assert_eq!((s.phi, s.w), (2.5, 3.0));
}

/// A bound refused names the value and the bound in the unit and in the display unit a
/// designer reads (rpm for drive.n).
#[test]
fn a_bound_is_refused_in_si_and_display_units() {
    let mut v = Values::<T>::start();
    v[T::drive_n] = 2e4;
    let e = check_bounds(&v).unwrap_err();
    assert_eq!(e.param, "drive.n");
    assert_eq!(
        e.to_string(),
        "drive.n = 20000: 20000 rad/s (190986 rpm) must be at most 10000 rad/s (95493 rpm)"
    );
}

/// The one rule of the shaft inputs: they are the shaft at the instant they were set, and
/// the shaft moves on from there at that speed and acceleration until they are set again
/// (so a mechanism whose inputs no host sets turns at the start value of `shaft.w`).
#[test]
fn the_shaft_moves_on_from_the_inputs_as_set() {
    let mut v = Values::<T>::start();
    assert_eq!(v.inputs_at, 0.0);
    let w0 = v[T::shaft_w];
    assert!(w0 > 0.0, "shaft.w starts at the nominal speed");
    let s = shaft::state(&v, 0.25);
    assert_eq!((s.phi, s.w, s.a), (w0 * 0.25, w0, 0.0));
    v[T::shaft_phi] = 2.0;
    v[T::shaft_w] = 3.0;
    v[T::shaft_a] = -1.0;
    v[T::drive_phi0] = 0.5;
    v.inputs_at = 5.0;
    let s = shaft::state(&v, 7.0);
    assert_eq!(s.phi, 2.0 + 3.0 * 2.0 - 0.5 * 4.0 + 0.5);
    assert_eq!((s.w, s.a), (3.0 - 2.0, -1.0));
    // the path of a step from 7.0 starts there, with the moved speed
    let p = shaft::path(&v, 7.0);
    assert_eq!((p.w, p.a), (1.0, -1.0));
    assert_eq!(p.absolute_phi(7.0), s.phi);
}

#[test]
fn reduce_splits_an_affine_torque_exactly() {
    let r = shaft::reduce(|a| 12.5 + 3.25 * a);
    assert_eq!((r.tau0, r.j_red), (12.5, 3.25));
    assert_eq!(r.torque(2.0), 12.5 + 6.5);
    // with the torque at the actual acceleration known: the same split, fewer evaluations
    for a in [0.0, 0.5, -4.0] {
        let mut calls = 0;
        let r = shaft::reduce_at(12.5 + 3.25 * a, a, |e| {
            calls += 1;
            12.5 + 3.25 * e
        });
        assert_eq!((r.tau0, r.j_red), (12.5, 3.25), "a = {a}");
        assert_eq!(calls, if a == 0.5 { 2 } else { 1 }, "a = {a}");
    }
    // a torque with a kink (friction changing regime) between 0 and a: exact at a
    let kinked = |e: f64| 10.0 + 2.0 * e + if e > 1.5 { 5.0 * (e - 1.5) } else { 0.0 };
    let r = shaft::reduce_at(kinked(4.0), 4.0, kinked);
    assert!((r.torque(4.0) - kinked(4.0)).abs() < 1e-12);
}

#[test]
fn reduce_at_rest_reuses_the_torque_only_at_a_constant_speed() {
    let kinked = |e: f64| 10.0 + 2.0 * e + if e > 1.5 { 5.0 * (e - 1.5) } else { 0.0 };
    let plain = shaft::reduce(kinked);
    for (a, evaluations) in [(0.0, 1), (0.5, 2), (4.0, 2)] {
        let mut calls = 0;
        let r = shaft::reduce_at_rest(kinked(a), a, |e| {
            calls += 1;
            kinked(e)
        });
        // reduce's split at every acceleration, bit for bit (not reduce_at's secant over [0, a])
        assert_eq!((r.tau0, r.j_red), (plain.tau0, plain.j_red), "a = {a}");
        assert_eq!(calls, evaluations, "a = {a}");
    }
}

#[test]
fn standalone_models_have_no_common_variables() {
    crate::model_variables! {
        enum D (standalone) {
            y = Var::output("shaft.phi", "rad", "y").depends(&[]),
            u = Var::input("load.tau", 0.0, "N.m", "u"),
        }
    }
    assert_eq!(D::table().len(), 2);
    assert_eq!(D::u.vr(), 1);
    // it drives the shaft: its inputs are held over a step, none is extrapolated
    const { assert!(!D::SHAFT_CONNECTOR && T::SHAFT_CONNECTOR) };
    empty_model!(Drive, D);
    const { assert!(!Drive::CAN_INTERPOLATE_INPUTS) };
    let mut v = Values::<D>::start();
    v[D::y] = 1.0;
    v[D::u] = 2.0;
    Drive.step(&mut v, 0.0, 0.5, &mut NoLog).unwrap();
    assert_eq!(v.raw(), &[1.0, 2.0]);
}

#[test]
fn settable_rules_follow_fmi2() {
    let t = T::table();
    let p = &t[T::p.vr() as usize];
    let c = &t[T::c.vr() as usize];
    let y = &t[T::y.vr() as usize];
    let phi = &t[T::shaft_phi.vr() as usize];
    assert!(p.settable(SetPhase::Instantiated) && p.settable(SetPhase::Initialization));
    assert!(
        !p.settable(SetPhase::Running),
        "fixed parameter after initialization"
    );
    assert!(!c.settable(SetPhase::Instantiated) && !c.settable(SetPhase::Initialization));
    assert!(!y.settable(SetPhase::Running));
    assert!(phi.settable(SetPhase::Instantiated) && phi.settable(SetPhase::Running));
}

/// An enumeration value is any `i32` a host passes: the ends of the range are no items (at
/// `i32::MIN`, `value - 1` overflowed: a panic with overflow checks, a wrap without).
#[test]
fn enumeration_items_of_any_host_integer() {
    static E: EnumType = EnumType {
        name: "E",
        description: "",
        items: &[("a", ""), ("b", "")],
    };
    assert_eq!(E.item(1), Some("a"));
    assert_eq!(E.item(2), Some("b"));
    for v in [i32::MIN, i32::MIN + 1, -1, 0, 3, i32::MAX] {
        assert_eq!(E.item(v), None, "{v}");
    }
}
