//! One run of a sweep in this process, on the plain Rust model: the parameters set, the model
//! prepared (a refusal becomes the row's reason), the shaft turned at constant speed (a driven
//! mechanism in its `constant_speed` mode) or the model stepped alone, each communication step
//! the same `Model::step` and `Model::evaluate` an FMU's `fmi2DoStep` and `fmi2GetReal` run,
//! and the metrics computed from the samples at the communication points.

use super::Row;
use super::file::{Length, Measure, Over, Plan, Stat, StepSize};
use crate::model::shaft;
use crate::model::{Log, Model, Severity, Values, check_bounds};
use std::f64::consts::PI;

/// Counts the warnings a model logs and keeps the first.
#[derive(Default)]
struct Capture {
    warnings: u64,
    first: String,
}

impl Log for Capture {
    fn log(&mut self, severity: Severity, message: &str) {
        if severity == Severity::Warning {
            if self.warnings == 0 {
                self.first = message.to_string();
            }
            self.warnings += 1;
        }
    }
}

/// Run `k` of `plan` on model `M` (`plan` was read for `M`: [`super::file::parse`]).
pub fn run<M: Model>(plan: &Plan, k: usize) -> Row {
    let params = plan.design.point(k);
    let mut log = Capture::default();
    // a panic in the model is a bug, but one run's bug must not take the sweep down: its row
    // says so
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        simulate::<M>(plan, &params, &mut log)
    }))
    .unwrap_or_else(|p| {
        let what = p
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| p.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Err(format!(
            "the model panicked (a bug of bindery-fmu, please report it): {what}"
        ))
    });
    let (metrics, error) = match result {
        Ok(m) => (m, String::new()),
        Err(e) => (Vec::new(), e),
    };
    Row {
        run: k,
        params,
        metrics,
        warnings: log.warnings,
        warning: log.first,
        error,
    }
}

fn simulate<M: Model>(plan: &Plan, params: &[f64], log: &mut Capture) -> Result<Vec<f64>, String> {
    let mut v = Values::<M::Var>::start();
    for &(vr, x) in &plan.fixed {
        v.raw_mut()[vr as usize] = x;
    }
    let mut rpm = plan.speed;
    for (s, &x) in plan.swept.iter().zip(params) {
        match s.vr {
            Some(vr) => v.raw_mut()[vr as usize] = x,
            None => rpm = Some(x),
        }
    }
    let driven = shaft::is_driven::<M::Var>();
    if driven {
        let constant = (shaft::DRIVE_MODE.items.iter())
            .position(|i| i.0 == "constant_speed")
            .expect("a drive mode constant_speed") as f64
            + 1.0;
        v.raw_mut()[shaft::MODE as usize] = constant;
        v.raw_mut()[shaft::N as usize] =
            rpm.expect("a driven model's plan has a speed") * PI / 30.0;
        if let Some(f) = plan.fidelity {
            v.raw_mut()[shaft::FIDELITY as usize] = f as i32 as f64;
        }
    }
    check_bounds(&v).map_err(|e| format!("parameters refused: {e}"))?;
    let mut m = M::prepare(&v).map_err(|e| format!("parameters refused: {e}"))?;
    m.calculated_parameters(&mut v);
    m.evaluate(&mut v, 0.0, log);

    // the time grid: a turn lasts 60/n s
    let turn = rpm.map(|n| 60.0 / n);
    let stop = match plan.length {
        Length::Turns(t) => t * turn.expect("turns only with a speed"),
        Length::Stop(s) => s,
    };
    let h = match plan.step {
        StepSize::PerTurn(n) => turn.expect("steps per turn only with a speed") / n as f64,
        StepSize::Seconds(h) => h,
    };
    let steps = (stop / h).round().max(1.0);
    if !(steps.is_finite() && steps as usize * plan.metrics.len() <= super::file::MAX_STEPS) {
        return Err(format!(
            "{steps} steps of {h} s: more than this sweep keeps per run ({} samples)",
            super::file::MAX_STEPS
        ));
    }
    let steps = steps as usize;

    // the outputs the metrics read, sampled at every communication point
    let mut outputs: Vec<u32> = (plan.metrics.iter())
        .filter_map(|m| match m.measure {
            Measure::Output { output, .. } => Some(output),
            Measure::Machine { .. } => None,
        })
        .collect();
    outputs.sort_unstable();
    outputs.dedup();
    let mut series: Vec<Vec<f64>> = vec![Vec::with_capacity(steps + 1); outputs.len()];
    let sample = |v: &Values<M::Var>, series: &mut Vec<Vec<f64>>| {
        for (s, &o) in series.iter_mut().zip(&outputs) {
            s.push(v.raw()[o as usize]);
        }
    };
    sample(&v, &mut series);
    for i in 0..steps {
        let t = i as f64 * h;
        m.step(&mut v, t, h, log)
            .map_err(|e| format!("step at t = {t} s refused: {e}"))?;
        m.evaluate(&mut v, (i + 1) as f64 * h, log);
        sample(&v, &mut series);
    }
    m.finish(&v, log);

    // the last turn: the samples from one turn before the end (the one there included)
    let last_turn_from = match turn {
        Some(tt) => steps.saturating_sub((tt / h - 1e-9).ceil() as usize),
        None => 0,
    };
    Ok(plan
        .metrics
        .iter()
        .map(|m| {
            let Measure::Output {
                output,
                stat: st,
                over,
            } = m.measure
            else {
                unreachable!("a model's plan measures outputs")
            };
            let x = &series[outputs.binary_search(&output).expect("sampled")];
            let from = match over {
                Over::LastTurn => last_turn_from,
                Over::Run => 0,
            };
            stat(st, &x[from..])
        })
        .collect())
}

/// A stat of the samples `x` (at least one).
pub fn stat(s: Stat, x: &[f64]) -> f64 {
    let n = x.len() as f64;
    match s {
        Stat::Max => x.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        Stat::Min => x.iter().copied().fold(f64::INFINITY, f64::min),
        Stat::Ptp => stat(Stat::Max, x) - stat(Stat::Min, x),
        Stat::Rms => (x.iter().map(|v| v * v).sum::<f64>() / n).sqrt(),
        Stat::Mean => x.iter().sum::<f64>() / n,
        Stat::Last => x[x.len() - 1],
        Stat::Any => f64::from(u8::from(x.iter().any(|&v| v != 0.0))),
        Stat::Rises => x.windows(2).filter(|w| w[0] == 0.0 && w[1] != 0.0).count() as f64,
        Stat::Increase => x[x.len() - 1] - x[0],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_of_a_known_series() {
        let x = [0.0, 3.0, -4.0, 0.0, 0.0, 1.0];
        assert_eq!(stat(Stat::Max, &x), 3.0);
        assert_eq!(stat(Stat::Min, &x), -4.0);
        assert_eq!(stat(Stat::Ptp, &x), 7.0);
        assert_eq!(stat(Stat::Rms, &x), (26.0f64 / 6.0).sqrt());
        assert_eq!(stat(Stat::Mean, &x), 0.0);
        assert_eq!(stat(Stat::Last, &x), 1.0);
        assert_eq!(stat(Stat::Any, &x), 1.0);
        assert_eq!(stat(Stat::Any, &[0.0, 0.0]), 0.0);
        assert_eq!(stat(Stat::Rises, &x), 2.0);
        assert_eq!(stat(Stat::Increase, &[2.0, 5.0, 7.0]), 5.0);
    }
}
