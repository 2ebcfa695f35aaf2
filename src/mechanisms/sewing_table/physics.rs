//! Pure mechanics of the translating sewing table (paper 000, `sewing-table.md`).
//!
//! Slot cam 1 on the main shaft O1 drives roller 2 on pusher 3, fixed to table 4 (saddle 4'),
//! which runs on rollers 5, 5' in guides 6. The table travels `x` = 0 (loading, I) → `table.stroke`
//! (sewing, III) along the cyclogram ([`crate::mechanics::cyclogram`]); the stroke comes from the
//! paper's synthesis from the rocking table of the BNSh-6A ([`Synthesis`]).
//!
//! Sign conventions: `x`, `v`, `a`, forces along the table's travel towards sewing (+x);
//! `F_x` is the force the cam must push the table with along +x; `cam.F` is the normal contact
//! force, positive when it pushes along +x (inner flank loaded).

// `!(x > 0.0)` is deliberate throughout: a NaN parameter fails the check too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::mechanics::cam::{offset_pitch_curvature_radius, pressure_angle};
use crate::mechanics::cyclogram::{CyclePoint, Cyclogram, Phase};
use crate::mechanics::hertz::Roller;
use crate::mechanics::hertz::Surface;
use crate::mechanics::motion_laws::MotionLaw;
use crate::mechanics::{ParamError, STANDARD_GRAVITY, Scalar, sgn};
use std::f64::consts::PI;

crate::fmi_enum! {
    /// Which table (`table.kind`).
    pub enum Kind ("TableKind", "Which sewing table") {
        Translating = 1 ("translating", "paper 000's translating table on a slot cam"),
        Rocking = 2 ("rocking", "the BNSh-6A's rocking table, same cyclogram, for comparison"),
    }
}

/// Parameters, SI units; field docs name the FMI variable (`sewing-table.md`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// `synth.l1`: rocking axis to the top in the sewing position, relative (paper 000: 1.0).
    pub l1: f64,
    /// `synth.R`: diagonal OA from the rocking axis to the top, relative (paper 000: 11.0).
    pub r: f64,
    /// `synth.alpha2`: swing of the rocking table, rad (paper 000: 20°).
    pub alpha2: f64,
    /// `synth.unit`: the relative unit, m (assumption 0.030, the perforators' λS = 1).
    pub unit: f64,
    /// `cycle.forward`, rad (82°).
    pub forward: f64,
    /// `cycle.dwell_sew`, rad (110°, assumption).
    pub dwell_sew: f64,
    /// `cycle.return`, rad (90°, assumption).
    pub ret: f64,
    /// `cycle.phi0`, rad (0).
    pub phi0: f64,
    /// `law.forward`.
    pub law_forward: MotionLaw,
    /// `law.return`.
    pub law_return: MotionLaw,
    /// `table.kind`.
    pub kind: Kind,
    /// `cam.R0`: base (pitch) radius, m (0.10).
    pub cam_r0: f64,
    /// `cam.e`: follower offset, m (0).
    pub cam_e: f64,
    /// `roller.r`, `roller.b` (the roller's width), m (0.015 both); `cam.E`, `roller.E`, Pa
    /// (2.1e11).
    pub roller: Roller,
    /// `table.m`: table, saddle, signature and perforator assembly, kg (8, assumption).
    pub table_m: f64,
    /// `guide.f`: rolling friction coefficient of the guides (0.005).
    pub guide_f: f64,
    /// `cam.J`: moment of inertia of the cam on the main shaft, kg·m² (0.02, assumption).
    pub cam_j: f64,
    /// `rocking.J`: the rocking table's moment of inertia about its axis O, kg·m²
    /// (assumption: `table.m` at the saddle radius `R·unit`, 8·0.33² = 0.8712).
    pub rocking_j: f64,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            l1: 1.0,
            r: 11.0,
            alpha2: 20f64.to_radians(),
            unit: 0.030,
            forward: 82f64.to_radians(),
            dwell_sew: 110f64.to_radians(),
            ret: 90f64.to_radians(),
            phi0: 0.0,
            law_forward: MotionLaw::Cycloidal,
            law_return: MotionLaw::Cycloidal,
            kind: Kind::Translating,
            cam_r0: 0.10,
            cam_e: 0.0,
            roller: Roller::steel(0.015, 0.015),
            table_m: 8.0,
            guide_f: 0.005,
            cam_j: 0.02,
            rocking_j: 0.8712,
        }
    }
}

