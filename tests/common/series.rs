//! Comparing sampled histories: the figures the tests check a run against another with (a
//! reference, a replay, the Rust model), and a `Log` that keeps the warnings of a plain Rust run.

use bindery_fmu::model::{Log, Severity, Values, VarSet};
use std::fmt::Debug;

/// The bit patterns of some samples: equal bits, the same run to the last bit.
pub fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|x| x.to_bits()).collect()
}

/// The bit patterns of rows of samples, row after row.
pub fn row_bits(rows: &[Vec<f64>]) -> Vec<u64> {
    rows.iter().flatten().map(|x| x.to_bits()).collect()
}

/// The largest difference of two histories sampled at the same instants (0 if empty).
pub fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The largest magnitude of a history (0 if empty).
pub fn peak_abs(x: &[f64]) -> f64 {
    x.iter().map(|x| x.abs()).fold(0.0, f64::max)
}

/// The largest value of a history, 0 if none is positive (a compressive contact force: it
/// only pushes).
pub fn peak(x: &[f64]) -> f64 {
    x.iter().cloned().fold(0.0, f64::max)
}

/// How far the peak magnitude of a force history is from its reference's, relative to the
/// reference's peak (at least 1 N).
pub fn peak_abs_rel_diff(force: &[f64], reference: &[f64]) -> f64 {
    let (pa, pb) = (peak_abs(force), peak_abs(reference));
    (pa - pb).abs() / pb.max(1.0)
}

/// Asserts that the variables `names` of a plain Rust run are finite; a failure names the
/// variable, its value and `at()` (the case and the instant).
pub fn assert_finite<V: VarSet + Debug>(v: &Values<V>, names: &[V], at: impl Fn() -> String) {
    for &name in names {
        let x = v[name];
        assert!(x.is_finite(), "{}: non-finite output {name:?} = {x}", at());
    }
}

/// The warnings a plain Rust run logs, in order (other severities are dropped).
#[derive(Debug, Default)]
pub struct Warnings(pub Vec<String>);

impl Log for Warnings {
    fn log(&mut self, s: Severity, m: &str) {
        if s == Severity::Warning {
            self.0.push(m.to_string());
        }
    }
}
