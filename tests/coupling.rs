//! `shaft.tau = shaft.tau0 + shaft.J_red*shaft.a` (the split a main-shaft drive solves with,
//! `model.rs`, `shaft::reduce`) against each mechanism's own torque at random states: exact when
//! friction does not depend on the shaft acceleration, within friction's share otherwise.

use bindery_fmu::mechanisms::{
    disc_knife_drive::{DiscKnifeDrive, model::V as D},
    geneva_knife_drive::{GenevaKnifeDrive, model::V as G},
    perforators::{Perforators, model::V as P},
    sewing_table::{SewingTable, model::V as S},
};
use bindery_fmu::model::{Model, NoLog, Values, VarSet};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// The variables the test needs of a mechanism.
struct Vars<V> {
    phi: V,
    w: V,
    a: V,
    tau: V,
    tau0: V,
    j_red: V,
}

/// `(τ(a2), τ0 + J_red·a2, J_red, τ0)` with `τ0`, `J_red` read at acceleration `a1`: the split is
/// a function of angle and speed only, so it must predict the torque at any other acceleration.
fn predict<M: Model>(
    vars: &Vars<M::Var>,
    set: &[(M::Var, f64)],
    phi: f64,
    w: f64,
    a1: f64,
    a2: f64,
) -> (f64, f64, f64, f64) {
    let mut v = Values::<M::Var>::start();
    for &(k, x) in set {
        v[k] = x;
    }
    let mut m = M::prepare(&v).expect("parameters");
    m.calculated_parameters(&mut v);
    v[vars.phi] = phi;
    v[vars.w] = w;
    v[vars.a] = a1;
    // one short step: an elastodynamic level then has its state, held while `a` changes
    m.do_step(&mut v, 0.0, 1e-5, &mut NoLog).expect("step");
    v.inputs_at = 1e-5; // the inputs are the shaft's at the step's end
    v[vars.phi] = phi;
    v[vars.w] = w;
    v[vars.a] = a1;
    m.evaluate(&mut v, 1e-5, &mut NoLog);
    let (tau0, j_red) = (v[vars.tau0], v[vars.j_red]);
    v[vars.a] = a2;
    m.evaluate(&mut v, 1e-5, &mut NoLog);
    (v[vars.tau], tau0 + j_red * a2, j_red, tau0)
}

/// Random states: every predicted torque within `tol_exact` (relative to the torque scale)
/// where `exact`, and at least `share` of the states exact otherwise; the reduced inertia
/// positive.
fn check<M: Model>(name: &str, vars: Vars<M::Var>, set: &[(M::Var, f64)], w_nom: f64, exact: bool)
where
    M::Var: VarSet,
{
    // a fixed seed: the same 400 states in every run
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases: 400,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    );
    let strategy = (
        0.0..std::f64::consts::TAU,
        0.2..1.5f64,
        -30.0..30.0f64,
        -30.0..30.0f64,
    );
    let exact_count = std::cell::Cell::new(0usize);
    let worst = std::cell::Cell::new(0.0f64);
    let total = std::cell::Cell::new(0usize);
    runner
        .run(&strategy, |(phi, wf, a1, a2)| {
            let (tau, pred, j_red, tau0) = predict::<M>(&vars, set, phi, wf * w_nom, a1, a2);
            prop_assert!(j_red >= 0.0, "{name}: J_red = {j_red} < 0 at phi = {phi}");
            let scale = 1.0 + tau.abs().max(tau0.abs());
            let err = (tau - pred).abs() / scale;
            total.set(total.get() + 1);
            if err <= 1e-9 {
                exact_count.set(exact_count.get() + 1);
            } else if exact {
                prop_assert!(
                    false,
                    "{name}: tau = {tau}, tau0 + J_red*a = {pred} at phi = {phi}, a = {a2}"
                );
            }
            worst.set(worst.get().max(err));
            Ok(())
        })
        .unwrap();
    let (exact_count, total, worst) = (exact_count.get(), total.get(), worst.get());
    eprintln!("{name}: {exact_count} of {total} states exact, worst relative error {worst:.3e}");
    if !exact {
        assert!(
            exact_count as f64 >= 0.8 * total as f64,
            "{name}: only {exact_count} of {total} states exact (worst relative error {worst})"
        );
        // friction changes the split by its coefficient's order, not more
        assert!(worst < 0.2, "{name}: worst relative error {worst}");
    }
}

macro_rules! vars {
    ($v:ident) => {
        Vars {
            phi: $v::shaft_phi,
            w: $v::shaft_w,
            a: $v::shaft_a,
            tau: $v::shaft_tau,
            tau0: $v::shaft_tau0,
            j_red: $v::shaft_J_red,
        }
    };
}

const RPM: f64 = std::f64::consts::PI / 30.0;

#[test]
fn geneva_knife_drive_split() {
    let frictionless = [(G::guide_mu, 0.0), (G::gear_eta, 1.0)];
    check::<GenevaKnifeDrive>(
        "Geneva, no friction",
        vars!(G),
        &frictionless,
        30.0 * RPM,
        true,
    );
    check::<GenevaKnifeDrive>("Geneva", vars!(G), &[], 30.0 * RPM, false);
    // elastodynamic level: the chain force is a state; only the rigid links upstream of the
    // compliance (crank, gear pair, cross, driver) act at the shaft
    let elastic = [
        (G::model_fidelity, 3.0),
        (G::guide_mu, 0.0),
        (G::gear_eta, 1.0),
    ];
    check::<GenevaKnifeDrive>("Geneva elastodynamic", vars!(G), &elastic, 30.0 * RPM, true);
}

#[test]
fn sewing_table_split() {
    check::<SewingTable>(
        "SewingTable, no friction",
        vars!(S),
        &[(S::guide_f, 0.0)],
        100.0 * RPM,
        true,
    );
    check::<SewingTable>(
        "SewingTable",
        vars!(S),
        &[(S::table_F_ext, 50.0)],
        100.0 * RPM,
        false,
    );
    let elastic = [(S::model_fidelity, 3.0)];
    check::<SewingTable>(
        "SewingTable elastodynamic",
        vars!(S),
        &elastic,
        100.0 * RPM,
        true,
    );
}

#[test]
fn perforators_split() {
    let frictionless = [(P::guide_mu, 0.0), (P::joint_f, 0.0)];
    check::<Perforators>(
        "Perforators, no friction",
        vars!(P),
        &frictionless,
        100.0 * RPM,
        true,
    );
    check::<Perforators>("Perforators", vars!(P), &[], 100.0 * RPM, false);
}

#[test]
fn disc_knife_drive_split() {
    let frictionless = [(D::guide_mu, 0.0), (D::support_mu, 0.0)];
    check::<DiscKnifeDrive>(
        "DiscKnifeDrive, no friction",
        vars!(D),
        &frictionless,
        300.0 * RPM,
        true,
    );
    check::<DiscKnifeDrive>("DiscKnifeDrive", vars!(D), &[], 300.0 * RPM, false);
}

#[test]
fn kinematic_level_has_no_torque_to_split() {
    let (tau, pred, j_red, tau0) =
        predict::<GenevaKnifeDrive>(&vars!(G), &[(G::model_fidelity, 1.0)], 0.3, 3.0, 1.0, 5.0);
    assert_eq!((tau, pred, j_red, tau0), (0.0, 0.0, 0.0, 0.0));
}
