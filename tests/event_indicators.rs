//! The event indicators of every mechanism's Model Exchange interface (elastodynamic level),
//! through the C ABI, sampled over two turns of the shaft along the motion the FMU's own
//! Co-Simulation integration gives: at constant speed (`drive.mode` = 2), driven through the
//! inputs at the same speed, braked to a standstill, and standing still. A host samples them
//! like a fixed-step integrator with event detection (fmi2SetTime, the inputs,
//! fmi2SetContinuousStates, fmi2GetEventIndicators, fmi2CompletedIntegratorStep, an event
//! where an indicator changed sign).
//!
//! No indicator is exactly zero at two consecutive samples: one resting at zero over an interval
//! (a rigid velocity in a dwell, every speed of a shaft at a standstill) is no event indicator,
//! and a root finder such as CVODE aborts on it ("Root found at and very near t"). The rigid
//! velocity of each mechanism's driven member (whose sign gives the guide friction's direction)
//! changes sign twice per turn, at its two reversals, and never at a standstill.

mod common;

use bindery_fmu::catalog::{self, Entry};
use common::*;
use std::f64::consts::TAU;

/// Per mechanism: the index of the indicator that is the rigid velocity of its driven member,
/// and its reversals per turn: the knife's bottom and the start of its working stroke after the
/// dwell; the table's forward travel and return; the lever rising and falling over the ramp on
/// the table's forward travel and again on its return; slider 5's dead centres.
const VELOCITY: &[(&str, usize, usize)] = &[
    ("GenevaKnifeDrive", 7, 2),
    ("SewingTable", 6, 2),
    ("Perforators", 6, 4),
    ("DiscKnifeDrive", 0, 2),
];

/// `drive.phi0`, rad.
const PHI0: f64 = 0.3;

/// How the shaft turns.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Drive {
    /// `drive.mode` = constant_speed at the nominal speed.
    ConstantSpeed,
    /// `drive.mode` = input, the inputs at the nominal speed.
    Input,
    /// Input, braked uniformly from the nominal speed to a standstill at half the run.
    RunDown,
    /// Input, the shaft at rest at angle 0.
    Standstill,
}

/// The shaft inputs (phi, w, a) at `t` for a run of length `stop` at speed `w0`.
fn shaft(drive: Drive, w0: f64, stop: f64, t: f64) -> [f64; 3] {
    match drive {
        Drive::ConstantSpeed | Drive::Input => [w0 * t, w0, 0.0],
        Drive::RunDown => {
            let t_stop = 0.5 * stop;
            let a = -w0 / t_stop;
            if t < t_stop {
                [w0 * t + 0.5 * a * t * t, w0 + a * t, a]
            } else {
                [0.5 * w0 * t_stop, 0.0, 0.0]
            }
        }
        Drive::Standstill => [0.0, 0.0, 0.0],
    }
}

/// One run: the indicators at each sample and the number of steps with an event.
struct Run {
    z: Vec<Vec<f64>>,
    events: usize,
}

