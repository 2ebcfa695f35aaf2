//! `auto`: which method the next attempt takes, by what each costs and by the stiffness tests
//! (Hairer's on the explicit steps, the held Jacobian's stability check as in LSODA).

use super::*;

/// `auto`: the implicit method's cost measure is multiplied by this at every window of the
/// explicit one.
const IMPLICIT_MEASURE_AGING: f64 = 0.85;

impl Integrator {
    /// The stepper of the next attempt over `hs`. `auto` leaves the implicit method when the
    /// Jacobian it holds says the step fits the explicit stability region three checks in a
    /// row (a check every 20 steps); the explicit method decides the other way by Hairer's
    /// stiffness test and needs no Jacobian.
    pub(super) fn stepper(&mut self, n: usize, hs: f64, steps: usize, st: &mut Stats) -> Stepper {
        match self.settings.method {
            Method::Rk4 => return Stepper::Rk4,
            Method::Dopri5 => return Stepper::Dopri,
            Method::Radau5 => return Stepper::Radau,
            Method::Auto => {}
        }
        let m = &mut self.mem;
        if m.stiff && m.radau.has_jac && steps.is_multiple_of(20) && !m.rejected {
            let h_stab = 3.3 / spectral_radius(n, &m.radau.jac).max(1e-300);
            if hs < 0.5 * h_stab {
                m.nonstiff_count = m.nonstiff_count.saturating_add(1);
                if m.nonstiff_count > 2 {
                    self.switch_method(st);
                }
            } else {
                m.nonstiff_count = 0;
            }
        }
        if self.mem.stiff {
            Stepper::Radau
        } else {
            Stepper::Dopri
        }
    }

    /// `auto` weighs the two methods by what they cost: over a window of accepted steps (50
    /// explicit, 20 implicit) the work (right-hand sides, Jacobians, factorizations) per
    /// simulated second. An explicit stretch that costs twice what the implicit method did when
    /// last measured hands over to it; one that has no such measure and does not run at the
    /// largest step tries the implicit method for a window, which keeps it if it is cheaper.
    /// (The explicit method's stiffness test and the Jacobian's stability check decide besides,
    /// as in LSODA: a chain resolved by the explicit method at steps far below its stability
    /// limit, ringing at a tolerance that resolves the ringing, is not stiff by either, yet the
    /// implicit method, which filters the ringing out, is cheaper.)
    pub(super) fn weigh_methods(&mut self, t: f64, hs: f64, max_step: f64, st: &mut Stats) {
        if self.settings.method != Method::Auto {
            return;
        }
        let work = self.mem.stats.work() + st.work();
        let m = &mut self.mem;
        m.window_steps = m.window_steps.saturating_add(1);
        if m.window_steps < if m.stiff { 20 } else { 50 } {
            return;
        }
        let rate = (work - m.window_work0) / (t - m.window_t0).max(f64::MIN_POSITIVE);
        let switch = if m.stiff {
            // a window of events and small steps (a cluster of cut and contact events) costs
            // more than the method does elsewhere: the measure rises at most twofold a window
            m.rate_implicit = if m.rate_implicit > 0.0 {
                rate.min(2.0 * m.rate_implicit)
            } else {
                rate
            };
            std::mem::take(&mut m.trial) && rate > m.rate_explicit
        } else {
            m.rate_explicit = rate;
            if m.rate_implicit > 0.0 {
                // the implicit method's measure ages (its window may have been a cluster of
                // events): what costs twice an aged measure is tried against it
                m.rate_implicit *= IMPLICIT_MEASURE_AGING;
                m.trial = rate > 2.0 * m.rate_implicit;
                m.trial
            } else {
                m.trial = hs < 0.5 * max_step;
                m.trial
            }
        };
        if switch {
            self.switch_method(st);
        }
        let m = &mut self.mem;
        m.window_t0 = t;
        m.window_work0 = work;
        m.window_steps = 0;
    }

    /// `auto` changes method: counters and the implicit method's history start afresh.
    pub(super) fn switch_method(&mut self, st: &mut Stats) {
        let m = &mut self.mem;
        m.stiff = !m.stiff;
        m.stiff_count = 0;
        m.nonstiff_count = 0;
        m.window_steps = 0;
        m.radau.h_old = 0.0;
        m.radau.h_acc = 0.0;
        st.switches += 1;
    }

    /// Hairer's stiffness test on an accepted Dormand–Prince step: 15 steps with h·|λ| > 3.25
    /// (not interrupted by six without) make `auto` take the implicit method.
    pub(super) fn stiffness_test(&mut self, hlamb: f64, st: &mut Stats) {
        let m = &mut self.mem;
        if hlamb > 3.25 {
            m.nonstiff_count = 0;
            m.stiff_count = m.stiff_count.saturating_add(1);
            if m.stiff_count >= 15 {
                m.stiff_count = 0;
                if self.settings.method == Method::Auto {
                    self.switch_method(st);
                }
            }
        } else {
            m.nonstiff_count = m.nonstiff_count.saturating_add(1);
            if m.nonstiff_count >= 6 {
                m.stiff_count = 0;
            }
        }
    }
}
