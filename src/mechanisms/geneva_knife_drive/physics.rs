//! Pure mechanics of the Geneva knife drive (paper 003, `geneva-knife-drive.md`).
//!
//! Chain: driver 1 (main shaft, angle φ, roller on radius r1) → Geneva cross 2 with Z slots
//! ([`crate::mechanics::geneva`]) → gear 3 on the cross driving gear 4 (crank turns per cross
//! turn `i`) → crank 5 (r2) → rod 6 (l) → slider 7 carrying the knife ([`crate::mechanics::slider_crank`]).
//!
//! The crank angle is `θ = i·γ`: with `i = Z` the crank makes one full turn per index, so the knife
//! makes its working and idle strokes while the cross moves and stands at the top (s = 0) for the
//! rest of the driver turn.
//!
//! Two errata of paper 003 are *not* copied (spec page, section Kinematics): the knife
//! displacement is the invariant `6 − cos 4γ − 5·cos ν` times `r2` (the paper multiplies by
//! `S = 2·r2`), and the knife velocity includes the gear ratio, `θ' = i·γ'` (the paper's
//! `V2 = V1·dγ/dφ` leaves `i` out).
//!
//! Sign conventions: knife displacement `s` from the top, down positive; `v`, `a` along `s`.
//! The rod force `P` is the spec's: its component along `s` on the slider is `P·cos ν`
//! (so `P > 0` drives the knife down, e.g. while cutting). The spec calls this "compression
//! positive"; with the spec's `s` formula the crank axis lies on the `+s` side of the slider
//! (s grows as the slider approaches the crank axis), so a positive `P` actually pulls the
//! slider towards the crank. The equations (and the energy balance) are the spec's either way;
//! only the label is in question.

use crate::mechanics::geneva::Geneva;
use crate::mechanics::slider_crank::{Pose, SliderCrank};
use crate::mechanics::{
    ParamError, STANDARD_GRAVITY, Scalar, check_non_negative, check_positive, sgn, wrap_angle_of,
};
use std::f64::consts::PI;

/// Parameters of the Geneva knife drive, SI units (`geneva-knife-drive.md`, table "Geometry and
/// parameters"). Field docs name the FMI variable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// `geneva.Z`: number of slots of the cross (paper 003: 4). At least 3.
    pub geneva_z: u32,
    /// `geneva.r1`: driver radius, centre to roller, m (assumption 0.08).
    pub geneva_r1: f64,
    /// `gear.i`: crank turns per cross turn (paper 003: 4); a positive whole multiple of Z.
    pub gear_i: u32,
    /// `gear.eta`: mesh efficiency of the gear pair, in (0, 1] (assumption 0.98).
    pub gear_eta: f64,
    /// `crank.r`: crank radius r2, m (assumption 0.07).
    pub crank_r: f64,
    /// `rod.l`: rod length l, m (paper 003: λ2 = l/r2 = 5, so 0.35).
    pub rod_l: f64,
    /// `knife.m`: mass of slider, knife housing and knife, kg (assumption 12).
    pub knife_m: f64,
    /// `rod.m`: rod mass, half lumped at the crank pin and half at the slider, kg (assumption 3).
    pub rod_m: f64,
    /// `crank.J`: moment of inertia of crank and gear 4 about the crank axis, kg·m² (0.05).
    pub crank_j: f64,
    /// `cross.J`: moment of inertia of cross and gear 3, kg·m² (assumption 0.08).
    pub cross_j: f64,
    /// `driver.J`: moment of inertia of the driver on the main shaft, kg·m² (assumption 0.03).
    pub driver_j: f64,
    /// `guide.mu`: Coulomb friction coefficient of the slider guides (assumption 0.1).
    pub guide_mu: f64,
    /// `cut.F_max`: cutting resistance on the knife at full engagement, N (assumption 15000).
    pub cut_f_max: f64,
    /// `cut.s_start`: knife displacement where it meets the stack, m (assumption 0.070).
    pub cut_s_start: f64,
    /// `cut.s_full`: knife displacement where the cutting force reaches F_max, m (0.075).
    pub cut_s_full: f64,
    /// `cut.s_end`: knife displacement where the stack is cut through, m (0.135).
    pub cut_s_end: f64,
    /// `drive.n`: nominal shaft speed, rad/s (spec: 30 rpm = π rad/s; used by
    /// `drive.mode = constant_speed`, see `interface.md`).
    pub drive_n: f64,
}