/// The paper's geometric synthesis of the translating table (paper 000, Fig. 3, eq. 1), in the
/// relative units of `synth.l1`, `synth.R`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Synthesis {
    /// `α1 = arcsin(l1/R)`, rad (paper: 5.22°).
    pub alpha1: f64,
    /// `A1A2 = 2R·sin(α2/2)` (paper: 3.82).
    pub a1a2: f64,
    /// `k1 = R·cos(α2/2)` (paper: 10.83).
    pub k1: f64,
    /// `α3 = 90° − (α1 + α2)`, rad (paper: 64.78°).
    pub alpha3: f64,
    /// `k2 = R·sin α3` (paper: 9.95).
    pub k2: f64,
    /// `k0 = k1 − k2`, eq. (1): vertical offset of the rocking saddle (paper: 0.88).
    pub k0: f64,
    /// `l2 = √(A1A2² − k0²)`: horizontal travel of the translating table (paper: 3.72).
    pub l2: f64,
}

/// Table motion at one shaft state (any [`Scalar`]: `f64`, or dual numbers for the exact
/// partial derivatives in the inputs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kinematics<T = f64> {
    /// Cyclogram point of the table travel (`x`, `dx/dφ`, `d²x/dφ²`, phase).
    pub c: CyclePoint<T>,
    /// `table.v = x'·ω`, m/s.
    pub v: T,
    /// `table.a = x''·ω² + x'·ε`, m/s².
    pub a: T,
    /// `cam.theta`: pressure angle θp, rad.
    pub theta: T,
    /// Signed curvature radius of the cam's pitch curve (positive convex), m.
    pub rho_pitch: T,
}

/// The rocking table with the same cyclogram applied to its swing (`sewing-table.md`, last
/// section; any [`Scalar`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rocking<T = f64> {
    /// `rocking.beta`: swing from the loading position, 0 → α2, rad.
    pub beta: T,
    /// `dβ/dφ`.
    pub beta_d: T,
    /// `rocking.w`, rad/s.
    pub w: T,
    /// `rocking.a`, rad/s².
    pub a: T,
    /// `rocking.x`: saddle displacement from loading, horizontal towards sewing, m.
    pub x: T,
    /// `dx/dβ`, m/rad.
    pub dx_dbeta: T,
    /// `rocking.y`: saddle displacement from loading, vertical, up positive, m.
    pub y: T,
    /// `rocking.M_inertia`: inertia torque `−J·β̈` about the rocking axis, N·m.
    pub m_inertia: T,
}

impl<T: Scalar> Rocking<T> {
    /// All zero: what is reported where the rocking table is not computed.
    pub fn zero() -> Self {
        let z = T::zero();
        Rocking {
            beta: z,
            beta_d: z,
            w: z,
            a: z,
            x: z,
            dx_dbeta: z,
            y: z,
            m_inertia: z,
        }
    }
}

/// Forces at one shaft state (level `kinetostatic`; any [`Scalar`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Forces<T = f64> {
    /// `table.F_inertia = −m·a`, N.
    pub f_inertia: T,
    /// `table.F_friction`: guide friction on the table along +x, `−f·N·sgn v`, N.
    pub f_friction: T,
    /// Guide load `N = m·g + |Fn·sin θp|`, N.
    pub guide_n: T,
    /// `F_x = m·a + f·N·sgn v − F_ext`: what the cam must push along +x, N.
    pub f_x: T,
    /// `cam.F = F_x/cos θp`, N.
    pub cam_f: T,
    /// `cam.rho`: curvature radius of the loaded flank, positive convex, negative concave, m.
    pub rho_flank: T,
    /// `cam.sigma_H`, Pa.
    pub sigma_h: T,
    /// `shaft.tau`, N·m.
    pub tau: T,
}

