//! FMI 2.0 conformance and robustness of every FMU of the catalog, through the C ABI (issue 7),
//! one concern a file:
//! - `matrix`: the call-sequence matrices, every function in every reachable state of the
//!   Co-Simulation and the Model Exchange state machine. A matrix is a table of rows (FMI
//!   function, [`Call`], how to call it with valid arguments) crossed with the states; the
//!   expected outcome comes from the runtime's own table (`fmi2::state::allowed`).
//! - `arguments`: bad arguments; `values`: bad values and FMU states;
//! - `lifecycle`: input derivatives, FMU-state and reset replay, parallel instances,
//!   instantiate/free cycles, freed and foreign handles.
//!
//! This file holds what they share: the catalog's variables, and the ways to drive an instance
//! into each state ([`STATES`] by [`drive_to`], [`MeState`]s by [`drive_me_to`]).

mod arguments;
#[path = "../common/mod.rs"]
mod common;
mod lifecycle;
mod matrix;
mod values;

use bindery_fmu::catalog::{self, Entry};
use bindery_fmu::fmi2::runtime::me::EventInfo;
use bindery_fmu::fmi2::state::{Call, ME_STATES, MeState, State, allowed, me_allowed};
use bindery_fmu::fmi2::types::*;
use bindery_fmu::model::{Causality, Var, VarType, Variability};
use common::series::bits;
use common::*;
use libloading::Symbol;
use std::ffi::{c_char, c_int};

/// The leak test measures the process's memory: it runs alone (write lock) while the other
/// tests of this binary, which allocate (and log) a lot, share the read lock.
static ALONE: std::sync::RwLock<()> = std::sync::RwLock::new(());

fn shared() -> std::sync::RwLockReadGuard<'static, ()> {
    ALONE.read().unwrap_or_else(|e| e.into_inner())
}

fn vars(e: &Entry) -> Vec<(u32, &'static Var)> {
    (e.variables)()
}

fn first(e: &Entry, pred: impl Fn(&Var) -> bool) -> Option<u32> {
    vars(e).into_iter().find(|(_, v)| pred(v)).map(|(vr, _)| vr)
}

/// The first three Real inputs: `shaft.phi`, `shaft.w`, `shaft.a` of a mechanism; the loads
/// `load.tau`, `load1.J_red`, `load1.tau0` of a drive (MainShaft).
fn drive_inputs(e: &Entry) -> [u32; 3] {
    let ins: Vec<u32> = vars(e)
        .into_iter()
        .filter(|(_, v)| v.causality == Causality::Input && v.ty == VarType::Real)
        .map(|(vr, _)| vr)
        .take(3)
        .collect();
    [ins[0], ins[1], ins[2]]
}

/// A mechanism, driven through the shaft connector (not the drive that turns it).
fn is_mechanism(e: &Entry) -> bool {
    first(e, |v| {
        v.name == "shaft.phi" && v.causality == Causality::Input
    })
    .is_some()
}

/// A tampered serialized FMU state is refused: it either does not deserialize, or setting it
/// is an Error whose message contains `why` (and the state is freed). The caller checks that
/// the instance is unchanged.
fn refuse_tampered(s: &Slave, bytes: &[u8], why: &str, case: &str) {
    let mut bad: FMUstate = std::ptr::null_mut();
    if s.deserialize(bytes, &mut bad) == Status::Ok {
        assert_eq!(s.set_state(bad), Status::Error, "{case}: accepted");
        assert_eq!(s.free_state(&mut bad), Status::Ok);
    }
    assert!(s.last_error().contains(why), "{case}: {}", s.last_error());
}

/// Every state of the co-simulation state machine that a bindery FMU can be in.
const STATES: [State; 6] = REACHABLE_STATES;

/// The serialized state of `probe`, an initialized instance, with its state code replaced:
/// how a host gets an instance into StepFailed or Error without a failing model (the runtime
/// restores the state a saved FMU state was taken in).
fn bytes_in_state(probe: &Slave, state: State) -> Vec<u8> {
    let mut bytes = probe.state_bytes();
    assert_eq!(
        u16::from_le_bytes([bytes[24], bytes[25]]),
        State::StepComplete.code()
    );
    bytes[24..26].copy_from_slice(&state.code().to_le_bytes());
    bytes
}

/// Drives a fresh instance into `state` by legal calls.
fn drive_to(s: &Slave, state: State) {
    let ok = |st: Status, what: &str| s.ok(st, what);
    match state {
        State::Instantiated => {}
        State::InitializationMode => ok(s.call0("fmi2EnterInitializationMode"), "enter"),
        State::StepComplete => ok(s.init(), "init"),
        State::Terminated => {
            ok(s.init(), "init");
            ok(s.call0("fmi2Terminate"), "terminate");
        }
        State::StepFailed | State::Error => {
            s.restore_bytes(&bytes_in_state(&s.fmu.initialized("probe"), state))
        }
        other => panic!("no way to reach {other:?}"),
    }
}

/// The FMU's number of event indicators.
fn n_indicators(e: &Entry) -> usize {
    (e.info)().event_indicators as usize
}

/// Drives a fresh Model Exchange instance into `state` by legal calls.
fn drive_me_to(s: &Slave, state: MeState) {
    let ok = |st: Status, what: &str| s.ok(st, what);
    match state {
        MeState::Instantiated => {}
        MeState::InitializationMode => ok(s.call0("fmi2EnterInitializationMode"), "enter"),
        MeState::EventMode => ok(s.init(), "init"),
        MeState::ContinuousTimeMode => {
            ok(s.init(), "init");
            ok(
                s.call0("fmi2EnterContinuousTimeMode"),
                "continuous-time mode",
            );
        }
        MeState::Terminated => {
            ok(s.init(), "init");
            ok(s.call0("fmi2Terminate"), "terminate");
        }
        MeState::Error => {
            // as for Co-Simulation: a saved state with the state code replaced
            let probe = s.fmu.me_instance("probe");
            probe.ok(probe.init(), "probe init");
            s.restore_bytes(&bytes_in_state(&probe, State::Error));
        }
    }
}
