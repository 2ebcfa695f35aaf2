//! Elastodynamic level of the disc-knife drive (`dynamics.md`, "DiscKnifeDrive: rod compliance
//! between crank pin and slider 5").
//!
//! # Model
//! Rod 4 is an axial spring of stiffness k (`elastic.k`) with a parallel damper c between the
//! crank pin B and hinge C of slider 5. Everything downstream of the rod (slider 5, holder 6 with
//! its knives, slider 7) is a rigid one-degree-of-freedom linkage: given the slider's position x
//! along its guide (C = (x, e)), the holder angle β(x), D(x) and S(x) are the exact kinematics of
//! [`Params::holder`] (eqs. 5, 6, 8) with x in place of the rigid x_C(φ). So the slider's x is the
//! one compliant degree of freedom, tied to its rigid position x_C(φ) by the rod:
//!
//! - rod length `L = |C − B|`, its rigid length `L_kin = |C_kin − B|` (= l2 for the exact
//!   kinematics; the series form's rod "breathes" and the spring follows that reference);
//! - shortening (`elastic.deflection`) `δ = L_kin − L`, the rod force (compression positive, as
//!   `rod.F`) `P = k·δ + c·δ̇`, pushing C along `ĉ = (C − B)/L`;
//! - damping `c = 2·ζ·√(k·M_ref)`, ζ = `elastic.zeta`, M_ref the reduced mass of the downstream
//!   chain at the outer dead centre ([`reduced_mass`]).
//!
//! # Equation of motion: the kinetostatic 7×7 system with the unknown swapped
//! The kinetostatic level solves the module docs' planar Newton–Euler system of slider 5, slider
//! 7 and the holder for `z = [P, C_x, C_y, D_x, D_y, N5, N7]` given the accelerations. Here P is
//! known (the spring) and the slider's acceleration ẍ is the unknown: with the exact transmission
//! ratios D' = dD/dx, S' = dS/dx, β' = dβ/dx (second-order dual numbers through the same
//! [`Params::holder`]) the accelerations are `a_C = (ẍ, 0)`, `a_D = D'·ẍ + D''·ẋ²`,
//! `a_S = S'·ẍ + S''·ẋ²`, `β̈ = β'·ẍ + β''·ẋ²`, so the same rows ([`Params::system_matrix`],
//! [`Params::system_rhs`]) hold with the first column `−(m5, 0, m7·D'_x, m7·D'_y, m_h·S'_x,
//! m_h·S'_y, J_h·β'/l4)` for ẍ and `P·ĉ` moved to the right-hand side. Without friction this is
//! Lagrange's equation of the chain, `M(x)·ẍ + ½·M'(x)·ẋ² = P·ĉ_x + Q(cut, weights)` with the
//! reduced mass `M = m5 + m7·|D'|² + m_h·|S'|² + J_h·β'²` (test
//! `frictionless_solve_is_lagrange`); with friction the normal forces N5, N7 come out of the same
//! solve, and Coulomb friction `μ·|N|` is resolved by the same sign search as the kinetostatic
//! level. The frictionless system is solved by its structure ([`Params::solve_system`], a 2×2
//! system in ẍ and N7 once the hinge forces are eliminated). Friction adds two rank-one terms
//! to the matrix ([`friction_columns`]), so that one solve serves every sign combination (the
//! Sherman–Morrison–Woodbury formula, [`with_friction`]; test
//! `friction_by_the_rank_two_update_is_the_direct_solve`), as one of the kinetostatic system
//! serves the jamming indicator's four ([`RodOde::lock_indicator`]).
//!
//! # Assumptions (as the Geneva model)
//! - The friction in both guides is directed against the **rigid** velocities (slider 5: ẋ_C(φ),
//!   slider 7: v_D(φ)·u): the chain's own vibration does not reverse the sliding direction, which
//!   keeps the friction free of chattering.
//! - The cutting force is that of the kinetostatic level (`cut.F` against the velocity of S
//!   relative to the block, in the working stroke ẋ_C(φ) > 0), evaluated on the rigid motion.
//! - Crank, shaft and the rod's half at the crank pin stay rigid: the shaft torque is the
//!   kinetostatic formula with the dynamic rod force along the elastic rod direction.
//!
//! # The jamming window
//! Where Coulomb friction self-locks a slider (the kinetostatic criterion: some friction sign
//! combination flips the sign of the determinant of the module docs' system; for the defaults
//! slider 7 for 174.63° < φ < 185.37°) the force system has no unique solution, and just outside
//! it the friction wedge amplifies every force without bound (the kinetostatic rod force reaches
//! 4.4e6 N at 185.37°). With the friction coupled as at the kinetostatic level and directed by
//! the rigid velocity, the elastic slider leaving the window is driven back into the wedge by a
//! friction that then does positive work, and the rod force grows without bound (seen: 2.8e5 N
//! and rising 25° after the window, then a step-size collapse). Dropping the friction inside the
//! window only, evaluated at the elastic geometry, makes a soft rod slide along the window's
//! boundary (a Filippov sliding mode: 20 s of events for 30 ms at k = 1e4 N/m).
//!
//! So this level treats the window as the kinetostatic one does (friction dropped,
//! `sliders.locked`, one log line per entry) and, to keep the right-hand side continuous, fades
//! both friction coefficients linearly to zero over the last [`WEDGE_BAND`] of the jamming
//! indicator g ([`RodOde::lock_indicator`], the determinant ratio, 1 without friction), evaluated
//! at the elastic geometry: μ_eff = μ·clamp(g/0.05, 0, 1). With the fade the indicator of the
//! effective friction stays ≥ 0.05, capping the wedge's amplification at 20×; outside the band
//! the friction is exactly the kinetostatic level's. Both kinks (g = 0, g = 0.05) are events.
//! `dyn.factor` still compares with the (singular) kinetostatic peak: with the defaults it is
//! small and says that the rigid model wedges; on a jam-free set (`support.mu` = 0, or a steeper
//! EQ) it is the dynamic overload factor.
//!
//! # States and events
//! `y = [x, ẋ, W]`: W is the work done on the downstream chain and the rod spring by the crank
//! pin, cutting, friction, damping and the weights, so `E − E0 − W` with
//! `E = ½·(m5·ẋ² + m7·|v_D|² + m_h·|v_S|² + J_h·β̇²) + ½·k·δ²` is the energy-balance residual.
//! Events: the crank dead centres
//! (ẋ_C(φ) = 0, which are also the start and end of the working stroke and the reversal of
//! slider 5's friction), the reversal of slider 7's rigid velocity (its friction), the boundaries
//! of the jamming window and of its friction fade, and a reversal of the shaft.
//!
//! # Jacobian
//! Exact: the whole right-hand side is generic over the number type and is evaluated on dual
//! numbers seeded in x and in ẋ (the discrete choices — friction signs, locking — are constant
//! near the point, between events).

