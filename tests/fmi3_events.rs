//! FMI 3.0 Co-Simulation events of the catalog's FMUs, through the C ABI: Event Mode's call
//! sequence, and steps that return early exactly at the mechanisms' events.

mod common;

use bindery_fmu::catalog::{self, Entry};
use bindery_fmu::model::VarType;
use common::fmi3::*;

/// Event Mode the FMI 3.0 way: after initialization an instance that uses it is in Event Mode
/// (no step there), leaves it with `fmi3EnterStepMode`, enters it again from Step Mode;
/// `fmi3UpdateDiscreteStates` asks for nothing more. An instance that does not use it is never
/// in Event Mode and says why.
#[test]
fn event_mode_the_fmi3_way() {
    let e = &catalog::all()[0];
    let f3 = Fmu3::of(e);
    let i = f3.instance_with("events", true, false);
    i.ok(i.init(), "init");
    i.assert_refused(
        i.do_step(0.0, 1e-3).0,
        "not allowed in state Event Mode",
        "step in Event Mode",
    );
    let (st, flags, _) = i.update_discrete_states();
    i.ok(st, "update");
    assert_eq!(flags, [false; 5]);
    i.ok(i.call0("fmi3EnterStepMode"), "step mode");
    i.ok(i.do_step(0.0, 1e-3).0, "step");
    i.ok(i.call0("fmi3EnterEventMode"), "event mode");
    // an FMU state taken in Event Mode comes back in Event Mode
    let bytes = i.state_bytes();
    i.ok(i.call0("fmi3EnterStepMode"), "step mode");
    i.restore_bytes(&bytes);
    i.assert_refused(
        i.do_step(1e-3, 1e-3).0,
        "Event Mode",
        "restored into Event Mode",
    );
    let plain = f3.instance("plain");
    plain.ok(plain.init(), "init");
    plain.assert_refused(
        plain.call0("fmi3EnterEventMode"),
        "eventModeUsed was false",
        "no event mode",
    );
    plain.assert_refused(
        plain.call0("fmi3EnterStepMode"),
        "eventModeUsed was false",
        "no event mode",
    );
}

/// The event outputs' bits of an instance (those marked as events).
fn event_bits(i: &Inst3, e: &Entry) -> Vec<u64> {
    let marked: Vec<(u32, VarType)> = (vars(e).into_iter())
        .filter(|(_, v)| v.event)
        .map(|(vr, v)| (vr, v.ty))
        .collect();
    (marked.iter())
        .map(|&(vr, ty)| match ty {
            VarType::Boolean => u64::from(i.get::<u8>("fmi3GetBoolean", &[vr]).1[0]),
            _ => i.get::<i32>("fmi3GetInt32", &[vr]).1[0] as u64,
        })
        .collect()
}

