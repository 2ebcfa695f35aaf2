//! Scenes (`scenes.md`): one simulation set-up in a small TOML file, and the FMU tailored to it.
//!
//! [`Scene::parse`] reads the file and refuses what is malformed, naming the key, its line and
//! the valid choices. [`tailor`] holds a scene against one mechanism's declarations: which
//! outputs it keeps (the scene's), which parameters (those that feed a computation stage the
//! outputs need, [`crate::model::Var::feeds`]), which inputs (those the kept outputs depend on;
//! none of the shaft's with a `constant_speed` drive), which stages run
//! ([`crate::model::Var::needs`], [`crate::model::Model::STAGES`]), the start values and the
//! model description with its GUID. The CLI exports the FMU with it; the FMU's binary (the
//! mechanism's own) runs the same code on `resources/scene.toml` at `fmi2Instantiate`, so both
//! agree on the variables and the GUID without a second source of truth.

use crate::md::{self, ModelInfo};
use crate::model::shaft::{self, Fidelity};
use crate::model::{
    Causality, Experiment, Model, Stage, Stages, Values, Var, VarSet, VarType, check_bounds,
};
use std::fmt;
use std::ops::Range;
use toml::de::{DeTable, DeValue};

/// The file name of a scene inside an FMU's `resources/`.
pub const RESOURCE_NAME: &str = "scene.toml";

/// The fidelity levels by their scene names (the items of `model.fidelity`).
pub const FIDELITIES: &[(&str, Fidelity)] = &[
    ("kinematic", Fidelity::Kinematic),
    ("kinetostatic", Fidelity::Kinetostatic),
    ("elastodynamic", Fidelity::Elastodynamic),
];

/// The name of a fidelity level in a scene.
pub fn fidelity_name(f: Fidelity) -> &'static str {
    FIDELITIES
        .iter()
        .find(|(_, x)| *x == f)
        .map(|(n, _)| *n)
        .unwrap_or("?")
}

/// A scene refused: which key, where, and why (with the valid choices).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// The offending key, e.g. `outputs[2]` or `parameters."crank.r"`; empty for the file.
    pub key: String,
    /// 1-based line of the key in the file, if known.
    pub line: Option<usize>,
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.line, self.key.is_empty()) {
            (Some(l), false) => write!(f, "line {l}: `{}`: {}", self.key, self.message),
            (Some(l), true) => write!(f, "line {l}: {}", self.message),
            (None, false) => write!(f, "`{}`: {}", self.key, self.message),
            (None, true) => write!(f, "{}", self.message),
        }
    }
}

impl std::error::Error for SceneError {}

/// A parameter value as written in the scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Bool(bool),
    Int(i64),
    Float(f64),
    Text(String),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Bool(b) => write!(f, "{b}"),
            Value::Int(i) => write!(f, "{i}"),
            Value::Float(x) => write!(f, "{x:?}"),
            Value::Text(s) => write!(f, "{s:?}"),
        }
    }
}

/// The keys of a scene file, of its `[experiment]` and of its `[drive]`.
pub const KEYS: &[&str] = &[
    "name",
    "mechanism",
    "fidelity",
    "outputs",
    "parameters",
    "experiment",
    "drive",
];
const EXPERIMENT_KEYS: &[&str] = &["start", "stop", "step", "tolerance"];
const DRIVE_KEYS: &[&str] = &["mode", "n", "phi0"];

/// A TOML table of the file, read key by key (toml's parser, without serde: the FMU's binary
/// parses the scene too, and serde's generated readers would add to its size what this does not).
struct Table<'a, 'i> {
    text: &'a str,
    /// `""` for the file, `"experiment."` for `[experiment]`, ...
    prefix: &'static str,
    table: &'a DeTable<'i>,
    /// Where the table is (for a missing key).
    span: Range<usize>,
}

type Item<'a, 'i> = (&'a DeValue<'i>, Range<usize>);

fn type_name(v: &DeValue) -> &'static str {
    match v {
        DeValue::String(_) => "a string",
        DeValue::Integer(_) => "an integer",
        DeValue::Float(_) => "a float",
        DeValue::Boolean(_) => "a boolean",
        DeValue::Datetime(_) => "a date-time",
        DeValue::Array(_) => "an array",
        DeValue::Table(_) => "a table",
    }
}

