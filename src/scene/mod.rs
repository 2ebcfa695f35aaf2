//! Scenes (`scenes.md`): one simulation set-up in a small TOML file, and the FMU tailored to it.
//!
//! [`Scene::parse`] reads the file and refuses what is malformed, naming the key, its line and
//! the valid choices. [`mod@tailor`] holds a scene against one mechanism's declarations: which
//! outputs it keeps (the scene's), which parameters (those that feed a computation stage the
//! outputs need, [`crate::model::Var::feeds`]), which inputs (those the kept outputs depend on;
//! none of the shaft's with a `constant_speed` drive), which stages run
//! ([`crate::model::Var::needs`], [`crate::model::Model::STAGES`]), the start values and the
//! GUID of its model description (written by the CLI, [`Tailored::model_description`]). The CLI exports the FMU with it; the FMU's binary (the
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

mod tailor;
pub use tailor::*;

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
pub(crate) struct Table<'a, 'i> {
    pub(crate) text: &'a str,
    /// `""` for the file, `"experiment."` for `[experiment]`, ...
    pub(crate) prefix: &'static str,
    pub(crate) table: &'a DeTable<'i>,
    /// Where the table is (for a missing key).
    pub(crate) span: Range<usize>,
}

pub(crate) type Item<'a, 'i> = (&'a DeValue<'i>, Range<usize>);

pub(crate) fn type_name(v: &DeValue) -> &'static str {
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
    pub(crate) fn error(&self, key: &str, span: Range<usize>, message: String) -> SceneError {
        SceneError {
            key: format!("{}{key}", self.prefix),
            line: Some(line_of(self.text, span.start)),
            message,
        }
    }

    /// Refuses a key not in `valid`, naming the valid ones.
    pub(crate) fn only(&self, valid: &[&str]) -> Result<(), SceneError> {
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

    pub(crate) fn get(&self, key: &str) -> Option<Item<'a, 'i>> {
        self.table
            .iter()
            .find(|(k, _)| k.get_ref() == key)
            .map(|(_, v)| (v.get_ref(), v.span()))
    }

    pub(crate) fn require(&self, key: &str, what: &str) -> Result<Item<'a, 'i>, SceneError> {
        self.get(key).ok_or_else(|| {
            self.error(
                key,
                self.span.clone(),
                format!("missing: the file needs `{key}` ({what})"),
            )
        })
    }

    pub(crate) fn wrong(&self, key: &str, (v, span): Item, want: &str) -> SceneError {
        self.error(key, span, format!("must be {want}, not {}", type_name(v)))
    }

    pub(crate) fn string(
        &self,
        key: &str,
        item: Item<'a, 'i>,
    ) -> Result<(String, Range<usize>), SceneError> {
        match item.0 {
            DeValue::String(s) => Ok((s.to_string(), item.1)),
            _ => Err(self.wrong(key, item, "a string")),
        }
    }

    pub(crate) fn number(
        &self,
        key: &str,
        item: Item<'a, 'i>,
    ) -> Result<(f64, Range<usize>), SceneError> {
        match number(item.0) {
            Some(x) => Ok((x, item.1)),
            None => Err(self.wrong(key, item, "a number")),
        }
    }

    pub(crate) fn table(
        &self,
        key: &str,
        prefix: &'static str,
    ) -> Result<Option<Table<'a, 'i>>, SceneError> {
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
pub(crate) fn number(v: &DeValue) -> Option<f64> {
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
pub(crate) fn value(v: &DeValue) -> Option<Value> {
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
pub(crate) fn line_of(text: &str, at: usize) -> usize {
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

/// The entry of `table` whose name (`name_of`) is `name`, else the message "unknown `what`
/// "name"; valid: a, b, c" (scene and sweep files: a level, a quantity, a statistic).
pub fn named<'a, T>(
    table: &'a [T],
    name_of: impl Fn(&T) -> &str,
    what: &str,
    name: &str,
) -> Result<&'a T, String> {
    table.iter().find(|x| name_of(x) == name).ok_or_else(|| {
        let valid: Vec<&str> = table.iter().map(&name_of).collect();
        format!("unknown {what} {name:?}; valid: {}", valid.join(", "))
    })
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
                let f = named(FIDELITIES, |f| f.0, "fidelity", &fid)
                    .map_err(|why| at("fidelity", span.clone(), why))?;
                (Some(f.1), span)
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

#[cfg(test)]
mod tests;
