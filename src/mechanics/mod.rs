//! Shared mechanics, written once and used by every mechanism.
//!
//! Pure functions of geometry and motion: no FFI, no FMI. Every formula names its source:
//! paper 003 (seed `003_*`, the Geneva knife drive), paper 002 (seed `002_*`, perforators and
//! Hertz stress, eq. 8), paper 004 (seed `004_*`, disc-knife drive), and the spec pages in
//! `shared/spec/` (`geneva-knife-drive.md`, `motion-laws.md`, `sewing-table.md`, ...).
//!
//! - [`motion_laws`]: normalized cam motion laws (cycloidal, harmonic, 3-4-5 polynomial).
//! - [`slider_crank`]: central and offset slider-crank, exact closed forms.
//! - [`geneva`]: external Geneva pair (driver with roller, cross with Z slots).
//! - [`hertz`]: Hertz line-contact stress.
//! - [`cam`]: pitch-curve curvature and pressure angle of a radial cam.
//! - [`circles`]: where two links meet (circle intersection, on dual numbers).
//! - [`cyclogram`]: forward / dwell / return / dwell over one shaft turn (paper 000, Fig. 2).
//! - [`slider_line`]: a link from a joint to a slider on a line (the perforators' rod, paper 000 Fig. 4).

pub mod cam;
pub mod circles;
pub mod cyclogram;
pub mod geneva;
pub mod hertz;
pub mod motion_laws;
pub mod slider_crank;
pub mod slider_line;

use std::f64::consts::TAU;

/// A number the mechanics computes with: `f64`, or a dual number (`num_dual`) whose dual part
/// carries a derivative along (the FMUs' exact partial derivatives). For `f64` the generic
/// functions make the same operations in the same order as plain `f64` code.
pub trait Scalar: num_dual::DualNum<Primitive = f64> + Copy {}
impl<T: num_dual::DualNum<Primitive = f64> + Copy> Scalar for T {}
use std::fmt;

/// Standard gravity g, m/s² (used by every mechanism's weights).
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// Sign with `sgn(0) = 0`: the direction of Coulomb friction, which opposes a velocity and
/// vanishes at rest (no static friction is modelled).
#[inline]
pub fn sgn(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Viscous damping `c = 2·ζ·√(k·m)` of a spring `k` carrying a mass `m` at the damping ratio
/// `ζ` (`elastic.zeta`; `dynamics.md`: ζ = c / (2√(k·m)), 1 the critical damping).
#[inline]
pub fn viscous_damping(k: f64, m: f64, zeta: f64) -> f64 {
    2.0 * zeta * (k * m).sqrt()
}

/// A linear spring with viscous damping: the compliant element of a chain at the
/// elastodynamic level (`dynamics.md`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringDamper {
    /// Stiffness k, N/m.
    pub k: f64,
    /// Damping c, N·s/m.
    pub c: f64,
    /// Natural angular frequency √(k/m) with the mass m it carries, rad/s.
    pub omega: f64,
}

impl SpringDamper {
    /// Refuses a spring of the elastodynamic level that carries no mass (`m`, made of the
    /// variable `param` = `value` as `what` says, not > 0): the chain's acceleration F/m would
    /// be unbounded, and no step could be taken (nor its natural frequency √(k/m) be finite).
    pub fn check_mass(
        m: f64,
        param: &'static str,
        value: f64,
        what: &str,
    ) -> Result<(), ParamError> {
        if m > 0.0 && m.is_finite() {
            Ok(())
        } else {
            Err(ParamError {
                param,
                value,
                condition: format!(
                    "the elastodynamic level needs a mass on the chain's spring: {what} is {m} kg (raise {param})"
                ),
            })
        }
    }

    /// Stiffness `k` carrying the mass `m` at the damping ratio `zeta` ([`viscous_damping`]).
    pub fn with_ratio(k: f64, m: f64, zeta: f64) -> SpringDamper {
        SpringDamper {
            k,
            c: viscous_damping(k, m, zeta),
            omega: (k / m).sqrt(),
        }
    }

    /// Force `k·δ + c·δ̇` at the deflection `delta` and its rate (any [`Scalar`]).
    #[inline]
    pub fn force<T: Scalar>(&self, delta: T, rate: T) -> T {
        delta * self.k + rate * self.c
    }

    /// Energy `½·k·δ²` of the spring at the deflection `delta` (any [`Scalar`]).
    #[inline]
    pub fn energy<T: Scalar>(&self, delta: T) -> T {
        delta * (0.5 * self.k) * delta
    }
}