/// The states of the Co-Simulation run at every `h` over `stop`, and the Model Exchange
/// indicators at them.
fn run(e: &Entry, f: &Fmu, drive: Drive, w0: f64, stop: f64, h: f64) -> Run {
    let vars = (e.variables)();
    let states: Vec<u32> = vars.iter().filter_map(|(_, v)| v.derivative).collect();
    let nz = (e.info)().event_indicators as usize;
    let inputs = [
        vr_of(e, "shaft.phi"),
        vr_of(e, "shaft.w"),
        vr_of(e, "shaft.a"),
    ];
    let mode = if drive == Drive::ConstantSpeed { 2 } else { 1 };
    let set = |s: &Slave| {
        s.ok(
            s.set_integer(&[vr_of(e, "model.fidelity")], &[3]),
            "model.fidelity",
        );
        s.ok(
            s.set_integer(&[vr_of(e, "drive.mode")], &[mode]),
            "drive.mode",
        );
        // a phase at which nothing happens: no reversal or dwell boundary at the turns' ends
        s.ok(s.set_real(&[vr_of(e, "drive.phi0")], &[PHI0]), "drive.phi0");
        s.ok(s.set_real(&inputs, &shaft(drive, w0, stop, 0.0)), "inputs");
    };
    let cs = f.slave("cs");
    set(&cs);
    cs.setup_and_init(0.0, None);
    let me = f.me_instance("me");
    me.me_start(set);
    let n = (stop / h).round() as usize;
    let mut r = Run {
        z: Vec::with_capacity(n),
        events: 0,
    };
    for j in 1..=n {
        let t0 = (j - 1) as f64 * h;
        let t = j as f64 * h;
        if mode == 1 {
            cs.ok(cs.set_real(&inputs, &shaft(drive, w0, stop, t0)), "inputs");
        }
        cs.ok(
            cs.do_step(t0, h),
            &format!("{} fmi2DoStep at {t0}", e.identifier),
        );
        let (st, x) = cs.get_real(&states);
        cs.ok(st, "the states");
        me.ok(me.set_time(t), "fmi2SetTime");
        me.ok(me.set_real(&inputs, &shaft(drive, w0, stop, t)), "inputs");
        me.ok(me.set_states(&x), "fmi2SetContinuousStates");
        let (st, z) = me.get_array("fmi2GetEventIndicators", nz);
        me.ok(st, "fmi2GetEventIndicators");
        let (st, asks) = me.completed_step();
        me.ok(st, "fmi2CompletedIntegratorStep");
        let crossed = r
            .z
            .last()
            .is_some_and(|z0: &Vec<f64>| z0.iter().zip(&z).any(|(a, b)| (*a > 0.0) != (*b > 0.0)));
        if asks || crossed {
            me.event();
            r.events += 1;
        }
        r.z.push(z);
    }
    r
}

/// Sign changes (from one side of zero to the other) of indicator `i` over the samples.
fn sign_changes(z: &[Vec<f64>], i: usize) -> usize {
    z.windows(2)
        .filter(|w| (w[0][i] < 0.0 && w[1][i] > 0.0) || (w[0][i] > 0.0 && w[1][i] < 0.0))
        .count()
}

#[test]
fn no_indicator_rests_at_zero_and_the_rigid_velocity_changes_sign_at_its_reversals() {
    let mut covered = 0;
    for e in catalog::all() {
        let Some(&(_, velocity, per_turn)) = VELOCITY.iter().find(|(id, ..)| *id == e.identifier)
        else {
            continue;
        };
        let f = Fmu::of(&e);
        let w0 = (e.variables)()
            .into_iter()
            .find(|(_, v)| v.name == "drive.n")
            .and_then(|(_, v)| v.start)
            .unwrap();
        let stop = 2.0 * TAU / w0; // two turns
        let h = 1e-3 * stop / 2.0; // 1000 samples a turn
        for drive in [
            Drive::ConstantSpeed,
            Drive::Input,
            Drive::RunDown,
            Drive::Standstill,
        ] {
            let label = format!("{} {drive:?}", e.identifier);
            let r = run(&e, &f, drive, w0, stop, h);
            let nz = r.z[0].len();
            for i in 0..nz {
                if let Some(j) =
                    r.z.windows(2)
                        .position(|w| w[0][i] == 0.0 && w[1][i] == 0.0)
                {
                    panic!(
                        "{label}: event indicator {i} is exactly zero at t = {} and {}",
                        (j + 1) as f64 * h,
                        (j + 2) as f64 * h
                    );
                }
            }
            let changes = sign_changes(&r.z, velocity);
            // the second turn (samples from t = stop/2 on; the first one sets the held sign,
            // which a start inside a dwell does not know)
            let second = sign_changes(&r.z[r.z.len() / 2 - 1..], velocity);
            match drive {
                Drive::ConstantSpeed | Drive::Input => {
                    assert_eq!(second, per_turn, "{label}: indicator {velocity}");
                    assert!(
                        (2 * per_turn - 1..=2 * per_turn).contains(&changes),
                        "{label}: {changes}"
                    );
                    assert!(
                        r.events >= changes,
                        "{label}: {} steps with events",
                        r.events
                    );
                }
                // braked to rest over the first half of the run (half a turn), at rest in the
                // second half
                Drive::RunDown => {
                    assert!((1..=per_turn + 1).contains(&changes), "{label}: {changes}");
                    assert_eq!(second, 0, "{label}");
                }
                Drive::Standstill => assert_eq!(changes, 0, "{label}"),
            }
            eprintln!(
                "{label}: {} samples, {} steps with events, rigid velocity (indicator {velocity}) {changes} sign changes",
                r.z.len(),
                r.events
            );
        }
        covered += 1;
    }
    assert_eq!(covered, VELOCITY.len());
}
