//! Non-finite and absurd states from a Model Exchange host, through the C ABI, for every FMU
//! with Model Exchange (the mechanisms at their elastodynamic level, MainShaft):
//!
//! - a NaN or ±Inf state in fmi2SetContinuousStates is refused (fmi2Error) before the model
//!   sees it, the log naming the state's variable (`elastic.x`, `shaft.w`, ...), and the
//!   instance goes on with its previous states: the same states, derivatives, indicators and
//!   outputs, bit for bit, and nothing else logged;
//! - finite states far off the motion (an explicit Euler step too large for a stiff chain) give
//!   finite derivatives and indicators, or fmi2Discard naming the derivative and the states (the
//!   model has no finite value there); no check runs on a NaN (DiscKnifeDrive's self-locking
//!   criterion at a slider position where the holder does not assemble said
//!   "|tan(beta + alpha)| = NaN < support.mu"); back at the previous states all is as before.

mod common;

use bindery_fmu::catalog::{self, Entry};
use bindery_fmu::fmi2::types::*;
use common::*;

/// The names of the continuous states of a catalog entry, in the order of the states.
fn state_names(e: &Entry) -> Vec<&'static str> {
    let vars = (e.variables)();
    vars.iter()
        .filter_map(|(_, v)| v.derivative)
        .map(|s| vars[s as usize].1.name)
        .collect()
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// Everything a host reads at the current point: states, derivatives, indicators, every Real
/// output (each call asserted fmi2OK).
fn point(s: &Slave, nx: usize, nz: usize, outs: &[u32]) -> Vec<f64> {
    let mut all = Vec::new();
    for (name, n) in [
        ("fmi2GetContinuousStates", nx),
        ("fmi2GetDerivatives", nx),
        ("fmi2GetEventIndicators", nz),
    ] {
        let (st, x) = s.get_array(name, n);
        s.ok(st, name);
        assert!(x.iter().all(|v| v.is_finite()), "{name}: {x:?}");
        all.extend(x);
    }
    let (st, y) = s.get_real(outs);
    s.ok(st, "fmi2GetReal");
    all.extend(y);
    all
}

/// A Model Exchange instance of `e` (elastodynamic level for a mechanism) in continuous-time
/// mode at t = 0.05 s, its inputs at their start values.
fn started<'a>(e: &Entry, f: &'a Fmu) -> Slave<'a> {
    let s = f.me_instance("me");
    let mechanism = (e.variables)()
        .iter()
        .any(|(_, v)| v.name == "model.fidelity");
    s.me_start(|s| {
        if mechanism {
            s.ok(
                s.set_integer(&[vr_of(e, "model.fidelity")], &[3]),
                "model.fidelity",
            );
        }
    });
    s.ok(s.set_time(0.05), "fmi2SetTime");
    s
}

#[test]
fn non_finite_states_are_refused_naming_the_state_and_change_nothing() {
    let mut covered = Vec::new();
    for e in catalog::all() {
        let names = state_names(&e);
        let nx = names.len();
        if nx == 0 {
            continue;
        }
        let nz = (e.info)().event_indicators as usize;
        let f = Fmu::of(&e);
        let s = started(&e, &f);
        let outs = real_outputs_of(&e);
        let before = point(&s, nx, nz, &outs);
        let x0 = before[..nx].to_vec();
        let logged = s.logs().len();
        for (i, name) in names.iter().enumerate() {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut x = x0.clone();
                x[i] = bad;
                let what = format!("{}: {name} = {bad}", e.identifier);
                s.assert_refused(
                    s.set_states(&x),
                    &format!("{name} = {bad} is not finite"),
                    &what,
                );
                assert!(
                    s.last_error().contains("the states are kept"),
                    "{what}: {}",
                    s.last_error()
                );
                // the instance goes on from its previous states
                assert_eq!(bits(&point(&s, nx, nz, &outs)), bits(&before), "{what}");
            }
        }
        // nothing but the refusals was logged (no check ran on the refused values)
        let logs = s.logs();
        let other: Vec<_> = logs[logged..]
            .iter()
            .filter(|l| l.0 != Status::Error && l.1 != "logAll")
            .collect();
        assert!(other.is_empty(), "{}: {other:?}", e.identifier);
        // and the host's next finite states are taken
        let mut x = x0.clone();
        x[0] += 1e-9;
        s.ok(s.set_states(&x), "fmi2SetContinuousStates");
        assert_eq!(
            bits(&s.get_array("fmi2GetContinuousStates", nx).1),
            bits(&x)
        );
        covered.push(e.identifier);
    }
    assert_eq!(covered.len(), 5, "{covered:?}");
}

#[test]
fn absurd_finite_states_give_finite_values_or_a_discard_naming_them() {
    let mut discards = Vec::new();
    for e in catalog::all() {
        let names = state_names(&e);
        let nx = names.len();
        if nx == 0 {
            continue;
        }
        let nz = (e.info)().event_indicators as usize;
        let f = Fmu::of(&e);
        let s = started(&e, &f);
        let outs = real_outputs_of(&e);
        let before = point(&s, nx, nz, &outs);
        let x0 = before[..nx].to_vec();
        // what an explicit Euler step of 1 ms makes of a stiff chain: the first state a metre
        // (or radian) off, its rate a thousand per second off
        let mut x = x0.clone();
        x[0] += 0.75;
        x[1] += 1e3;
        s.ok(s.set_states(&x), "fmi2SetContinuousStates");
        for (call, n) in [("fmi2GetDerivatives", nx), ("fmi2GetEventIndicators", nz)] {
            let (st, v) = s.get_array(call, n);
            let what = format!("{} {call} at {x:?}", e.identifier);
            match st {
                Status::Ok => assert!(v.iter().all(|v| v.is_finite()), "{what}: {v:?}"),
                Status::Discard => {
                    let msg = &s.logs().last().unwrap().2.clone();
                    assert!(
                        msg.contains("is not finite")
                            && names.iter().all(|n| msg.contains(&format!("{n} = "))),
                        "{what}: {msg}"
                    );
                    if call == "fmi2GetDerivatives" {
                        assert!(msg.contains("der("), "{msg}");
                    }
                    discards.push(format!("{}: {msg}", e.identifier));
                }
                _ => panic!("{what}: {st:?} {:?}", s.logs()),
            }
        }
        let (st, _) = s.get_real(&outs);
        s.ok(st, "fmi2GetReal");
        // no check compared a NaN: every message naming a NaN names the quantity that is one
        for l in s.logs() {
            assert!(
                !(l.2.contains("NaN <") || l.2.contains("NaN >")),
                "{}: {:?}",
                e.identifier,
                l
            );
        }
        if e.identifier == "DiscKnifeDrive" {
            let warned: Vec<_> = s
                .logs()
                .into_iter()
                .filter(|l| l.0 == Status::Warning)
                .collect();
            assert!(
                warned
                    .iter()
                    .any(|l| l.2.contains("does not assemble") && l.2.contains("holder.beta = NaN")),
                "{warned:?}"
            );
            assert!(
                !warned.iter().any(|l| l.2.contains("self-locks")),
                "{warned:?}"
            );
        }
        // back at the previous states, everything is as it was
        s.ok(s.set_states(&x0), "fmi2SetContinuousStates");
        assert_eq!(
            bits(&point(&s, nx, nz, &outs)),
            bits(&before),
            "{}",
            e.identifier
        );
    }
    // the lever outside its linkage, the slider beyond the holder's dead point
    for id in ["Perforators", "DiscKnifeDrive"] {
        assert!(
            discards.iter().any(|d| d.starts_with(id)),
            "{id}: {discards:?}"
        );
    }
}