use super::friction::{
    friction_columns, friction_det, friction_sign_search, sign_combinations, with_friction,
};
use super::physics::{Kinematics, Params, Vec2, dot, norm};
use crate::mechanics::{Scalar, SpringDamper, sgn};
use crate::solver::chain::Peaks;
use crate::solver::chain::{ChainOde, LastAt, LastPoint, dual_jacobian};
use crate::solver::{OdeSystem, ShaftPath};
use num_dual::{Dual2, DualNum};
use std::cell::Cell;

/// What depends on time only: the rigid drive at one instant (any [`Scalar`]: `f64`, or dual
/// numbers along the shaft inputs).
#[derive(Clone, Copy, Debug)]
pub struct Rigid<T = f64> {
    /// Rigid kinematics at the shaft state.
    pub kin: Kinematics<T>,
    /// Velocity of the crank pin B, m/s.
    pub v_b: Vec2<T>,
    /// Rod length at the rigid position, m, and its rate, m/s.
    pub l_kin: T,
    pub l_kin_d: T,
    /// Cutting force at S (kinetostatic level, rigid motion), N.
    pub load: Vec2<T>,
    /// Directions of the rigid slider velocities (friction), `(sgn ẋ_C, sgn v_D·u)`.
    pub slip: (f64, f64),
}

