//! The FMI 2.0 `modelDescription.xml`, generated from a model's variable declarations
//! ([`crate::model`]) with quick-xml, and its GUID: a hash of that content.
//!
//! Elements follow the order of the FMI 2.0 XSD (`fmi2ModelDescription.xsd`): CoSimulation,
//! UnitDefinitions, TypeDefinitions, LogCategories, DefaultExperiment, ModelVariables,
//! ModelStructure. Nothing time- or machine-dependent goes in, so the file (and the GUID) is
//! reproducible.
//!
//! `generationDateAndTime` is the one date: [`VERSION_DATE`] in what [`describe`] writes (the
//! committed `modelDescription/*.xml`), and the date of the commit an FMU is built from in the
//! packaged file ([`stamp`]; the CLI takes it from `SOURCE_DATE_EPOCH` or `git log`). The GUID
//! is the hash of the description without it, so it names the interface, not the moment of
//! packaging, and both files carry the same GUID.

use crate::model::{
    Causality, EnumType, Experiment, Initial, Model, Var, VarSet, VarType, Variability,
};
use serde::Serialize;

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

/// A description written by [`describe`] with its `generationDateAndTime` set to `date`
/// (xs:dateTime, e.g. from [`date_time`]); the GUID does not change.
pub fn stamp(xml: &str, date: &str) -> String {
    xml.replacen(
        &format!("generationDateAndTime=\"{VERSION_DATE}\""),
        &format!(
            "generationDateAndTime=\"{}\"",
            quick_xml::escape::escape(date)
        ),
        1,
    )
}

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
        }
    }
}

/// A unit: its SI base-unit exponents and display units (name, factor: display = factor*value).
struct UnitDef {
    name: &'static str,
    /// exponents of kg, m, s, rad
    base: [i8; 4],
    display: &'static [(&'static str, f64)],
}

const DEG_PER_RAD: f64 = 180.0 / std::f64::consts::PI;
const RPM_PER_RAD_S: f64 = 30.0 / std::f64::consts::PI;

/// Every unit the models may use. A variable with a unit not listed here is a programming
/// error caught by the tests of every model.
const UNITS: &[UnitDef] = &[
    UnitDef {
        name: "m",
        base: [0, 1, 0, 0],
        display: &[("mm", 1000.0)],
    },
    UnitDef {
        name: "m/s",
        base: [0, 1, -1, 0],
        display: &[("mm/s", 1000.0)],
    },
    UnitDef {
        name: "m/s2",
        base: [0, 1, -2, 0],
        display: &[],
    },
    UnitDef {
        name: "rad",
        base: [0, 0, 0, 1],
        display: &[("deg", DEG_PER_RAD)],
    },
    UnitDef {
        name: "rad/s",
        base: [0, 0, -1, 1],
        display: &[("rpm", RPM_PER_RAD_S), ("deg/s", DEG_PER_RAD)],
    },
    UnitDef {
        name: "rad/s2",
        base: [0, 0, -2, 1],
        display: &[("deg/s2", DEG_PER_RAD)],
    },
    UnitDef {
        name: "s",
        base: [0, 0, 1, 0],
        display: &[],
    },
    UnitDef {
        name: "kg",
        base: [1, 0, 0, 0],
        display: &[],
    },
    UnitDef {
        name: "kg.m2",
        base: [1, 2, 0, 0],
        display: &[],
    },
    UnitDef {
        name: "N",
        base: [1, 1, -2, 0],
        display: &[("kN", 1e-3)],
    },
    UnitDef {
        name: "N/m",
        base: [1, 0, -2, 0],
        display: &[],
    },
    UnitDef {
        name: "N.s/m",
        base: [1, 0, -1, 0],
        display: &[],
    },
    UnitDef {
        name: "N.m",
        base: [1, 2, -2, 0],
        display: &[],
    },
    UnitDef {
        name: "N.m/rad",
        base: [1, 2, -2, -1],
        display: &[],
    },
    UnitDef {
        name: "N.m.s/rad",
        base: [1, 2, -1, -1],
        display: &[],
    },
    UnitDef {
        name: "J",
        base: [1, 2, -2, 0],
        display: &[],
    },
    UnitDef {
        name: "W",
        base: [1, 2, -3, 0],
        display: &[],
    },
    UnitDef {
        name: "Pa",
        base: [1, -1, -2, 0],
        display: &[("MPa", 1e-6)],
    },
];

