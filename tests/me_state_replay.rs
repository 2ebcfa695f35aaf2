//! FMU-state replay in Model Exchange, through the C ABI: for every FMU of the catalog with a
//! Model Exchange interface, at each of its levels, a small fixed-step host (Heun on
//! fmi2GetDerivatives / fmi2SetContinuousStates / fmi2SetTime, fmi2CompletedIntegratorStep,
//! events at sign changes of the event indicators) saves the FMU state mid-run, goes on, and
//! replays from the saved state: set again on the same instance, serialized and deserialized
//! into the same instance and into a fresh one. Every output (Real, Integer, Boolean), the
//! continuous states, the event indicators and the steps with events of the replay are those of
//! the run, bit for bit, and so is the serialized state at the end. A state of one interface
//! given to an instance of the other is refused with a reason and changes nothing, or, where the
//! runtime accepts it, continues where it was taken.
//!
//! A state saved one step before an event that changes a counter or a flag replays that event
//! too: the FMU state holds the event indicators of the last event or completed step, which the
//! next event is compared with (Perforators' lacked them and counted no lift-off after such a
//! restore, found by this test).

mod common;

use bindery_fmu::catalog::{self, Entry};
use bindery_fmu::fmi2::runtime::me::EventInfo;
use bindery_fmu::fmi2::types::*;
use bindery_fmu::model::{Causality, VarType};
use common::series::row_bits;
use common::*;

type GetArr = unsafe extern "C" fn(Component, *mut Real, usize) -> Status;
type SetArr = unsafe extern "C" fn(Component, *const Real, usize) -> Status;
type SetTime = unsafe extern "C" fn(Component, Real) -> Status;
type Completed = unsafe extern "C" fn(Component, Boolean, *mut Boolean, *mut Boolean) -> Status;
type NewDiscrete = unsafe extern "C" fn(Component, *mut EventInfo) -> Status;

/// One FMU with Model Exchange at one level, and the run its host makes.
struct Case<'a> {
    e: &'a Entry,
    f: &'a Fmu,
    /// `model.fidelity` of a mechanism (None: a drive such as MainShaft, without levels).
    level: Option<i32>,
    nx: usize,
    nz: usize,
    /// The first three Real inputs: the shaft connector of a mechanism, the loads of a drive.
    inputs: [u32; 3],
    /// The mean speed of a mechanism's shaft (rad/s): its nominal one, `shaft.w`'s start, but
    /// where said in `tag`.
    w0: f64,
    /// What else sets the case apart, for the messages (empty: nothing).
    tag: &'static str,
    outs: Vec<u32>,
    /// The Integer (and Enumeration) and Boolean outputs (counters and flags such as
    /// `contact.liftoffs`, which events change).
    int_outs: Vec<u32>,
    bool_outs: Vec<u32>,
    /// The name of each column of a row: the Real, Integer and Boolean outputs, the states, the
    /// indicators, `event`.
    columns: Vec<String>,
    /// Step size and number of steps.
    h: f64,
    n: usize,
}

