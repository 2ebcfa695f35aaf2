//! The watch of a unilateral contact at the kinetostatic level (a roller held on a ramp or cam
//! by a spring): over each step, the contact force along the shaft's path, sampled at most 0.25°
//! of shaft angle apart, the shaft extrapolated from its state at the step's start
//! (`φ + ω·τ + ε·τ²/2`, as the step moves it). It keeps the smallest force of the current and of
//! the last completed shaft turn (`roller.F_margin`) and whether the contact would have had to
//! pull during the last step (`roller.lost_contact`); the lift-offs of a turn are warned once
//! per turn ([`TurnDigest`]). In Co-Simulation each communication step is watched, in Model
//! Exchange the span since the last completed integrator step: the same samples for the same
//! steps, so the outputs mean the same in both interfaces.

use crate::digest::TurnDigest;
use crate::mechanics::Scalar;
use crate::model::Log;
use crate::model::saved::Rule;
use crate::model::shaft::ShaftState;
use std::f64::consts::TAU;

/// What a mechanism tells the watch.
pub trait WatchedContact {
    /// The contact force at shaft angle `phi`, speed `w`, acceleration `a`: negative where the
    /// contact would have to pull.
    fn contact_force(&self, phi: f64, w: f64, a: f64) -> f64;
    /// The shaft angle where a turn starts.
    fn turn_start(&self) -> f64;
    /// The warning of a turn's lift-offs: `g.worst = [pull, phi, t, w]` of the worst sample
    /// (the force the contact would have to pull with, N; absolute shaft angle; time; speed).
    fn liftoff_report(&self, g: &TurnDigest<4>) -> String;
}

/// "once", "3 times".
pub fn times(n: f64) -> String {
    if n == 1.0 {
        "once".into()
    } else {
        format!("{n} times")
    }
}

/// Per-turn state of the watch, advanced by [`ContactWatch::watch`] over each step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactWatch {
    /// Index of the shaft turn being sampled (NaN before the first step).
    pub cycle: f64,
    /// Smallest contact force in that turn so far.
    pub cur_min: f64,
    /// Smallest contact force of the last completed turn (+inf if none).
    pub last_min: f64,
    /// A negative contact force during the last step.
    pub lost_step: bool,
    /// The last sample was negative (to count the onset once).
    pub prev_negative: bool,
    /// The lift-offs of the turn: `[pull, phi, t, w]` of the worst sample, reported once per
    /// turn.
    pub liftoff: TurnDigest<4>,
    /// Model Exchange: the time of the last completed integrator step (NaN: none yet) and the
    /// shaft there, where the next completed step's span starts.
    pub me_t: f64,
    pub me_shaft: ShaftState,
}

impl Default for ContactWatch {
    fn default() -> Self {
        Self {
            cycle: f64::NAN,
            cur_min: f64::INFINITY,
            last_min: f64::INFINITY,
            lost_step: false,
            prev_negative: false,
            me_t: f64::NAN,
            me_shaft: ShaftState {
                phi: f64::NAN,
                w: f64::NAN,
                a: f64::NAN,
            },
            liftoff: TurnDigest::default(),
        }
    }
}

impl ContactWatch {
    /// Numbers of [`ContactWatch::save`] (5 before Model Exchange watched its steps, 9 before
    /// the lift-offs were reported once per turn: still restored).
    pub const LEN: usize = 9 + TurnDigest::<4>::LEN;

    /// Watches the contact force along the shaft's path from `st` at `t0` over `h` (`h = 0`: the
    /// one point): samples at most 0.25° of shaft angle apart, the turn minima, a negative force
    /// (`lost_step`, the onset logged with the angle).
    pub fn watch<C: WatchedContact>(
        &mut self,
        c: &C,
        st: ShaftState,
        t0: f64,
        h: f64,
        log: &mut dyn Log,
    ) {
        let dphi = (st.w * h).abs() + 0.5 * (st.a * h * h).abs();
        let n = ((dphi / 0.25f64.to_radians()).ceil() as usize).clamp(1, 4000);
        let s = self;
        s.lost_step = false;
        for j in 0..=n {
            let tau = h * j as f64 / n as f64;
            let phi = st.phi + st.w * tau + 0.5 * st.a * tau * tau;
            let w = st.w + st.a * tau;
            let f = c.contact_force(phi, w, st.a);
            let cycle = ((phi - c.turn_start()) / TAU).floor();
            let report = |g: &TurnDigest<4>| c.liftoff_report(g);
            if s.cycle.is_nan() {
                s.cycle = cycle;
            } else if cycle != s.cycle {
                s.last_min = s.cur_min;
                s.cur_min = f64::INFINITY;
                s.cycle = cycle;
            }
            s.liftoff.at_turn(cycle, log, &report);
            s.cur_min = s.cur_min.min(f);
            let negative = f < 0.0;
            if negative {
                s.lost_step = true;
                let data = [-f, phi, t0 + tau, w];
                if s.prev_negative {
                    s.liftoff.worsen(data);
                } else {
                    s.liftoff.note(cycle, data, log, &report);
                }
            }
            s.prev_negative = negative;
        }
    }

