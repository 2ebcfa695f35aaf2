//! The cyclogram of a cam-driven member (`sewing-table.md`, section "Cyclogram and motion";
//! paper 000, Fig. 2): one shaft turn is forward travel, dwell at the far end ("sewing"), return
//! travel, dwell at the near end ("loading"); rise and fall follow separately chosen normalized
//! laws ([`crate::mechanics::motion_laws`]).
//!
//! Used by `SewingTable` (table travel, and the rocking table's swing angle) and by `Perforators`
//! (the table position the ramp is traversed with).

// `!(x > 0.0)` is deliberate throughout: a NaN parameter fails the check too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::mechanics::motion_laws::MotionLaw;
use crate::mechanics::{ParamError, Scalar, wrap_angle_of};
use std::f64::consts::TAU;

/// The four phases of a turn (`table.phase` in `sewing-table.md`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Forward travel (loading I → sewing III), `table.phase` = 0.
    Forward = 0,
    /// Dwell at the far end (sewing), 1.
    DwellFar = 1,
    /// Return travel, 2.
    Return = 2,
    /// Dwell at the near end (loading), 3.
    DwellNear = 3,
}

/// A cyclogram: phase angles (rad), where the forward travel starts, the laws, the displacement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cyclogram {
    /// Displacement `h` from the near to the far end (m, or rad for a swing).
    pub h: f64,
    /// Shaft angle of the forward travel Φf (`cycle.forward`), rad.
    pub forward: f64,
    /// Dwell at the far end (`cycle.dwell_sew`), rad.
    pub dwell_far: f64,
    /// Shaft angle of the return Φr (`cycle.return`), rad.
    pub ret: f64,
    /// Shaft angle where the forward travel starts (`cycle.phi0`), rad.
    pub phi0: f64,
    /// Law of the forward travel (`law.forward`).
    pub law_forward: MotionLaw,
    /// Law of the return travel (`law.return`), applied as a fall.
    pub law_return: MotionLaw,
}

/// Position of the member at one shaft angle, with derivatives in the shaft angle φ (any
/// [`Scalar`]: `f64`, or dual numbers for the derivatives in the inputs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CyclePoint<T = f64> {
    pub phase: Phase,
    /// Shaft angle since the start of the forward travel, in `[0, 2π)`, rad.
    pub psi: T,
    /// Displacement `x` from the near end.
    pub x: T,
    /// `dx/dφ`.
    pub dx: T,
    /// `d²x/dφ²`.
    pub ddx: T,
}

impl<T: Scalar> CyclePoint<T> {
    /// Velocity `v = x'·ω` and acceleration `a = x''·ω² + x'·ε` (chain rule, `interface.md`;
    /// any [`Scalar`]).
    pub fn motion(&self, w: T, eps: T) -> (T, T) {
        (self.dx * w, self.ddx * w * w + self.dx * eps)
    }
}

impl Cyclogram {
    /// The dwell at the near end: `2π` minus the other three phases (`cycle.dwell_load`), rad.
    pub fn dwell_near(&self) -> f64 {
        TAU - self.forward - self.dwell_far - self.ret
    }

    /// Checks the phases (`sewing-table.md`: the loading dwell is refused if ≤ 0). Parameter names
    /// are the FMI ones.
    pub fn validate(&self) -> Result<(), ParamError> {
        crate::require!(
            self.forward > 0.0,
            "cycle.forward",
            self.forward,
            "the forward travel needs a positive shaft angle"
        );
        crate::require!(
            self.ret > 0.0,
            "cycle.return",
            self.ret,
            "the return travel needs a positive shaft angle"
        );
        crate::require!(
            self.dwell_far >= 0.0,
            "cycle.dwell_sew",
            self.dwell_far,
            "must not be negative"
        );
        crate::require!(
            self.dwell_near() > 0.0,
            "cycle.dwell_sew",
            self.dwell_far,
            "cycle.forward + cycle.dwell_sew + cycle.return = {:.4} deg leaves no loading dwell (cycle.dwell_load = {:.4} deg must be > 0)",
            (self.forward + self.dwell_far + self.ret).to_degrees(),
            self.dwell_near().to_degrees()
        );
        Ok(())
    }

    /// The member at shaft angle `phi` (any real; 2π-periodic): phase, `x`, `dx/dφ`, `d²x/dφ²`
    /// (`motion-laws.md`: rise `h·L(u)`, fall `h·(1 − L(u))`).
    pub fn at<T: Scalar>(&self, phi: T) -> CyclePoint<T> {
        let psi = wrap_angle_of(phi - self.phi0);
        let f_end = self.forward;
        let d_end = f_end + self.dwell_far;
        let r_end = d_end + self.ret;
        let (phase, (x, dx, ddx)) = if psi.re() < f_end {
            (
                Phase::Forward,
                self.law_forward.rise(self.h, self.forward, psi),
            )
        } else if psi.re() < d_end {
            (Phase::DwellFar, (T::from(self.h), T::zero(), T::zero()))
        } else if psi.re() < r_end {
            (
                Phase::Return,
                self.law_return.fall(self.h, self.ret, psi - d_end),
            )
        } else {
            (Phase::DwellNear, (T::zero(), T::zero(), T::zero()))
        };
        CyclePoint {
            phase,
            psi,
            x,
            dx,
            ddx,
        }
    }

