//! The elastodynamic level of the Perforators: the lever on the ramp through the unilateral
//! contact as a compliant chain ([`ChainModel`]), what it tracks between steps and its reports.

use super::*;

/// The lever on the ramp through the unilateral contact: the constants of the elastodynamic
/// level.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct LeverChain {
    pub(super) contact: Contact,
    /// The lever angles the linkage works in.
    pub(super) range: (f64, f64),
}

crate::chain_memory! {
    /// What the elastodynamic level tracks between steps.
    #[derive(Clone, Debug, PartialEq)]
    pub(super) struct LeverMemory {
        pub(super) track: Track,
        /// Whether the roller lifted off during the last step.
        pub(super) lost: Lost,
        /// The lift-offs of the turn, reported once per turn: `[0, phi, t, w]` of the first
        /// (absolute shaft angle, time, speed).
        pub(super) liftoff: TurnDigest<4>,
    }
}

/// One number ([`Lost::save`]).
impl Saved for Lost {
    const LEN: usize = 1;
    fn save(&self, out: &mut Vec<f64>) {
        out.push(Lost::save(self));
    }
    fn restore(s: &[f64]) -> Result<Lost, String> {
        match s[0] {
            x if (0.0..16.0).contains(&x) && x.fract() == 0.0 => Ok(Lost::restore(x)),
            x => Err(format!(
                "lift-off flags = {x}, not a whole number from 0 to 15"
            )),
        }
    }
}

/// A digest whose numbers do not restore (a host's damage) refuses the FMU state.
impl<const N: usize> Saved for TurnDigest<N> {
    const LEN: usize = TurnDigest::<N>::LEN;
    fn save(&self, out: &mut Vec<f64>) {
        TurnDigest::save(self, out);
    }
    fn restore(s: &[f64]) -> Result<Self, String> {
        TurnDigest::restore(s)
    }
}

/// The warning of a turn's lift-offs at the elastodynamic level.
pub(super) fn bounce_report(d: &Drive, g: &TurnDigest<4>, total: f64) -> String {
    let [_, phi, t, w] = g.worst;
    format!(
        "roller lifts off the ramp {} in the shaft turn {} (elastodynamic level; {total} lift-offs so far), the first at shaft angle {:.2} deg ({:.2} deg into the turn) at t = {t:.6} s, {:.1} rpm: spring.M0 = {} N.m, spring.kt = {} N.m/rad cannot hold it on at this speed (contact.F_impact: the force of the landings)",
        times(g.count),
        g.turn,
        phi.to_degrees(),
        crate::mechanics::wrap_angle(phi - d.cyc.phi0).to_degrees(),
        w * 30.0 / std::f64::consts::PI,
        d.p.spring_m0,
        d.p.spring_kt
    )
}

/// Whether the roller lifted off during the last step (`roller.lost_contact` of the
/// elastodynamic level): the last communication step in Co-Simulation; in Model Exchange the
/// span between the host's last two completed integrator steps, where a step that ends at an
/// event does not end the span (a host stops its integration at the event, as a Co-Simulation
/// step locates it inside and runs on).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Lost {
    /// Reported: a lift-off during the last step.
    pub(super) step: bool,
    /// Model Exchange: a lift-off during the span running since.
    pub(super) pending: bool,
    /// Model Exchange: the last call was a completed step, and `step` before it (an event now
    /// continues the span that step ended).
    pub(super) just_completed: bool,
    pub(super) before: bool,
}

impl Lost {
    /// A Co-Simulation step, in which the roller `lifted` off or not.
    pub(super) fn co_simulation_step(&mut self, lifted: bool) {
        *self = Lost {
            step: lifted,
            ..Lost::default()
        };
    }
    /// Model Exchange: the host completed an integrator step.
    pub(super) fn completed(&mut self) {
        self.before = self.step;
        self.step = std::mem::take(&mut self.pending);
        self.just_completed = true;
    }
    /// Model Exchange: an event, at which the roller `lifted` off or not.
    pub(super) fn event(&mut self, lifted: bool) {
        if std::mem::take(&mut self.just_completed) {
            self.pending = self.step;
            self.step = self.before;
        }
        self.pending |= lifted;
    }
    /// The flags as one number of the FMU state (a state saved before Model Exchange tracked
    /// them holds `step` as 0 or 1).
    pub(super) fn save(&self) -> f64 {
        f64::from(
            u8::from(self.step)
                | u8::from(self.pending) << 1
                | u8::from(self.just_completed) << 2
                | u8::from(self.before) << 3,
        )
    }
    pub(super) fn restore(x: f64) -> Lost {
        let b = x as u8;
        Lost {
            step: b & 1 != 0,
            pending: b & 2 != 0,
            just_completed: b & 4 != 0,
            before: b & 8 != 0,
        }
    }
}

