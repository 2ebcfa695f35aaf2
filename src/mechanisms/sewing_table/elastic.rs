//! Elastodynamic level of the translating sewing table (`dynamics.md`): the table (mass m) is
//! tied to its rigid position x_kin(φ) by the cam-follower chain's stiffness k and damping
//! c = 2·ζ·√(k·m), through the slot's clearance `cam.clearance` (total play; default 0):
//!
//! `m·ẍ = F_c(δ, δ̇) − f·(m·g + |F_c·tan θp|)·sgn ẋ_kin + F_ext`,  δ = x_kin − x,
//!
//! with `F_c = k·(δ − g) + c·δ̇ ≥ 0` on the pushing flank (δ > g), `k·(δ + g) + c·δ̇ ≤ 0` on the
//! other flank (δ < −g) and 0 while the roller crosses the gap (|δ| ≤ g, g = clearance/2);
//! without play the slot holds the roller between both flanks, `F_c = k·δ + c·δ̇`. With
//! clearance the roller leaves one flank (a lift-off, counted) and impacts the other (a landing;
//! the largest force after a landing is the impact force). The guide friction takes its
//! direction from the rigid velocity (as in the Geneva drive: no chattering at rest).
//!
//! States `y = [x, ẋ, W]`, W the work on table and follower spring (energy balance).
//! Events: the four cyclogram phase boundaries, both flanks (δ = ±g, with clearance only), the
//! rigid velocity's sign (friction direction; at rest in the dwells it holds the sign of its
//! last motion).

use super::physics::{Kinematics, Params};
use crate::mechanics::{STANDARD_GRAVITY, Scalar, SpringDamper, max_of, min_of, sgn};
use crate::solver::chain::{ChainOde, LastAt, Peaks};
use crate::solver::{OdeSystem, ShaftPath};
use std::cell::Cell;

/// The ODE of one communication step.
pub struct TableOde<'a> {
    pub p: &'a Params,
    /// The follower chain's stiffness and damping.
    pub spring: SpringDamper,
    /// Half the clearance, m.
    pub gap: f64,
    pub f_ext: f64,
    pub path: ShaftPath,
    /// What it tracks over accepted steps and events.
    pub memory: Cell<TableMemory>,
    /// The last rigid motion computed ([`TableOde::rigid_at`]).
    pub rigid: LastAt<Kinematics>,
}

crate::chain_memory! {
    /// What [`TableOde`] tracks between steps.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct TableMemory {
        /// Peak tracking over accepted steps and the dynamic factor of the last complete turn.
        pub peaks: Peaks,
        /// Lift-offs so far.
        pub liftoffs: f64 [Count],
        /// Largest contact force after a landing, N.
        pub impact: f64,
        /// Between a landing and the next lift-off.
        pub landed: bool,
    }
}

/// Everything at one instant (any [`Scalar`]: `f64` in the ODE, dual numbers for the exact
/// partial derivatives).
#[derive(Clone, Copy, Debug)]
pub struct Point<T = f64> {
    pub kin: Kinematics<T>,
    pub x: T,
    pub xd: T,
    pub xdd: T,
    pub delta: T,
    pub f_c: T,
    pub power: T,
    /// Penetration of the loaded flank (0 in the gap), m.
    pub pen: T,
    /// The guide friction against the rigid motion, `f·(m·g + |F_c·tan θp|)·sgn ẋ_kin`, N.
    pub f_fr: T,
    pub f_rigid: T,
}

