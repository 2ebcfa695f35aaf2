//! Exact partial derivatives through the C ABI, for every FMU that offers them
//! (`providesDirectionalDerivative`): FMI 2.0's `fmi2GetDirectionalDerivative` in
//! Co-Simulation (the knowns: the Real inputs) and Model Exchange (also the continuous states,
//! the unknowns also the state derivatives), and FMI 3.0's directional and adjoint derivatives,
//! against central finite differences of the same FMU's values; and the refusals: a known that
//! is no input or state, an unknown that is no continuous output or derivative, a NaN seed.

mod common;

use bindery_fmu::catalog::{self, Entry};
use bindery_fmu::fmi2::types::*;
use bindery_fmu::model::{Causality, VarType, Variability};
use common::*;

type DirDer = unsafe extern "C" fn(
    Component,
    *const ValueReference,
    usize,
    *const ValueReference,
    usize,
    *const Real,
    *mut Real,
) -> Status;

fn directional(s: &Slave, unknowns: &[u32], knowns: &[u32], seed: &[f64]) -> (Status, Vec<f64>) {
    let mut out = vec![f64::NAN; unknowns.len()];
    // SAFETY: the FMI function with arrays of the lengths it is told.
    let st = unsafe {
        s.fmu.sym::<DirDer>("fmi2GetDirectionalDerivative")(
            s.c,
            unknowns.as_ptr(),
            unknowns.len(),
            knowns.as_ptr(),
            knowns.len(),
            seed.as_ptr(),
            out.as_mut_ptr(),
        )
    };
    (st, out)
}

fn offering() -> Vec<Entry> {
    catalog::all()
        .into_iter()
        .filter(|e| (e.info)().partials)
        .collect()
}

/// The Real inputs and the continuous Real outputs of `e`.
fn inputs_and_outputs(e: &Entry) -> (Vec<u32>, Vec<u32>) {
    let vars = (e.variables)();
    let real = |v: &bindery_fmu::model::Var| matches!(v.ty, VarType::Real);
    let inputs = vars
        .iter()
        .filter(|(_, v)| v.causality == Causality::Input && real(v))
        .map(|(vr, _)| *vr)
        .collect();
    let outputs = vars
        .iter()
        .filter(|(_, v)| {
            v.causality == Causality::Output && real(v) && v.variability == Variability::Continuous
        })
        .map(|(vr, _)| *vr)
        .collect();
    (inputs, outputs)
}

/// Central differences of `f` (the unknowns' values) along the known `i` of `x0`, step `h`,
/// with the unknowns' magnitudes there (for the differences' rounding error).
fn central(
    x0: &[f64],
    i: usize,
    h: f64,
    f: &mut dyn FnMut(&[f64]) -> Vec<f64>,
) -> (Vec<f64>, Vec<f64>) {
    let (mut a, mut b) = (x0.to_vec(), x0.to_vec());
    a[i] += h;
    b[i] -= h;
    let (fa, fb) = (f(&a), f(&b));
    let d = fa
        .iter()
        .zip(&fb)
        .map(|(p, m)| (p - m) / (2.0 * h))
        .collect();
    let mag = fa
        .iter()
        .zip(&fb)
        .map(|(p, m)| p.abs().max(m.abs()))
        .collect();
    (d, mag)
}

/// The exact column against the central difference `fd` of step `h` over values of magnitude
/// `mag`: within 1e-6 of the column's scale (the differences' truncation error, h² times the
/// third derivative, stays below that at the steps used), plus the differences' rounding
/// error, 1e-14 of the value over h (a value large against its own slope, as an energy or a
/// stiff chain's force along a slow input, loses digits in the difference, not in the exact
/// column).
fn assert_column(
    what: &str,
    exact: &[f64],
    (fd, mag): &(Vec<f64>, Vec<f64>),
    h: f64,
    names: &[&str],
) {
    for (((x, d), y), n) in exact.iter().zip(fd).zip(mag).zip(names) {
        let scale = x.abs().max(d.abs()).max(1e-3);
        assert!(
            (x - d).abs() <= 1e-6 * scale + 1e-14 * y / h,
            "{what}: d {n}: exact {x:e}, central difference {d:e}"
        );
    }
}

fn names(e: &Entry, vrs: &[u32]) -> Vec<&'static str> {
    let vars = (e.variables)();
    vrs.iter().map(|&r| vars[r as usize].1.name).collect()
}