impl<T: Scalar> Forces<T> {
    /// All zero: what is reported where the forces are not computed.
    pub fn zero() -> Self {
        let z = T::zero();
        Forces {
            f_inertia: z,
            f_friction: z,
            guide_n: z,
            f_x: z,
            cam_f: z,
            rho_flank: z,
            sigma_h: z,
            tau: z,
        }
    }
}

/// Samples per travel phase in the initialization checks (undercut, self-locking).
const SAMPLES: usize = 2000;

impl Params {
    /// Paper 000's synthesis (Fig. 3, eq. 1).
    pub fn synthesis(&self) -> Synthesis {
        let alpha1 = (self.l1 / self.r).asin();
        let a1a2 = 2.0 * self.r * (0.5 * self.alpha2).sin();
        let k1 = self.r * (0.5 * self.alpha2).cos();
        let alpha3 = 0.5 * PI - (alpha1 + self.alpha2);
        let k2 = self.r * alpha3.sin();
        let k0 = k1 - k2;
        let l2 = (a1a2 * a1a2 - k0 * k0).sqrt();
        Synthesis {
            alpha1,
            a1a2,
            k1,
            alpha3,
            k2,
            k0,
            l2,
        }
    }

    /// `table.stroke = l2·unit`, m.
    pub fn stroke(&self) -> f64 {
        self.synthesis().l2 * self.unit
    }

    /// The table's cyclogram (displacement `table.stroke`).
    pub fn cyclogram(&self) -> Cyclogram {
        Cyclogram {
            h: self.stroke(),
            forward: self.forward,
            dwell_far: self.dwell_sew,
            ret: self.ret,
            phi0: self.phi0,
            law_forward: self.law_forward,
            law_return: self.law_return,
        }
    }

    /// Checks what the mechanism cannot work with; named by FMI variable.
    pub fn validate(&self) -> Result<(), ParamError> {
        crate::require!(
            self.l1 > 0.0 && self.l1 < self.r,
            "synth.l1",
            self.l1,
            "must lie in (0, synth.R = {}) for arcsin(l1/R)",
            self.r
        );
        let s = self.synthesis();
        // synth.alpha2 must leave an angle alpha3 > 0 and then a real l2
        let alpha2_refused = if !(s.alpha3 > 0.0) {
            Some(format!(
                "alpha1 + alpha2 = {:.3} deg must stay below 90 deg",
                (s.alpha1 + self.alpha2).to_degrees()
            ))
        } else if !(s.l2 > 0.0) {
            Some(format!(
                "A1A2 = {:.4} must exceed k0 = {:.4} (l2 = sqrt(A1A2^2 - k0^2))",
                s.a1a2,
                s.k0.abs()
            ))
        } else {
            None
        };
        if let Some(condition) = alpha2_refused {
            return Err(ParamError::new("synth.alpha2", self.alpha2, condition));
        }
        self.cyclogram().validate()?;
        crate::require!(
            self.cam_e.abs() < self.cam_r0,
            "cam.e",
            self.cam_e,
            "the offset must be smaller than cam.R0 = {}",
            self.cam_r0
        );
        if self.kind == Kind::Translating {
            // the travel's points once, for both checks
            let pts = self.travel_points();
            if let Some((phi, _)) = self.undercut_on(&pts, self.cam_r0) {
                let r0_min = self.smallest_r0();
                return Err(ParamError::new(
                    "cam.R0",
                    self.cam_r0,
                    format!(
                        "undercut cam: a convex slot flank's curvature radius falls to {:.5} m <= roller.r = {} m at shaft angle {:.2} deg; the smallest cam.R0 that avoids it is {:.4} m",
                        self.undercut(self.cam_r0).map(|u| u.1).unwrap_or(0.0) + self.roller.r,
                        self.roller.r,
                        phi.to_degrees(),
                        r0_min
                    ),
                ));
            }
            let worst = self.max_tan_pressure_angle(&pts);
            crate::require!(
                !(self.guide_f * worst.0 >= 1.0),
                "guide.f",
                self.guide_f,
                "the table jams: guide.f*|tan(theta_p)| = {:.3} >= 1 at shaft angle {:.2} deg",
                self.guide_f * worst.0,
                worst.1.to_degrees()
            );
        }
        Ok(())
    }

