//! Radau IIA of order 5 as Hairer's RADAU5 takes it (Hairer, Wanner, *Solving ODEs II*, IV.8,
//! and `radau5.f`): the simplified Newton iteration on the transformed system (one real and one
//! complex `n×n` matrix), started from the last step's collocation polynomial, with the
//! convergence-rate prediction that stops a hopeless iteration early; the Jacobian and the
//! factorizations kept while the iteration converges fast; the embedded error estimate
//! (`ESTRAD`), the step controller with Gustafsson's prediction, and the tolerance
//! transformation. Also the spectral radius `auto` compares with the explicit stability limit.

use super::lu::Lu;
use super::*;
use nalgebra::Complex;

/// Newton iterations at most (Hairer's `NIT`).
const NIT: usize = 7;
/// A Newton contraction below this keeps the Jacobian for the next step (Hairer's `THET`; his
/// 0.001 for small systems re-evaluated it on 40 % of the steps of the stiff chains here, and
/// each new Jacobian costs a factorization; 0.1, his value for costly Jacobians, keeps it on
/// all but 1–20 % for at most 4 % more right-hand sides, as `bindery report` counts them).
const THET: f64 = 0.1;
/// Step controller: safety factor, and `h_new/h` within `[1/FACL, 1/FACR]`.
const SAFE: f64 = 0.9;
const FACL: f64 = 5.0;
const FACR: f64 = 0.125;
/// A new step size within `[QUOT1, QUOT2]·h` keeps `h` and the factorizations: Hairer's values
/// where a factorization is costly. His small-system 1.0 and 1.2 factorized on a quarter of the
/// accepted steps of the stiff Geneva and SewingTable chains, mostly while the steps grow after
/// an event; these on a sixth, for 5 % more right-hand sides (`bindery report`'s counts).
const QUOT1: f64 = 0.99;
const QUOT2: f64 = 2.0;
/// A step size this close (relative) to the factorized one keeps the factorization.
const LU_SLACK: f64 = 1e-3;
/// Largest stopping tolerance of the Newton iteration, as a fraction of the (transformed)
/// tolerance: Hairer's `FNEWT`, `min(0.03, rtol'^0.5)`, is 0.03 at rtol 1e-3 and above 0.01 for
/// rtol above 3.2e-5 (his "smaller values make the code slower, but safer"). There the iterate
/// left a stiff chain's coordinate off by up to 0.03 of the tolerance, kilonewtons of force at
/// 1e12 N/m, which near the disc knives' jamming window flipped the guides' friction and ended
/// in Newton failures and steps of microseconds; converged to 0.01, that chain's run at rtol 1e-3
/// takes a third of the right-hand sides and a quarter of the factorizations, and the other
/// chains' counts move by about 1 % (`bindery report`'s counts; BENCHMARKS.md). At rtol 3.2e-5
/// and below nothing changes.
const FNEWT_MAX: f64 = 0.01;

/// The method's constants (`radau5.f`): nodes, error-estimate weights, the eigenvalues of the
/// inverse of the coefficient matrix (`u1` real, `alph ± i·beta`) and the transformation `T`,
/// `T⁻¹` that decouples the stage system.
struct Tab {
    c1: f64,
    c2: f64,
    dd: [f64; 3],
    u1: f64,
    alph: f64,
    beta: f64,
    t: [[f64; 3]; 3],
    ti: [[f64; 3]; 3],
}

/// The method's constants, computed once per process ([`make_tab`]; made at each attempt, their
/// cube and square roots were 3 % of a stiff GenevaKnifeDrive run's instructions).
fn tab() -> &'static Tab {
    static TAB: std::sync::OnceLock<Tab> = std::sync::OnceLock::new();
    TAB.get_or_init(make_tab)
}

#[allow(clippy::excessive_precision)] // `radau5.f`'s digits, as printed there
fn make_tab() -> Tab {
    let sq6 = 6f64.sqrt();
    let (c81, c9) = (81f64.cbrt(), 9f64.cbrt());
    let u1 = (6.0 + c81 - c9) / 30.0;
    let alph = (12.0 - c81 + c9) / 60.0;
    let beta = (c81 + c9) * 3f64.sqrt() / 60.0;
    let cno = alph * alph + beta * beta;
    Tab {
        c1: (4.0 - sq6) / 10.0,
        c2: (4.0 + sq6) / 10.0,
        dd: [
            -(13.0 + 7.0 * sq6) / 3.0,
            (-13.0 + 7.0 * sq6) / 3.0,
            -1.0 / 3.0,
        ],
        u1: 1.0 / u1,
        alph: alph / cno,
        beta: beta / cno,
        t: [
            [
                9.1232394870892942792e-02,
                -0.14125529502095420843,
                -3.0029194105147424492e-02,
            ],
            [
                0.24171793270710701896,
                0.20412935229379993199,
                0.38294211275726193779,
            ],
            [0.96604818261509293619, 1.0, 0.0],
        ],
        ti: [
            [
                4.3255798900631553510,
                0.33919925181580986954,
                0.54177053993587487119,
            ],
            [
                -4.1787185915519047273,
                -0.32768282076106238708,
                0.47662355450055045196,
            ],
            [
                -0.50287263494578687595,
                2.5719269498556054292,
                -0.59603920482822492497,
            ],
        ],
    }
}

