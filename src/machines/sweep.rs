//! A sweep of a whole machine ([`crate::ssp::machines`]: the main-shaft drive with its motor and
//! flywheel, and the mechanisms it turns), run in this process with the same fixed-step master as
//! `bindery machines` ([`crate::machines::simulate`]). Its parameters are named
//! `component.variable` (`drive.fly.J`, `table.table.m`); its metrics are the machine's figures
//! over the last main-shaft turns of the run: the coefficient of speed fluctuation δ, the speed's
//! mean and extremes, the motor torque's peak and RMS, the start-up time.
//!
//! ```toml
//! machine = "ThreadSewingMachine"
//! [swept]
//! "drive.fly.J" = { from = 0.02, to = 0.5, points = 25 }
//! [experiment]
//! stop = 3.0
//! [metrics]
//! delta = { quantity = "delta", turns = 2 }
//! ```

use super::{simulate, startup_time, steady, variables_of};
use crate::model::{Causality, Var};
use crate::scene::{SceneError, line_of, named, nearest};
use crate::ssp::Machine;
use crate::sweep::plan::{Length, Measure, Metric, Plan, QUANTITIES, Quantity, StepSize, Swept};
use crate::sweep::read::{
    axis, design_of, in_file_order, metric_tables, parse_toml, root, value_for,
};
use crate::sweep::{Row, Runner};
use std::ops::Range;

/// What a machine sweep sets: the machine, its fixed values and the swept parameters'
/// components and variables, `(component, variable)`.
#[derive(Clone, Debug, PartialEq)]
pub struct MachineRun {
    pub machine: Machine,
    pub fixed: Vec<(&'static str, &'static str, f64)>,
    pub targets: Vec<(&'static str, &'static str)>,
}

const KEYS: &[&str] = &[
    "machine",
    "fixed",
    "swept",
    "sampling",
    "experiment",
    "metrics",
];