/// One evaluation of the model (generic: f64 or dual numbers).
#[derive(Clone, Copy, Debug)]
pub struct Eval<T> {
    /// Slider acceleration ẍ, m/s².
    pub xdd: T,
    /// dW/dt, W.
    pub power: T,
    /// Rod shortening δ, m.
    pub delta: T,
    /// Dynamic rod force P, compression positive, N.
    pub force: T,
    /// Unit vector from B towards C.
    pub rod_dir: [T; 2],
    /// `[ẍ, C_x, C_y, D_x, D_y, N5, N7]`.
    pub z: [T; 7],
    /// Friction factors used (k5, k7 of the module docs of `physics`); 0 while locked.
    pub k5: T,
    pub k7: T,
    /// The jamming criterion holds at this geometry: friction dropped.
    pub locked: bool,
    /// The jamming indicator at this geometry ([`RodOde::lock_indicator`]).
    pub lock_g: T,
}

/// Width of the band of the jamming indicator ([`RodOde::lock_indicator`], 1 without friction,
/// 0 where a slider self-locks) over which the guide friction fades out.
pub const WEDGE_BAND: f64 = 0.05;

/// The factor on both friction coefficients at jamming indicator `g`: 1 for g ≥ WEDGE_BAND,
/// falling linearly to 0 at g = 0, 0 inside the window (module docs, "The jamming window").
pub fn friction_fade<T: DualNum<Primitive = f64> + Copy>(g: T) -> T {
    if g.re() >= WEDGE_BAND {
        T::one()
    } else if g.re() <= 0.0 {
        T::zero()
    } else {
        g / WEDGE_BAND
    }
}

/// How close to the holder's dead point (|cos(β + α)| = 1, eq. 5: CD along EQ's normal, β' and
/// the reduced mass unbounded) the elastic slider may come, as the fraction of the rigid
/// motion's own distance `1 − max|c|` that must remain: beyond it the right-hand side is NaN,
/// the step collapses and the communication step is a Discard naming the dead point. A rod soft
/// enough for the slider to overrun the rigid motion's range gets there (it would approach the
/// dead point asymptotically, with ever smaller steps).
pub const DEAD_POINT_FRACTION: f64 = 0.1;

/// The threshold of |c| for [`DEAD_POINT_FRACTION`]: `1 − 0.1·(1 − max|c|)`, max over the turn
/// of the rigid motion (3600 samples).
pub fn dead_point_threshold(p: &Params) -> f64 {
    let c_max = (0..3600)
        .map(|j| {
            let phi = std::f64::consts::TAU * f64::from(j) / 3600.0;
            p.assembly_cos(p.slider_x(phi).0).abs()
        })
        .fold(0.0, f64::max);
    1.0 - DEAD_POINT_FRACTION * (1.0 - c_max.min(1.0))
}

/// Reduced (generalized) mass of the downstream chain at slider position `x`, kg:
/// `M = m5 + m7·|D'|² + m_h·|S'|² + J_h·β'²` (primes: d/dx).
pub fn reduced_mass(p: &Params, x: f64) -> f64 {
    let (beta, d, s) = p.holder(Dual2::new(x, 1.0, 0.0));
    p.mass_c()
        + p.slider7_m * (d[0].v1 * d[0].v1 + d[1].v1 * d[1].v1)
        + p.holder_m * (s[0].v1 * s[0].v1 + s[1].v1 * s[1].v1)
        + p.holder_j * beta.v1 * beta.v1
}

/// The least [`reduced_mass`] over the slider positions of a turn of the rigid motion (3600
/// samples), kg: the elastodynamic level needs it > 0 (`SpringDamper::check_mass`).
pub fn least_reduced_mass(p: &Params) -> f64 {
    (0..3600)
        .map(|j| {
            reduced_mass(
                p,
                p.slider_x(std::f64::consts::TAU * f64::from(j) / 3600.0).0,
            )
        })
        .fold(f64::INFINITY, f64::min)
}

