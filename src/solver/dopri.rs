//! Dormand–Prince 5(4) (Hairer, Nørsett, Wanner, *Solving ODEs I*, DOPRI5): the step, its
//! error estimate and stiffness test, the starting step size (HINIT).

use super::*;

// Dormand–Prince 5(4) coefficients.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// the continuous extension of order 4 (Hairer's DOPRI5, `D1`..`D7`)
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Dormand–Prince's continuous extension of order 4 at `θ ∈ [0, 1]` of a step, its stages in
/// `d5` (Hairer's `CONTD5`).
pub(super) fn dense(e: &Ends, d5: &[f64], theta: f64, out: &mut [f64]) {
    let Ends { y, f0, y1, f1, h } = *e;
    let theta1 = 1.0 - theta;
    for i in 0..y.len() {
        let ydiff = y1[i] - y[i];
        let bspl = h * f0[i] - ydiff;
        let r4 = ydiff - h * f1[i] - bspl;
        out[i] = y[i] + theta * (ydiff + theta1 * (bspl + theta * (r4 + theta1 * d5[i])));
    }
}

/// Cubic Hermite interpolation of the state at `t0 + s`, `s ∈ [0, h]`.
pub(super) fn hermite(e: &Ends, s: f64, out: &mut [f64]) {
    let Ends {
        y: y0,
        f0,
        y1,
        f1,
        h,
    } = *e;
    let th = s / h;
    let h00 = (1.0 + 2.0 * th) * (1.0 - th) * (1.0 - th);
    let h10 = th * (1.0 - th) * (1.0 - th);
    let h01 = th * th * (3.0 - 2.0 * th);
    let h11 = th * th * (th - 1.0);
    for i in 0..y0.len() {
        out[i] = h00 * y0[i] + h10 * h * f0[i] + h01 * y1[i] + h11 * h * f1[i];
    }
}

impl Integrator {
    pub(super) fn initial_step(
        &self,
        sys: &dyn OdeSystem,
        t: f64,
        y: &[f64],
        f0: &[f64],
        max_step: f64,
        st: &mut Stats,
    ) -> f64 {
        // Hairer's starting step: h = 0.01 * ||y|| / ||f||, refined by a second derivative.
        let n = y.len();
        let sc = |i: usize| sys.abs_tol(i, self.settings.atol, y) + self.settings.rtol * y[i].abs();
        let d0 = (0..n).map(|i| (y[i] / sc(i)).powi(2)).sum::<f64>().sqrt();
        let d1 = (0..n).map(|i| (f0[i] / sc(i)).powi(2)).sum::<f64>().sqrt();
        let h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        }
        .min(max_step);
        let mut y1 = vec![0.0; n];
        let mut f1 = vec![0.0; n];
        for i in 0..n {
            y1[i] = y[i] + h0 * f0[i];
        }
        sys.rhs(t + h0, &y1, &mut f1);
        st.rhs_evals += 1;
        let d2 = (0..n)
            .map(|i| ((f1[i] - f0[i]) / sc(i)).powi(2))
            .sum::<f64>()
            .sqrt()
            / h0;
        let h1 = if d1.max(d2) <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / d1.max(d2)).powf(0.2)
        };
        (100.0 * h0).min(h1).min(max_step).max(1e-12)
    }

    pub(super) fn dopri(
        &self,
        at: Start,
        h: f64,
        y1: &mut [f64],
        k7: &mut [f64],
        st: &mut Stats,
    ) -> Attempt {
        let Start {
            sys, t, y, f0: k1, ..
        } = at;
        let n = y.len();
        let [mut k2, mut k3, mut k4, mut k5, mut k6, mut ys] = [[0.0; MAX_DIM]; 6];
        let (k2, k3, k4, k5, k6, ys) = (
            &mut k2[..n],
            &mut k3[..n],
            &mut k4[..n],
            &mut k5[..n],
            &mut k6[..n],
            &mut ys[..n],
        );
        for i in 0..n {
            ys[i] = y[i] + h * A21 * k1[i];
        }
        sys.rhs(t + C2 * h, ys, k2);
        for i in 0..n {
            ys[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i]);
        }
        sys.rhs(t + C3 * h, ys, k3);
        for i in 0..n {
            ys[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
        }
        sys.rhs(t + C4 * h, ys, k4);
        for i in 0..n {
            ys[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
        }
        sys.rhs(t + C5 * h, ys, k5);
        for i in 0..n {
            ys[i] =
                y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]);
        }
        sys.rhs(t + h, ys, k6);
        for i in 0..n {
            y1[i] =
                y[i] + h * (A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i]);
        }
        sys.rhs(t + h, y1, k7);
        st.rhs_evals += 6;
        let mut d5 = [0.0; MAX_DIM];
        for i in 0..n {
            d5[i] =
                h * (D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] + D6 * k6[i] + D7 * k7[i]);
        }
        let mut e = [0.0; MAX_DIM];
        for i in 0..n {
            e[i] =
                h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
        }
        let err = self.norm(&e[..n], y, y1);
        // Hairer's stiffness estimate: h*|k7 - k6| / |y1 - ys|
        let mut num = 0.0;
        let mut den = 0.0;
        for i in 0..n {
            num += (k7[i] - k6[i]).powi(2);
            den += (y1[i] - ys[i]).powi(2);
        }
        let hlamb = if den > 0.0 {
            h * (num / den).sqrt()
        } else {
            0.0
        };
        Attempt {
            err: if err.is_finite() { err } else { f64::INFINITY },
            hlamb,
            radau: None,
            dopri_d5: Some(d5),
        }
    }
}
