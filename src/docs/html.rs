//! `documentation/index.html`: one self-contained page (inline CSS, no script, no external
//! resource; the figures are PNGs next to it), in the order a machine designer reads: what the
//! mechanism is and a picture of what it does, the questions it answers with the output that
//! answers each (numbers at the defaults, computed when the page is made), the figures, how it
//! is modelled, then every variable, grouped, with values in display units next to SI. Readable
//! from a phone's width up: tables wrap their cells, and below 700 px each row becomes a card.

use super::sweep::Sweep;
use super::{Figure, number};
use crate::md::{ModelInfo, display_factor, fmt_real};
use crate::model::{Causality, Var, VarType, Variability};
use std::fmt::Write;

/// `s` with `& < > " '` replaced by character references: safe as element text and inside a
/// quoted attribute.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}

const CSS: &str = "\
*{box-sizing:border-box}
html{-webkit-text-size-adjust:100%;text-size-adjust:100%}
body{font-family:\"DejaVu Sans\",\"Segoe UI\",Helvetica,Arial,sans-serif;color:#222;max-width:1100px;margin:0 auto;padding:1em;line-height:1.5;overflow-wrap:break-word}
h1{font-size:1.7em;margin:.4em 0 .2em}
h2{font-size:1.3em;margin-top:1.8em;border-bottom:1px solid #ccc}
h3{font-size:1.08em;margin:1.4em 0 .4em}
p.lead{font-size:1.08em;color:#333}
p.meta,p.note{color:#555;font-size:.92em}
nav{font-size:.95em;margin:.6em 0 1em}
nav a{margin-right:1em;display:inline-block}
a{color:#1f5fa8}
code{font-family:\"DejaVu Sans Mono\",Consolas,monospace;font-size:.9em;overflow-wrap:anywhere}
pre{white-space:pre-wrap;overflow-wrap:anywhere;background:#f6f8fa;padding:.6em;font-size:.85em}
table{border-collapse:collapse;width:100%;font-size:.9em;table-layout:fixed;margin:.4em 0 1em}
th,td{border:1px solid #d4d4d4;padding:.3em .45em;text-align:left;vertical-align:top;overflow-wrap:anywhere}
thead th{background:#eef1f5}
tr.group th{background:#f6f6f6;font-weight:normal;color:#555;font-size:.95em}
td .si,td .vr,td .level{color:#777;font-size:.9em}
td .vr{white-space:nowrap}
ul.items{margin:.3em 0 0;padding-left:1.3em}
col.name{width:24%}
col.value{width:24%}
col.unit{width:12%}
col.ask{width:30%}
col.out{width:22%}
figure{margin:1.5em 0}
figure img{max-width:100%;height:auto;border:1px solid #ddd}
figcaption{color:#444;font-size:.95em;margin-top:.3em}
footer{margin-top:3em;color:#888;font-size:.85em}
@media (max-width:700px){
body{padding:.6em}
h1{font-size:1.35em}
table.cards,table.cards tbody,table.cards tr,table.cards td,table.cards th{display:block;width:100%}
table.cards thead,table.cards colgroup{display:none}
table.cards tr{border:1px solid #d4d4d4;margin:.5em 0}
table.cards tr.group{border:none;margin:1em 0 .2em}
table.cards td,table.cards th{border:none;padding:.15em .5em}
table.cards td.name{background:#eef1f5;font-weight:bold}
table.cards td[data-label]::before{content:attr(data-label) \": \";color:#666}
}
";

/// A question a designer brings, the outputs that answer it and the answer at the defaults.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Question {
    pub ask: String,
    pub outputs: Vec<&'static str>,
    /// Plain text (escaped on the page).
    pub answer: String,
}

impl Question {
    pub fn new(ask: &str, outputs: &[&'static str], answer: impl Into<String>) -> Self {
        Question {
            ask: ask.into(),
            outputs: outputs.to_vec(),
            answer: answer.into(),
        }
    }
}

/// Everything one documentation page shows.
#[derive(Clone, Copy)]
pub struct Page<'a> {
    pub info: &'a ModelInfo,
    /// Every variable, by value reference.
    pub vars: &'a [(u32, &'a Var)],
    /// What the mechanism is (the caller's HTML).
    pub what: &'a str,
    /// The picture next to it.
    pub picture: Option<&'a Figure>,
    pub questions: &'a [Question],
    pub figures: &'a [Figure],
    /// How it is modelled: levels, assumptions, errata (the caller's HTML).
    pub notes: &'a str,
    /// The outputs over a turn at the defaults, for the table.
    pub sweep: Option<&'a Sweep>,
}

impl<'a> Page<'a> {
    /// A page of a model's variables with an introduction only.
    pub fn plain(info: &'a ModelInfo, vars: &'a [(u32, &'a Var)], what: &'a str) -> Self {
        Page {
            info,
            vars,
            what,
            picture: None,
            questions: &[],
            figures: &[],
            notes: "",
            sweep: None,
        }
    }
}

/// The value `x` (SI) of a variable: in its display unit with the SI value after it
/// ("300 rpm (31.4159 rad/s)"), or in SI; Integer, Boolean, Enumeration as their type reads.
fn value(v: &Var, x: f64) -> String {
    match v.ty {
        VarType::Real => {
            let si = format!("{} {}", number(x, 6), escape(v.unit.unwrap_or("")));
            match (v.unit, v.display_unit) {
                (Some(u), Some(d)) if d != u => match display_factor(u, d) {
                    Some(f) => format!(
                        "{} {} <span class=\"si\">({})</span>",
                        number(x * f, 6),
                        escape(d),
                        si.trim_end()
                    ),
                    None => si.trim_end().to_string(),
                },
                _ => si.trim_end().to_string(),
            }
        }
        VarType::Integer => format!("{}", x as i64),
        VarType::Boolean => (x != 0.0).to_string(),
        VarType::Enumeration(t) => match t.item(x as i32) {
            Some(item) => format!("<code>{}</code> ({})", escape(item), x as i64),
            None => format!("{}", x as i64),
        },
    }
}

/// The bounds of a parameter ("0 … 1", "≥ 0"), in the same units as its value.
fn bounds(v: &Var) -> String {
    let show = |x: f64| match v.ty {
        VarType::Real => {
            let f = match (v.unit, v.display_unit) {
                (Some(u), Some(d)) if d != u => display_factor(u, d).unwrap_or(1.0),
                _ => 1.0,
            };
            number(x * f, 6)
        }
        _ => format!("{}", x as i64),
    };
    let unit = match (v.ty, v.display_unit.or(v.unit)) {
        (VarType::Real, Some(u)) if !u.is_empty() => format!(" {}", escape(u)),
        _ => String::new(),
    };
    match (v.min, v.max) {
        (Some(lo), Some(hi)) => format!("{} … {}{unit}", show(lo), show(hi)),
        (Some(lo), None) => format!("≥ {}{unit}", show(lo)),
        (None, Some(hi)) => format!("≤ {}{unit}", show(hi)),
        (None, None) => "any".into(),
    }
}

/// The unit of a variable as a host shows it, with SI after it: "mm (m)".
fn unit(v: &Var) -> String {
    match (v.unit, v.display_unit) {
        (Some(u), Some(d)) if d != u => {
            format!("{} <span class=\"si\">({})</span>", escape(d), escape(u))
        }
        (Some(u), _) if !u.is_empty() => escape(u),
        _ => "–".into(),
    }
}

/// The description, with an Enumeration's items listed.
fn description(v: &Var) -> String {
    let mut desc = escape(v.description);
    if let VarType::Enumeration(t) = v.ty {
        desc.push_str("<ul class=\"items\">");
        for (i, (name, d)) in t.items.iter().enumerate() {
            let _ = write!(
                desc,
                "<li><code>{}</code> = <code>{}</code>",
                i + 1,
                escape(name)
            );
            if !d.is_empty() {
                let _ = write!(desc, ": {}", escape(d));
            }
            desc.push_str("</li>");
        }
        desc.push_str("</ul>");
    }
    if v.causality == Causality::Parameter && v.variability == Variability::Tunable {
        desc.push_str(" <span class=\"level\">(tunable during the run)</span>");
    }
    desc
}

/// The anchor of a variable's row.
pub fn anchor(name: &str) -> String {
    format!("v-{name}")
}

/// The name cell of a variable.
fn name_cell(vr: u32, v: &Var) -> String {
    format!(
        "<td class=\"name\"><code>{}</code> <span class=\"vr\">vr {vr}</span></td>",
        escape(v.name)
    )
}

/// The subsystem of a variable: its name up to the first dot.
fn group(name: &str) -> &str {
    name.split_once('.').map_or(name, |(g, _)| g)
}

/// A table of variables: its heading, anchor, a sentence under the heading, its columns
/// (heading, `col` class) and whether its rows are grouped by subsystem.
struct Table<'a> {
    title: &'a str,
    id: &'a str,
    lead: &'a str,
    columns: &'a [(&'a str, &'a str)],
    grouped: bool,
}

/// Writes a table of `vars`; `cells` gives a row's cells after the name.
fn table(out: &mut String, t: Table, vars: &[(u32, &Var)], cells: &dyn Fn(&Var) -> Vec<String>) {
    let Table {
        title,
        id,
        lead,
        columns,
        grouped,
    } = t;
    if vars.is_empty() {
        return;
    }
    let _ = writeln!(out, "<h3 id=\"{id}\">{title} ({})</h3>", vars.len());
    if !lead.is_empty() {
        let _ = writeln!(out, "<p>{lead}</p>");
    }
    out.push_str("<table class=\"cards\">\n<colgroup>");
    for (_, class) in columns {
        let _ = write!(out, "<col class=\"{class}\">");
    }
    out.push_str("</colgroup>\n<thead><tr>");
    for (head, _) in columns {
        let _ = write!(out, "<th>{head}</th>");
    }
    out.push_str("</tr></thead>\n<tbody>\n");
    let mut last = None;
    for (vr, v) in vars {
        let g = group(v.name);
        if grouped && last != Some(g) {
            let _ = writeln!(
                out,
                "<tr class=\"group\"><th colspan=\"{}\">{}</th></tr>",
                columns.len(),
                escape(g)
            );
        }
        last = Some(g);
        let _ = write!(
            out,
            "<tr id=\"{}\">{}",
            escape(&anchor(v.name)),
            name_cell(*vr, v)
        );
        for (cell, (head, _)) in cells(v).iter().zip(&columns[1..]) {
            let _ = write!(out, "<td data-label=\"{head}\">{cell}</td>");
        }
        out.push_str("</tr>\n");
    }
    out.push_str("</tbody>\n</table>\n");
}

/// Variables of one causality, outputs and parameters sorted by subsystem (first appearance).
fn of<'a>(vars: &[(u32, &'a Var)], c: Causality) -> Vec<(u32, &'a Var)> {
    let mut out: Vec<(u32, &Var)> = vars
        .iter()
        .filter(|(_, v)| v.causality == c)
        .copied()
        .collect();
    let mut order: Vec<&str> = vec![];
    for (_, v) in &out {
        if !order.contains(&group(v.name)) {
            order.push(group(v.name));
        }
    }
    out.sort_by_key(|(_, v)| order.iter().position(|g| *g == group(v.name)));
    out
}

fn figure(out: &mut String, f: &Figure) {
    let (w, h) = super::FIGURE_SIZE;
    let _ = writeln!(
        out,
        "<figure>\n<img src=\"{}\" alt=\"{}\" width=\"{w}\" height=\"{h}\">\n<figcaption>{}</figcaption>\n</figure>",
        escape(&f.file),
        escape(&f.title),
        escape(&f.caption)
    );
}

/// What a communication step does, the same for every FMU: the outputs after `fmi2DoStep(t, h)`
/// are at `t + h`; how the inputs move over the step (the shaft's extrapolation where the FMU
/// takes input derivatives, held otherwise); what the outputs kept over steps are formed over in
/// each interface.
fn steps_html(info: &ModelInfo, vars: &[(u32, &Var)]) -> String {
    let me = vars.iter().any(|(_, v)| v.derivative.is_some());
    let inputs = vars.iter().any(|(_, v)| v.causality == Causality::Input);
    let mut s = String::from(
        "<h2>Communication steps</h2>\n<p>After <code>fmi2DoStep(t, h)</code> every output is at \
         <i>t</i>&nbsp;+&nbsp;<i>h</i>, at every fidelity level. ",
    );
    if info.can_interpolate_inputs {
        s.push_str(
            "The shaft inputs are the shaft's angle, speed and acceleration at the instant they are \
             set; until they are set again the FMU moves the shaft on from there at that speed and \
             acceleration, in Co-Simulation and Model Exchange alike. Their start values are angle 0 \
             at the nominal speed, so with nothing connected the mechanism runs at its nominal \
             speed, and a host that connects them drives it (in Model Exchange it sets them after \
             <code>fmi2SetTime</code>). ",
        );
        s.push_str(
            "Over the step the shaft turns as its inputs at <i>t</i> say, \
             &phi;(<i>t</i>&nbsp;+&nbsp;&tau;) = <code>shaft.phi</code> + <code>shaft.w</code>&middot;&tau; \
             + <code>shaft.a</code>&middot;&tau;&sup2;/2, or with the derivatives of \
             <code>shaft.phi</code> (orders 1, 2) and <code>shaft.w</code> (order 1) set for that step \
             with <code>fmi2SetRealInputDerivatives</code> (<code>canInterpolateInputs</code>); the FMU \
             then leaves <code>shaft.phi</code>, <code>shaft.w</code> and <code>shaft.a</code> where that \
             leads, until the host sets them. Co-Simulation thus gives what Model Exchange gives at \
             <i>t</i>&nbsp;+&nbsp;<i>h</i> with the inputs of that instant: exactly for a shaft at \
             constant acceleration, otherwise to the order of the extrapolation (angle \
             <i>h</i>&sup3;, speed <i>h</i>&sup2;, acceleration <i>h</i>). A host that sets the inputs \
             of <i>t</i>&nbsp;+&nbsp;<i>h</i> before it reads gets the outputs at its own values.",
        );
    } else if inputs {
        s.push_str("The inputs are held over the step.");
    } else {
        s.push_str("The FMU drives its shaft itself; it has no inputs.");
    }
    s.push_str("</p>\n");
    if me {
        s.push_str(
            "<p>Outputs that keep something across steps (statistics of the last shaft turn, \
             counters, what happened during the last step, the step count) are formed over the same \
             spans in Co-Simulation and Model Exchange: a communication step, or the span between the \
             host's completed integrator steps (<code>fmi2CompletedIntegratorStep</code>); their \
             descriptions below say how. Peaks taken at the accepted integration steps are as fine \
             as those steps: in Model Exchange the host's (FMPy completes one at each output \
             point), so an output interval short against the fastest oscillation catches them as the \
             FMU's own integrator does.</p>\n",
        );
    }
    s
}

/// The documentation page. The caller's HTML (`what`, `notes`) is inserted as is; every other
/// text is escaped. Deterministic.
pub fn page_html(p: &Page) -> String {
    let info = p.info;
    let mut out = String::with_capacity(16384 + 600 * p.vars.len());
    let name = escape(info.model_name);
    let _ = write!(
        out,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{name}</title>\n<style>\n{CSS}</style>\n</head>\n<body>\n<h1>{name}</h1>\n"
    );
    if !info.description.is_empty() {
        let _ = writeln!(out, "<p class=\"lead\">{}</p>", escape(info.description));
    }
    // Model Exchange is declared where some variable is a state derivative (md::describe)
    let interfaces = if p.vars.iter().any(|(_, v)| v.derivative.is_some()) {
        "Co-Simulation and Model Exchange"
    } else {
        "Co-Simulation"
    };
    let partials = if info.partials {
        " It gives exact partial derivatives of its outputs (and state derivatives) with respect \
         to its inputs (and states): <code>fmi2GetDirectionalDerivative</code>, FMI 3.0's \
         directional and adjoint derivatives, computed on dual numbers from the formulas of the \
         outputs themselves."
    } else {
        ""
    };
    let _ = writeln!(
        out,
        "<p class=\"meta\">{} {interfaces} FMU <code>{}</code>, bindery-fmu {}, license {}.{partials}</p>",
        crate::package::VERSION_MARK,
        escape(info.identifier),
        env!("CARGO_PKG_VERSION"),
        escape(crate::md::LICENSE)
    );
    let inputs = of(p.vars, Causality::Input);
    let outputs = of(p.vars, Causality::Output);
    let parameters = of(p.vars, Causality::Parameter);
    let calculated = of(p.vars, Causality::CalculatedParameter);
    let locals = of(p.vars, Causality::Local);
    // contents
    let mut nav = vec![];
    if !p.what.trim().is_empty() || p.picture.is_some() {
        nav.push(("what", "What it is"));
    }
    if !p.questions.is_empty() {
        nav.push(("questions", "What it answers"));
    }
    if !p.figures.is_empty() {
        nav.push(("figures", "Figures"));
    }
    nav.push(("platforms", "Platforms"));
    nav.push(("model", "How it is modelled"));
    nav.push(("variables", "Variables"));
    out.push_str("<nav>");
    for (id, text) in &nav {
        let _ = write!(out, "<a href=\"#{id}\">{text}</a>");
    }
    out.push_str("</nav>\n");

    if nav[0].0 == "what" {
        out.push_str("<section id=\"what\">\n<h2>What it is</h2>\n");
        out.push_str(p.what.trim());
        out.push('\n');
        if let Some(f) = p.picture {
            figure(&mut out, f);
        }
        out.push_str("</section>\n");
    }

    if !p.questions.is_empty() {
        out.push_str("<section id=\"questions\">\n<h2>What it answers</h2>\n");
        let speed = p
            .sweep
            .filter(|s| s.rpm.is_finite())
            .map_or(String::new(), |s| {
                format!("nominal speed {} rpm, ", number(s.rpm, 6))
            });
        let _ = writeln!(
            out,
            "<p>At the defaults: {speed}every parameter at its start value; computed from the model when this page was made.</p>"
        );
        out.push_str(
            "<table class=\"cards\">\n<colgroup><col class=\"ask\"><col class=\"out\"><col></colgroup>\n\
             <thead><tr><th>Question</th><th>Output</th><th>At the defaults</th></tr></thead>\n<tbody>\n",
        );
        for q in p.questions {
            let links: Vec<String> = q
                .outputs
                .iter()
                .map(|o| {
                    format!(
                        "<a href=\"#{}\"><code>{}</code></a>",
                        escape(&anchor(o)),
                        escape(o)
                    )
                })
                .collect();
            let _ = writeln!(
                out,
                "<tr><td data-label=\"Question\">{}</td><td data-label=\"Output\">{}</td><td data-label=\"At the defaults\">{}</td></tr>",
                escape(&q.ask),
                links.join(", "),
                escape(&q.answer)
            );
        }
        out.push_str("</tbody>\n</table>\n</section>\n");
    }

    if !p.figures.is_empty() {
        out.push_str("<section id=\"figures\">\n<h2>Figures</h2>\n");
        for f in p.figures {
            figure(&mut out, f);
        }
        out.push_str("</section>\n");
    }

    // the packager puts the platforms of the binaries it packs here
    out.push_str("<section id=\"platforms\">\n");
    out.push_str(crate::package::PLATFORMS_MARK);
    out.push_str("\n</section>\n");

    out.push_str("<section id=\"model\">\n<h2>How it is modelled</h2>\n");
    if !p.notes.trim().is_empty() {
        out.push_str(p.notes.trim());
        out.push('\n');
    }
    let e = info.experiment;
    let _ = write!(
        out,
        "<p>Default experiment: start {} s, stop {} s, communication step {} s",
        number(e.start, 6),
        number(e.stop, 6),
        number(e.step, 6)
    );
    if let Some(tol) = e.tolerance {
        let _ = write!(out, ", tolerance {}", fmt_real(tol));
    }
    out.push_str(".</p>\n</section>\n");
    out.push_str(&steps_html(info, p.vars));

    let _ = writeln!(
        out,
        "<section id=\"variables\">\n<h2>Variables</h2>\n<p>{} variables. The FMU takes and gives SI values; a host such as FMPy sets start values in SI (<code>drive.n</code> in rad/s: 100 rpm is 10.472). Values are shown in the display unit a host may show (rpm, deg, mm, MPa) with SI in parentheses; <code>vr</code> is the value reference.</p>",
        p.vars.len()
    );
    table(
        &mut out,
        Table {
            title: "Inputs",
            id: "inputs",
            lead: "",
            columns: &[("Name", "name"), ("Start", "value"), ("Description", "")],
            grouped: false,
        },
        &inputs,
        &|v| vec![value(v, v.start.unwrap_or(0.0)), description(v)],
    );
    let turn = p
        .sweep
        .filter(|s| s.rpm.is_finite())
        .map(|s| format!("Over a turn at {} rpm, defaults", number(s.rpm, 6)));
    let out_cols: Vec<(&str, &str)> = match &turn {
        Some(t) => vec![
            ("Name", "name"),
            ("Unit", "unit"),
            (t.as_str(), "value"),
            ("Description", ""),
        ],
        None => vec![("Name", "name"), ("Unit", "unit"), ("Description", "")],
    };
    table(
        &mut out,
        Table {
            title: "Outputs",
            id: "outputs",
            lead: "By subsystem.",
            columns: &out_cols,
            grouped: true,
        },
        &outputs,
        &|v| {
            let mut c = vec![unit(v)];
            if let Some(s) = p.sweep.filter(|s| s.rpm.is_finite()) {
                let level = match s.level(v.name) {
                    Some(crate::model::shaft::Fidelity::Elastodynamic) => {
                        " <span class=\"level\">(elastodynamic level)</span>"
                    }
                    _ => "",
                };
                c.push(format!("{}{level}", escape(&s.range(v.name))));
            }
            c.push(description(v));
            c
        },
    );
    table(
        &mut out,
        Table {
            title: "Parameters",
            id: "parameters",
            lead: "By subsystem; a value outside its range is refused at initialization.",
            columns: &[
                ("Name", "name"),
                ("Value", "value"),
                ("Range", "unit"),
                ("Description", ""),
            ],
            grouped: true,
        },
        &parameters,
        &|v| vec![value(v, v.start.unwrap_or(0.0)), bounds(v), description(v)],
    );
    table(
        &mut out,
        Table {
            title: "Calculated parameters",
            id: "calculated",
            lead: "Derived from the parameters at initialization.",
            columns: &[
                ("Name", "name"),
                ("At the defaults", "value"),
                ("Description", ""),
            ],
            grouped: false,
        },
        &calculated,
        &|v| {
            vec![
                p.sweep
                    .and_then(|s| s.initial(v.name))
                    .map_or("–".into(), |x| value(v, x)),
                description(v),
            ]
        },
    );
    table(
        &mut out,
        Table {
            title: "Model Exchange states",
            id: "states",
            lead: "The continuous states and their derivatives a Model Exchange host integrates.",
            columns: &[("Name", "name"), ("Unit", "unit"), ("Description", "")],
            grouped: false,
        },
        &locals,
        &|v| vec![unit(v), description(v)],
    );
    out.push_str("</section>\n");
    let _ = write!(
        out,
        "<footer>Generated by bindery-fmu {}.</footer>\n</body>\n</html>\n",
        env!("CARGO_PKG_VERSION")
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::docs::Series;
    use crate::model::{EnumType, Experiment};

    static MODE: EnumType = EnumType {
        name: "Mode",
        description: "m",
        items: &[("kinematic", "prescribed"), ("dyn<amic>", "")],
    };

    fn info() -> ModelInfo {
        ModelInfo {
            identifier: "knife",
            model_name: "Knife <drive> & \"co\"",
            description: "Cuts 'books'",
            experiment: Experiment {
                start: 0.0,
                stop: 2.0,
                step: 1e-3,
                tolerance: Some(1e-6),
            },
            event_indicators: 0,
            can_interpolate_inputs: false,
            terminals: &[],
            variables: 0,
            partials: false,
        }
    }

    fn vars() -> Vec<Var> {
        vec![
            Var::input("shaft.phi", 0.0, "rad", "angle"),
            Var::parameter("crank.r", 0.07, "m", "radius <from [3]> & more")
                .min(0.0)
                .max(1.0),
            Var::parameter("drive.n", 10.0 * std::f64::consts::PI, "rad/s", "speed"),
            Var::int_parameter("n", 4, "slots"),
            Var::bool_parameter("b", true, "flag"),
            Var::enum_parameter("mode", &MODE, "dyn<amic>", "mode"),
            Var::output("knife.s", "m", "stroke"),
            Var::output("rod.F", "N", "force"),
            Var::bool_output("knife.lift", "lifted"),
        ]
    }

    fn refs(vars: &[Var]) -> Vec<(u32, &Var)> {
        vars.iter()
            .enumerate()
            .map(|(i, v)| (i as u32 + 10, v))
            .collect()
    }

    #[test]
    fn escapes_special_characters() {
        let figs = [Figure {
            file: "f\"1.png".into(),
            title: "t<".into(),
            caption: "x < y & \"z\"".into(),
            series: vec![Series::default()],
            ..Default::default()
        }];
        let vars = vars();
        let refs = refs(&vars);
        let info = info();
        let page = page_html(&Page {
            figures: &figs,
            ..Page::plain(&info, &refs, "<p>intro <b>kept</b></p>")
        });
        assert_eq!(
            escape(r#"<a href="x">&'</a>"#),
            "&lt;a href=&quot;x&quot;&gt;&amp;&#39;&lt;/a&gt;"
        );
        assert!(page.contains("<title>Knife &lt;drive&gt; &amp; &quot;co&quot;</title>"));
        assert!(page.contains("Cuts &#39;books&#39;"));
        assert!(page.contains("radius &lt;from [3]&gt; &amp; more"));
        assert!(
            page.contains("<p>intro <b>kept</b></p>"),
            "the caller's HTML"
        );
        assert!(page.contains("<img src=\"f&quot;1.png\" alt=\"t&lt;\""));
        assert!(page.contains("<figcaption>x &lt; y &amp; &quot;z&quot;</figcaption>"));
        assert!(!page.contains("dyn<amic>"));
        assert!(page.contains("<code>dyn&lt;amic&gt;</code> (2)"));
    }

    #[test]
    fn every_variable_once_grouped_in_display_units() {
        let vars = vars();
        let refs = refs(&vars);
        let info = info();
        let page = page_html(&Page::plain(&info, &refs, ""));
        for (vr, v) in &refs {
            let row = format!(
                "<tr id=\"v-{0}\"><td class=\"name\"><code>{0}</code> <span class=\"vr\">vr {vr}</span></td>",
                v.name
            );
            assert_eq!(page.matches(&row).count(), 1, "{}", v.name);
        }
        // groups in causality order: inputs, outputs, parameters
        let at = |s: &str| page.find(s).unwrap_or_else(|| panic!("{s} missing"));
        assert!(
            at("id=\"inputs\"") < at("id=\"outputs\"")
                && at("id=\"outputs\"") < at("id=\"parameters\"")
        );
        assert!(page.contains("<tr class=\"group\"><th colspan=\"3\">knife</th></tr>"));
        // display units next to SI, with sensible digits
        assert!(
            page.contains("300 rpm <span class=\"si\">(31.4159 rad/s)</span>"),
            "drive.n"
        );
        assert!(page.contains("70 mm <span class=\"si\">(0.07 m)</span>"));
        assert!(page.contains("0 … 1000 mm"), "crank.r bounds");
        assert!(
            page.contains("mm <span class=\"si\">(m)</span>"),
            "knife.s unit"
        );
        assert!(!page.contains("31.41592653589793"));
        assert!(page.contains("<td data-label=\"Value\">true</td>"));
        assert!(page.contains("<li><code>1</code> = <code>kinematic</code>: prescribed</li>"));
        assert!(page.contains("tolerance 1e-6"));
        assert!(!page.contains("id=\"figures\""));
        assert_eq!(
            page,
            page_html(&Page::plain(&info, &refs, "")),
            "deterministic"
        );
    }

    #[test]
    fn reading_order_and_question_links() {
        let vars = vars();
        let refs = refs(&vars);
        let info = info();
        let fig = |f: &str| Figure {
            file: f.into(),
            series: vec![Series::default()],
            ..Default::default()
        };
        let (pic, figs) = (fig("pic.png"), [fig("a.png")]);
        let questions = [Question::new("How far?", &["knife.s"], "140 mm")];
        let page = page_html(&Page {
            picture: Some(&pic),
            questions: &questions,
            figures: &figs,
            notes: "<p>notes</p>",
            ..Page::plain(&info, &refs, "<p>what</p>")
        });
        let at = |s: &str| page.find(s).unwrap_or_else(|| panic!("{s} missing"));
        let order = [
            "<p>what</p>",
            "src=\"pic.png\"",
            "id=\"questions\"",
            "src=\"a.png\"",
            "<p>notes</p>",
            "id=\"variables\"",
        ];
        for w in order.windows(2) {
            assert!(at(w[0]) < at(w[1]), "{} before {}", w[0], w[1]);
        }
        assert!(page.contains("<a href=\"#v-knife.s\"><code>knife.s</code></a>"));
        assert!(page.contains("id=\"v-knife.s\""));
    }

    #[test]
    fn every_page_says_what_a_step_does() {
        let vars = vars();
        let refs: Vec<(u32, &Var)> = vars
            .iter()
            .enumerate()
            .map(|(i, v)| (i as u32, v))
            .collect();
        let page = |info: &ModelInfo, refs: &[(u32, &Var)]| page_html(&Page::plain(info, refs, ""));
        let held = page(&info(), &refs);
        assert!(held.contains("every output is at <i>t</i>&nbsp;+&nbsp;<i>h</i>"));
        let shaft = page(
            &ModelInfo {
                can_interpolate_inputs: true,
                ..info()
            },
            &refs,
        );
        assert!(shaft.contains("fmi2SetRealInputDerivatives") && !held.contains("fmi2SetReal"));
        assert!(held.contains("The inputs are held over the step."));
        let outputs: Vec<(u32, &Var)> = refs
            .iter()
            .copied()
            .filter(|(_, v)| v.causality != Causality::Input)
            .collect();
        assert!(page(&info(), &outputs).contains("drives its shaft itself"));
    }
}