/// With early return allowed, a step ends exactly at the first event inside it: at the
/// returned time an event output has its new value, a step from the same start ending a
/// nanosecond earlier still shows the old one; between events the steps are the host's.
/// SewingTable's events (early returns, or changes that fall on a step's end) are its
/// cyclogram's phase boundaries, at the angles its parameters give (82, 192, 282 and 360 deg
/// at the defaults), to 1e-9 deg.
#[test]
fn early_return_stops_exactly_at_each_event() {
    for e in catalog::all() {
        if !vars(&e).iter().any(|(_, v)| v.event) {
            continue;
        }
        let f3 = Fmu3::of(&e);
        let (inputs, rows) = cross_check_inputs(&e);
        let i = f3.instance_with("early", true, true);
        let probe = f3.instance_with("probe", true, false);
        // the Perforators' event is the roller lifting off its ramp (contact.liftoffs): at the
        // elastodynamic level above the lift-off speed (130 rpm: every turn)
        let liftoff = e.identifier == "Perforators";
        let rows = if liftoff {
            let w = 130.0 * std::f64::consts::PI / 30.0;
            let fid = vr_of(&e, "model.fidelity").unwrap();
            i.ok(i.set("fmi3SetInt64", &[fid], &[3i64]), "elastodynamic");
            probe.ok(probe.set("fmi3SetInt64", &[fid], &[3i64]), "elastodynamic");
            (0..=500)
                .map(|k| {
                    let t = k as f64 * 2e-3;
                    vec![t, w * t, w, 0.0]
                })
                .collect()
        } else {
            rows
        };
        i.ok(i.init(), "init");
        i.ok(i.call0("fmi3EnterStepMode"), "step mode");
        let input_at = |t: f64| -> Vec<f64> {
            // the cross-check rows, linear in between (constant speed: exact)
            let k = rows
                .iter()
                .rposition(|r| r[0] <= t)
                .unwrap()
                .min(rows.len() - 2);
            let f = (t - rows[k][0]) / (rows[k + 1][0] - rows[k][0]);
            (1..rows[k].len())
                .map(|j| rows[k][j] + f * (rows[k + 1][j] - rows[k][j]))
                .collect()
        };
        let (mut t, stop, h) = (0.0, rows[rows.len() - 1][0], rows[1][0] - rows[0][0]);
        let (mut events, mut changes, mut last_bits) = (vec![], vec![], None);
        // (which event output, rose) of the early returns
        let mut kinds = std::collections::BTreeSet::new();
        while t < stop - 1e-12 {
            let step = h.min(stop - t);
            i.ok(i.set("fmi3SetFloat64", &inputs, &input_at(t)), "inputs");
            let bytes = i.state_bytes();
            let before = event_bits(&i, &e);
            // the host's input at t may cross a boundary itself (it rounds to either side)
            if last_bits.as_ref().is_some_and(|b| *b != before) {
                changes.push(t);
            }
            let (st, [handling, terminate, early], last) = i.do_step(t, step);
            i.ok(st, "step");
            assert!(!terminate);
            assert_eq!(
                handling, early,
                "{}: eventHandlingNeeded with early return",
                e.identifier
            );
            if event_bits(&i, &e) != before {
                changes.push(last);
            }
            last_bits = Some(event_bits(&i, &e));
            if early {
                assert!(
                    last > t && last < t + step,
                    "{}: {last} in ({t}, {})",
                    e.identifier,
                    t + step
                );
                let after = event_bits(&i, &e);
                assert_ne!(
                    after, before,
                    "{} at {last}: no event output changed",
                    e.identifier
                );
                // a nanosecond earlier from the same start: nothing changed yet (rigid levels:
                // the event's time to a nanosecond; a lift-off: to the time the integrator
                // inside the step locates it, which moves with the step's end by its own error,
                // as the bisection's trials end at different times). Not where the host's input
                // put the step's start next to the event (a step of a few floating-point times).
                let delta = if liftoff { 1e-6 } else { 1e-9 };
                if last - t > 2.0 * delta {
                    probe.restore_bytes(&bytes);
                    probe.ok(probe.do_step(t, last - t - delta).0, "probe");
                    assert_eq!(
                        event_bits(&probe, &e),
                        before,
                        "{} just before {last}",
                        e.identifier
                    );
                }
                probe.restore_bytes(&bytes);
                probe.ok(probe.do_step(t, last - t).0, "probe");
                assert_eq!(event_bits(&probe, &e), after, "{} at {last}", e.identifier);
                events.push(last);
                for (j, (b, a)) in before.iter().zip(&after).enumerate() {
                    if b != a {
                        kinds.insert((j, a > b || (*a == 1 && *b > 1)));
                    }
                }
                i.ok(i.call0("fmi3EnterEventMode"), "event mode");
                i.ok(i.update_discrete_states().0, "update");
                i.ok(i.call0("fmi3EnterStepMode"), "step mode");
            } else {
                assert_eq!(last, t + step);
            }
            t = last;
        }
        let marked: Vec<&str> = (vars(&e).into_iter())
            .filter(|(_, v)| v.event)
            .map(|(_, v)| v.name)
            .collect();
        let seen = |name: &str, rose: bool| {
            let j = marked.iter().position(|n| *n == name).unwrap();
            kinds.contains(&(j, rose))
        };
        match e.identifier {
            // the cut's start and its cut-through, the roller entering and leaving the slots
            "GenevaKnifeDrive" => {
                for (name, rose) in [("knife.in_stack", true), ("knife.in_stack", false)] {
                    assert!(seen(name, rose), "Geneva: {name} rising {rose}: {kinds:?}");
                }
            }
            // a lift-off and a landing
            "Perforators" => {
                for (name, rose) in [("contact.open", true), ("contact.open", false)] {
                    assert!(
                        seen(name, rose),
                        "Perforators: {name} rising {rose}: {kinds:?}"
                    );
                }
            }
            _ => {}
        }
        assert!(
            !events.is_empty(),
            "{}: no event over the cross-check run",
            e.identifier
        );
        if e.identifier == "SewingTable" {
            let par = |n: &str| i.get::<f64>("fmi3GetFloat64", &[vr_of(&e, n).unwrap()]).1[0];
            let (phi0, fwd, sew, ret) = (
                par("cycle.phi0"),
                par("cycle.forward"),
                par("cycle.dwell_sew"),
                par("cycle.return"),
            );
            let w = rows[0][2];
            let turn = std::f64::consts::TAU;
            let mut expected = vec![];
            for k in 0..3 {
                for b in [fwd, fwd + sew, fwd + sew + ret, turn] {
                    let te = (phi0 + b + k as f64 * turn) / w;
                    if te > 1e-9 && te < stop + 1e-9 {
                        expected.push(te);
                    }
                }
            }
            expected.sort_by(f64::total_cmp);
            // a change at a step's end is no early return; and where the host's input at the
            // event's time rounds to the old side (the shaft angle interpolated from the input
            // file), the output changes back and again one floating-point time later: one event
            changes.dedup_by(|b, a| (*b - *a).abs() < 1e-12);
            assert_eq!(
                changes.len(),
                expected.len(),
                "{changes:?} against {expected:?}"
            );
            for (got, want) in changes.iter().zip(&expected) {
                let deg = (got - want).abs() * w.to_degrees();
                assert!(
                    deg < 1e-9,
                    "phase boundary at {got} s, expected {want} s ({deg} deg off)"
                );
            }
        }
    }
}