impl<'a, 'i> Table<'a, 'i> {
    fn error(&self, key: &str, span: Range<usize>, message: String) -> SceneError {
        SceneError {
            key: format!("{}{key}", self.prefix),
            line: Some(line_of(self.text, span.start)),
            message,
        }
    }

    /// Refuses a key not in `valid`, naming the valid ones.
    fn only(&self, valid: &[&str]) -> Result<(), SceneError> {
        for (k, _) in self.table.iter() {
            if !valid.contains(&k.get_ref().as_ref()) {
                return Err(self.error(
                    k.get_ref(),
                    k.span(),
                    format!("unknown key; valid: {}", valid.join(", ")),
                ));
            }
        }
        Ok(())
    }

    fn get(&self, key: &str) -> Option<Item<'a, 'i>> {
        self.table
            .iter()
            .find(|(k, _)| k.get_ref() == key)
            .map(|(_, v)| (v.get_ref(), v.span()))
    }

    fn require(&self, key: &str, what: &str) -> Result<Item<'a, 'i>, SceneError> {
        self.get(key).ok_or_else(|| {
            self.error(
                key,
                self.span.clone(),
                format!("missing: the scene needs `{key}` ({what})"),
            )
        })
    }

    fn wrong(&self, key: &str, (v, span): Item, want: &str) -> SceneError {
        self.error(key, span, format!("must be {want}, not {}", type_name(v)))
    }

    fn string(&self, key: &str, item: Item<'a, 'i>) -> Result<(String, Range<usize>), SceneError> {
        match item.0 {
            DeValue::String(s) => Ok((s.to_string(), item.1)),
            _ => Err(self.wrong(key, item, "a string")),
        }
    }

    fn number(&self, key: &str, item: Item<'a, 'i>) -> Result<(f64, Range<usize>), SceneError> {
        match number(item.0) {
            Some(x) => Ok((x, item.1)),
            None => Err(self.wrong(key, item, "a number")),
        }
    }

    fn table(&self, key: &str, prefix: &'static str) -> Result<Option<Table<'a, 'i>>, SceneError> {
        match self.get(key) {
            None => Ok(None),
            Some((DeValue::Table(t), span)) => Ok(Some(Table {
                text: self.text,
                prefix,
                table: t,
                span,
            })),
            Some(item) => Err(self.wrong(key, item, "a table")),
        }
    }
}

/// A TOML number as `f64` (an integer too).
fn number(v: &DeValue) -> Option<f64> {
    match v {
        DeValue::Float(f) => {
            let x: f64 = f.as_str().parse().ok()?;
            (x.is_finite() || f.as_str().contains("inf") || x.is_nan()).then_some(x)
        }
        DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix())
            .ok()
            .map(|i| i as f64),
        _ => None,
    }
}

/// A scene parameter's value.
fn value(v: &DeValue) -> Option<Value> {
    match v {
        DeValue::Boolean(b) => Some(Value::Bool(*b)),
        DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix())
            .ok()
            .map(Value::Int),
        DeValue::Float(_) => number(v).map(Value::Float),
        DeValue::String(s) => Some(Value::Text(s.to_string())),
        _ => None,
    }
}

/// The scene's drive (`[drive]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Drive {
    /// Driven through the shaft inputs (no `[drive]`, or `mode = "input"`), mounted at the
    /// phase `phi0` rad on the shaft when given (`drive.phi0` is added to `shaft.phi`).
    Input { phi0: Option<f64> },
    /// Runs alone at `n` rpm from the shaft angle `phi0` rad.
    ConstantSpeed { rpm: f64, phi0: f64 },
}

/// A parsed scene, with where each item was written (for messages naming a line).
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The whole file, as read.
    pub text: String,
    pub name: String,
    pub mechanism: String,
    /// The level of a mechanism; `None` for a model without levels (the drive MainShaft).
    pub fidelity: Option<Fidelity>,
    /// Output names and their byte spans.
    pub outputs: Vec<(String, Range<usize>)>,
    /// Parameter names, values and the spans of the key.
    pub parameters: Vec<(String, Value, Range<usize>)>,
    pub experiment: Option<Experiment>,
    pub drive: Drive,
    spans: Spans,
}

#[derive(Clone, Debug, PartialEq, Default)]
struct Spans {
    name: Range<usize>,
    mechanism: Range<usize>,
    fidelity: Range<usize>,
    outputs: Range<usize>,
    drive: Range<usize>,
}