/// The dot product of two plane vectors.
#[inline]
pub fn dot<T: Scalar>(a: (T, T), b: (T, T)) -> T {
    a.0 * b.0 + a.1 * b.1
}

/// The cross product `a × b` of two plane vectors (the z component).
#[inline]
pub fn cross<T: Scalar>(a: (T, T), b: (T, T)) -> T {
    a.0 * b.1 - a.1 * b.0
}

/// The angle `phi` reduced to one turn, in `[0, 2π)`.
///
/// Uses `rem_euclid`, so negative angles wrap forwards; rounding can make `rem_euclid` return
/// exactly `2π` for a tiny negative input, which is mapped to 0. For `|phi|` up to 1e9 the result
/// carries the absolute rounding of `phi` itself (about `|phi|·1.1e-16`), nothing more.
/// A non-finite `phi` gives NaN.
#[inline]
pub fn wrap_angle(phi: f64) -> f64 {
    if (0.0..TAU).contains(&phi) {
        // already within the turn, where `rem_euclid` returns `phi` itself (and saves its
        // floating-point remainder, a software routine on most targets)
        return phi;
    }
    let psi = phi.rem_euclid(TAU);
    if psi >= TAU { 0.0 } else { psi }
}

/// [`wrap_angle`] for any [`Scalar`]: the reduced angle with the derivative of `phi` (the
/// whole turns taken out are constant). For `f64` exactly [`wrap_angle`].
#[inline]
pub fn wrap_angle_of<T: Scalar>(phi: T) -> T {
    let psi = wrap_angle(phi.re());
    if T::NDERIV == 0 {
        T::from(psi)
    } else {
        phi - phi.re() + psi
    }
}

/// `√(x² + y²)` for any [`Scalar`]: `f64::hypot` for `f64` (what the plain code computes), the
/// dual numbers' square root otherwise (the same function: its derivative is
/// `(x·dx + y·dy)/√(x² + y²)`).
#[inline]
pub fn hypot<T: Scalar>(x: T, y: T) -> T {
    if T::NDERIV == 0 {
        T::from(x.re().hypot(y.re()))
    } else {
        (x * x + y * y).sqrt()
    }
}

/// `f64::min(x, m)` for any [`Scalar`] (`m` where `x` is NaN, as `f64::min`).
#[inline]
pub fn min_of<T: Scalar>(x: T, m: f64) -> T {
    if x.re() <= m { x } else { T::from(m) }
}

/// `f64::max(x, m)` for any [`Scalar`] (`m` where `x` is NaN, as `f64::max`).
#[inline]
pub fn max_of<T: Scalar>(x: T, m: f64) -> T {
    if x.re() >= m { x } else { T::from(m) }
}

/// `f64::clamp(x, lo, hi)` for any [`Scalar`] (NaN stays NaN, as `f64::clamp`): the bound
/// where `x` lies beyond it, with the derivative 0 there.
#[inline]
pub fn clamp_of<T: Scalar>(x: T, lo: f64, hi: f64) -> T {
    debug_assert!(lo <= hi);
    if x.re() < lo {
        T::from(lo)
    } else if x.re() > hi {
        T::from(hi)
    } else {
        x
    }
}

/// A parameter set a mechanism cannot work with: which parameter, its value and the violated
/// condition (`interface.md`: refused at `fmi2ExitInitializationMode` with one log line).
///
/// Displayed as `"geneva.Z = 2: needs at least 3 slots"`.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError {
    /// The FMI variable name, e.g. `"geneva.Z"`.
    pub param: &'static str,
    /// Its value (integers as `f64`).
    pub value: f64,
    /// What is wrong, in words a user can act on.
    pub condition: String,
}

impl ParamError {
    /// Builds an error for `param = value` violating `condition`.
    pub fn new(param: &'static str, value: f64, condition: impl Into<String>) -> Self {
        Self {
            param,
            value,
            condition: condition.into(),
        }
    }
}

