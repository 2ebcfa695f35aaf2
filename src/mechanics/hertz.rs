//! Hertz line contact (roller on cam or ramp), paper 002 eq. 8 and `sewing-table.md`; and the
//! unilateral force law `F = K·δ^(10/9)` of a line contact (`dynamics.md`, Palmgren's approach).
//!
//! `σH = 0.418·√(q·E/ρ)`, with the load per unit length `q = F/b`, the reduced modulus
//! `E = 2·E1·E2/(E1 + E2)` and the reduced radius `1/ρ = 1/r1 ± 1/r2` (+ for a convex
//! counter-surface, − for a concave one). The factor 0.418 is `√(1/(2π(1 − ν²)))` for
//! Poisson's ratio ν = 0.3 (steel on steel).

use crate::mechanics::Scalar;
use std::fmt;

/// Hertz factor of paper 002 eq. 8 (ν = 0.3).
pub const HERTZ_FACTOR: f64 = 0.418;

/// Shape of the second body's surface where the roller touches it (`sewing-table.md`:
/// "+ convex flank, − concave").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Surface {
    /// Convex: curvatures add, `1/ρ = 1/r1 + 1/r2`.
    Convex,
    /// Concave: curvatures subtract, `1/ρ = 1/r1 − 1/r2`.
    Concave,
}

/// Why a Hertz stress cannot be given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HertzError {
    /// The reduced curvature `1/ρ` is ≤ 0: a concave surface as tight as the roller or tighter
    /// (conformal contact or a roller that does not fit; for a cam, an undercut profile).
    NonPositiveCurvature {
        /// The reduced curvature `1/r1 − 1/r2`, 1/m.
        inv_rho: f64,
    },
    /// A non-positive or non-finite width, modulus or roller radius, or a non-finite force.
    InvalidInput(&'static str),
}

impl fmt::Display for HertzError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HertzError::NonPositiveCurvature { inv_rho } => {
                write!(
                    f,
                    "reduced curvature 1/rho = {inv_rho} 1/m is not positive (conformal or undercut contact)"
                )
            }
            HertzError::InvalidInput(what) => write!(f, "invalid Hertz input: {what}"),
        }
    }
}

impl std::error::Error for HertzError {}

/// Reduced modulus `E = 2·E1·E2/(E1 + E2)` (paper 002, below eq. 8), Pa.
#[inline]
pub fn reduced_modulus(e1: f64, e2: f64) -> f64 {
    2.0 * e1 * e2 / (e1 + e2)
}

/// Reduced curvature `1/ρ = 1/r1 ± 1/r2` (paper 002, below eq. 8), 1/m. `r2 = ∞` is a flat.
#[inline]
pub fn reduced_curvature<T: Scalar>(r1: f64, r2: T, surface: Surface) -> T {
    // a flat (r2 infinite, over a whole stretch): 1/r2 = 0 with the derivative 0
    let inv_r2 = if r2.re().is_infinite() {
        T::from(1.0 / r2.re())
    } else {
        T::one() / r2
    };
    match surface {
        Surface::Convex => inv_r2 + 1.0 / r1,
        Surface::Concave => T::from(1.0 / r1) - inv_r2,
    }
}

/// Hertz line-contact stress `σH = 0.418·√(q·E/ρ)` (paper 002 eq. 8), Pa.
///
/// `force` F (N) presses a roller of radius `r1` (m) and width `b` (m) against a surface of
/// curvature radius `r2` (m, `f64::INFINITY` for a flat) of the given shape; `e1`, `e2` are the
/// two Young's moduli (Pa). The stress depends on the magnitude of the force (the caller decides
/// which flank carries it). Errors when `1/ρ ≤ 0` or an input is out of range.
pub fn line_contact_stress<T: Scalar>(
    force: T,
    b: f64,
    e1: f64,
    e2: f64,
    r1: f64,
    r2: T,
    surface: Surface,
) -> Result<T, HertzError> {
    if !force.re().is_finite() {
        return Err(HertzError::InvalidInput("force must be finite"));
    }
    if !(b > 0.0 && b.is_finite()) {
        return Err(HertzError::InvalidInput("contact width b must be positive"));
    }
    if !(e1 > 0.0 && e2 > 0.0 && e1.is_finite() && e2.is_finite()) {
        return Err(HertzError::InvalidInput("moduli must be positive"));
    }
    if !(r1 > 0.0 && r1.is_finite() && r2.re() > 0.0) {
        return Err(HertzError::InvalidInput("radii must be positive"));
    }
    let inv_rho = reduced_curvature(r1, r2, surface);
    if inv_rho.re() <= 0.0 {
        return Err(HertzError::NonPositiveCurvature {
            inv_rho: inv_rho.re(),
        });
    }
    let q = force.abs() / b;
    if q.re() == 0.0 {
        // no force, no stress: the stress's minimum, a cusp of √|F| whose slope is unbounded
        // on either side; a dual number gets the derivative 0 there (a subgradient), not NaN
        return Ok(T::zero());
    }
    Ok((q * reduced_modulus(e1, e2) * inv_rho).sqrt() * HERTZ_FACTOR)
}

