//! Normalized cam motion laws (spec page `motion-laws.md`).
//!
//! A law maps the phase fraction `u ∈ [0, 1]` of a rise to the displacement fraction `L(u)`,
//! `L(0) = 0`, `L(1) = 1`. Paper 002 recommends the cycloidal law ("Co") for the needles' working
//! stroke and the harmonic law ("K") for their idle stroke; that identification is the spec's
//! assumption.

use crate::mechanics::Scalar;
use std::f64::consts::{PI, TAU};

/// A normalized motion law (`motion-laws.md`, table "Normalized motion laws").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MotionLaw {
    /// Cycloidal (sine acceleration), paper 002's "Co":
    /// `L = u − sin(2πu)/(2π)`, `L' = 1 − cos(2πu)`, `L'' = 2π·sin(2πu)`.
    Cycloidal,
    /// Harmonic (cosine acceleration), paper 002's "K":
    /// `L = (1 − cos πu)/2`, `L' = (π/2)·sin πu`, `L'' = (π²/2)·cos πu`.
    /// Its acceleration jumps at both ends of the rise.
    Harmonic,
    /// 3-4-5 polynomial: `L = 10u³ − 15u⁴ + 6u⁵`, `L' = 30u² − 60u³ + 30u⁴`,
    /// `L'' = 60u − 180u² + 120u³`.
    Poly345,
}

impl MotionLaw {
    /// All the laws, for tests and enumerations.
    pub const ALL: [MotionLaw; 3] = [
        MotionLaw::Cycloidal,
        MotionLaw::Harmonic,
        MotionLaw::Poly345,
    ];

    /// `(L(u), L'(u), L''(u))` of the normalized law (`motion-laws.md`), derivatives in `u`.
    ///
    /// `u` is clamped to `[0, 1]`: before the rise `(0, 0, 0)`, after it `(1, 0, 0)` (the rest
    /// around a rise). At `u = 0` and `u = 1` exactly the formula is evaluated, so the harmonic
    /// law returns its one-sided `L'' = ±π²/2` there. NaN gives NaN.
    #[inline]
    pub fn eval<T: Scalar>(self, u: T) -> (T, T, T) {
        if u.re() < 0.0 {
            return (T::zero(), T::zero(), T::zero());
        }
        if u.re() > 1.0 {
            return (T::one(), T::zero(), T::zero());
        }
        match self {
            MotionLaw::Cycloidal => {
                let (s, c) = (u * TAU).sin_cos();
                (u - s / TAU, T::one() - c, s * TAU)
            }
            MotionLaw::Harmonic => {
                let (s, c) = (u * PI).sin_cos();
                ((T::one() - c) * 0.5, s * (0.5 * PI), c * (0.5 * PI * PI))
            }
            MotionLaw::Poly345 => {
                let u2 = u * u;
                let u3 = u2 * u;
                (
                    u3 * (u * (u * 6.0 - 15.0) + 10.0),
                    u2 * (u * (u * 30.0 - 60.0) + 30.0),
                    u * (u * (u * 120.0 - 180.0) + 60.0),
                )
            }
        }
    }

    /// A rise of height `h` over the phase angle `span` (> 0), `phi` measured from the start of
    /// the rise: `(x, dx/dφ, d²x/dφ²)` with `x = h·L(u)`, `dx/dφ = h·L'(u)/Φ`,
    /// `d²x/dφ² = h·L''(u)/Φ²`, `u = φ/Φ` (`motion-laws.md`).
    #[inline]
    pub fn rise<T: Scalar>(self, h: f64, span: f64, phi: T) -> (T, T, T) {
        debug_assert!(
            span > 0.0,
            "a rise needs a positive phase angle, got {span}"
        );
        let (l, l1, l2) = self.eval(phi / span);
        (l * h, l1 * h / span, l2 * h / (span * span))
    }