impl Case<'_> {
    fn label(&self) -> String {
        match self.level {
            Some(l) => format!("{} level {l}{}", self.e.identifier, self.tag),
            None => format!("{}{}", self.e.identifier, self.tag),
        }
    }

    fn time(&self, j: usize) -> f64 {
        j as f64 * self.h
    }

    /// The inputs at `t`: a mechanism's shaft turns near its nominal speed with a ripple
    /// (angle, speed and acceleration consistent); a drive's loads follow a fixed law.
    fn inputs_at(&self, t: f64) -> [f64; 3] {
        if self.level.is_some() {
            let (r, om) = (0.02, 15.0);
            [
                self.w0 * t + r * (om * t).sin(),
                self.w0 + r * om * (om * t).cos(),
                -r * om * om * (om * t).sin(),
            ]
        } else {
            [
                2.0 * t + 0.3 * (3.0 * t).sin(),
                2.0 + 0.9 * (3.0 * t).cos(),
                -2.7 * (3.0 * t).sin(),
            ]
        }
    }

    fn set_inputs(&self, s: &Slave, t: f64) {
        s.ok(
            s.set_real(&self.inputs, &self.inputs_at(t)),
            &format!("{}: fmi2SetReal inputs at t = {t}", self.label()),
        );
    }

    /// An instance of `ty` at this case's level, initialized at t = 0 with the inputs there; a
    /// Model Exchange one through its event iteration into continuous-time mode.
    fn start(&self, name: &str, ty: FmuType) -> Slave<'_> {
        let s = self.f.instance(name, ty);
        if let Some(l) = self.level {
            s.ok(
                s.set_integer(&[vr_of(self.e, "model.fidelity")], &[l]),
                "model.fidelity",
            );
        }
        s.ok(s.setup(0.0, None), "fmi2SetupExperiment");
        s.ok(
            s.call0("fmi2EnterInitializationMode"),
            "fmi2EnterInitializationMode",
        );
        self.set_inputs(&s, 0.0);
        s.ok(
            s.call0("fmi2ExitInitializationMode"),
            "fmi2ExitInitializationMode",
        );
        if ty == FmuType::ModelExchange {
            self.event_iteration(&s, 0.0);
            s.ok(
                s.call0("fmi2EnterContinuousTimeMode"),
                "fmi2EnterContinuousTimeMode",
            );
        }
        s
    }

    /// fmi2NewDiscreteStates until no new discrete states are needed (in event mode).
    fn event_iteration(&self, s: &Slave, t: f64) {
        for _ in 0..10 {
            let mut info = EventInfo::default();
            // SAFETY: the FMI function with a valid fmi2EventInfo.
            let st = unsafe { s.fmu.sym::<NewDiscrete>("fmi2NewDiscreteStates")(s.c, &mut info) };
            s.ok(
                st,
                &format!("{}: fmi2NewDiscreteStates at t = {t}", self.label()),
            );
            assert_eq!(info.terminate_simulation, FALSE, "{} t = {t}", self.label());
            if info.new_discrete_states_needed == FALSE {
                return;
            }
        }
        panic!("{}: event iteration at t = {t} does not end", self.label());
    }

    fn get(&self, s: &Slave, name: &str, n: usize) -> Vec<f64> {
        let mut x = vec![f64::NAN; n];
        if n > 0 {
            // SAFETY: the FMI function with an array of n reals.
            let st = unsafe { s.fmu.sym::<GetArr>(name)(s.c, x.as_mut_ptr(), n) };
            s.ok(st, &format!("{}: {name}", self.label()));
        }
        x
    }

    fn set_states(&self, s: &Slave, x: &[f64], t: f64) {
        // SAFETY: the FMI function with an array of nx reals.
        let st =
            unsafe { s.fmu.sym::<SetArr>("fmi2SetContinuousStates")(s.c, x.as_ptr(), x.len()) };
        s.ok(
            st,
            &format!("{}: fmi2SetContinuousStates at t = {t}", self.label()),
        );
    }

    fn set_time(&self, s: &Slave, t: f64) {
        // SAFETY: the FMI function.
        let st = unsafe { s.fmu.sym::<SetTime>("fmi2SetTime")(s.c, t) };
        s.ok(st, &format!("{}: fmi2SetTime({t})", self.label()));
    }

    /// The row at the current point: every Real output, the Integer and Boolean outputs, the
    /// states, the indicators, then `event` (1 if the step that led here had an event).
    fn row(&self, s: &Slave, event: bool) -> Vec<f64> {
        let (st, mut row) = s.get_real(&self.outs);
        s.ok(st, &format!("{}: fmi2GetReal", self.label()));
        let (st, ints) = s.get_integer(&self.int_outs);
        s.ok(st, &format!("{}: fmi2GetInteger", self.label()));
        row.extend(ints.into_iter().map(f64::from));
        let (st, bools) = s.get_boolean(&self.bool_outs);
        s.ok(st, &format!("{}: fmi2GetBoolean", self.label()));
        row.extend(bools.into_iter().map(|b| f64::from(u8::from(b))));
        row.extend(self.get(s, "fmi2GetContinuousStates", self.nx));
        row.extend(self.get(s, "fmi2GetEventIndicators", self.nz));
        row.push(f64::from(u8::from(event)));
        row
    }

    /// One Heun step from point `j` to `j + 1` in continuous-time mode; an event at its end if
    /// fmi2CompletedIntegratorStep asks for one or an indicator changed sign. The host keeps
    /// nothing between steps: the states and indicators are read from the FMU. Whether there
    /// was an event.
    fn step(&self, s: &Slave, j: usize) -> bool {
        let (t1, h) = (self.time(j + 1), self.h);
        let x0 = self.get(s, "fmi2GetContinuousStates", self.nx);
        let z0 = self.get(s, "fmi2GetEventIndicators", self.nz);
        let d0 = self.get(s, "fmi2GetDerivatives", self.nx);
        self.set_time(s, t1);
        self.set_inputs(s, t1);
        let xp: Vec<f64> = x0.iter().zip(&d0).map(|(x, d)| x + h * d).collect();
        self.set_states(s, &xp, t1);
        let d1 = self.get(s, "fmi2GetDerivatives", self.nx);
        let x1: Vec<f64> = (0..self.nx)
            .map(|i| x0[i] + 0.5 * h * (d0[i] + d1[i]))
            .collect();
        self.set_states(s, &x1, t1);
        let (mut enter, mut terminate) = (FALSE, FALSE);
        // SAFETY: the FMI function with two valid result pointers.
        let st = unsafe {
            s.fmu.sym::<Completed>("fmi2CompletedIntegratorStep")(
                s.c,
                TRUE,
                &mut enter,
                &mut terminate,
            )
        };
        s.ok(
            st,
            &format!("{}: fmi2CompletedIntegratorStep at t = {t1}", self.label()),
        );
        assert_eq!(terminate, FALSE, "{} t = {t1}", self.label());
        let z1 = self.get(s, "fmi2GetEventIndicators", self.nz);
        let crossed = z0.iter().zip(&z1).any(|(a, b)| (*a > 0.0) != (*b > 0.0));
        let event = enter == TRUE || crossed;
        if event {
            s.ok(
                s.call0("fmi2EnterEventMode"),
                &format!("{}: fmi2EnterEventMode at t = {t1}", self.label()),
            );
            self.event_iteration(s, t1);
            s.ok(
                s.call0("fmi2EnterContinuousTimeMode"),
                &format!("{}: fmi2EnterContinuousTimeMode at t = {t1}", self.label()),
            );
        }
        event
    }

    /// The rows of points `from..=to`: the row at `from` is read before the first step (with
    /// `event_at_from`, as the run had it), then one after each step.
    fn run(&self, s: &Slave, from: usize, to: usize, event_at_from: bool) -> Vec<Vec<f64>> {
        let mut rows = vec![self.row(s, event_at_from)];
        for j in from..to {
            let event = self.step(s, j);
            rows.push(self.row(s, event));
        }
        rows
    }

    /// Asserts that `replay`, the rows of points `k..`, are `reference[k..]` bit for bit; a
    /// mismatch names the case, `what`, the first point (step and time) and column that differ.
    fn assert_replays(&self, what: &str, k: usize, reference: &[Vec<f64>], replay: &[Vec<f64>]) {
        let expected = &reference[k..];
        assert_eq!(replay.len(), expected.len(), "{}: {what}", self.label());
        if row_bits(replay) == row_bits(expected) {
            return;
        }
        for (i, (a, b)) in replay.iter().zip(expected).enumerate() {
            for (c, (x, y)) in a.iter().zip(b).enumerate() {
                assert_eq!(
                    x.to_bits(),
                    y.to_bits(),
                    "{}: {what}, from step {k}: step {} (t = {}), {}: replayed {x:e}, run {y:e}",
                    self.label(),
                    k + i,
                    self.time(k + i),
                    self.columns[c]
                );
            }
        }
    }

    /// Asserts that the instance's serialized state is `expected` (the run's at its end).
    fn assert_state_is(&self, s: &Slave, what: &str, expected: &[u8]) {
        let now = s.state_bytes();
        if now != expected {
            let at = now.iter().zip(expected).position(|(a, b)| a != b);
            panic!(
                "{}: {what}: the serialized state at step {} differs from the run's ({} vs {} bytes, first difference at byte {at:?})",
                self.label(),
                self.n,
                now.len(),
                expected.len()
            );
        }
    }
}

