//! Pure mechanics of the disc-knife drive (paper 004, `disc-knife-drive.md`).
//!
//! # Geometry and symbols
//! Origin at the crank axis A, x along the guide of slider 5, y across it (the block is fed
//! along −y). Crank 3 (length l1) turns with the shaft: crank pin B = l1·(cos φ, sin φ).
//! Rod 4 (l2 = λ2·l1) joins B to slider 5 at C = (x_C, e) ([`SliderCrank`], paper 004 eq. 1 in
//! its exact form `x_C = l1·cos φ + √(l2² − (l1·sin φ − e)²)`, or the paper's series form with
//! `kinematics.series`). Knife holder 6 is hinged to slider 5 at C and to slider 7 at
//! D = C + l4·(cos β, sin β) (eq. 6); slider 7 slides along the support line EQ through
//! Q = (x_Q, y_Q), direction `u = (sin α, cos α)` (α from the vertical, eq. 5). The knives work at
//! S = C + l_S·l4·(cos β, sin β) (eq. 8, l_S = `holder.lS`).
//!
//! # Holder angle (eq. 5)
//! D on EQ: `(x_D − x_Q)·cos α − (y_D − y_Q)·sin α = 0`, i.e.
//! `cos(β + α) = c`, `c = ((x_Q − x_C)·cos α − (y_Q − e)·sin α)/l4`, and
//! `β = −α + b·arccos c`, b = `assembly.branch` (±1). For e = 0 this is the spec's
//! `c = cos α·K`, `K = (x_Q − tan α·y_Q − x_C)/l4`; the spec's K leaves out e, which would put D off
//! EQ for e ≠ 0 (test `support_point_stays_on_eq_with_eccentricity`). The holder assembles only
//! where |c| < 1; at |c| = 1 CD is normal to EQ (a dead point: β̇ unbounded and the force system
//! singular). [`Params::validate`] scans the turn for it.
//!
//! # Derivatives
//! x_C and its φ-derivatives come from [`SliderCrank`] (closed forms, or the differentiated
//! series, eqs. 2–4); β, D and S are computed once by generic code ([`Params::holder`]) that runs
//! on second-order dual numbers (`num_dual::Dual2`) seeded with (x_C, x_C', x_C''): exact first
//! and second φ-derivatives, no differencing. Time derivatives by the chain rule
//! (`interface.md`): `q̇ = q'·ω`, `q̈ = q''·ω² + q'·ε`.
//!
//! # Working stroke
//! `knife.working` is true while slider C moves to +x (ẋ_C > 0: for ω > 0 and e = 0, crank angles
//! π < φ < 2π). Only then the cutting force acts.
//!
//! # Kinetostatics: one planar Newton–Euler system per instant
//! Bodies and masses (assumption where the paper is silent; `rod.m` lumped half at the crank pin
//! B, half at C):
//! - crank 3 with half the rod: `J_A = crank.J + rod.m/2·l1²` about A; the crank's own centre of
//!   mass is on the axis A;
//! - slider 5 with half the rod: `m5 = slider5.m + rod.m/2` at C, on its guide y = e;
//! - slider 7: `slider7.m` at D, on EQ;
//! - holder 6 with its knives: `holder.m` at S, `holder.J` about S.
//!
//! Gravity `gravity.g` acts along −y on every mass (default 0: the mechanism works in a
//! horizontal plane, its weights carried out of plane).
//!
//! Unknowns `z = [P, C_x, C_y, D_x, D_y, N5, N7]`:
//! - `P` (`rod.F`): rod force, **compression positive**: the rod pushes C with `P·ĉ`,
//!   `ĉ = (C − B)/|C − B|` (from the crank pin towards C), and the crank pin with `−P·ĉ`;
//! - `(C_x, C_y)`: force of slider 5 on the holder at hinge C (the holder pushes slider 5 with
//!   the opposite); `pinC.F = |(C_x, C_y)|`;
//! - `(D_x, D_y)`: force of slider 7 on the holder at hinge D; `pinD.F = |(D_x, D_y)|`;
//! - `N5` (`guide.N`): normal force of the guide on slider 5, along +y;
//! - `N7` (`support.N`): normal force of EQ on slider 7, along `n = (cos α, −sin α)`.
//!
//! Coulomb friction opposes each slider's velocity: on slider 5 `−μ5·|N5|·sgn(ẋ_C)` along x, on
//! slider 7 `−μ7·|N7|·sgn(v_D·u)` along u (0 when the slider stands: static friction is not
//! modelled). With `|N| = σ·N` for an assumed sign σ the system is linear:
//!
//! | row | equation |
//! | --- | --- |
//! | slider 5, x | `P·ĉ_x − C_x − k5·N5 = m5·ẍ_C` |
//! | slider 5, y | `P·ĉ_y − C_y + N5 = m5·g` |
//! | slider 7, x | `−D_x + N7·(n_x − k7·u_x) = m7·a_Dx` |
//! | slider 7, y | `−D_y + N7·(n_y − k7·u_y) = m7·(a_Dy + g)` |
//! | holder, x | `C_x + D_x = m_h·a_Sx − F_x` |
//! | holder, y | `C_y + D_y = m_h·(a_Sy + g) − F_y` |
//! | holder, moment about S / l4 | `((C − S) × (C_x, C_y) + (D − S) × (D_x, D_y))/l4 = J_h·β̈/l4` |
//!
//! with `k5 = μ5·σ5·sgn(ẋ_C)`, `k7 = μ7·σ7·sgn(v_D·u)` and `F = (F_x, F_y)` the cutting force at S.
//! The frictionless system is solved once, by its structure ([`Params::solve_system`]: the
//! hinge forces and N5 eliminated by the rows they stand in, a 2×2 system in P and N7 left); its
//! normal-force signs give σ; friction adds two rank-one terms ([`super::friction`]), so each
//! sign combination's solution and determinant follow from that one solve, and the other
//! combinations are tried until the solution agrees with its σ. The system is a piecewise-linear map of z; where every sign
//! combination gives a determinant of the sign the frictionless one has, that map is a bijection
//! (coherent orientation), so exactly one combination agrees.
//!
//! Where some combination flips that sign, Coulomb friction **self-locks** a slider: the force
//! system has no solution for some loads and two for others. For slider 7 this happens where CD
//! is within the friction angle of EQ's normal, `|tan(β + α)| < support.mu` (the determinant's
//! factor `−sin(β + α) ∓ k7·cos(β + α)` changes sign), i.e. near the holder's dead point. The
//! spec's defaults (α = 45°, μ = 0.1) do this for 174.63° < φ < 185.37°: the drive would wedge
//! there and, leaving that zone in the working stroke, the forces rise steeply (the wedge
//! effect). Such an instant is flagged (`sliders.locked`, a warning in the log) and its forces
//! are computed without friction, a lower bound; a parameter set is not refused for it.
//!
//! Cutting force (assumption, spec): magnitude `cut.F` at S during the working stroke, opposing
//! the velocity of S relative to the block, `v_rel = v_S − (0, −V) = (v_Sx, v_Sy + V)`;
//! `F = −cut.F·v_rel/|v_rel|`; 0 in the idle stroke.
//!
//! Crank (moment about A of crank 3 with the rod's half at B):
//! `τ = J_A·ε + P·(B × ĉ) + rod.m/2·g·l1·cos φ`; the crank sits on the shaft, so
//! `shaft.tau = τ` and `shaft.P = τ·ω`.