impl Default for Params {
    /// The spec's defaults (`geneva-knife-drive.md`).
    fn default() -> Self {
        Self {
            geneva_z: 4,
            geneva_r1: 0.08,
            gear_i: 4,
            gear_eta: 0.98,
            crank_r: 0.07,
            rod_l: 0.35,
            knife_m: 12.0,
            rod_m: 3.0,
            crank_j: 0.05,
            cross_j: 0.08,
            driver_j: 0.03,
            guide_mu: 0.1,
            cut_f_max: 15000.0,
            cut_s_start: 0.070,
            cut_s_full: 0.075,
            cut_s_end: 0.135,
            drive_n: PI, // 30 rpm
        }
    }
}

/// Positions, velocities and accelerations of every member at one shaft state.
/// Derivatives with a `_d`/`_dd` suffix are with respect to the driver angle ψ; `_w`/`_a` and
/// `v`/`a` are time derivatives (chain rule on `shaft.w`, `shaft.a`). Any [`Scalar`]: `f64`, or
/// dual numbers along the inputs (the exact partial derivatives).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Kinematics<T = f64> {
    /// Driver angle within its turn, `ψ = φ mod 2π`, rad.
    pub psi: T,
    /// Roller in a slot (`ψ ∈ [0, 2φe]`): the cross, crank and knife move.
    pub engaged: bool,
    /// `cross.gamma`: cross angle within the index, 0 → 2π/Z (2π/Z in the dwell), rad.
    pub gamma: T,
    /// `γ' = dγ/dψ`.
    pub gamma_d: T,
    /// `γ'' = d²γ/dψ²`, 1/rad.
    pub gamma_dd: T,
    /// `cross.w = γ'·ω`, rad/s.
    pub cross_w: T,
    /// `cross.a = γ''·ω² + γ'·ε`, rad/s².
    pub cross_a: T,
    /// `crank.theta = i·γ mod 2π ∈ [0, 2π)`, rad (0 in the dwell).
    pub theta: T,
    /// `crank.w = θ̇ = i·γ'·ω`, rad/s.
    pub crank_w: T,
    /// `crank.a = θ̈ = i·(γ''·ω² + γ'·ε)`, rad/s².
    pub crank_a: T,
    /// `rod.nu`: rod angle, `sin ν = sin θ/λ2`, rad.
    pub nu: T,
    /// `sin ν`.
    pub sin_nu: T,
    /// `cos ν`.
    pub cos_nu: T,
    /// The slider-crank's pose at `theta` (positions and θ-derivatives), for the accelerations
    /// at another shaft acceleration ([`Params::at_shaft_accel`]).
    pub pose: Pose<T>,
    /// Rod angular velocity ν̇, rad/s.
    pub nu_w: T,
    /// Rod angular acceleration ν̈, rad/s².
    pub nu_a: T,
    /// `knife.s`: displacement from the top, down positive,
    /// `r2·(1 + λ2 − cos θ − √(λ2² − sin²θ))`, m.
    pub s: T,
    /// `ds/dθ = r2·sin(θ + ν)/cos ν`, m/rad.
    pub ds_dtheta: T,
    /// `d²s/dθ²`, m/rad².
    pub dds_dtheta: T,
    /// `ds/dψ = ds/dθ·i·γ'`, m/rad.
    pub s_d: T,
    /// `d²s/dψ² = d²s/dθ²·(i·γ')² + ds/dθ·i·γ''`, m/rad².
    pub s_dd: T,
    /// `knife.v = ds/dθ·θ̇`, m/s.
    pub v: T,
    /// `knife.a = d²s/dθ²·θ̇² + ds/dθ·θ̈`, m/s².
    pub a: T,
    /// `knife.dwell`: the cross is locked and the knife stands at the top (`!engaged`).
    pub dwell: bool,
    /// Distance roller – cross centre ρ (the roller's lever on the cross while engaged), m.
    pub rho: T,
}