/// The ODE of one communication step.
pub struct RodOde<'a> {
    pub p: &'a Params,
    /// The rod's stiffness and damping.
    pub spring: SpringDamper,
    pub path: ShaftPath,
    /// |c| at which the slider counts as at the holder's dead point ([`dead_point_threshold`]).
    pub c_dead: f64,
    /// Peak tracking over accepted steps and the dynamic factor of the last complete turn.
    pub peaks: Cell<Peaks>,
    /// The last rigid drives computed ([`RodOde::rigid`]).
    rigid_last: LastAt<Rigid>,
    /// The last balance computed ([`RodOde::eval_kept`]).
    eval_last: LastPoint<Eval<f64>>,
}

/// Everything at one instant, for the outputs (any [`Scalar`]).
#[derive(Clone, Copy, Debug)]
pub struct Point<T = f64> {
    pub rigid: Rigid<T>,
    /// The downstream kinematics at the elastic slider position (time derivatives; `w`, `eps`
    /// the shaft's), `working` that of the rigid motion.
    pub kin: Kinematics<T>,
    pub eval: Eval<T>,
    /// Crank torque from the dynamic rod force, N·m.
    pub shaft_tau: T,
}

impl<'a> RodOde<'a> {
    /// The rod's spring `k` at the damping ratio `zeta` (reference mass: [`reduced_mass`] at
    /// the outer dead centre).
    pub fn spring(p: &Params, k: f64, zeta: f64) -> SpringDamper {
        let x0 = p.slider_x(0.0).0;
        SpringDamper::with_ratio(k, reduced_mass(p, x0), zeta)
    }

    /// The rod's ODE on `path`, with `c_dead` ([`dead_point_threshold`]) and the peaks so far.
    pub fn new(
        p: &'a Params,
        spring: SpringDamper,
        path: ShaftPath,
        c_dead: f64,
        peaks: Peaks,
    ) -> Self {
        RodOde {
            p,
            spring,
            path,
            c_dead,
            peaks: Cell::new(peaks),
            rigid_last: LastAt::default(),
            eval_last: LastPoint::default(),
        }
    }

    /// The rigid drive at time t (the last ones kept, [`LastAt`]).
    pub fn rigid(&self, t: f64) -> Rigid {
        self.rigid_last
            .on_path(&self.path, t, |phi, w, a| self.rigid_at(phi, w, a))
    }

    /// The balance at `(t, y)` ([`RodOde::eval`]), the kept one if it is the last computed
    /// there ([`LastPoint`]): the step's last right-hand side and `on_step` share it.
    fn eval_kept(&self, t: f64, y: &[f64]) -> Eval<f64> {
        self.eval_last
            .get_or(t, y, || self.eval(&self.rigid(t), y[0], y[1]))
    }

    /// The rigid drive at the shaft angle `phi`, speed `w`, acceleration `a` (any [`Scalar`]).
    pub fn rigid_at<T: Scalar>(&self, phi: T, w: T, a: T) -> Rigid<T> {
        let p = self.p;
        let kin = p.kinematics(phi, w, a);
        let v_b = Vec2::new(-kin.b.y * w, kin.b.x * w);
        let rod = Vec2::new(kin.x_c - kin.b.x, T::from(p.crank_e) - kin.b.y);
        let l_kin = norm(rod);
        let l_kin_d = dot(
            Vec2::new(rod.x / l_kin, rod.y / l_kin),
            Vec2::new(kin.v_c - v_b.x, T::zero() - v_b.y),
        );
        Rigid {
            kin,
            v_b,
            l_kin,
            l_kin_d,
            load: p.cut_force(&kin),
            slip: p.slip_signs(&kin, sgn(w.re())),
        }
    }