fn unit_def(name: &str) -> Option<&'static UnitDef> {
    UNITS.iter().find(|u| u.name == name)
}

/// The factor of a display unit of `unit` (display value = factor × SI value), as declared in
/// the model description: `display_factor("rad/s", "rpm")` = 30/π.
pub fn display_factor(unit: &str, display: &str) -> Option<f64> {
    unit_def(unit)?
        .display
        .iter()
        .find(|(n, _)| *n == display)
        .map(|(_, f)| *f)
}

/// Formats a real the way every attribute is written: shortest round-trip form.
pub fn fmt_real(x: f64) -> String {
    format!("{x:?}")
}

// ---- serde shapes of the XML ---------------------------------------------------------------

#[derive(Serialize)]
#[serde(rename = "fmiModelDescription")]
struct Fmd {
    #[serde(rename = "@fmiVersion")]
    fmi_version: &'static str,
    #[serde(rename = "@modelName")]
    model_name: String,
    #[serde(rename = "@guid")]
    guid: String,
    #[serde(rename = "@description")]
    description: String,
    #[serde(rename = "@author")]
    author: &'static str,
    #[serde(rename = "@version")]
    version: &'static str,
    #[serde(rename = "@copyright")]
    copyright: &'static str,
    #[serde(rename = "@license")]
    license: &'static str,
    #[serde(rename = "@generationTool")]
    generation_tool: String,
    #[serde(
        rename = "@generationDateAndTime",
        skip_serializing_if = "Option::is_none"
    )]
    generation_date: Option<&'static str>,
    #[serde(rename = "@variableNamingConvention")]
    naming: &'static str,
    #[serde(rename = "@numberOfEventIndicators")]
    event_indicators: u32,
    #[serde(rename = "ModelExchange", skip_serializing_if = "Option::is_none")]
    model_exchange: Option<ModelExch>,
    #[serde(rename = "CoSimulation")]
    co_simulation: CoSim,
    #[serde(rename = "UnitDefinitions")]
    units: Units,
    #[serde(rename = "TypeDefinitions", skip_serializing_if = "Types::is_empty")]
    types: Types,
    #[serde(rename = "LogCategories")]
    log_categories: LogCats,
    #[serde(rename = "DefaultExperiment")]
    experiment: DefaultExperiment,
    #[serde(rename = "ModelVariables")]
    variables: ModelVariables,
    #[serde(rename = "ModelStructure")]
    structure: ModelStructure,
}

#[derive(Serialize)]
struct ModelExch {
    #[serde(rename = "@modelIdentifier")]
    model_identifier: String,
    #[serde(rename = "@needsExecutionTool")]
    needs_execution_tool: bool,
    #[serde(rename = "@completedIntegratorStepNotNeeded")]
    completed_step_not_needed: bool,
    #[serde(rename = "@canBeInstantiatedOnlyOncePerProcess")]
    once_per_process: bool,
    #[serde(rename = "@canNotUseMemoryManagementFunctions")]
    no_memory_functions: bool,
    #[serde(rename = "@canGetAndSetFMUstate")]
    get_set_state: bool,
    #[serde(rename = "@canSerializeFMUstate")]
    serialize_state: bool,
    #[serde(rename = "@providesDirectionalDerivative")]
    directional_derivative: bool,
}