/// The cases: every FMU with Model Exchange (continuous states), at each of its levels: a
/// mechanism's elastodynamic level (3 states, its event indicators) with small steps over about
/// a turn of its shaft, where its contacts open and close; its kinematic and kinetostatic levels
/// (no states: zeros, indicators that never change sign) with larger ones; a drive (MainShaft:
/// its own states, no indicators, no levels) as the elastodynamic level. Perforators also at
/// 130 rpm, above its lift-off speed: the roller lifts off the ramp and lands again and again
/// (events that change `contact.liftoffs` and `roller.lost_contact`).
fn cases<'a>(e: &'a Entry, f: &'a Fmu) -> Vec<Case<'a>> {
    let vars = (e.variables)();
    let nx = vars.iter().filter(|(_, v)| v.derivative.is_some()).count();
    if nx == 0 {
        return vec![];
    }
    let nz = (e.info)().event_indicators as usize;
    let ins: Vec<u32> = vars
        .iter()
        .filter(|(_, v)| v.causality == Causality::Input && v.ty == VarType::Real)
        .map(|(vr, _)| *vr)
        .take(3)
        .collect();
    let mechanism = vars.iter().any(|(_, v)| v.name == "model.fidelity");
    let w0 = if mechanism {
        vars.iter()
            .find(|(_, v)| v.name == "shaft.w")
            .and_then(|(_, v)| v.start)
            .expect("shaft.w has a start")
    } else {
        0.0
    };
    let outputs = |ty: fn(&VarType) -> bool| -> (Vec<u32>, Vec<String>) {
        vars.iter()
            .filter(|(_, v)| v.causality == Causality::Output && ty(&v.ty))
            .map(|(vr, v)| (*vr, v.name.to_string()))
            .unzip()
    };
    let (outs, mut columns) = outputs(|t| *t == VarType::Real);
    let (int_outs, names) = outputs(|t| matches!(t, VarType::Integer | VarType::Enumeration(_)));
    columns.extend(names);
    let (bool_outs, names) = outputs(|t| *t == VarType::Boolean);
    columns.extend(names);
    columns.extend((0..nx).map(|i| format!("state x[{i}]")));
    columns.extend((0..nz).map(|i| format!("event indicator z[{i}]")));
    columns.push("event".into());
    // (Heun is stable on the stiffest chain, Perforators', up to about h = 5e-5 s)
    let levels: Vec<(Option<i32>, f64, usize)> = if mechanism {
        vec![
            (Some(1), 5e-4, 600),
            (Some(2), 5e-4, 600),
            (Some(3), 5e-5, 4000),
        ]
    } else {
        vec![(None, 5e-5, 4000)]
    };
    let mut cases: Vec<Case> = levels
        .into_iter()
        .map(|(level, h, n)| Case {
            e,
            f,
            level,
            nx,
            nz,
            inputs: [ins[0], ins[1], ins[2]],
            w0,
            tag: "",
            outs: outs.clone(),
            int_outs: int_outs.clone(),
            bool_outs: bool_outs.clone(),
            columns: columns.clone(),
            h,
            n,
        })
        .collect();
    if e.identifier == "Perforators" {
        let elastic = cases.last().expect("the elastodynamic level");
        let lift_off = Case {
            w0: 130.0 * std::f64::consts::PI / 30.0,
            tag: " at 130 rpm",
            n: 2000,
            columns: elastic.columns.clone(),
            outs: elastic.outs.clone(),
            int_outs: elastic.int_outs.clone(),
            bool_outs: elastic.bool_outs.clone(),
            ..*elastic
        };
        cases.push(lift_off);
    }
    cases
}

