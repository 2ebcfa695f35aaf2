//! Reference results inside every FMU, in the layout of the FMI layered standard for reference
//! results (FMI-LS-REF, as the Reference FMUs ship them): `extra/org.fmi-standard.fmi-ls-ref/`
//! holds `fmi-ls-manifest.xml` and `<Model>_out.csv`, the outputs of the model's cross-check
//! experiment (`fmus/<Model>/<Model>_in.csv`, times from `<Model>_ref.opt`), with the inputs it
//! ran on (`<Model>_in.csv`).
//!
//! The build computes them with the FMU's own code, stepped as an FMI host's Co-Simulation
//! loop steps the FMU: the inputs of `t_k` set, [`Model::step`] over `h`, the outputs evaluated
//! at `t_k + h` (the first row after initialization at the inputs of the start time). The tests
//! check them against a host's run of the built FMU (bit for bit) and the committed
//! cross-check results. A scene's FMU: the scene's start values and stages, its default
//! experiment, the mechanism's cross-check inputs it lists (`crate::catalog::scene_reference`).

use crate::model::{Log, Model, NoLog, Values, VarSet, check_bounds};

/// The folder of FMI-LS-REF inside an FMU.
pub const FOLDER: &str = "extra/org.fmi-standard.fmi-ls-ref";

/// A cross-check experiment: the input table (`time` first) and its step.
pub struct Experiment<'a> {
    /// The text of `<Model>_in.csv` (quoted header, `time` first).
    pub input_csv: &'a str,
    pub start: f64,
    pub stop: f64,
    pub step: f64,
    /// The outputs to record (the columns of `<Model>_ref.csv`).
    pub outputs: &'a [String],
    /// A tailored FMU's start values and stages (its scene's), else the model's.
    pub tailored: Option<(&'a [f64], crate::model::Stages)>,
}

/// The columns of a CSV header, unquoted.
pub fn header(csv: &str) -> Vec<String> {
    (csv.lines().next().unwrap_or("").split(','))
        .map(|c| c.trim().trim_matches('"').to_string())
        .collect()
}

/// The outputs of model `M` over experiment `x`, as CSV text (quoted header, `time` first,
/// every number in its shortest round-trip form).
pub fn run<M: Model>(x: &Experiment) -> Result<String, String> {
    let names = header(x.input_csv);
    let table = <M::Var as VarSet>::table();
    let vr = |name: &str| -> Result<usize, String> {
        (table.iter())
            .position(|v| v.name == name)
            .ok_or_else(|| format!("{}: no variable {name:?}", M::IDENTIFIER))
    };
    let inputs: Vec<usize> = (names.iter().skip(1))
        .filter(|n| !n.is_empty())
        .map(|n| vr(n))
        .collect::<Result<_, _>>()?;
    let outputs: Vec<usize> = x.outputs.iter().map(|n| vr(n)).collect::<Result<_, _>>()?;
    let rows: Vec<Vec<f64>> = (x.input_csv.lines().skip(1))
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            (l.split(','))
                .map(|c| c.trim().parse::<f64>().map_err(|e| format!("{l:?}: {e}")))
                .collect()
        })
        .collect::<Result<_, _>>()?;
    // the inputs at time t: the table's rows, linear in between and held before the first and
    // after the last, in a host's arithmetic (FMPy's: w0*v0 + w1*v1 with w0 = (t1 - t)/(t1 - t0)),
    // so that a host's run over the same inputs gives these rows
    let input_at = |t: f64| -> Vec<f64> {
        let i1 = rows.partition_point(|r| r[0] < t);
        if rows.is_empty() {
            return vec![];
        }
        if i1 == 0 || rows.len() < 2 {
            return rows[0][1..].to_vec();
        }
        if i1 == rows.len() {
            return rows[rows.len() - 1][1..].to_vec();
        }
        let (r0, r1) = (&rows[i1 - 1], &rows[i1]);
        let w0 = (r1[0] - t) / (r1[0] - r0[0]);
        let w1 = 1.0 - w0;
        (1..r0.len()).map(|j| w0 * r0[j] + w1 * r1[j]).collect()
    };
    let mut log = NoLog;
    let mut v = Values::<M::Var>::start();
    if let Some((start, stages)) = x.tailored {
        v.raw_mut().copy_from_slice(start);
        v.stages = stages;
    }
    let set = |v: &mut Values<M::Var>, t: f64| {
        for (&i, x) in inputs.iter().zip(input_at(t)) {
            v.raw_mut()[i] = x;
        }
        v.inputs_at = t;
    };
    v.inputs_at = x.start;
    set(&mut v, x.start);
    check_bounds(&v).map_err(|e| e.to_string())?;
    let mut m = M::prepare(&v).map_err(|e| e.to_string())?;
    m.calculated_parameters(&mut v);
    m.evaluate(&mut v, x.start, &mut log);
    let mut out = String::new();
    let quoted: Vec<String> = std::iter::once("time")
        .chain(x.outputs.iter().map(String::as_str))
        .map(|c| format!("\"{c}\""))
        .collect();
    out.push_str(&quoted.join(","));
    out.push('\n');
    let row = |v: &Values<M::Var>, t: f64, out: &mut String| {
        let cells: Vec<String> = std::iter::once(t)
            .chain(outputs.iter().map(|&i| v.raw()[i]))
            .map(|x| format!("{x:?}"))
            .collect();
        out.push_str(&cells.join(","));
        out.push('\n');
    };
    row(&v, x.start, &mut out);
    let n = ((x.stop - x.start) / x.step).round() as usize;
    for k in 0..n {
        // the host's grid: t_k = start + k*step, each step to the next point
        let t = x.start + k as f64 * x.step;
        let h = (x.start + (k + 1) as f64 * x.step) - t;
        set(&mut v, t);
        m.step(&mut v, t, h, &mut log as &mut dyn Log)
            .map_err(|e| format!("step from t = {t}: {e}"))?;
        m.evaluate(&mut v, t + h, &mut log);
        v.clear_input_derivatives();
        row(&v, t + h, &mut out);
    }
    Ok(out)
}

