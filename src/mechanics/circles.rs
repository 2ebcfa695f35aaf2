//! Where two links meet: the intersection of the circle of radius `r1` about `P` with the circle
//! of radius `r2` about `Q`, the closure of a four-bar or a rocker-slider loop (paper 002,
//! Fig. 1; `legacy-needle-drive.md`, "Closure equations"). Generic over dual numbers, so one
//! body of code gives positions and their exact derivatives.

// `!(x >= 0.0)` is deliberate: a NaN fails the check too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use num_dual::DualNum;

/// The point `X` with `|X − P| = r1` and `|X − Q| = r2` on the side `sigma` of the line P→Q
/// (+1: left of P→Q, −1: right): with `d = |Q − P|`, `e = (Q − P)/d`, `e⊥ = (−e_y, e_x)`,
/// `a = (r1² − r2² + d²)/(2d)`, `h = √(r1² − a²)`, `X = P + a·e + σ·h·e⊥`.
///
/// `Err(h²)` when the circles do not meet (`h² < 0`: the loop does not assemble).
pub fn intersect<T: DualNum<Primitive = f64> + Copy>(
    p: [T; 2],
    q: [T; 2],
    r1: f64,
    r2: f64,
    sigma: f64,
) -> Result<[T; 2], f64> {
    let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
    let d2 = dx * dx + dy * dy;
    let d = d2.sqrt();
    let (ex, ey) = (dx / d, dy / d);
    let a = (d2 + r1 * r1 - r2 * r2) / (d * 2.0f64);
    let h2 = -(a * a) + r1 * r1;
    if !(h2.re() >= 0.0) {
        return Err(h2.re());
    }
    let h = h2.sqrt() * sigma;
    Ok([p[0] + ex * a - ey * h, p[1] + ey * a + ex * h])
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::Dual64;

    #[test]
    fn meets_both_circles_on_the_chosen_side() {
        let (p, q): ([f64; 2], [f64; 2]) = ([0.3, -0.2], [1.1, 0.5]);
        for sigma in [1.0, -1.0] {
            let x = intersect(p, q, 0.7, 0.6, sigma).unwrap();
            let r1 = ((x[0] - p[0]).powi(2) + (x[1] - p[1]).powi(2)).sqrt();
            let r2 = ((x[0] - q[0]).powi(2) + (x[1] - q[1]).powi(2)).sqrt();
            assert!((r1 - 0.7).abs() < 1e-14 && (r2 - 0.6).abs() < 1e-14);
            let side = (q[0] - p[0]) * (x[1] - p[1]) - (q[1] - p[1]) * (x[0] - p[0]);
            assert_eq!(side.signum(), sigma);
        }
        assert!(intersect(p, q, 0.1, 0.1, 1.0).is_err());
    }

    #[test]
    fn derivative_matches_differences() {
        // Q moves along x: dX/dq_x by dual numbers against central differences
        let at = |qx: f64| intersect::<f64>([0.0, 0.0], [qx, 0.4], 0.5, 0.45, 1.0).unwrap();
        let x = intersect(
            [Dual64::from(0.0), Dual64::from(0.0)],
            [Dual64::new(0.6, 1.0), Dual64::from(0.4)],
            0.5,
            0.45,
            1.0,
        )
        .unwrap();
        let h = 1e-6;
        let (a, b) = (at(0.6 + h), at(0.6 - h));
        for i in 0..2 {
            assert!((x[i].eps - (a[i] - b[i]) / (2.0 * h)).abs() < 1e-8);
        }
    }
}
