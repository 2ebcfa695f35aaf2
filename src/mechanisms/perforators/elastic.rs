//! Elastodynamic level of the perforator drive (`dynamics.md`, Perforators bullet): the lever
//! rotation Δγ is the degree of freedom, its inertia the lever's `lever.J` plus the carriage
//! reduced to it (`J_eff = J + m·s'(Δγ)²`, as the kinetostatic level's rod and carriage balance
//! has it), closed on the fixed ramp by spring 13 through a **unilateral** contact.
//!
//! The table is rigid and moves with the shaft (`x_t(φ)` of the cyclogram). At table position
//! x_t the roller centre can only move on its circle about the pivot O1, which crosses the ramp's
//! pitch curve at the rigid lever angle Δγ_r(x_t); the penetration of the roller into the ramp
//! along the ramp's upward normal n at that point is
//!
//! `δ = n·(R(Δγ_r) − R(Δγ))`  (> 0: pressed in; < 0: lifted off by −δ),
//!
//! its rate `δ̇ = ṅ·(R(Δγ_r) − R(Δγ)) + a_r·Δγ̇_r − a·Δγ̇` with the lever arms of the normal
//! `a = n·R'(Δγ)` and `ṅ = dn/dx_t·ẋ_t` (the contact point moves along the ramp with the table). Contact force
//! (`contact.law`): Hertz line contact `K·δ^(10/9)` ([`crate::mechanics::hertz`], K from the
//! roller width and moduli) or linear `contact.k·δ`, plus the damping `contact.c·δ̇`, and never
//! pulling: `F_c = max(0, F_el(δ) + c·δ̇)` for δ > 0, 0 otherwise. The lever's angular
//! acceleration follows from the kinetostatic level's own balance about O1
//! ([`super::physics::Drive::moment_left`], rod, carriage, spring, gravity, piercing, guide and
//! hinge friction, the table's acceleration) solved for Δγ̈ with the contact force given. The
//! friction and piercing loads take their directions from the rigid motion (assumption, as in
//! the Geneva drive: the lever's ringing does not reverse the sliding; no chattering at rest).
//!
//! Energy balance: `E = ½·J_eff·Δγ̇² + M0·Δγ + ½·kt·Δγ² + m·g·cos α·s + V_c(δ)` in the table
//! frame, and W the work of friction, piercing, the table's inertial force on the carriage, the
//! contact damping and the moving ramp (`F_el·(δ̇ + a·Δγ̇)`): `E − E0 − W` is the integration's
//! residual. States `y = [q, q̇, W]` with the deflection `q = Δγ_r − Δγ` from the rigid rotation
//! (not Δγ itself: a stiff contact's force then stays continuous through the implicit method's
//! Newton iterates, which start from a constant state while the ramp moves on).
//!
//! Events: the four cyclogram phase boundaries, contact opening and closing (δ = 0), the contact
//! force reaching zero while pressed in (released by the damping), the rigid lever velocity's
//! sign (friction and piercing direction; at rest it holds the sign of its last motion), and
//! the piercing load's corners (`pierce.s_in`, their middle, `pierce.s_out`, at the elastic
//! needle position).

#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::physics::{Drive, Forces, Kinematics, Linkage};
use crate::mechanics::hertz::{line_contact_energy, line_contact_force};
use crate::mechanics::{STANDARD_GRAVITY, Scalar, dot, max_of, sgn};
use crate::solver::chain::{ChainOde, LastAt, LastPoint};
use crate::solver::{OdeSystem, ShaftPath};
use std::cell::Cell;
use std::f64::consts::TAU;

crate::fmi_enum! {
    /// `contact.law`.
    pub enum ContactLaw ("ContactLaw", "Force law of the unilateral ramp contact") {
        Hertz = 1 ("hertz", "Hertz line contact K*pen^(10/9), K from roller.b and the moduli (Palmgren)"),
        Linear = 2 ("linear", "linear spring contact.k*pen"),
    }
}

/// The contact: law, its stiffness constant (K in N/m^(10/9) for Hertz, N/m for linear), the
/// damping `contact.c`, N·s/m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    pub law: ContactLaw,
    pub k: f64,
    pub c: f64,
    /// Natural angular frequency of the lever on the contact, rad/s: √(k_δ/m_red), k_δ the
    /// law's slope at the spring's preload in the loading dwell, m_red
    /// [`LeverOde::reduced_mass`] (1 where the preload presses nothing in).
    pub omega: f64,
}