/// Largest modulus of the eigenvalues of an n×n row-major matrix.
///
/// A last column of zeros (a state that enters no derivative, as a chain's work `W`) makes the
/// matrix block lower triangular: its eigenvalues are the leading block's and 0, so that block
/// is taken instead. One or two rows are solved in closed form (the chain's `[x, ẋ]` block:
/// `λ = tr/2 ± √(tr²/4 − det)`), more by nalgebra's Schur decomposition.
pub fn spectral_radius(n: usize, jac: &[f64]) -> f64 {
    let jac = &jac[..n * n];
    if jac.iter().any(|x| !x.is_finite()) {
        return f64::INFINITY;
    }
    if n > 1 && (0..n).all(|i| jac[i * n + n - 1] == 0.0) {
        let m = n - 1;
        let mut lead = [0.0; MAX_DIM * MAX_DIM];
        for i in 0..m {
            lead[i * m..(i + 1) * m].copy_from_slice(&jac[i * n..i * n + m]);
        }
        return spectral_radius(m, &lead);
    }
    match n {
        0 => 0.0,
        1 => jac[0].abs(),
        2 => {
            let (half_tr, det) = (0.5 * (jac[0] + jac[3]), jac[0] * jac[3] - jac[1] * jac[2]);
            let disc = half_tr * half_tr - det;
            if disc >= 0.0 {
                // real: the larger modulus is |tr/2| + √disc
                half_tr.abs() + disc.sqrt()
            } else {
                // a complex pair: |λ|² = det
                det.sqrt()
            }
        }
        _ => DMatrix::from_row_slice(n, n, jac)
            .complex_eigenvalues()
            .iter()
            .map(|z| z.norm())
            .fold(0.0, f64::max),
    }
}

/// The factorized Newton matrices `u1/h·I − J` and `(alph + i·beta)/h·I − J` for one Jacobian
/// and step size: a function of [`RadauMemory::jac`] and [`RadauMemory::lu_h`], kept beside the
/// memory (not in it) and made again, bit for bit, when they do not match it.
#[derive(Clone, Debug, Default)]
pub(super) struct Factors(Option<Box<FactorsOf>>);

#[derive(Clone, Debug)]
pub(super) struct FactorsOf {
    jac: [f64; MAX_DIM * MAX_DIM],
    h: f64,
    e1: Lu<f64>,
    e2: Lu<Complex<f64>>,
}

/// Derived data: two integrators with equal memories are equal whatever they have at hand.
impl PartialEq for Factors {
    fn eq(&self, _: &Factors) -> bool {
        true
    }
}

impl Factors {
    /// The factors for `jac` and `h` (n×n), made if those at hand are for others; `None` if a
    /// matrix is singular.
    fn of(&mut self, n: usize, jac: &[f64; MAX_DIM * MAX_DIM], h: f64) -> Option<&FactorsOf> {
        let current = self
            .0
            .as_ref()
            .is_some_and(|f| f.h.to_bits() == h.to_bits() && f.jac[..n * n] == jac[..n * n]);
        if !current {
            let tb = tab();
            let (fac1, alphn, betan) = (tb.u1 / h, tb.alph / h, tb.beta / h);
            let mut e1 = [0.0; MAX_DIM * MAX_DIM];
            let mut e2 = [Complex::default(); MAX_DIM * MAX_DIM];
            for i in 0..n {
                for j in 0..n {
                    e1[i * n + j] = -jac[i * n + j];
                    e2[i * n + j] = Complex::new(-jac[i * n + j], 0.0);
                }
                e1[i * n + i] += fac1;
                e2[i * n + i] += Complex::new(alphn, betan);
            }
            self.0 = Some(Box::new(FactorsOf {
                jac: *jac,
                h,
                e1: Lu::new(n, e1)?,
                e2: Lu::new(n, e2)?,
            }));
        }
        self.0.as_deref()
    }
}