#[derive(Serialize)]
struct CoSim {
    #[serde(rename = "@modelIdentifier")]
    model_identifier: String,
    #[serde(rename = "@needsExecutionTool")]
    needs_execution_tool: bool,
    #[serde(rename = "@canHandleVariableCommunicationStepSize")]
    variable_step: bool,
    #[serde(rename = "@canInterpolateInputs")]
    interpolate_inputs: bool,
    #[serde(rename = "@maxOutputDerivativeOrder")]
    max_output_derivative_order: u32,
    #[serde(rename = "@canRunAsynchronuously")]
    async_run: bool,
    #[serde(rename = "@canBeInstantiatedOnlyOncePerProcess")]
    once_per_process: bool,
    #[serde(rename = "@canNotUseMemoryManagementFunctions")]
    no_memory_functions: bool,
    #[serde(rename = "@canGetAndSetFMUstate")]
    get_set_state: bool,
    #[serde(rename = "@canSerializeFMUstate")]
    serialize_state: bool,
    #[serde(rename = "@providesDirectionalDerivative")]
    directional_derivative: bool,
}

#[derive(Serialize)]
struct Units {
    #[serde(rename = "Unit")]
    unit: Vec<Unit>,
}

#[derive(Serialize)]
struct Unit {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "BaseUnit")]
    base: BaseUnit,
    #[serde(rename = "DisplayUnit", skip_serializing_if = "Vec::is_empty")]
    display: Vec<DisplayUnit>,
}

#[derive(Serialize)]
struct BaseUnit {
    #[serde(rename = "@kg", skip_serializing_if = "Option::is_none")]
    kg: Option<i8>,
    #[serde(rename = "@m", skip_serializing_if = "Option::is_none")]
    m: Option<i8>,
    #[serde(rename = "@s", skip_serializing_if = "Option::is_none")]
    s: Option<i8>,
    #[serde(rename = "@rad", skip_serializing_if = "Option::is_none")]
    rad: Option<i8>,
}

#[derive(Serialize)]
struct DisplayUnit {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "@factor")]
    factor: String,
}

#[derive(Serialize)]
struct Types {
    #[serde(rename = "SimpleType")]
    simple: Vec<SimpleType>,
}

impl Types {
    fn is_empty(&self) -> bool {
        self.simple.is_empty()
    }
}

#[derive(Serialize)]
struct SimpleType {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "@description")]
    description: &'static str,
    #[serde(rename = "Enumeration")]
    enumeration: EnumItems,
}

#[derive(Serialize)]
struct EnumItems {
    #[serde(rename = "Item")]
    item: Vec<Item>,
}

#[derive(Serialize)]
struct Item {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "@value")]
    value: i32,
    #[serde(rename = "@description")]
    description: &'static str,
}

#[derive(Serialize)]
struct LogCats {
    #[serde(rename = "Category")]
    category: Vec<Category>,
}

#[derive(Serialize)]
struct Category {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "@description")]
    description: &'static str,
}

#[derive(Serialize)]
struct DefaultExperiment {
    #[serde(rename = "@startTime")]
    start: String,
    #[serde(rename = "@stopTime")]
    stop: String,
    #[serde(rename = "@tolerance", skip_serializing_if = "Option::is_none")]
    tolerance: Option<String>,
    #[serde(rename = "@stepSize")]
    step: String,
}

#[derive(Serialize)]
struct ModelVariables {
    #[serde(rename = "ScalarVariable")]
    vars: Vec<ScalarVariable>,
}

#[derive(Serialize)]
struct ScalarVariable {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "@valueReference")]
    vr: u32,
    #[serde(rename = "@description", skip_serializing_if = "str::is_empty")]
    description: &'static str,
    #[serde(rename = "@causality")]
    causality: &'static str,
    #[serde(rename = "@variability")]
    variability: &'static str,
    #[serde(rename = "@initial", skip_serializing_if = "Option::is_none")]
    initial: Option<&'static str>,
    #[serde(rename = "$value")]
    ty: TypeElement,
}

#[derive(Serialize)]
enum TypeElement {
    Real(RealAttrs),
    Integer(IntAttrs),
    Boolean(BoolAttrs),
    Enumeration(EnumAttrs),
}