use super::friction::{
    friction_columns, friction_det, friction_sign_search, sign_combinations, with_friction,
};
use crate::mechanics::slider_crank::SliderCrank;
use crate::mechanics::{
    ParamError, Scalar, check_finite, check_non_negative, check_positive, sgn, wrap_angle_of,
};
use nalgebra::Vector2;
use num_dual::{Dual2, DualNum};
use std::f64::consts::{PI, TAU};

/// A point or vector in the plane of the mechanism, m (or m/s, m/s², N); of dual numbers for
/// the partial derivatives.
pub type Vec2<T = f64> = Vector2<T>;

/// A [`Scalar`] the outputs are computed in: `f64`, and the dual numbers of the partial
/// derivatives (with num-dual's nalgebra traits; the force system's pivots are chosen on the
/// values, so the values are the `f64` solve's).
pub trait LinScalar: Scalar + nalgebra::ComplexField {}
impl<T: Scalar + nalgebra::ComplexField> LinScalar for T {}

/// Parameters of the disc-knife drive, SI units (`disc-knife-drive.md`, table "Parameters").
/// Field docs name the FMI variable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// `crank.l1`: crank length l1, m (assumption 0.019).
    pub crank_l1: f64,
    /// `rod.lambda2`: λ2 = l2/l1 (paper 004: 2).
    pub rod_lambda2: f64,
    /// `crank.e`: eccentricity e of slider 5's guide, m (paper 004: 0).
    pub crank_e: f64,
    /// `holder.l4`: holder length CD, m (assumption 0.022).
    pub holder_l4: f64,
    /// `holder.lS`: fraction of l4 from C to the knife point S (paper 004's example: 0.5).
    pub holder_ls: f64,
    /// `support.alpha`: angle α of the support line EQ from the vertical, rad (paper: 45°…70°).
    pub support_alpha: f64,
    /// `support.xQ`: x of point Q on EQ, m (assumption 0.060).
    pub support_xq: f64,
    /// `support.yQ`: y of point Q on EQ, m (assumption 0.010).
    pub support_yq: f64,
    /// `assembly.branch`: +1 or −1, which of the two holder positions (default +1).
    pub branch: i32,
    /// `kinematics.series`: use the paper's series form (1) for x_C (default false).
    pub series: bool,
    /// `holder.m`: holder and knives, at S, kg (assumption 0.8).
    pub holder_m: f64,
    /// `holder.J`: moment of inertia of holder and knives about S, kg·m² (assumption 0: the spec
    /// lumps the holder at S).
    pub holder_j: f64,
    /// `slider5.m`, kg (assumption 0.3).
    pub slider5_m: f64,
    /// `slider7.m`, kg (assumption 0.2).
    pub slider7_m: f64,
    /// `rod.m`: rod mass, half at the crank pin, half at C, kg (assumption 0.15).
    pub rod_m: f64,
    /// `crank.J`: crank's moment of inertia about A, kg·m² (assumption 2e-4).
    pub crank_j: f64,
    /// `guide.mu`: Coulomb friction of slider 5 in its guide (assumption 0.1).
    pub guide_mu: f64,
    /// `support.mu`: Coulomb friction of slider 7 on EQ (assumption 0.1).
    pub support_mu: f64,
    /// `cut.F`: cutting force at S during the working stroke, N (assumption 150).
    pub cut_f: f64,
    /// `feed.V`: feed speed of the block along −y, m/s (assumption 0.2).
    pub feed_v: f64,
    /// `gravity.g`: gravity along −y, m/s² (assumption 0: horizontal plane).
    pub gravity_g: f64,
    /// `drive.n`: nominal shaft speed, rad/s (assumption 300 rpm).
    pub drive_n: f64,
}