/// Forces and torques at one shaft state (level `kinetostatic`; any [`Scalar`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Forces<T = f64> {
    /// `knife.F_cut`: cutting resistance on the knife, ≥ 0, acting against its descent, N.
    pub f_cut: T,
    /// `knife.F_inertia`: d'Alembert inertia force of the slider mass along s, `−m_s·a`, N.
    pub f_inertia: T,
    /// `rod.F`: rod force P; its component along s on the slider is `P·cos ν` (spec: "compression
    /// positive"; see the module docs on that label), N.
    pub rod_f: T,
    /// `guide.N`: lateral component of the rod force on the slider, `P·sin ν`, which the guides
    /// take (signed; friction uses its magnitude), N.
    pub guide_n: T,
    /// `crank.tau`: torque gear 4 applies to the crank, `P·r2·sin(θ + ν) + (crank.J + rod.m/2·r2²)·θ̈`, N·m.
    pub crank_tau: T,
    /// `cross.tau`: torque the roller applies to the cross, `i·τ_crank` over or times η, plus
    /// `cross.J·γ̈`, N·m (0 in the dwell: the locking arcs hold the cross).
    pub cross_tau: T,
    /// `geneva.F`: contact force roller – slot flank, `τ_cross/ρ` (0 in the dwell), N.
    pub geneva_f: T,
    /// `shaft.tau`: torque required at the main shaft, N·m.
    pub shaft_tau: T,
    /// `shaft.P = shaft.tau·ω`, W.
    pub shaft_p: T,
}

impl Params {
    /// Geneva ratio `λ = a/r1 = 1/sin(π/Z)` (paper 003: 1.414).
    pub fn lambda(&self) -> f64 {
        1.0 / (PI / f64::from(self.geneva_z)).sin()
    }

    /// `geneva.a`: centre distance `r1/sin(π/Z)`, m (calculated parameter).
    pub fn a(&self) -> f64 {
        self.geneva_r1 * self.lambda()
    }

    /// `knife.stroke = 2·r2`, m (calculated parameter; paper 003: S = 2·r2).
    pub fn stroke(&self) -> f64 {
        2.0 * self.crank_r
    }

    /// `λ2 = l/r2` (paper 003: 5).
    pub fn lambda2(&self) -> f64 {
        self.rod_l / self.crank_r
    }

    /// Translating mass of the slider: `m_s = knife.m + rod.m/2`, kg.
    pub fn slider_mass(&self) -> f64 {
        self.knife_m + 0.5 * self.rod_m
    }

    /// Rotating inertia about the crank axis: `crank.J + rod.m/2·r2²`, kg·m².
    pub fn crank_inertia(&self) -> f64 {
        self.crank_j + 0.5 * self.rod_m * self.crank_r * self.crank_r
    }

    /// The Geneva pair of this drive.
    pub fn geneva(&self) -> Geneva {
        Geneva::new(self.geneva_z, self.geneva_r1)
    }

    /// The (central) slider-crank of this drive.
    pub fn slider_crank(&self) -> SliderCrank {
        SliderCrank::central(self.crank_r, self.rod_l)
    }