impl Contact {
    /// The contact of a drive: Hertz takes K from `roller.b`, `ramp.E`, `roller.E`.
    pub fn new(d: &Drive, law: ContactLaw, k_linear: f64, c: f64) -> Contact {
        let k = match law {
            ContactLaw::Hertz => d.p.roller.stiffness(),
            ContactLaw::Linear => k_linear,
        };
        let mut contact = Contact {
            law,
            k,
            c,
            omega: 1.0,
        };
        let preload = d.loading_force();
        let omega =
            (contact.elastic(contact.penetration_of(preload)).1 / LeverOde::reduced_mass(d)).sqrt();
        if omega.is_finite() && omega > 0.0 {
            contact.omega = omega;
        }
        contact
    }

    /// Elastic force at penetration δ and its slope (any [`Scalar`]).
    #[inline]
    pub fn elastic<T: Scalar>(&self, pen: T) -> (T, T) {
        match self.law {
            ContactLaw::Hertz => line_contact_force(self.k, pen),
            ContactLaw::Linear if pen.re() > 0.0 => (pen * self.k, T::from(self.k)),
            ContactLaw::Linear => (T::zero(), T::zero()),
        }
    }

    /// Elastic energy at penetration δ (any [`Scalar`]).
    pub fn energy<T: Scalar>(&self, pen: T) -> T {
        match self.law {
            ContactLaw::Hertz => line_contact_energy(self.k, pen),
            ContactLaw::Linear if pen.re() > 0.0 => pen * (0.5 * self.k) * pen,
            ContactLaw::Linear => T::zero(),
        }
    }

    /// Penetration at which the elastic force is `f` (≥ 0; any [`Scalar`]).
    pub fn penetration_of<T: Scalar>(&self, f: T) -> T {
        if !(f.re() > 0.0 && self.k > 0.0) {
            return T::zero();
        }
        match self.law {
            ContactLaw::Hertz => (f / self.k).powf(0.9),
            ContactLaw::Linear => f / self.k,
        }
    }
}

crate::chain_memory! {
    /// Per-turn tracking over accepted steps.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct Peaks {
        /// Index of the shaft turn.
        pub cycle: f64 [Whole],
        /// Peak dynamic contact force, peak |kinetostatic contact force|, smallest dynamic force.
        pub dyn_max: f64,
        pub rigid_max: f64,
        pub dyn_min: f64 [OrInf],
    }
}

impl Peaks {
    pub fn new(cycle: f64) -> Peaks {
        Peaks {
            cycle,
            dyn_max: 0.0,
            rigid_max: 0.0,
            dyn_min: f64::INFINITY,
        }
    }
}

crate::chain_memory! {
    /// What the ODE tracks through its steps and events (interior mutability).
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct Track {
        pub peaks: Peaks,
        /// K_d of the last complete turn (NaN: none yet).
        pub k_d: f64 [OrNan],
        /// Smallest dynamic contact force of the last complete turn (+inf: none yet).
        pub last_min: f64 [OrInf],
        /// Lift-offs so far, and the absolute shaft angle of the last.
        pub liftoffs: f64 [Count],
        pub lift_phi: f64 [OrNan],
        /// Largest contact force in the first compression after a landing, N.
        pub impact: f64,
        /// In the first compression after a landing.
        pub landed: bool,
    }
}

impl Track {
    pub fn new(cycle: f64) -> Track {
        Track {
            peaks: Peaks::new(cycle),
            k_d: f64::NAN,
            last_min: f64::INFINITY,
            liftoffs: 0.0,
            lift_phi: f64::NAN,
            impact: 0.0,
            landed: false,
        }
    }
}

/// The ODE of one communication step.
pub struct LeverOde<'a> {
    pub d: &'a Drive,
    pub contact: Contact,
    pub path: ShaftPath,
    pub track: Cell<Track>,
    /// The lever angles the linkage has a position for ([`LeverOde::linkage_range`]).
    pub range: (f64, f64),
    /// The first lever angle met outside that range (NaN: none), for the error message.
    pub out_of_range: Cell<f64>,
    /// The last rigid motion computed ([`LeverOde::rigid_at`]).
    pub rigid: LastAt<Kinematics>,
    /// The last point computed ([`ChainOde::point_kept`]).
    pub last: LastPoint<Point>,
}

