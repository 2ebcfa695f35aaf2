//! The perforator drive's kinetostatic balance (paper 002's rod and carriage balance, the lever
//! about its pivot O1): the forces at one shaft state with the contact force what the balance
//! leaves for the ramp, and, for the elastodynamic level, the moments left over with the contact
//! force given.

use super::{Drive, Kinematics, Linkage};
use crate::mechanics::hertz::Surface;
use crate::mechanics::{STANDARD_GRAVITY, Scalar, cross, dot, sgn};

/// Forces at one shaft state (any [`Scalar`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Forces<T = f64> {
    /// `pierce.Q` (≥ 0, against the needles' motion).
    pub pierce_q: T,
    /// `perforators.F_inertia`.
    pub f_inertia: T,
    /// `rod.F`, compression positive.
    pub rod_f: T,
    /// Carriage guide normal force (magnitude).
    pub guide_n: T,
    /// `spring.M`.
    pub spring_m: T,
    /// Hinge friction moment reduced to the lever.
    pub joint_m: T,
    /// `roller.F`: contact force the ramp must push with (< 0: lift-off).
    pub roller_f: T,
    /// `roller.sigma_H`.
    pub sigma_h: T,
    /// `table.F`: force on the table along +x_t.
    pub table_f: T,
    /// `shaft.tau`: the perforators' share at the main shaft, `−table.F·dx_t/dφ`.
    pub tau: T,
}

/// The carriage's share of a lever balance ([`Drive::carriage_balance`]).
struct CarriageBalance<T> {
    /// `pierce.Q`, `rod.F` and the guide's normal force.
    qt: T,
    rod: T,
    guide_n: T,
    /// The rod's direction from joint A to B, and its angle's rate per unit Δγ.
    e: (T, T),
    th: T,
    /// The rod's moment on the lever about O1.
    m_rod: T,
}

/// At most this many Newton iterations on the lever's balance with hinge friction
/// ([`Drive::forces_with`]); it takes two or three.
const BALANCE_ITERATIONS: usize = 8;

impl Drive {
    /// Forces (kinetostatic level) for kinematics `k`.
    pub fn forces<T: Scalar>(&self, k: &Kinematics<T>) -> Forces<T> {
        self.forces_with(k, true)
    }

    /// As [`Drive::forces`]; with `hertz` false the Hertz stress is not computed (`sigma_h` 0).
    /// The friction and piercing loads take their directions from the motion `k`, the linkage
    /// is the one as made at the lever angle `k.gamma` (the roller arm as designed). Any
    /// [`Scalar`]: the carriage's guide side, the contact's sign and the profile's shape are
    /// taken on the real parts. The contact force is what the lever's balance about O1 leaves
    /// for the ramp; the hinge friction depends on it, so the balance is solved by Newton's
    /// method from the frictionless force until its step is at the rounding of the force (two
    /// or three iterations: the friction's share of the moment is a few per cent). The roller
    /// is on the ramp here, so its arm about the normal is the linkage's.
    pub fn forces_with<T: Scalar>(&self, k: &Kinematics<T>, hertz: bool) -> Forces<T> {
        let (sv, sw) = (sgn(k.v.re()), sgn(k.gamma_w.re()));
        let link = self.linkage(k.gamma);
        let c = self.carriage_balance(k, &link, sv);
        let spring_m = self.spring_moment(k.gamma);
        let (r, _, _) = link.r;
        let arm = cross(r, k.normal);
        // the lever's balance without the contact: J·Δγ̈ − M_rod − M_spring = F_c·a + M_joint(F_c)
        let m = k.gamma_a * self.made.lever_j - c.m_rod - spring_m;
        let mut fc = m / arm;
        for _ in 0..BALANCE_ITERATIONS {
            let (joint_m, joint_fc) = self.joint_moment_fc(&c, fc, k.normal, sw);
            let step = (fc * arm + joint_m - m) / (arm + joint_fc);
            fc -= step;
            if !(step.re().abs() > 4.0 * f64::EPSILON * fc.re().abs()) {
                break;
            }
        }
        let joint_m = self.joint_moment(&c, fc, k.normal, sw);
        self.forces_of(k, &c, spring_m, joint_m, fc, hertz)
    }

    /// The lever's balance about O1 with the contact force `fc` given (the elastodynamic level:
    /// the penetration makes it): the moment `J·Δγ̈ − M_rod − M_spring − M_joint − F_c·a` left
    /// over at the acceleration `k.gamma_a` (`a` the roller's arm about the ramp normal), zero on
    /// the lever's motion, and the forces there, `roller.F` = `fc`. Nothing is divided by the
    /// arm, which vanishes where the lever swings far off the ramp. Also that moment's
    /// derivative in `fc` (the arm and the hinge friction's share).
    pub fn moment_left<T: Scalar>(
        &self,
        k: &Kinematics<T>,
        link: &Linkage<T>,
        (sv, sw): (f64, f64),
        fc: T,
    ) -> (T, T, Forces<T>) {
        let c = self.carriage_balance(k, link, sv);
        let spring_m = self.spring_moment(k.gamma);
        let (joint_m, joint_fc) = self.joint_moment_fc(&c, fc, k.normal, sw);
        let (r, _, _) = link.r;
        let arm = cross(r, k.normal);
        let left = k.gamma_a * self.made.lever_j - c.m_rod - spring_m - joint_m - fc * arm;
        let forces = self.forces_of(k, &c, spring_m, joint_m, fc, true);
        (left, -joint_fc - arm, forces)
    }