    /// The jamming indicator at slider position `x` with rod direction `rod_dir`: the smallest
    /// ratio of the determinant of the kinetostatic system with friction (every sign
    /// combination of μ5, μ7) to the frictionless one. ≤ 0: self-locking (friction dropped).
    ///
    /// Friction changes the frictionless matrix A0 by two rank-one terms, `−k5·e0·e5ᵀ` (row 0,
    /// column N5) and `−k7·w·e6ᵀ` (w = u_x·e2 + u_y·e3, column N7), so by the matrix determinant
    /// lemma `det A/det A0 = (1 − k5·p5)·(1 − k7·q6) − k5·k7·q5·p6` with `p = A0⁻¹·e0`,
    /// `q = A0⁻¹·w`: one solve ([`Params::solve_system`]) for all four combinations.
    pub fn lock_indicator<T: DualNum<Primitive = f64> + Copy>(&self, x: T, rod_dir: [T; 2]) -> T {
        let p = self.p;
        if p.guide_mu == 0.0 && p.support_mu == 0.0 {
            return T::one();
        }
        let (_, d, s) = p.holder(x);
        let o = T::zero();
        let col0 = [rod_dir[0], rod_dir[1], o, o, o, o, o];
        let cp = [x, T::from(p.crank_e)];
        match p.solve_system(col0, cp, d, s, friction_columns(p.support_dir())) {
            Some([pv, qv]) => self.lock_of(&pv, &qv),
            None => T::from(-1.0), // a singular frictionless system: the holder's dead point
        }
    }

    /// The jamming indicator from `pv = A0⁻¹·e0`, `qv = A0⁻¹·w` of the kinetostatic system
    /// ([`friction_columns`]): the smallest [`friction_det`] over the sign combinations.
    fn lock_of<T: DualNum<Primitive = f64> + Copy>(&self, pv: &[T; 7], qv: &[T; 7]) -> T {
        let (m5, m7) = (self.p.guide_mu, self.p.support_mu);
        let mut best = T::from(f64::INFINITY);
        for (k5, k7) in sign_combinations(m5, m7) {
            let g = friction_det(pv, qv, T::from(k5), T::from(k7));
            if g.re() < best.re() {
                best = g;
            }
        }
        best
    }