/// The fidelity levels `e` runs at (`model.fidelity`: 1 kinematic, 2 kinetostatic, 3
/// elastodynamic; those its parameters refuse are left out), `None` for an FMU without the
/// parameter; each with the Integer start value that selects it.
fn levels(e: &Entry) -> Vec<Option<(u32, i32)>> {
    let vars = (e.variables)();
    let Some(vr) = vars
        .iter()
        .find(|(_, v)| v.name == "model.fidelity")
        .map(|(vr, _)| *vr)
    else {
        return vec![None];
    };
    let f = Fmu::of(e);
    (1..=3)
        .filter(|&level| {
            let s = f.slave("level");
            s.ok(s.setup(0.0, None), "fmi2SetupExperiment");
            s.ok(
                s.set_integer(&[vr], &[level]),
                "fmi2SetInteger model.fidelity",
            );
            s.init() == Status::Ok
        })
        .map(|level| Some((vr, level)))
        .collect()
}

/// `e`'s name at `level` (for messages).
fn at_level(e: &Entry, level: Option<(u32, i32)>) -> String {
    match level {
        Some((_, l)) => format!("{} at model.fidelity = {l}", e.identifier),
        None => e.identifier.to_string(),
    }
}

/// Inputs away from zero: a load on the shaft, an inertia, a force.
fn excite(x0: &mut [f64]) {
    for (i, x) in x0.iter_mut().enumerate() {
        if *x == 0.0 {
            *x = 3.0 + i as f64;
        }
    }
}

#[test]
fn co_simulation_partials_equal_central_differences_of_the_outputs() {
    let list = offering();
    assert!(!list.is_empty(), "no FMU offers partial derivatives");
    for (e, level) in list
        .iter()
        .flat_map(|e| levels(e).into_iter().map(move |l| (e, l)))
    {
        let (inputs, outputs) = inputs_and_outputs(e);
        let f = Fmu::of(e);
        let integers: Vec<_> = level.into_iter().collect();
        let s = f.started(
            "cs",
            &Start {
                integers: &integers,
                ..Start::default()
            },
        );
        let (st, mut x0) = s.get_real(&inputs);
        s.ok(st, "fmi2GetReal inputs");
        excite(&mut x0);
        s.ok(s.set_real(&inputs, &x0), "fmi2SetReal");
        // a few steps: the drive turning, its state away from the start
        for k in 0..50 {
            s.ok(s.do_step(k as f64 * 1e-2, 1e-2), "fmi2DoStep");
        }
        let out_names = names(e, &outputs);
        // the inputs set now: the shaft's instant is now, for the columns as for the
        // differences (after the steps it has turned on from the instant it was set)
        s.ok(s.set_real(&inputs, &x0), "fmi2SetReal");
        for (i, &k) in inputs.iter().enumerate() {
            let (st, exact) = directional(&s, &outputs, &[k], &[1.0]);
            s.ok(st, "fmi2GetDirectionalDerivative");
            let h = 1e-5 * x0[i].abs().max(1.0);
            let fd = central(&x0, i, h, &mut |x| {
                s.ok(s.set_real(&inputs, x), "fmi2SetReal");
                let (st, y) = s.get_real(&outputs);
                s.ok(st, "fmi2GetReal");
                y
            });
            s.ok(s.set_real(&inputs, &x0), "fmi2SetReal");
            let what = format!("{} CS, known {}", at_level(e, level), names(e, &[k])[0]);
            assert_column(&what, &exact, &fd, h, &out_names);
        }
        // a direction over all knowns at once is the sum of the columns (linear in the seed)
        let seed: Vec<f64> = (0..inputs.len()).map(|i| 0.5 + i as f64).collect();
        let (st, along) = directional(&s, &outputs, &inputs, &seed);
        s.ok(st, "fmi2GetDirectionalDerivative");
        let (mut sum, mut terms) = (vec![0.0; outputs.len()], vec![0.0; outputs.len()]);
        for (i, &k) in inputs.iter().enumerate() {
            let (_, col) = directional(&s, &outputs, &[k], &[1.0]);
            for ((a, t), c) in sum.iter_mut().zip(&mut terms).zip(col) {
                *a += seed[i] * c;
                *t += (seed[i] * c).abs();
            }
        }
        // to rounding: of the terms and of the value, whose derivative may be a cancellation
        // of large terms inside the model (a Hertz stress in the dwell)
        let (_, y) = s.get_real(&outputs);
        for (((a, b), t), y) in along.iter().zip(&sum).zip(&terms).zip(&y) {
            assert!(
                (a - b).abs() <= 1e-12 * t.max(y.abs()).max(1.0),
                "{}: {a} vs {b}",
                at_level(e, level)
            );
        }
    }
}