/// What the elastodynamic level carries between steps: `y = [q, q̇, W]`, q the lever's
/// deflection from its rigid rotation. Model Exchange: `g_prev` holds the event indicators just
/// after the last event (or at the start), the contact mode the host's integration is in; they
/// travel with the FMU state (`SAVED_INDICATORS`), so that an event right after a restore
/// (a lift-off, a landing) is counted as in the run.
pub(super) type Dynamic = Chain<LeverChain>;

impl ChainModel for LeverChain {
    type Var = V;
    type Physics = Drive;
    type Memory = LeverMemory;
    type Ode<'a> = LeverOde<'a>;
    const SAVED_INDICATORS: usize = <Perforators as Dynamics<V>>::EVENT_INDICATORS;

    fn ode<'a>(
        &self,
        d: &'a Drive,
        path: ShaftPath,
        _: &Values<V>,
        m: &LeverMemory,
    ) -> LeverOde<'a> {
        LeverOde {
            d,
            contact: self.contact,
            path,
            track: Cell::new(m.track),
            range: self.range,
            out_of_range: Cell::new(f64::NAN),
            rigid: Default::default(),
            last: Default::default(),
        }
    }
    fn start(_: &LeverOde, path: &ShaftPath, m: &mut LeverMemory) {
        m.track = Track::new(path.cycle(path.t0));
        m.lost = Lost::default();
        m.liftoff = TurnDigest::default();
    }
    fn absorb(ode: &LeverOde, m: &mut LeverMemory) {
        m.track = ode.track.get();
    }

    /// Whether the roller lifted off in the step; the turn's lift-offs are counted and
    /// reported once the turn is over ([`bounce_report`]).
    fn after_step(
        &self,
        ode: &LeverOde,
        m: &mut LeverMemory,
        time: f64,
        h: f64,
        log: &mut dyn Log,
    ) {
        let drive = ode.d;
        let tr = ode.track.get();
        let new = tr.liftoffs - m.track.liftoffs;
        m.lost.co_simulation_step(new > 0.0);
        let report = |g: &TurnDigest<4>| bounce_report(drive, g, tr.liftoffs);
        let turn_of = |phi: f64| ((phi - drive.cyc.phi0) / TAU).floor();
        if new > 0.0 {
            let (_, w, _) = ode.path.at(time + h);
            let phi = tr.lift_phi;
            m.liftoff
                .note(turn_of(phi), [0.0, phi, time, w], log, &report);
            m.liftoff.count += new - 1.0;
        }
        m.liftoff
            .at_turn(turn_of(ode.path.absolute_phi(time + h)), log, &report);
    }

    /// A lever thrown out of the linkage's range is named.
    fn step_failed(&self, ode: &LeverOde, _: &[f64; 3], why: String) -> String {
        let g = ode.out_of_range.get();
        if g.is_nan() {
            why
        } else {
            format!(
                "{why}: the lever reached {:.1} deg, outside the {:.1} .. {:.1} deg where the rod holds the carriage: at {:.0} rpm the roller is thrown that far off the ramp; lower the speed or stiffen spring.M0, spring.kt",
                g.to_degrees(),
                self.range.0.to_degrees(),
                self.range.1.to_degrees(),
                ode.path.w * 30.0 / std::f64::consts::PI
            )
        }
    }

    /// The host stops at the root, where the crossing indicator is zero to its tolerance with
    /// either sign: the mode after the event is that of the state an instant later (an Euler
    /// step of 1 ns along the right-hand side). A lift-off is logged.
    fn me_event(
        &self,
        ode: &LeverOde,
        time: f64,
        y: &[f64; 3],
        g_prev: &mut Vec<f64>,
        _m: &LeverMemory,
        _log: &mut dyn Log,
    ) {
        let dt = 1e-9 * time.abs().max(1.0);
        let mut dy = [0.0; 3];
        ode.rhs(time, y, &mut dy);
        let y_after: Vec<f64> = y.iter().zip(&dy).map(|(y, f)| y + dt * f).collect();
        let mut g = vec![0.0; N_EVENTS];
        ode.events_held(time + dt, &y_after, g_prev, &mut g);
        if g_prev.len() == g.len() {
            ode.on_event_held(time, y, g_prev, &g);
        }
        *g_prev = g;
    }

    /// The contact mode changes at events only (a host completes its step at the root, before
    /// the event): the indicators of the mode are kept from the last event.
    fn me_completed_step(&self, ode: &LeverOde, time: f64, y: &[f64; 3], g_prev: &mut Vec<f64>) {
        ode.on_step(time, y);
        if g_prev.is_empty() {
            let mut g = vec![0.0; N_EVENTS];
            ode.events_held(time, y, g_prev, &mut g);
            *g_prev = g;
        }
    }
}
