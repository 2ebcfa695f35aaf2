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

use super::sample::{Axis, Design, Dist, Method};
use super::{Row, Runner};
use crate::model::shaft::{self, Fidelity};
use crate::model::{Causality, Model, Values, Var, VarSet, check_bounds};
use crate::scene::{
    FIDELITIES, Item, Scene, SceneError, Table, fidelity_name, levels_of, line_of, nearest, number,
    value, value_of,
};
use std::ops::Range;
use toml::de::{DeTable, DeValue};

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
const SAMPLING_KEYS: &[&str] = &["method", "samples", "seed"];
const EXPERIMENT_KEYS: &[&str] = &["speed", "turns", "stop", "steps_per_turn", "step"];
const METRIC_KEYS: &[&str] = &["output", "stat", "over"];
/// The name of the shaft speed among the swept parameters (rpm).
pub const SPEED: &str = "speed";
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
    /// ([`super::machine`]).
    Machine {
        quantity: super::machine::Quantity,
        turns: f64,
    },
}

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
    /// The model's runner.
    pub runner: Runner,
    /// A sweep of a whole machine: its components, what the parameters set ([`super::machine`]).
    pub machine: Option<super::machine::MachineRun>,
}

impl Plan {
    /// Number of runs.
    pub fn runs(&self) -> usize {
        self.design.runs()
    }

    /// Run `k` on this process.
    pub fn run(&self, k: usize) -> Row {
        (self.runner)(self, k)
    }

    /// The columns of a row: the swept parameters', then the metrics'.
    pub fn columns(&self) -> Vec<String> {
        (self.swept.iter().map(|s| s.name.clone()))
            .chain(self.metrics.iter().map(|m| m.name.clone()))
            .collect()
    }
}

/// The model a sweep file names (`model`, or the `mechanism` of its `scene`) and the path of
/// its scene file, read before the file is checked against the model.
pub fn model_of(text: &str) -> Result<(Option<String>, Option<String>), SceneError> {
    match target_of(text)? {
        Target::Model(m) => Ok((Some(m), None)),
        Target::Scene(s) => Ok((None, Some(s))),
        Target::Machine(m) => Err(SceneError {
            key: "machine".into(),
            line: None,
            message: format!("{m:?} is a machine, not a model"),
        }),
    }
}

/// What a sweep runs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Target {
    /// A model of the catalog, by identifier.
    Model(String),
    /// A scene file, by its path relative to the sweep file.
    Scene(String),
    /// A machine ([`crate::ssp::machines`]), by name.
    Machine(String),
}

/// Which of `model`, `scene` or `machine` a sweep file names (exactly one).
pub fn target_of(text: &str) -> Result<Target, SceneError> {
    let doc = parse_toml(text)?;
    let root = root(text, doc.get_ref());
    let mut found = Vec::new();
    for key in ["model", "scene", "machine"] {
        if let Some(item) = root.get(key) {
            let (v, span) = root.string(key, item)?;
            found.push((key, v, span));
        }
    }
    match found.len() {
        0 => Err(root.error(
            "model",
            0..0,
            "missing: the file needs `model` (a model identifier), `scene` (a scene file) or `machine` (a machine's name)"
                .into(),
        )),
        1 => {
            let (key, v, _) = found.remove(0);
            Ok(match key {
                "model" => Target::Model(v),
                "scene" => Target::Scene(v),
                _ => Target::Machine(v),
            })
        }
        _ => Err(root.error(
            found[1].0,
            found[1].2.clone(),
            format!(
                "give one of `model`, `scene` or `machine`, not `{}` and `{}`: a scene names its model, a machine its components",
                found[0].0, found[1].0
            ),
        )),
    }
}

pub(super) fn parse_toml(text: &str) -> Result<toml::Spanned<DeTable<'_>>, SceneError> {
    DeTable::parse(text).map_err(|e| SceneError {
        key: String::new(),
        line: e.span().map(|s| line_of(text, s.start)),
        message: e.message().trim().to_string(),
    })
}