/// A Radau IIA attempt that converged: its error estimate and Newton iterations, and the stage
/// increments `Z` (3 × n) from which the collocation polynomial is made.
pub(super) struct RadauStep {
    pub err: f64,
    pub newt: usize,
    pub z: [f64; 3 * MAX_DIM],
}

/// Why a Radau IIA attempt did not converge, and by how much to shrink the step for the next
/// (Hairer's label 78: one half; or the convergence-rate prediction's factor).
#[derive(Debug)]
pub(super) struct NewtonFailure {
    pub factor: f64,
    pub reason: String,
}

impl NewtonFailure {
    fn halve(reason: impl Into<String>) -> NewtonFailure {
        NewtonFailure {
            factor: 0.5,
            reason: reason.into(),
        }
    }
}

impl Integrator {
    /// Before a Radau IIA attempt over `h` from `(t, y)`: a new Jacobian where the memory asks
    /// for one, and the factorization for `h` (counted where the method decides it; made at
    /// hand by [`Factors::of`]).
    pub(super) fn radau_prepare(
        &mut self,
        sys: &dyn OdeSystem,
        t: f64,
        y: &[f64],
        h: f64,
        st: &mut Stats,
    ) {
        let r = &mut self.mem.radau;
        if !r.has_jac || r.need_jac {
            sys.jacobian(t, y, &mut r.jac[..y.len() * y.len()]);
            st.jac_evals += 1;
            r.has_jac = true;
            r.jac_fresh = true;
            r.need_jac = false;
            r.lu_h = 0.0;
        }
        // a step within a thousandth of the factorized one (the last step of a communication
        // step, shortened to its end) iterates with the factors at hand: a simplified Newton
        // iteration with a matrix that close converges as fast
        if (h - r.lu_h).abs() > LU_SLACK * r.lu_h {
            r.lu_h = h;
            st.decomps += 1;
        }
    }