    /// Checks that the drive can be assembled and run; the first violation found.
    pub fn validate(&self) -> Result<(), ParamError> {
        let z = self.geneva_z;
        crate::require!(z >= 3, "geneva.Z", f64::from(z), "needs at least 3 slots");
        check_positive(
            "geneva.r1",
            self.geneva_r1,
            "the driver radius must be positive",
        )?;
        let i = self.gear_i;
        crate::require!(
            i != 0,
            "gear.i",
            0.0,
            "must be a positive whole multiple of geneva.Z = {z}"
        );
        crate::require!(
            i.is_multiple_of(z),
            "gear.i",
            f64::from(i),
            "must be a whole multiple of geneva.Z = {z} so the crank makes whole turns per index"
        );
        crate::require!(
            self.gear_eta > 0.0 && self.gear_eta <= 1.0,
            "gear.eta",
            self.gear_eta,
            "the mesh efficiency must be in (0, 1]"
        );
        check_positive("crank.r", self.crank_r, "the crank radius must be positive")?;
        crate::require!(
            self.rod_l > self.crank_r && self.rod_l.is_finite(),
            "rod.l",
            self.rod_l,
            "the rod must be longer than crank.r = {} for the crank to turn",
            self.crank_r
        );
        check_non_negative(&[
            ("knife.m", self.knife_m),
            ("rod.m", self.rod_m),
            ("crank.J", self.crank_j),
            ("cross.J", self.cross_j),
            ("driver.J", self.driver_j),
        ])?;
        crate::require!(
            self.guide_mu >= 0.0 && self.guide_mu.is_finite(),
            "guide.mu",
            self.guide_mu,
            "the friction coefficient must be >= 0"
        );
        // Largest rod angle: tan ν_max = r2/√(l² − r2²). With μ·tan ν ≥ 1 the guide friction would
        // wedge the slider (the slider equation has no solution while it is pushed).
        let tan_nu_max =
            self.crank_r / (self.rod_l * self.rod_l - self.crank_r * self.crank_r).sqrt();
        crate::require!(
            !(self.guide_mu * tan_nu_max >= 1.0),
            "guide.mu",
            self.guide_mu,
            "the slider would jam in its guides: needs guide.mu * tan(nu_max) < 1, tan(nu_max) = {tan_nu_max}"
        );
        crate::require!(
            self.cut_f_max >= 0.0 && self.cut_f_max.is_finite(),
            "cut.F_max",
            self.cut_f_max,
            "the cutting force must be a finite value >= 0"
        );
        let stroke = self.stroke();
        // the cut's window in order: 0 <= cut.s_start <= cut.s_full <= cut.s_end <= the stroke
        let mut below: Option<(&str, f64)> = None;
        for (param, s) in [
            ("cut.s_start", self.cut_s_start),
            ("cut.s_full", self.cut_s_full),
            ("cut.s_end", self.cut_s_end),
        ] {
            if !(s >= below.map_or(0.0, |b| b.1) && s <= stroke) {
                let condition = match below {
                    None => format!("must lie within the knife stroke [0, {stroke}]"),
                    Some((b, sb)) => format!("must lie between {b} = {sb} and the stroke {stroke}"),
                };
                return Err(ParamError::new(param, s, condition));
            }
            below = Some((param, s));
        }
        crate::require!(
            self.drive_n.is_finite(),
            "drive.n",
            self.drive_n,
            "the nominal speed must be finite"
        );
        Ok(())
    }

    /// Positions, velocities and accelerations at shaft angle `phi` (any real value), speed `w`
    /// (rad/s) and acceleration `eps` (rad/s²). Exact closed forms (spec section Kinematics).
    #[inline]
    pub fn kinematics(&self, phi: f64, w: f64, eps: f64) -> Kinematics {
        self.kinematics_of(&self.geneva(), phi, w, eps)
    }