#[derive(Serialize)]
struct RealAttrs {
    #[serde(rename = "@unit", skip_serializing_if = "Option::is_none")]
    unit: Option<&'static str>,
    #[serde(rename = "@displayUnit", skip_serializing_if = "Option::is_none")]
    display_unit: Option<&'static str>,
    #[serde(rename = "@min", skip_serializing_if = "Option::is_none")]
    min: Option<String>,
    #[serde(rename = "@max", skip_serializing_if = "Option::is_none")]
    max: Option<String>,
    #[serde(rename = "@start", skip_serializing_if = "Option::is_none")]
    start: Option<String>,
    #[serde(rename = "@derivative", skip_serializing_if = "Option::is_none")]
    derivative: Option<usize>,
}

#[derive(Serialize)]
struct IntAttrs {
    #[serde(rename = "@min", skip_serializing_if = "Option::is_none")]
    min: Option<i64>,
    #[serde(rename = "@max", skip_serializing_if = "Option::is_none")]
    max: Option<i64>,
    #[serde(rename = "@start", skip_serializing_if = "Option::is_none")]
    start: Option<i64>,
}

#[derive(Serialize)]
struct BoolAttrs {
    #[serde(rename = "@start", skip_serializing_if = "Option::is_none")]
    start: Option<bool>,
}

#[derive(Serialize)]
struct EnumAttrs {
    #[serde(rename = "@declaredType")]
    declared_type: &'static str,
    #[serde(rename = "@start", skip_serializing_if = "Option::is_none")]
    start: Option<i64>,
}

#[derive(Serialize)]
struct ModelStructure {
    #[serde(rename = "Outputs")]
    outputs: Unknowns,
    #[serde(rename = "Derivatives", skip_serializing_if = "Option::is_none")]
    derivatives: Option<Unknowns>,
    #[serde(rename = "InitialUnknowns")]
    initial: Unknowns,
}

#[derive(Serialize)]
struct Unknowns {
    #[serde(rename = "Unknown")]
    unknown: Vec<Unknown>,
}

#[derive(Serialize)]
struct Unknown {
    #[serde(rename = "@index")]
    index: usize,
    #[serde(rename = "@dependencies", skip_serializing_if = "Option::is_none")]
    dependencies: Option<String>,
}

fn causality_str(c: Causality) -> &'static str {
    match c {
        Causality::Parameter => "parameter",
        Causality::CalculatedParameter => "calculatedParameter",
        Causality::Input => "input",
        Causality::Output => "output",
        Causality::Local => "local",
    }
}

fn variability_str(v: Variability) -> &'static str {
    match v {
        Variability::Constant => "constant",
        Variability::Fixed => "fixed",
        Variability::Tunable => "tunable",
        Variability::Discrete => "discrete",
        Variability::Continuous => "continuous",
    }
}

fn initial_str(i: Initial) -> &'static str {
    match i {
        Initial::Exact => "exact",
        Initial::Approx => "approx",
        Initial::Calculated => "calculated",
    }
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

fn enum_types(vars: &[Var]) -> Vec<&'static EnumType> {
    let mut out: Vec<&'static EnumType> = Vec::new();
    for v in vars {
        if let VarType::Enumeration(t) = v.ty
            && !out.iter().any(|o| o.name == t.name)
        {
            out.push(t);
        }
    }
    out
}