    /// One Radau IIA attempt from `at` over `h` ([`Integrator::radau_prepare`] first): the
    /// state `y1` and its derivative `f1`. `refine`: Hairer's second error estimate where the
    /// first fails (the first step, or after a rejection).
    pub(super) fn radau(
        &mut self,
        at: Start,
        h: f64,
        y1: &mut [f64],
        f1: &mut [f64],
        st: &mut Stats,
    ) -> Result<RadauStep, NewtonFailure> {
        let Start { sys, t, y, f0 } = at;
        let n = y.len();
        let tb = tab();
        let rtol = self.scale.rtol_radau;
        let fnewt = (10.0 * f64::EPSILON / rtol).max(0.03f64.min(rtol.sqrt()).min(FNEWT_MAX));
        let mut factors = std::mem::take(&mut self.factors);
        let Some(fa) = factors.of(n, &self.mem.radau.jac, self.mem.radau.lu_h) else {
            self.factors = factors;
            return Err(NewtonFailure::halve("singular Newton matrix in radau5"));
        };
        let (fac1, alphn, betan) = (tb.u1 / h, tb.alph / h, tb.beta / h);
        let r = self.mem.radau;
        // starting values: the last step's collocation polynomial, else zero
        let mut z = [0.0; 3 * MAX_DIM];
        let mut w = [0.0; 3 * MAX_DIM];
        if r.h_old > 0.0 {
            let c3q = h / r.h_old;
            let cq = [tb.c1 * c3q, tb.c2 * c3q, c3q];
            let (c1m1, c2m1) = (tb.c1 - 1.0, tb.c2 - 1.0);
            for i in 0..n {
                let (ak1, ak2, ak3) = (r.cont[i], r.cont[n + i], r.cont[2 * n + i]);
                for s in 0..3 {
                    z[s * n + i] = cq[s] * (ak1 + (cq[s] - c2m1) * (ak2 + (cq[s] - c1m1) * ak3));
                }
                for s in 0..3 {
                    w[s * n + i] = (0..3).map(|q| tb.ti[s][q] * z[q * n + i]).sum();
                }
            }
        }
        let mut faccon = r.faccon.max(f64::EPSILON).powf(0.8);
        let mut theta = THET;
        let (mut dyno_old, mut thq_old) = (0.0, 0.0);
        let mut fz = [0.0; 3 * MAX_DIM];
        let mut newt = 0;
        let outcome = loop {
            if newt >= NIT {
                break Err(NewtonFailure::halve(format!(
                    "Newton iteration of radau5 did not converge in {NIT} iterations"
                )));
            }
            stage_rhs(sys, t, h, [tb.c1, tb.c2, 1.0], y, &z, &mut fz);
            st.rhs_evals += 3;
            // the transformed right-hand sides, less the stages' own part (Hairer's SLVRAD)
            let mut d1 = [0.0; MAX_DIM];
            let mut d2 = [Complex::default(); MAX_DIM];
            for i in 0..n {
                let a: [f64; 3] = std::array::from_fn(|s| {
                    (0..3).map(|q| tb.ti[s][q] * fz[q * n + i]).sum::<f64>()
                });
                let (s2, s3) = (-w[n + i], -w[2 * n + i]);
                d1[i] = a[0] - w[i] * fac1;
                d2[i] = Complex::new(
                    a[1] + s2 * alphn - s3 * betan,
                    a[2] + s3 * alphn + s2 * betan,
                );
            }
            fa.e1.solve(&mut d1);
            fa.e2.solve(&mut d2);
            newt += 1;
            let mut dw = [0.0; 3 * MAX_DIM];
            for i in 0..n {
                dw[i] = d1[i];
                dw[n + i] = d2[i].re;
                dw[2 * n + i] = d2[i].im;
            }
            let mut sq = 0.0;
            for s in 0..3 {
                sq += self.radau_norm(&dw[s * n..(s + 1) * n], y).powi(2);
            }
            let dyno = (sq / 3.0).sqrt();
            if !dyno.is_finite() {
                break Err(NewtonFailure::halve("non-finite Newton iterate in radau5"));
            }
            if newt > 1 && newt < NIT {
                let thq = dyno / dyno_old;
                theta = if newt == 2 {
                    thq
                } else {
                    (thq * thq_old).sqrt()
                };
                thq_old = thq;
                if theta < 0.99 {
                    faccon = theta / (1.0 - theta);
                    let left = (NIT - 1 - newt) as i32;
                    let dyth = faccon * dyno * theta.powi(left) / fnewt;
                    if dyth >= 1.0 {
                        // it would not converge in the iterations left: a smaller step now
                        let qnewt = dyth.clamp(1e-4, 20.0);
                        break Err(NewtonFailure {
                            factor: 0.8 * qnewt.powf(-1.0 / (4.0 + f64::from(left))),
                            reason: format!(
                                "Newton iteration of radau5 too slow (contraction {theta:.2})"
                            ),
                        });
                    }
                } else {
                    break Err(NewtonFailure::halve(format!(
                        "Newton iteration of radau5 diverges (contraction {theta:.2})"
                    )));
                }
            }
            dyno_old = dyno.max(f64::EPSILON);
            for i in 0..n {
                let f: [f64; 3] = std::array::from_fn(|s| w[s * n + i] + dw[s * n + i]);
                for s in 0..3 {
                    w[s * n + i] = f[s];
                    z[s * n + i] = (0..3).map(|q| tb.t[s][q] * f[q]).sum();
                }
            }
            if faccon * dyno <= fnewt {
                break Ok(());
            }
        };
        self.mem.radau.theta = theta;
        self.mem.radau.faccon = faccon;
        if let Err(e) = outcome {
            self.factors = factors;
            return Err(e);
        }
        // Components left out of the norms (work integrals): their stage values are one
        // iteration behind; settle them on the converged stages.
        if (0..n).any(|i| sys.error_weight(i) == 0.0) {
            stage_rhs(sys, t, h, [tb.c1, tb.c2, 1.0], y, &z, &mut fz);
            st.rhs_evals += 3;
            let a = radau_a();
            for s in 0..3 {
                for i in (0..n).filter(|&i| sys.error_weight(i) == 0.0) {
                    z[s * n + i] = h * (0..3).map(|q| a[s][q] * fz[q * n + i]).sum::<f64>();
                }
            }
        }
        for i in 0..n {
            y1[i] = y[i] + z[2 * n + i];
        }
        // error estimate (ESTRAD)
        let mut f2 = [0.0; MAX_DIM];
        let mut e = [0.0; MAX_DIM];
        for i in 0..n {
            f2[i] = (tb.dd[0] * z[i] + tb.dd[1] * z[n + i] + tb.dd[2] * z[2 * n + i]) / h;
            e[i] = f2[i] + f0[i];
        }
        fa.e1.solve(&mut e);
        let mut err = self.radau_norm(&e[..n], y).max(1e-10);
        if err >= 1.0 && (self.mem.rejected || self.mem.stats.steps + st.steps == 0) {
            let mut yp = [0.0; MAX_DIM];
            for i in 0..n {
                yp[i] = y[i] + e[i];
            }
            let mut fp = [0.0; MAX_DIM];
            sys.rhs(t, &yp[..n], &mut fp[..n]);
            st.rhs_evals += 1;
            for i in 0..n {
                e[i] = fp[i] + f2[i];
            }
            fa.e1.solve(&mut e);
            err = self.radau_norm(&e[..n], y).max(1e-10);
        }
        self.factors = factors;
        sys.rhs(t + h, y1, f1);
        st.rhs_evals += 1;
        Ok(RadauStep {
            err: if err.is_finite() { err } else { f64::INFINITY },
            newt,
            z,
        })
    }