impl Default for Params {
    /// The spec's defaults (`disc-knife-drive.md`).
    fn default() -> Self {
        Self {
            crank_l1: 0.019,
            rod_lambda2: 2.0,
            crank_e: 0.0,
            holder_l4: 0.022,
            holder_ls: 0.5,
            support_alpha: PI / 4.0,
            support_xq: 0.060,
            support_yq: 0.010,
            branch: 1,
            series: false,
            holder_m: 0.8,
            holder_j: 0.0,
            slider5_m: 0.3,
            slider7_m: 0.2,
            rod_m: 0.15,
            crank_j: 2e-4,
            guide_mu: 0.1,
            support_mu: 0.1,
            cut_f: 150.0,
            feed_v: 0.2,
            gravity_g: 0.0,
            drive_n: PI * (300.0 / 30.0), // 300 rpm, bit-identical to the FMU start value
        }
    }
}

/// Positions, velocities and accelerations at one shaft state. `_d`/`_dd` are derivatives in the
/// crank angle φ; `v_`/`a_`, `_w`/`_eps` time derivatives. Any [`Scalar`] (`f64`, or dual
/// numbers along the inputs for the partial derivatives).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kinematics<T = f64> {
    /// Crank angle within the turn, `φ mod 2π`, rad.
    pub phi: T,
    /// Shaft speed ω, rad/s.
    pub w: T,
    /// Shaft acceleration ε, rad/s².
    pub eps: T,
    /// Crank pin B, m.
    pub b: Vec2<T>,
    /// `slider.x`: x_C, m.
    pub x_c: T,
    /// dx_C/dφ, m/rad.
    pub x_c_d: T,
    /// d²x_C/dφ², m/rad².
    pub x_c_dd: T,
    /// `slider.v`: ẋ_C, m/s.
    pub v_c: T,
    /// `slider.a`: ẍ_C, m/s².
    pub a_c: T,
    /// Unit vector from B towards C, along the rod.
    pub rod_dir: Vec2<T>,
    /// `c = cos(β + α)` of eq. 5 (the spec's cos α·K); |c| < 1 where the holder assembles.
    pub c: T,
    /// `holder.beta`: β, rad.
    pub beta: T,
    /// dβ/dφ.
    pub beta_d: T,
    /// d²β/dφ², 1/rad.
    pub beta_dd: T,
    /// `holder.w`: β̇, rad/s.
    pub beta_w: T,
    /// `holder.eps`: β̈, rad/s².
    pub beta_eps: T,
    /// `support.x`, `support.y`: point D, m.
    pub d: Vec2<T>,
    /// dD/dφ, m/rad.
    pub d_d: Vec2<T>,
    /// d²D/dφ², m/rad².
    pub d_dd: Vec2<T>,
    /// Velocity of D, m/s.
    pub v_d: Vec2<T>,
    /// Acceleration of D, m/s².
    pub a_d: Vec2<T>,
    /// `knife.x`, `knife.y`: point S, m.
    pub s: Vec2<T>,
    /// dS/dφ, m/rad.
    pub s_d: Vec2<T>,
    /// d²S/dφ², m/rad².
    pub s_dd: Vec2<T>,
    /// `knife.vx`, `knife.vy`, m/s.
    pub v_s: Vec2<T>,
    /// `knife.ax`, `knife.ay`, m/s².
    pub a_s: Vec2<T>,
    /// `knife.working`: the working stroke, ẋ_C > 0.
    pub working: bool,
}

/// Forces and torques at one shaft state (level `kinetostatic`); signs as in the module docs.
/// Any [`Scalar`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Forces<T = f64> {
    /// `cut.Fx`, `cut.Fy`: cutting force on the holder at S, N.
    pub cut: Vec2<T>,
    /// `rod.F`: rod force P, compression positive, N.
    pub rod_f: T,
    /// Force of slider 5 on the holder at C, N (`pinC.F` is its magnitude).
    pub pin_c: Vec2<T>,
    /// Force of slider 7 on the holder at D, N (`pinD.F` is its magnitude).
    pub pin_d: Vec2<T>,
    /// `guide.N`: normal force of the guide on slider 5, along +y, N.
    pub guide_n: T,
    /// `support.N`: normal force of EQ on slider 7, along (cos α, −sin α), N.
    pub support_n: T,
    /// Friction force on slider 5 along +x, N.
    pub guide_friction: T,
    /// Friction force on slider 7 along u = (sin α, cos α), N.
    pub support_friction: T,
    /// `sliders.locked`: Coulomb friction self-locks a slider at this instant (no unique solution
    /// of the force system); the forces are then those without friction.
    pub locked: bool,
    /// `shaft.tau`: torque the shaft applies to the crank, N·m.
    pub shaft_tau: T,
    /// `shaft.P = τ·ω`, W.
    pub shaft_p: T,
}