fn scalar_variable(vr: u32, v: &Var, index_of: impl Fn(u32) -> Option<usize>) -> ScalarVariable {
    let ty = match v.ty {
        VarType::Real => TypeElement::Real(RealAttrs {
            unit: v.unit,
            display_unit: v.display_unit,
            min: v.min.map(fmt_real),
            max: v.max.map(fmt_real),
            start: v.start.map(fmt_real),
            derivative: v.derivative.and_then(index_of),
        }),
        VarType::Integer => TypeElement::Integer(IntAttrs {
            min: v.min.map(|x| x as i64),
            max: v.max.map(|x| x as i64),
            start: v.start.map(|x| x as i64),
        }),
        VarType::Boolean => TypeElement::Boolean(BoolAttrs {
            start: v.start.map(|x| x != 0.0),
        }),
        VarType::Enumeration(t) => TypeElement::Enumeration(EnumAttrs {
            declared_type: t.name,
            start: v.start.map(|x| x as i64),
        }),
    };
    ScalarVariable {
        name: v.name,
        vr,
        description: v.description,
        causality: causality_str(v.causality),
        variability: variability_str(v.variability),
        initial: v.initial.map(initial_str),
        ty,
    }
}

/// The description with this GUID; `dated`: with [`VERSION_DATE`] (the GUID is the hash of
/// the undated one).
fn build(info: &ModelInfo, vars: &[(u32, &Var)], guid: &str, dated: bool) -> Fmd {
    // Value reference -> 1-based index in ModelVariables.
    let index_of = |vr: u32| vars.iter().position(|(r, _)| *r == vr).map(|p| p + 1);
    let mut used_units: Vec<&'static UnitDef> = vars
        .iter()
        .filter_map(|(_, v)| v.unit.and_then(unit_def))
        .collect();
    used_units.sort_by_key(|u| u.name);
    used_units.dedup_by_key(|u| u.name);
    let units = used_units
        .iter()
        .map(|u| {
            let nz = |x: i8| (x != 0).then_some(x);
            Unit {
                name: u.name,
                base: BaseUnit {
                    kg: nz(u.base[0]),
                    m: nz(u.base[1]),
                    s: nz(u.base[2]),
                    rad: nz(u.base[3]),
                },
                display: u
                    .display
                    .iter()
                    .map(|(n, f)| DisplayUnit {
                        name: n,
                        factor: fmt_real(*f),
                    })
                    .collect(),
            }
        })
        .collect();
    let plain: Vec<Var> = vars.iter().map(|(_, v)| (*v).clone()).collect();
    let types = enum_types(&plain)
        .into_iter()
        .map(|t| SimpleType {
            name: t.name,
            description: t.description,
            enumeration: EnumItems {
                item: t
                    .items
                    .iter()
                    .enumerate()
                    .map(|(i, (n, d))| Item {
                        name: n,
                        value: i as i32 + 1,
                        description: d,
                    })
                    .collect(),
            },
        })
        .collect();
    let outputs = vars
        .iter()
        .enumerate()
        .filter(|(_, (_, v))| v.causality == Causality::Output)
        .map(|(i, (_, v))| {
            let deps: Vec<String> = v
                .depends
                .iter()
                .filter_map(|&d| index_of(d))
                .map(|k| k.to_string())
                .collect();
            Unknown {
                index: i + 1,
                dependencies: Some(deps.join(" ")),
            }
        })
        .collect();
    let initial = vars
        .iter()
        .enumerate()
        .filter(|(_, (_, v))| {
            (matches!(v.causality, Causality::Output | Causality::Local)
                && matches!(v.initial, Some(Initial::Approx | Initial::Calculated)))
                || (v.causality == Causality::CalculatedParameter)
        })
        .map(|(i, _)| Unknown {
            index: i + 1,
            dependencies: None,
        })
        .collect();
    // Model Exchange: state derivatives (their dependencies are not declared: any state, any
    // input).
    let derivatives: Vec<Unknown> = vars
        .iter()
        .enumerate()
        .filter(|(_, (_, v))| v.derivative.is_some())
        .map(|(i, _)| Unknown {
            index: i + 1,
            dependencies: None,
        })
        .collect();
    let e = info.experiment;
    Fmd {
        fmi_version: "2.0",
        model_name: info.model_name.to_string(),
        guid: guid.to_string(),
        description: info.description.to_string(),
        author: AUTHOR,
        version: env!("CARGO_PKG_VERSION"),
        copyright: COPYRIGHT,
        license: LICENSE,
        generation_tool: format!("bindery-fmu {}", env!("CARGO_PKG_VERSION")),
        generation_date: dated.then_some(VERSION_DATE),
        naming: "structured",
        event_indicators: if derivatives.is_empty() {
            0
        } else {
            info.event_indicators
        },
        model_exchange: (!derivatives.is_empty()).then(|| ModelExch {
            model_identifier: info.identifier.to_string(),
            needs_execution_tool: false,
            completed_step_not_needed: false,
            once_per_process: false,
            no_memory_functions: true,
            get_set_state: true,
            serialize_state: true,
            directional_derivative: false,
        }),
        co_simulation: CoSim {
            model_identifier: info.identifier.to_string(),
            needs_execution_tool: false,
            variable_step: true,
            interpolate_inputs: info.can_interpolate_inputs,
            max_output_derivative_order: 0,
            async_run: false,
            once_per_process: false,
            no_memory_functions: true,
            get_set_state: true,
            serialize_state: true,
            directional_derivative: false,
        },
        units: Units { unit: units },
        types: Types { simple: types },
        log_categories: LogCats {
            category: LOG_CATEGORIES
                .iter()
                .map(|(n, d)| Category {
                    name: n,
                    description: d,
                })
                .collect(),
        },
        experiment: DefaultExperiment {
            start: fmt_real(e.start),
            stop: fmt_real(e.stop),
            tolerance: e.tolerance.map(fmt_real),
            step: fmt_real(e.step),
        },
        variables: ModelVariables {
            vars: vars
                .iter()
                .map(|(vr, v)| scalar_variable(*vr, v, index_of))
                .collect(),
        },
        structure: ModelStructure {
            outputs: Unknowns { unknown: outputs },
            derivatives: (!derivatives.is_empty()).then_some(Unknowns {
                unknown: derivatives,
            }),
            initial: Unknowns { unknown: initial },
        },
    }
}

