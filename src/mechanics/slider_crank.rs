//! Central and offset slider-crank, exact closed forms.
//!
//! Geometry: crank of radius `r` turning about the origin, crank pin at `r·(cos θ, sin θ)`; rod of
//! length `l`; slider C on the guide line `y = e` (eccentricity `e`, 0 for a central
//! slider-crank). Then (paper 004, exact form of its eq. 1; `disc-knife-drive.md`)
//!
//! `x_C = r·cos θ + √(l² − (r·sin θ − e)²)`,  rod angle ν: `sin ν = (r·sin θ − e)/l`,
//!
//! ν being the rod's inclination to the guide. The slider's displacement from the outer dead
//! centre (the slider farthest from the crank axis), `s = x_max − x_C` with
//! `x_max = √((l + r)² − e²)`, is the knife displacement of `geneva-knife-drive.md`: for `e = 0`
//! it is `s = r·(1 + λ2 − cos θ − √(λ2² − sin²θ))`, `λ2 = l/r`, paper 003's invariant
//! `6 − cos 4γ − 5·cos ν` times `r` (with θ = 4γ, λ2 = 5).
//!
//! Derivatives are exact closed forms in θ; time derivatives follow by the chain rule. The
//! pose and its motion are generic over [`Scalar`]: the same operations, in the same order, on
//! `f64` and on the dual numbers of the FMUs' partial derivatives.

use super::Scalar;

/// A slider-crank: crank radius `r`, rod length `l`, guide eccentricity `e` (all in m).
///
/// The crank turns fully only if `l > r + |e|` ([`SliderCrank::can_turn`]); outside that the
/// functions return NaN where the rod cannot reach the guide.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SliderCrank {
    /// Crank radius r (paper 003: r2; paper 004: l1), m.
    pub r: f64,
    /// Rod length l (paper 003: l = λ2·r2; paper 004: l2 = λ2·l1), m.
    pub l: f64,
    /// Eccentricity e of the guide line from the crank axis (paper 004: e = ε·l1), m.
    pub e: f64,
}

/// Positions of a slider-crank at one crank angle, with derivatives in θ (any [`Scalar`]:
/// `f64`, or dual numbers along the FMUs' inputs for their partial derivatives).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pose<T = f64> {
    /// Slider position from the crank axis along the guide, `x_C`, m.
    pub x: T,
    /// `dx_C/dθ`, m/rad.
    pub dx: T,
    /// `d²x_C/dθ²`, m/rad².
    pub ddx: T,
    /// Slider displacement from the outer dead centre, `s = x_max − x_C ≥ 0`, m.
    pub s: T,
    /// `ds/dθ = r·sin(θ + ν)/cos ν`, m/rad.
    pub ds: T,
    /// `d²s/dθ²`, m/rad².
    pub dds: T,
    /// Rod angle ν, `sin ν = (r·sin θ − e)/l`, rad.
    pub nu: T,
    /// `sin ν = (r·sin θ − e)/l` (exact, without a round trip through ν).
    pub sin_nu: T,
    /// `cos ν = √(l² − (r·sin θ − e)²)/l`.
    pub cos_nu: T,
    /// `dν/dθ`.
    pub dnu: T,
    /// `d²ν/dθ²`, 1/rad.
    pub ddnu: T,
}

impl<T: Scalar> Pose<T> {
    /// This pose's velocities and accelerations for crank speed `theta_w` = θ̇ and acceleration
    /// `theta_a` = θ̈ (chain rule, `interface.md`): no trigonometry, so a mechanism can take the
    /// same pose at another crank acceleration cheaply.
    #[inline]
    pub fn motion(self, theta_w: T, theta_a: T) -> Motion<T> {
        let w2 = theta_w * theta_w;
        Motion {
            pose: self,
            v: self.ds * theta_w,
            a: self.dds * w2 + self.ds * theta_a,
            nu_w: self.dnu * theta_w,
            nu_a: self.ddnu * w2 + self.dnu * theta_a,
        }
    }
}