/// Where a parameter set cannot assemble: the first interval of crank angles (from φ = 0 on)
/// with |c| ≥ 1, its boundaries refined by bisection, and the worst |c| found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AssemblyFailure {
    /// First crank angle where the holder cannot assemble, rad (negative when the interval runs
    /// through φ = 0).
    pub from: f64,
    /// Last crank angle where it cannot, rad (> `from`).
    pub to: f64,
    /// The largest |c| of the scan (> 1).
    pub worst: f64,
    /// The crank angle of that largest |c|, rad.
    pub worst_at: f64,
}

/// 2-D cross product (z component; any [`Scalar`]).
#[inline]
fn cross<T: Scalar>(a: Vec2<T>, b: Vec2<T>) -> T {
    a.x * b.y - a.y * b.x
}

/// `|v|`, as nalgebra's `norm` computes it for `f64` (`√(x² + y²)`; any [`Scalar`]).
#[inline]
pub fn norm<T: Scalar>(v: Vec2<T>) -> T {
    (v.x * v.x + v.y * v.y).sqrt()
}

/// `a·b` as nalgebra's `dot` computes it for `f64` (any [`Scalar`]).
#[inline]
pub fn dot<T: Scalar>(a: Vec2<T>, b: Vec2<T>) -> T {
    a.x * b.x + a.y * b.y
}

/// `v·f` by components (any [`Scalar`]).
#[inline]
fn scaled<T: Scalar>(v: Vec2<T>, f: T) -> Vec2<T> {
    Vec2::new(v.x * f, v.y * f)
}

/// Samples of the assembly scan per turn.
const SCAN: usize = 7200;

impl Params {
    /// `rod.l2 = λ2·l1`, m (calculated parameter).
    pub fn rod_l2(&self) -> f64 {
        self.rod_lambda2 * self.crank_l1
    }

    /// The slider-crank 3-4-5 (shared mechanics).
    pub fn slider_crank(&self) -> SliderCrank {
        SliderCrank::offset(self.crank_l1, self.rod_l2(), self.crank_e)
    }

    /// `slider.stroke`: stroke of slider 5, m (calculated parameter; 2·l1 for e = 0).
    pub fn stroke(&self) -> f64 {
        self.slider_crank().stroke()
    }

    /// Translating mass at C: `slider5.m + rod.m/2`, kg.
    pub fn mass_c(&self) -> f64 {
        self.slider5_m + 0.5 * self.rod_m
    }

    /// Rotating inertia about A: `crank.J + rod.m/2·l1²`, kg·m².
    pub fn inertia_a(&self) -> f64 {
        self.crank_j + 0.5 * self.rod_m * self.crank_l1 * self.crank_l1
    }

    /// Unit vector u = (sin α, cos α) along EQ.
    pub fn support_dir(&self) -> Vec2 {
        let (sa, ca) = self.support_alpha.sin_cos();
        Vec2::new(sa, ca)
    }

    /// Unit normal n = (cos α, −sin α) of EQ (the direction of `support.N`).
    pub fn support_normal(&self) -> Vec2 {
        let (sa, ca) = self.support_alpha.sin_cos();
        Vec2::new(ca, -sa)
    }

    /// x_C with dx_C/dφ and d²x_C/dφ² at crank angle `phi`: exact ([`SliderCrank::pose`]) or,
    /// with `kinematics.series`, the paper's series form (1) ([`SliderCrank::x_series`]).
    /// Any [`Scalar`].
    #[inline]
    pub fn slider_x<T: Scalar>(&self, phi: T) -> (T, T, T) {
        let sc = self.slider_crank();
        if self.series {
            sc.x_series(phi)
        } else {
            let p = sc.pose(phi);
            (p.x, p.dx, p.ddx)
        }
    }

    /// `c = cos(β + α)` of eq. 5 for slider position `x_c` (generic: also on dual numbers).
    #[inline]
    pub fn assembly_cos<D: DualNum<Primitive = f64> + Copy>(&self, x_c: D) -> D {
        let (sa, ca) = self.support_alpha.sin_cos();
        let l4 = self.holder_l4;
        (-x_c + self.support_xq) * (ca / l4) - (self.support_yq - self.crank_e) * sa / l4
    }

    /// β, D and S for slider position `x_c` (eqs. 5, 6, 8), generic over the number type so the
    /// same code gives exact derivatives on dual numbers. NaN where |c| > 1.
    #[inline]
    pub fn holder<D: DualNum<Primitive = f64> + Copy>(&self, x_c: D) -> (D, [D; 2], [D; 2]) {
        let c = self.assembly_cos(x_c);
        let beta = c.acos() * f64::from(self.branch) - self.support_alpha;
        let (sb, cb) = beta.sin_cos();
        let (l4, ls) = (self.holder_l4, self.holder_ls * self.holder_l4);
        let e = self.crank_e;
        (
            beta,
            [x_c + cb * l4, sb * l4 + e],
            [x_c + cb * ls, sb * ls + e],
        )
    }

