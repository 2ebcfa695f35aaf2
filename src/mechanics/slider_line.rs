//! A link of length `l` from a joint A to a slider B on a fixed line: the perforators' rod 10 and
//! carriage 11 (paper 000, Fig. 4; `perforators.md`, section "Exact kinematics").
//!
//! The line is `B = e·n + s·u` with `n = (cos α, sin α)` (from the origin to the line, at distance
//! `e`, the paper's eccentricity λ2) and `u = (−sin α, cos α)` along it. Then
//!
//! `s(A) = u·A + √(l² − (e − n·A)²)`, the link angle ν to the line: `sin ν = (e − n·A)/l`
//! (`perforators.md`; at the lowest position this is paper 000 eq. 2).
//!
//! The inverse, for a joint on a circle `|A| = r` about the origin, is the intersection of the
//! circles `|A| = r` and `|A − B| = l`, on a chosen branch.

// `!(x > 0.0)` is deliberate throughout: a NaN parameter fails the check too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::{Scalar, dot};

/// The line and the link.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SliderLine {
    /// Link length λ1, m.
    pub l: f64,
    /// Distance of the line from the origin λ2 ("eccentricity"), m.
    pub e: f64,
    /// Angle α of the line from the vertical (the line's normal `n` from the x-axis), rad
    /// (private: `n` and `u` are made from it once, in [`SliderLine::new`]).
    alpha: f64,
    /// `n` and `u` ([`Self::n`], [`Self::u`]), made once: every pose needs them.
    n: (f64, f64),
    u: (f64, f64),
}

/// Slider position and link angle for a joint position and its derivatives in a parameter q
/// (any [`Scalar`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SliderPose<T = f64> {
    /// `s`, position of B along `u`.
    pub s: T,
    /// `ds/dq`.
    pub ds: T,
    /// `d²s/dq²`.
    pub dds: T,
    /// `sin ν = (e − n·A)/l`.
    pub sin_nu: T,
    /// `cos ν = √(l² − (e − n·A)²)/l`.
    pub cos_nu: T,
}

/// A plane vector of `f64` as one of `T`.
#[inline]
fn of<T: Scalar>(x: (f64, f64)) -> (T, T) {
    (T::from(x.0), T::from(x.1))
}

impl SliderLine {
    /// The line at distance `e` and angle `alpha` with a link of length `l`.
    pub fn new(l: f64, e: f64, alpha: f64) -> SliderLine {
        SliderLine {
            l,
            e,
            alpha,
            n: (alpha.cos(), alpha.sin()),
            u: (-alpha.sin(), alpha.cos()),
        }
    }

    /// Unit normal `n = (cos α, sin α)`.
    pub fn n(&self) -> (f64, f64) {
        self.n
    }

    /// Unit direction `u = (−sin α, cos α)` of the line.
    pub fn u(&self) -> (f64, f64) {
        self.u
    }

    /// The slider B at position `s` (any [`Scalar`]).
    pub fn b<T: Scalar>(&self, s: T) -> (T, T) {
        let (n, u) = (self.n(), self.u());
        (s * u.0 + self.e * n.0, s * u.1 + self.e * n.1)
    }

    /// `s` and its derivatives for a joint at `a` moving with `a1 = dA/dq`, `a2 = d²A/dq²`:
    /// `s = u·A + c`, `c = √(l² − p²)`, `p = e − n·A`; `s' = u·A' + p·(n·A')/c`;
    /// `s'' = u·A'' + (p·(n·A'') − (n·A')²)/c − p²·(n·A')²/c³`. NaN if the link cannot reach.
    /// Any [`Scalar`], with the same floating-point operations for `f64`.
    pub fn pose<T: Scalar>(&self, a: (T, T), a1: (T, T), a2: (T, T)) -> SliderPose<T> {
        let (n, u) = (of(self.n()), of(self.u()));
        let p = T::from(self.e) - dot(n, a);
        let c = (T::from(self.l * self.l) - p * p).sqrt();
        let m = dot(n, a1);
        let m2 = dot(n, a2);
        SliderPose {
            s: dot(u, a) + c,
            ds: dot(u, a1) + p * m / c,
            dds: dot(u, a2) + (p * m2 - m * m) / c - p * p * m * m / (c * c * c),
            sin_nu: p / self.l,
            cos_nu: c / self.l,
        }
    }