impl TableOde<'_> {
    /// The rigid motion at `t` on this step's path, the last one kept ([`LastAt`]).
    fn rigid_at(&self, t: f64) -> Kinematics {
        self.rigid
            .on_path(&self.path, t, |phi, w, a| self.p.kinematics(phi, w, a))
    }

    /// The chain's spring `k` at the damping ratio `zeta` on the table's mass.
    pub fn spring(p: &Params, k: f64, zeta: f64) -> SpringDamper {
        SpringDamper::with_ratio(k, p.table_m, zeta)
    }

    /// The chain at the rigid motion `kin` and the states `y` ([`TableOde::point_with`] at
    /// this step's `table.F_ext`).
    pub fn point_at(&self, kin: &Kinematics, y: &[f64]) -> Point {
        self.point_with(kin, y, self.f_ext)
    }

    /// The chain at the rigid motion `kin`, the states `y` and the external force `f_ext`, any
    /// [`Scalar`] (the flank in contact and the friction's direction decided on the real
    /// parts): the module's equation of motion, `ẍ` and the power `Ẇ` with the chain's force
    /// and the rigid force `F_x` of [`Params::forces_with`].
    pub fn point_with<T: Scalar>(&self, kin: &Kinematics<T>, y: &[T], f_ext: T) -> Point<T> {
        let m = self.p.table_m;
        let (x, xd) = (y[0], y[1]);
        let delta = kin.c.x - x;
        let deltad = kin.v - xd;
        let (pen, f_c) = if self.gap <= 0.0 {
            // no play: the slot holds the roller between both flanks at once
            (delta, self.spring.force(delta, deltad))
        } else if delta.re() > self.gap {
            let pen = delta - self.gap;
            (pen, max_of(self.spring.force(pen, deltad), 0.0))
        } else if delta.re() < -self.gap {
            let pen = delta + self.gap;
            (pen, min_of(self.spring.force(pen, deltad), 0.0))
        } else {
            (T::zero(), T::zero())
        };
        let f_fr = ((f_c * kin.theta.tan()).abs() + m * STANDARD_GRAVITY)
            * self.p.guide_f
            * sgn(kin.v.re());
        let xdd = (f_c - f_fr + f_ext) / m;
        let power =
            pen * self.spring.k * kin.v + (f_c - pen * self.spring.k) * xd + (f_ext - f_fr) * xd;
        let f_rigid = self.p.forces_with(kin, T::zero(), f_ext, false).f_x;
        Point {
            kin: *kin,
            x,
            xd,
            xdd,
            delta,
            f_c,
            power,
            pen,
            f_fr,
            f_rigid,
        }
    }

    /// Energy of table and follower spring at a point, J (any [`Scalar`]).
    pub fn energy_of<T: Scalar>(&self, pt: &Point<T>) -> T {
        pt.xd * (0.5 * self.p.table_m) * pt.xd + self.spring.energy(pt.pen)
    }

    /// [`ChainOde::initial_state`] at the rigid motion `kin`, the shaft acceleration `a` and
    /// the external force `f_ext` (any [`Scalar`]; the flank taken on the real part).
    pub fn initial_state_at<T: Scalar>(&self, kin: &Kinematics<T>, a: T, f_ext: T) -> [T; 3] {
        let f = self.p.forces_with(kin, a, f_ext, false).f_x;
        let side = if f.re() >= 0.0 { 1.0 } else { -1.0 };
        [
            kin.c.x - f / self.spring.k - side * self.gap,
            kin.v,
            T::zero(),
        ]
    }
}

impl ChainOde for TableOde<'_> {
    type Point = Point;

    fn point(&self, t: f64, y: &[f64]) -> Point {
        self.point_at(&self.rigid_at(t), y)
    }
    /// Energy of table and follower spring, J.
    fn energy(&self, pt: &Point) -> f64 {
        self.energy_of(pt)
    }
    fn natural_frequency(&self) -> f64 {
        self.spring.omega
    }
    /// The table in equilibrium on its rigid motion at time t (roller on the flank that holds
    /// the rigid force, the spring carrying it).
    fn initial_state(&self, t: f64) -> [f64; 3] {
        let (phi, w, a) = self.path.at(t);
        let kin = self.p.kinematics(phi, w, a);
        self.initial_state_at(&kin, a, self.f_ext)
    }
}

