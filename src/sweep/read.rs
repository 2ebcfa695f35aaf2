//! What every sweep file has, read the same way for a model, a scene or a machine: which of
//! them it names, its tables in the order written, the swept parameters' axes and the design.

use super::plan::{MAX_RUNS, Swept};
use super::sample::{Axis, Design, Dist, Method};
use crate::model::Var;
use crate::scene::{Item, SceneError, Table, line_of, number, value, value_of};
use std::ops::Range;
use toml::de::{DeTable, DeValue};

const SAMPLING_KEYS: &[&str] = &["method", "samples", "seed"];

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

pub(crate) fn parse_toml(text: &str) -> Result<toml::Spanned<DeTable<'_>>, SceneError> {
    DeTable::parse(text).map_err(|e| SceneError {
        key: String::new(),
        line: e.span().map(|s| line_of(text, s.start)),
        message: e.message().trim().to_string(),
    })
}

pub(crate) fn root<'a, 'i>(text: &'a str, table: &'a DeTable<'i>) -> Table<'a, 'i> {
    Table {
        text,
        prefix: "",
        table,
        span: 0..0,
    }
}

pub(crate) type Entry<'a, 'i> = (
    &'a toml::Spanned<toml::de::DeString<'i>>,
    &'a toml::Spanned<DeValue<'i>>,
);

/// The entries of the table `section` in the order the file writes them (the parser's table is
/// sorted by key: the swept parameters' order decides which varies fastest and the columns'
/// order), each with its name and its key as the messages name it (`section."name"`).
pub(crate) fn in_file_order<'a, 'i>(
    t: &'a DeTable<'i>,
    section: &str,
) -> Vec<(String, String, Entry<'a, 'i>)> {
    let mut e: Vec<Entry> = t.iter().collect();
    e.sort_by_key(|(k, _)| k.span().start);
    (e.into_iter())
        .map(|(k, v)| {
            let name = k.get_ref().to_string();
            (name.clone(), format!("{section}.{name:?}"), (k, v))
        })
        .collect()
}

/// The design of a sweep file: its swept axes and its `[sampling]`, checked (a random axis needs
/// samples, a deterministic design refuses them; at most [`MAX_RUNS`] runs).
pub(crate) fn design_of(root: &Table, axes: Vec<Axis>) -> Result<Design, SceneError> {
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
pub(crate) fn whole(t: &Table, key: &str, item: Item, lo: i64, hi: i64) -> Result<i64, SceneError> {
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
pub(crate) fn axis(
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
                Some(var) => value_for(t.text, key, var, x)?,
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

/// The `[metrics]` entries in the order written, each as its name, its key (`metrics."name"`)
/// and its table, with the checks every sweep file gets: `[metrics]` is there and not empty, a
/// metric is a table of `keys` only (`example` shows one), its name is not already a column.
pub(crate) fn metric_tables<'a, 'i>(
    root: &Table<'a, 'i>,
    swept: &[Swept],
    keys: &[&str],
    example: &str,
) -> Result<Vec<(String, String, Table<'a, 'i>)>, SceneError> {
    let at = |key: &str, span: &Range<usize>, message: String| SceneError {
        key: key.into(),
        line: Some(line_of(root.text, span.start)),
        message,
    };
    let m = root.table("metrics", "metrics.")?.ok_or_else(|| {
        at(
            "metrics",
            &(0..0),
            format!("missing: the file needs [metrics], e.g. {example}"),
        )
    })?;
    let mut out = Vec::new();
    for (name, key, (k, v)) in in_file_order(m.table, "metrics") {
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
            let shape = example.split_once(" = ").map_or(example, |e| e.1);
            return Err(at(&key, &v.span(), format!("must be a table: {shape}")));
        };
        let mt = Table {
            text: root.text,
            prefix: "metrics.",
            table: mt,
            span: v.span(),
        };
        mt.only(keys).map_err(|e| SceneError {
            key: format!("{key}.{}", e.key.trim_start_matches("metrics.")),
            ..e
        })?;
        out.push((name, key, mt));
    }
    if out.is_empty() {
        return Err(at(
            "metrics",
            &m.span,
            "is empty: a sweep asks for at least one metric".into(),
        ));
    }
    Ok(out)
}

/// The value written for a parameter `var` at `key` (a number, a boolean or an item name),
/// type-checked against its declaration.
pub(crate) fn value_for(
    text: &str,
    key: &str,
    var: &Var,
    v: &toml::Spanned<DeValue>,
) -> Result<f64, SceneError> {
    let at = |message: String| SceneError {
        key: key.into(),
        line: Some(line_of(text, v.span().start)),
        message,
    };
    let x = value(v.get_ref())
        .ok_or_else(|| at("must be a number, a boolean or an item name".into()))?;
    value_of(var, &x).map_err(at)
}
