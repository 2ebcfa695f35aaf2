//! The report's chain cases (`bindery report`) run in-process through the model's
//! Co-Simulation step, for instruction counts with callgrind (repeatable on a loaded machine;
//! no timing here): the case at its elastodynamic level, a constant speed, `auto` (or the method
//! named) at `rtol`,
//! in calls of 1 ms as inside `fmi2DoStep`, `prepare` included. Prints the sum of the position
//! output over the run, so two builds can be seen to compute the same.
//!
//! ```sh
//! cargo bench --bench chain_cases --no-run
//! valgrind --tool=callgrind target/release/deps/chain_cases-<hash> sewing 1e-3
//! ```
//! Cases: `geneva` (k = 5e7 N/m), `sewing` (1e7), `perforators` (linear contact 1e8),
//! `disc` (rod 2e8); a third argument sets the stiffness, a fourth the method (`auto`, the
//! default, `dopri5` or `radau5`).

use bindery_fmu::mechanisms::{
    disc_knife_drive::DiscKnifeDrive, geneva_knife_drive::GenevaKnifeDrive,
    perforators::Perforators, sewing_table::SewingTable,
};
use bindery_fmu::model::{Model, NoLog, Values};
use bindery_fmu::solver::Method;

/// One case: `(name, value)` start values, the run's length (s) and its position output.
fn run<M: Model>(set: &[(&str, f64)], stop: f64, x: &str) -> f64 {
    let mut v = Values::<M::Var>::start();
    for (name, value) in set {
        v.set_named(name, *value);
    }
    let mut m = M::prepare(&v).expect("the case's parameters");
    let (ix, n) = (
        Values::<M::Var>::index_of(x),
        (stop / 1e-3_f64).round() as usize,
    );
    let mut sum = 0.0;
    for i in 0..n {
        m.step(&mut v, i as f64 * 1e-3, 1e-3, &mut NoLog)
            .expect("a step");
        m.evaluate(&mut v, (i + 1) as f64 * 1e-3, &mut NoLog);
        sum += v.raw()[ix];
    }
    sum
}

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let (Some(case), Some(rtol)) = (args.first(), args.get(1).and_then(|s| s.parse().ok())) else {
        eprintln!(
            "usage: chain_cases geneva|sewing|perforators|disc RTOL [STIFFNESS [auto|dopri5|radau5]]"
        );
        return;
    };
    let rtol: f64 = rtol;
    let k = |default: f64| args.get(2).and_then(|s| s.parse().ok()).unwrap_or(default);
    let method = match args.get(3).map(String::as_str) {
        None | Some("auto") => Method::Auto,
        Some("dopri5") => Method::Dopri5,
        Some("radau5") => Method::Radau5,
        Some(other) => {
            eprintln!("unknown method {other}: auto, dopri5 or radau5");
            return;
        }
    };
    let common = |rpm: f64, k_name: &'static str, k: f64| {
        vec![
            ("model.fidelity", 3.0),
            ("drive.mode", 2.0),
            ("drive.n", rpm * std::f64::consts::PI / 30.0),
            (k_name, k),
            ("solver.rtol", rtol),
            ("solver.atol", (rtol * 1e-3).min(3.0 / k)),
            ("solver.method", f64::from(method as i32)),
        ]
    };
    let sum = match case.as_str() {
        "geneva" => run::<GenevaKnifeDrive>(&common(30.0, "elastic.k", k(5e7)), 0.5, "knife.s"),
        "sewing" => run::<SewingTable>(&common(100.0, "elastic.k", k(1e7)), 0.6, "table.x"),
        "perforators" => {
            let mut set = common(100.0, "contact.k", k(1e8));
            set.push(("contact.law", 2.0));
            run::<Perforators>(&set, 0.3, "lever.gamma")
        }
        "disc" => run::<DiscKnifeDrive>(&common(300.0, "elastic.k", k(2e8)), 0.2, "slider.x"),
        other => {
            eprintln!("unknown case {other}: geneva, sewing, perforators or disc");
            return;
        }
    };
    println!("{sum:.17e}");
}
