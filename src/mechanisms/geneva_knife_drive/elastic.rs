//! Elastodynamic level of the Geneva knife drive (`dynamics.md`): the knife slider (mass
//! m_s = knife.m + rod.m/2) is tied to its rigid position s_kin(φ) by the drive chain's
//! stiffness k and damping c = 2·ζ·√(k·m_s):
//!
//! `m_s·ẍ = k·(s_kin − x) + c·(ṡ_kin − ẋ) + m_s·g − F_cut(x, ẋ) − F_friction`,
//!
//! with the guide friction `μ·|F_el·tan ν|` (the chain force's lateral component through the rod
//! at the rigid rod angle ν), directed against the rigid velocity ṡ_kin (assumption: the
//! knife's own vibration does not reverse the sliding direction in the guides; it keeps the
//! friction free of chattering), and the cutting force of the kinetostatic level evaluated at
//! the elastic position and velocity.
//!
//! States `y = [x, ẋ, W]`: W is the work done on the knife and its chain spring by the drive,
//! gravity, cutting, friction and damping, so `E − E0 − W` (E = ½·m_s·ẋ² + ½·k·δ²) is the
//! energy-balance residual of the integration.
//!
//! Events: Geneva entry and exit (ψ = 0 and ψ = 2φe, where γ'' jumps), the stack's edges
//! (`cut.s_start`, `cut.s_full`, cut-through at `cut.s_end`), the knife stopping inside the
//! stack (ẋ = 0) and the rigid velocity reversing (friction direction; at rest in the dwell it
//! holds the sign of its last motion).

use super::physics::{Kinematics, Params};
use crate::mechanics::geneva::Geneva;
use crate::mechanics::{STANDARD_GRAVITY, Scalar, SpringDamper, sgn};
use crate::solver::chain::Peaks;
use crate::solver::chain::{ChainOde, LastAt, LastPoint, dual_jacobian};
use crate::solver::{OdeSystem, ShaftPath};
use num_dual::Dual64;
use std::cell::Cell;

/// Half width of the velocity band in which the knife sticks at the cut front (Karnopp): the
/// cutting resistance holds whatever drive force up to its full value, m/s.
pub const V_STICK: f64 = 1e-5;

/// The ODE of one communication step.
pub struct KnifeOde<'a> {
    pub p: &'a Params,
    /// `p`'s Geneva pair, built once per ODE ([`Params::geneva`] costs a sine; the
    /// right-hand side is evaluated many times per step).
    pub geneva: Geneva,
    /// The chain's stiffness and damping.
    pub spring: SpringDamper,
    pub path: ShaftPath,
    /// What it tracks over accepted steps and events.
    pub memory: Cell<KnifeMemory>,
    /// The last shaft angles and rigid motions computed ([`KnifeOde::rigid_at`]).
    pub rigid: LastAt<(f64, Kinematics)>,
    /// The last point computed ([`ChainOde::point_kept`]).
    pub last: LastPoint<Point>,
}

impl KnifeOde<'_> {
    /// The shaft angle and the rigid motion at `t` on this step's path ([`LastAt`]).
    fn rigid_at(&self, t: f64) -> (f64, Kinematics) {
        self.rigid.on_path(&self.path, t, |phi, w, a| {
            (phi, self.p.kinematics_of(&self.geneva, phi, w, a))
        })
    }
}

crate::chain_memory! {
    /// What [`KnifeOde`] tracks between steps.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct KnifeMemory {
        /// Of the driver turns: peak |F_el| and peak |F_rigid|, K_d.
        pub peaks: Peaks,
        /// The stack is cut through in this stroke (set at cut-through, cleared when the knife
        /// rises back above `cut.s_start`): no cutting resistance.
        pub cut_done: bool,
    }
}

impl KnifeMemory {
    /// Nothing tracked yet, in driver turn `turn`, the stack not cut.
    pub fn new(turn: f64) -> KnifeMemory {
        KnifeMemory {
            peaks: Peaks::new(turn),
            cut_done: false,
        }
    }
}

/// The knife and its chain at one instant (any [`Scalar`]: `f64` for the ODE, dual numbers
/// along the knowns for the exact partial derivatives). The rigid motion it was computed on is
/// not copied in: the right-hand side reads only `xdd` and `power`, and a copy of the
/// [`Kinematics`] with each point was about 8 % of a stiff run's instructions; the outputs take
/// the kinematics beside the point.
#[derive(Clone, Copy, Debug, Default)]
pub struct Point<T = f64> {
    pub x: T,
    pub xd: T,
    pub xdd: T,
    /// Deflection δ = s_kin − x, m.
    pub delta: T,
    /// Chain force on the knife along s, k·δ + c·δ̇, N.
    pub f_el: T,
    pub f_cut: T,
    pub f_fr: T,
    /// dW/dt.
    pub power: T,
    /// The rigid (kinetostatic) chain force along s at this instant, N.
    pub f_rigid: T,
}