    /// Positions, velocities and accelerations at shaft angle `phi` (any real value), speed `w`
    /// and acceleration `eps` (any [`Scalar`]: the same operations on `f64` and on the dual
    /// numbers of the partial derivatives).
    #[inline]
    pub fn kinematics<T: Scalar>(&self, phi: T, w: T, eps: T) -> Kinematics<T> {
        let phi = wrap_angle_of(phi);
        self.assemble(phi, self.slider_x(phi), w, eps)
    }

    /// The kinematics at crank angle `phi` (in one turn) for the slider position `x` with its
    /// derivatives `x1`, `x2` in a driving variable whose rate is `w` and acceleration `eps`:
    /// for the rigid drive x_C(φ) with φ-derivatives and the shaft's ω, ε; for the elastic level
    /// ([`crate::mechanisms::disc_knife_drive::elastic`]) the slider's own x, ẋ, ẍ with w = 1,
    /// eps = 0 (time itself is the variable). One body of code for both; any [`Scalar`].
    #[inline]
    pub fn assemble<T: Scalar>(
        &self,
        phi: T,
        (x, x1, x2): (T, T, T),
        w: T,
        eps: T,
    ) -> Kinematics<T> {
        let (beta, d, s) = self.holder(Dual2::new(x, x1, x2));
        let c = self.assembly_cos(x);
        let (sp, cp) = phi.sin_cos();
        let b = Vec2::new(cp * self.crank_l1, sp * self.crank_l1);
        let rod = Vec2::new(x - b.x, T::from(self.crank_e) - b.y);
        let l = norm(rod);
        let rod_dir = Vec2::new(rod.x / l, rod.y / l);
        let w2 = w * w;
        let vel = |d1: T| d1 * w;
        let acc = |d1: T, d2: T| d2 * w2 + d1 * eps;
        let pt = |p: [Dual2<T>; 2]| {
            let d1 = Vec2::new(p[0].v1, p[1].v1);
            let d2 = Vec2::new(p[0].v2, p[1].v2);
            (
                Vec2::new(p[0].re, p[1].re),
                d1,
                d2,
                Vec2::new(vel(d1.x), vel(d1.y)),
                Vec2::new(acc(d1.x, d2.x), acc(d1.y, d2.y)),
            )
        };
        let (d, d_d, d_dd, v_d, a_d) = pt(d);
        let (s, s_d, s_dd, v_s, a_s) = pt(s);
        let v_c = vel(x1);
        Kinematics {
            phi,
            w,
            eps,
            b,
            x_c: x,
            x_c_d: x1,
            x_c_dd: x2,
            v_c,
            a_c: acc(x1, x2),
            rod_dir,
            c,
            beta: beta.re,
            beta_d: beta.v1,
            beta_dd: beta.v2,
            beta_w: vel(beta.v1),
            beta_eps: acc(beta.v1, beta.v2),
            d,
            d_d,
            d_dd,
            v_d,
            a_d,
            s,
            s_d,
            s_dd,
            v_s,
            a_s,
            working: v_c.re() > 0.0,
        }
    }

    /// Cutting force on the holder at S (module docs): `−cut.F·v_rel/|v_rel|` in the working
    /// stroke, 0 otherwise (and 0 if S stands still relative to the block).
    /// Any [`Scalar`].
    #[inline]
    pub fn cut_force<T: Scalar>(&self, k: &Kinematics<T>) -> Vec2<T> {
        let v_rel = Vec2::new(k.v_s.x, k.v_s.y + self.feed_v);
        let n = norm(v_rel);
        if k.working && n.re() > 0.0 {
            scaled(v_rel, T::from(-self.cut_f) / n)
        } else {
            Vec2::new(T::zero(), T::zero())
        }
    }

    /// The holder's hinges C and D seen from S over l4, `(C − S)/l4` and `(D − S)/l4`: the arms
    /// of the hinge forces in the holder's moment row (module docs).
    #[inline]
    fn holder_arms<T: DualNum<Primitive = f64> + Copy>(
        &self,
        c: [T; 2],
        d: [T; 2],
        s: [T; 2],
    ) -> ([T; 2], [T; 2]) {
        let inv_l4 = 1.0 / self.holder_l4;
        (
            [(c[0] - s[0]) * inv_l4, (c[1] - s[1]) * inv_l4],
            [(d[0] - s[0]) * inv_l4, (d[1] - s[1]) * inv_l4],
        )
    }

