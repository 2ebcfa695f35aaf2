//! Radial cam with a translating roller follower: pitch-curve curvature and pressure angle
//! (`sewing-table.md`, section "Cam and forces").
//!
//! The pitch curve (path of the roller centre) in polar form is `r(φ) = R0 + x(φ)` for a follower
//! on a line through the cam axis (`e = 0`), `x` the follower's displacement law.

use crate::mechanics::Scalar;

/// Curvature radius of a polar curve `r(φ)`:
/// `ρ = (r² + r'²)^{3/2}/(r² + 2r'² − r·r'')` (`sewing-table.md`, ρpitch), derivatives in φ.
///
/// Signed: positive where the curve is convex (seen from the cam axis), negative where concave;
/// infinite at an inflection (denominator 0).
#[inline]
pub fn polar_curvature_radius(r: f64, dr: f64, ddr: f64) -> f64 {
    let n = r * r + dr * dr;
    n * n.sqrt() / (n + dr * dr - r * ddr)
}

/// Pitch-curve curvature radius of a radial cam `r(φ) = R0 + x(φ)` (`e = 0`), from the follower
/// law `x`, `dx/dφ`, `d²x/dφ²` (`sewing-table.md`). Signed as [`polar_curvature_radius`].
#[inline]
pub fn pitch_curvature_radius(r0: f64, x: f64, dx: f64, ddx: f64) -> f64 {
    polar_curvature_radius(r0 + x, dx, ddx)
}

/// Signed pitch-curve curvature radius of a radial cam with a translating roller follower offset
/// by `e` from the cam axis, for any `e` with `|e| < R0` (extends `sewing-table.md`'s `e = 0`
/// formula, to which it reduces).
///
/// In the follower's frame the roller centre is `Q = (e, y)`, `y = √(R0² − e²) + x(φ)`; in the
/// cam's frame it is `P = Rot(−φ)·Q`, so `P' = Rot(−φ)(Q' − K·Q)`,
/// `P'' = Rot(−φ)(Q'' − 2K·Q' − Q)` (`K` the quarter turn), and
/// `ρ = −|P'|³/(P' × P'')`: positive where convex (seen from the cam axis), as
/// [`polar_curvature_radius`].
#[inline]
pub fn offset_pitch_curvature_radius<T: Scalar>(r0: f64, e: f64, x: T, dx: T, ddx: T) -> T {
    let y = x + (r0 * r0 - e * e).sqrt();
    // V1 = Q' − K·Q with Q = (e, y), Q' = (0, dx), K·Q = (−y, e)
    let v1 = (y, dx - e);
    // V2 = Q'' − 2K·Q' − Q with Q'' = (0, ddx), K·Q' = (−dx, 0)
    let v2 = (dx * 2.0 - e, ddx - y);
    let n = v1.0 * v1.0 + v1.1 * v1.1;
    -(n * n.sqrt()) / (v1.0 * v2.1 - v1.1 * v2.0)
}