/// A roller on a cam or a ramp: what the Hertz formulas of its line contact take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roller {
    /// `roller.r`: radius, m.
    pub r: f64,
    /// `roller.b`: width, the length of the line contact, m.
    pub b: f64,
    /// Young's modulus of the surface the roller runs on (`cam.E`, `ramp.E`), Pa.
    pub e_track: f64,
    /// `roller.E`: Young's modulus of the roller, Pa.
    pub e: f64,
}

impl Roller {
    /// Radius `r`, width `b`, the moduli of the track and of the roller.
    pub const fn new(r: f64, b: f64, e_track: f64, e: f64) -> Roller {
        Roller { r, b, e_track, e }
    }

    /// A steel roller of radius `r` and width `b` on steel (2.1e11 Pa both).
    pub const fn steel(r: f64, b: f64) -> Roller {
        Roller::new(r, b, 2.1e11, 2.1e11)
    }

    /// [`line_contact_stress`] under `force` on a surface of curvature radius `rho` (m, its
    /// magnitude) and shape `surface`; NaN where the formula has no answer (a reduced
    /// curvature not above 0, an input out of range).
    pub fn stress<T: Scalar>(&self, force: T, rho: T, surface: Surface) -> T {
        line_contact_stress(force, self.b, self.e_track, self.e, self.r, rho, surface)
            .unwrap_or(T::from(f64::NAN))
    }

    /// [`line_contact_stiffness`] of the roller's contact.
    pub fn stiffness(&self) -> f64 {
        line_contact_stiffness(self.b, self.e_track, self.e)
    }
}

/// Palmgren's line-contact approach of a steel roller, `δ = 3.84e-5·Q^0.9/l^0.8` (δ in mm, Q in
/// N, l the contact length in mm; A. Palmgren, *Ball and Roller Bearing Engineering*), in SI
/// units: `δ = PALMGREN_SI·Q^0.9·l^-0.8`.
pub const PALMGREN_SI: f64 = 3.84e-5 * 1e-3 * 0.003_981_071_705_534_972; // × 1000^-0.8

/// The modulus Palmgren's constant holds for (steel), Pa.
pub const PALMGREN_E: f64 = 2.1e11;

/// Stiffness constant `K` of the unilateral Hertz line contact `F = K·δ^(10/9)` (`dynamics.md`:
/// "force ∝ penetration^(10/9)"), N/m^(10/9): Palmgren's approach inverted,
/// `K = b^(8/9)·PALMGREN_SI^(-10/9)`, scaled to other materials by the reduced modulus
/// (`δ` depends on the load through `Q/(E·b)`): `K·E/PALMGREN_E`.
pub fn line_contact_stiffness(b: f64, e1: f64, e2: f64) -> f64 {
    reduced_modulus(e1, e2) / PALMGREN_E * b.powf(8.0 / 9.0) * PALMGREN_SI.powf(-10.0 / 9.0)
}

/// Force of the Hertz line contact at penetration `pen` (m): `K·pen^(10/9)`, 0 when `pen ≤ 0`
/// (the contact cannot pull); with `dF/dpen` (any [`Scalar`]).
#[inline]
pub fn line_contact_force<T: Scalar>(k: f64, pen: T) -> (T, T) {
    if pen.re() > 0.0 {
        let p19 = pen.powf(1.0 / 9.0);
        (pen * k * p19, p19 * (10.0 / 9.0 * k))
    } else {
        (T::zero(), T::zero())
    }
}