/// 1-based line of a byte offset.
fn line_of(text: &str, at: usize) -> usize {
    text.as_bytes()[..at.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// Levenshtein distance (for "did you mean").
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, &cb) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(ca != cb))
                .min(prev[j + 1] + 1)
                .min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

/// "did you mean a, b, c?" (the nearest names), or every valid name when there are few.
pub fn nearest(word: &str, valid: &[&str]) -> String {
    if valid.len() <= 8 {
        return format!("valid: {}", valid.join(", "));
    }
    let mut ranked: Vec<(usize, &str)> = valid.iter().map(|v| (distance(word, v), *v)).collect();
    ranked.sort();
    let near: Vec<&str> = ranked.iter().take(5).map(|r| r.1).collect();
    format!(
        "nearest of the {} valid names: {}",
        valid.len(),
        near.join(", ")
    )
}

impl Scene {
    /// An error at a byte span of this scene's file.
    fn error_at(&self, key: impl Into<String>, span: &Range<usize>, message: String) -> SceneError {
        SceneError {
            key: key.into(),
            line: Some(line_of(&self.text, span.start)),
            message,
        }
    }

    /// Reads a scene file; refuses bad syntax, unknown keys, wrong types and bad values of the
    /// mechanism-independent keys.
    pub fn parse(text: &str) -> Result<Scene, SceneError> {
        let doc = DeTable::parse(text).map_err(|e| SceneError {
            key: String::new(),
            line: e.span().map(|s| line_of(text, s.start)),
            message: e.message().trim().to_string(),
        })?;
        let root = Table {
            text,
            prefix: "",
            table: doc.get_ref(),
            span: 0..0,
        };
        root.only(KEYS)?;
        let at = |key: &str, span: Range<usize>, message: String| SceneError {
            key: key.into(),
            line: Some(line_of(text, span.start)),
            message,
        };
        let (name, name_span) = root.string("name", root.require("name", "a string")?)?;
        let name_ok = !name.is_empty()
            && name.len() <= 64
            && name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
        if !name_ok {
            return Err(at(
                "name",
                name_span,
                format!(
                    "{name:?} is not a valid scene name: 1 to 64 ASCII letters, digits, '-' or '_' (it becomes the modelIdentifier suffix)"
                ),
            ));
        }
        let (mechanism, mechanism_span) =
            root.string("mechanism", root.require("mechanism", "a string")?)?;
        // required of a mechanism, refused for a drive (MainShaft): [`tailor`] knows which
        let (fidelity, fidelity_span) = match root.get("fidelity") {
            None => (None, 0..0),
            Some(item) => {
                let (fid, span) = root.string("fidelity", item)?;
                let f = FIDELITIES
                    .iter()
                    .find(|(n, _)| *n == fid.as_str())
                    .map(|(_, f)| *f)
                    .ok_or_else(|| {
                        at(
                            "fidelity",
                            span.clone(),
                            format!(
                                "unknown fidelity {fid:?}; valid: {}",
                                FIDELITIES
                                    .iter()
                                    .map(|f| f.0)
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            ),
                        )
                    })?;
                (Some(f), span)
            }
        };
        let outputs_item = root.require("outputs", "an array of output names")?;
        let outputs_span = outputs_item.1.clone();
        let DeValue::Array(list) = outputs_item.0 else {
            return Err(root.wrong("outputs", outputs_item, "an array of output names"));
        };
        let mut outputs: Vec<(String, Range<usize>)> = Vec::new();
        for (i, o) in list.iter().enumerate() {
            let key = format!("outputs[{i}]");
            let (DeValue::String(name), span) = (o.get_ref(), o.span()) else {
                return Err(root.wrong(&key, (o.get_ref(), o.span()), "a string"));
            };
            if outputs.iter().any(|(p, _)| p == name.as_ref()) {
                return Err(at(&key, span, format!("{name:?} is listed twice")));
            }
            outputs.push((name.to_string(), span));
        }
        if outputs.is_empty() {
            return Err(at(
                "outputs",
                outputs_span.clone(),
                "is empty: a scene asks for at least one output".into(),
            ));
        }
        let mut parameters = Vec::new();
        if let Some(p) = root.table("parameters", "parameters.")? {
            for (k, v) in p.table.iter() {
                let key = format!("parameters.{:?}", k.get_ref());
                let x = value(v.get_ref()).ok_or_else(|| {
                    at(
                        &key,
                        k.span(),
                        format!(
                            "must be a number, a boolean or a string, not {}",
                            type_name(v.get_ref())
                        ),
                    )
                })?;
                parameters.push((k.get_ref().to_string(), x, k.span()));
            }
        }
        let experiment = match root.table("experiment", "experiment.")? {
            None => None,
            Some(e) => {
                e.only(EXPERIMENT_KEYS)?;
                let opt = |key: &str| e.get(key).map(|item| e.number(key, item)).transpose();
                let start = opt("start")?;
                let (stop, stop_span) = e.number("stop", e.require("stop", "a time in s")?)?;
                let (step, step_span) = e.number("step", e.require("step", "a time in s")?)?;
                let tolerance = opt("tolerance")?;
                if let Some((x, s)) = &start
                    && !x.is_finite()
                {
                    return Err(at("experiment.start", s.clone(), "must be finite".into()));
                }
                let t0 = start.as_ref().map(|s| s.0).unwrap_or(0.0);
                if !(stop.is_finite() && stop > t0) {
                    return Err(at(
                        "experiment.stop",
                        stop_span,
                        format!("= {stop} must be finite and after experiment.start = {t0}"),
                    ));
                }
                if !(step.is_finite() && step > 0.0 && step <= stop - t0) {
                    return Err(at(
                        "experiment.step",
                        step_span,
                        format!("= {step} must be > 0 and at most stop - start"),
                    ));
                }
                if let Some((x, s)) = &tolerance
                    && !(x.is_finite() && *x > 0.0)
                {
                    return Err(at("experiment.tolerance", s.clone(), "must be > 0".into()));
                }
                Some(Experiment {
                    start: t0,
                    stop,
                    step,
                    tolerance: tolerance.map(|t| t.0),
                })
            }
        };
        let mut drive_span = 0..0;
        let drive = match root.table("drive", "drive.")? {
            None => Drive::Input { phi0: None },
            Some(d) => {
                drive_span = d.span.clone();
                d.only(DRIVE_KEYS)?;
                let (mode, mode_span) =
                    d.string("mode", d.require("mode", "input or constant_speed")?)?;
                let n = d.get("n").map(|item| d.number("n", item)).transpose()?;
                let phi0 = d
                    .get("phi0")
                    .map(|item| d.number("phi0", item))
                    .transpose()?;
                let finite = |phi0: Option<(f64, Range<usize>)>| match phi0 {
                    Some((x, s)) if !x.is_finite() => {
                        Err(at("drive.phi0", s, "must be finite (rad)".into()))
                    }
                    p => Ok(p.map(|p| p.0)),
                };
                match mode.as_str() {
                    "input" => {
                        if let Some((_, s)) = n {
                            return Err(at(
                                "drive.n",
                                s,
                                "applies to mode = \"constant_speed\" only".into(),
                            ));
                        }
                        Drive::Input {
                            phi0: finite(phi0)?,
                        }
                    }
                    "constant_speed" => {
                        let (rpm, n_span) = n.ok_or_else(|| {
                            at(
                                "drive.n",
                                mode_span.clone(),
                                "mode = \"constant_speed\" needs the speed n (rpm)".into(),
                            )
                        })?;
                        // drive.n is bounded to +-1e4 rad/s
                        if !(rpm.is_finite() && (rpm * std::f64::consts::PI / 30.0).abs() <= 1e4) {
                            return Err(at(
                                "drive.n",
                                n_span,
                                format!(
                                    "= {rpm} rpm must be finite and within +-95493 rpm (1e4 rad/s)"
                                ),
                            ));
                        }
                        Drive::ConstantSpeed {
                            rpm,
                            phi0: finite(phi0)?.unwrap_or(0.0),
                        }
                    }
                    other => {
                        return Err(at(
                            "drive.mode",
                            mode_span,
                            format!("unknown drive mode {other:?}; valid: input, constant_speed"),
                        ));
                    }
                }
            }
        };
        Ok(Scene {
            text: text.to_string(),
            name,
            mechanism,
            fidelity,
            outputs,
            parameters,
            experiment,
            drive,
            spans: Spans {
                name: name_span,
                mechanism: mechanism_span,
                fidelity: fidelity_span,
                outputs: outputs_span,
                drive: drive_span,
            },
        })
    }