    /// The model at slider position `x`, velocity `xd`, on the rigid drive `r` (generic: the
    /// state on `f64` or dual numbers, the rigid drive on `f64` or the state's dual numbers).
    pub fn eval<R: Scalar, T: Scalar + From<R>>(&self, r: &Rigid<R>, x: T, xd: T) -> Eval<T> {
        let up = <T as From<R>>::from;
        let p = self.p;
        let e = p.crank_e;
        // rod: length, direction, rate (C = (x, e), v_C = (ẋ, 0))
        let rx = x - up(r.kin.b.x);
        let ry = up(R::from(e) - r.kin.b.y);
        let l = (rx * rx + ry * ry).sqrt();
        let cd = [rx / l, ry / l];
        let l_d = cd[0] * (xd - up(r.v_b.x)) - cd[1] * up(r.v_b.y);
        let delta = -l + up(r.l_kin);
        let delta_d = -l_d + up(r.l_kin_d);
        let load = Vec2::new(up(r.load.x), up(r.load.y));
        let force = delta * self.spring.k + delta_d * self.spring.c;
        // the downstream chain and its transmission ratios d/dx
        let (beta, d, s) = p.holder(Dual2::new(x, T::one(), T::zero()));
        let xd2 = xd * xd;
        let (m5, m7, mh) = (p.mass_c(), p.slider7_m, p.holder_m);
        let col0 = [
            T::from(-m5),
            T::zero(),
            d[0].v1 * (-m7),
            d[1].v1 * (-m7),
            s[0].v1 * (-mh),
            s[1].v1 * (-mh),
            beta.v1 * (-p.holder_j / p.holder_l4),
        ];
        let mut rhs = p.system_rhs(
            T::zero(),
            [d[0].v2 * xd2, d[1].v2 * xd2],
            [s[0].v2 * xd2, s[1].v2 * xd2],
            beta.v2 * xd2,
            load,
        );
        rhs[0] -= force * cd[0];
        rhs[1] -= force * cd[1];
        let (cp, dp, sp) = ([x, T::from(e)], [d[0].re, d[1].re], [s[0].re, s[1].re]);
        // one solve of the frictionless system for z0, what friction adds, and the
        // jamming indicator: the kinetostatic system differs from this one in its first column
        // only (the rod's direction for the acceleration's coefficients), `A0 + d·e0ᵀ`
        let [e0, w] = friction_columns(p.support_dir());
        let d_col = [
            cd[0] - col0[0],
            cd[1] - col0[1],
            -col0[2],
            -col0[3],
            -col0[4],
            -col0[5],
            -col0[6],
        ];
        let all = p.solve_system(col0, cp, dp, sp, [rhs, e0, w, d_col]);
        let [z0, pv, qv, dv] = all.unwrap_or([[T::from(f64::NAN); 7]; 4]);
        let solved = [z0, pv, qv];
        let den = dv[0] + 1.0; // det of the kinetostatic system over this one's
        let lock_g = if p.guide_mu == 0.0 && p.support_mu == 0.0 {
            T::one()
        } else if all.is_none() || den.re() == 0.0 || !den.re().is_finite() {
            // a singular system (the holder's dead point), or none (it does not assemble)
            T::from(-1.0)
        } else {
            // its A⁻¹·e0 and A⁻¹·w by Sherman–Morrison: A⁻¹·v = A0⁻¹·v − dv·(A0⁻¹·v)₀/(1 + dv₀)
            let sm = |v: &[T; 7]| {
                let f = v[0] / den;
                std::array::from_fn(|i| v[i] - dv[i] * f)
            };
            self.lock_of(&sm(&pv), &sm(&qv))
        };
        let locked = lock_g.re() <= 0.0;
        let fade = friction_fade(lock_g);
        let (f5, f7) = (
            fade * (p.guide_mu * r.slip.0),
            fade * (p.support_mu * r.slip.1),
        );
        let (z, k5, k7) = if f5.re() == 0.0 && f7.re() == 0.0 {
            (z0, T::zero(), T::zero())
        } else {
            // as the kinetostatic level
            friction_sign_search(z0, f5, f7, |k5, k7| with_friction(&solved, k5, k7))
        };
        let c_abs = p.assembly_cos(x.re()).abs();
        let xdd = if c_abs.is_nan() || c_abs >= self.c_dead {
            T::from(f64::NAN)
        } else {
            z[0]
        };
        // power into chain and spring
        let u = p.support_dir();
        let v_d = [d[0].v1 * xd, d[1].v1 * xd];
        let v_s = [s[0].v1 * xd, s[1].v1 * xd];
        let g = p.gravity_g;
        let power =
            delta * self.spring.k * (cd[0] * up(r.v_b.x) + cd[1] * up(r.v_b.y) + up(r.l_kin_d))
                + delta_d * cd[0] * xd * self.spring.c
                + v_s[0] * load.x
                + v_s[1] * load.y
                - z[5] * k5 * xd
                - z[6] * k7 * (v_d[0] * u.x + v_d[1] * u.y)
                - (v_d[1] * p.slider7_m + v_s[1] * p.holder_m) * g;
        Eval {
            xdd,
            power,
            delta,
            force,
            rod_dir: cd,
            z,
            k5,
            k7,
            locked,
            lock_g,
        }
    }

    /// As [`RodOde::point`] on a given rigid drive (any [`Scalar`]: the one source of the
    /// outputs at this level and of their partial derivatives).
    pub fn point_on<T: Scalar>(&self, r: &Rigid<T>, y: &[T]) -> Point<T> {
        let ev = self.eval(r, y[0], y[1]);
        let mut kin = self
            .p
            .assemble(r.kin.phi, (y[0], y[1], ev.xdd), T::one(), T::zero());
        kin.w = r.kin.w;
        kin.eps = r.kin.eps;
        kin.working = r.kin.working;
        let shaft_tau =
            self.p
                .crank_torque(&kin, ev.force, Vec2::new(ev.rod_dir[0], ev.rod_dir[1]));
        Point {
            rigid: *r,
            kin,
            eval: ev,
            shaft_tau,
        }
    }
}