    /// The shaft angles where the four phases start (forward travel, far dwell, return, near
    /// dwell), from `phi0` on, rad.
    pub fn boundaries(&self) -> [f64; 4] {
        let b0 = self.phi0;
        [
            b0,
            b0 + self.forward,
            b0 + self.forward + self.dwell_far,
            b0 + self.forward + self.dwell_far + self.ret,
        ]
    }

    /// Event indicators of the four phase changes at the shaft angle `phi` counted on over the
    /// turns (not wrapped): `sin((φ − b)/2)` for each of the [`Cyclogram::boundaries`] `b`, a sign
    /// change at each crossing and at no other angle of a turn.
    pub fn phase_indicators(&self, phi: f64) -> [f64; 4] {
        self.boundaries().map(|b| ((phi - b) * 0.5).sin())
    }

    /// Shaft angle (since the start of the forward travel) where the forward travel reaches the
    /// fraction `q ∈ [0, 1]` of `h`, by bisection on the monotone rise (for symmetric laws and
    /// `q = 1/2` it is exactly `Φf/2`).
    pub fn forward_angle_at(&self, q: f64) -> f64 {
        let (mut lo, mut hi) = (0.0, self.forward);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if self.law_forward.eval(mid / self.forward).0 < q {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;

    fn spec() -> Cyclogram {
        Cyclogram {
            h: 0.111518,
            forward: 82f64.to_radians(),
            dwell_far: 110f64.to_radians(),
            ret: 90f64.to_radians(),
            phi0: 0.0,
            law_forward: MotionLaw::Cycloidal,
            law_return: MotionLaw::Cycloidal,
        }
    }

    #[test]
    fn phases_and_ends() {
        let c = spec();
        assert_abs_diff_eq!(c.dwell_near().to_degrees(), 78.0, epsilon = 1e-12);
        let at = |deg: f64| c.at(deg.to_radians());
        assert_eq!(at(0.0).phase, Phase::Forward);
        assert_eq!(at(81.9).phase, Phase::Forward);
        assert_eq!(at(82.1).phase, Phase::DwellFar);
        assert_eq!(at(191.9).phase, Phase::DwellFar);
        assert_eq!(at(192.1).phase, Phase::Return);
        assert_eq!(at(281.9).phase, Phase::Return);
        assert_eq!(at(282.1).phase, Phase::DwellNear);
        assert_eq!(at(359.9).phase, Phase::DwellNear);
        assert_eq!(at(0.0).x, 0.0);
        assert_eq!(at(100.0).x, c.h);
        assert_eq!(at(300.0).x, 0.0);
        // continuity of x and x' at every boundary (cycloidal: also x'')
        for b in [82.0, 192.0, 282.0, 360.0] {
            let (l, r) = (at(b - 1e-9), at(b + 1e-9));
            assert_abs_diff_eq!(l.x, r.x, epsilon = 1e-10);
            assert_abs_diff_eq!(l.dx, r.dx, epsilon = 1e-8);
            assert_abs_diff_eq!(l.ddx, r.ddx, epsilon = 1e-6);
        }
        // periodic, and phi0 shifts the whole diagram
        assert_abs_diff_eq!(c.at(0.7).x, c.at(0.7 + 3.0 * TAU).x, epsilon = 1e-12);
        let s = Cyclogram { phi0: 0.4, ..c };
        assert_abs_diff_eq!(s.at(1.1).x, c.at(0.7).x, epsilon = 1e-15);
    }

    #[test]
    fn derivatives_match_finite_differences() {
        for law_r in MotionLaw::ALL {
            let c = Cyclogram {
                law_forward: MotionLaw::Poly345,
                law_return: law_r,
                ..spec()
            };
            for k in 1..720 {
                let phi = TAU * (k as f64 + 0.37) / 720.0;
                let e = 1e-6;
                let p = c.at(phi);
                let fd = (c.at(phi + e).x - c.at(phi - e).x) / (2.0 * e);
                let fd2 = (c.at(phi + e).dx - c.at(phi - e).dx) / (2.0 * e);
                assert_abs_diff_eq!(p.dx, fd, epsilon = 1e-8);
                assert_abs_diff_eq!(p.ddx, fd2, epsilon = 1e-6);
            }
        }
    }

    #[test]
    fn half_travel_at_half_the_forward_angle() {
        // paper 000, Fig. 2: half the table travel at phi = 41 deg of the 82 deg forward travel.
        let c = spec();
        assert_abs_diff_eq!(c.forward_angle_at(0.5).to_degrees(), 41.0, epsilon = 1e-9);
        assert_abs_diff_eq!(c.at(41f64.to_radians()).x, c.h / 2.0, epsilon = 1e-15);
    }

    #[test]
    fn refuses_phases_that_do_not_fit() {
        let c = spec();
        let e = Cyclogram {
            dwell_far: 200f64.to_radians(),
            ..c
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.param, "cycle.dwell_sew");
        assert!(e.condition.contains("cycle.dwell_load"), "{e}");
        assert_eq!(
            Cyclogram { forward: 0.0, ..c }
                .validate()
                .unwrap_err()
                .param,
            "cycle.forward"
        );
        assert_eq!(
            Cyclogram { ret: -1.0, ..c }.validate().unwrap_err().param,
            "cycle.return"
        );
        assert!(c.validate().is_ok());
    }
}