#[test]
fn model_exchange_partials_equal_central_differences_of_derivatives_and_outputs() {
    let list = offering();
    for (e, level) in list
        .iter()
        .flat_map(|e| levels(e).into_iter().map(move |l| (e, l)))
    {
        let nx = n_states(e);
        if nx == 0 {
            continue;
        }
        let vars = (e.variables)();
        let ders: Vec<u32> = vars
            .iter()
            .filter(|(_, v)| v.derivative.is_some())
            .map(|(vr, _)| *vr)
            .collect();
        let states: Vec<u32> = vars.iter().filter_map(|(_, v)| v.derivative).collect();
        let (inputs, outputs) = inputs_and_outputs(e);
        let f = Fmu::of(e);
        let s = f.me_instance("me");
        s.me_start(|s| {
            if let Some((vr, l)) = level {
                s.ok(s.set_integer(&[vr], &[l]), "fmi2SetInteger model.fidelity");
            }
        });
        let (_, mut u0) = s.get_real(&inputs);
        excite(&mut u0);
        s.ok(s.set_real(&inputs, &u0), "fmi2SetReal");
        let (st, x) = s.get_array("fmi2GetContinuousStates", nx);
        s.ok(st, "fmi2GetContinuousStates");
        // states away from the start: the drive at some speed; a mechanism's chain a little
        // off its equilibrium (its stiffness makes a larger deflection a different machine),
        // and the differences' step to that scale
        let (offset, step) = if level.is_some() {
            (1e-6, 1e-8)
        } else {
            (1.0, 1e-5)
        };
        let x0: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(i, v)| v + offset * (1.0 + 2.0 * i as f64) * v.abs().max(1.0))
            .collect();
        s.ok(s.set_states(&x0), "fmi2SetContinuousStates");
        let mut unknowns = ders.clone();
        unknowns.extend(&outputs);
        let unknown_names = names(e, &unknowns);
        let values = |s: &Slave| {
            let (st, mut v) = s.get_array("fmi2GetDerivatives", nx);
            s.ok(st, "fmi2GetDerivatives");
            let (st, y) = s.get_real(&outputs);
            s.ok(st, "fmi2GetReal");
            v.extend(y);
            v
        };
        for (i, &k) in states.iter().enumerate() {
            let (st, exact) = directional(&s, &unknowns, &[k], &[1.0]);
            s.ok(st, "fmi2GetDirectionalDerivative");
            let h = step * x0[i].abs().max(1.0);
            let fd = central(&x0, i, h, &mut |x| {
                s.ok(s.set_states(x), "fmi2SetContinuousStates");
                values(&s)
            });
            s.ok(s.set_states(&x0), "fmi2SetContinuousStates");
            let what = format!("{} ME, state {}", at_level(e, level), names(e, &[k])[0]);
            assert_column(&what, &exact, &fd, h, &unknown_names);
        }
        for (i, &k) in inputs.iter().enumerate() {
            let (st, exact) = directional(&s, &unknowns, &[k], &[1.0]);
            s.ok(st, "fmi2GetDirectionalDerivative");
            let h = 1e-5 * u0[i].abs().max(1.0);
            let fd = central(&u0, i, h, &mut |u| {
                s.ok(s.set_real(&inputs, u), "fmi2SetReal");
                values(&s)
            });
            s.ok(s.set_real(&inputs, &u0), "fmi2SetReal");
            let what = format!("{} ME, input {}", at_level(e, level), names(e, &[k])[0]);
            assert_column(&what, &exact, &fd, h, &unknown_names);
        }
    }
}