/// Whether the step to point `i` of `rows` had an event.
fn event_at(rows: &[Vec<f64>], i: usize) -> bool {
    *rows[i].last().unwrap() != 0.0
}

/// Whether the step to point `i` changed an Integer or Boolean output (a counter or a flag).
fn discrete_change(c: &Case, rows: &[Vec<f64>], i: usize) -> bool {
    let discrete = c.outs.len()..c.outs.len() + c.int_outs.len() + c.bool_outs.len();
    rows[i][discrete.clone()] != rows[i - 1][discrete]
}

/// The points to save at of [`model_exchange_fmu_states_replay_bit_identically`]: the middle,
/// the point before the first event after it (the replay's first step has the event) and the
/// point two steps before the first event that changes an Integer or Boolean output (its
/// second step has it).
fn middle_and_events(c: &Case, reference: &[Vec<f64>]) -> Vec<usize> {
    let mut ks = vec![c.n / 2];
    ks.extend(
        (c.n / 2 + 2..=c.n)
            .find(|&i| event_at(reference, i))
            .map(|i| i - 1),
    );
    ks.extend(
        (3..=c.n)
            .find(|&i| event_at(reference, i) && discrete_change(c, reference, i))
            .map(|i| i - 2),
    );
    ks
}

/// Checks 1 and 2 for one case: a reference run of a first instance; a second instance makes
/// the same run, saving its state (fmi2GetFMUstate and fmi2SerializeFMUstate) at the points
/// `save_at` chooses from the reference; from each saved state the rest of the run is
/// replayed: the state set again on the same instance; serialized, freed, deserialized and set
/// on the same instance; and on a fresh instance. The number of steps with events and the
/// points saved at.
fn assert_me_replays(
    c: &Case,
    save_at: fn(&Case, &[Vec<f64>]) -> Vec<usize>,
) -> (usize, Vec<usize>) {
    let probe = c.start("reference", FmuType::ModelExchange);
    let reference = c.run(&probe, 0, c.n, false);
    drop(probe);
    let events = (1..=c.n).filter(|&i| event_at(&reference, i)).count();
    let mut ks = save_at(c, &reference);
    ks.sort_unstable();
    ks.dedup();
    if ks.is_empty() {
        return (events, ks);
    }
    let s = c.start("run", FmuType::ModelExchange);
    let mut rows = Vec::with_capacity(c.n + 1);
    let mut saved = Vec::new();
    let mut from = 0;
    for &k in &ks {
        let part = c.run(&s, from, k, event_at(&reference, from));
        rows.extend(part.into_iter().skip(usize::from(from > 0)));
        let (state, bytes) = s.save_state();
        saved.push((k, state, bytes));
        from = k;
    }
    let part = c.run(&s, from, c.n, event_at(&reference, from));
    rows.extend(part.into_iter().skip(usize::from(from > 0)));
    c.assert_replays(
        "the run that saved states vs. another instance's run",
        0,
        &reference,
        &rows,
    );
    let end = s.state_bytes();
    for (k, mut state, bytes) in saved {
        let ev = event_at(&reference, k);
        // 1. the saved state set again on the same instance
        s.ok(s.set_state(state), "fmi2SetFMUstate");
        let replay = c.run(&s, k, c.n, ev);
        c.assert_replays("fmi2SetFMUstate", k, &reference, &replay);
        c.assert_state_is(&s, "fmi2SetFMUstate", &end);
        // 2. serialized, freed, deserialized: into the same instance ...
        let (st, again) = s.serialize(state);
        s.ok(st, "fmi2SerializeFMUstate");
        assert!(
            again == bytes,
            "{}: the state saved at step {k} serializes differently after it was used",
            c.label()
        );
        s.ok(s.free_state(&mut state), "fmi2FreeFMUstate");
        assert!(state.is_null(), "a freed state is NULL");
        let mut copy = s.deserialized(&bytes);
        s.ok(s.set_state(copy), "fmi2SetFMUstate");
        // (freed before the replay: the instance holds its own copy)
        s.ok(s.free_state(&mut copy), "fmi2FreeFMUstate");
        let replay = c.run(&s, k, c.n, ev);
        c.assert_replays(
            "deserialized into the same instance",
            k,
            &reference,
            &replay,
        );
        c.assert_state_is(&s, "deserialized into the same instance", &end);
        // ... and into a fresh instance, instantiated and initialized as the run's
        let fresh = c.start("fresh", FmuType::ModelExchange);
        fresh.restore_bytes(&bytes);
        let replay = c.run(&fresh, k, c.n, ev);
        c.assert_replays("deserialized into a fresh instance", k, &reference, &replay);
        c.assert_state_is(&fresh, "deserialized into a fresh instance", &end);
    }
    (events, ks)
}

