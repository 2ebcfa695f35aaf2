//! External Geneva pair: driver (radius `r1`, one roller) and cross with `Z` slots.
//!
//! Paper 003 (§2, "Мальтійський механізм розглядаємо в системі (i, ω, r1)") and
//! `geneva-knife-drive.md`, section Kinematics:
//!
//! - `λ = a/r1 = 1/sin(π/Z)` (paper 003: λ = 1.414 for Z = 4); centre distance `a = r1/sin(π/Z)`;
//! - half engagement angle `φe = π/2 − π/Z` (paper 003: 0.785 for Z = 4);
//! - driver angle within its turn `ψ = φ mod 2π`; the roller is in a slot for `ψ ∈ [0, 2φe]`;
//! - with `u = φe − ψ`: `γ = π/Z − atan(sin u/(λ − cos u))` (paper 003's γ(φ), with
//!   `0.5·γΣ = π/Z`), `γ' = (λ·cos u − 1)/(1 + λ² − 2λ·cos u)`,
//!   `γ'' = λ(λ² − 1)·sin u/(1 + λ² − 2λ·cos u)²`;
//! - outside the slot the cross is locked at `γ = 2π/Z`, `γ' = γ'' = 0`;
//! - roller–cross-centre distance `ρ = √(a² + r1² − 2·a·r1·cos u) = r1·√(1 + λ² − 2λ·cos u)`.
//!
//! Geometry used in the tests: driver centre at the origin, cross centre at `(a, 0)`, roller at
//! `r1·(cos u, sin u)`.

use super::{Scalar, wrap_angle_of};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// An external Geneva pair with `Z ≥ 3` slots (fewer cannot work: λ would be ≤ 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geneva {
    z: u32,
    r1: f64,
    lambda: f64,
    half_index: f64,
    phi_e: f64,
}

/// State of the Geneva pair at one driver angle; derivatives with respect to the driver angle
/// (any [`Scalar`]: `f64`, or dual numbers along the FMUs' inputs for their partial
/// derivatives).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GenevaState<T = f64> {
    /// Driver angle within its turn, `ψ = φ mod 2π ∈ [0, 2π)`, rad.
    pub psi: T,
    /// Whether the roller is in a slot: `ψ ∈ [0, 2φe]`.
    pub engaged: bool,
    /// `u = φe − ψ`, the roller's angle from the line of centres, rad.
    pub u: T,
    /// Cross angle within the current index, 0 → 2π/Z while engaged, 2π/Z in the dwell, rad.
    pub gamma: T,
    /// `γ' = dγ/dψ` (0 in the dwell).
    pub gamma_d: T,
    /// `γ'' = d²γ/dψ²` (0 in the dwell), 1/rad.
    pub gamma_dd: T,
    /// Distance roller – cross centre `ρ` (defined for every ψ; the roller's lever on the cross
    /// while engaged), m.
    pub rho: T,
}

impl Geneva {
    /// A Geneva pair with `z` slots and driver radius `r1` (m). Does not validate: `z < 3` or
    /// `r1 ≤ 0` give meaningless (possibly infinite) results; mechanisms refuse them first.
    pub fn new(z: u32, r1: f64) -> Self {
        let half_index = PI / f64::from(z);
        Self {
            z,
            r1,
            lambda: 1.0 / half_index.sin(),
            half_index,
            phi_e: FRAC_PI_2 - half_index,
        }
    }

    /// Number of slots Z.
    pub fn slots(&self) -> u32 {
        self.z
    }

    /// Driver radius r1 (centre to roller), m.
    pub fn r1(&self) -> f64 {
        self.r1
    }

    /// `λ = a/r1 = 1/sin(π/Z)`.
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// Centre distance `a = r1/sin(π/Z)`, m.
    pub fn centre_distance(&self) -> f64 {
        self.r1 * self.lambda
    }

    /// Half engagement angle `φe = π/2 − π/Z`, rad.
    pub fn half_engagement(&self) -> f64 {
        self.phi_e
    }

    /// Cross turn per index `2π/Z`, rad.
    pub fn index_angle(&self) -> f64 {
        2.0 * self.half_index
    }

    /// Fraction of the driver turn the cross stands still: `1 − 2φe/2π = 1/2 + 1/Z`.
    pub fn dwell_fraction(&self) -> f64 {
        1.0 - 2.0 * self.phi_e / TAU
    }