/// [`Pose`] plus time derivatives for a crank moving with `θ̇`, `θ̈`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion<T = f64> {
    /// Positions and θ-derivatives.
    pub pose: Pose<T>,
    /// Slider velocity `ṡ = ds/dθ·θ̇` (along s; `ẋ_C = −ṡ`), m/s.
    pub v: T,
    /// Slider acceleration `s̈ = d²s/dθ²·θ̇² + ds/dθ·θ̈`, m/s².
    pub a: T,
    /// Rod angular velocity `ν̇`, rad/s.
    pub nu_w: T,
    /// Rod angular acceleration `ν̈`, rad/s².
    pub nu_a: T,
}

impl SliderCrank {
    /// A central slider-crank (`e = 0`).
    pub const fn central(r: f64, l: f64) -> Self {
        Self { r, l, e: 0.0 }
    }

    /// An offset slider-crank with eccentricity `e`.
    pub const fn offset(r: f64, l: f64, e: f64) -> Self {
        Self { r, l, e }
    }

    /// `λ2 = l/r` (papers 003 and 004).
    pub fn lambda2(&self) -> f64 {
        self.l / self.r
    }

    /// Whether the crank can make full turns: `r > 0` and `l > r + |e|`.
    pub fn can_turn(&self) -> bool {
        self.r > 0.0 && self.l > self.r + self.e.abs()
    }

    /// Outer dead centre `x_max = √((l + r)² − e²)`: slider farthest from the crank axis (s = 0).
    pub fn x_max(&self) -> f64 {
        ((self.l + self.r).powi(2) - self.e * self.e).sqrt()
    }

    /// Inner dead centre `x_min = √((l − r)² − e²)`.
    pub fn x_min(&self) -> f64 {
        ((self.l - self.r).powi(2) - self.e * self.e).sqrt()
    }

    /// Stroke `x_max − x_min` (`2r` for a central slider-crank: paper 003's `S = 2·r2`).
    pub fn stroke(&self) -> f64 {
        if self.e == 0.0 {
            2.0 * self.r
        } else {
            self.x_max() - self.x_min()
        }
    }

    /// Positions and their θ-derivatives at crank angle `theta` (exact closed forms; any
    /// [`Scalar`]).
    ///
    /// `s` is computed without cancellation near the dead centre (`1 − cos θ` and
    /// `√(l² − e²) − √(l² − y²)` rewritten as quotients), so small displacements keep their
    /// relative accuracy.
    #[inline]
    pub fn pose<T: Scalar>(&self, theta: T) -> Pose<T> {
        let Self { r, l, e } = *self;
        let (st, ct) = theta.sin_cos();
        let rs = st * r;
        let y = rs - e;
        let w = (T::from(l * l) - y * y).sqrt(); // l·cos ν
        let dy = ct * r;
        let ddy = -rs;
        let inv_w = T::one() / w;
        let inv_w3 = inv_w * inv_w * inv_w;
        let x = ct * r + w;
        let dx = -rs - y * dy * inv_w;
        let ddx = ct * (-r) - (dy * dy + y * ddy) * inv_w - y * y * dy * dy * inv_w3;
        // s = x_max − x = c0 + r·(1 − cos θ) + (w0 − w), with w0 = √(l² − e²),
        // c0 = x_max − r − w0 (0 for e = 0) and w0 − w = (y² − e²)/(w0 + w).
        let one_minus_cos = if ct.re() >= 0.0 {
            st * st / (ct + 1.0)
        } else {
            T::one() - ct
        };
        let (c0, w0) = if e == 0.0 {
            (0.0, l)
        } else {
            let w0 = (l * l - e * e).sqrt();
            (self.x_max() - r - w0, w0)
        };
        let s = one_minus_cos * r + c0 + rs * (rs - 2.0 * e) / (w + w0);
        Pose {
            x,
            dx,
            ddx,
            s,
            ds: -dx,
            dds: -ddx,
            nu: y.atan2(w),
            sin_nu: y / l,
            cos_nu: w / l,
            dnu: dy * inv_w,
            ddnu: ddy * inv_w + dy * dy * y * inv_w3,
        }
    }

    /// [`SliderCrank::pose`] plus velocities and accelerations for crank speed `theta_w` = θ̇ and
    /// acceleration `theta_a` = θ̈ (chain rule, `interface.md`; any [`Scalar`]).
    #[inline]
    pub fn motion<T: Scalar>(&self, theta: T, theta_w: T, theta_a: T) -> Motion<T> {
        self.pose(theta).motion(theta_w, theta_a)
    }