/// `require!(ok, "param", value, "condition {}", args..)`: returns the [`ParamError`] for
/// `param = value` violating the condition unless `ok` holds (the message is formatted only
/// then). Write `ok` so that a NaN fails it (`x > 0.0`, not `!(x <= 0.0)`).
#[macro_export]
macro_rules! require {
    ($ok:expr, $param:expr, $value:expr, $($condition:tt)+) => {
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` on purpose: NaN fails
        if !($ok) {
            return Err($crate::mechanics::ParamError::new($param, $value, format!($($condition)+)));
        }
    };
}

/// Refuses the first of `params` (name, value) that is not a finite value ≥ 0: masses, moments
/// of inertia, friction coefficients, forces.
pub fn check_non_negative(params: &[(&'static str, f64)]) -> Result<(), ParamError> {
    first_failing(
        params,
        |v| v >= 0.0 && v.is_finite(),
        "must be a finite value >= 0",
    )
}

/// Refuses the first of `params` (name, value) that is not finite: coordinates, offsets and
/// speeds of either sign.
pub fn check_finite(params: &[(&'static str, f64)]) -> Result<(), ParamError> {
    first_failing(params, f64::is_finite, "must be finite")
}

/// Refuses `param = value` with `condition` unless the value is finite and > 0: lengths, radii,
/// ratios, ratings.
pub fn check_positive(param: &'static str, value: f64, condition: &str) -> Result<(), ParamError> {
    first_failing(&[(param, value)], |v| v > 0.0 && v.is_finite(), condition)
}

/// Refuses the first of `params` that is not `ok`, with `condition`.
fn first_failing(
    params: &[(&'static str, f64)],
    ok: impl Fn(f64) -> bool,
    condition: &str,
) -> Result<(), ParamError> {
    match params.iter().find(|(_, v)| !ok(*v)) {
        Some(&(name, v)) => Err(ParamError::new(name, v, condition)),
        None => Ok(()),
    }
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}: {}", self.param, self.value, self.condition)
    }
}

impl std::error::Error for ParamError {}

/// Asserts that the first and second derivatives `f(x).1` and `f(x).2` match central
/// differences of `f(.).0` and `f(.).1` with the step `h`, within `eps1` and `eps2`: the check of
/// a closed form's derivatives (motion laws, slider-crank).
#[cfg(test)]
#[track_caller]
pub(crate) fn assert_derivatives_match_differences(
    f: impl Fn(f64) -> (f64, f64, f64),
    x: f64,
    h: f64,
    eps1: f64,
    eps2: f64,
) {
    let (_, d1, d2) = f(x);
    let (plus, minus) = (f(x + h), f(x - h));
    approx::assert_abs_diff_eq!(d1, (plus.0 - minus.0) / (2.0 * h), epsilon = eps1);
    approx::assert_abs_diff_eq!(d2, (plus.1 - minus.1) / (2.0 * h), epsilon = eps2);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_angle_stays_in_one_turn() {
        assert_eq!(wrap_angle(0.0), 0.0);
        assert_eq!(wrap_angle(TAU), 0.0);
        assert!((wrap_angle(-0.5) - (TAU - 0.5)).abs() < 1e-15);
        assert!((wrap_angle(3.0 * TAU + 1.0) - 1.0).abs() < 1e-14);
        // A tiny negative angle: rem_euclid rounds to exactly 2π, which must become 0.
        let w = wrap_angle(-1e-300);
        assert!((0.0..TAU).contains(&w));
        for phi in [1e9, -1e9, 123_456_789.123, -987_654_321.5] {
            let w = wrap_angle(phi);
            assert!((0.0..TAU).contains(&w), "{phi} -> {w}");
        }
        assert!(wrap_angle(f64::NAN).is_nan());
    }

    /// The shortcut inside the turn returns what `rem_euclid` would, bit for bit.
    #[test]
    fn wrap_angle_within_the_turn_is_rem_euclid() {
        let by_rem = |phi: f64| {
            let psi = phi.rem_euclid(TAU);
            if psi >= TAU { 0.0 } else { psi }
        };
        let below_tau = f64::from_bits(TAU.to_bits() - 1);
        let mut x = 0.37_f64;
        let mut phis = vec![
            0.0,
            -0.0,
            1e-300,
            f64::MIN_POSITIVE,
            below_tau,
            TAU,
            -1e-300,
        ];
        for _ in 0..1000 {
            x = (x * 997.0 + 0.123).fract();
            phis.extend([x * TAU, x * 20.0 - 10.0]);
        }
        for phi in phis {
            assert_eq!(wrap_angle(phi).to_bits(), by_rem(phi).to_bits(), "{phi:e}");
        }
    }

    #[test]
    fn param_error_display() {
        let e = ParamError::new("geneva.Z", 2.0, "needs at least 3 slots");
        assert_eq!(e.to_string(), "geneva.Z = 2: needs at least 3 slots");
        let e = ParamError::new("rod.l", 0.05, "must be longer than crank.r = 0.07");
        assert_eq!(
            e.to_string(),
            "rod.l = 0.05: must be longer than crank.r = 0.07"
        );
    }
}