    /// A fall of height `h` over the phase angle `span` (> 0), `phi` from the start of the fall:
    /// `x = h·(1 − L(u))` and its derivatives (`motion-laws.md`).
    #[inline]
    pub fn fall<T: Scalar>(self, h: f64, span: f64, phi: T) -> (T, T, T) {
        let (x, dx, ddx) = self.rise(h, span, phi);
        (T::from(h) - x, -dx, -ddx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanics::assert_derivatives_match_differences;
    use approx::assert_abs_diff_eq;

    /// Dense grid of the rise, ends included.
    fn grid(n: usize) -> impl Iterator<Item = f64> {
        (0..=n).map(move |k| k as f64 / n as f64)
    }

    #[test]
    fn end_values() {
        for law in MotionLaw::ALL {
            let (l0, d0, _) = law.eval(0.0);
            let (l1, d1, _) = law.eval(1.0);
            assert_abs_diff_eq!(l0, 0.0, epsilon = 1e-15);
            assert_abs_diff_eq!(l1, 1.0, epsilon = 1e-15);
            assert_abs_diff_eq!(d0, 0.0, epsilon = 1e-15);
            assert_abs_diff_eq!(d1, 0.0, epsilon = 1e-15);
            // Symmetric laws: half the rise at half the phase.
            assert_abs_diff_eq!(law.eval(0.5).0, 0.5, epsilon = 1e-15);
        }
        // Acceleration at the ends: zero except for the harmonic law.
        assert_abs_diff_eq!(MotionLaw::Cycloidal.eval(0.0).2, 0.0, epsilon = 1e-12);
        assert_abs_diff_eq!(MotionLaw::Cycloidal.eval(1.0).2, 0.0, epsilon = 1e-12);
        assert_abs_diff_eq!(MotionLaw::Poly345.eval(0.0).2, 0.0, epsilon = 1e-12);
        assert_abs_diff_eq!(MotionLaw::Poly345.eval(1.0).2, 0.0, epsilon = 1e-12);
        assert_abs_diff_eq!(
            MotionLaw::Harmonic.eval(0.0).2,
            PI * PI / 2.0,
            epsilon = 1e-12
        );
        assert_abs_diff_eq!(
            MotionLaw::Harmonic.eval(1.0).2,
            -PI * PI / 2.0,
            epsilon = 1e-12
        );
    }

    #[test]
    fn outside_the_rise_is_rest() {
        for law in MotionLaw::ALL {
            assert_eq!(law.eval(-0.1), (0.0, 0.0, 0.0));
            assert_eq!(law.eval(-1e9), (0.0, 0.0, 0.0));
            assert_eq!(law.eval(1.1), (1.0, 0.0, 0.0));
            assert_eq!(law.eval(f64::INFINITY), (1.0, 0.0, 0.0));
        }
    }

    /// Peak values from `motion-laws.md`.
    #[test]
    fn peak_values() {
        let peaks = |law: MotionLaw| {
            grid(200_000).fold((0.0f64, 0.0f64), |(v, a), u| {
                let (_, d1, d2) = law.eval(u);
                (v.max(d1.abs()), a.max(d2.abs()))
            })
        };
        let (v, a) = peaks(MotionLaw::Cycloidal);
        assert_abs_diff_eq!(v, 2.0, epsilon = 1e-9);
        assert_abs_diff_eq!(a, TAU, epsilon = 1e-9);
        let (v, a) = peaks(MotionLaw::Harmonic);
        assert_abs_diff_eq!(v, PI / 2.0, epsilon = 1e-9);
        assert_abs_diff_eq!(a, PI * PI / 2.0, epsilon = 1e-9);
        let (v, a) = peaks(MotionLaw::Poly345);
        assert_abs_diff_eq!(v, 1.875, epsilon = 1e-9);
        assert_abs_diff_eq!(a, 10.0 / 3f64.sqrt(), epsilon = 1e-8);
        assert_abs_diff_eq!(10.0 / 3f64.sqrt(), 5.7735, epsilon = 5e-5);
        // Where the peaks are, exactly.
        assert_abs_diff_eq!(MotionLaw::Poly345.eval(0.5).1, 1.875, epsilon = 1e-15);
        let u_star = 0.5 - 3f64.sqrt() / 6.0;
        assert_abs_diff_eq!(
            MotionLaw::Poly345.eval(u_star).2,
            10.0 / 3f64.sqrt(),
            epsilon = 1e-12
        );
        assert_abs_diff_eq!(MotionLaw::Cycloidal.eval(0.25).2, TAU, epsilon = 1e-12);
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-6;
        for law in MotionLaw::ALL {
            for u in grid(400).filter(|&u| u > 2.0 * h && u < 1.0 - 2.0 * h) {
                assert_derivatives_match_differences(|u| law.eval(u), u, h, 1e-8, 1e-7);
            }
        }
    }

    #[test]
    fn rise_and_fall_scaling() {
        let (h, span) = (0.11152, 82f64.to_radians());
        for law in MotionLaw::ALL {
            for k in 0..=50 {
                let phi = span * k as f64 / 50.0;
                let (x, dx, ddx) = law.rise(h, span, phi);
                let (l, l1, l2) = law.eval(phi / span);
                assert_abs_diff_eq!(x, h * l, epsilon = 1e-15);
                assert_abs_diff_eq!(dx, h * l1 / span, epsilon = 1e-15);
                assert_abs_diff_eq!(ddx, h * l2 / (span * span), epsilon = 1e-13);
                let (xf, dxf, ddxf) = law.fall(h, span, phi);
                assert_abs_diff_eq!(x + xf, h, epsilon = 1e-15);
                assert_abs_diff_eq!(dx + dxf, 0.0, epsilon = 1e-15);
                assert_abs_diff_eq!(ddx + ddxf, 0.0, epsilon = 1e-15);
            }
            // Chain rule in φ against finite differences.
            let (phi, e) = (0.4 * span, 1e-6);
            let fd = (law.rise(h, span, phi + e).0 - law.rise(h, span, phi - e).0) / (2.0 * e);
            assert_abs_diff_eq!(law.rise(h, span, phi).1, fd, epsilon = 1e-9);
            let fd2 = (law.rise(h, span, phi + e).1 - law.rise(h, span, phi - e).1) / (2.0 * e);
            assert_abs_diff_eq!(law.rise(h, span, phi).2, fd2, epsilon = 1e-7);
            // Before and after: rest at 0 and at h.
            assert_eq!(law.rise(h, span, -0.1), (0.0, 0.0, 0.0));
            assert_eq!(law.rise(h, span, span + 0.1), (h, 0.0, 0.0));
            assert_eq!(law.fall(h, span, span + 0.1), (0.0, 0.0, 0.0));
        }
    }
}