/// Checks 1 and 2 for every FMU with Model Exchange, at each level: a replay from a saved FMU
/// state, set again, or serialized and deserialized into the same or a fresh instance, is the
/// run bit for bit (every output, the states, the indicators and where the events are).
#[test]
fn model_exchange_fmu_states_replay_bit_identically() {
    let mut covered = Vec::new();
    for e in catalog::all() {
        let f = Fmu::of(&e);
        for c in cases(&e, &f) {
            let t = std::time::Instant::now();
            let (events, ks) = assert_me_replays(&c, middle_and_events);
            eprintln!(
                "{}: {} steps of {} s, {events} steps with events, saved at {ks:?}, {:.0?}",
                c.label(),
                c.n,
                c.h,
                t.elapsed()
            );
            // the elastodynamic level's contacts open and close, or its phases change, in the
            // run (the replays go through events; SewingTable's third of a turn has one, the end
            // of the forward travel: its start on a cyclogram boundary, where the indicators
            // hold their signs, is none)
            if c.level == Some(3) {
                assert!(events >= 1, "{}: {events} events", c.label());
            }
            covered.push(c.label());
        }
    }
    // every FMU has Model Exchange
    assert_eq!(covered.len(), 4 * 3 + 1 + 1, "{covered:?}");
}

/// Co-Simulation steps of `c.h` from point `from` to `to`, the inputs set before each: the
/// Real outputs at `to`.
fn cs_run(c: &Case, s: &Slave, from: usize, to: usize) -> Vec<f64> {
    for j in from..to {
        c.set_inputs(s, c.time(j));
        s.ok(
            s.do_step(c.time(j), c.h),
            &format!("{}: fmi2DoStep at t = {}", c.label(), c.time(j)),
        );
    }
    let (st, y) = s.get_real(&c.outs);
    s.ok(st, "fmi2GetReal");
    y
}

