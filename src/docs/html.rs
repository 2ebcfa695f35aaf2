//! `documentation/index.html`: one self-contained page (inline CSS, no script, no external
//! resource; the figures are PNGs next to it).

use super::Figure;
use crate::md::{ModelInfo, fmt_real};
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
body{font-family:\"DejaVu Sans\",\"Segoe UI\",Helvetica,Arial,sans-serif;color:#222;max-width:1100px;margin:2em auto;padding:0 1em;line-height:1.45}
h1{font-size:1.7em;margin-bottom:.2em}
h2{font-size:1.3em;margin-top:1.8em;border-bottom:1px solid #ccc}
p.lead{font-size:1.08em;color:#333}
p.meta{color:#555;font-size:.92em}
code,.name{font-family:\"DejaVu Sans Mono\",Consolas,monospace;font-size:.92em}
table{border-collapse:collapse;width:100%;font-size:.88em}
th,td{border:1px solid #d4d4d4;padding:.3em .45em;text-align:left;vertical-align:top}
th{background:#eef1f5;position:sticky;top:0}
tr:nth-child(even) td{background:#fafafa}
td.num{text-align:right;white-space:nowrap;font-family:\"DejaVu Sans Mono\",Consolas,monospace}
td.name{white-space:nowrap}
.du{color:#666}
ul.items{margin:.3em 0 0;padding-left:1.3em}
tr.input td.name{color:#1f5fa8}
tr.output td.name{color:#a0301f}
figure{margin:1.5em 0}
figure img{max-width:100%;height:auto;border:1px solid #ddd}
figcaption{color:#444;font-size:.95em;margin-top:.3em}
footer{margin-top:3em;color:#888;font-size:.85em}
";

fn causality(c: Causality) -> &'static str {
    match c {
        Causality::Parameter => "parameter",
        Causality::CalculatedParameter => "calculatedParameter",
        Causality::Input => "input",
        Causality::Output => "output",
        Causality::Local => "local",
    }
}

fn variability(v: Variability) -> &'static str {
    match v {
        Variability::Constant => "constant",
        Variability::Fixed => "fixed",
        Variability::Tunable => "tunable",
        Variability::Discrete => "discrete",
        Variability::Continuous => "continuous",
    }
}

/// A start, min or max value written as its type writes it (escaped).
fn value(ty: VarType, x: Option<f64>) -> String {
    let Some(x) = x else { return String::new() };
    match ty {
        VarType::Real => fmt_real(x),
        VarType::Integer => format!("{}", x as i64),
        VarType::Boolean => (x != 0.0).to_string(),
        VarType::Enumeration(t) => match t.item(x as i32) {
            Some(item) => format!("{} ({})", x as i64, escape(item)),
            None => format!("{}", x as i64),
        },
    }
}

fn row(out: &mut String, vr: u32, v: &Var) {
    let class = match v.causality {
        Causality::Input => " class=\"input\"",
        Causality::Output => " class=\"output\"",
        _ => "",
    };
    let ty = match v.ty {
        VarType::Real => "Real".to_string(),
        VarType::Integer => "Integer".to_string(),
        VarType::Boolean => "Boolean".to_string(),
        VarType::Enumeration(t) => format!("Enumeration <code>{}</code>", escape(t.name)),
    };
    let unit = match (v.unit, v.display_unit) {
        (Some(u), Some(d)) if d != u => format!(
            "{} <span class=\"du\" title=\"display unit\">({})</span>",
            escape(u),
            escape(d)
        ),
        (Some(u), _) => escape(u),
        (None, _) => String::new(),
    };
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
    let _ = writeln!(
        out,
        "<tr{class}><td class=\"name\">{}</td><td class=\"num\">{vr}</td><td>{}</td><td>{}</td><td>{ty}</td><td>{unit}</td>\
         <td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td>{desc}</td></tr>",
        escape(v.name),
        causality(v.causality),
        variability(v.variability),
        value(v.ty, v.start),
        value(v.ty, v.min),
        value(v.ty, v.max),
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

/// The documentation page of a model: its name and description, `intro_html` (inserted as
/// is: the caller's own HTML, e.g. what the mechanism is and which paper it follows), the
/// default experiment, a table of every variable in `vars` (value reference, declaration)
/// and each figure as an image (`figure.file`, next to the page) with its caption. Every
/// other text is escaped. Deterministic.
pub fn index_html(
    info: &ModelInfo,
    vars: &[(u32, &Var)],
    intro_html: &str,
    figures: &[Figure],
) -> String {
    let mut out = String::with_capacity(8192 + 600 * vars.len());
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
    let interfaces = if vars.iter().any(|(_, v)| v.derivative.is_some()) {
        "Co-Simulation and Model Exchange"
    } else {
        "Co-Simulation"
    };
    let _ = writeln!(
        out,
        "<p class=\"meta\">FMI 2.0 {interfaces} FMU, model identifier <code>{}</code>.</p>",
        escape(info.identifier)
    );
    if !intro_html.trim().is_empty() {
        let _ = writeln!(
            out,
            "<section class=\"intro\">\n{}\n</section>",
            intro_html.trim()
        );
    }

    let e = info.experiment;
    let _ = write!(
        out,
        "<h2>Default experiment</h2>\n<p>Start {} s, stop {} s, communication step {} s",
        fmt_real(e.start),
        fmt_real(e.stop),
        fmt_real(e.step)
    );
    if let Some(tol) = e.tolerance {
        let _ = write!(out, ", tolerance {}", fmt_real(tol));
    }
    out.push_str(".</p>\n");
    out.push_str(&steps_html(info, vars));

    let _ = writeln!(
        out,
        "<h2>Variables</h2>\n<p>{} variables. Units are SI; the unit in parentheses is the display unit.</p>\n<table>\n<thead><tr>\
         <th>Name</th><th>VR</th><th>Causality</th><th>Variability</th><th>Type</th><th>Unit (display)</th>\
         <th>Start</th><th>Min</th><th>Max</th><th>Description</th></tr></thead>\n<tbody>",
        vars.len()
    );
    for (vr, v) in vars {
        row(&mut out, *vr, v);
    }
    out.push_str("</tbody>\n</table>\n");

    if !figures.is_empty() {
        out.push_str("<h2>Figures</h2>\n");
        let (w, h) = super::FIGURE_SIZE;
        for f in figures {
            let _ = writeln!(
                out,
                "<figure>\n<img src=\"{}\" alt=\"{}\" width=\"{w}\" height=\"{h}\">\n<figcaption>{}</figcaption>\n</figure>",
                escape(&f.file),
                escape(&f.title),
                escape(&f.caption)
            );
        }
    }
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
        }
    }

    fn vars() -> Vec<Var> {
        vec![
            Var::input("shaft.phi", 0.0, "rad", "angle"),
            Var::parameter("crank.r", 0.07, "m", "radius <from [3]> & more")
                .min(0.0)
                .max(1.0),
            Var::int_parameter("n", 4, "slots"),
            Var::bool_parameter("b", true, "flag"),
            Var::enum_parameter("mode", &MODE, "dyn<amic>", "mode"),
            Var::output("knife.s", "m", "stroke"),
            Var::bool_output("lift", "lifted"),
        ]
    }

    #[test]
    fn escapes_special_characters() {
        assert_eq!(
            escape(r#"<a href="x">&'</a>"#),
            "&lt;a href=&quot;x&quot;&gt;&amp;&#39;&lt;/a&gt;"
        );
        let figs = [Figure {
            file: "f\"1.png".into(),
            title: "t<".into(),
            caption: "x < y & \"z\"".into(),
            series: vec![Series::default()],
            ..Default::default()
        }];
        let vars = vars();
        let refs: Vec<(u32, &Var)> = vars
            .iter()
            .enumerate()
            .map(|(i, v)| (i as u32, v))
            .collect();
        let page = index_html(&info(), &refs, "<p>intro <b>kept</b></p>", &figs);
        assert!(page.contains("<title>Knife &lt;drive&gt; &amp; &quot;co&quot;</title>"));
        assert!(page.contains("Cuts &#39;books&#39;"));
        assert!(page.contains("radius &lt;from [3]&gt; &amp; more"));
        assert!(
            page.contains("<p>intro <b>kept</b></p>"),
            "intro is the caller's HTML"
        );
        assert!(page.contains("<img src=\"f&quot;1.png\" alt=\"t&lt;\""));
        assert!(page.contains("<figcaption>x &lt; y &amp; &quot;z&quot;</figcaption>"));
        assert!(!page.contains("dyn<amic>"));
        assert!(page.contains("2 (dyn&lt;amic&gt;)"));
    }

    #[test]
    fn table_lists_every_variable() {
        let vars = vars();
        let refs: Vec<(u32, &Var)> = vars
            .iter()
            .enumerate()
            .map(|(i, v)| (i as u32 + 10, v))
            .collect();
        let page = index_html(&info(), &refs, "", &[]);
        for (vr, v) in &refs {
            assert!(
                page.contains(&format!(
                    "<td class=\"name\">{}</td><td class=\"num\">{vr}</td>",
                    v.name
                )),
                "{}",
                v.name
            );
        }
        assert_eq!(page.matches("<tr").count(), vars.len() + 1);
        assert!(page.contains("m <span class=\"du\" title=\"display unit\">(mm)</span>"));
        assert!(page.contains(
            "<td class=\"num\">0.07</td><td class=\"num\">0.0</td><td class=\"num\">1.0</td>"
        ));
        assert!(page.contains("<td class=\"num\">true</td>"));
        assert!(page.contains("<li><code>1</code> = <code>kinematic</code>: prescribed</li>"));
        assert!(page.contains("tolerance 1e-6"));
        assert!(!page.contains("<h2>Figures</h2>"));
        assert_eq!(page, index_html(&info(), &refs, "", &[]), "deterministic");
    }

    #[test]
    fn every_page_says_what_a_step_does() {
        let vars = vars();
        let refs: Vec<(u32, &Var)> = vars
            .iter()
            .enumerate()
            .map(|(i, v)| (i as u32, v))
            .collect();
        let page = |info: &ModelInfo, refs: &[(u32, &Var)]| index_html(info, refs, "", &[]);
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
