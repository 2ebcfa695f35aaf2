//! The report's anchors: each case's chain ODE as the model builds it at the case's parameters
//! (`ChainAccess`), integrated in this process by our methods (in calls of 1 ms, as inside
//! `fmi2DoStep`) and by a kept library, `differential-equations` (its Radau5 and DOPRI5, in the
//! same calls of 1 ms, the same right-hand side and Jacobian): the largest error of the first state on that grid against a reference (our
//! dopri5 at rtol 1e-11, else radau5), the time (median of 3 runs) and the counts, which do not
//! depend on the machine's load.

use crate::report::{Case, case_values};
use bindery_fmu::mechanisms::disc_knife_drive::DiscKnifeDrive;
use bindery_fmu::mechanisms::geneva_knife_drive::GenevaKnifeDrive;
use bindery_fmu::mechanisms::perforators::Perforators;
use bindery_fmu::mechanisms::sewing_table::SewingTable;
use bindery_fmu::model::Model;
use bindery_fmu::solver::chain::ChainAccess;
use bindery_fmu::solver::library::Library;
use bindery_fmu::solver::{Integrator, Method, OdeSystem, Settings, Stats};
use differential_equations::prelude::*;
use std::time::Instant;

/// Work of one run.
#[derive(Clone, Copy, Debug, Default)]
pub struct Counts {
    pub steps: usize,
    pub rejected: usize,
    pub rhs: usize,
    pub jac: usize,
    pub lu: usize,
}

/// One run of one method at one tolerance.
pub struct Anchor {
    /// `auto`, `dopri5`, `radau5` (ours) or `library radau5`, `library dopri5`.
    pub method: &'static str,
    pub rtol: f64,
    /// Largest error of the first state on the 1 ms grid; `None`: the run failed (`note`).
    pub err: Option<f64>,
    pub secs: f64,
    pub counts: Counts,
    pub note: String,
}

/// The methods of the anchors, ours first.
pub const METHODS: [&str; 5] = [
    "auto",
    "dopri5",
    "radau5",
    "library radau5",
    "library dopri5",
];

/// The absolute tolerance of a case at `rtol`, as the report's runs set it.
fn atol(c: &Case, rtol: f64) -> f64 {
    (rtol * 1e-3).min(3.0 / c.k)
}

/// Our method over `n` calls of 1 ms from `y0`: the first state on the grid and the counts.
fn ours(
    o: &dyn OdeSystem,
    y0: [f64; 3],
    n: usize,
    method: Method,
    rtol: f64,
    atol: f64,
) -> Result<(Vec<f64>, Counts), String> {
    let mut it = Integrator::new(Settings {
        method,
        rtol,
        atol,
        max_step: 1e-3,
        max_steps: 5_000_000,
    });
    let mut y = y0;
    let mut xs = vec![y[0]];
    for i in 0..n {
        it.integrate(o, i as f64 * 1e-3, (i + 1) as f64 * 1e-3, &mut y)?;
        xs.push(y[0]);
    }
    let s: Stats = it.mem.stats;
    Ok((
        xs,
        Counts {
            steps: s.steps,
            rejected: s.rejected,
            rhs: s.rhs_evals,
            jac: s.jac_evals,
            lu: s.decomps,
        },
    ))
}

/// The library's method from `y0` in calls of 1 ms, as it would run inside `fmi2DoStep` (a new
/// problem each call, started where the last ended): the first state on the grid, the counts.
fn library(
    o: &dyn OdeSystem,
    y0: [f64; 3],
    n: usize,
    radau: bool,
    rtol: f64,
    atol: f64,
) -> Result<(Vec<f64>, Counts), String> {
    let lib = Library(o);
    let mut y = y0;
    let mut xs = vec![y[0]];
    let mut counts = Counts::default();
    for i in 0..n {
        let (a, b) = (i as f64 * 1e-3, (i + 1) as f64 * 1e-3);
        let ivp = IVP::ode(&lib, a, b, y);
        let sol = if radau {
            ivp.method(
                ImplicitRungeKutta::radau5()
                    .rtol(rtol)
                    .atol(atol)
                    .max_steps(5_000_000),
            )
            .solve()
        } else {
            ivp.method(
                ExplicitRungeKutta::dopri5()
                    .rtol(rtol)
                    .atol(atol)
                    .max_steps(5_000_000),
            )
            .solve()
        }
        .map_err(|e| {
            format!("at t = {a}: {e:?}")
                .chars()
                .take(90)
                .collect::<String>()
        })?;
        y = *sol.y.last().ok_or("no solution")?;
        xs.push(y[0]);
        counts.steps += sol.steps.accepted;
        counts.rejected += sol.steps.rejected;
        counts.rhs += sol.evals.function;
        counts.jac += sol.evals.jacobian;
        counts.lu += sol.evals.decompositions;
    }
    Ok((xs, counts))
}

