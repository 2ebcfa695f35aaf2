//! The sweep file: which model, its fixed and swept parameters, the design, the experiment and
//! the metrics (the sweep page of the documentation, `docs/sweeps.md`, shows every key).
//!
//! ```toml
//! model = "Perforators"
//! fidelity = "kinetostatic"
//! [fixed]
//! "roller.r" = 0.02
//! [swept]
//! "spring.M0" = { from = 2.0, to = 12.0, points = 11 }
//! "spring.kt" = { values = [5.0, 10.0, 20.0] }
//! [experiment]
//! speed = 130            # rpm
//! turns = 2
//! steps_per_turn = 720
//! [metrics]
//! F_min = { output = "roller.F", stat = "min" }
//! ```
//!
//! Values are in SI units (as in the model description), the speed in rpm. A malformed file is
//! refused naming the key and its line; a value the model refuses for one run (out of its
//! bounds, a linkage that does not assemble) is not an error of the file: that run's row
//! carries the reason.

pub use super::plan::*;
pub use super::read::{Target, model_of, target_of};
use super::read::{
    axis, design_of, in_file_order, metric_tables, parse_toml, root, value_for, whole,
};
use crate::model::shaft;
use crate::model::{Causality, Model, Values, VarSet, check_bounds};
use crate::scene::{
    FIDELITIES, Scene, SceneError, fidelity_name, levels_of, line_of, named, nearest, value_of,
};
use std::ops::Range;

/// The keys of a sweep file and of its tables.
pub const KEYS: &[&str] = &[
    "model",
    "scene",
    "machine",
    "fidelity",
    "fixed",
    "swept",
    "sampling",
    "experiment",
    "metrics",
];
const EXPERIMENT_KEYS: &[&str] = &["speed", "turns", "stop", "steps_per_turn", "step"];
const METRIC_KEYS: &[&str] = &["output", "stat", "over"];
/// The name of the shaft speed among the swept parameters (rpm).
pub const SPEED: &str = "speed";