pub(super) fn root<'a, 'i>(text: &'a str, table: &'a DeTable<'i>) -> Table<'a, 'i> {
    Table {
        text,
        prefix: "",
        table,
        span: 0..0,
    }
}

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
        let names: Vec<&str> = FIDELITIES.iter().map(|f| f.0).collect();
        fidelity = Some(
            FIDELITIES
                .iter()
                .find(|x| x.0 == f)
                .map(|x| x.1)
                .ok_or_else(|| {
                    at(
                        "fidelity",
                        &span,
                        format!("unknown level {f:?}; valid: {}", names.join(", ")),
                    )
                })?,
        );
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
        for (k, v) in in_file_order(t.table) {
            let key = format!("fixed.{:?}", k.get_ref());
            let name = k.get_ref().as_ref();
            let vr = param(&key, name, &k.span())?;
            let x = value(v.get_ref())
                .ok_or_else(|| {
                    t.wrong(
                        name,
                        (v.get_ref(), v.span()),
                        "a number, a boolean or an item name",
                    )
                })
                .and_then(|x| {
                    value_of(&table[vr as usize], &x).map_err(|e| at(&key, &v.span(), e))
                })?;
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
        for (k, v) in in_file_order(t.table) {
            let name = k.get_ref().to_string();
            let key = format!("swept.{name:?}");
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
    let m = root
        .table("metrics", "metrics.")?
        .ok_or_else(|| at("metrics", &(0..0), "missing: the file needs [metrics], e.g. F_max = { output = \"rod.F\", stat = \"max\" }".into()))?;
    let mut metrics = Vec::new();
    let outputs: Vec<&str> = (table.iter())
        .filter(|v| matches!(v.causality, Causality::Output | Causality::Local))
        .map(|v| v.name)
        .collect();
    for (k, v) in in_file_order(m.table) {
        let name = k.get_ref().to_string();
        let key = format!("metrics.{name:?}");
        if swept.iter().any(|s| s.name == name)
            || ["run", "warnings", "warning", "error"].contains(&name.as_str())
        {
            return Err(at(
                &key,
                &k.span(),
                format!("{name:?} is already a column of the results"),
            ));
        }
        let DeValue::Table(mt) = v.get_ref() else {
            return Err(at(
                &key,
                &v.span(),
                "must be a table: { output = \"...\", stat = \"max\" }".into(),
            ));
        };
        let mt = Table {
            text,
            prefix: "metrics.",
            table: mt,
            span: v.span(),
        };
        mt.only(METRIC_KEYS).map_err(|e| SceneError {
            key: format!("{key}.{}", e.key.trim_start_matches("metrics.")),
            ..e
        })?;
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
        let stat = STATS
            .iter()
            .find(|s| s.0 == stat)
            .map(|s| s.1)
            .ok_or_else(|| {
                at(
                    &key,
                    &span,
                    format!(
                        "unknown stat {stat:?}; valid: {}",
                        STATS.iter().map(|s| s.0).collect::<Vec<_>>().join(", ")
                    ),
                )
            })?;
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
    if metrics.is_empty() {
        return Err(at(
            "metrics",
            &m.span,
            "is empty: a sweep asks for at least one metric".into(),
        ));
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
        runner: super::run::run::<M>,
        machine: None,
    })
}

pub(super) type Entry<'a, 'i> = (
    &'a toml::Spanned<toml::de::DeString<'i>>,
    &'a toml::Spanned<DeValue<'i>>,
);

/// A table's entries in the order the file writes them (the parser's table is sorted by key):
/// the swept parameters' order decides which varies fastest and the columns' order.
pub(super) fn in_file_order<'a, 'i>(t: &'a DeTable<'i>) -> Vec<Entry<'a, 'i>> {
    let mut e: Vec<Entry> = t.iter().collect();
    e.sort_by_key(|(k, _)| k.span().start);
    e
}

/// The design of a sweep file: its swept axes and its `[sampling]`, checked (a random axis needs
/// samples, a deterministic design refuses them; at most [`MAX_RUNS`] runs).
pub(super) fn design_of(root: &Table, axes: Vec<Axis>) -> Result<Design, SceneError> {
    let at = |key: &str, span: &Range<usize>, message: String| SceneError {
        key: key.into(),
        line: Some(line_of(root.text, span.start)),
        message,
    };
    let random = axes.iter().any(|a| matches!(a, Axis::Random(_)));
    let (mut method, mut samples, mut seed) = (Method::MonteCarlo, 1usize, 0u64);
    match root.table("sampling", "sampling.")? {
        Some(s) => {
            s.only(SAMPLING_KEYS)?;
            if !random {
                return Err(at(
                    "sampling",
                    &s.span,
                    "no swept parameter is random (uniform, normal or tolerance): a deterministic run needs no samples".into(),
                ));
            }
            if let Some(item) = s.get("method") {
                let (m, span) = s.string("method", item)?;
                method = match m.as_str() {
                    "monte_carlo" => Method::MonteCarlo,
                    "latin_hypercube" => Method::LatinHypercube,
                    _ => {
                        return Err(s.error(
                            "method",
                            span,
                            format!("unknown method {m:?}; valid: monte_carlo, latin_hypercube"),
                        ));
                    }
                };
            }
            let item = s.require("samples", "how many draws, an integer")?;
            samples = whole(&s, "samples", item, 1, MAX_RUNS as i64)? as usize;
            if let Some(item) = s.get("seed") {
                seed = whole(&s, "seed", item, 0, i64::MAX)? as u64;
            }
        }
        None if random => {
            let span = root.get("swept").map(|i| i.1).unwrap_or(0..0);
            return Err(at(
                "sampling",
                &span,
                "missing: a random swept parameter needs [sampling] with `samples` (and `seed`, `method`)".into(),
            ));
        }
        None => {}
    }
    let design = Design {
        axes,
        method,
        samples,
        seed,
    };
    let runs = design
        .axes
        .iter()
        .try_fold(samples, |n, a| match a {
            Axis::Values(v) => n.checked_mul(v.len()),
            Axis::Random(_) => Some(n),
        })
        .filter(|&n| n <= MAX_RUNS);
    if runs.is_none() {
        let span = root.get("swept").map(|i| i.1).unwrap_or(0..0);
        return Err(at(
            "swept",
            &span,
            format!("the design has more than {MAX_RUNS} runs"),
        ));
    }

    Ok(design)
}

/// An integer in `[lo, hi]`.
pub(super) fn whole(t: &Table, key: &str, item: Item, lo: i64, hi: i64) -> Result<i64, SceneError> {
    match item.0 {
        DeValue::Integer(i) => match i64::from_str_radix(i.as_str(), i.radix()) {
            Ok(k) if (lo..=hi).contains(&k) => Ok(k),
            _ => Err(t.error(key, item.1, format!("must be an integer from {lo} to {hi}"))),
        },
        _ => Err(t.wrong(key, item, "an integer")),
    }
}

/// The axis of a swept parameter: `{ values = [...] }`, `{ from, to, points }`,
/// `{ uniform = [lo, hi] }`, `{ normal = [mean, sd] }` or `{ tolerance = t }` around the
/// nominal value (the fixed one, else the model's default), uniform or, with
/// `distribution = "normal"`, normal with t = 3 standard deviations.
pub(super) fn axis(
    t: &Table,
    key: &str,
    item: Item,
    var: Option<&Var>,
    nominal: Option<f64>,
) -> Result<Axis, SceneError> {
    let at = |span: Range<usize>, message: String| SceneError {
        key: key.into(),
        line: Some(line_of(t.text, span.start)),
        message,
    };
    let forms = "{ values = [...] }, { from = a, to = b, points = n }, { uniform = [lo, hi] }, { normal = [mean, sd] } or { tolerance = t }";
    let DeValue::Table(a) = item.0 else {
        return Err(at(item.1, format!("must be a table: {forms}")));
    };
    let a = Table {
        text: t.text,
        prefix: "",
        table: a,
        span: item.1.clone(),
    };
    let keys: Vec<String> = a
        .table
        .iter()
        .map(|(k, _)| k.get_ref().to_string())
        .collect();
    let has = |k: &str| keys.iter().any(|x| x == k);
    let pair = |k: &str| -> Result<(f64, f64), SceneError> {
        let (v, span) = a.get(k).expect("present");
        match v {
            DeValue::Array(xs) if xs.len() == 2 => {
                let x: Vec<Option<f64>> = xs.iter().map(|x| number(x.get_ref())).collect();
                match (x[0], x[1]) {
                    (Some(p), Some(q)) if p.is_finite() && q.is_finite() => Ok((p, q)),
                    _ => Err(at(span, format!("`{k}` must be two finite numbers"))),
                }
            }
            _ => Err(at(span, format!("`{k}` must be an array of two numbers"))),
        }
    };
    let only = |valid: &[&str]| {
        a.only(valid).map_err(|e| SceneError {
            key: key.into(),
            message: format!("`{}`: {}", e.key, e.message),
            ..e
        })
    };
    let f64_of = |k: &str| -> Result<f64, SceneError> {
        let item = a.get(k).expect("present");
        let (x, span) = a.number(k, item).map_err(|e| SceneError {
            key: key.into(),
            ..e
        })?;
        if !x.is_finite() {
            return Err(at(span, format!("`{k}` must be finite")));
        }
        Ok(x)
    };
    if has("values") {
        only(&["values"])?;
        let (v, span) = a.get("values").expect("present");
        let DeValue::Array(xs) = v else {
            return Err(at(span, "`values` must be an array".into()));
        };
        let mut out = Vec::new();
        for x in xs.iter() {
            let val = match var {
                None => number(x.get_ref())
                    .filter(|x| x.is_finite() && *x > 0.0)
                    .ok_or_else(|| at(x.span(), "a speed must be a number > 0 (rpm)".into()))?,
                Some(var) => {
                    let v = value(x.get_ref()).ok_or_else(|| {
                        at(
                            x.span(),
                            "must be a number, a boolean or an item name".into(),
                        )
                    })?;
                    value_of(var, &v).map_err(|e| at(x.span(), e))?
                }
            };
            out.push(val);
        }
        if out.is_empty() {
            return Err(at(span, "`values` is empty".into()));
        }
        return Ok(Axis::Values(out));
    }
    let real = |what: &str| -> Result<(), SceneError> {
        match var {
            Some(v) if v.ty != crate::model::VarType::Real => Err(at(
                item.1.clone(),
                format!(
                    "{what} needs a Real parameter; {} is not (give `values`)",
                    v.name
                ),
            )),
            _ => Ok(()),
        }
    };
    if has("from") || has("to") || has("points") {
        only(&["from", "to", "points"])?;
        real("from/to/points")?;
        for k in ["from", "to", "points"] {
            if !has(k) {
                return Err(at(
                    item.1.clone(),
                    format!("missing `{k}`: a range needs from, to and points"),
                ));
            }
        }
        let (lo, hi) = (f64_of("from")?, f64_of("to")?);
        let n = whole(
            &a,
            "points",
            a.get("points").expect("present"),
            1,
            1_000_000,
        )
        .map_err(|e| SceneError {
            key: key.into(),
            ..e
        })? as usize;
        if n == 1 && lo != hi {
            return Err(at(item.1.clone(), "one point needs from = to".into()));
        }
        let values = (0..n)
            .map(|i| {
                if n == 1 {
                    lo
                } else if i == n - 1 {
                    hi
                } else {
                    lo + (hi - lo) * i as f64 / (n - 1) as f64
                }
            })
            .collect();
        return Ok(Axis::Values(values));
    }
    real("a distribution")?;
    if has("uniform") {
        only(&["uniform"])?;
        let (lo, hi) = pair("uniform")?;
        if lo >= hi {
            return Err(at(
                item.1.clone(),
                format!("uniform = [{lo}, {hi}]: want lo < hi"),
            ));
        }
        return Ok(Axis::Random(Dist::Uniform { lo, hi }));
    }
    if has("normal") {
        only(&["normal"])?;
        let (mean, sd) = pair("normal")?;
        if sd <= 0.0 {
            return Err(at(
                item.1.clone(),
                format!("normal = [{mean}, {sd}]: want a standard deviation > 0"),
            ));
        }
        return Ok(Axis::Random(Dist::Normal { mean, sd }));
    }
    if has("tolerance") {
        only(&["tolerance", "distribution"])?;
        let t = f64_of("tolerance")?;
        if t <= 0.0 {
            return Err(at(item.1.clone(), "`tolerance` must be > 0".into()));
        }
        let n = nominal.ok_or_else(|| {
            at(
                item.1.clone(),
                "a tolerance needs a nominal value: fix the parameter in [fixed]".into(),
            )
        })?;
        let normal = match a.get("distribution") {
            None => false,
            Some(d) => match a.string("distribution", d.clone())?.0.as_str() {
                "uniform" => false,
                "normal" => true,
                other => {
                    return Err(at(
                        d.1,
                        format!(
                            "unknown distribution {other:?}; valid: uniform (n ± t), normal (t = 3 standard deviations)"
                        ),
                    ));
                }
            },
        };
        return Ok(Axis::Random(if normal {
            Dist::Normal {
                mean: n,
                sd: t / 3.0,
            }
        } else {
            Dist::Uniform {
                lo: n - t,
                hi: n + t,
            }
        }));
    }
    Err(at(item.1.clone(), format!("must be one of {forms}")))
}