/// Everything at one instant (any [`Scalar`]: `f64` in the ODE, dual numbers for the exact
/// partial derivatives).
#[derive(Clone, Copy, Debug)]
pub struct Point<T = f64> {
    /// Rigid kinematics (the reference) at the shaft state.
    pub rigid: Kinematics<T>,
    /// Kinematics of the elastic lever (table motion as the rigid one).
    pub kin: Kinematics<T>,
    /// Forces of the kinetostatic balance at the elastic state, with the dynamic contact force.
    pub forces: Forces<T>,
    /// Penetration δ, m, and its rate, m/s.
    pub pen: T,
    pub pen_d: T,
    /// Elastic contact force F_el(δ), its slope, the force before the clamp, the contact force.
    pub f_el: T,
    pub k_c: T,
    pub f_pre: T,
    pub f_c: T,
    /// Lever arms of the normal at the elastic and the rigid lever angle, m.
    pub arm: T,
    pub arm_r: T,
    /// Reduced inertia J + m·s'², kg·m².
    pub j_eff: T,
    /// `∂Δγ̈/∂F_c` of the balance (friction included), rad/(s²·N).
    pub ga_fc: T,
    /// dW/dt, W.
    pub power: T,
}

impl LeverOde<'_> {
    /// The rigid motion at `t` on this step's path, the last one kept ([`LastAt`]).
    fn rigid_at(&self, t: f64) -> Kinematics {
        self.rigid
            .on_path(&self.path, t, |phi, w, a| self.d.kinematics(phi, w, a))
    }

    /// Reduced inertia at lever angle Δγ (any [`Scalar`]).
    pub fn j_eff<T: Scalar>(d: &Drive, g: T) -> T {
        Self::j_eff_of(d, d.carriage(g).ds)
    }

    /// [`LeverOde::j_eff`] from the carriage's `ds/dΔγ` there.
    fn j_eff_of<T: Scalar>(d: &Drive, ds: T) -> T {
        ds * d.p.perf_m * ds + d.p.lever_j
    }

    /// The lever angles the linkage works in: from the lowest position down and up to where the
    /// rod cannot hold the carriage any more (no position, or the carriage turning back), less
    /// 0.02 rad.
    pub fn linkage_range(d: &Drive) -> (f64, f64) {
        let ok = |g: f64| {
            let c = d.carriage(g);
            c.s.is_finite() && c.ds > 0.0
        };
        let step = 1e-3;
        let mut hi = 0.0;
        while hi < std::f64::consts::PI && ok(hi + step) {
            hi += step;
        }
        let mut lo = 0.0;
        while lo > -std::f64::consts::PI && ok(lo - step) {
            lo -= step;
        }
        (lo + 0.02, hi - 0.02)
    }

    /// Effective mass at the roller along the ramp normal in the lowest position (dwell at
    /// loading): `J_eff/a²`, kg; `c = 2·ζ·√(k·m)` gives a damping ratio ζ.
    pub fn reduced_mass(d: &Drive) -> f64 {
        let k = d.at_loading();
        let (_, r1, _) = d.p.roller(k.gamma);
        let a = dot(k.normal, r1);
        Self::j_eff(d, k.gamma) / (a * a)
    }

    /// The kinematics of the elastic lever at Δγ, Δγ̇, Δγ̈ on the table of `rigid`, the
    /// linkage as made at Δγ `link`.
    fn kin_at<T: Scalar>(
        &self,
        rigid: &Kinematics<T>,
        link: &Linkage<T>,
        (g, gw, ga): (T, T, T),
    ) -> Kinematics<T> {
        let pose = link.pose;
        Kinematics {
            s: pose.s - self.d.made_s0,
            v: pose.ds * gw,
            a: pose.dds * gw * gw + pose.ds * ga,
            gamma: g,
            gamma_w: gw,
            gamma_a: ga,
            sin_nu: pose.sin_nu,
            ..*rigid
        }
    }

    /// The lever at the rigid motion `rigid` and the states `y` (any [`Scalar`]: the contact,
    /// the clamp, the friction's directions and the secant steps decided on the real parts).
    pub fn point_at<T: Scalar>(&self, rigid: &Kinematics<T>, y: &[T]) -> Point<T> {
        let d = self.d;
        let p = &d.p;
        let (g, gw) = (rigid.gamma - y[0], rigid.gamma_w - y[1]);
        let n = rigid.normal;
        let (rr, rr1, _) = p.roller(rigid.gamma);
        // the angle's linkage (the roller arm is as designed), once for the whole balance
        let link = d.linkage(g);
        let (r, r1, _) = link.r;
        let arm = dot(n, r1);
        let arm_r = dot(n, rr1);
        let pen = dot(n, (rr.0 - r.0, rr.1 - r.1));
        let n_t = (rigid.normal_x.0 * rigid.v_t, rigid.normal_x.1 * rigid.v_t);
        let pen_d = dot(n_t, (rr.0 - r.0, rr.1 - r.1)) + arm_r * rigid.gamma_w - arm * gw;
        let (f_el, k_c) = self.contact.elastic(pen);
        let f_pre = if pen.re() > 0.0 {
            f_el + pen_d * self.contact.c
        } else {
            T::zero()
        };
        let f_c = max_of(f_pre, 0.0);
        // directions of friction and piercing from the rigid motion
        let sv = sgn(rigid.v.re());
        let sw = sgn(rigid.gamma_w.re());
        let j_eff = Self::j_eff_of(d, link.pose.ds);
        let outside = !(g.re() >= self.range.0 && g.re() <= self.range.1);
        // the balance with the contact force given is affine in the lever acceleration but for
        // the friction's corners: a Newton step with the frictionless slope J_eff, then secant
        // steps; only the accelerations change from one to the next
        let a0 = rigid.gamma_a;
        let at_a0 = self.kin_at(rigid, &link, (g, gw, a0));
        let left = |ga: T| {
            let (pose, k) = (&link.pose, at_a0);
            let k = Kinematics {
                a: pose.dds * gw * gw + pose.ds * ga,
                gamma_a: ga,
                ..k
            };
            let (m, dm, f) = d.moment_left(&k, &link, (sv, sw), f_c);
            (m, k, f, dm)
        };
        let (r0, mut kin, mut forces, mut d_left_fc) = left(a0);
        // ∂Δγ̈/∂(moment left), −1/J_eff without friction
        let mut slope = -j_eff.recip();
        let tol = 1e-12 * (f_c.re().max(1.0) * arm.re().abs() + (a0.re() * j_eff.re()).abs());
        if r0.re().abs() > tol && r0.re().is_finite() {
            let (mut a0, mut r0) = (a0, r0);
            let mut a1 = a0 + r0 * slope;
            for _ in 0..4 {
                let (r1, k1, f1, dm1) = left(a1);
                (kin, forces, d_left_fc) = (k1, f1, dm1);
                if r1.re() != r0.re() && r1.re().is_finite() {
                    slope = -(a1 - a0) / (r1 - r0);
                }
                if r1.re().abs() <= tol || r1.re() == r0.re() || !r1.re().is_finite() {
                    break;
                }
                let a2 = a1 + r1 * slope;
                (a0, r0) = (a1, r1);
                a1 = a2;
            }
        }
        // ∂Δγ̈/∂F_c: the contact's moment and the hinge friction's share of it
        let ga_fc = slope * d_left_fc;
        if outside {
            // no position of the linkage: the integrator meets a non-finite derivative and
            // fails the step; the model names the angle
            if self.out_of_range.get().is_nan() {
                self.out_of_range.set(g.re());
            }
            kin.gamma_a = T::from(f64::NAN);
        }
        let (sa, _) = d.alpha_sin_cos;
        let ds = link.pose.ds;
        let q_fr = forces.joint_m - ds * (forces.pierce_q + forces.guide_n * p.guide_mu) * sv;
        let power = gw * (q_fr - ds * p.perf_m * rigid.a_t * sa)
            + (f_c - f_el) * arm * gw
            + f_el * (pen_d + arm * gw);
        Point {
            rigid: *rigid,
            kin,
            forces,
            pen,
            pen_d,
            f_el,
            k_c,
            f_pre,
            f_c,
            arm,
            arm_r,
            j_eff,
            ga_fc,
            power,
        }
    }

    /// Kinetostatic (rigid) contact force at time t (any [`Scalar`]).
    pub fn rigid_force<T: Scalar>(&self, rigid: &Kinematics<T>) -> T {
        self.d.forces(rigid).roller_f
    }

    /// [`ChainOde::energy`] at a point, any [`Scalar`].
    pub fn energy_of<T: Scalar>(&self, pt: &Point<T>) -> T {
        let p = &self.d.p;
        let g = pt.kin.gamma;
        pt.j_eff * 0.5 * pt.kin.gamma_w * pt.kin.gamma_w
            + g * p.spring_m0
            + g * (0.5 * p.spring_kt) * g
            + pt.kin.s * (p.perf_m * STANDARD_GRAVITY * p.alpha.cos())
            + self.contact.energy(pt.pen)
    }

    /// [`ChainOde::initial_state`] on the rigid motion `rigid`, any [`Scalar`].
    pub fn initial_state_at<T: Scalar>(&self, rigid: &Kinematics<T>) -> [T; 3] {
        let f = self.d.forces(rigid).roller_f;
        let pen = self.contact.penetration_of(f);
        let p = &self.d.p;
        let n = rigid.normal;
        let (rr, rr1, _) = p.roller(rigid.gamma);
        let arm_r = dot(n, rr1);
        // Newton on n·(R(Δγ_r) − R(Δγ_r − q)) = δ
        let mut q = pen / arm_r;
        for _ in 0..3 {
            let (r, r1, _) = p.roller(rigid.gamma - q);
            q -= (dot(n, (rr.0 - r.0, rr.1 - r.1)) - pen) / dot(n, r1);
        }
        let (_, r1, _) = p.roller(rigid.gamma - q);
        let arm = dot(n, r1);
        [q, rigid.gamma_w * (T::one() - arm_r / arm), T::zero()]
    }

    /// In contact for the event functions `g`: pressed in, and pressing.
    pub fn in_contact(g: &[f64]) -> bool {
        g[4] > 0.0 && g[5] > 0.0
    }
}

