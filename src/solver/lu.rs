//! Dense LU factorization with partial pivoting of the small systems the integrators solve
//! (`n ≤` [`MAX_DIM`]), real and complex, on the stack: no allocation on a step (Hairer's
//! `DEC`/`SOL` and `DECC`/`SOLC` of `decsol.f`).

use super::MAX_DIM;
use nalgebra::Complex;
use std::ops::{Add, Div, Mul, Sub};

/// The numbers an [`Lu`] works on: `f64` and `Complex<f64>`.
pub trait Scalar:
    Copy + Default + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// The size that decides the pivot (`|re| + |im|` for a complex number, as `DECC`).
    fn size(self) -> f64;
}

impl Scalar for f64 {
    fn size(self) -> f64 {
        self.abs()
    }
}

impl Scalar for Complex<f64> {
    fn size(self) -> f64 {
        self.re.abs() + self.im.abs()
    }
}

/// The factors `P·A = L·U` of an `n×n` matrix (row-major, `L` unit lower below the diagonal).
#[derive(Clone, Copy, Debug)]
pub struct Lu<T> {
    n: usize,
    a: [T; MAX_DIM * MAX_DIM],
    /// Row `k` was swapped with row `piv[k]` at elimination step `k`.
    piv: [usize; MAX_DIM],
}

impl<T: Scalar> Lu<T> {
    /// Factorizes the `n×n` row-major matrix `a` (its first `n·n` entries); `None` if it is
    /// singular (a zero pivot) or not finite.
    pub fn new(n: usize, mut a: [T; MAX_DIM * MAX_DIM]) -> Option<Lu<T>> {
        assert!(n <= MAX_DIM, "system dimension");
        let mut piv = [0; MAX_DIM];
        for k in 0..n {
            let mut p = k;
            for i in k + 1..n {
                if a[i * n + k].size() > a[p * n + k].size() {
                    p = i;
                }
            }
            let pivot = a[p * n + k].size();
            if !(pivot > 0.0 && pivot.is_finite()) {
                return None;
            }
            piv[k] = p;
            if p != k {
                for j in 0..n {
                    a.swap(k * n + j, p * n + j);
                }
            }
            for i in k + 1..n {
                let l = a[i * n + k] / a[k * n + k];
                a[i * n + k] = l;
                for j in k + 1..n {
                    a[i * n + j] = a[i * n + j] - l * a[k * n + j];
                }
            }
        }
        Some(Lu { n, a, piv })
    }

    /// Solves `A·x = b` in place (`b` holds at least `n` entries; the first `n` are used).
    pub fn solve(&self, b: &mut [T]) {
        let (n, a) = (self.n, &self.a);
        for k in 0..n {
            b.swap(k, self.piv[k]);
        }
        for i in 1..n {
            let mut s = b[i];
            for j in 0..i {
                s = s - a[i * n + j] * b[j];
            }
            b[i] = s;
        }
        for i in (0..n).rev() {
            let mut s = b[i];
            for j in i + 1..n {
                s = s - a[i * n + j] * b[j];
            }
            b[i] = s / a[i * n + i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `A·x` for the row-major `n×n` matrix `a`.
    fn times<T: Scalar>(n: usize, a: &[T], x: &[T]) -> Vec<T> {
        (0..n)
            .map(|i| (0..n).fold(T::default(), |s, j| s + a[i * n + j] * x[j]))
            .collect()
    }

    #[test]
    fn solves_a_real_system_that_needs_pivoting() {
        let n = 3;
        let mut a = [0.0; MAX_DIM * MAX_DIM];
        // a zero in the first pivot position: without row exchange this fails
        a[..9].copy_from_slice(&[0.0, 2.0, 1.0, 1.0, -1.0, 3.0, 4.0, 0.5, -2.0]);
        let x = [1.0, -2.0, 0.5];
        let mut b = times(n, &a[..9], &x);
        Lu::new(n, a).expect("regular").solve(&mut b);
        for i in 0..n {
            assert!((b[i] - x[i]).abs() < 1e-14, "{b:?}");
        }
    }

    #[test]
    fn solves_a_complex_system_and_refuses_a_singular_one() {
        let n = 2;
        let c = |re, im| Complex::new(re, im);
        let mut a = [Complex::default(); MAX_DIM * MAX_DIM];
        a[..4].copy_from_slice(&[c(1.0, 2.0), c(0.0, -1.0), c(3.0, 0.0), c(2.0, 1.0)]);
        let x = [c(0.5, -1.0), c(2.0, 0.25)];
        let mut b = times(n, &a[..4], &x);
        Lu::new(n, a).expect("regular").solve(&mut b);
        for i in 0..n {
            assert!((b[i] - x[i]).norm() < 1e-14, "{b:?}");
        }
        let mut s = [0.0; MAX_DIM * MAX_DIM];
        s[..4].copy_from_slice(&[1.0, 2.0, 2.0, 4.0]);
        assert!(Lu::new(2, s).is_none());
        s[0] = f64::NAN;
        assert!(Lu::new(2, s).is_none());
    }
}
