//! FMU-state replay in Co-Simulation, through the C ABI, at the elastodynamic level where the
//! FMU integrates inside fmi2DoStep: for every FMU with an integrator, with `solver.method =
//! auto` on its default chain and on one a hundred times stiffer (where `auto` goes between
//! Dormand–Prince and Radau IIA), the state is serialized after every communication step; from
//! a sample of them a fresh instance, given the deserialized state, replays the following steps
//! with every Real, Integer and Boolean output equal to the run's bit for bit.
//!
//! What the integrator carries between steps (next step size, mode, the counters that decide a
//! switch, statistics) is one value in the state (`solver::Memory`): with only part of it saved
//! (the step size and the mode), replays from a state taken while a switch counter ran took
//! other steps (up to 3.8e-8 apart on a two-state probe).

mod common;

use bindery_fmu::catalog;
use bindery_fmu::model::{Causality, VarType};
use common::*;

#[test]
fn co_simulation_states_replay_bit_for_bit_under_auto() {
    let mut cases = 0;
    for e in catalog::all() {
        let vars = (e.variables)();
        let vr = |name: &str| vars.iter().find(|(_, v)| v.name == name).map(|(vr, _)| *vr);
        let Some(method) = vr("solver.method") else {
            continue;
        };
        let outs = |ty: fn(&VarType) -> bool| -> Vec<u32> {
            vars.iter()
                .filter(|(_, v)| v.causality == Causality::Output && ty(&v.ty))
                .map(|(vr, _)| *vr)
                .collect()
        };
        let reals = outs(|t| *t == VarType::Real);
        let ints = outs(|t| matches!(t, VarType::Integer | VarType::Enumeration(_)));
        let bools = outs(|t| *t == VarType::Boolean);
        let f = Fmu::of(&e);
        let mut integers = vec![(method, 1)]; // auto
        if let (Some(fid), Some(mode)) = (vr("model.fidelity"), vr("drive.mode")) {
            integers.extend([(fid, 3), (mode, 2)]); // elastodynamic, at constant speed
        }
        let k = vr("elastic.k");
        let k0 = k.and_then(|vr| vars.iter().find(|(r, _)| *r == vr)?.1.start);
        let stiffness: Vec<Vec<(u32, f64)>> = match (k, k0) {
            (Some(vr), Some(k0)) => vec![vec![], vec![(vr, 100.0 * k0)]],
            _ => vec![vec![]],
        };
        for reals_set in &stiffness {
            let start = Start {
                reals: reals_set,
                integers: &integers,
                ..Start::default()
            };
            let label = format!("{} {:?}", e.identifier, reals_set);
            let row = |s: &Slave| -> Vec<u64> {
                let (st, r) = s.get_real(&reals);
                s.ok(st, "fmi2GetReal");
                let (st, i) = s.get_integer(&ints);
                s.ok(st, "fmi2GetInteger");
                let (st, b) = s.get_boolean(&bools);
                s.ok(st, "fmi2GetBoolean");
                r.iter()
                    .map(|x| x.to_bits())
                    .chain(i.iter().map(|&x| x as u64))
                    .chain(b.iter().map(|&x| x as u64))
                    .collect()
            };
            let (h, n, window) = (2e-3, 300, 12);
            let run = f.started("run", &start);
            let mut rows = vec![];
            let mut states = vec![];
            for j in 0..n {
                states.push(run.state_bytes());
                run.ok(run.do_step(j as f64 * h, h), &format!("{label}: step {j}"));
                rows.push(row(&run));
            }
            for from in (0..n - window).step_by(7) {
                let again = f.started("replay", &start);
                again.restore_bytes(&states[from]);
                for (j, expected) in rows.iter().enumerate().skip(from).take(window) {
                    again.ok(again.do_step(j as f64 * h, h), "replayed step");
                    assert!(
                        row(&again) == *expected,
                        "{label}: the replay from step {from} differs at step {j}"
                    );
                }
            }
            cases += 1;
        }
    }
    assert!(cases >= 8, "{cases} cases");
}