impl RodOde<'_> {
    /// Energy of the downstream chain and the rod spring at `pt`, J (any [`Scalar`]).
    pub fn energy_of<T: Scalar>(&self, pt: &Point<T>) -> T {
        let p = self.p;
        let k = &pt.kin;
        let sq = |v: Vec2<T>| v.x * v.x + v.y * v.y;
        (k.v_c * p.mass_c() * k.v_c
            + sq(k.v_d) * p.slider7_m
            + sq(k.v_s) * p.holder_m
            + k.beta_w * p.holder_j * k.beta_w)
            * 0.5
            + self.spring.energy(pt.eval.delta)
    }
}

impl ChainOde for RodOde<'_> {
    type Point = Point;

    /// The model at time t and state y, for the outputs.
    fn point(&self, t: f64, y: &[f64]) -> Point {
        self.point_on(&self.rigid(t), y)
    }
    /// Energy of the downstream chain and the rod spring, J.
    fn energy(&self, pt: &Point) -> f64 {
        self.energy_of(pt)
    }
    fn natural_frequency(&self) -> f64 {
        self.spring.omega
    }
    /// The state in equilibrium on the rigid motion at time t: the rod shortened by the
    /// kinetostatic rod force over k (none where that is over 5 % of the rod's length: a
    /// start at the jamming wedge), the slider at the rigid velocity.
    fn initial_state(&self, t: f64) -> [f64; 3] {
        let r = self.rigid(t);
        let p = self.p;
        let f = p.kinetostatics(&r.kin).rod_f;
        let d0 = f / self.spring.k;
        let d0 = if d0.is_finite() && d0.abs() < 0.05 * r.l_kin {
            d0
        } else {
            0.0
        };
        let ry = p.crank_e - r.kin.b.y;
        let x = r.kin.b.x + ((r.l_kin - d0).powi(2) - ry * ry).sqrt();
        // not beyond the holder's dead point (a soft rod at a high speed near the inner dead
        // centre): then from the rigid position
        let x = if x.is_finite() && p.assembly_cos(x).abs() < self.c_dead {
            x
        } else {
            r.kin.x_c
        };
        [x, r.kin.v_c, 0.0]
    }
}

impl OdeSystem for RodOde<'_> {
    crate::chain_rhs!(via Self::eval_kept: ev => ev.xdd, ev.power);
    fn jacobian(&self, t: f64, y: &[f64], j: &mut [f64]) {
        let r = self.rigid(t);
        dual_jacobian(y, j, |x, xd| {
            let ev = self.eval(&r, x, xd);
            (ev.xdd, ev.power)
        });
    }
    fn n_events(&self) -> usize {
        5
    }
    /// The event indicators (Model Exchange's too). The rigid speeds `g[0]`, `g[1]`, `g[4]` are
    /// exactly zero while the shaft stands still; the integrators and the Model Exchange hooks
    /// hold their signs then ([`crate::solver::hold_signs`]).
    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let r = self.rigid(t);
        let p = self.p;
        // the crank dead centres (slider 5's rigid velocity: working stroke, its friction)
        g[0] = r.kin.x_c_d;
        // slider 7's rigid velocity along EQ (its friction)
        g[1] = r.kin.d_d.dot(&p.support_dir());
        let rx = y[0] - r.kin.b.x;
        let ry = p.crank_e - r.kin.b.y;
        let l = rx.hypot(ry);
        // the jamming window and its friction fade (at the elastic geometry)
        let lock_g = self.lock_indicator(y[0], [rx / l, ry / l]);
        g[2] = lock_g;
        g[3] = lock_g - WEDGE_BAND;
        // the shaft reversing
        g[4] = r.kin.w;
    }
    fn on_step(&self, t: f64, y: &[f64]) {
        let r = self.rigid(t);
        let ev = self.eval_kept(t, y);
        let f_rigid = self.p.kinetostatics(&r.kin).rod_f.abs();
        let f_el = ev.force.abs();
        let cyc = self.path.cycle(t);
        self.peaks.update(|mut p| {
            p.track(cyc, f_el, f_rigid);
            p
        });
    }
}

#[cfg(test)]
#[path = "elastic_tests.rs"]
mod tests;