/// The columns of `csv` (`time` first) that are in `keep`, and the rows, as CSV text.
pub fn columns(csv: &str, keep: &[&str]) -> String {
    let head = header(csv);
    let idx: Vec<usize> = (0..head.len())
        .filter(|&j| j == 0 || keep.contains(&head[j].as_str()))
        .collect();
    let mut out = String::new();
    for (i, line) in csv.lines().filter(|l| !l.trim().is_empty()).enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        let picked: Vec<String> = (idx.iter())
            .map(|&j| match i {
                0 => format!("\"{}\"", head[j]),
                _ => cells[j].trim().to_string(),
            })
            .collect();
        out.push_str(&picked.join(","));
        out.push('\n');
    }
    out
}

/// The files of FMI-LS-REF in `extra/` for model (or scene FMU) `name`: the manifest, the
/// result and the inputs it ran on.
pub fn files(name: &str, x: &Experiment, result: String) -> Vec<(String, Vec<u8>)> {
    let folder = FOLDER.trim_start_matches("extra/");
    vec![
        (
            format!("{folder}/fmi-ls-manifest.xml"),
            manifest(name, x.start, x.stop, x.step).into_bytes(),
        ),
        (format!("{folder}/{name}_out.csv"), result.into_bytes()),
        (
            format!("{folder}/{name}_in.csv"),
            x.input_csv.as_bytes().to_vec(),
        ),
    ]
}

/// `fmi-ls-manifest.xml` of FMI-LS-REF naming the result and the inputs it ran on.
pub fn manifest(model: &str, start: f64, stop: f64, step: f64) -> String {
    format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiReferences
    xmlns:fmi-ls="http://fmi-standard.org/fmi-ls-manifest"
    fmi-ls:fmi-ls-name="org.fmi-standard.fmi-ls-ref"
    fmi-ls:fmi-ls-version="1.0.0-alpha.1"
    fmi-ls:fmi-ls-description="Reference results of the cross-check experiment">
  <Related type="text/csv" source="{model}_out.csv" role="result" description="Outputs of the cross-check experiment: Co-Simulation from {start:?} s to {stop:?} s in steps of {step:?} s, the inputs of {model}_in.csv at each step's start (the first row: after initialization)"/>
  <Related type="text/csv" source="{model}_in.csv" role="input" description="The inputs the result ran on: linear between rows, held after the last"/>
</fmiReferences>
"#
    )
}