    /// Largest `γ'`, at `ψ = φe` (roller on the line of centres): `1/(λ − 1)`.
    pub fn max_gamma_d(&self) -> f64 {
        1.0 / (self.lambda - 1.0)
    }

    /// `γ''` just after entry (it jumps there from 0): `λ·cos(π/Z)/(λ² − 1)`.
    pub fn entry_gamma_dd(&self) -> f64 {
        self.lambda * self.half_index.cos() / (self.lambda * self.lambda - 1.0)
    }

    /// The pair at driver angle `phi` (any real value; reduced with [`super::wrap_angle`]; any
    /// [`Scalar`], the engagement decided on its value).
    #[inline]
    pub fn at<T: Scalar>(&self, phi: T) -> GenevaState<T> {
        let psi = wrap_angle_of(phi);
        let u = T::from(self.phi_e) - psi;
        let lam = self.lambda;
        // the sine only where it is used (the dwell, three quarters of a turn, needs none)
        let cu = u.cos();
        let d = T::from(1.0 + lam * lam) - cu * (2.0 * lam); // (ρ/r1)², ≥ (λ − 1)² > 0
        let rho = d.sqrt() * self.r1;
        let engaged = psi.re() <= 2.0 * self.phi_e;
        if engaged {
            let su = u.sin();
            GenevaState {
                psi,
                engaged,
                u,
                gamma: T::from(self.half_index) - su.atan2(T::from(lam) - cu),
                gamma_d: (cu * lam - 1.0) / d,
                gamma_dd: su * (lam * (lam * lam - 1.0)) / (d * d),
                rho,
            }
        } else {
            GenevaState {
                psi,
                engaged,
                u,
                gamma: T::from(2.0 * self.half_index),
                gamma_d: T::zero(),
                gamma_dd: T::zero(),
                rho,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;
    use std::f64::consts::FRAC_PI_4;

    const R1: f64 = 0.08;

    #[test]
    fn paper_003_constants_for_four_slots() {
        let g = Geneva::new(4, R1);
        // Paper 003: λ = 1.414, φe = 0.785, γΣ = 1.57.
        assert_abs_diff_eq!(g.lambda(), 1.414, epsilon = 5e-4);
        assert_abs_diff_eq!(g.lambda(), 2f64.sqrt(), epsilon = 1e-15);
        assert_abs_diff_eq!(g.half_engagement(), 0.785, epsilon = 5e-4);
        assert_abs_diff_eq!(g.index_angle(), 1.57, epsilon = 5e-3);
        assert_abs_diff_eq!(g.centre_distance(), R1 * 2f64.sqrt(), epsilon = 1e-16);
        assert_abs_diff_eq!(g.dwell_fraction(), 0.75, epsilon = 1e-15);
        assert_abs_diff_eq!(g.max_gamma_d(), 2.4142, epsilon = 5e-5);
        assert_abs_diff_eq!(g.entry_gamma_dd(), 1.0, epsilon = 1e-15);
    }

    #[test]
    fn index_ends_and_middle() {
        for z in 3..=12 {
            let g = Geneva::new(z, R1);
            let idx = g.index_angle();
            let s0 = g.at(0.0);
            assert!(s0.engaged);
            assert_abs_diff_eq!(s0.gamma, 0.0, epsilon = 1e-15);
            assert_abs_diff_eq!(s0.gamma_d, 0.0, epsilon = 1e-15);
            assert_abs_diff_eq!(s0.gamma_dd, g.entry_gamma_dd(), epsilon = 1e-13);
            let mid = g.at(g.half_engagement());
            assert_abs_diff_eq!(mid.gamma, idx / 2.0, epsilon = 1e-15);
            assert_abs_diff_eq!(mid.gamma_d, g.max_gamma_d(), epsilon = 1e-13);
            assert_abs_diff_eq!(mid.gamma_dd, 0.0, epsilon = 1e-15);
            assert_abs_diff_eq!(mid.rho, g.centre_distance() - R1, epsilon = 1e-15);
            let exit = g.at(2.0 * g.half_engagement());
            assert!(exit.engaged);
            assert_abs_diff_eq!(exit.gamma, idx, epsilon = 1e-14);
            assert_abs_diff_eq!(exit.gamma_d, 0.0, epsilon = 1e-15);
            assert_abs_diff_eq!(exit.gamma_dd, -g.entry_gamma_dd(), epsilon = 1e-13);
            let dwell = g.at(2.0 * g.half_engagement() + 1e-9);
            assert!(!dwell.engaged);
            assert_eq!(
                (dwell.gamma, dwell.gamma_d, dwell.gamma_dd),
                (idx, 0.0, 0.0)
            );
            // γ' is largest at the middle, and γ rises monotonically over the engagement.
            let n = 2000;
            let mut last = -1.0;
            for k in 0..=n {
                let s = g.at(2.0 * g.half_engagement() * k as f64 / n as f64);
                assert!(s.gamma_d <= g.max_gamma_d() + 1e-12);
                assert!(s.gamma_d >= -1e-15);
                assert!(s.gamma >= last);
                last = s.gamma;
            }
        }
    }

    /// Independent geometry: roller at r1·(cos u, sin u), cross centre at (a, 0).
    #[test]
    fn matches_the_geometry() {
        for z in [3, 4, 6, 8] {
            let g = Geneva::new(z, R1);
            let a = g.centre_distance();
            for k in 0..=500 {
                let psi = 2.0 * g.half_engagement() * k as f64 / 500.0;
                let s = g.at(psi);
                let u = g.half_engagement() - psi;
                let (ax, ay) = (R1 * u.cos(), R1 * u.sin());
                // The slot through the roller, seen from the cross centre, from the line of centres.
                let slot = ay.atan2(a - ax);
                assert_abs_diff_eq!(s.gamma, PI / f64::from(z) - slot, epsilon = 1e-14);
                assert_abs_diff_eq!(s.rho, ((ax - a).powi(2) + ay * ay).sqrt(), epsilon = 1e-15);
                assert_abs_diff_eq!(
                    s.rho,
                    (a * a + R1 * R1 - 2.0 * a * R1 * u.cos()).sqrt(),
                    epsilon = 1e-15
                );
            }
            // At entry the roller meets the slot tangentially: driver arm ⟂ slot (no impact).
            let u = g.half_engagement();
            let (ax, ay) = (R1 * u.cos(), R1 * u.sin());
            assert_abs_diff_eq!(ax * (ax - a) + ay * ay, 0.0, epsilon = 1e-15);
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-6;
        for z in [3, 4, 5, 8] {
            let g = Geneva::new(z, R1);
            let span = 2.0 * g.half_engagement();
            for k in 1..400 {
                let psi = span * k as f64 / 400.0;
                let (s, sp, sm) = (g.at(psi), g.at(psi + h), g.at(psi - h));
                assert_abs_diff_eq!(s.gamma_d, (sp.gamma - sm.gamma) / (2.0 * h), epsilon = 1e-8);
                assert_abs_diff_eq!(
                    s.gamma_dd,
                    (sp.gamma_d - sm.gamma_d) / (2.0 * h),
                    epsilon = 1e-7
                );
            }
        }
    }

    #[test]
    fn any_driver_angle() {
        let g = Geneva::new(4, R1);
        // Negative angles wrap forwards.
        let s = g.at(-0.1);
        assert_abs_diff_eq!(s.psi, TAU - 0.1, epsilon = 1e-15);
        assert!(!s.engaged);
        let a = g.at(0.3);
        let b = g.at(0.3 - 5.0 * TAU);
        assert_abs_diff_eq!(a.gamma, b.gamma, epsilon = 1e-13);
        assert_abs_diff_eq!(a.gamma_dd, b.gamma_dd, epsilon = 1e-12);
        // |φ| up to 1e9: finite, ψ in one turn.
        for phi in [1e9, -1e9, 1e9 + FRAC_PI_4, -7.5e8] {
            let s = g.at(phi);
            assert!((0.0..TAU).contains(&s.psi));
            for v in [s.gamma, s.gamma_d, s.gamma_dd, s.rho] {
                assert!(v.is_finite());
            }
        }
        // The dwell covers 3/4 of the turn.
        let n = 100_000;
        let dwell = (0..n)
            .filter(|k| !g.at(TAU * *k as f64 / n as f64).engaged)
            .count();
        assert_abs_diff_eq!(dwell as f64 / n as f64, 0.75, epsilon = 2.0 / n as f64);
    }
}