    /// Spring 13's moment on the lever at Δγ, `−(M0 + kt·Δγ)`.
    fn spring_moment<T: Scalar>(&self, g: T) -> T {
        -(g * self.made.spring_kt + self.made.spring_m0)
    }

    /// The carriage along its guide (paper 002's rod and carriage balance): the piercing load,
    /// the rod force and the guide's normal force, and what the lever takes from them.
    fn carriage_balance<T: Scalar>(
        &self,
        k: &Kinematics<T>,
        link: &Linkage<T>,
        sv: f64,
    ) -> CarriageBalance<T> {
        let p = &self.made;
        let m = p.perf_m;
        let g = STANDARD_GRAVITY;
        let (sa, ca) = self.alpha_sin_cos;
        let qt = self.pierce_load(k.s, T::from(sv), k.phase);
        let (a, a1, _) = link.a;
        let pose = link.pose;
        let b = self.made_line.b(pose.s);
        let l1 = self.made_line.l;
        let e = ((b.0 - a.0) / l1, (b.1 - a.1) / l1);
        let (cu, cn) = (pose.cos_nu, pose.sin_nu);
        let kk = k.a_t * m * ca + -m * g * sa;
        let gg = k.a * m + m * g * ca + k.a_t * m * sa + qt * sv;
        let mu = p.guide_mu;
        let mut rod = (gg + kk * (mu * sv)) / (cu - cn * (mu * sv));
        if (rod * cn + kk).re() < 0.0 {
            rod = (gg - kk * (mu * sv)) / (cu + cn * (mu * sv));
        }
        // rod angle rate per unit Δγ: e' = (B' − A')/l1, θ' = e × e'
        let bu = self.made_line.u();
        let e1 = ((pose.ds * bu.0 - a1.0) / l1, (pose.ds * bu.1 - a1.1) / l1);
        CarriageBalance {
            qt,
            rod,
            guide_n: (rod * cn + kk).abs(),
            e,
            th: cross(e, e1),
            m_rod: -rod * cross(a, e),
        }
    }

    /// The hinge friction moment reduced to the lever, against its motion `sw`, with the contact
    /// force `fc` (pin O1 carries the rod's and the contact's forces).
    fn joint_moment<T: Scalar>(&self, c: &CarriageBalance<T>, fc: T, n: (T, T), sw: f64) -> T {
        self.joint_moment_fc(c, fc, n, sw).0
    }

    /// [`Drive::joint_moment`] and its derivative in `fc`.
    fn joint_moment_fc<T: Scalar>(
        &self,
        c: &CarriageBalance<T>,
        fc: T,
        n: (T, T),
        sw: f64,
    ) -> (T, T) {
        let p = &self.made;
        let fr = -sw * p.joint_f * p.joint_r;
        let fo = (c.rod * c.e.0 - fc * n.0, c.rod * c.e.1 - fc * n.1);
        let fo_abs = dot(fo, fo).sqrt();
        let m = (fo_abs + c.rod.abs() * ((T::one() - c.th).abs() + c.th.abs())) * fr;
        let m_fc = if fo_abs.re() > 0.0 {
            -dot(fo, n) / fo_abs * fr
        } else {
            T::zero()
        };
        (m, m_fc)
    }

    /// The forces of a balance.
    fn forces_of<T: Scalar>(
        &self,
        k: &Kinematics<T>,
        c: &CarriageBalance<T>,
        spring_m: T,
        joint_m: T,
        fc: T,
        hertz: bool,
    ) -> Forces<T> {
        let p = &self.made;
        let m = p.perf_m;
        let (sa, _) = self.alpha_sin_cos;
        let sigma_h = if hertz && fc.re() > 0.0 {
            let surface = if k.rho.re() > 0.0 {
                Surface::Convex
            } else {
                Surface::Concave
            };
            p.roller.stress(fc, k.rho.abs(), surface)
        } else {
            T::zero()
        };
        let table_f = -fc * k.normal.0 - (k.a_t + k.a * sa) * m;
        Forces {
            pierce_q: c.qt,
            f_inertia: (k.a + k.a_t * sa) * -m,
            rod_f: c.rod,
            guide_n: c.guide_n,
            spring_m,
            joint_m,
            roller_f: fc,
            sigma_h,
            table_f,
            tau: -table_f * k.x_t_d,
        }
    }
}