impl KnifeOde<'_> {
    /// The chain's spring `k` at the damping ratio `zeta` on the knife's mass.
    pub fn spring(p: &Params, k: f64, zeta: f64) -> SpringDamper {
        SpringDamper::with_ratio(k, p.slider_mass(), zeta)
    }

    /// As [`KnifeOde::point`], for given kinematics and the state's `y[0] = x`, `y[1] = ẋ`
    /// (any [`Scalar`]: the one source of the right-hand side and of the outputs at this level,
    /// and of their partial derivatives; the friction's direction, the stack and the sticking
    /// band decided on the values).
    #[inline]
    pub fn point_at<T: Scalar>(&self, kin: &Kinematics<T>, y: &[T]) -> Point<T> {
        let m = self.p.slider_mass();
        let (x, xd) = (y[0], y[1]);
        let delta = kin.s - x;
        let deltad = kin.v - xd;
        let f_el = self.spring.force(delta, deltad);
        let tan_nu = kin.sin_nu / kin.cos_nu;
        let sgn_v = sgn(kin.v.re());
        let f_fr = (f_el * tan_nu).abs() * self.p.guide_mu * sgn_v;
        let f_drive = f_el + m * STANDARD_GRAVITY - f_fr;
        let f_cut = self.cut(x, xd, f_drive);
        let xdd = (f_drive - f_cut) / m;
        let power = delta * self.spring.k * kin.v
            + deltad * self.spring.c * xd
            + (T::from(m * STANDARD_GRAVITY) - f_cut - f_fr) * xd;
        // rigid chain force along s: m_s·a − m_s·g + F_cut + friction (kinetostatic level)
        let f_rigid = {
            let r = (kin.a - STANDARD_GRAVITY) * m + self.p.cut_force(kin.s, kin.v);
            let kf = tan_nu.abs() * self.p.guide_mu * sgn_v;
            if r.re() >= 0.0 {
                r / (T::one() - kf)
            } else {
                r / (kf + 1.0)
            }
        };
        Point {
            x,
            xd,
            xdd,
            delta,
            f_el,
            f_cut,
            f_fr,
            power,
            f_rigid,
        }
    }

    /// Energy of knife and chain spring at the point `pt`, J (any [`Scalar`]).
    #[inline]
    pub fn energy_of<T: Scalar>(&self, pt: &Point<T>) -> T {
        pt.xd * (0.5 * self.p.slider_mass()) * pt.xd + self.spring.energy(pt.delta)
    }

    /// Is the knife in the uncut stack?
    fn in_stack(&self, x: f64) -> bool {
        !self.memory.get().cut_done && x >= self.p.cut_s_start && x <= self.p.cut_s_end
    }

    /// Cutting resistance at the elastic position and velocity, with the drive force
    /// `f_drive` pushing the knife down (for sticking at the cut front); any [`Scalar`].
    fn cut<T: Scalar>(&self, x: T, xd: T, f_drive: T) -> T {
        if !self.in_stack(x.re()) {
            return T::zero();
        }
        let cap = if x.re() >= self.p.cut_s_full {
            T::from(self.p.cut_f_max)
        } else {
            (x - self.p.cut_s_start) * self.p.cut_f_max / (self.p.cut_s_full - self.p.cut_s_start)
        };
        if xd.re() > V_STICK {
            cap
        } else if xd.re() < -V_STICK {
            T::zero()
        } else if f_drive.re() < 0.0 {
            // f64::clamp(f_drive, 0, cap)
            T::zero()
        } else if f_drive.re() > cap.re() {
            cap
        } else {
            f_drive
        }
    }

    /// Cycle index of the driver at time t.
    pub fn cycle(&self, t: f64) -> f64 {
        self.path.cycle(t)
    }
}

impl ChainOde for KnifeOde<'_> {
    type Point = Point;

    /// Evaluates the model at time t and state y.
    fn point(&self, t: f64, y: &[f64]) -> Point {
        self.point_at(&self.rigid_at(t).1, y)
    }
    fn last_point(&self) -> Option<&LastPoint<Point>> {
        Some(&self.last)
    }
    /// Energy of knife and chain spring, J.
    fn energy(&self, pt: &Point) -> f64 {
        self.energy_of(pt)
    }
    fn natural_frequency(&self) -> f64 {
        self.spring.omega
    }
    /// The state in static equilibrium on the rigid motion at time t: at rest relative to the
    /// chain, the spring holding the weight.
    fn initial_state(&self, t: f64) -> [f64; 3] {
        let (phi, w, a) = self.path.at(t);
        let kin = self.p.kinematics_of(&self.geneva, phi, w, a);
        let x = if self.spring.k > 0.0 {
            kin.s + self.p.slider_mass() * STANDARD_GRAVITY / self.spring.k
        } else {
            kin.s
        };
        [x, kin.v, 0.0]
    }
}