    /// Shaft angles sampled over the two travel phases (the dwells are circles of radius
    /// `R0 + x`).
    fn travel_samples(&self) -> impl Iterator<Item = f64> + '_ {
        let start_ret = self.forward + self.dwell_sew;
        (0..=SAMPLES)
            .map(move |k| self.phi0 + self.forward * k as f64 / SAMPLES as f64)
            .chain(
                (0..=SAMPLES)
                    .map(move |k| self.phi0 + start_ret + self.ret * k as f64 / SAMPLES as f64),
            )
    }

    /// With base radius `r0`: the shaft angle where the smaller convex flank radius
    /// `|ρpitch| − r_roller` is least, and that value, if it is ≤ 0 (an undercut cam).
    pub fn undercut(&self, r0: f64) -> Option<(f64, f64)> {
        self.undercut_on(&self.travel_points(), r0)
    }

    /// The cyclogram's points at [`Params::travel_samples`] with their shaft angles: what
    /// [`Params::undercut`] takes of the motion, the same for every base radius.
    fn travel_points(&self) -> Vec<(f64, CyclePoint)> {
        let c = self.cyclogram();
        self.travel_samples().map(|phi| (phi, c.at(phi))).collect()
    }

    /// [`Params::undercut`] on the travel's points `pts` ([`Params::travel_points`]).
    fn undercut_on(&self, pts: &[(f64, CyclePoint)], r0: f64) -> Option<(f64, f64)> {
        let mut worst = (0.0, f64::INFINITY);
        for &(phi, p) in pts {
            let rho = offset_pitch_curvature_radius(r0, self.cam_e, p.x, p.dx, p.ddx).abs();
            let convex = rho - self.roller.r;
            if convex < worst.1 {
                worst = (phi, convex);
            }
        }
        // also the dwells: circles about the axis
        let dwell = r0.min((r0 * r0 - self.cam_e * self.cam_e).sqrt()) - self.roller.r;
        if dwell < worst.1 {
            worst = (self.phi0 - 1e-3, dwell);
        }
        (worst.1 <= 0.0).then_some(worst)
    }

    /// The smallest base radius `cam.R0` without undercut (bisection to 1e-6 m, rounded up).
    pub fn smallest_r0(&self) -> f64 {
        let pts = self.travel_points();
        let mut lo = self.cam_e.abs();
        let mut hi = self.cam_r0.max(self.roller.r).max(1e-3);
        for _ in 0..60 {
            if self.undercut_on(&pts, hi).is_none() {
                break;
            }
            lo = hi;
            hi *= 2.0;
        }
        // At most 200 halvings, and stop where floats cannot split the bracket any more: with a
        // huge bracket (a fuzzed cam.R0 of 1e20 m) an absolute 1e-7 is below the float spacing
        // and `mid` would equal `lo` or `hi` for ever.
        for _ in 0..200 {
            if hi - lo <= 1e-7 {
                break;
            }
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if self.undercut_on(&pts, mid).is_some() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        (hi * 1e4).ceil() / 1e4
    }

    /// Largest `|tan θp|` over the travel's points `pts` ([`Params::travel_points`]), and where.
    fn max_tan_pressure_angle(&self, pts: &[(f64, CyclePoint)]) -> (f64, f64) {
        let mut worst = (0.0, self.phi0);
        for &(phi, p) in pts {
            let t = pressure_angle(self.cam_r0, self.cam_e, p.x, p.dx)
                .tan()
                .abs();
            if t > worst.0 {
                worst = (t, phi);
            }
        }
        worst
    }

    /// Table kinematics (translating table) at `phi`, `w`, `eps` (any [`Scalar`]).
    pub fn kinematics<T: Scalar>(&self, phi: T, w: T, eps: T) -> Kinematics<T> {
        let c = self.cyclogram().at(phi);
        let (v, a) = c.motion(w, eps);
        Kinematics {
            c,
            v,
            a,
            theta: pressure_angle(self.cam_r0, self.cam_e, c.x, c.dx),
            rho_pitch: offset_pitch_curvature_radius(self.cam_r0, self.cam_e, c.x, c.dx, c.ddx),
        }
    }

    /// The rocking table: swing `β` 0 → α2 with the same cyclogram; its saddle at angle
    /// `α1 + α2 − β` from the vertical on the circle of radius `R·unit` (any [`Scalar`]).
    pub fn rocking<T: Scalar>(&self, phi: T, w: T, eps: T) -> Rocking<T> {
        let c = Cyclogram {
            h: self.alpha2,
            ..self.cyclogram()
        }
        .at(phi);
        let (bw, ba) = c.motion(w, eps);
        let s = self.synthesis();
        let rr = self.r * self.unit;
        let psi0 = s.alpha1 + self.alpha2;
        let psi = T::from(psi0) - c.x;
        Rocking {
            beta: c.x,
            beta_d: c.dx,
            w: bw,
            a: ba,
            x: (T::from(psi0.sin()) - psi.sin()) * rr,
            dx_dbeta: psi.cos() * rr,
            y: (psi.cos() - psi0.cos()) * rr,
            m_inertia: ba * -self.rocking_j,
        }
    }

    /// Forces of the translating table, with the external force `f_ext` along +x.
    ///
    /// `F_x = m·a + f·N·sgn v − F_ext` with `N = m·g + |F_x·tan θp|` is solved exactly:
    /// `F_x = F0/(1 − f·sgn v·|tan θp|·sgn F0)`, `F0 = m·a − F_ext + f·sgn v·m·g`.
    pub fn forces<T: Scalar>(&self, k: &Kinematics<T>, eps: T, f_ext: T) -> Forces<T> {
        self.forces_with(k, eps, f_ext, true)
    }

    /// As [`Params::forces`]; with `hertz` false the Hertz stress is not computed (`sigma_h` is
    /// NaN), for what does not read it. Any [`Scalar`]: the signs of `v` and `F0` and the
    /// loaded flank are taken on the real parts.
    #[inline]
    pub fn forces_with<T: Scalar>(
        &self,
        k: &Kinematics<T>,
        eps: T,
        f_ext: T,
        hertz: bool,
    ) -> Forces<T> {
        let m = self.table_m;
        let sv = sgn(k.v.re());
        let t = k.theta.tan().abs();
        let f0 = k.a * m - f_ext + self.guide_f * sv * m * STANDARD_GRAVITY;
        let f_x = f0 / (T::one() - t * (self.guide_f * sv) * sgn(f0.re()));
        let cam_f = f_x / k.theta.cos();
        let guide_n = (cam_f * k.theta.sin()).abs() + m * STANDARD_GRAVITY;
        // loaded flank: the inner flank pushes +x; the flank on the centre-of-curvature side is
        // convex with |ρ| − r, the other concave with |ρ| + r
        let inner_on_centre_side = k.rho_pitch.re() > 0.0;
        let loaded_inner = f_x.re() >= 0.0;
        let convex = inner_on_centre_side == loaded_inner;
        let rp = k.rho_pitch.abs();
        let (rho_flank, surface) = if convex {
            (rp - self.roller.r, Surface::Convex)
        } else {
            (-(rp + self.roller.r), Surface::Concave)
        };
        let sigma_h = if hertz {
            self.roller.stress(cam_f, rho_flank.abs(), surface)
        } else {
            T::from(f64::NAN)
        };
        Forces {
            f_inertia: k.a * -m,
            f_friction: guide_n * -self.guide_f * sv,
            guide_n,
            f_x,
            cam_f,
            rho_flank,
            sigma_h,
            tau: f_x * k.c.dx + eps * self.cam_j,
        }
    }

    /// Shaft torque of the rocking table: `(J·β̈ − F_ext·dx/dβ)·β' + cam.J·ε` (no friction or
    /// weight modelled for the comparison).
    pub fn rocking_tau<T: Scalar>(&self, r: &Rocking<T>, eps: T, f_ext: T) -> T {
        (r.a * self.rocking_j - f_ext * r.dx_dbeta) * r.beta_d + eps * self.cam_j
    }

    /// `table.phase` as an integer.
    pub fn phase_index(p: Phase) -> i32 {
        p as i32
    }
}

#[cfg(test)]
#[path = "physics_tests.rs"]
mod tests;