/// Elastic energy stored in the Hertz line contact at penetration `pen`: `9/19·K·pen^(19/9)`, J
/// (any [`Scalar`]).
#[inline]
pub fn line_contact_energy<T: Scalar>(k: f64, pen: T) -> T {
    if pen.re() > 0.0 {
        pen.powf(19.0 / 9.0) * (9.0 / 19.0 * k)
    } else {
        T::zero()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use std::f64::consts::PI;

    /// Hand calculation: F = 1000 N, b = 15 mm, steel on steel (2.1e11 Pa), roller 15 mm on a
    /// convex flank of 100 mm: 1/ρ = 66.667 + 10 = 76.667 1/m, q = 66 667 N/m,
    /// q·E/ρ = 66 667 · 2.1e11 · 76.667 = 1.07333e18, √ = 1.03602e9, × 0.418 = 433.06 MPa.
    #[test]
    fn hand_calculation() {
        // Then a concave flank of 100 mm: 1/ρ = 56.667 → 372.31 MPa; and steel on bronze
        // (1.1e11): E = 2·2.1·1.1/3.2 e11 = 1.44375e11 → 359.07 MPa.
        assert_relative_eq!(
            reduced_modulus(2.1e11, 1.1e11),
            1.44375e11,
            max_relative = 1e-12
        );
        for (e2, surface, sigma) in [
            (2.1e11, Surface::Convex, 433.06e6),
            (2.1e11, Surface::Concave, 372.31e6),
            (1.1e11, Surface::Convex, 359.07e6),
        ] {
            let s = line_contact_stress(1000.0, 0.015, 2.1e11, e2, 0.015, 0.1, surface).unwrap();
            assert_relative_eq!(s, sigma, max_relative = 1e-4);
        }
        // Same modulus: E = E1; a flat: 1/ρ = 1/r1; the force's sign does not matter.
        assert_relative_eq!(
            reduced_modulus(2.1e11, 2.1e11),
            2.1e11,
            max_relative = 1e-15
        );
        let flat = line_contact_stress(
            -1000.0,
            0.015,
            2.1e11,
            2.1e11,
            0.015,
            f64::INFINITY,
            Surface::Convex,
        );
        let expected = HERTZ_FACTOR * (1000.0 / 0.015 * 2.1e11 / 0.015f64).sqrt();
        assert_relative_eq!(flat.unwrap(), expected, max_relative = 1e-15);
        // Scaling: σ ∝ √F.
        let s1 =
            line_contact_stress(250.0, 0.015, 2.1e11, 2.1e11, 0.015, 0.1, Surface::Convex).unwrap();
        assert_relative_eq!(s1, 433.06e6 / 2.0, max_relative = 1e-4);
    }

    #[test]
    fn factor_is_classical_hertz_for_steel() {
        // σ = √(F·E'/(π·b·ρ)), E' = E/(2(1 − ν²)) for equal materials: factor √(1/(2π(1 − ν²))).
        let nu: f64 = 0.3;
        assert_relative_eq!(
            (1.0 / (2.0 * PI * (1.0 - nu * nu))).sqrt(),
            HERTZ_FACTOR,
            max_relative = 1e-3
        );
    }

    #[test]
    fn refuses_non_positive_curvature_and_bad_input() {
        // A concave surface exactly as tight as the roller, and a tighter one.
        assert!(matches!(
            line_contact_stress(100.0, 0.01, 2e11, 2e11, 0.015, 0.015, Surface::Concave),
            Err(HertzError::NonPositiveCurvature { inv_rho }) if inv_rho == 0.0
        ));
        assert!(matches!(
            line_contact_stress(100.0, 0.01, 2e11, 2e11, 0.015, 0.01, Surface::Concave),
            Err(HertzError::NonPositiveCurvature { inv_rho }) if inv_rho < 0.0
        ));
        for bad in [
            line_contact_stress(100.0, 0.0, 2e11, 2e11, 0.015, 0.1, Surface::Convex),
            line_contact_stress(100.0, 0.01, -2e11, 2e11, 0.015, 0.1, Surface::Convex),
            line_contact_stress(100.0, 0.01, 2e11, 2e11, 0.0, 0.1, Surface::Convex),
            line_contact_stress(f64::NAN, 0.01, 2e11, 2e11, 0.015, 0.1, Surface::Convex),
            line_contact_stress(100.0, 0.01, 2e11, 2e11, 0.015, -0.1, Surface::Convex),
        ] {
            assert!(matches!(bad, Err(HertzError::InvalidInput(_))), "{bad:?}");
        }
        // Zero force: zero stress.
        assert_eq!(
            line_contact_stress(0.0, 0.01, 2e11, 2e11, 0.015, 0.1, Surface::Convex),
            Ok(0.0)
        );
        // on dual numbers: 0 with the derivative 0 at zero force (not NaN from √0), the
        // slope of √F just off it
        let d = |f: f64, df: f64| {
            let f = num_dual::Dual64::new(f, df);
            line_contact_stress(f, 0.01, 2e11, 2e11, 0.015, 0.1.into(), Surface::Convex).unwrap()
        };
        let at0 = d(0.0, 1.0);
        assert_eq!((at0.re, at0.eps), (0.0, 0.0));
        let s = d(4.0, 1.0);
        assert_relative_eq!(s.eps, s.re / 8.0, max_relative = 1e-12);
    }
    /// Palmgren's formula by hand: a 10 mm steel roller under 1000 N approaches by
    /// 3.84e-5·1000^0.9/10^0.8 = 3.84e-5·501.19/6.3096 = 3.0503e-3 mm; the force law gives the
    /// load back, its slope is 10/9·F/δ, its energy the integral of the force.
    #[test]
    fn palmgren_line_contact_force_law() {
        let k = line_contact_stiffness(0.010, 2.1e11, 2.1e11);
        let d = 3.0503e-6;
        let (f, df) = line_contact_force(k, d);
        assert_relative_eq!(f, 1000.0, max_relative = 2e-4);
        assert_relative_eq!(df, 10.0 / 9.0 * f / d, max_relative = 1e-12);
        assert_eq!(line_contact_force(k, -1e-6), (0.0, 0.0));
        // the energy's derivative is the force
        let h = 1e-12;
        let de = (line_contact_energy(k, d + h) - line_contact_energy(k, d - h)) / (2.0 * h);
        assert_relative_eq!(de, f, max_relative = 1e-5);
        // a softer material: the same load needs more approach
        let k2 = line_contact_stiffness(0.010, 2.1e11, 1.1e11);
        assert!(k2 < k);
    }
}