fn to_xml(fmd: &Fmd) -> String {
    let mut body = String::new();
    let mut ser = quick_xml::se::Serializer::new(&mut body);
    ser.indent(' ', 2);
    fmd.serialize(ser).expect("model description serializes");
    format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n{body}\n")
}

/// 128-bit FNV-1a: a small, dependency-free, stable content hash.
pub fn fnv1a_128(bytes: &[u8]) -> u128 {
    let mut h: u128 = 0x6c62272e07bb014262b821756295c58d;
    for &b in bytes {
        h ^= b as u128;
        h = h.wrapping_mul(0x0000000001000000000000000000013B);
    }
    h
}

/// Formats a 128-bit hash as a GUID `{xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx}`.
pub fn format_guid(h: u128) -> String {
    let s = format!("{h:032x}");
    format!(
        "{{{}-{}-{}-{}-{}}}",
        &s[0..8],
        &s[8..12],
        &s[12..16],
        &s[16..20],
        &s[20..32]
    )
}

/// The model description of the given variables (by value reference) and its GUID, which is
/// the hash of the description written with an empty GUID and no `generationDateAndTime`.
pub fn describe_vars(info: &ModelInfo, vars: &[(u32, &Var)]) -> (String, String) {
    let unsigned = to_xml(&build(info, vars, "", false));
    let guid = format_guid(fnv1a_128(unsigned.as_bytes()));
    (to_xml(&build(info, vars, &guid, true)), guid)
}

/// The full model description of a model type, and its GUID.
pub fn describe<M: Model>() -> (String, String) {
    let vars: Vec<(u32, &Var)> = <M::Var as VarSet>::table()
        .iter()
        .enumerate()
        .map(|(i, v)| (i as u32, v))
        .collect();
    describe_vars(&ModelInfo::of::<M>(), &vars)
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
    fn guid_format_and_stability() {
        let g = format_guid(fnv1a_128(b"abc"));
        assert_eq!(g.len(), 38);
        assert_eq!(g, format_guid(fnv1a_128(b"abc")));
        assert_ne!(g, format_guid(fnv1a_128(b"abd")));
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