    /// Inverse for a joint on the circle `|A| = r`: the joint A for the slider at `s`, on the
    /// branch `sign` (±1: which side of the line from the origin to B). `None` if the circles do
    /// not meet. Any [`Scalar`] `s` (the branch decided on the real part).
    pub fn joint_on_circle<T: Scalar>(&self, r: f64, s: T, sign: f64) -> Option<(T, T)> {
        let b = self.b(s);
        let d = dot(b, b).sqrt();
        let a = (d * d + (r * r - self.l * self.l)) / (d * 2.0);
        let h2 = T::from(r * r) - a * a;
        if !(h2.re() >= 0.0) {
            return None;
        }
        let h = h2.sqrt();
        let (bx, by) = (b.0 / d, b.1 / d);
        Some((a * bx - h * sign * by, a * by + h * sign * bx))
    }

    /// Which branch a joint position lies on: the sign of `B × A` (for [`Self::joint_on_circle`]).
    pub fn branch_of(&self, a: (f64, f64)) -> f64 {
        let b = self.b(self.pose(a, (0.0, 0.0), (0.0, 0.0)).s);
        (b.0 * a.1 - b.1 * a.0).signum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;

    fn paper() -> SliderLine {
        SliderLine::new(1.07, 2.0, 37f64.to_radians())
    }

    /// A joint on a circle of radius 2.03 at angle t − 6°, as the perforators' lever arm λ3.
    fn joint(t: f64) -> ((f64, f64), (f64, f64), (f64, f64)) {
        let r = 2.03;
        let g = t - 6f64.to_radians();
        (
            (r * g.cos(), r * g.sin()),
            (-r * g.sin(), r * g.cos()),
            (-r * g.cos(), -r * g.sin()),
        )
    }

    #[test]
    fn link_length_and_line_hold() {
        let sl = paper();
        for k in 0..40 {
            let (a, a1, a2) = joint(k as f64 * 0.01);
            let p = sl.pose(a, a1, a2);
            let b = sl.b(p.s);
            let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
            assert_abs_diff_eq!(len, 1.07, epsilon = 1e-14);
            assert_abs_diff_eq!(p.sin_nu.powi(2) + p.cos_nu.powi(2), 1.0, epsilon = 1e-14);
            // sin ν is the link's component along n
            assert_abs_diff_eq!(
                p.sin_nu,
                dot(sl.n(), (b.0 - a.0, b.1 - a.1)) / 1.07,
                epsilon = 1e-14
            );
            let _ = a2;
        }
        // paper 000 eq. 2 at the lowest position: ν = 28.79°
        let (a, _, _) = joint(0.0);
        assert_abs_diff_eq!(
            sl.pose(a, (0.0, 0.0), (0.0, 0.0))
                .sin_nu
                .asin()
                .to_degrees(),
            28.79,
            epsilon = 0.005
        );
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let sl = paper();
        let e = 1e-6;
        for k in 0..40 {
            let t = k as f64 * 0.0123;
            let (a, a1, a2) = joint(t);
            let p = sl.pose(a, a1, a2);
            let f = |t: f64| {
                let (a, a1, a2) = joint(t);
                sl.pose(a, a1, a2)
            };
            assert_abs_diff_eq!(p.ds, (f(t + e).s - f(t - e).s) / (2.0 * e), epsilon = 1e-8);
            assert_abs_diff_eq!(
                p.dds,
                (f(t + e).ds - f(t - e).ds) / (2.0 * e),
                epsilon = 1e-7
            );
        }
    }

    #[test]
    fn inverse_recovers_the_joint() {
        let sl = paper();
        let (a0, _, _) = joint(0.0);
        let sign = sl.branch_of(a0);
        for k in 0..50 {
            let (a, _, _) = joint(k as f64 * 0.01);
            let s = sl.pose(a, (0.0, 0.0), (0.0, 0.0)).s;
            let back = sl.joint_on_circle(2.03, s, sign).unwrap();
            assert_abs_diff_eq!(back.0, a.0, epsilon = 1e-12);
            assert_abs_diff_eq!(back.1, a.1, epsilon = 1e-12);
        }
        assert!(sl.joint_on_circle(2.03, 50.0, sign).is_none());
    }
}