impl OdeSystem for TableOde<'_> {
    crate::chain_rhs!(pt => pt.xdd, pt.power);
    fn jacobian(&self, t: f64, y: &[f64], j: &mut [f64]) {
        let pt = self.point(t, y);
        let m = self.p.table_m;
        let contact = self.gap <= 0.0 || pt.f_c != 0.0;
        let tan = pt.kin.theta.tan();
        // ∂F_fr/∂F_c
        let dfr = self.p.guide_f * tan.abs() * sgn(pt.f_c) * sgn(pt.kin.v);
        let (dfc_dx, dfc_dv) = if contact {
            (-self.spring.k, -self.spring.c)
        } else {
            (0.0, 0.0)
        };
        let a_x = dfc_dx * (1.0 - dfr) / m;
        let a_v = dfc_dv * (1.0 - dfr) / m;
        j.copy_from_slice(&[0.0, 1.0, 0.0, a_x, a_v, 0.0, 0.0, 0.0, 0.0]);
    }
    fn n_events(&self) -> usize {
        7
    }
    /// The event indicators (Model Exchange's too). `g[6]`, the rigid table velocity, is
    /// exactly zero through both dwells; the integrators and the Model Exchange hooks hold its
    /// sign there ([`crate::solver::hold_signs`]), so that its events are its reversals.
    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let (phi, _, _) = self.path.at(t);
        let abs_phi = phi + self.path.turns * std::f64::consts::TAU;
        // the four cyclogram phase boundaries (forward travel, far dwell, return, near dwell)
        g[..4].copy_from_slice(&self.p.cyclogram().phase_indicators(abs_phi));
        let kin = self.rigid_at(t);
        let delta = kin.c.x - y[0];
        // with play: the roller on the pushing flank (δ > g), on the other one (δ < −g)
        if self.gap > 0.0 {
            g[4] = delta - self.gap;
            g[5] = delta + self.gap;
        } else {
            g[4] = 1.0;
            g[5] = 1.0;
        }
        // the rigid velocity: the guide friction's direction
        g[6] = kin.v;
    }
    fn on_event(&self, _t: f64, _y: &[f64], before: &[f64], after: &[f64]) {
        if self.gap <= 0.0 {
            return;
        }
        let in_contact = |g: &[f64]| g[4] > 0.0 || g[5] < 0.0;
        let mut m = self.memory.get();
        match (in_contact(before), in_contact(after)) {
            (true, false) => {
                m.liftoffs += 1.0;
                m.landed = false;
            }
            (false, true) => m.landed = true,
            _ => {}
        }
        self.memory.set(m);
    }
    fn on_step(&self, t: f64, y: &[f64]) {
        let pt = self.point(t, y);
        let mut m = self.memory.get();
        if m.landed {
            m.impact = m.impact.max(pt.f_c.abs());
        }
        let cyc = self.path.cycle(t);
        m.peaks.track(cyc, pt.f_c.abs(), pt.f_rigid.abs());
        self.memory.set(m);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::{Integrator, Method, Settings};

    /// The table on a stiff chain (1e12 N/m, the shaft standing still, as in a dwell), released
    /// 1 nm from its equilibrium: the ringing decays to the rounding of x within about a
    /// millisecond. With `atol` at the force of 3 N (3/k), as the report sets it, the rate's
    /// absolute tolerance (3e-12 m/s) lay below the noise a rounding of x puts into ẋ, and
    /// Radau IIA's Newton iteration stalled on it at steps of microseconds
    /// ([`crate::solver::chain::rate_tolerance`]).
    #[test]
    fn a_stiff_chain_at_rest_is_not_asked_for_its_rate_below_the_rounding_of_its_position() {
        let p = Params::default();
        let k = 1e12;
        let o = TableOde {
            p: &p,
            spring: TableOde::spring(&p, k, 0.05),
            gap: 0.0,
            f_ext: 0.0,
            path: ShaftPath::new(0.0, 1.0, 0.0, 0.0),
            memory: Cell::new(TableMemory {
                peaks: Peaks::new(0.0),
                liftoffs: 0.0,
                impact: 0.0,
                landed: false,
            }),
            rigid: LastAt::default(),
        };
        let mut y = o.initial_state(0.0);
        assert!(y[0].abs() > 0.01, "a position far from 0: {}", y[0]);
        let rest = y[0];
        y[0] += 1e-9;
        let mut it = Integrator::new(Settings {
            method: Method::Radau5,
            rtol: 1e-4,
            atol: 3.0 / k,
            ..Settings::default()
        });
        let (mut steps, mut rejected) = (0, 0);
        for i in 0..20 {
            let st = it
                .integrate(&o, i as f64 * 1e-3, (i + 1) as f64 * 1e-3, &mut y)
                .expect("the chain at rest");
            steps += st.steps;
            rejected += st.rejected;
        }
        assert!(
            (y[0] - rest).abs() < 1e-15,
            "back at rest: {:e}",
            y[0] - rest
        );
        // 281 steps and 46 rejected (the ringing's decay in the first millisecond, then a step
        // a millisecond); with the rate's tolerance at atol, 777 and 154 (the noise stalled it
        // through the second millisecond)
        assert!(
            steps <= 400 && rejected <= 80,
            "{steps} steps, {rejected} rejected in 20 ms"
        );
    }
}