    /// The module docs' 7×7 matrix with the first column `col0` (the rod force P's
    /// coefficients at the kinetostatic level; the slider's acceleration's at the elastic level)
    /// and the holder's points C, D, S. The models solve it by its structure
    /// ([`Params::solve_system`]); the tests take it as the reference, with friction too.
    #[inline]
    pub fn system_matrix<T: DualNum<Primitive = f64> + Copy>(
        &self,
        col0: [T; 7],
        c: [T; 2],
        d: [T; 2],
        s: [T; 2],
        k5: T,
        k7: T,
    ) -> [[T; 7]; 7] {
        let (u, n) = (self.support_dir(), self.support_normal());
        let (r_c, r_d) = self.holder_arms(c, d, s);
        let (o, l) = (T::zero(), T::one());
        let f = T::from;
        [
            [col0[0], -l, o, o, o, -k5, o],
            [col0[1], o, -l, o, o, l, o],
            [col0[2], o, o, -l, o, o, f(n.x) - k7 * u.x],
            [col0[3], o, o, o, -l, o, f(n.y) - k7 * u.y],
            [col0[4], l, o, l, o, o, o],
            [col0[5], o, l, o, l, o, o],
            [col0[6], -r_c[1], r_c[0], -r_d[1], r_d[0], o, o],
        ]
    }

    /// The module docs' system without friction ([`Params::system_matrix`] with `k5 = k7 = 0`)
    /// solved for each right-hand side of `bs`, by its structure: the hinge forces C, D and N5
    /// each stand with a unit coefficient in one row, so eliminating them leaves two equations
    /// in `z0` (P, or ẍ at the elastic level) and N7 (`cᵢ = col0[i]`, `bᵢ` a right-hand side,
    /// `r_C = (C − S)/l4`, `r_D = (D − S)/l4`):
    /// - the chain's balance along x (rows slider 5 x + slider 7 x + holder x):
    ///   `(c0 + c2 + c4)·z0 + n_x·N7 = b0 + b2 + b4`;
    /// - the holder's moment with `C_x = c0·z0 − b0`, `D_x = c2·z0 + n_x·N7 − b2`,
    ///   `D_y = c3·z0 + n_y·N7 − b3` and `C_y = b5 − c5·z0 − D_y`:
    ///   `(c6 − r_Cy·c0 − r_Cx·(c3 + c5) − r_Dy·c2 + r_Dx·c3)·z0 + ((r_Dx − r_Cx)·n_y − r_Dy·n_x)·N7
    ///   = b6 − r_Cy·b0 − r_Cx·(b3 + b5) − r_Dy·b2 + r_Dx·b3`;
    ///
    /// then `N5 = b1 − c1·z0 + C_y`. About 60 operations a right-hand side where Gaussian
    /// elimination of the 7×7 matrix takes some 800 (test
    /// `the_structured_solve_is_the_elimination`). `None` where the 2×2 determinant is 0 or not
    /// finite (the holder's dead point, or a holder that does not assemble). Generic, so that
    /// the elastic level differentiates it exactly on dual numbers.
    #[inline]
    pub fn solve_system<T: DualNum<Primitive = f64> + Copy, const M: usize>(
        &self,
        col0: [T; 7],
        c: [T; 2],
        d: [T; 2],
        s: [T; 2],
        bs: [[T; 7]; M],
    ) -> Option<[[T; 7]; M]> {
        let n = self.support_normal();
        let (r_c, r_d) = self.holder_arms(c, d, s);
        let [c0, c1, c2, c3, c4, c5, c6] = col0;
        let (a11, a12) = (c0 + c2 + c4, n.x);
        let a21 = c6 - r_c[1] * c0 - r_c[0] * (c3 + c5) - r_d[1] * c2 + r_d[0] * c3;
        let a22 = (r_d[0] - r_c[0]) * n.y - r_d[1] * n.x;
        let det = a11 * a22 - a21 * a12;
        if det.re() == 0.0 || !det.re().is_finite() {
            return None;
        }
        Some(bs.map(|[b0, b1, b2, b3, b4, b5, b6]| {
            let r1 = b0 + b2 + b4;
            let r2 = b6 - r_c[1] * b0 - r_c[0] * (b3 + b5) - r_d[1] * b2 + r_d[0] * b3;
            let z0 = (r1 * a22 - r2 * a12) / det;
            let n7 = (a11 * r2 - a21 * r1) / det;
            let (dx, dy) = (c2 * z0 + n7 * n.x - b2, c3 * z0 + n7 * n.y - b3);
            let cy = b5 - c5 * z0 - dy;
            [z0, c0 * z0 - b0, cy, dx, dy, b1 - c1 * z0 + cy, n7]
        }))
    }

    /// The module docs' right-hand side: inertia forces of slider 5 (acceleration `a_c` along
    /// x), slider 7 (`a_d`), the holder (`a_s` at S, `beta_eps`) with the weights and the
    /// external force `load` at S. Generic (see [`Params::system_matrix`]).
    #[inline]
    pub fn system_rhs<T: DualNum<Primitive = f64> + Copy>(
        &self,
        a_c: T,
        a_d: [T; 2],
        a_s: [T; 2],
        beta_eps: T,
        load: Vec2<T>,
    ) -> [T; 7] {
        let g = self.gravity_g;
        let (m5, m7, mh) = (self.mass_c(), self.slider7_m, self.holder_m);
        [
            a_c * m5,
            T::from(m5 * g),
            a_d[0] * m7,
            (a_d[1] + g) * m7,
            a_s[0] * mh - load.x,
            (a_s[1] + g) * mh - load.y,
            beta_eps * self.holder_j / self.holder_l4,
        ]
    }