    /// The error for a mechanism name none of `known` has.
    pub fn unknown_mechanism(&self, known: &[&str]) -> SceneError {
        self.error_at(
            "mechanism",
            &self.spans.mechanism,
            format!(
                "unknown mechanism {:?}; valid: {}",
                self.mechanism,
                known.join(", ")
            ),
        )
    }
}

/// The FMU tailored to a scene, for one mechanism.
#[derive(Clone, Debug)]
pub struct Tailored {
    pub scene: Scene,
    /// `modelIdentifier`: mechanism + the scene name's suffix.
    pub identifier: String,
    pub info: ModelInfo,
    /// Every variable of the mechanism, by value reference: exposed in this FMU?
    pub exposed: Vec<bool>,
    /// Start values of every variable (the scene's parameters, drive and fidelity applied).
    pub start: Vec<f64>,
    /// Start values of the exposed variables as written in the description.
    pub variables: Vec<(u32, Var)>,
    /// The stages that run.
    pub stages: Stages,
    /// The GUID of its model description ([`Tailored::model_description`]).
    pub guid: String,
}

impl Tailored {
    /// The variables the FMU lists, by value reference.
    pub fn refs(&self) -> Vec<(u32, &Var)> {
        self.variables.iter().map(|(vr, v)| (*vr, v)).collect()
    }