/// Reads a sweep file of `machine`.
pub fn parse(text: &str, machine: Machine) -> Result<Plan, SceneError> {
    let doc = parse_toml(text)?;
    let root = root(text, doc.get_ref());
    root.only(KEYS)?;
    let at = |key: &str, span: &Range<usize>, message: String| SceneError {
        key: key.into(),
        line: Some(line_of(text, span.start)),
        message,
    };
    // `component.variable`: a parameter of one of the machine's components
    let param = |key: &str,
                 name: &str,
                 span: &Range<usize>|
     -> Result<(&'static str, &'static Var), SceneError> {
        let names: Vec<&str> = machine.components.iter().map(|c| c.name).collect();
        let Some(c) = machine
            .components
            .iter()
            .find(|c| name.starts_with(c.name) && name[c.name.len()..].starts_with('.'))
        else {
            return Err(at(
                key,
                span,
                format!(
                    "{name:?} is not component.variable of {}: its components are {}",
                    machine.name,
                    names.join(", ")
                ),
            ));
        };
        let var_name = &name[c.name.len() + 1..];
        let table = variables_of(c.fmu).expect("a machine's components are catalog models");
        let params: Vec<&str> = (table.iter())
            .filter(|v| v.causality == Causality::Parameter)
            .map(|v| v.name)
            .collect();
        match table
            .iter()
            .find(|v| v.name == var_name && v.causality == Causality::Parameter)
        {
            Some(v) => Ok((c.name, v)),
            None => Err(at(
                key,
                span,
                format!(
                    "{} ({}) has no parameter {var_name:?}; {}",
                    c.name,
                    c.fmu,
                    nearest(var_name, &params)
                ),
            )),
        }
    };
    let mut fixed: Vec<(&'static str, &'static str, f64)> = Vec::new();
    if let Some(t) = root.table("fixed", "fixed.")? {
        for (name, key, (k, v)) in in_file_order(t.table, "fixed") {
            let (c, var) = param(&key, &name, &k.span())?;
            let x = value_for(text, &key, var, v)?;
            fixed.push((c, var.name, x));
        }
    }
    let mut swept = Vec::new();
    let mut targets = Vec::new();
    let mut axes = Vec::new();
    if let Some(t) = root.table("swept", "swept.")? {
        for (name, key, (k, v)) in in_file_order(t.table, "swept") {
            let (c, var) = param(&key, &name, &k.span())?;
            if fixed.iter().any(|f| f.0 == c && f.1 == var.name) {
                return Err(at(
                    &key,
                    &k.span(),
                    format!("{name} is both fixed and swept"),
                ));
            }
            // the nominal value: the machine's own, else the model's default
            let nominal = (machine.components.iter())
                .find(|x| x.name == c)
                .and_then(|x| x.params.iter().find(|p| p.0 == var.name).map(|p| p.1))
                .or(var.start);
            axes.push(axis(&t, &key, (v.get_ref(), v.span()), Some(var), nominal)?);
            swept.push(Swept {
                name,
                vr: None,
                unit: var.unit.unwrap_or(""),
            });
            targets.push((c, var.name));
        }
    }
    let design = design_of(&root, axes)?;

    // the experiment: the machine's own stop time and step unless given
    let (mut stop, mut step) = (machine.stop, machine.step);
    if let Some(e) = root.table("experiment", "experiment.")? {
        e.only(&["stop", "step"])?;
        for (key, slot) in [("stop", &mut stop), ("step", &mut step)] {
            if let Some(item) = e.get(key) {
                let (x, span) = e.number(key, item)?;
                if !(x.is_finite() && x > 0.0) {
                    return Err(e.error(key, span, format!("= {x} must be finite and > 0")));
                }
                *slot = x;
            }
        }
        if step > stop {
            return Err(e.error(
                "step",
                e.span.clone(),
                format!("= {step} is longer than stop = {stop}"),
            ));
        }
    }

    let mut metrics = Vec::new();
    let example = "delta = { quantity = \"delta\", turns = 2 }";
    for (name, key, mt) in metric_tables(&root, &swept, &["quantity", "turns"], example)? {
        let (q, span) = mt.string(
            "quantity",
            mt.require(
                "quantity",
                "delta, w_mean, w_min, w_max, tau_peak, tau_rms or startup",
            )?,
        )?;
        let &(_, quantity, unit) =
            named(QUANTITIES, |x| x.0, "quantity", &q).map_err(|why| at(&key, &span, why))?;
        let turns = match mt.get("turns") {
            None => 1.0,
            Some(item) => {
                let (x, span) = mt.number("turns", item)?;
                if !(x.is_finite() && x > 0.0) {
                    return Err(at(&key, &span, format!("turns = {x} must be > 0")));
                }
                x
            }
        };
        metrics.push(Metric {
            name,
            unit,
            measure: Measure::Machine { quantity, turns },
        });
    }
    Ok(Plan {
        text: text.to_string(),
        scene: None,
        model: machine.name,
        fidelity: None,
        fixed: Vec::new(),
        swept,
        design,
        speed: None,
        length: Length::Stop(stop),
        step: StepSize::Seconds(step),
        metrics,
        runner: {
            let mr = MachineRun {
                machine,
                fixed,
                targets,
            };
            Runner(std::sync::Arc::new(move |plan: &Plan, k: usize| {
                run(&mr, plan, k)
            }))
        },
    })
}

/// Run `k` of a machine sweep.
fn run(mr: &MachineRun, plan: &Plan, k: usize) -> Row {
    let params = plan.design.point(k);
    let (Length::Stop(stop), StepSize::Seconds(h)) = (plan.length, plan.step) else {
        unreachable!("a machine sweep runs for a time in steps of a time")
    };
    let mut set = mr.fixed.clone();
    set.extend(
        mr.targets
            .iter()
            .zip(&params)
            .map(|(&(c, v), &x)| (c, v, x)),
    );
    let result =
        std::panic::catch_unwind(|| simulate(&mr.machine, &set, stop, h)).unwrap_or_else(|_| {
            Err("the machine's simulation panicked (a bug of bindery-fmu, please report it)".into())
        });
    let (metrics, error) = match result {
        Err(e) => (Vec::new(), e),
        Ok(tr) => (
            plan.metrics
                .iter()
                .map(|m| {
                    let Measure::Machine { quantity, turns } = m.measure else {
                        unreachable!("a machine's plan measures the machine")
                    };
                    let s = steady(&tr, turns);
                    match quantity {
                        Quantity::Delta => s.delta,
                        Quantity::WMean => s.w_mean,
                        Quantity::WMin => s.w_min,
                        Quantity::WMax => s.w_max,
                        Quantity::TauPeak => s.tau_peak,
                        Quantity::TauRms => s.tau_rms,
                        Quantity::Startup => startup_time(&tr, 0.95, s.w_mean).unwrap_or(f64::NAN),
                    }
                })
                .collect(),
            String::new(),
        ),
    };
    Row {
        run: k,
        params,
        metrics,
        warnings: 0,
        warning: String::new(),
        error,
    }
}