    /// As [`Params::kinematics`], with the Geneva pair built once (it costs a sine: the FMU
    /// builds it when it prepares the model, not in every step). Any [`Scalar`]: the same
    /// operations for `f64` and for the dual numbers of the partial derivatives, the
    /// engagement decided on the value.
    #[inline(always)]
    pub fn kinematics_of<T: Scalar>(&self, geneva: &Geneva, phi: T, w: T, eps: T) -> Kinematics<T> {
        let g = geneva.at(phi);
        let i = f64::from(self.gear_i);
        // θ = i·γ, θ' = i·γ', θ'' = i·γ'' (paper 003 leaves i out of the velocity: erratum).
        // In the dwell θ = i·2π/Z is a whole number of turns: exactly 0.
        let theta = if g.engaged {
            wrap_angle_of(g.gamma * i)
        } else {
            T::zero()
        };
        let theta_d = g.gamma_d * i;
        let theta_dd = g.gamma_dd * i;
        let cross_w = g.gamma_d * w;
        let crank_w = cross_w * i;
        let m = self.slider_crank().motion(theta, crank_w, T::zero());
        let p = m.pose;
        let k = Kinematics {
            psi: g.psi,
            engaged: g.engaged,
            gamma: g.gamma,
            gamma_d: g.gamma_d,
            gamma_dd: g.gamma_dd,
            cross_w,
            cross_a: T::zero(),
            theta,
            crank_w,
            crank_a: T::zero(),
            nu: p.nu,
            sin_nu: p.sin_nu,
            cos_nu: p.cos_nu,
            pose: p,
            nu_w: m.nu_w,
            nu_a: T::zero(),
            s: p.s,
            ds_dtheta: p.ds,
            dds_dtheta: p.dds,
            s_d: p.ds * theta_d,
            s_dd: p.dds * theta_d * theta_d + p.ds * theta_dd,
            v: m.v,
            a: T::zero(),
            dwell: !g.engaged,
            rho: g.rho,
        };
        self.at_shaft_accel(&k, w, eps)
    }

    /// The kinematics `k` (computed at shaft speed `w`) at shaft acceleration `eps` instead:
    /// positions and velocities do not depend on it and every acceleration is affine in it
    /// (`cross.a = γ''·ω² + γ'·ε`, then the slider-crank's chain rule `x'' = x_θθ·θ̇² + x_θ·θ̈`),
    /// so only the accelerations are recomputed, with no trigonometry: what
    /// [`crate::model::shaft::reduce_at`] evaluates to split the shaft torque into `τ0` and
    /// `J_red`. The same operations as [`Params::kinematics_of`] (which ends in this call): the
    /// result is bit-identical to `kinematics_of(.., phi, w, eps)`. Any [`Scalar`].
    #[inline]
    pub fn at_shaft_accel<T: Scalar>(&self, k: &Kinematics<T>, w: T, eps: T) -> Kinematics<T> {
        let i = f64::from(self.gear_i);
        let cross_a = k.gamma_dd * w * w + k.gamma_d * eps;
        let crank_a = cross_a * i;
        let m = k.pose.motion(k.crank_w, crank_a);
        Kinematics {
            cross_a,
            crank_a,
            nu_a: m.nu_a,
            a: m.a,
            ..*k
        }
    }

    /// Is the knife in the stack: descending (`v > 0`) with `s ∈ [s_start, s_end]`?
    #[inline]
    pub fn in_stack(&self, s: f64, v: f64) -> bool {
        v > 0.0 && s >= self.cut_s_start && s <= self.cut_s_end
    }

    /// Cutting resistance on the knife (spec, Kinetostatics): 0 unless the knife descends
    /// (`v > 0`) with `s ∈ [s_start, s_end]`; rises linearly from 0 at `s_start` to `F_max` at
    /// `s_full`, then stays at `F_max` until `s_end` (cut through). N, ≥ 0. Any [`Scalar`], the
    /// phase decided on the values.
    #[inline]
    pub fn cut_force<T: Scalar>(&self, s: T, v: T) -> T {
        if !self.in_stack(s.re(), v.re()) {
            T::zero()
        } else if s.re() >= self.cut_s_full {
            T::from(self.cut_f_max)
        } else {
            (s - self.cut_s_start) * self.cut_f_max / (self.cut_s_full - self.cut_s_start)
        }
    }