/// Asserts that two output rows are equal bit for bit, naming the first output that differs.
fn assert_same_outputs(c: &Case, what: &str, a: &[f64], b: &[f64]) {
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert_eq!(
            x.to_bits(),
            y.to_bits(),
            "{}: {what}: {}: {x:e} vs {y:e}",
            c.label(),
            c.columns[i]
        );
    }
}

/// Check 3 for one case, the state saved at point `k`:
/// - a Model Exchange state saved in continuous-time mode, given to a Co-Simulation instance,
///   is refused (fmi2Error, a logged reason) and changes nothing: the instance steps on as its
///   twin that was never given it;
/// - one saved in event mode is accepted (it is the runtime's StepComplete state): the
///   Co-Simulation instance then has the Model Exchange instance's outputs and time, and steps
///   on from there;
/// - a Co-Simulation state given to a Model Exchange instance is accepted into event mode
///   (continuous-time calls refused until fmi2EnterContinuousTimeMode), with the
///   Co-Simulation instance's outputs, and the host integrates on from there.
fn assert_states_cross_interfaces(c: &Case, k: usize) {
    let me = c.start("me", FmuType::ModelExchange);
    let me_rows = c.run(&me, 0, k, false);
    let me_outs = &me_rows[k][..c.outs.len()];
    let ct_bytes = me.state_bytes();
    // refused: continuous-time mode
    let cs = c.start("cs", FmuType::CoSimulation);
    let twin = c.start("twin", FmuType::CoSimulation);
    let (a, b) = (cs_run(c, &cs, 0, 10), cs_run(c, &twin, 0, 10));
    assert_same_outputs(c, "twin Co-Simulation instances", &a, &b);
    let before = cs.state_bytes();
    let mut st = cs.deserialized(&ct_bytes);
    let set = cs.set_state(st);
    cs.assert_refused(
        set,
        "continuous-time mode",
        &format!(
            "{}: a Model Exchange state in continuous-time mode set on a Co-Simulation instance",
            c.label()
        ),
    );
    cs.ok(cs.free_state(&mut st), "fmi2FreeFMUstate");
    assert!(
        cs.state_bytes() == before,
        "{}: the refused state changed the Co-Simulation instance",
        c.label()
    );
    let (a, b) = (cs_run(c, &cs, 10, 20), cs_run(c, &twin, 10, 20));
    assert_same_outputs(c, "after the refused state vs. its twin", &a, &b);
    // accepted: event mode
    me.ok(me.call0("fmi2EnterEventMode"), "fmi2EnterEventMode");
    let ev_bytes = me.state_bytes();
    cs.restore_bytes(&ev_bytes);
    let (st, y) = cs.get_real(&c.outs);
    cs.ok(st, "fmi2GetReal");
    assert_same_outputs(
        c,
        "Co-Simulation instance set to a Model Exchange state in event mode",
        &y,
        me_outs,
    );
    let y = cs_run(c, &cs, k, k + 10);
    assert!(
        y.iter().all(|x| x.is_finite()),
        "{}: Co-Simulation from a Model Exchange state: {y:?}",
        c.label()
    );
    // a Co-Simulation state on the Model Exchange instance (in continuous-time mode again)
    me.ok(
        me.call0("fmi2EnterContinuousTimeMode"),
        "fmi2EnterContinuousTimeMode",
    );
    let cs_bytes = twin.state_bytes();
    let (st, cs_outs) = twin.get_real(&c.outs);
    twin.ok(st, "fmi2GetReal");
    me.restore_bytes(&cs_bytes);
    let (st, y) = me.get_real(&c.outs);
    me.ok(st, "fmi2GetReal");
    assert_same_outputs(
        c,
        "Model Exchange instance set to a Co-Simulation state",
        &y,
        &cs_outs,
    );
    let x = c.get(&me, "fmi2GetContinuousStates", c.nx);
    // SAFETY: the FMI function with an array of nx reals.
    let set = unsafe { me.fmu.sym::<SetArr>("fmi2SetContinuousStates")(me.c, x.as_ptr(), c.nx) };
    me.assert_refused(
        set,
        "fmi2SetContinuousStates",
        &format!(
            "{}: a Model Exchange instance set to a Co-Simulation state is in event mode",
            c.label()
        ),
    );
    c.event_iteration(&me, c.time(20));
    me.ok(
        me.call0("fmi2EnterContinuousTimeMode"),
        "fmi2EnterContinuousTimeMode",
    );
    let rows = c.run(&me, 20, 40, false);
    assert!(
        rows.iter().flatten().all(|x| x.is_finite()),
        "{}: Model Exchange from a Co-Simulation state",
        c.label()
    );
}