#[test]
fn bad_knowns_unknowns_and_seeds_are_refused() {
    // (a model without partials refuses the call: fmi2::runtime_tests, every FMU here has them)
    for e in catalog::all() {
        let (inputs, outputs) = inputs_and_outputs(&e);
        let f = Fmu::of(&e);
        let s = f.initialized("cs");
        let what = e.identifier;
        assert!((e.info)().partials, "{what} offers no partial derivatives");
        let vars = (e.variables)();
        let parameter = vars
            .iter()
            .find(|(_, v)| v.causality == Causality::Parameter)
            .map(|(vr, _)| *vr)
            .unwrap();
        let (st, _) = directional(&s, &outputs[..1], &[parameter], &[1.0]);
        s.assert_refused(st, "is no known of a partial derivative", what);
        // in Co-Simulation a state is no known
        if let Some(state) = vars.iter().find_map(|(_, v)| v.derivative)
            && !inputs.contains(&state)
        {
            let (st, _) = directional(&s, &outputs[..1], &[state], &[1.0]);
            s.assert_refused(st, "the knowns are the Real inputs", what);
        }
        let (st, _) = directional(&s, &[parameter], &inputs[..1], &[1.0]);
        s.assert_refused(st, "is no unknown of a partial derivative", what);
        let (st, _) = directional(&s, &outputs[..1], &[u32::MAX], &[1.0]);
        s.assert_refused(st, "unknown value reference", what);
        let (st, _) = directional(&s, &outputs[..1], &inputs[..1], &[f64::NAN]);
        s.assert_refused(st, "not finite", what);
        // NULL arrays with counts
        // SAFETY: the FMI function; the NULL pointers are what is tested.
        let st = unsafe {
            s.fmu.sym::<DirDer>("fmi2GetDirectionalDerivative")(
                s.c,
                std::ptr::null(),
                1,
                inputs.as_ptr(),
                1,
                [1.0].as_ptr(),
                [0.0].as_mut_ptr(),
            )
        };
        s.assert_refused(st, "NULL", what);
        // and the instance goes on
        let (st, _) = directional(&s, &outputs, &inputs, &vec![1.0; inputs.len()]);
        s.ok(st, "fmi2GetDirectionalDerivative after the refusals");
    }
}

/// FMI 3.0: `fmi3GetDirectionalDerivative` gives the same columns as FMI 2.0's at the same
/// point, and `fmi3GetAdjointDerivative` the rows of the same Jacobian (its transpose); the
/// counts are checked.
mod fmi3 {
    use super::common::fmi3::*;
    use super::{inputs_and_outputs, offering};
    use bindery_fmu::fmi3::types::*;
    use libloading::Symbol;

    type Partial = unsafe extern "C" fn(
        Instance,
        *const ValueReference,
        usize,
        *const ValueReference,
        usize,
        *const Float64,
        usize,
        *mut Float64,
        usize,
    ) -> Status;

    fn partial(
        s: &Inst3,
        name: &str,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        n_out: usize,
    ) -> (Status, Vec<f64>) {
        let f: Symbol<Partial> = s.fmu.sym(name);
        let mut out = vec![f64::NAN; n_out];
        // SAFETY: the FMI function with arrays of the lengths it is told.
        let st = unsafe {
            f(
                s.c,
                unknowns.as_ptr(),
                unknowns.len(),
                knowns.as_ptr(),
                knowns.len(),
                seed.as_ptr(),
                seed.len(),
                out.as_mut_ptr(),
                n_out,
            )
        };
        (st, out)
    }

    #[test]
    fn directional_and_adjoint_derivatives_are_one_jacobian() {
        for e in offering() {
            let (inputs, outputs) = inputs_and_outputs(&e);
            let f = Fmu3::of(&e);
            let s = f.instance("cs3");
            s.ok(s.init(), "initialization");
            let (_, mut u0) = s.get::<f64>("fmi3GetFloat64", &inputs);
            super::excite(&mut u0);
            s.ok(s.set("fmi3SetFloat64", &inputs, &u0), "fmi3SetFloat64");
            for k in 0..20 {
                s.ok(s.do_step(k as f64 * 1e-2, 1e-2).0, "fmi3DoStep");
            }
            // the Jacobian by columns (directional) and by rows (adjoint)
            let mut cols = Vec::new();
            for &k in &inputs {
                let (st, c) = partial(
                    &s,
                    "fmi3GetDirectionalDerivative",
                    &outputs,
                    &[k],
                    &[1.0],
                    outputs.len(),
                );
                s.ok(st, "fmi3GetDirectionalDerivative");
                cols.push(c);
            }
            for (i, &o) in outputs.iter().enumerate() {
                let (st, row) = partial(
                    &s,
                    "fmi3GetAdjointDerivative",
                    &[o],
                    &inputs,
                    &[1.0],
                    inputs.len(),
                );
                s.ok(st, "fmi3GetAdjointDerivative");
                for (j, r) in row.iter().enumerate() {
                    assert_eq!(r.to_bits(), cols[j][i].to_bits(), "{}", e.identifier);
                }
            }
            // wrong counts are refused, naming the rule
            let (st, _) = partial(
                &s,
                "fmi3GetDirectionalDerivative",
                &outputs,
                &inputs[..1],
                &[1.0],
                1,
            );
            s.assert_refused(st, "nSensitivity = nUnknowns", e.identifier);
            let (st, _) = partial(
                &s,
                "fmi3GetAdjointDerivative",
                &outputs[..1],
                &inputs,
                &[1.0, 2.0],
                inputs.len(),
            );
            s.assert_refused(st, "nSeed = nUnknowns", e.identifier);
        }
    }
}