    /// Forces and torques (spec section Kinetostatics) for kinematics `k` computed at shaft speed
    /// `w` and acceleration `eps`. Needs validated parameters. Any [`Scalar`]: the friction's
    /// direction, the regime of the slider equation and the power flow through the gear pair
    /// are decided on the values.
    ///
    /// Slider (`m_s = knife.m + rod.m/2`) along s:
    /// `P·cos ν − μ·|P·sin ν|·sgn(v) + m_s·g − F_cut = m_s·a`. The friction term depends on |P|:
    /// with `c = cos ν`, `k = μ·|sin ν|·sgn(v)` the left side `c·P − k·|P|` is strictly increasing
    /// in P when `|k| < c` (guaranteed by [`Params::validate`]), so the unique solution is
    /// `P = R/(c − k)` for `R = m_s·(a − g) + F_cut ≥ 0` and `P = R/(c + k)` for `R < 0`.
    #[inline]
    pub fn kinetostatics<T: Scalar>(&self, k: &Kinematics<T>, w: T, eps: T) -> Forces<T> {
        let m_s = self.slider_mass();
        let (sin_nu, cos_nu) = (k.sin_nu, k.cos_nu);
        let f_cut = self.cut_force(k.s, k.v);
        let rhs = (k.a - STANDARD_GRAVITY) * m_s + f_cut;
        let sgn_v = sgn(k.v.re());
        let kf = sin_nu.abs() * self.guide_mu * sgn_v;
        let p = if rhs.re() >= 0.0 {
            rhs / (cos_nu - kf)
        } else {
            rhs / (cos_nu + kf)
        };
        // Crank: rod force on the arm r2·sin(θ + ν) = ds/dθ·cos ν, plus the rotating inertia.
        let crank_tau = p * k.ds_dtheta * cos_nu + k.crank_a * self.crank_inertia();
        let (cross_tau, geneva_f, shaft_tau) = self.behind_crank(k, crank_tau, eps);
        Forces {
            f_cut,
            f_inertia: k.a * (-m_s),
            rod_f: p,
            guide_n: p * sin_nu,
            crank_tau,
            cross_tau,
            geneva_f,
            shaft_tau,
            shaft_p: shaft_tau * w,
        }
    }

    /// The torque `crank_tau` on the crank carried through the gear pair (η by the direction of
    /// the power flow at the crank) to the cross and the driver at kinematics `k` and shaft
    /// acceleration `eps`: `(cross.tau, geneva.F, shaft.tau)` (any [`Scalar`]). In the dwell the
    /// locking arcs hold the cross: nothing flows to the shaft but the driver's own inertia.
    /// The kinetostatic and the elastodynamic level share it (the latter with the chain force
    /// on the crank).
    #[inline]
    pub fn behind_crank<T: Scalar>(&self, k: &Kinematics<T>, crank_tau: T, eps: T) -> (T, T, T) {
        let i = f64::from(self.gear_i);
        let gear = if crank_tau.re() * k.crank_w.re() >= 0.0 {
            crank_tau * i / self.gear_eta
        } else {
            crank_tau * i * self.gear_eta
        };
        if k.engaged {
            let cross_tau = gear + k.cross_a * self.cross_j;
            (
                cross_tau,
                cross_tau / k.rho,
                cross_tau * k.gamma_d + eps * self.driver_j,
            )
        } else {
            (T::zero(), T::zero(), eps * self.driver_j)
        }
    }

    /// Kinetic energy of the drive at kinematics `k` and shaft speed `w`, J: slider
    /// `½·m_s·v²`, crank with half the rod `½·(crank.J + rod.m/2·r2²)·θ̇²`, cross `½·cross.J·γ̇²`,
    /// driver `½·driver.J·ω²`.
    #[inline]
    pub fn kinetic_energy(&self, k: &Kinematics, w: f64) -> f64 {
        0.5 * (self.slider_mass() * k.v * k.v
            + self.crank_inertia() * k.crank_w * k.crank_w
            + self.cross_j * k.cross_w * k.cross_w
            + self.driver_j * w * w)
    }
}

#[cfg(test)]
#[path = "physics_tests.rs"]
mod tests;