    /// Its model description (with [`Tailored::guid`]).
    #[cfg(feature = "tools")]
    pub fn model_description(&self) -> String {
        md::describe_vars(&self.info, &self.refs()).0
    }
}

/// `modelIdentifier` of a scene's FMU: the mechanism's, `_`, the scene name with `-` as `_`
/// (a C identifier: the binary is `binaries/linux64/<it>.so`).
pub fn identifier(mechanism: &str, scene_name: &str) -> String {
    format!("{mechanism}_{}", scene_name.replace('-', "_"))
}

/// Every stage `s` needs, with the stages they require, closed.
pub fn closure(stages: &[Stage], s: Stages) -> Stages {
    let mut out = s;
    loop {
        let mut next = out;
        for i in out.indices(stages.len()) {
            next = next.or(stages[i].requires);
        }
        if next == out {
            return out;
        }
        out = next;
    }
}

/// The fidelity levels at which every stage of `needs` is computed.
pub fn levels_of(stages: &[Stage], needs: Stages) -> Vec<Fidelity> {
    let needs = closure(stages, needs);
    FIDELITIES
        .iter()
        .map(|f| f.1)
        .filter(|f| {
            needs
                .indices(stages.len())
                .all(|i| stages[i].levels.contains(f))
        })
        .collect()
}

/// The stages that run at `fidelity` whatever the outputs ([`Stage::always`]).
fn always(stages: &[Stage], fidelity: Fidelity) -> Stages {
    stages
        .iter()
        .enumerate()
        .filter(|(_, s)| s.always && s.levels.contains(&fidelity))
        .fold(Stages::NONE, |acc, (i, _)| acc.or(Stages::bit(i as u32)))
}

/// Is this parameter set by the scene's own keys (`fidelity`, `[drive]`) rather than
/// `[parameters]`?
fn structural(vr: u32) -> bool {
    matches!(vr, shaft::MODE | shaft::N | shaft::PHI0 | shaft::FIDELITY)
}

/// The scene's value for a parameter declaration, type-checked.
fn value_of(v: &Var, x: &Value) -> Result<f64, String> {
    match (v.ty, x) {
        (VarType::Real, Value::Float(f)) => Ok(*f),
        (VarType::Real, Value::Int(i)) => Ok(*i as f64),
        (VarType::Integer, Value::Int(i)) => i32::try_from(*i)
            .map(f64::from)
            .map_err(|_| format!("{i} does not fit a 32-bit Integer")),
        (VarType::Boolean, Value::Bool(b)) => Ok(f64::from(u8::from(*b))),
        (VarType::Enumeration(t), Value::Text(s)) => t
            .items
            .iter()
            .position(|it| it.0 == s.as_str())
            .map(|p| (p + 1) as f64)
            .ok_or_else(|| {
                format!(
                    "{s:?} is not an item of {}; valid: {}",
                    t.name,
                    t.items.iter().map(|i| i.0).collect::<Vec<_>>().join(", ")
                )
            }),
        (ty, x) => Err(format!(
            "{x} is not a value of type {}",
            match ty {
                VarType::Real => "Real (a number)".to_string(),
                VarType::Integer => "Integer (a whole number)".to_string(),
                VarType::Boolean => "Boolean (true or false)".to_string(),
                VarType::Enumeration(t) => format!(
                    "{} (one of {})",
                    t.name,
                    t.items.iter().map(|i| i.0).collect::<Vec<_>>().join(", ")
                ),
            }
        )),
    }
}

