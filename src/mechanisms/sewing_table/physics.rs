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
use crate::mechanics::hertz::{Surface, line_contact_stress};
use crate::mechanics::motion_laws::MotionLaw;
use crate::mechanics::{ParamError, STANDARD_GRAVITY, sgn};
use std::f64::consts::PI;

/// Which table (`table.kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// The paper's translating table on a slot cam (default).
    Translating = 1,
    /// The existing rocking table of the BNSh-6A, for comparison.
    Rocking = 2,
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
    /// `roller.r`, m (0.015).
    pub roller_r: f64,
    /// `roller.b`: roller width, m (0.015).
    pub roller_b: f64,
    /// `cam.E`, Pa (2.1e11).
    pub cam_e_mod: f64,
    /// `roller.E`, Pa (2.1e11).
    pub roller_e_mod: f64,
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
            roller_r: 0.015,
            roller_b: 0.015,
            cam_e_mod: 2.1e11,
            roller_e_mod: 2.1e11,
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

/// Table motion at one shaft state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kinematics {
    /// Cyclogram point of the table travel (`x`, `dx/dφ`, `d²x/dφ²`, phase).
    pub c: CyclePoint,
    /// `table.v = x'·ω`, m/s.
    pub v: f64,
    /// `table.a = x''·ω² + x'·ε`, m/s².
    pub a: f64,
    /// `cam.theta`: pressure angle θp, rad.
    pub theta: f64,
    /// Signed curvature radius of the cam's pitch curve (positive convex), m.
    pub rho_pitch: f64,
}

/// The rocking table with the same cyclogram applied to its swing (`sewing-table.md`, last
/// section).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rocking {
    /// `rocking.beta`: swing from the loading position, 0 → α2, rad.
    pub beta: f64,
    /// `dβ/dφ`.
    pub beta_d: f64,
    /// `rocking.w`, rad/s.
    pub w: f64,
    /// `rocking.a`, rad/s².
    pub a: f64,
    /// `rocking.x`: saddle displacement from loading, horizontal towards sewing, m.
    pub x: f64,
    /// `dx/dβ`, m/rad.
    pub dx_dbeta: f64,
    /// `rocking.y`: saddle displacement from loading, vertical, up positive, m.
    pub y: f64,
    /// `rocking.M_inertia`: inertia torque `−J·β̈` about the rocking axis, N·m.
    pub m_inertia: f64,
}