    /// Crank torque (module docs): `τ = J_A·ε + P·(B × ĉ) + rod.m/2·g·l1·cos φ` for a rod force
    /// `p` along `rod_dir` (from the crank pin B towards C).
    /// Any [`Scalar`].
    #[inline]
    pub fn crank_torque<T: Scalar>(&self, k: &Kinematics<T>, p: T, rod_dir: Vec2<T>) -> T {
        k.eps * self.inertia_a()
            + p * cross(k.b, rod_dir)
            + k.b.x * (0.5 * self.rod_m * self.gravity_g)
    }

    /// Signs of the slider velocities, `(sgn ẋ_C, sgn v_D·u)`, from the φ-derivatives and the
    /// sign of ω (so the same at every speed of one direction).
    /// Any [`Scalar`] (the signs of the values).
    #[inline]
    pub fn slip_signs<T: Scalar>(&self, k: &Kinematics<T>, w_sign: f64) -> (f64, f64) {
        let u = self.support_dir();
        (
            sgn(k.x_c_d.re()) * w_sign,
            sgn(dot(k.d_d.map(|x| x.re()), u)) * w_sign,
        )
    }

    /// Forces and torques at kinematics `k` with the cutting force of [`Params::cut_force`].
    /// Any [`LinScalar`].
    #[inline]
    pub fn kinetostatics<T: LinScalar>(&self, k: &Kinematics<T>) -> Forces<T> {
        self.kinetostatics_with_load(k, self.cut_force(k))
    }

    /// Forces and torques at kinematics `k` with an external force `load` on the holder at S
    /// (the module docs' system). Needs validated parameters. Any [`LinScalar`]: the friction
    /// signs, the self-locking and the sign search decided on the values.
    pub fn kinetostatics_with_load<T: LinScalar>(
        &self,
        k: &Kinematics<T>,
        load: Vec2<T>,
    ) -> Forces<T> {
        let rhs = self.system_rhs(
            k.a_c,
            [k.a_d.x, k.a_d.y],
            [k.a_s.x, k.a_s.y],
            k.beta_eps,
            load,
        );
        // one solve of the frictionless system for z0 and what friction adds to it
        let cd = k.rod_dir;
        let o = T::zero();
        let [e0, w] = friction_columns(self.support_dir());
        let solved = self.solve_system(
            [cd.x, cd.y, o, o, o, o, o],
            [k.x_c, T::from(self.crank_e)],
            [k.d.x, k.d.y],
            [k.s.x, k.s.y],
            [rhs, e0, w],
        );
        let (s5, s7) = self.slip_signs(k, sgn(k.w.re()));
        let (f5, f7) = (self.guide_mu * s5, self.support_mu * s7);
        let friction = f5 != 0.0 || f7 != 0.0;
        let (z, k5, k7, locked) = match solved {
            // a singular frictionless system (the holder's dead point): no solution
            None => ([T::from(f64::NAN); 7], 0.0, 0.0, friction),
            Some(solved) => {
                let det = |k5: f64, k7: f64| friction_det(&solved[1], &solved[2], o + k5, o + k7);
                let locked = friction
                    && sign_combinations(1.0, 1.0)
                        .iter()
                        .any(|&(a5, a7)| det(f5 * a5, f7 * a7).re() <= 0.0);
                if !friction || locked {
                    (solved[0], 0.0, 0.0, locked)
                } else {
                    let (z, k5, k7) = friction_sign_search(solved[0], f5, f7, |k5, k7| {
                        with_friction(&solved, o + k5, o + k7)
                    });
                    (z, k5, k7, false)
                }
            }
        };
        let (p, n5, n7) = (z[0], z[5], z[6]);
        let tau = self.crank_torque(k, p, k.rod_dir);
        Forces {
            cut: load,
            rod_f: p,
            pin_c: Vec2::new(z[1], z[2]),
            pin_d: Vec2::new(z[3], z[4]),
            guide_n: n5,
            support_n: n7,
            guide_friction: n5 * (-k5),
            support_friction: n7 * (-k7),
            locked,
            shaft_tau: tau,
            shaft_p: tau * k.w,
        }
    }

    /// Kinetic energy, J: `½·J_A·ω² + ½·m5·ẋ_C² + ½·m7·|v_D|² + ½·m_h·|v_S|² + ½·J_h·β̇²`
    /// (rod lumped half at B, half at C).
    pub fn kinetic_energy(&self, k: &Kinematics) -> f64 {
        0.5 * (self.inertia_a() * k.w * k.w
            + self.mass_c() * k.v_c * k.v_c
            + self.slider7_m * k.v_d.norm_squared()
            + self.holder_m * k.v_s.norm_squared()
            + self.holder_j * k.beta_w * k.beta_w)
    }

    /// Potential energy of the weights, J: `g·(rod.m/2·y_B + m5·e + m7·y_D + m_h·y_S)`.
    pub fn potential_energy(&self, k: &Kinematics) -> f64 {
        self.gravity_g
            * (0.5 * self.rod_m * k.b.y
                + self.mass_c() * self.crank_e
                + self.slider7_m * k.d.y
                + self.holder_m * k.s.y)
    }