/// Holds a scene against mechanism `M`: refuses an output or parameter it does not have (with
/// the nearest valid names), an output its fidelity does not compute (naming the levels that
/// do), a value of the wrong type or out of bounds, and a set the mechanism cannot assemble
/// with; otherwise the tailored FMU's variables, start values, stages and description.
pub fn tailor<M: Model>(scene: &Scene) -> Result<Tailored, SceneError> {
    if scene.mechanism != M::IDENTIFIER {
        return Err(scene.unknown_mechanism(&[M::IDENTIFIER]));
    }
    let table = <M::Var as VarSet>::table();
    let stages = M::STAGES;
    let vr_of = |name: &str| table.iter().position(|v| v.name == name);
    // a mechanism is driven through the shaft connector and has levels; a drive (MainShaft)
    // turns the shaft itself and has neither
    let driven = shaft::is_driven::<M::Var>();
    let fid = match (driven, scene.fidelity) {
        (true, Some(f)) => Some(f),
        (true, None) => {
            return Err(SceneError {
                key: "fidelity".into(),
                line: None,
                message: format!(
                    "missing: a scene of {} needs `fidelity` (kinematic, kinetostatic or elastodynamic)",
                    M::IDENTIFIER
                ),
            });
        }
        (false, Some(_)) => {
            return Err(scene.error_at(
                "fidelity",
                &scene.spans.fidelity,
                format!(
                    "{} has no fidelity levels (it drives the shaft): leave `fidelity` out",
                    M::IDENTIFIER
                ),
            ));
        }
        (false, None) => None,
    };
    let is_structural = |vr: u32| driven && structural(vr);
    if !driven && !scene.spans.drive.is_empty() {
        return Err(scene.error_at(
            "drive",
            &scene.spans.drive,
            format!(
                "{} drives the shaft itself: a scene of it has no [drive]",
                M::IDENTIFIER
            ),
        ));
    }

    // ---- outputs: exist, are outputs (or calculated parameters), computed at this fidelity
    let output_names: Vec<&str> = table
        .iter()
        .filter(|v| {
            matches!(
                v.causality,
                Causality::Output | Causality::CalculatedParameter
            )
        })
        .map(|v| v.name)
        .collect();
    let mut wanted = vec![false; table.len()];
    for (i, (name, span)) in scene.outputs.iter().enumerate() {
        let key = format!("outputs[{i}]");
        let Some(vr) = vr_of(name) else {
            return Err(scene.error_at(
                key,
                span,
                format!(
                    "{} has no output {name:?}; {}",
                    M::IDENTIFIER,
                    nearest(name, &output_names)
                ),
            ));
        };
        let v = &table[vr];
        if !matches!(
            v.causality,
            Causality::Output | Causality::CalculatedParameter
        ) {
            return Err(scene.error_at(
                key,
                span,
                format!(
                    "{name:?} is a{} {}, not an output{}",
                    if v.causality == Causality::Input {
                        "n"
                    } else {
                        ""
                    },
                    format!("{:?}", v.causality).to_lowercase(),
                    if v.causality == Causality::Parameter {
                        " (set it under [parameters])"
                    } else {
                        ""
                    }
                ),
            ));
        }
        let levels = levels_of(stages, v.needs);
        if let Some(fid) = fid
            && !levels.contains(&fid)
        {
            let names: Vec<&str> = levels.iter().map(|f| fidelity_name(*f)).collect();
            return Err(scene.error_at(
                key,
                span,
                format!(
                    "{name:?} is not computed at fidelity {:?}; {}",
                    fidelity_name(fid),
                    if names.is_empty() {
                        "no fidelity level of this mechanism computes it".to_string()
                    } else {
                        format!("it is at: {}", names.join(", "))
                    }
                ),
            ));
        }
        wanted[vr] = true;
    }

    // ---- the stages that run
    let mut needed = fid.map_or(Stages::NONE, |f| always(stages, f));
    for (vr, v) in table.iter().enumerate() {
        if wanted[vr] {
            needed = needed.or(v.needs);
        }
    }
    let needed = closure(stages, needed);
    // the checks that guard the user stay wherever what they check is computed
    let guards = stages
        .iter()
        .enumerate()
        .filter(|(_, s)| {
            s.guards && fid.is_some_and(|f| s.levels.contains(&f)) && needed.contains(s.requires)
        })
        .fold(Stages::NONE, |acc, (i, _)| acc.or(Stages::bit(i as u32)));
    let needed = closure(stages, needed.or(guards));
    // states and derivatives of the level (Model Exchange) come with the stages they belong to
    let locals: Vec<bool> = table
        .iter()
        .map(|v| {
            v.causality == Causality::Local && v.needs != Stages::NONE && needed.contains(v.needs)
        })
        .collect();

    // ---- start values: the scene's parameters, type- and bound-checked
    let mut values = Values::<M::Var>::start();
    let param_names: Vec<&str> = table
        .iter()
        .enumerate()
        .filter(|(vr, v)| v.causality == Causality::Parameter && !is_structural(*vr as u32))
        .map(|(_, v)| v.name)
        .collect();
    for (name, x, span) in &scene.parameters {
        let key = format!("parameters.{name:?}");
        let Some(vr) = vr_of(name) else {
            return Err(scene.error_at(
                key,
                span,
                format!(
                    "{} has no parameter {name:?}; {}",
                    M::IDENTIFIER,
                    nearest(name, &param_names)
                ),
            ));
        };
        let v = &table[vr];
        if v.causality != Causality::Parameter {
            return Err(scene.error_at(
                key,
                span,
                format!(
                    "{name:?} is not a parameter but a{} {:?} variable{}",
                    if v.causality == Causality::Input {
                        "n"
                    } else {
                        ""
                    },
                    v.causality,
                    if v.causality == Causality::Output {
                        " (list it under outputs)"
                    } else {
                        ""
                    }
                ),
            ));
        }
        if is_structural(vr as u32) {
            return Err(scene.error_at(
                key,
                span,
                format!(
                    "{name:?} is set by the scene's {} key, not under [parameters]",
                    if vr as u32 == shaft::FIDELITY {
                        "`fidelity`"
                    } else {
                        "[drive]"
                    }
                ),
            ));
        }
        let x = value_of(v, x).map_err(|m| scene.error_at(key.clone(), span, m))?;
        values.raw_mut()[vr] = x;
    }
    // the drive's phase: a parameter of the FMU when the scene sets it
    let phi0 = match scene.drive {
        Drive::Input { phi0 } => phi0,
        Drive::ConstantSpeed { phi0, .. } => Some(phi0),
    };
    if let Some(fid) = fid {
        let raw = values.raw_mut();
        raw[shaft::FIDELITY as usize] = fid as i32 as f64;
        if let Drive::ConstantSpeed { rpm, .. } = scene.drive {
            raw[shaft::MODE as usize] = 2.0;
            raw[shaft::N as usize] = std::f64::consts::PI * (rpm / 30.0);
        } else {
            raw[shaft::MODE as usize] = 1.0;
        }
        if let Some(phi0) = phi0 {
            raw[shaft::PHI0 as usize] = phi0;
        }
    }
    values.stages = needed;
    let param_error = |e: crate::model::ParamError| {
        let (key, span) = if e.param == "model.fidelity" {
            ("fidelity".to_string(), scene.spans.fidelity.clone())
        } else if let Some((n, _, s)) =
            scene
                .parameters
                .iter()
                .find(|p| p.0 == e.param)
                .or_else(|| {
                    // the mechanism blames one of its parameters for a condition that names the
                    // scene's (a rod shorter than the crank radius the scene set)
                    scene
                        .parameters
                        .iter()
                        .find(|p| e.condition.contains(p.0.as_str()))
                })
        {
            (format!("parameters.{n:?}"), s.clone())
        } else if e.param.starts_with("drive.") {
            ("drive".to_string(), scene.spans.drive.clone())
        } else {
            // a default the scene did not touch, refused with the scene's other values
            return SceneError {
                key: format!("parameters.{:?}", e.param),
                line: None,
                message: format!("refused by {} with this scene's values: {e}", M::IDENTIFIER),
            };
        };
        scene.error_at(key, &span, format!("refused by {}: {e}", M::IDENTIFIER))
    };
    check_bounds(&values).map_err(param_error)?;
    M::prepare(&values).map_err(param_error)?;

    // ---- which variables the FMU lists
    let constant_speed = matches!(scene.drive, Drive::ConstantSpeed { .. });
    let mut used_inputs = vec![false; table.len()];
    for (vr, v) in table.iter().enumerate() {
        if wanted[vr] {
            for &d in v.depends {
                used_inputs[d as usize] = true;
            }
        }
    }
    if <M::Var as VarSet>::SHAFT_CONNECTOR
        && (fid == Some(Fidelity::Elastodynamic)
            || [shaft::PHI, shaft::W, shaft::A]
                .iter()
                .any(|&i| used_inputs[i as usize]))
    {
        // a step moves the shaft from all three inputs (Model::step, at every level; the ODE
        // of the elastodynamic level on that path): an output of the angle alone at an instant
        // is, after the step, one of the angle, speed and acceleration at the step's start
        for i in [shaft::PHI, shaft::W, shaft::A] {
            used_inputs[i as usize] = true;
        }
    }
    let exposed: Vec<bool> = table
        .iter()
        .enumerate()
        .map(|(vr, v)| {
            let r = vr as u32;
            match v.causality {
                Causality::Output | Causality::CalculatedParameter => wanted[vr],
                Causality::Local => locals[vr],
                Causality::Input => {
                    used_inputs[vr]
                        && !(constant_speed && matches!(r, shaft::PHI | shaft::W | shaft::A))
                }
                Causality::Parameter => {
                    if is_structural(r) {
                        (constant_speed && r == shaft::N) || (phi0.is_some() && r == shaft::PHI0)
                    } else {
                        v.feeds == Stages::ALL || v.feeds.intersects(needed)
                    }
                }
            }
        })
        .collect();
    let start = values.raw().to_vec();
    let variables: Vec<(u32, Var)> = table
        .iter()
        .enumerate()
        .filter(|(vr, _)| exposed[*vr])
        .map(|(vr, v)| {
            let mut v = v.clone();
            if v.start.is_some() {
                v.start = Some(start[vr]);
            }
            (vr as u32, v)
        })
        .collect();
    let identifier = identifier(M::IDENTIFIER, &scene.name);
    let leak = |s: String| -> &'static str { crate::lifetime::keep(s).as_str() };
    let info = ModelInfo {
        identifier: leak(identifier.clone()),
        model_name: leak(identifier.clone()),
        description: leak(format!(
            "{} Tailored to the scene {:?}{}: only its outputs, the parameters and inputs they use.",
            M::DESCRIPTION,
            scene.name,
            fid.map_or(String::new(), |f| format!(" ({} level)", fidelity_name(f)))
        )),
        experiment: scene.experiment.unwrap_or(M::EXPERIMENT),
        event_indicators: M::EVENT_INDICATORS as u32,
        // input derivatives shape the shaft's path over a step at every level, and need the
        // shaft angle as an input (not with a constant-speed drive)
        can_interpolate_inputs: M::CAN_INTERPOLATE_INPUTS && exposed[shaft::PHI as usize],
    };
    let refs: Vec<(u32, &Var)> = variables.iter().map(|(vr, v)| (*vr, v)).collect();
    let guid = md::guid::guid(&info, &refs);
    Ok(Tailored {
        scene: scene.clone(),
        identifier,
        info,
        exposed,
        start,
        variables,
        stages: needed,
        guid,
    })
}

