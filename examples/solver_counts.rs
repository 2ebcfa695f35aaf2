//! The integrators' work on the mechanisms' chains, in counts (they do not depend on the
//! machine): accepted and rejected steps, right-hand sides, Jacobians, LU factorizations, and
//! the largest position error on the 1 ms grid against a reference at rtol 1e-11, with the wall
//! time of one run beside them. `cargo run --release --example solver_counts [rtol ...]`

use bindery_fmu::mechanisms::disc_knife_drive::elastic::{RodOde, dead_point_threshold};
use bindery_fmu::mechanisms::disc_knife_drive::physics::Params as DiscParams;
use bindery_fmu::mechanisms::geneva_knife_drive::elastic::KnifeOde;
use bindery_fmu::mechanisms::geneva_knife_drive::physics::Params as GenevaParams;
use bindery_fmu::mechanisms::perforators::elastic::{Contact, ContactLaw, LeverOde, Track};
use bindery_fmu::mechanisms::perforators::physics::{Drive, Params as PerfParams};
use bindery_fmu::solver::chain::{ChainOde, Peaks};
use bindery_fmu::solver::{Integrator, Method, OdeSystem, Settings, ShaftPath, Stats};
use std::cell::Cell;
use std::time::Instant;

fn geneva(p: &GenevaParams, k: f64) -> KnifeOde<'_> {
    KnifeOde {
        p,
        geneva: p.geneva(),
        k,
        c: KnifeOde::damping(p, k, 0.05),
        path: ShaftPath::new(0.0, 0.0, std::f64::consts::PI, 0.0),
        peaks: Cell::new(Peaks::new(0.0)),
        cut_done: Cell::new(false),
    }
}

fn disc(p: &DiscParams, k: f64) -> RodOde<'_> {
    RodOde {
        p,
        k,
        c: RodOde::damping(p, k, 0.05),
        path: ShaftPath::new(0.0, 0.0, p.drive_n, 0.0),
        c_dead: dead_point_threshold(p),
        peaks: Cell::new(Peaks::new(0.0)),
    }
}

fn lever(d: &Drive, k: f64) -> LeverOde<'_> {
    LeverOde {
        d,
        contact: Contact {
            law: ContactLaw::Linear,
            k,
            c: 2.0 * 0.05 * (k * LeverOde::reduced_mass(d)).sqrt(),
        },
        path: ShaftPath::new(0.0, 0.0, 100.0 * std::f64::consts::PI / 30.0, 0.0),
        track: Cell::new(Track::new(0.0)),
        range: LeverOde::linkage_range(d),
        out_of_range: Cell::new(f64::NAN),
    }
}

/// `o` from `y0` over `n` intervals of 1 ms with one integrator: the first state at every grid
/// point, the counters, the time.
fn run(
    o: &dyn OdeSystem,
    y0: [f64; 3],
    n: usize,
    method: Method,
    rtol: f64,
    atol: f64,
) -> Result<(Vec<f64>, Stats, f64), String> {
    let mut it = Integrator::new(Settings {
        method,
        rtol,
        atol,
        max_step: 1e-3,
        max_steps: 10_000_000,
    });
    let mut y = y0;
    let mut xs = vec![y[0]];
    let t0 = Instant::now();
    for i in 0..n {
        let (a, b) = (i as f64 * 1e-3, (i + 1) as f64 * 1e-3);
        it.integrate(o, a, b, &mut y)?;
        xs.push(y[0]);
    }
    Ok((xs, it.mem.stats, t0.elapsed().as_secs_f64()))
}

fn main() {
    let tols: Vec<f64> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let tols = if tols.is_empty() {
        vec![1e-4, 1e-6, 1e-8]
    } else {
        tols
    };
    let gp = GenevaParams::default();
    let dp = DiscParams::default();
    let pd = PerfParams::default().drive().unwrap();
    // (label, ODE, its scale of the first state's error: the chain's deflection at 1 kN)
    let cases: Vec<(&str, Box<dyn OdeSystem + '_>, [f64; 3], usize, f64)> = vec![
        (
            "Geneva 5e7",
            Box::new(geneva(&gp, 5e7)),
            geneva(&gp, 5e7).initial_state(0.0),
            230,
            5e7,
        ),
        (
            "Geneva 1e12",
            Box::new(geneva(&gp, 1e12)),
            geneva(&gp, 1e12).initial_state(0.0),
            230,
            1e12,
        ),
        (
            "Disc 2e8",
            Box::new(disc(&dp, 2e8)),
            disc(&dp, 2e8).initial_state(0.0),
            200,
            2e8,
        ),
        (
            "Disc 1e12",
            Box::new(disc(&dp, 1e12)),
            disc(&dp, 1e12).initial_state(0.0),
            200,
            1e12,
        ),
        (
            "Perforators 1e8",
            Box::new(lever(&pd, 1e8)),
            lever(&pd, 1e8).initial_state(0.0),
            300,
            1e8,
        ),
        (
            "Perforators 1e10",
            Box::new(lever(&pd, 1e10)),
            lever(&pd, 1e10).initial_state(0.0),
            300,
            1e10,
        ),
    ];
    println!(
        "case | method | rtol | error | steps | rejected | rhs | jac | LU | events | switches | ms"
    );
    let only = std::env::var("CASE").ok();
    for (label, o, y0, n, k) in &cases {
        if only.as_deref().is_some_and(|c| !label.contains(c)) {
            continue;
        }
        let atol = |rtol: f64| (rtol * 1e-3).min(3.0 / k);
        let reference = run(o.as_ref(), *y0, *n, Method::Dopri5, 1e-11, atol(1e-11))
            .or_else(|_| run(o.as_ref(), *y0, *n, Method::Radau5, 1e-11, atol(1e-11)));
        let Ok((xr, _, _)) = reference else {
            println!("{label}: no reference");
            continue;
        };
        for &rtol in &tols {
            for method in [Method::Auto, Method::Dopri5, Method::Radau5] {
                match run(o.as_ref(), *y0, *n, method, rtol, atol(rtol)) {
                    Ok((x, s, secs)) => {
                        let e = x
                            .iter()
                            .zip(&xr)
                            .map(|(a, b)| (a - b).abs())
                            .fold(0.0, f64::max);
                        println!(
                            "{label} | {method:?} | {rtol:e} | {e:.2e} | {} | {} | {} | {} | {} | {} | {} | {:.1}",
                            s.steps,
                            s.rejected,
                            s.rhs_evals,
                            s.jac_evals,
                            lu(&s),
                            s.events,
                            s.switches,
                            secs * 1e3
                        );
                    }
                    Err(e) => println!(
                        "{label} | {method:?} | {rtol:e} | failed: {}",
                        &e[..e.len().min(80)]
                    ),
                }
            }
        }
    }
}

fn lu(s: &Stats) -> String {
    format!("{:?}", s)
        .split("decomps: ")
        .nth(1)
        .map_or("-".into(), |r| r.split(',').next().unwrap_or("").into())
}
