//! The report's anchors: each case's chain ODE as the model builds it at the case's parameters
//! (`ChainAccess`), integrated in this process by our methods (in calls of 1 ms, as inside
//! `fmi2DoStep`) and by a kept library, `differential-equations` (its Radau5 and DOPRI5, in the
//! same calls of 1 ms, the same right-hand side and Jacobian): the largest error of the first
//! state on that grid against a reference (our dopri5 at rtol 1e-11, else radau5), the time (the
//! median of repeated runs, all of a case's timed together in rounds,
//! [`crate::timing::timed_in_rounds`]) and the counts, which do not depend on the
//! machine's load.

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

/// A method of the anchors: ours, or the library's Radau5 (`radau`) or DOPRI5.
#[derive(Clone, Copy)]
enum Runner {
    Ours(Method),
    Library { radau: bool },
}

/// The methods of the anchors, ours first.
const RUNNERS: [(&str, Runner); 5] = [
    ("auto", Runner::Ours(Method::Auto)),
    ("dopri5", Runner::Ours(Method::Dopri5)),
    ("radau5", Runner::Ours(Method::Radau5)),
    ("library radau5", Runner::Library { radau: true }),
    ("library dopri5", Runner::Library { radau: false }),
];

/// The absolute tolerance of a case at `rtol`, as the report's runs set it.
fn atol(c: &Case, rtol: f64) -> f64 {
    (rtol * 1e-3).min(3.0 / c.k)
}

/// `runner` over `n` calls of 1 ms from `y0`: the first state on the grid and the counts. The
/// library runs as it would inside `fmi2DoStep`: a new problem each call, started where the
/// last ended.
fn run(
    o: &dyn OdeSystem,
    y0: [f64; 3],
    n: usize,
    runner: Runner,
    rtol: f64,
    atol: f64,
) -> Result<(Vec<f64>, Counts), String> {
    let method = match runner {
        Runner::Ours(m) => m,
        Runner::Library { .. } => Method::Dopri5,
    };
    let mut it = Integrator::new(Settings {
        method,
        rtol,
        atol,
        max_step: 1e-3,
        max_steps: 5_000_000,
    });
    let mut y = y0;
    let mut xs = vec![y[0]];
    let mut counts = Counts::default();
    for i in 0..n {
        let (a, b) = (i as f64 * 1e-3, (i + 1) as f64 * 1e-3);
        match runner {
            Runner::Ours(_) => {
                it.integrate(o, a, b, &mut y)?;
            }
            Runner::Library { radau } => {
                library_call(o, (a, b), &mut y, radau, (rtol, atol), &mut counts)?
            }
        }
        xs.push(y[0]);
    }
    if let Runner::Ours(_) = runner {
        let s: Stats = it.mem.stats;
        counts = Counts {
            steps: s.steps,
            rejected: s.rejected,
            rhs: s.rhs_evals,
            jac: s.jac_evals,
            lu: s.decomps,
        };
    }
    Ok((xs, counts))
}

/// One call of the library's method over `span`, its work added to `counts`.
fn library_call(
    o: &dyn OdeSystem,
    (a, b): (f64, f64),
    y: &mut [f64; 3],
    radau: bool,
    (rtol, atol): (f64, f64),
    counts: &mut Counts,
) -> Result<(), String> {
    let lib = Library(o);
    let ivp = IVP::ode(&lib, a, b, *y);
    // the absolute tolerance per state as ours at the call's start ([`OdeSystem::abs_tol`])
    let atol: [f64; 3] = std::array::from_fn(|i| o.abs_tol(i, atol, &y[..]));
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
    *y = *sol.y.last().ok_or("no solution")?;
    counts.steps += sol.steps.accepted;
    counts.rejected += sol.steps.rejected;
    counts.rhs += sol.evals.function;
    counts.jac += sol.evals.jacobian;
    counts.lu += sol.evals.decompositions;
    Ok(())
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
    let tight = |m| run(o, y0, n, Runner::Ours(m), 1e-11, atol(c, 1e-11));
    let reference = tight(Method::Dopri5).or_else(|_| tight(Method::Radau5))?.0;
    let rungs: Vec<(f64, &str, Runner)> = tols
        .iter()
        .flat_map(|&rtol| RUNNERS.map(|(method, runner)| (rtol, method, runner)))
        .collect();
    let anchor = |i: usize, secs: f64, last: &Result<(Vec<f64>, Counts), String>| {
        let (rtol, method, _) = rungs[i];
        match last {
            Ok((xs, counts)) => Anchor {
                method,
                rtol,
                err: Some(
                    xs.iter()
                        .zip(&reference)
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0, f64::max),
                ),
                secs,
                counts: *counts,
                note: String::new(),
            },
            Err(e) => Anchor {
                method,
                rtol,
                err: None,
                secs,
                counts: Counts::default(),
                note: e.chars().take(90).collect(),
            },
        }
    };
    // all rungs timed together in rounds: the machine's load falls on ours and the library's alike
    let timed = crate::timing::timed_in_rounds(
        rungs.len(),
        |i| {
            let (rtol, _, runner) = rungs[i];
            run(o, y0, n, runner, rtol, atol(c, rtol))
        },
        |i, secs, last| each(&anchor(i, secs, last)),
    );
    let all = timed
        .iter()
        .enumerate()
        .map(|(i, (secs, last))| anchor(i, *secs, last))
        .collect();
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