/// Check 3 for every FMU with Model Exchange, at each level: FMU states between the two
/// interfaces (see [`assert_states_cross_interfaces`]).
#[test]
fn fmu_states_between_model_exchange_and_co_simulation() {
    for e in catalog::all() {
        let f = Fmu::of(&e);
        for c in cases(&e, &f) {
            assert_states_cross_interfaces(&c, 50);
        }
    }
}

/// The point before each event that changes an Integer or Boolean output, for every case: the
/// first step of the replay has the event.
fn before_discrete_events(c: &Case, reference: &[Vec<f64>]) -> Vec<usize> {
    (2..=c.n)
        .filter(|&i| event_at(reference, i) && discrete_change(c, reference, i))
        .map(|i| i - 1)
        .take(3)
        .collect()
}

/// A state saved in continuous-time mode one step before an event that changes a counter or a
/// flag: the replay's first step (fmi2CompletedIntegratorStep, then the event) must make the
/// same transition as the run.
#[test]
fn model_exchange_replay_from_just_before_a_discrete_event() {
    // every case runs (the panics of those that fail are printed); then the list of them
    let mut failed = Vec::new();
    for e in catalog::all() {
        let f = Fmu::of(&e);
        for c in cases(&e, &f) {
            let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                assert_me_replays(&c, before_discrete_events)
            }));
            match run {
                Ok((_, ks)) => eprintln!("{}: saved at {ks:?}: replayed", c.label()),
                Err(_) => failed.push(c.label()),
            }
        }
    }
    assert!(failed.is_empty(), "failed: {failed:?}");
}