/// Forces at one shaft state (level `kinetostatic`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Forces {
    /// `table.F_inertia = −m·a`, N.
    pub f_inertia: f64,
    /// `table.F_friction`: guide friction on the table along +x, `−f·N·sgn v`, N.
    pub f_friction: f64,
    /// Guide load `N = m·g + |Fn·sin θp|`, N.
    pub guide_n: f64,
    /// `F_x = m·a + f·N·sgn v − F_ext`: what the cam must push along +x, N.
    pub f_x: f64,
    /// `cam.F = F_x/cos θp`, N.
    pub cam_f: f64,
    /// `cam.rho`: curvature radius of the loaded flank, positive convex, negative concave, m.
    pub rho_flank: f64,
    /// `cam.sigma_H`, Pa.
    pub sigma_h: f64,
    /// `shaft.tau`, N·m.
    pub tau: f64,
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
        if !(self.l1 > 0.0 && self.l1 < self.r) {
            return Err(ParamError::new(
                "synth.l1",
                self.l1,
                format!("must lie in (0, synth.R = {}) for arcsin(l1/R)", self.r),
            ));
        }
        let s = self.synthesis();
        if !(s.alpha3 > 0.0) {
            return Err(ParamError::new(
                "synth.alpha2",
                self.alpha2,
                format!(
                    "alpha1 + alpha2 = {:.3} deg must stay below 90 deg",
                    (s.alpha1 + self.alpha2).to_degrees()
                ),
            ));
        }
        if !(s.l2 > 0.0) {
            return Err(ParamError::new(
                "synth.alpha2",
                self.alpha2,
                format!(
                    "A1A2 = {:.4} must exceed k0 = {:.4} (l2 = sqrt(A1A2^2 - k0^2))",
                    s.a1a2,
                    s.k0.abs()
                ),
            ));
        }
        self.cyclogram().validate()?;
        if !(self.cam_e.abs() < self.cam_r0) {
            return Err(ParamError::new(
                "cam.e",
                self.cam_e,
                format!("the offset must be smaller than cam.R0 = {}", self.cam_r0),
            ));
        }
        if self.kind == Kind::Translating {
            if let Some((phi, _)) = self.undercut(self.cam_r0) {
                let r0_min = self.smallest_r0();
                return Err(ParamError::new(
                    "cam.R0",
                    self.cam_r0,
                    format!(
                        "undercut cam: a convex slot flank's curvature radius falls to {:.5} m <= roller.r = {} m at shaft angle {:.2} deg; the smallest cam.R0 that avoids it is {:.4} m",
                        self.undercut(self.cam_r0).map(|u| u.1).unwrap_or(0.0) + self.roller_r,
                        self.roller_r,
                        phi.to_degrees(),
                        r0_min
                    ),
                ));
            }
            let worst = self.max_tan_pressure_angle();
            if self.guide_f * worst.0 >= 1.0 {
                return Err(ParamError::new(
                    "guide.f",
                    self.guide_f,
                    format!(
                        "the table jams: guide.f*|tan(theta_p)| = {:.3} >= 1 at shaft angle {:.2} deg",
                        self.guide_f * worst.0,
                        worst.1.to_degrees()
                    ),
                ));
            }
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
        let c = self.cyclogram();
        let mut worst = (0.0, f64::INFINITY);
        for phi in self.travel_samples() {
            let p = c.at(phi);
            let rho = offset_pitch_curvature_radius(r0, self.cam_e, p.x, p.dx, p.ddx).abs();
            let convex = rho - self.roller_r;
            if convex < worst.1 {
                worst = (phi, convex);
            }
        }
        // also the dwells: circles about the axis
        let dwell = r0.min((r0 * r0 - self.cam_e * self.cam_e).sqrt()) - self.roller_r;
        if dwell < worst.1 {
            worst = (self.phi0 - 1e-3, dwell);
        }
        (worst.1 <= 0.0).then_some(worst)
    }

    /// The smallest base radius `cam.R0` without undercut (bisection to 1e-6 m, rounded up).
    pub fn smallest_r0(&self) -> f64 {
        let mut lo = self.cam_e.abs();
        let mut hi = self.cam_r0.max(self.roller_r).max(1e-3);
        for _ in 0..60 {
            if self.undercut(hi).is_none() {
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
            if self.undercut(mid).is_some() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        (hi * 1e4).ceil() / 1e4
    }

    /// Largest `|tan θp|` over the travel, and where.
    fn max_tan_pressure_angle(&self) -> (f64, f64) {
        let c = self.cyclogram();
        let mut worst = (0.0, self.phi0);
        for phi in self.travel_samples() {
            let p = c.at(phi);
            let t = pressure_angle(self.cam_r0, self.cam_e, p.x, p.dx)
                .tan()
                .abs();
            if t > worst.0 {
                worst = (t, phi);
            }
        }
        worst
    }

    /// Table kinematics (translating table) at `phi`, `w`, `eps`.
    pub fn kinematics(&self, phi: f64, w: f64, eps: f64) -> Kinematics {
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
    /// `α1 + α2 − β` from the vertical on the circle of radius `R·unit`.
    pub fn rocking(&self, phi: f64, w: f64, eps: f64) -> Rocking {
        let c = Cyclogram {
            h: self.alpha2,
            ..self.cyclogram()
        }
        .at(phi);
        let (bw, ba) = c.motion(w, eps);
        let s = self.synthesis();
        let rr = self.r * self.unit;
        let psi0 = s.alpha1 + self.alpha2;
        let psi = psi0 - c.x;
        Rocking {
            beta: c.x,
            beta_d: c.dx,
            w: bw,
            a: ba,
            x: rr * (psi0.sin() - psi.sin()),
            dx_dbeta: rr * psi.cos(),
            y: rr * (psi.cos() - psi0.cos()),
            m_inertia: -self.rocking_j * ba,
        }
    }

    /// Forces of the translating table, with the external force `f_ext` along +x.
    ///
    /// `F_x = m·a + f·N·sgn v − F_ext` with `N = m·g + |F_x·tan θp|` is solved exactly:
    /// `F_x = F0/(1 − f·sgn v·|tan θp|·sgn F0)`, `F0 = m·a − F_ext + f·sgn v·m·g`.
    pub fn forces(&self, k: &Kinematics, eps: f64, f_ext: f64) -> Forces {
        self.forces_with(k, eps, f_ext, true)
    }

    /// As [`Params::forces`]; with `hertz` false the Hertz stress is not computed (`sigma_h` is
    /// NaN), for what does not read it.
    pub fn forces_with(&self, k: &Kinematics, eps: f64, f_ext: f64, hertz: bool) -> Forces {
        let m = self.table_m;
        let sv = sgn(k.v);
        let t = k.theta.tan().abs();
        let f0 = m * k.a - f_ext + self.guide_f * sv * m * STANDARD_GRAVITY;
        let f_x = f0 / (1.0 - self.guide_f * sv * t * sgn(f0));
        let cam_f = f_x / k.theta.cos();
        let guide_n = m * STANDARD_GRAVITY + (cam_f * k.theta.sin()).abs();
        // loaded flank: the inner flank pushes +x; the flank on the centre-of-curvature side is
        // convex with |ρ| − r, the other concave with |ρ| + r
        let inner_on_centre_side = k.rho_pitch > 0.0;
        let loaded_inner = f_x >= 0.0;
        let convex = inner_on_centre_side == loaded_inner;
        let rp = k.rho_pitch.abs();
        let (rho_flank, surface) = if convex {
            (rp - self.roller_r, Surface::Convex)
        } else {
            (-(rp + self.roller_r), Surface::Concave)
        };
        let sigma_h = if hertz {
            line_contact_stress(
                cam_f,
                self.roller_b,
                self.cam_e_mod,
                self.roller_e_mod,
                self.roller_r,
                rho_flank.abs(),
                surface,
            )
            .unwrap_or(f64::NAN)
        } else {
            f64::NAN
        };
        Forces {
            f_inertia: -m * k.a,
            f_friction: -self.guide_f * guide_n * sv,
            guide_n,
            f_x,
            cam_f,
            rho_flank,
            sigma_h,
            tau: f_x * k.c.dx + self.cam_j * eps,
        }
    }

    /// Shaft torque of the rocking table: `(J·β̈ − F_ext·dx/dβ)·β' + cam.J·ε` (no friction or
    /// weight modelled for the comparison).
    pub fn rocking_tau(&self, r: &Rocking, eps: f64, f_ext: f64) -> f64 {
        (self.rocking_j * r.a - f_ext * r.dx_dbeta) * r.beta_d + self.cam_j * eps
    }

    /// `table.phase` as an integer.
    pub fn phase_index(p: Phase) -> i32 {
        p as i32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;
    use std::f64::consts::TAU;

    /// `x` printed with `decimals` digits equals `printed`.
    fn printed(x: f64, printed: f64, decimals: i32) {
        let half = 0.5 * 10f64.powi(-decimals);
        assert!(
            (x - printed).abs() <= half + 1e-12,
            "{x} does not print as {printed}"
        );
    }

    const W100: f64 = 100.0 * PI / 30.0;

    #[test]
    fn paper_synthesis_numbers() {
        let s = Params::default().synthesis();
        printed(s.alpha1.to_degrees(), 5.22, 2);
        printed(s.a1a2, 3.82, 2);
        printed(s.k1, 10.83, 2);
        printed(s.k2, 9.95, 2);
        printed(s.alpha3.to_degrees(), 64.78, 2);
        printed(s.k0, 0.88, 2);
        printed(s.l2, 3.72, 2);
        // table.stroke = l2·unit = 0.11152 m
        printed(Params::default().stroke(), 0.11152, 5);
    }

    #[test]
    fn rocking_saddle_geometry_against_the_synthesis() {
        // Independent: the saddle's end positions on the circle. The chord is A1A2 (3.82); the
        // paper's k0 = k1 - k2 is not the saddle's true height difference (1.003), so its
        // l2 = 3.72 is not the saddle's true horizontal travel (3.686) either: the paper's choice,
        // kept as the translating table's travel.
        let p = Params::default();
        let end = p.rocking(p.forward + 0.1, 0.0, 0.0);
        let chord = (end.x.powi(2) + end.y.powi(2)).sqrt() / p.unit;
        assert_abs_diff_eq!(chord, p.synthesis().a1a2, epsilon = 1e-12);
        printed(end.x / p.unit, 3.686, 3);
        printed(end.y / p.unit, 1.003, 3);
        let start = p.rocking(p.forward + p.dwell_sew + p.ret + 0.1, 0.0, 0.0);
        assert_eq!((start.x, start.y), (0.0, 0.0));
    }

    #[test]
    fn spec_reference_values_at_100_rpm() {
        let p = Params::default();
        let k = p.kinematics(0.5, W100, 0.0);
        printed(k.c.x, 0.024560, 6);
        printed(k.v, 1.29297, 5);
        printed(k.a, 30.4377, 4);
        assert_eq!(k.c.phase, Phase::Forward);
        let k = p.kinematics(1.0, W100, 0.0);
        printed(k.c.x, 0.094756, 6);
        printed(k.v, 1.07433, 5);
        printed(k.a, -35.5847, 4);
    }

    #[test]
    fn half_travel_at_41_degrees() {
        let p = Params::default();
        let c = p.cyclogram();
        assert_abs_diff_eq!(c.forward_angle_at(0.5).to_degrees(), 41.0, epsilon = 1e-9);
        assert_abs_diff_eq!(
            p.kinematics(41f64.to_radians(), 1.0, 0.0).c.x,
            p.stroke() / 2.0,
            epsilon = 1e-15
        );
    }

    #[test]
    fn velocities_and_accelerations_match_finite_differences() {
        for kind in [Kind::Translating, Kind::Rocking] {
            let p = Params {
                kind,
                law_return: MotionLaw::Poly345,
                ..Params::default()
            };
            let (w, eps) = (W100, 3.0);
            // a shaft with constant acceleration: phi(t) = phi + w t + eps t²/2
            for k in 0..360 {
                let phi = TAU * (k as f64 + 0.3) / 360.0;
                let h = 1e-6;
                let at = |t: f64| (phi + w * t + 0.5 * eps * t * t, w + eps * t);
                let x = |t: f64| {
                    let (f, ww) = at(t);
                    let k = p.kinematics(f, ww, eps);
                    let r = p.rocking(f, ww, eps);
                    (k.c.x, k.v, r.beta, r.w, r.x)
                };
                let k0 = p.kinematics(phi, w, eps);
                let r0 = p.rocking(phi, w, eps);
                let (a, b) = (x(-h), x(h));
                assert_abs_diff_eq!(k0.v, (b.0 - a.0) / (2.0 * h), epsilon = 1e-6);
                assert_abs_diff_eq!(k0.a, (b.1 - a.1) / (2.0 * h), epsilon = 1e-4);
                assert_abs_diff_eq!(r0.w, (b.2 - a.2) / (2.0 * h), epsilon = 1e-6);
                assert_abs_diff_eq!(r0.a, (b.3 - a.3) / (2.0 * h), epsilon = 1e-4);
                assert_abs_diff_eq!(r0.dx_dbeta * r0.w, (b.4 - a.4) / (2.0 * h), epsilon = 1e-6);
            }
        }
    }

    #[test]
    fn power_balance_without_friction() {
        // tau*w = d/dt(m v²/2 + J w²/2) − F_ext·v, at constant and accelerating shaft
        for kind in [Kind::Translating, Kind::Rocking] {
            let p = Params {
                guide_f: 0.0,
                kind,
                ..Params::default()
            };
            for (w, eps, f_ext) in [(W100, 0.0, 0.0), (W100, 5.0, 0.0), (W100, 5.0, -37.0)] {
                for k in 0..360 {
                    let phi = TAU * (k as f64 + 0.5) / 360.0;
                    let (tau, power_kin) = match kind {
                        Kind::Translating => {
                            let km = p.kinematics(phi, w, eps);
                            let f = p.forces(&km, eps, f_ext);
                            (f.tau, p.table_m * km.v * km.a - f_ext * km.v)
                        }
                        Kind::Rocking => {
                            let r = p.rocking(phi, w, eps);
                            (
                                p.rocking_tau(&r, eps, f_ext),
                                p.rocking_j * r.w * r.a - f_ext * r.dx_dbeta * r.w,
                            )
                        }
                    };
                    let lhs = tau * w;
                    let rhs = power_kin + p.cam_j * w * eps;
                    assert_abs_diff_eq!(lhs, rhs, epsilon = 1e-9 * (1.0 + rhs.abs()));
                }
            }
        }
    }

    #[test]
    fn friction_is_dissipative_and_solved_exactly() {
        let p = Params {
            guide_f: 0.05,
            ..Params::default()
        };
        let q = Params { guide_f: 0.0, ..p };
        for k in 0..360 {
            let phi = TAU * (k as f64 + 0.5) / 360.0;
            let km = p.kinematics(phi, W100, 0.0);
            let f = p.forces(&km, 0.0, 12.0);
            // the equation of the spec holds with N from the solved force
            let n = p.table_m * STANDARD_GRAVITY + (f.cam_f * km.theta.sin()).abs();
            assert_abs_diff_eq!(f.guide_n, n, epsilon = 1e-12 * n);
            assert_abs_diff_eq!(
                f.f_x,
                p.table_m * km.a + p.guide_f * n * sgn(km.v) + 0.0 - 12.0,
                epsilon = 1e-9 * (1.0 + f.f_x.abs())
            );
            assert_abs_diff_eq!(f.f_friction, -p.guide_f * n * sgn(km.v), epsilon = 1e-12);
            // friction only adds power drawn
            let f0 = q.forces(&km, 0.0, 12.0);
            assert!(f.tau * W100 >= f0.tau * W100 - 1e-12);
        }
    }

    #[test]
    fn flank_and_hertz_stress() {
        let p = Params::default();
        for k in 0..720 {
            let phi = TAU * (k as f64 + 0.5) / 720.0;
            let km = p.kinematics(phi, W100, 0.0);
            let f = p.forces(&km, 0.0, 0.0);
            let rp = km.rho_pitch.abs();
            assert!(
                (f.rho_flank.abs() - (rp - p.roller_r)).abs() < 1e-12
                    || (f.rho_flank.abs() - (rp + p.roller_r)).abs() < 1e-12
            );
            // independent σH of eq. 8
            let inv = 1.0 / p.roller_r + 1.0 / f.rho_flank;
            let expected = 0.418 * ((f.cam_f.abs() / p.roller_b) * 2.1e11 * inv).sqrt();
            assert_abs_diff_eq!(f.sigma_h, expected, epsilon = 1e-9 * expected.max(1.0));
            // in the dwells: pitch circle R0 + x
            if matches!(km.c.phase, Phase::DwellFar | Phase::DwellNear) {
                assert_abs_diff_eq!(km.rho_pitch, p.cam_r0 + km.c.x, epsilon = 1e-12);
                assert_eq!(km.theta, 0.0);
            }
        }
        // accelerating: the cam pushes +x on the inner flank; decelerating: the outer one
        let acc = p.forces(&p.kinematics(0.5, W100, 0.0), 0.0, 0.0);
        assert!(acc.f_x > 0.0 && acc.cam_f > 0.0);
        let dec = p.forces(&p.kinematics(1.0, W100, 0.0), 0.0, 0.0);
        assert!(dec.f_x < 0.0 && dec.cam_f < 0.0);
    }

    #[test]
    fn undercut_is_refused_naming_angle_and_smallest_r0() {
        let p = Params::default();
        assert!(p.validate().is_ok());
        assert!(p.undercut(p.cam_r0).is_none());
        let r0_min = p.smallest_r0();
        let small = Params {
            cam_r0: 0.5 * r0_min,
            ..p
        };
        let e = small.validate().unwrap_err();
        assert_eq!(e.param, "cam.R0");
        assert!(
            e.condition.contains("undercut") && e.condition.contains("shaft angle"),
            "{e}"
        );
        assert!(e.condition.contains(&format!("{r0_min:.4}")), "{e}");
        // the reported radius works, a bit smaller does not
        assert!(
            Params {
                cam_r0: r0_min,
                ..p
            }
            .undercut(r0_min)
            .is_none()
        );
        assert!(p.undercut(r0_min - 2e-4).is_some());
        // the angle named lies in a travel phase where the pitch curve is tightest
        let (phi, _) = small.undercut(small.cam_r0).unwrap();
        let ph = small.cyclogram().at(phi).phase;
        assert!(matches!(ph, Phase::Forward | Phase::Return), "{ph:?}");
    }

    /// A fuzzed huge base radius once made the bisection spin for ever (the float spacing at
    /// 1e20 is far above its 1e-7 m tolerance); it must end, finite.
    #[test]
    fn smallest_r0_terminates_for_huge_and_tiny_radii() {
        let p = Params::default();
        for r0 in [1e20, 1e300, 1e-300, 0.0] {
            let r = Params { cam_r0: r0, ..p }.smallest_r0();
            assert!(r.is_finite() || r0 >= 1e300, "{r0}: {r}");
        }
    }

    #[test]
    fn other_refusals() {
        let p = Params::default();
        assert_eq!(
            Params { l1: 12.0, ..p }.validate().unwrap_err().param,
            "synth.l1"
        );
        assert_eq!(
            Params { alpha2: 1.6, ..p }.validate().unwrap_err().param,
            "synth.alpha2"
        );
        assert_eq!(
            Params { cam_e: 0.2, ..p }.validate().unwrap_err().param,
            "cam.e"
        );
        assert_eq!(
            Params { guide_f: 5.0, ..p }.validate().unwrap_err().param,
            "guide.f"
        );
        assert_eq!(
            Params {
                dwell_sew: 3.5,
                ..p
            }
            .validate()
            .unwrap_err()
            .param,
            "cycle.dwell_sew"
        );
        // the rocking table has no slot cam to undercut
        assert!(
            Params {
                cam_r0: 0.02,
                kind: Kind::Rocking,
                ..p
            }
            .validate()
            .is_ok()
        );
    }

    #[test]
    fn rocking_inertia_torque_is_larger() {
        // what the paper's redesign removes: the rocking table's peak inertia torque at the shaft
        // against the translating table's, same cyclogram and mass
        let p = Params {
            guide_f: 0.0,
            ..Params::default()
        };
        let (mut tr, mut ro) = (0.0f64, 0.0f64);
        for k in 0..3600 {
            let phi = TAU * k as f64 / 3600.0;
            tr = tr.max(p.forces(&p.kinematics(phi, W100, 0.0), 0.0, 0.0).tau.abs());
            ro = ro.max(p.rocking_tau(&p.rocking(phi, W100, 0.0), 0.0, 0.0).abs());
        }
        assert!(tr > 0.0 && ro > 0.0);
        // same travel and mass at radius R·unit: the swing's torque exceeds the slide's by (R·unit·α2/stroke)²
        let ratio = (p.r * p.unit * p.alpha2 / p.stroke()).powi(2);
        assert_abs_diff_eq!(ro / tr, ratio, epsilon = 1e-3 * ratio);
    }
}
