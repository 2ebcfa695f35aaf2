//! The `documentation/` of a tailored FMU: the usual page of its variables, preceded by the scene
//! and by what the FMU leaves out (outputs, parameters, inputs, computations) and why.

use super::escape;
use crate::md::fmt_real;
use crate::model::{Causality, Model, Stages, Var, VarSet, VarType, shaft};
use crate::scene::{Drive, Tailored, closure, fidelity_name, levels_of};
use std::fmt::Write;

/// What one left-out item is, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct LeftOut {
    pub name: String,
    pub why: String,
}

/// Everything a tailored FMU of `M` leaves out, by kind: outputs (and calculated parameters),
/// parameters, inputs, computation stages, Model Exchange states.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Report {
    pub outputs: Vec<LeftOut>,
    pub parameters: Vec<LeftOut>,
    pub inputs: Vec<LeftOut>,
    pub stages: Vec<LeftOut>,
    pub states: Vec<LeftOut>,
}

fn value_text(v: &Var, x: f64) -> String {
    match v.ty {
        VarType::Real => format!("{} {}", fmt_real(x), v.unit.unwrap_or("")),
        VarType::Integer => format!("{}", x as i64),
        VarType::Boolean => format!("{}", x != 0.0),
        VarType::Enumeration(t) => t.item(x as i32).unwrap_or("?").to_string(),
    }
    .trim()
    .to_string()
}

fn stage_names(stages: &[crate::model::Stage], s: Stages) -> String {
    let names: Vec<&str> = s.indices(stages.len()).map(|i| stages[i].name).collect();
    names.join(", ")
}

/// What `t` leaves out of `M`'s full FMU, and why.
pub fn report<M: Model>(t: &Tailored) -> Report {
    let table = <M::Var as VarSet>::table();
    let stages = M::STAGES;
    let fid = t.scene.fidelity;
    let fname = fid.map_or("", fidelity_name);
    let driven = shaft::is_driven::<M::Var>();
    let mut r = Report::default();
    for (vr, v) in table.iter().enumerate() {
        if t.exposed[vr] {
            continue;
        }
        let item = |why: String| LeftOut {
            name: v.name.to_string(),
            why,
        };
        match v.causality {
            Causality::Output | Causality::CalculatedParameter => {
                let levels = levels_of(stages, v.needs);
                r.outputs.push(item(if fid.is_none_or(|f| levels.contains(&f)) {
                    "not among the scene's outputs".into()
                } else {
                    format!(
                        "not among the scene's outputs, and not computed at the {fname} level (needs: {})",
                        stage_names(stages, closure(stages, v.needs))
                    )
                }));
            }
            Causality::Input => r.inputs.push(item(match t.scene.drive {
                Drive::ConstantSpeed { rpm, .. }
                    if matches!(vr as u32, shaft::PHI | shaft::W | shaft::A) =>
                {
                    format!("the FMU drives itself at {rpm} rpm (constant_speed)")
                }
                _ => "no output of the scene depends on it".into(),
            })),
            Causality::Parameter => {
                let x = value_text(v, t.start[vr]);
                // the common drive and level parameters of a mechanism (a drive has none)
                let common = if driven { vr as u32 } else { u32::MAX };
                let why = match common {
                    shaft::FIDELITY => format!("fixed by the scene's fidelity: {x}"),
                    shaft::MODE => format!("fixed by the scene's drive: {x}"),
                    shaft::N => format!(
                        "used by a constant_speed drive only; the scene drives through the inputs (kept at {x})"
                    ),
                    shaft::PHI0 => format!(
                        "the scene sets no phase of the mechanism on the shaft (kept at {x})"
                    ),
                    _ => format!(
                        "influences only {} (kept inside at {x}), which no output of the scene needs",
                        stage_names(stages, v.feeds)
                    ),
                };
                r.parameters.push(item(why));
            }
            Causality::Local => r.states.push(item(format!(
                "state or derivative of {}, not run at the {fname} level",
                stage_names(stages, v.needs)
            ))),
        }
    }
    for (i, s) in stages.iter().enumerate() {
        let bit = Stages::bit(i as u32);
        if t.stages.contains(bit) {
            continue;
        }
        let readers: Vec<&str> = table
            .iter()
            .filter(|v| closure(stages, v.needs).contains(bit))
            .map(|v| v.name)
            .collect();
        r.stages.push(LeftOut {
            name: s.name.to_string(),
            why: if fid.is_none_or(|f| s.levels.contains(&f)) {
                format!(
                    "{}. Skipped: no output of the scene needs it (it computes {})",
                    s.description,
                    readers.join(", ")
                )
            } else {
                format!("{}. Skipped: not part of the {fname} level", s.description)
            },
        });
    }
    r
}

fn table(out: &mut String, title: &str, what: &str, items: &[LeftOut]) {
    let _ = writeln!(out, "<h3>{} ({})</h3>", escape(title), items.len());
    if items.is_empty() {
        out.push_str("<p>None.</p>\n");
        return;
    }
    let _ = writeln!(
        out,
        "<table>\n<thead><tr><th>{}</th><th>Why</th></tr></thead>\n<tbody>",
        escape(what)
    );
    for i in items {
        let _ = writeln!(
            out,
            "<tr><td><code>{}</code></td><td>{}</td></tr>",
            escape(&i.name),
            escape(&i.why)
        );
    }
    out.push_str("</tbody>\n</table>\n");
}

/// The HTML inserted before the variable table: the scene, and what is left out.
pub fn intro_html<M: Model>(t: &Tailored) -> String {
    let r = report::<M>(t);
    let mut out = String::new();
    let n_all = <M::Var as VarSet>::table().len();
    let _ = writeln!(
        out,
        "<p>This FMU is <code>{}</code> tailored to the scene <code>{}</code>{}: it lists {} of the {} variables of the full <code>{}</code> FMU, and its binary (the mechanism's own) reads the scene from <code>resources/scene.toml</code> and computes only what those outputs need. The full FMU is the scene that asks for everything.</p>",
        escape(M::IDENTIFIER),
        escape(&t.scene.name),
        t.scene
            .fidelity
            .map_or(String::new(), |f| format!(" ({} level)", fidelity_name(f))),
        t.variables.len(),
        n_all,
        escape(M::IDENTIFIER)
    );
    let _ = writeln!(
        out,
        "<h2>The scene</h2>\n<pre>{}</pre>",
        escape(t.scene.text.trim_end())
    );
    out.push_str("<h2>What this FMU leaves out, and why</h2>\n");
    table(&mut out, "Computations skipped", "Stage", &r.stages);
    table(&mut out, "Outputs left out", "Output", &r.outputs);
    table(&mut out, "Parameters left out", "Parameter", &r.parameters);
    table(&mut out, "Inputs left out", "Input", &r.inputs);
    table(
        &mut out,
        "Model Exchange states left out",
        "Variable",
        &r.states,
    );
    out
}

/// Every file of the tailored FMU's `documentation/` (index.html).
pub fn documentation<M: Model>(t: &Tailored) -> Result<Vec<(String, Vec<u8>)>, String> {
    let vars: Vec<(u32, &Var)> = t.variables.iter().map(|(vr, v)| (*vr, v)).collect();
    super::documentation(&t.info, &vars, &intro_html::<M>(t), &[])
}