/// Number of event functions.
pub const N_EVENTS: usize = 10;

impl ChainOde for LeverOde<'_> {
    type Point = Point;

    fn point(&self, t: f64, y: &[f64]) -> Point {
        self.point_at(&self.rigid_at(t), y)
    }
    fn last_point(&self) -> Option<&LastPoint<Point>> {
        Some(&self.last)
    }
    /// Energy of lever, carriage, spring 13, weight and contact, table frame, J.
    fn energy(&self, pt: &Point) -> f64 {
        self.energy_of(pt)
    }
    fn natural_frequency(&self) -> f64 {
        self.contact.omega
    }
    /// The lever in equilibrium on its rigid motion at time t: pressed in by the kinetostatic
    /// contact force (on the ramp without force if that is negative), at the rigid normal speed.
    fn initial_state(&self, t: f64) -> [f64; 3] {
        let (phi, w, a) = self.path.at(t);
        let rigid = self.d.kinematics(phi, w, a);
        self.initial_state_at(&rigid)
    }
}

impl OdeSystem for LeverOde<'_> {
    crate::chain_rhs!(pt => pt.rigid.gamma_a - pt.kin.gamma_a, pt.power);
    fn jacobian(&self, t: f64, y: &[f64], j: &mut [f64]) {
        // the contact (the stiff part) through the balance's own ∂Δγ̈/∂F_c; spring 13 and the
        // arm's turning; the linkage's slow terms left out
        // (q̈ = Δγ̈_r − Δγ̈ and Δγ = Δγ_r − q: ∂q̈/∂q = ∂Δγ̈/∂Δγ, ∂q̈/∂q̇ = ∂Δγ̈/∂Δγ̇)
        let pt = self.point(t, y);
        let p = &self.d.p;
        let (_, _, r2) = p.roller(pt.kin.gamma);
        let arm_g = dot(pt.rigid.normal, r2);
        let mut dg = (pt.f_c * arm_g - p.spring_kt) / pt.j_eff;
        let mut dw = 0.0;
        if pt.f_pre > 0.0 {
            let c = self.contact.c;
            let (_, r1, _) = p.roller(pt.kin.gamma);
            let n_x = pt.rigid.normal_x;
            let n_t_r1 = (n_x.0 * r1.0 + n_x.1 * r1.1) * pt.rigid.v_t;
            dg += pt.ga_fc * (-pt.k_c * pt.arm - c * (arm_g * pt.kin.gamma_w + n_t_r1));
            dw = pt.ga_fc * (-c * pt.arm);
        }
        j.copy_from_slice(&[0.0, 1.0, 0.0, dg, dw, 0.0, 0.0, 0.0, 0.0]);
    }
    fn n_events(&self) -> usize {
        N_EVENTS
    }
    /// The event indicators (Model Exchange's too). `g[6]`, the rigid lever velocity, is exactly
    /// zero while the table dwells and while the roller is on the ramp's flat; the integrators
    /// and the Model Exchange hooks hold its sign there ([`crate::solver::hold_signs`]), so that
    /// its events are its reversals.
    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let (phi, _, _) = self.path.at(t);
        let abs_phi = phi + self.path.turns * TAU;
        // the four cyclogram phase boundaries of the table
        g[..4].copy_from_slice(&self.d.cyc.phase_indicators(abs_phi));
        let rigid = self.rigid_at(t);
        let p = &self.d.p;
        let n = rigid.normal;
        let (g_el, w_el) = (rigid.gamma - y[0], rigid.gamma_w - y[1]);
        let (rr, rr1, _) = p.roller(rigid.gamma);
        let (r, r1, _) = p.roller(g_el);
        let pen = dot(n, (rr.0 - r.0, rr.1 - r.1));
        // contact opening and closing (penetration δ = 0), the contact force reaching zero
        // while pressed in (released by the damping)
        g[4] = pen;
        g[5] = if pen > 0.0 {
            let n_t = (rigid.normal_x.0 * rigid.v_t, rigid.normal_x.1 * rigid.v_t);
            let pen_d = dot(n_t, (rr.0 - r.0, rr.1 - r.1)) + dot(n, rr1) * rigid.gamma_w
                - dot(n, r1) * w_el;
            self.contact.elastic(pen).0 + self.contact.c * pen_d
        } else {
            1.0
        };
        // the rigid lever velocity: the friction's and the piercing load's direction
        g[6] = rigid.gamma_w;
        // the piercing load's corners at the elastic needle position
        let q = (self.d.carriage(g_el).s - self.d.made_s0) / self.d.stroke;
        g[7] = q - p.pierce_s_in;
        g[8] = q - 0.5 * (p.pierce_s_in + p.pierce_s_out);
        g[9] = q - p.pierce_s_out;
    }
    fn on_event(&self, t: f64, _y: &[f64], before: &[f64], after: &[f64]) {
        let mut tr = self.track.get();
        match (Self::in_contact(before), Self::in_contact(after)) {
            (true, false) => {
                tr.liftoffs += 1.0;
                tr.lift_phi = self.path.absolute_phi(t);
                tr.landed = false;
            }
            (false, true) => tr.landed = true,
            _ => {}
        }
        self.track.set(tr);
    }
    fn on_step(&self, t: f64, y: &[f64]) {
        let pt = self.point_kept(t, y);
        let mut tr = self.track.get();
        if tr.landed {
            tr.impact = tr.impact.max(pt.f_c);
            if pt.pen_d < 0.0 {
                tr.landed = false; // past the largest compression
            }
        }
        let f_rigid = self.rigid_force(&pt.rigid).abs();
        let cyc = self.path.cycle(t);
        if cyc != tr.peaks.cycle {
            if tr.peaks.rigid_max > 0.0 {
                tr.k_d = tr.peaks.dyn_max / tr.peaks.rigid_max;
            }
            tr.last_min = tr.peaks.dyn_min;
            tr.peaks = Peaks::new(cyc);
        }
        let pk = &mut tr.peaks;
        pk.dyn_max = pk.dyn_max.max(pt.f_c);
        pk.rigid_max = pk.rigid_max.max(f_rigid);
        pk.dyn_min = pk.dyn_min.min(pt.f_c);
        self.track.set(tr);
    }
}