impl OdeSystem for KnifeOde<'_> {
    crate::chain_rhs!(pt => pt.xdd, pt.power);
    /// The exact derivative of the right-hand side ([`KnifeOde::point_at`] on dual numbers), so
    /// that it holds in every branch the point takes: in the sticking band at the cut front the
    /// cutting force balances the drive and the knife's acceleration does not depend on the
    /// state (the hand-written form this replaces had the sliding knife's derivative there).
    fn jacobian(&self, t: f64, y: &[f64], j: &mut [f64]) {
        let (phi, w, a) = self.path.at(t);
        let c = Dual64::from;
        let kin = self.p.kinematics_of(&self.geneva, c(phi), c(w), c(a));
        dual_jacobian(y, j, |x, xd| {
            let pt = self.point_at(&kin, &[x, xd]);
            (pt.xdd, pt.power)
        });
    }
    fn n_events(&self) -> usize {
        8
    }
    /// The event indicators (Model Exchange's too). `g[7]`, the rigid knife velocity, is
    /// exactly zero through the dwell (three quarters of a turn); the integrators and the Model
    /// Exchange hooks hold its sign there ([`crate::solver::hold_signs`]), so that its events are
    /// its reversals: the bottom of the stroke and the start of the next working stroke.
    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let exit = 2.0 * self.geneva.half_engagement();
        let (phi, kin) = self.rigid_at(t);
        // Geneva entry (ψ = 0) and exit (ψ = 2φe): γ'' jumps
        g[0] = phi.sin();
        g[1] = (phi - exit).sin();
        // the elastic knife at the stack's top, at full cutting force, cut through
        g[2] = y[0] - self.p.cut_s_start;
        g[3] = y[0] - self.p.cut_s_full;
        g[4] = y[0] - self.p.cut_s_end;
        // in the uncut stack: the knife's velocity leaving the sticking band ±V_STICK
        let stack = self.in_stack(y[0]);
        g[5] = if stack { y[1] - V_STICK } else { 1.0 };
        g[6] = if stack { y[1] + V_STICK } else { 1.0 };
        // the rigid velocity: the guide friction's direction
        g[7] = kin.v;
    }
    fn on_event(&self, _t: f64, _y: &[f64], before: &[f64], after: &[f64]) {
        let mut m = self.memory.get();
        if before[4] < 0.0 && after[4] >= 0.0 {
            m.cut_done = true; // cut through
        }
        if before[2] > 0.0 && after[2] <= 0.0 {
            m.cut_done = false; // back above the stack: the next one comes
        }
        self.memory.set(m);
    }
    fn on_step(&self, t: f64, y: &[f64]) {
        let pt = self.point_kept(t, y);
        let cyc = self.cycle(t);
        let mut m = self.memory.get();
        m.peaks.track(cyc, pt.f_el.abs(), pt.f_rigid.abs());
        self.memory.set(m);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::shaft::ShaftPath;
    use crate::solver::chain::assert_jacobian_at;

    /// The Jacobian agrees with central differences of the right-hand side: sliding, in the
    /// stack and out of it, and in the sticking band at the cut front.
    #[test]
    fn jacobian_is_the_derivative_of_the_rhs() {
        let p = Params::default();
        let o = KnifeOde {
            p: &p,
            geneva: p.geneva(),
            spring: KnifeOde::spring(&p, 5e7, 0.05),
            path: ShaftPath::new(0.0, 0.3, std::f64::consts::PI, 0.0),
            memory: Cell::new(KnifeMemory::new(0.0)),
            rigid: LastAt::default(),
            last: LastPoint::default(),
        };
        let (s0, s1) = (p.cut_s_start, p.cut_s_full);
        let mut in_band = 0;
        for j in 0..40 {
            let t = 0.5 * (j as f64 + 0.37) / 40.0;
            // sticking in the stack: the chain's force half the cutting force the front holds
            let kin = o.rigid_at(t).1;
            let xd = 0.3 * V_STICK;
            let f = 0.25 * p.cut_f_max;
            let stick = kin.s - (f - o.spring.c * (kin.v - xd)) / o.spring.k;
            for (x, xd) in [
                (s0 - 1e-3, 0.4),
                (0.5 * (s0 + s1), 0.4),
                (0.5 * (s0 + s1), xd),
                (stick, xd),
            ] {
                let y = [x, xd, 0.0];
                assert_jacobian_at(&o, t, y, [1e-9, 1e-3 * xd.abs().max(V_STICK)]);
                // sticking: the cutting force balances the drive
                let pt = o.point(t, &y);
                in_band += usize::from(pt.f_cut != 0.0 && pt.xdd == 0.0);
            }
        }
        assert!(in_band > 0, "no point sticks");
    }
}
