//! Radau IIA of order 5 (Hairer, Wanner, *Solving ODEs II*, RADAU5): the tableau, the step with
//! its simplified Newton iteration and error estimate (ESTRAD), the spectral radius `auto`
//! compares with the explicit stability limit.

use super::*;

/// Radau IIA (order 5) tableau.
struct RadauTab {
    c: [f64; 3],
    a: [[f64; 3]; 3],
    dd: [f64; 3],
    u1: f64,
}

fn radau_tab() -> RadauTab {
    let s6 = 6f64.sqrt();
    RadauTab {
        c: [(4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0],
        a: [
            [
                (88.0 - 7.0 * s6) / 360.0,
                (296.0 - 169.0 * s6) / 1800.0,
                (-2.0 + 3.0 * s6) / 225.0,
            ],
            [
                (296.0 + 169.0 * s6) / 1800.0,
                (88.0 + 7.0 * s6) / 360.0,
                (-2.0 - 3.0 * s6) / 225.0,
            ],
            [(16.0 - s6) / 36.0, (16.0 + s6) / 36.0, 1.0 / 9.0],
        ],
        dd: [
            -(13.0 + 7.0 * s6) / 3.0,
            (-13.0 + 7.0 * s6) / 3.0,
            -1.0 / 3.0,
        ],
        u1: 1.0 / ((6.0 + 81f64.powf(1.0 / 3.0) - 9f64.powf(1.0 / 3.0)) / 30.0),
    }
}

/// Largest modulus of the eigenvalues of an n×n row-major matrix.
pub fn spectral_radius(n: usize, jac: &[f64]) -> f64 {
    let m = DMatrix::from_row_slice(n, n, &jac[..n * n]);
    if m.iter().any(|x| !x.is_finite()) {
        return f64::INFINITY;
    }
    m.complex_eigenvalues()
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max)
}

impl Integrator {
    pub(super) fn radau(
        &self,
        at: Start,
        h: f64,
        y1: &mut [f64],
        f1: &mut [f64],
        st: &mut Stats,
    ) -> Result<Attempt, String> {
        let Start { sys, t, y, f0, jac } = at;
        let n = y.len();
        let tab = radau_tab();
        let m = 3 * n;
        // Newton matrix I - h (A ⊗ J)
        let mut mat = DMatrix::<f64>::identity(m, m);
        for bi in 0..3 {
            for bj in 0..3 {
                let a = h * tab.a[bi][bj];
                for i in 0..n {
                    for j in 0..n {
                        mat[(bi * n + i, bj * n + j)] -= a * jac[i * n + j];
                    }
                }
            }
        }
        let lu = mat.lu();
        let rtol = self.settings.rtol;
        let fnewt = (10.0 * f64::EPSILON / rtol).max(0.03f64.min(rtol.sqrt()));
        let mut z = vec![0.0; m];
        let mut fz = vec![0.0; m];
        let mut yi = [0.0; MAX_DIM];
        let mut prev = f64::NAN;
        let mut converged = false;
        let zero = vec![0.0; n];
        for it in 0..10 {
            for s in 0..3 {
                for i in 0..n {
                    yi[i] = y[i] + z[s * n + i];
                }
                sys.rhs(t + tab.c[s] * h, &yi[..n], &mut fz[s * n..(s + 1) * n]);
            }
            st.rhs_evals += 3;
            let mut r = nalgebra::DVector::<f64>::zeros(m);
            for s in 0..3 {
                for i in 0..n {
                    let mut acc = 0.0;
                    for q in 0..3 {
                        acc += tab.a[s][q] * fz[q * n + i];
                    }
                    r[s * n + i] = -z[s * n + i] + h * acc;
                }
            }
            let Some(dz) = lu.solve(&r) else {
                return Err("singular Newton matrix in radau5".into());
            };
            let mut nrm = 0.0;
            for s in 0..3 {
                nrm += self
                    .norm(sys, &dz.as_slice()[s * n..(s + 1) * n], y, &zero)
                    .powi(2);
            }
            let nrm = (nrm / 3.0).sqrt();
            for k in 0..m {
                z[k] += dz[k];
            }
            if !nrm.is_finite() {
                return Err("non-finite Newton iterate in radau5".into());
            }

            if nrm <= 1e-3 * fnewt {
                converged = true;
                break;
            }
            if it > 0 {
                let theta = nrm / prev;
                if theta >= 0.99 {
                    return Err(format!(
                        "Newton iteration of radau5 diverges (contraction {theta:.2})"
                    ));
                }
                let eta = theta / (1.0 - theta);
                if eta * nrm <= fnewt {
                    converged = true;
                    break;
                }
            } else if nrm <= 1e-2 * fnewt {
                converged = true;
                break;
            }
            prev = nrm;
        }
        if !converged {
            return Err("Newton iteration of radau5 did not converge in 10 iterations".into());
        }
        // Components left out of the norms (work integrals): their stage values are fixed
        // point updates one iteration behind; settle them on the converged stages.
        if (0..n).any(|i| sys.error_weight(i) == 0.0) {
            for s in 0..3 {
                for i in 0..n {
                    yi[i] = y[i] + z[s * n + i];
                }
                sys.rhs(t + tab.c[s] * h, &yi[..n], &mut fz[s * n..(s + 1) * n]);
            }
            st.rhs_evals += 3;
            for s in 0..3 {
                for i in (0..n).filter(|&i| sys.error_weight(i) == 0.0) {
                    z[s * n + i] = h * (0..3).map(|q| tab.a[s][q] * fz[q * n + i]).sum::<f64>();
                }
            }
        }
        for i in 0..n {
            y1[i] = y[i] + z[2 * n + i];
        }
        // error estimate (Hairer, radau5.f ESTRAD)
        let fac1 = tab.u1 / h;
        let mut e1 = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for j in 0..n {
                e1[(i, j)] = -jac[i * n + j];
            }
            e1[(i, i)] += fac1;
        }
        let lu1 = e1.lu();
        let mut f2 = vec![0.0; n];
        let mut cont = nalgebra::DVector::<f64>::zeros(n);
        for i in 0..n {
            f2[i] = (tab.dd[0] * z[i] + tab.dd[1] * z[n + i] + tab.dd[2] * z[2 * n + i]) / h;
            cont[i] = f2[i] + f0[i];
        }
        let mut errv = lu1.solve(&cont).ok_or("singular error matrix in radau5")?;
        let mut err = self.norm(sys, errv.as_slice(), y, y1);
        if err >= 1.0 {
            // Hairer's refinement for stiff components
            let mut yp = [0.0; MAX_DIM];
            for i in 0..n {
                yp[i] = y[i] + errv[i];
            }
            let mut fp = [0.0; MAX_DIM];
            sys.rhs(t, &yp[..n], &mut fp[..n]);
            st.rhs_evals += 1;
            for i in 0..n {
                cont[i] = fp[i] + f2[i];
            }
            errv = lu1.solve(&cont).ok_or("singular error matrix in radau5")?;
            err = self.norm(sys, errv.as_slice(), y, y1);
        }
        sys.rhs(t + h, y1, f1);
        st.rhs_evals += 1;
        Ok(Attempt {
            err: if err.is_finite() { err } else { f64::INFINITY },
            hlamb: 0.0,
        })
    }
}