    /// Model Exchange, at a completed integrator step at `time` with the shaft `now`: the span
    /// since the last one watched as a Co-Simulation step over it would be (the first: the
    /// point alone), and `now` kept as the next span's start.
    pub fn me_watch<C: WatchedContact>(
        &mut self,
        c: &C,
        now: ShaftState,
        time: f64,
        log: &mut dyn Log,
    ) {
        if self.me_t.is_nan() {
            self.watch(c, now, time, 0.0, log);
        } else if time > self.me_t {
            let (t0, st) = (self.me_t, self.me_shaft);
            self.watch(c, st, t0, time - t0, log);
        }
        self.me_t = time;
        self.me_shaft = now;
    }

    /// `roller.F_margin` with the force `f` now: the last completed turn's smallest force, or
    /// during the first turn the smallest so far and now.
    ///
    /// Any [`Scalar`]: for dual numbers the derivative of that formula, 0 where the value is
    /// a past one, the force's where it is the force now (also where it equals the smallest
    /// so far).
    pub fn margin<T: Scalar>(&self, f: T) -> T {
        if self.last_min.is_finite() {
            T::from(self.last_min)
        } else if T::NDERIV == 0 {
            T::from(self.cur_min.min(f.re()))
        } else if self.cur_min.is_nan() || f.re() <= self.cur_min {
            f
        } else {
            T::from(self.cur_min)
        }
    }

    /// The numbers of the FMU state.
    pub fn save(&self) -> Vec<f64> {
        let mut out = vec![
            self.cycle,
            self.cur_min,
            self.last_min,
            self.lost_step as u8 as f64,
            self.prev_negative as u8 as f64,
            self.me_t,
            self.me_shaft.phi,
            self.me_shaft.w,
            self.me_shaft.a,
        ];
        self.liftoff.save(&mut out);
        out
    }

    /// From [`ContactWatch::save`]'s numbers (none: a fresh watch); `model` names the FMU in
    /// the error.
    pub fn restore(state: &[f64], model: &str) -> Result<ContactWatch, String> {
        match *state {
            [] => Ok(ContactWatch::default()),
            [cycle, cur_min, last_min, lost, prev, ref me @ ..]
                if me.is_empty() || me.len() == 4 || me.len() == 4 + TurnDigest::<4>::LEN =>
            {
                // every number as the watch can hold it (a host may alter a state)
                let refused = |e: String| format!("{model} state refused: {e}");
                let flag = |what: &str, x: f64| match x {
                    0.0 => Ok(false),
                    1.0 => Ok(true),
                    _ => Err(refused(format!("{what} = {x:?}, not 0 or 1"))),
                };
                let min = |what, x| Rule::OrInf.check(what, x).map_err(refused);
                let mut s = ContactWatch {
                    cycle: Rule::WholeOrNan.check("turn", cycle).map_err(refused)?,
                    cur_min: min("turn minimum", cur_min)?,
                    last_min: min("last turn minimum", last_min)?,
                    lost_step: flag("lost contact", lost)?,
                    prev_negative: flag("negative force", prev)?,
                    ..ContactWatch::default()
                };
                if let [t, phi, w, a, ..] = *me {
                    let or_nan = |what, x| Rule::OrNan.check(what, x).map_err(refused);
                    s.me_t = or_nan("last completed step", t)?;
                    s.me_shaft = ShaftState {
                        phi: or_nan("shaft angle there", phi)?,
                        w: or_nan("shaft speed there", w)?,
                        a: or_nan("shaft acceleration there", a)?,
                    };
                }
                if me.len() > 4 {
                    s.liftoff = TurnDigest::restore(&me[4..]).map_err(refused)?;
                }
                Ok(s)
            }
            _ => Err(format!(
                "{model} state has {} values, expected {} (or 5, 9)",
                state.len(),
                Self::LEN
            )),
        }
    }
}