/// Pressure angle of a translating roller follower with offset `e` on a cam of base (pitch)
/// radius `R0` (`sewing-table.md`): `θp = atan((dx/dφ − e)/(√(R0² − e²) + x))`, rad.
/// Needs `|e| < R0`. Any [`Scalar`] law, as [`offset_pitch_curvature_radius`].
#[inline]
pub fn pressure_angle<T: Scalar>(r0: f64, e: f64, x: T, dx: T) -> T {
    ((dx - e) / (x + (r0 * r0 - e * e).sqrt())).atan()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanics::motion_laws::MotionLaw;
    use crate::mechanics::slider_crank::SliderCrank;
    use approx::assert_abs_diff_eq;
    use std::f64::consts::{PI, TAU};

    #[test]
    fn circle_about_the_axis() {
        // x constant (a dwell): the pitch curve is the circle R0 + x, at any angle.
        for (r0, x) in [(0.1, 0.0), (0.1, 0.03), (0.05, 0.0)] {
            assert_abs_diff_eq!(
                pitch_curvature_radius(r0, x, 0.0, 0.0),
                r0 + x,
                epsilon = 1e-16
            );
            assert_abs_diff_eq!(pressure_angle(r0, 0.0, x, 0.0), 0.0, epsilon = 1e-16);
        }
    }

    /// A circle of radius R whose centre is d off the cam axis: in polar form
    /// r(φ) = d·cos φ + √(R² − d²·sin²φ), which is the slider-crank position x_C with r = d,
    /// l = R. Its curvature radius is R everywhere.
    #[test]
    fn eccentric_circle() {
        let (d, big_r) = (0.02, 0.1);
        let sc = SliderCrank::central(d, big_r);
        for k in 0..360 {
            let phi = TAU * k as f64 / 360.0;
            let p = sc.pose(phi);
            assert_abs_diff_eq!(
                polar_curvature_radius(p.x, p.dx, p.ddx),
                big_r,
                epsilon = 1e-15
            );
        }
    }

    #[test]
    fn concave_and_pressure_angle_geometry() {
        // A circle of radius R seen from a point outside it bulges away from that point on the near
        // side: r(φ) = d cos φ − √(R² − d² sin²φ) with d > R is the near arc, concave (ρ = −R).
        let (d, big_r) = (0.2, 0.05);
        for phi in [-0.1f64, 0.0, 0.15] {
            let s: f64 = (big_r * big_r - d * d * phi.sin().powi(2)).sqrt();
            let r = |p: f64| d * p.cos() - (big_r * big_r - d * d * p.sin().powi(2)).sqrt();
            let h = 1e-4;
            let dr = (r(phi + h) - r(phi - h)) / (2.0 * h);
            let ddr = (r(phi + h) - 2.0 * r(phi) + r(phi - h)) / (h * h);
            assert!(s > 0.0);
            assert_abs_diff_eq!(
                polar_curvature_radius(r(phi), dr, ddr),
                -big_r,
                epsilon = 1e-6
            );
        }
        // A cam circular about its axis pushing an offset follower: θp = −asin(e/R0).
        let (r0, e) = (0.1, 0.03);
        assert_abs_diff_eq!(
            pressure_angle(r0, e, 0.0, 0.0),
            -(e / r0).asin(),
            epsilon = 1e-15
        );
        // Archimedean spiral r = R0 + c·φ, e = 0: tan θp = r'/r (angle of the normal to the radius).
        let c: f64 = 0.02;
        for phi in [0.0, 1.0, 2.5] {
            let th = pressure_angle(r0, 0.0, c * phi, c);
            assert_abs_diff_eq!(th.tan(), c / (r0 + c * phi), epsilon = 1e-15);
        }
    }

    #[test]
    fn offset_curvature_reduces_to_the_polar_formula() {
        let (r0, h, span) = (0.1, 0.03, PI / 2.0);
        let law = MotionLaw::Cycloidal;
        for k in 0..=50 {
            let (x, dx, ddx) = law.rise(h, span, span * k as f64 / 50.0);
            let a = offset_pitch_curvature_radius(r0, 0.0, x, dx, ddx);
            let b = pitch_curvature_radius(r0, x, dx, ddx);
            assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{a} vs {b}");
        }
        // an offset follower on a dwell: the circle sqrt(R0^2 - e^2 + ...) about the axis
        let (e, x) = (0.03, 0.02);
        let y = (r0 * r0 - e * e).sqrt() + x;
        assert_abs_diff_eq!(
            offset_pitch_curvature_radius(r0, e, x, 0.0, 0.0),
            (e * e + y * y).sqrt(),
            epsilon = 1e-14
        );
        // against the curvature of the roller-centre path built in the cam frame, by differences
        let path = |p: f64| {
            let (x, _, _) = law.rise(h, span, p);
            let y = (r0 * r0 - e * e).sqrt() + x;
            let (s, c) = (-p).sin_cos();
            (c * e - s * y, s * e + c * y)
        };
        for p in [0.3, 0.8, 1.2] {
            let d = 1e-4;
            let (a, b, c) = (path(p - d), path(p), path(p + d));
            let v = ((c.0 - a.0) / (2.0 * d), (c.1 - a.1) / (2.0 * d));
            let w = (
                (c.0 - 2.0 * b.0 + a.0) / (d * d),
                (c.1 - 2.0 * b.1 + a.1) / (d * d),
            );
            let n = v.0 * v.0 + v.1 * v.1;
            let rho_fd = -(n * n.sqrt()) / (v.0 * w.1 - v.1 * w.0);
            let (x, dx, ddx) = law.rise(h, span, p);
            let rho = offset_pitch_curvature_radius(r0, e, x, dx, ddx);
            assert_abs_diff_eq!(rho, rho_fd, epsilon = 1e-5 * rho.abs());
        }
    }

    #[test]
    fn cam_with_a_motion_law() {
        // A cycloidal rise of 30 mm over 90°: finite curvature, derivatives consistent with the
        // polar formula evaluated on finite-difference derivatives of r(φ).
        let (r0, h, span) = (0.1, 0.03, PI / 2.0);
        let law = MotionLaw::Cycloidal;
        for k in 1..50 {
            let phi = span * k as f64 / 50.0;
            let (x, dx, ddx) = law.rise(h, span, phi);
            let e = 1e-5;
            let r = |p: f64| r0 + law.rise(h, span, p).0;
            let dr = (r(phi + e) - r(phi - e)) / (2.0 * e);
            let ddr = (r(phi + e) - 2.0 * r(phi) + r(phi - e)) / (e * e);
            let rho = pitch_curvature_radius(r0, x, dx, ddx);
            assert!(rho.is_finite());
            assert_abs_diff_eq!(
                rho,
                polar_curvature_radius(r(phi), dr, ddr),
                epsilon = 1e-4 * rho.abs()
            );
        }
    }
}