    /// After an accepted attempt of `h`: the collocation polynomial the next step starts its
    /// Newton iteration from, Gustafsson's predictive controller, and whether the next step keeps
    /// the Jacobian (the iteration converged fast) and `h` with its factorization (the new step
    /// would be between 0.99 and 2 times this one). The next step size.
    pub(super) fn radau_accepted(&mut self, n: usize, h: f64, step: &RadauStep) -> f64 {
        let tb = tab();
        let (mut h_new, mut quot) = Integrator::radau_h_new(h, step.err, step.newt);
        let r = &mut self.mem.radau;
        if r.h_acc > 0.0 {
            let facgus = (r.h_acc / h) * (step.err * step.err / r.err_acc).powf(0.25) / SAFE;
            quot = quot.max(facgus.clamp(FACR, FACL));
            h_new = h / quot;
        }
        r.h_acc = h;
        r.err_acc = step.err.max(1e-2);
        let (c1m1, c2m1, c1mc2) = (tb.c1 - 1.0, tb.c2 - 1.0, tb.c1 - tb.c2);
        let z = &step.z;
        for i in 0..n {
            let (z1, z2, z3) = (z[i], z[n + i], z[2 * n + i]);
            r.cont[i] = (z2 - z3) / c2m1;
            let ak = (z1 - z2) / c1mc2;
            let acont3 = (ak - z1 / tb.c1) / tb.c2;
            r.cont[n + i] = (ak - r.cont[i]) / c1m1;
            r.cont[2 * n + i] = r.cont[n + i] - acont3;
        }
        r.h_old = h;
        r.jac_fresh = false;
        if self.mem.rejected {
            h_new = h_new.min(h);
        }
        if r.theta <= THET {
            if (QUOT1..=QUOT2).contains(&(h_new / h)) {
                h_new = h;
            }
        } else {
            r.need_jac = true;
        }
        h_new
    }

    /// Hairer's new step size after a Radau IIA attempt of `h` with error `err` in `newt`
    /// iterations (not yet the predictive part).
    pub(super) fn radau_h_new(h: f64, err: f64, newt: usize) -> (f64, f64) {
        let cfac = SAFE * (1 + 2 * NIT) as f64;
        let fac = SAFE.min(cfac / (newt + 2 * NIT) as f64);
        let quot = FACR.max(FACL.min(err.powf(0.25) / fac));
        (h / quot, quot)
    }
}

/// Radau IIA's collocation polynomial at `θ ∈ [0, 1]` of a step to `y1`, its stages `z`
/// (relative to the step's start; Hairer's `CONTR5`, with `s = θ − 1`).
pub(super) fn dense(z: &[f64], y1: &[f64], theta: f64, out: &mut [f64]) {
    let tb = tab();
    let n = y1.len();
    let (c1m1, c2m1, c1mc2) = (tb.c1 - 1.0, tb.c2 - 1.0, tb.c1 - tb.c2);
    let s = theta - 1.0;
    for i in 0..n {
        let (z1, z2, z3) = (z[i], z[n + i], z[2 * n + i]);
        let c2 = (z2 - z3) / c2m1;
        let ak = (z1 - z2) / c1mc2;
        let acont3 = (ak - z1 / tb.c1) / tb.c2;
        let c3 = (ak - c2) / c1m1;
        let c4 = c3 - acont3;
        out[i] = y1[i] + s * (c2 + (s - c2m1) * (c3 + (s - c1m1) * c4));
    }
}

/// The right-hand side at the three collocation points `t + c_s*h`, states `y + z_s`, into
/// `fz` (stage after stage, `n` numbers each).
fn stage_rhs(
    sys: &dyn OdeSystem,
    t: f64,
    h: f64,
    c: [f64; 3],
    y: &[f64],
    z: &[f64],
    fz: &mut [f64],
) {
    let n = y.len();
    let mut yi = [0.0; MAX_DIM];
    for (s, c) in c.into_iter().enumerate() {
        for i in 0..n {
            yi[i] = y[i] + z[s * n + i];
        }
        sys.rhs(t + c * h, &yi[..n], &mut fz[s * n..(s + 1) * n]);
    }
}

/// The coefficient matrix of Radau IIA (order 5).
fn radau_a() -> [[f64; 3]; 3] {
    let s6 = 6f64.sqrt();
    [
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
    ]
}
