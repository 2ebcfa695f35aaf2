//! The FMI 2.0 model description: what every description states besides the variables
//! (log categories, authorship, units), the model's information ([`ModelInfo`]), the
//! declarations' check ([`check`]), the GUID ([`guid`]: a hash of what the description states)
//! and, with the `tools` feature, the XML writer ([`xml`]).
//!
//! Elements follow the order of the FMI 2.0 XSD (`fmi2ModelDescription.xsd`): CoSimulation,
//! UnitDefinitions, TypeDefinitions, LogCategories, DefaultExperiment, ModelVariables,
//! ModelStructure. Nothing time- or machine-dependent goes in, so the file (and the GUID) is
//! reproducible.
//!
//! `generationDateAndTime` is the one date: [`VERSION_DATE`] in what `describe` writes (the
//! committed `modelDescription/*.xml`), and the date of the commit an FMU is built from in the
//! packaged file (`stamp`; the CLI takes it from `SOURCE_DATE_EPOCH` or `git log`). The GUID
//! does not hash it, so it names the interface, not the moment of packaging, and both files
//! carry the same GUID.

pub mod guid;
#[cfg(feature = "tools")]
pub mod terminals;
#[cfg(feature = "tools")]
pub mod xml;
#[cfg(feature = "tools")]
pub mod xml3;

pub use guid::{fnv1a_128, format_guid};
#[cfg(feature = "tools")]
pub use xml::{describe, describe_vars, stamp};
#[cfg(feature = "tools")]
pub use xml3::{describe3, describe3_vars};

use crate::model::{Causality, Experiment, Model, Var, VarType, Variability};

/// Log categories the runtime knows (`fmi2SetDebugLogging`), with their descriptions.
pub const LOG_CATEGORIES: &[(&str, &str)] = &[
    (
        "logEvents",
        "Events of the mechanism: phase changes, roller lift-off, initialization",
    ),
    ("logStatusWarning", "Calls that return fmi2Warning"),
    ("logStatusDiscard", "Calls that return fmi2Discard"),
    (
        "logStatusError",
        "Calls that return fmi2Error, with the reason",
    ),
    ("logStatusFatal", "Calls that return fmi2Fatal"),
    ("logAll", "Every message, including each FMI call"),
];

/// Who makes the FMUs and on which terms: Cargo.toml's version and license; it names no
/// authors, so the project does.
pub const AUTHOR: &str = "the bindery-fmu authors";
pub const COPYRIGHT: &str = "Copyright the bindery-fmu authors";
pub const LICENSE: &str = env!("CARGO_PKG_LICENSE");

/// `generationDateAndTime` of the committed descriptions and of a build with no commit date at
/// hand (no git, no `SOURCE_DATE_EPOCH`): the date of the repository's first commit, where
/// version 0.1.0 began. Stable, so the committed files do not go stale with every commit.
pub const VERSION_DATE: &str = "2026-11-22T10:56:58Z";

/// Seconds since 1970-01-01T00:00:00Z as an xs:dateTime in UTC, e.g. `2026-11-22T10:56:58Z`
/// (days to civil date: H. Hinnant, "chrono-compatible low-level date algorithms").
pub fn date_time(epoch: i64) -> String {
    let (days, secs) = (epoch.div_euclid(86_400), epoch.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        secs / 3600,
        secs % 3600 / 60,
        secs % 60
    )
}

/// What the description says of the model besides its variables.
#[derive(Clone, Debug)]
pub struct ModelInfo {
    pub identifier: &'static str,
    pub model_name: &'static str,
    pub description: &'static str,
    pub experiment: Experiment,
    /// Model Exchange: number of event indicators (the interface is declared when some variable
    /// is a state derivative).
    pub event_indicators: u32,
    /// `canInterpolateInputs` of the Co-Simulation interface.
    pub can_interpolate_inputs: bool,
    /// The terminals (FMI 3.0's `terminalsAndIcons.xml`; those whose variables are all listed).
    pub terminals: &'static [crate::model::shaft::Terminal],
    /// The number of the model's variables (a tailored FMU lists some): FMI 3.0's independent
    /// variable `time` has this value reference, its event indicators the next ones.
    pub variables: u32,
    /// Exact partial derivatives ([`Model::PARTIALS`]): directional (FMI 2.0 and 3.0) and
    /// adjoint (FMI 3.0).
    pub partials: bool,
}

impl ModelInfo {
    /// The info of a model type.
    pub fn of<M: Model>() -> Self {
        ModelInfo {
            identifier: M::IDENTIFIER,
            model_name: M::MODEL_NAME,
            description: M::DESCRIPTION,
            experiment: M::EXPERIMENT,
            event_indicators: M::EVENT_INDICATORS as u32,
            can_interpolate_inputs: M::CAN_INTERPOLATE_INPUTS,
            terminals: M::TERMINALS,
            variables: <M::Var as crate::model::VarSet>::table().len() as u32,
            partials: M::PARTIALS,
        }
    }
}

pub use crate::model::units::{UNITS, UnitDef, display_factor, unit_def};

/// Formats a real the way every attribute is written: shortest round-trip form.
pub fn fmt_real(x: f64) -> String {
    format!("{x:?}")
}

/// Checks a declaration table for what FMI 2.0 forbids, so a bad declaration fails the
/// model's tests instead of a host's validation.
pub fn check(vars: &[Var]) -> Result<(), String> {
    let mut names = std::collections::HashSet::new();
    for (i, v) in vars.iter().enumerate() {
        let e = |m: &str| Err(format!("variable {} ({}): {m}", i, v.name));
        if !names.insert(v.name) {
            return e("declared twice");
        }
        if v.name.is_empty() || v.name.contains(char::is_whitespace) {
            return e("not a structured name");
        }
        if let Some(u) = v.unit {
            if unit_def(u).is_none() {
                return e(&format!("unit {u} missing from md::UNITS"));
            }
            if let Some(d) = v.display_unit
                && !unit_def(u).is_some_and(|ud| ud.display.iter().any(|x| x.0 == d))
            {
                return e(&format!("display unit {d} not defined for {u}"));
            }
        }
        let needs_start = matches!(v.causality, Causality::Parameter | Causality::Input);
        if needs_start != v.start.is_some() {
            return e("start value required exactly for parameters and inputs");
        }
        if let (Some(lo), Some(s)) = (v.min, v.start)
            && s < lo
        {
            return e("start below min");
        }
        if let (Some(hi), Some(s)) = (v.max, v.start)
            && s > hi
        {
            return e("start above max");
        }
        if v.causality == Causality::Output
            && v.depends.iter().any(|&d| {
                vars.get(d as usize)
                    .is_none_or(|x| x.causality != Causality::Input)
            })
        {
            return e("an output may depend only on inputs");
        }
        if v.ty != VarType::Real && v.variability == Variability::Continuous {
            return e("only Real variables can be continuous");
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates() {
        assert_eq!(date_time(0), "1970-01-01T00:00:00Z");
        assert_eq!(date_time(1_700_000_000), "2023-11-14T22:13:20Z");
        assert_eq!(date_time(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(date_time(-1), "1969-12-31T23:59:59Z");
        // the first commit's committer date, as git gives it (%ct, %cI)
        assert_eq!(date_time(1_795_345_018), VERSION_DATE);
    }

    #[test]
    fn reals_are_written_round_trip() {
        for x in [
            0.0,
            1.0,
            -2.0,
            0.07,
            1e-3,
            2.1e11,
            57.29577951308232,
            1e-12,
            12345.678,
        ] {
            assert_eq!(fmt_real(x).parse::<f64>().unwrap(), x, "{x}");
        }
    }
}
