//! The module docs' 7×7 system with Coulomb friction in both guides, shared by the kinetostatic
//! level ([`super::physics::Params::kinetostatics_with_load`]) and the elastodynamic one
//! ([`super::elastic::RodOde::eval`]): the friction factors change the frictionless matrix A0 by
//! two rank-one terms ([`friction_columns`]), so one solve with A0
//! ([`super::physics::Params::solve_system`]) gives the solution for every
//! sign combination ([`with_friction`]) and every determinant ratio `det A / det A0`
//! ([`friction_det`], the self-locking test); the sign search picks the combination whose normal
//! forces agree with the signs it assumed ([`friction_sign_search`]).

use crate::mechanics::Scalar;
use nalgebra::Vector2;
use num_dual::DualNum;
use std::ops::{Index, Mul};

/// The four combinations of the signs σ5, σ7 starting with `(g5, g7)`: `(g5, g7)`, `(−g5, g7)`,
/// `(g5, −g7)`, `(−g5, −g7)` (module docs, kinetostatics).
#[inline]
pub fn sign_combinations(g5: f64, g7: f64) -> [(f64, f64); 4] {
    [(g5, g7), (-g5, g7), (g5, -g7), (-g5, -g7)]
}

/// The sign search of the module docs' system with Coulomb friction: `solve(k5, k7)` solves it
/// for `z = [P or ẍ, C_x, C_y, D_x, D_y, N5, N7]` with the friction factors `k5`, `k7` (`f5`,
/// `f7` times the signs σ5, σ7). The signs of the frictionless solution `z0`'s N5, N7 first, then
/// the other combinations ([`sign_combinations`]); the one solution that agrees with its assumed
/// signs is returned with its `k5`, `k7`. Should none agree to rounding (|N| ≈ 0), the least
/// disagreeing one. The kinetostatic level ([`super::physics::Params::kinetostatics_with_load`]) and the
/// elastodynamic one ([`super::elastic::RodOde::eval`]) search so; `z` any [`Scalar`] vector,
/// `f5`, `f7` of `f64` or of `z`'s numbers.
pub fn friction_sign_search<T, Z, F>(z0: Z, f5: F, f7: F, solve: impl Fn(F, F) -> Z) -> (Z, F, F)
where
    T: Scalar,
    Z: Index<usize, Output = T>,
    F: Copy + From<f64> + Mul<f64, Output = F>,
{
    let sig = |x: T| if x.re() < 0.0 { -1.0 } else { 1.0 };
    let (g5, g7) = (sig(z0[5]), sig(z0[6]));
    let mut best = (f64::INFINITY, z0, F::from(0.0), F::from(0.0));
    for (a5, a7) in sign_combinations(g5, g7) {
        let z = solve(f5 * a5, f7 * a7);
        let miss = (-a5 * z[5].re()).max(0.0) + (-a7 * z[6].re()).max(0.0);
        if miss < best.0 {
            best = (miss, z, f5 * a5, f7 * a7);
        }
        if miss == 0.0 {
            break;
        }
    }
    (best.1, best.2, best.3)
}

/// The two columns friction adds to the module docs' system
/// ([`super::physics::Params::system_matrix`]): with the friction factors `k5`, `k7` the matrix
/// is `A0 − k5·e0·e5ᵀ − k7·w·e6ᵀ`, A0 the frictionless one, `e0` the unit vector of row 0 (slider
/// 5's balance along its guide) and `w = u_x·e2 + u_y·e3` (slider 7's, along EQ, `u` its
/// direction `support_dir`); `e5`, `e6` pick the unknowns N5, N7.
pub fn friction_columns<T: DualNum<Primitive = f64> + Copy>(u: Vector2<f64>) -> [[T; 7]; 2] {
    let mut e0 = [T::zero(); 7];
    e0[0] = T::one();
    let mut w = [T::zero(); 7];
    (w[2], w[3]) = (T::from(u.x), T::from(u.y));
    [e0, w]
}

/// `det A / det A0` for the friction factors `k5`, `k7` ([`friction_columns`]), by the matrix
/// determinant lemma, from `pv = A0⁻¹·e0` and `qv = A0⁻¹·w`.
pub fn friction_det<T: DualNum<Primitive = f64> + Copy>(
    pv: &[T; 7],
    qv: &[T; 7],
    k5: T,
    k7: T,
) -> T {
    (-pv[5] * k5 + 1.0) * (-qv[6] * k7 + 1.0) - qv[5] * pv[6] * (k5 * k7)
}

/// The solution of the system with friction, `A·z = b` ([`friction_columns`]), from the
/// frictionless one `z0 = A0⁻¹·b` and `pv`, `qv` ([`friction_det`]) by the Sherman–Morrison–
/// Woodbury formula: `z = z0 + k5·z5·pv + k7·z6·qv`, with N5 = z5 and N7 = z6 from the 2×2 system
/// those two components make. No elimination per sign combination; NaN where `det A = 0`.
pub fn with_friction<T: DualNum<Primitive = f64> + Copy>(
    [z0, pv, qv]: &[[T; 7]; 3],
    k5: T,
    k7: T,
) -> [T; 7] {
    let det = friction_det(pv, qv, k5, k7);
    if det.re() == 0.0 {
        return [T::from(f64::NAN); 7];
    }
    let z5 = ((-qv[6] * k7 + 1.0) * z0[5] + qv[5] * k7 * z0[6]) / det;
    let z6 = ((-pv[5] * k5 + 1.0) * z0[6] + pv[6] * k5 * z0[5]) / det;
    let (a, b) = (k5 * z5, k7 * z6);
    std::array::from_fn(|i| z0[i] + a * pv[i] + b * qv[i])
}

/// Solves a 7×7 system for several right-hand sides `bs` at once, by Gaussian elimination with
/// partial pivoting on the real parts (generic: on dual numbers it carries the exact derivative
/// of the solution). `None` if singular. The tests' reference for the structured solve
/// ([`super::physics::Params::solve_system`]) and the rank-two update ([`with_friction`]).
#[cfg(test)]
pub fn solve7_for<T: DualNum<Primitive = f64> + Copy, const M: usize>(
    mut a: [[T; 7]; 7],
    mut bs: [[T; 7]; M],
) -> Option<[[T; 7]; M]> {
    for col in 0..7 {
        let piv =
            (col..7).max_by(|&i, &j| a[i][col].re().abs().total_cmp(&a[j][col].re().abs()))?;
        if a[piv][col].re() == 0.0 || !a[piv][col].re().is_finite() {
            return None;
        }
        a.swap(col, piv);
        for b in &mut bs {
            b.swap(col, piv);
        }
        let pivot = a[col];
        for r in col + 1..7 {
            let f = a[r][col] / pivot[col];
            for (x, &t) in a[r].iter_mut().zip(pivot.iter()).skip(col) {
                *x -= f * t;
            }
            for b in &mut bs {
                let bp = b[col];
                b[r] -= f * bp;
            }
        }
    }
    Some(bs.map(|b| {
        let mut z = [T::zero(); 7];
        for r in (0..7).rev() {
            let mut acc = b[r];
            for c in r + 1..7 {
                acc -= a[r][c] * z[c];
            }
            z[r] = acc / a[r][r];
        }
        z
    }))
}