/// The anchors of case `c` over the tolerances `tols`; `each` is told of every finished run.
pub fn anchors(
    c: &Case,
    tols: &[f64],
    each: &mut dyn FnMut(&Anchor),
) -> Result<Vec<Anchor>, String> {
    match c.mech {
        "GenevaKnifeDrive" => anchors_of::<GenevaKnifeDrive>(c, tols, each),
        "SewingTable" => anchors_of::<SewingTable>(c, tols, each),
        "Perforators" => anchors_of::<Perforators>(c, tols, each),
        "DiscKnifeDrive" => anchors_of::<DiscKnifeDrive>(c, tols, each),
        m => Err(format!("no anchors for {m}")),
    }
}

fn anchors_of<M: Model + ChainAccess<Var = <M as Model>::Var>>(
    c: &Case,
    tols: &[f64],
    each: &mut dyn FnMut(&Anchor),
) -> Result<Vec<Anchor>, String> {
    let v = case_values::<M>(c, 1, 1e-6)?;
    let mut m = M::prepare(&v).map_err(|e| e.to_string())?;
    let n = (c.stop / 1e-3).round() as usize;
    let mut out = Err(format!(
        "{} has no chain at the elastodynamic level",
        c.mech
    ));
    m.with_chain_ode(&v, 0.0, &mut |o, y0| {
        out = on_ode(c, o, y0, n, tols, each);
    });
    out
}

fn on_ode(
    c: &Case,
    o: &dyn OdeSystem,
    y0: [f64; 3],
    n: usize,
    tols: &[f64],
    each: &mut dyn FnMut(&Anchor),
) -> Result<Vec<Anchor>, String> {
    let reference = ours(o, y0, n, Method::Dopri5, 1e-11, atol(c, 1e-11))
        .or_else(|_| ours(o, y0, n, Method::Radau5, 1e-11, atol(c, 1e-11)))?
        .0;
    let mut all = vec![];
    for &rtol in tols {
        for method in METHODS {
            let run = || match method {
                "auto" => ours(o, y0, n, Method::Auto, rtol, atol(c, rtol)),
                "dopri5" => ours(o, y0, n, Method::Dopri5, rtol, atol(c, rtol)),
                "radau5" => ours(o, y0, n, Method::Radau5, rtol, atol(c, rtol)),
                "library radau5" => library(o, y0, n, true, rtol, atol(c, rtol)),
                _ => library(o, y0, n, false, rtol, atol(c, rtol)),
            };
            let mut times = vec![];
            let mut last = Err(String::new());
            for _ in 0..3 {
                let t0 = Instant::now();
                last = run();
                times.push(t0.elapsed().as_secs_f64());
                if last.is_err() {
                    break;
                }
            }
            times.sort_by(f64::total_cmp);
            let a = match last {
                Ok((xs, counts)) => Anchor {
                    method,
                    rtol,
                    err: Some(
                        xs.iter()
                            .zip(&reference)
                            .map(|(a, b)| (a - b).abs())
                            .fold(0.0, f64::max),
                    ),
                    secs: times[times.len() / 2],
                    counts,
                    note: String::new(),
                },
                Err(e) => Anchor {
                    method,
                    rtol,
                    err: None,
                    secs: times[0],
                    counts: Counts::default(),
                    note: e.chars().take(90).collect(),
                },
            };
            each(&a);
            all.push(a);
        }
    }
    Ok(all)
}

/// The counts of the anchors as a Markdown table (machine-independent: compare them across runs).
pub fn counts_table(anchors: &[Anchor]) -> String {
    let mut md = String::from(
        "\nThe same chain ODE in this process, ours and `differential-equations`, both in calls of 1 ms as inside fmi2DoStep: error of the first state against our dopri5 at rtol 1e-11, and the work.\n\n| method | rtol | error | time (s) | steps | rejected | right-hand sides | Jacobians | LU | LU per step |\n| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for a in anchors {
        let c = a.counts;
        let per_step = if c.steps > 0 {
            format!("{:.2}", c.lu as f64 / c.steps as f64)
        } else {
            "–".into()
        };
        md.push_str(&format!(
            "| {} | {:e} | {} | {:.4} | {} | {} | {} | {} | {} | {} |\n",
            a.method,
            a.rtol,
            a.err
                .map_or(format!("failed: {}", a.note), |e| format!("{e:.2e}")),
            a.secs,
            c.steps,
            c.rejected,
            c.rhs,
            c.jac,
            c.lu,
            per_step
        ));
    }
    md
}
