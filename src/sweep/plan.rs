//! What a sweep file says, checked: the plan of the runs ([`Plan`]), its columns (swept
//! parameters, metrics) and what each metric measures.

use super::sample::Design;
use super::{Row, Runner};
use crate::model::shaft::Fidelity;

/// Most runs a sweep may have.
pub const MAX_RUNS: usize = 100_000_000;
/// Most samples of one run's metric series (steps times outputs), to keep a run's memory small.
pub const MAX_STEPS: usize = 10_000_000;

/// What a metric computes from an output's samples in its window.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stat {
    Max,
    Min,
    /// max − min.
    Ptp,
    /// Root mean square.
    Rms,
    Mean,
    /// The value at the end of the run.
    Last,
    /// 1 if the output was ever nonzero (true), else 0: a flag such as a lift-off.
    Any,
    /// How many times the output turned from zero to nonzero: events of a flag.
    Rises,
    /// The output's increase over the window: events of a counter such as `contact.liftoffs`.
    Increase,
}

/// Every stat by its name in a sweep file.
pub const STATS: &[(&str, Stat)] = &[
    ("max", Stat::Max),
    ("min", Stat::Min),
    ("ptp", Stat::Ptp),
    ("rms", Stat::Rms),
    ("mean", Stat::Mean),
    ("last", Stat::Last),
    ("any", Stat::Any),
    ("rises", Stat::Rises),
    ("increase", Stat::Increase),
];

/// The samples a metric is computed over.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Over {
    /// The last shaft turn of the run (the samples after `stop − 2π/ω`, and the one at that
    /// instant).
    LastTurn,
    /// Every sample, from time 0.
    Run,
}

/// One metric: a column of the results.
#[derive(Clone, Debug, PartialEq)]
pub struct Metric {
    pub name: String,
    /// Its unit ("" if none).
    pub unit: &'static str,
    pub measure: Measure,
}

/// What a metric measures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Measure {
    /// A statistic of a model's output (value reference) over a window.
    Output { output: u32, stat: Stat, over: Over },
    /// A figure of a whole machine's run over its last `turns` main-shaft turns
    /// (`crate::machines::sweep`).
    Machine { quantity: Quantity, turns: f64 },
}

/// A figure of a whole machine's run (`crate::machines::sweep`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// δ = (ω_max − ω_min)/ω_mean of the main shaft.
    Delta,
    /// Mean, smallest and largest main-shaft speed, rad/s.
    WMean,
    WMin,
    WMax,
    /// Peak |motor torque| and its RMS, N·m (at the motor shaft).
    TauPeak,
    TauRms,
    /// Time until the main shaft first reaches 95 % of its mean speed over the last turns, s.
    Startup,
}

/// Every quantity by its name in a sweep file, with its unit.
pub const QUANTITIES: &[(&str, Quantity, &str)] = &[
    ("delta", Quantity::Delta, ""),
    ("w_mean", Quantity::WMean, "rad/s"),
    ("w_min", Quantity::WMin, "rad/s"),
    ("w_max", Quantity::WMax, "rad/s"),
    ("tau_peak", Quantity::TauPeak, "N.m"),
    ("tau_rms", Quantity::TauRms, "N.m"),
    ("startup", Quantity::Startup, "s"),
];

/// A swept parameter: a column of the results.
#[derive(Clone, Debug, PartialEq)]
pub struct Swept {
    pub name: String,
    /// Its unit ("" if none; rpm for the speed).
    pub unit: &'static str,
    /// Its value reference; `None` for the speed (rpm).
    pub vr: Option<u32>,
}

/// How long a run is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Length {
    /// Shaft turns at the run's speed.
    Turns(f64),
    /// Seconds.
    Stop(f64),
}

/// How long a communication step is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepSize {
    /// Steps per shaft turn at the run's speed.
    PerTurn(usize),
    /// Seconds.
    Seconds(f64),
}

/// A sweep file, checked against its model: everything a run needs.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The file as read (an interrupted sweep resumes only with the same text).
    pub text: String,
    /// The scene file's text, if the sweep starts from one.
    pub scene: Option<String>,
    pub model: &'static str,
    /// `None`: the model's default level (or a model without levels).
    pub fidelity: Option<Fidelity>,
    /// Parameters held for every run, in SI: (value reference, value).
    pub fixed: Vec<(u32, f64)>,
    pub swept: Vec<Swept>,
    pub design: Design,
    /// The speed when it is not swept, rpm (`None` for a model that drives itself).
    pub speed: Option<f64>,
    pub length: Length,
    pub step: StepSize,
    pub metrics: Vec<Metric>,
    /// What runs one point of the design: a model's runner ([`super::run::run`]), or a
    /// machine's (`crate::machines::sweep`), which carries the machine.
    pub runner: Runner,
}

impl Plan {
    /// Number of runs.
    pub fn runs(&self) -> usize {
        self.design.runs()
    }

    /// Run `k` on this process.
    pub fn run(&self, k: usize) -> Row {
        (self.runner.0)(self, k)
    }

    /// The columns of a row: the swept parameters', then the metrics'.
    pub fn columns(&self) -> Vec<String> {
        (self.swept.iter().map(|s| s.name.clone()))
            .chain(self.metrics.iter().map(|m| m.name.clone()))
            .collect()
    }
}