/// Reads a sweep file of model `M` (with the text of its scene file, if it names one) and
/// checks it against the model: names, types, fixed values against their bounds, outputs the
/// fidelity level computes, the design, the experiment.
pub fn parse<M: Model>(text: &str, scene_text: Option<&str>) -> Result<Plan, SceneError> {
    let doc = parse_toml(text)?;
    let root = root(text, doc.get_ref());
    root.only(KEYS)?;
    let table = <M::Var as VarSet>::table();
    let driven = shaft::is_driven::<M::Var>();
    let at = |key: &str, span: &Range<usize>, message: String| SceneError {
        key: key.into(),
        line: Some(line_of(text, span.start)),
        message,
    };
    let param = |key: &str, name: &str, span: &Range<usize>| -> Result<u32, SceneError> {
        let Some(i) = table.iter().position(|v| v.name == name) else {
            let names: Vec<&str> = (table.iter())
                .filter(|v| v.causality == Causality::Parameter)
                .map(|v| v.name)
                .collect();
            return Err(at(
                key,
                span,
                format!(
                    "{} has no parameter {name:?}; {}",
                    M::IDENTIFIER,
                    nearest(name, &names)
                ),
            ));
        };
        let v = &table[i];
        if v.causality != Causality::Parameter {
            return Err(at(
                key,
                span,
                format!("{name} is not a parameter of {}", M::IDENTIFIER),
            ));
        }
        if driven && matches!(i as u32, shaft::MODE | shaft::N | shaft::FIDELITY) {
            return Err(at(
                key,
                span,
                format!(
                    "{name} is set by the sweep: the speed as `speed` (rpm, in [experiment] or [swept]), the level as `fidelity`"
                ),
            ));
        }
        Ok(i as u32)
    };

    // the scene a sweep may start from: its level, parameters and constant speed
    let scene = match (root.get("scene"), scene_text) {
        (Some(_), Some(t)) => Some(Scene::parse(t).map_err(|e| SceneError {
            message: format!("in the scene file: {e}"),
            key: "scene".into(),
            line: root.get("scene").map(|(_, s)| line_of(text, s.start)),
        })?),
        (Some(item), None) => {
            return Err(at("scene", &item.1, "the scene file was not given".into()));
        }
        (None, _) => None,
    };

    let mut fidelity = scene.as_ref().and_then(|s| s.fidelity);
    if let Some(item) = root.get("fidelity") {
        let (f, span) = root.string("fidelity", item)?;
        if !driven {
            return Err(at(
                "fidelity",
                &span,
                format!("{} has no fidelity levels", M::IDENTIFIER),
            ));
        }
        let level = named(FIDELITIES, |f| f.0, "level", &f);
        fidelity = Some(level.map_err(|why| at("fidelity", &span, why))?.1);
    }

    // fixed parameters: the scene's, then the file's
    let mut fixed: Vec<(u32, f64)> = Vec::new();
    let mut set_fixed = |vr: u32, x: f64| {
        fixed.retain(|f| f.0 != vr);
        fixed.push((vr, x));
    };
    if let Some(s) = &scene {
        for (name, x, _) in &s.parameters {
            let vr = param("scene", name, &(0..0))?;
            let v = value_of(&table[vr as usize], x).map_err(|e| at("scene", &(0..0), e))?;
            set_fixed(vr, v);
        }
        match s.drive {
            crate::scene::Drive::ConstantSpeed { phi0, .. }
            | crate::scene::Drive::Input { phi0: Some(phi0) } => set_fixed(shaft::PHI0, phi0),
            crate::scene::Drive::Input { phi0: None } => {}
        }
    }
    if let Some(t) = root.table("fixed", "fixed.")? {
        for (name, key, (k, v)) in in_file_order(t.table, "fixed") {
            let vr = param(&key, &name, &k.span())?;
            let x = value_for(text, &key, &table[vr as usize], v)?;
            set_fixed(vr, x);
        }
    }
    {
        // the fixed values alone must be within their bounds
        let mut vals = Values::<M::Var>::start();
        for &(vr, x) in &fixed {
            vals.raw_mut()[vr as usize] = x;
        }
        if let Err(e) = check_bounds(&vals) {
            let span = (root.get("fixed").map(|i| i.1)).unwrap_or(0..0);
            return Err(at(&format!("fixed.{:?}", e.param), &span, e.to_string()));
        }
    }

    // swept parameters
    let mut swept = Vec::new();
    let mut axes = Vec::new();
    if let Some(t) = root.table("swept", "swept.")? {
        for (name, key, (k, v)) in in_file_order(t.table, "swept") {
            let vr = if name == SPEED {
                if !driven {
                    return Err(at(
                        &key,
                        &k.span(),
                        format!("{} drives itself: no speed to sweep", M::IDENTIFIER),
                    ));
                }
                None
            } else {
                Some(param(&key, &name, &k.span())?)
            };
            if fixed.iter().any(|f| Some(f.0) == vr) && root.get("fixed").is_some() {
                // a scene's value is overridden silently; the file's own [fixed] is a conflict
                if let Some(ft) = root.table("fixed", "fixed.")?
                    && ft.get(&name).is_some()
                {
                    return Err(at(
                        &key,
                        &k.span(),
                        format!("{name} is both fixed and swept"),
                    ));
                }
            }
            let var = vr.map(|vr| &table[vr as usize]);
            let nominal = vr
                .and_then(|vr| fixed.iter().find(|f| f.0 == vr).map(|f| f.1))
                .or_else(|| var.and_then(|v| v.start));
            axes.push(axis(&t, &key, (v.get_ref(), v.span()), var, nominal)?);
            swept.push(Swept {
                name,
                vr,
                unit: var.map_or("rpm", |v| v.unit.unwrap_or("")),
            });
        }
    }

    let design = design_of(&root, axes)?;

    // the experiment
    let e = root.table("experiment", "experiment.")?.ok_or_else(|| {
        at(
            "experiment",
            &(0..0),
            "missing: the file needs [experiment] (turns or stop, and the step)".into(),
        )
    })?;
    e.only(EXPERIMENT_KEYS)?;
    let positive = |key: &str| -> Result<Option<(f64, Range<usize>)>, SceneError> {
        match e.get(key) {
            None => Ok(None),
            Some(item) => {
                let (x, span) = e.number(key, item)?;
                if !(x.is_finite() && x > 0.0) {
                    return Err(e.error(key, span, format!("= {x} must be finite and > 0")));
                }
                Ok(Some((x, span)))
            }
        }
    };
    let scene_speed = scene.as_ref().and_then(|s| match s.drive {
        crate::scene::Drive::ConstantSpeed { rpm, .. } => Some(rpm),
        _ => None,
    });
    let speed_swept = swept.iter().any(|s| s.vr.is_none());
    let speed = match positive("speed")? {
        Some((_, span)) if !driven => {
            return Err(e.error(
                "speed",
                span,
                format!("{} drives itself: it has no speed to set", M::IDENTIFIER),
            ));
        }
        Some((_, span)) if speed_swept => {
            return Err(e.error("speed", span, "the speed is swept ([swept] speed)".into()));
        }
        Some((x, _)) => Some(x),
        None => scene_speed,
    };
    if driven && speed.is_none() && !speed_swept {
        return Err(e.error(
            "speed",
            e.span.clone(),
            "missing: the shaft speed in rpm (or sweep `speed`)".into(),
        ));
    }
    let length = match (positive("turns")?, positive("stop")?) {
        (Some(_), Some((_, span))) => {
            return Err(e.error("stop", span, "give `turns` or `stop`, not both".into()));
        }
        (Some((_, span)), None) if !driven => {
            return Err(e.error(
                "turns",
                span,
                format!("{} drives itself: give `stop` in s", M::IDENTIFIER),
            ));
        }
        (Some((x, _)), None) => Length::Turns(x),
        (None, Some((x, _))) => Length::Stop(x),
        (None, None) => {
            return Err(e.error(
                "turns",
                e.span.clone(),
                "missing: `turns` (shaft turns) or `stop` (s)".into(),
            ));
        }
    };
    let step = match (e.get("steps_per_turn"), positive("step")?) {
        (Some(_), Some((_, span))) => {
            return Err(e.error(
                "step",
                span,
                "give `steps_per_turn` or `step`, not both".into(),
            ));
        }
        (Some(item), None) => {
            if !driven {
                return Err(e.error(
                    "steps_per_turn",
                    item.1,
                    format!("{} drives itself: give `step` in s", M::IDENTIFIER),
                ));
            }
            StepSize::PerTurn(whole(&e, "steps_per_turn", item, 1, 1_000_000)? as usize)
        }
        (None, Some((x, _))) => StepSize::Seconds(x),
        (None, None) => StepSize::PerTurn(if driven { 720 } else { 0 }),
    };
    if step == StepSize::PerTurn(0) {
        return Err(e.error(
            "step",
            e.span.clone(),
            "missing: the communication step in s".into(),
        ));
    }

    // the metrics
    let mut metrics = Vec::new();
    let outputs: Vec<&str> = (table.iter())
        .filter(|v| matches!(v.causality, Causality::Output | Causality::Local))
        .map(|v| v.name)
        .collect();
    let example = "F_max = { output = \"rod.F\", stat = \"max\" }";
    for (name, key, mt) in metric_tables(&root, &swept, METRIC_KEYS, example)? {
        let (output, span) = mt.string("output", mt.require("output", "an output's name")?)?;
        let Some(i) = table.iter().position(|x| {
            x.name == output && matches!(x.causality, Causality::Output | Causality::Local)
        }) else {
            return Err(at(
                &key,
                &span,
                format!(
                    "{} has no output {output:?}; {}",
                    M::IDENTIFIER,
                    nearest(&output, &outputs)
                ),
            ));
        };
        if let Some(f) = fidelity {
            let levels = levels_of(M::STAGES, table[i].needs);
            if !levels.contains(&f) {
                return Err(at(
                    &key,
                    &span,
                    format!(
                        "{output} is not computed at the {} level; it is at: {}",
                        fidelity_name(f),
                        levels
                            .iter()
                            .map(|l| fidelity_name(*l))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ));
            }
        }
        let (stat, span) = mt.string(
            "stat",
            mt.require(
                "stat",
                "max, min, ptp, rms, mean, last, any, rises or increase",
            )?,
        )?;
        let stat = named(STATS, |s| s.0, "stat", &stat)
            .map_err(|why| at(&key, &span, why))?
            .1;
        let over = match mt.get("over") {
            None if driven => Over::LastTurn,
            None => Over::Run,
            Some(item) => {
                let (o, span) = mt.string("over", item)?;
                match o.as_str() {
                    "run" => Over::Run,
                    "last_turn" if driven => Over::LastTurn,
                    "last_turn" => {
                        return Err(at(
                            &key,
                            &span,
                            format!(
                                "{} drives itself: no shaft turn to take; over = \"run\"",
                                M::IDENTIFIER
                            ),
                        ));
                    }
                    _ => {
                        return Err(at(
                            &key,
                            &span,
                            format!("unknown window {o:?}; valid: last_turn, run"),
                        ));
                    }
                }
            }
        };
        let unit = if matches!(stat, Stat::Any | Stat::Rises) {
            ""
        } else {
            table[i].unit.unwrap_or("")
        };
        metrics.push(Metric {
            name,
            unit,
            measure: Measure::Output {
                output: i as u32,
                stat,
                over,
            },
        });
    }
    Ok(Plan {
        text: text.to_string(),
        scene: scene_text.map(str::to_string),
        model: M::IDENTIFIER,
        fidelity,
        fixed,
        swept,
        design,
        speed,
        length,
        step,
        metrics,
        runner: super::Runner(std::sync::Arc::new(super::run::run::<M>)),
    })
}