    /// |c| at crank angle `phi` (NaN-free for a crank that turns).
    fn abs_c(&self, phi: f64) -> f64 {
        self.assembly_cos(self.slider_x(phi).0).abs()
    }

    /// Scans the turn (7200 samples, then bisection to 1e-12 rad) for crank angles where the
    /// holder cannot assemble (|c| ≥ 1); `None` if it assembles everywhere. Reports the interval
    /// holding the first failing sample from φ = 0 on; its start is negative when the interval
    /// runs through φ = 0.
    pub fn assembly_failure(&self) -> Option<AssemblyFailure> {
        let at = |j: isize| TAU * j as f64 / SCAN as f64;
        let bad_at = |phi: f64| self.abs_c(phi) >= 1.0;
        let bad: Vec<bool> = (0..SCAN as isize).map(|j| bad_at(at(j))).collect();
        let is_bad = |j: isize| bad[j.rem_euclid(SCAN as isize) as usize];
        let first = bad.iter().position(|&b| b)? as isize;
        let (mut worst, mut worst_at) = (0.0, 0.0);
        for j in 0..SCAN as isize {
            let c = self.abs_c(at(j));
            if c > worst {
                (worst, worst_at) = (c, at(j));
            }
        }
        if bad.iter().all(|&b| b) {
            return Some(AssemblyFailure {
                from: 0.0,
                to: TAU,
                worst,
                worst_at,
            });
        }
        // The boundary between a good and a bad angle, by bisection.
        let refine = |mut good: f64, mut badp: f64| {
            while (badp - good).abs() > 1e-12 {
                let mid = 0.5 * (good + badp);
                if bad_at(mid) { badp = mid } else { good = mid }
            }
            badp
        };
        let (mut j0, mut j1) = (first, first);
        while is_bad(j0 - 1) {
            j0 -= 1;
        }
        while is_bad(j1 + 1) {
            j1 += 1;
        }
        Some(AssemblyFailure {
            from: refine(at(j0 - 1), at(j0)),
            to: refine(at(j1 + 1), at(j1)),
            worst,
            worst_at,
        })
    }

    /// Checks every parameter and that the drive assembles and runs on the whole turn; the first
    /// violation found.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_positive(
            "crank.l1",
            self.crank_l1,
            "the crank length must be positive",
        )?;
        check_finite(&[("crank.e", self.crank_e)])?;
        crate::require!(
            self.slider_crank().can_turn() && self.rod_lambda2.is_finite(),
            "rod.lambda2",
            self.rod_lambda2,
            "the rod l2 = lambda2*l1 must be longer than crank.l1 + |crank.e| = {} m for the crank to turn",
            self.crank_l1 + self.crank_e.abs()
        );
        crate::require!(
            !self.series || self.crank_e == 0.0,
            "crank.e",
            self.crank_e,
            "the series form (1) of paper 004 holds for e = 0 only: set crank.e = 0 or kinematics.series = false"
        );
        check_positive(
            "holder.l4",
            self.holder_l4,
            "the holder length must be positive",
        )?;
        crate::require!(
            self.holder_ls.is_finite() && (0.0..=1.0).contains(&self.holder_ls),
            "holder.lS",
            self.holder_ls,
            "S lies between C and D: must be in [0, 1]"
        );
        crate::require!(
            self.support_alpha.is_finite() && self.support_alpha.abs() <= 0.5 * PI,
            "support.alpha",
            self.support_alpha,
            "the angle of EQ from the vertical must be in [-pi/2, pi/2]"
        );
        check_finite(&[
            ("support.xQ", self.support_xq),
            ("support.yQ", self.support_yq),
        ])?;
        crate::require!(
            self.branch == 1 || self.branch == -1,
            "assembly.branch",
            f64::from(self.branch),
            "must be +1 or -1 (the two positions of the holder)"
        );
        check_non_negative(&[
            ("holder.m", self.holder_m),
            ("holder.J", self.holder_j),
            ("slider5.m", self.slider5_m),
            ("slider7.m", self.slider7_m),
            ("rod.m", self.rod_m),
            ("crank.J", self.crank_j),
            ("guide.mu", self.guide_mu),
            ("support.mu", self.support_mu),
            ("cut.F", self.cut_f),
        ])?;
        check_finite(&[
            ("feed.V", self.feed_v),
            ("gravity.g", self.gravity_g),
            ("drive.n", self.drive_n),
        ])?;
        if let Some(f) = self.assembly_failure() {
            return Err(ParamError::new(
                "holder.l4",
                self.holder_l4,
                format!(
                    "the holder cannot reach the support line EQ (support.alpha = {:.3} deg, support.xQ = {} m, support.yQ = {} m) for crank angles from {:.4} deg to {:.4} deg: |cos(beta + alpha)| = {:.4} > 1 at {:.2} deg (eq. 5)",
                    self.support_alpha.to_degrees(),
                    self.support_xq,
                    self.support_yq,
                    f.from.to_degrees(),
                    f.to.to_degrees(),
                    f.worst,
                    f.worst_at.to_degrees()
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "physics_tests.rs"]
mod tests;
