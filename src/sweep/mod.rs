//! Design sweeps (`bindery sweep`): one model run natively for every point of a design of its
//! parameters (a grid, lists, Monte Carlo or a Latin hypercube), each run reduced to the
//! metrics the sweep file asks for (max, min, peak-to-peak, RMS, ... of an output over the last
//! shaft turn or the whole run; event counts; flags; the log's warnings).
//!
//! - [`plan`]: what a checked sweep file says ([`Plan`]: the runs, their columns, the metrics);
//! - [`mod@file`]: a model's sweep file (TOML), refused with the key and its line when malformed;
//!   [`read`]: what every sweep file has (which model, scene or machine; the axes, the design);
//!   a whole machine's sweep is `crate::machines::sweep`, which builds on these;
//! - [`sample`]: the design, which values run `k` takes, the same in every process;
//! - [`plot`]: the figure a person wants of each metric (a map, a histogram, lines);
//! - [`run`]: one run, in this process, on the plain Rust model (no FMI call, no Python);
//! - [`store`]: the results as Parquet parts (and CSV), written as runs finish, and which runs
//!   an interrupted sweep has finished;
//! - [`row`]: a run's result as one line of text (the workers of a Dask cluster send them so),
//!   exact to the bit.
//!
//! The runs are independent: the CLI spreads them over threads (or Dask workers), and any
//! split gives the same rows bit for bit.

pub mod file;
pub mod plan;
pub mod plot;
pub mod read;
pub mod row;
pub mod run;
pub mod sample;
pub mod store;
#[cfg(test)]
mod tests;

pub use plan::{Measure, Metric, Over, Plan, Stat, Swept};
pub use row::Row;

/// What runs one point of a plan: a model's runner, or a machine's, which carries the machine.
#[derive(Clone)]
pub struct Runner(pub std::sync::Arc<RunFn>);

/// Runs point `k` of a plan.
pub type RunFn = dyn Fn(&Plan, usize) -> Row + Send + Sync;

impl std::fmt::Debug for Runner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Runner")
    }
}