    /// Moment arm of the rod force about the crank axis, `r·sin(θ + ν)`: a rod force P (along
    /// the rod) loads the crank with `P·r·sin(θ + ν)` (`geneva-knife-drive.md`, Kinetostatics).
    #[inline]
    pub fn torque_arm(&self, theta: f64) -> f64 {
        let (st, ct) = theta.sin_cos();
        let y = self.r * st - self.e;
        let w = (self.l * self.l - y * y).sqrt();
        // sin(θ + ν) = sin θ·cos ν + cos θ·sin ν, cos ν = w/l, sin ν = y/l.
        self.r * (st * w + ct * y) / self.l
    }

    /// Velocity ratio `ds/dθ = r·sin(θ + ν)/cos ν` (virtual work: the rod force's component along
    /// the guide, `P·cos ν`, times ds equals `P·r·sin(θ + ν)·dθ`).
    #[inline]
    pub fn velocity_ratio(&self, theta: f64) -> f64 {
        let (st, ct) = theta.sin_cos();
        let y = self.r * st - self.e;
        let w = (self.l * self.l - y * y).sqrt();
        self.r * (st * w + ct * y) / w
    }

    /// Paper 004's series form (its eq. 1, "with sufficient accuracy", `e = 0` only; `e` is
    /// ignored): `x_C = r·(λ2 + cos θ − sin²θ/(2λ2))`, returned with `dx_C/dθ` and `d²x_C/dθ²`
    /// (its eqs. 2–4 by differentiation; any [`Scalar`]).
    #[inline]
    pub fn x_series<T: Scalar>(&self, theta: T) -> (T, T, T) {
        let l2 = self.lambda2();
        let (st, ct) = theta.sin_cos();
        let (s2, c2) = (theta * 2.0).sin_cos();
        (
            (ct + l2 - st * st / (2.0 * l2)) * self.r,
            (-st - s2 / (2.0 * l2)) * self.r,
            (-ct - c2 / l2) * self.r,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanics::assert_derivatives_match_differences;
    use approx::{assert_abs_diff_eq, assert_relative_eq};
    use std::f64::consts::{FRAC_PI_2, PI, TAU};

    /// The Geneva knife drive's crank (r2 = 0.07, λ2 = 5), the disc-knife drive's (l1 = 19 mm,
    /// λ2 = 2), and two offset ones, one with negative e.
    const CASES: [SliderCrank; 4] = [
        SliderCrank::central(0.07, 0.35),
        SliderCrank::central(0.019, 0.038),
        SliderCrank::offset(0.05, 0.16, 0.02),
        SliderCrank::offset(0.03, 0.07, -0.015),
    ];

    fn angles() -> impl Iterator<Item = f64> {
        (0..=720).map(|k| -PI + k as f64 * TAU / 720.0 + 1e-3)
    }

    #[test]
    fn central_matches_the_spec_formula() {
        let sc = CASES[0];
        let (r, l2) = (sc.r, sc.lambda2());
        assert_abs_diff_eq!(l2, 5.0, epsilon = 1e-15);
        for th in angles() {
            let p = sc.pose(th);
            let spec = r * (1.0 + l2 - th.cos() - (l2 * l2 - th.sin().powi(2)).sqrt());
            assert_abs_diff_eq!(p.s, spec, epsilon = 1e-16);
            // Paper 003's invariant 6 − cos θ − 5·cos ν, times r2.
            let nu = (th.sin() / 5.0).asin();
            assert_abs_diff_eq!(p.s, r * (6.0 - th.cos() - 5.0 * nu.cos()), epsilon = 1e-16);
            assert_abs_diff_eq!(p.nu, nu, epsilon = 1e-15);
        }
        assert_eq!(sc.pose(0.0).s, 0.0);
        assert_abs_diff_eq!(sc.pose(PI).s, 2.0 * r, epsilon = 1e-16);
        assert_eq!(sc.stroke(), 0.14);
    }

    #[test]
    fn offset_matches_the_disc_knife_form() {
        // x_C = l1·cos φ + √(l2² − (l1·sin φ − e)²) (disc-knife-drive.md).
        for sc in CASES {
            for th in angles() {
                let x = sc.r * th.cos() + (sc.l * sc.l - (sc.r * th.sin() - sc.e).powi(2)).sqrt();
                let p = sc.pose(th);
                assert_abs_diff_eq!(p.x, x, epsilon = 1e-15);
                assert_abs_diff_eq!(p.s, sc.x_max() - x, epsilon = 1e-15);
                // The rod really has length l: pin (r cos θ, r sin θ) to slider (x, e).
                let d = ((p.x - sc.r * th.cos()).powi(2) + (sc.e - sc.r * th.sin()).powi(2)).sqrt();
                assert_abs_diff_eq!(d, sc.l, epsilon = 1e-15);
                assert_abs_diff_eq!(p.nu.sin(), (sc.r * th.sin() - sc.e) / sc.l, epsilon = 1e-15);
                assert!(
                    p.s >= -1e-16 && p.s <= sc.stroke() + 1e-15,
                    "s = {} out of stroke",
                    p.s
                );
            }
        }
    }

    /// disc-knife-drive.md reference values: x_C at φ = 0, π/2, π and the series form at π/2.
    #[test]
    fn disc_knife_reference_values() {
        let sc = SliderCrank::central(0.019, 2.0 * 0.019);
        assert_abs_diff_eq!(sc.pose(0.0).x * 1e3, 57.000, epsilon = 5e-4);
        assert_abs_diff_eq!(sc.pose(FRAC_PI_2).x * 1e3, 32.909, epsilon = 5e-4);
        assert_abs_diff_eq!(sc.pose(PI).x * 1e3, 19.000, epsilon = 5e-4);
        assert_abs_diff_eq!(sc.x_series(FRAC_PI_2).0 * 1e3, 33.250, epsilon = 5e-4);
        // The series form agrees with the exact one at the dead centres.
        assert_abs_diff_eq!(sc.x_series(0.0).0, sc.pose(0.0).x, epsilon = 1e-15);
        assert_abs_diff_eq!(sc.x_series(PI).0, sc.pose(PI).x, epsilon = 1e-15);
    }

    #[test]
    fn series_derivatives_match_finite_differences() {
        let sc = CASES[1];
        let h = 1e-5;
        for th in angles() {
            assert_derivatives_match_differences(|th| sc.x_series(th), th, h, 1e-11, 1e-11);
        }
    }

    #[test]
    fn theta_derivatives_match_finite_differences() {
        let h = 1e-5;
        for sc in CASES {
            for th in angles() {
                let (p, pp, pm) = (sc.pose(th), sc.pose(th + h), sc.pose(th - h));
                let scale = sc.r;
                assert_abs_diff_eq!(p.ds, (pp.s - pm.s) / (2.0 * h), epsilon = 1e-9 * scale);
                assert_abs_diff_eq!(p.dds, (pp.ds - pm.ds) / (2.0 * h), epsilon = 1e-9 * scale);
                assert_abs_diff_eq!(p.dx, (pp.x - pm.x) / (2.0 * h), epsilon = 1e-9 * scale);
                assert_abs_diff_eq!(p.ddx, (pp.dx - pm.dx) / (2.0 * h), epsilon = 1e-9 * scale);
                // Second derivative straight from positions, too (a wider step: round-off / h²).
                let h2 = 1e-4;
                let fd2 = (sc.pose(th + h2).s - 2.0 * p.s + sc.pose(th - h2).s) / (h2 * h2);
                assert_abs_diff_eq!(p.dds, fd2, epsilon = 1e-6 * scale);
                assert_abs_diff_eq!(p.dnu, (pp.nu - pm.nu) / (2.0 * h), epsilon = 1e-9);
                assert_abs_diff_eq!(p.ddnu, (pp.dnu - pm.dnu) / (2.0 * h), epsilon = 1e-9);
            }
        }
    }

    #[test]
    fn time_derivatives_by_chain_rule() {
        // θ(t) = θ0 + w·t + α·t²/2: compare v, a, ν̇, ν̈ with differences in time.
        let h = 1e-6;
        for sc in CASES {
            for (w, alpha) in [(12.0, 0.0), (-7.0, 35.0), (3.0, -400.0)] {
                let tol = 1e-8 * sc.r * (1.0 + w * w + f64::abs(alpha));
                for th0 in angles().step_by(7) {
                    let th = |t: f64| th0 + w * t + 0.5 * alpha * t * t;
                    let m = sc.motion(th0, w, alpha);
                    let (sp, sm) = (sc.pose(th(h)), sc.pose(th(-h)));
                    let (mp, mm) = (
                        sc.motion(th(h), w + alpha * h, alpha),
                        sc.motion(th(-h), w - alpha * h, alpha),
                    );
                    assert_abs_diff_eq!(m.v, (sp.s - sm.s) / (2.0 * h), epsilon = tol);
                    assert_abs_diff_eq!(m.a, (mp.v - mm.v) / (2.0 * h), epsilon = 100.0 * tol);
                    assert_abs_diff_eq!(m.nu_w, (sp.nu - sm.nu) / (2.0 * h), epsilon = tol / sc.r);
                    assert_abs_diff_eq!(
                        m.nu_a,
                        (mp.nu_w - mm.nu_w) / (2.0 * h),
                        epsilon = 100.0 * tol / sc.r
                    );
                }
            }
        }
    }

    /// ds/dθ = r·sin(θ + ν)/cos ν, with ν taken from its definition sin ν = (r sin θ − e)/l.
    #[test]
    fn velocity_ratio_identity() {
        for sc in CASES {
            for th in angles() {
                let nu = ((sc.r * th.sin() - sc.e) / sc.l).asin();
                let identity = sc.r * (th + nu).sin() / nu.cos();
                let p = sc.pose(th);
                assert_abs_diff_eq!(p.ds, identity, epsilon = 1e-15);
                assert_abs_diff_eq!(sc.velocity_ratio(th), identity, epsilon = 1e-15);
                assert_abs_diff_eq!(sc.torque_arm(th), sc.r * (th + nu).sin(), epsilon = 1e-15);
                assert_abs_diff_eq!(sc.torque_arm(th), p.ds * p.nu.cos(), epsilon = 1e-15);
                assert_abs_diff_eq!(p.sin_nu, p.nu.sin(), epsilon = 1e-15);
                assert_abs_diff_eq!(p.cos_nu, p.nu.cos(), epsilon = 1e-15);
            }
        }
    }

    #[test]
    fn dead_centres_and_stroke() {
        for sc in CASES {
            // Outer dead centre: crank and rod aligned, θ = asin(e/(l + r)).
            let th_o = (sc.e / (sc.l + sc.r)).asin();
            let p = sc.pose(th_o);
            assert_abs_diff_eq!(p.s, 0.0, epsilon = 1e-15);
            assert_abs_diff_eq!(p.ds, 0.0, epsilon = 1e-14);
            // Inner dead centre: crank and rod overlap, θ = π + asin(e/(l − r)).
            let th_i = PI + (sc.e / (sc.l - sc.r)).asin();
            let p = sc.pose(th_i);
            assert_relative_eq!(p.s, sc.stroke(), max_relative = 1e-12);
            assert_abs_diff_eq!(p.ds, 0.0, epsilon = 1e-14);
        }
        // Small displacements keep relative accuracy (no cancellation near the dead centre).
        let sc = CASES[0];
        let th = 1e-9;
        let expected = 0.5 * sc.r * th * th * (1.0 + 1.0 / sc.lambda2());
        assert_relative_eq!(sc.pose(th).s, expected, max_relative = 1e-9);
        assert_relative_eq!(sc.pose(-th).s, expected, max_relative = 1e-9);
    }

    #[test]
    fn can_turn() {
        assert!(CASES.iter().all(SliderCrank::can_turn));
        assert!(!SliderCrank::central(0.07, 0.07).can_turn());
        assert!(!SliderCrank::offset(0.05, 0.06, 0.02).can_turn());
        assert!(!SliderCrank::central(0.0, 0.3).can_turn());
        // A crank that cannot turn gives NaN where the rod cannot reach the guide.
        assert!(SliderCrank::central(0.1, 0.05).pose(FRAC_PI_2).s.is_nan());
    }
}
