//! `--set NAME=VALUE` of the CLI: a parameter of a catalog FMU by name. The value is in the
//! parameter's display unit where it declares one (rpm for rad/s, deg for rad, mm for m, MPa
//! for Pa), else in its SI unit, or carries its unit (`120rpm`, `0.2 rad`); it is checked
//! against the parameter's bounds, which the error names in both units.

use bindery_fmu::docs::number;
use bindery_fmu::md::display_factor;
use bindery_fmu::model::{Causality, Var, VarType};

/// One parameter setting, in SI.
#[derive(Clone, Debug, PartialEq)]
pub struct Setting {
    pub name: &'static str,
    pub vr: u32,
    pub value: f64,
}

/// `x` (SI) of `v` as the user reads it: in the display unit with the SI value after it.
pub fn shown(v: &Var, x: f64) -> String {
    let si = format!("{} {}", number(x, 6), v.unit.unwrap_or(""))
        .trim_end()
        .to_string();
    match (v.unit, v.display_unit) {
        (Some(u), Some(d)) if d != u => match display_factor(u, d) {
            Some(f) => format!("{} {d} ({si})", number(x * f, 6)),
            None => si,
        },
        _ => si,
    }
}

/// Splits `text` into a finite number and an optional unit after it (`120rpm`, `0.2 rad`).
fn number_and_unit(text: &str) -> Option<(f64, Option<&str>)> {
    let text = text.trim();
    let finite = |s: &str| s.trim().parse::<f64>().ok().filter(|x| x.is_finite());
    if let Some(x) = finite(text) {
        return Some((x, None));
    }
    (1..text.len())
        .rev()
        .filter(|&i| text.is_char_boundary(i))
        .find_map(|i| {
            let unit = text[i..].trim();
            let ok = !unit.is_empty() && !unit.starts_with(|c: char| c.is_ascii_digit());
            finite(&text[..i]).filter(|_| ok).map(|x| (x, Some(unit)))
        })
}

/// The settings of `texts` (NAME=VALUE) for `model`: a later setting of a name replaces an
/// earlier one; a name in `reserved` is refused with `why` (what the command sets itself).
pub fn parse_all(
    model: &str,
    vars: &[(u32, &'static Var)],
    texts: &[String],
    reserved: &[&str],
    why: &str,
) -> Result<Vec<Setting>, String> {
    let mut out: Vec<Setting> = Vec::new();
    for t in texts {
        let s = parse(model, vars, t)?;
        if reserved.contains(&s.name) {
            return Err(format!("{}: {why}", s.name));
        }
        out.retain(|o| o.name != s.name);
        out.push(s);
    }
    Ok(out)
}

/// The parameter `NAME=VALUE` of the FMU `model` (its variables `vars`), in SI, checked against
/// its bounds. Errors name the parameter, the value, the bounds, or the valid names.
pub fn parse(model: &str, vars: &[(u32, &'static Var)], text: &str) -> Result<Setting, String> {
    let Some((name, value)) = text.split_once('=') else {
        return Err(format!("--set {text:?}: want NAME=VALUE, e.g. spring.M0=8"));
    };
    let (name, value) = (name.trim(), value.trim());
    let parameters = || {
        vars.iter()
            .filter(|(_, v)| v.causality == Causality::Parameter)
            .map(|(_, v)| v.name)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let Some(&(vr, v)) = vars.iter().find(|(_, v)| v.name == name) else {
        return Err(format!(
            "{model} has no parameter {name:?}; its parameters: {}",
            parameters()
        ));
    };
    if v.causality != Causality::Parameter {
        return Err(format!(
            "{name} is not a parameter of {model} (it is computed by the model); its parameters: {}",
            parameters()
        ));
    }
    let x = match v.ty {
        VarType::Enumeration(t) => match t.items.iter().position(|(item, _)| *item == value) {
            Some(i) => (i + 1) as f64,
            None => match value.parse::<i32>().ok().filter(|&k| t.item(k).is_some()) {
                Some(k) => f64::from(k),
                None => {
                    let items: Vec<String> = (t.items.iter().enumerate())
                        .map(|(i, (item, _))| format!("{item} ({})", i + 1))
                        .collect();
                    return Err(format!(
                        "{name} = {value:?}: not one of {}",
                        items.join(", ")
                    ));
                }
            },
        },
        VarType::Boolean => match value {
            "true" | "1" => 1.0,
            "false" | "0" => 0.0,
            _ => return Err(format!("{name} = {value:?}: want true or false")),
        },
        VarType::Integer => match value.parse::<i64>() {
            Ok(k) => k as f64,
            Err(_) => return Err(format!("{name} = {value:?}: want an integer")),
        },
        VarType::Real => {
            let Some((x, unit)) = number_and_unit(value) else {
                return Err(format!("{name} = {value:?}: not a finite number"));
            };
            let si = v.unit.unwrap_or("");
            let display = v.display_unit.filter(|d| Some(*d) != v.unit);
            let factor = match unit {
                None => display.and_then(|d| display_factor(si, d)).unwrap_or(1.0),
                Some(u) if u == si => 1.0,
                Some(u) => display_factor(si, u).ok_or_else(|| {
                    format!(
                        "{name} = {value:?}: {u} is not a unit of {name}; give it in {}",
                        display.map_or(si.to_string(), |d| format!("{d} or {si}"))
                    )
                })?,
            };
            x / factor
        }
    };
    let out_of = |bound: &str, b: f64| {
        format!(
            "{name} = {value} is {bound} {}; {name} lies in [{}, {}]",
            shown(v, b),
            v.min.map_or("-inf".into(), |m| shown(v, m)),
            v.max.map_or("inf".into(), |m| shown(v, m)),
        )
    };
    if let Some(min) = v.min.filter(|&m| x < m) {
        return Err(out_of("below its minimum", min));
    }
    if let Some(max) = v.max.filter(|&m| x > m) {
        return Err(out_of("above its maximum", max));
    }
    Ok(Setting {
        name: v.name,
        vr,
        value: x,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_and_unit_split() {
        assert_eq!(number_and_unit("120"), Some((120.0, None)));
        assert_eq!(number_and_unit("120rpm"), Some((120.0, Some("rpm"))));
        assert_eq!(number_and_unit("1e5 N/m"), Some((1e5, Some("N/m"))));
        assert_eq!(number_and_unit("-2.5e-3m"), Some((-2.5e-3, Some("m"))));
        assert_eq!(number_and_unit("nan"), None);
        assert_eq!(number_and_unit("inf"), None);
        assert_eq!(number_and_unit("rpm"), None);
        assert_eq!(number_and_unit(""), None);
    }
}