/// [`tailor`] from the text of a scene file.
pub fn tailor_text<M: Model>(text: &str) -> Result<Tailored, SceneError> {
    tailor::<M>(&Scene::parse(text)?)
}

/// The tailored FMU of the scene text, computed once per text and model type (an FMU's binary
/// reads `resources/scene.toml` at every `fmi2Instantiate`; describing takes milliseconds).
pub fn cached<M: Model>(text: &str) -> Result<std::sync::Arc<Tailored>, SceneError> {
    use std::sync::{Arc, Mutex};
    type Cache = Vec<(std::any::TypeId, u128, Arc<Tailored>)>;
    static CACHE: Mutex<Cache> = Mutex::new(Vec::new());
    let id = std::any::TypeId::of::<M>();
    let h = md::fnv1a_128(text.as_bytes());
    if let Some(t) = CACHE
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .iter()
        .find(|c| c.0 == id && c.1 == h)
    {
        return Ok(t.2.clone());
    }
    let t = Arc::new(tailor_text::<M>(text)?);
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if cache.is_empty() {
        crate::lifetime::on_release(|| {
            *CACHE.lock().unwrap_or_else(|e| e.into_inner()) = Vec::new();
        });
    }
    if cache.len() < 64 {
        cache.push((id, h, t.clone()));
    }
    Ok(t)
}

#[cfg(test)]
mod tests;
