//! The XML of `modelDescription.xml` (quick-xml and serde), written at build time by the
//! tools (`bindery build`, `bindery describe`); the FMU binary does not carry it.

use super::guid::guid;
use super::{
    AUTHOR, COPYRIGHT, LICENSE, LOG_CATEGORIES, ModelInfo, UnitDef, VERSION_DATE, fmt_real,
    unit_def,
};
use crate::model::{Causality, EnumType, Initial, Model, Var, VarType, Variability};
use serde::Serialize;

/// A description written by [`describe`] with its `generationDateAndTime` set to `date`
/// (xs:dateTime, e.g. from [`super::date_time`]); the GUID does not change.
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
    #[serde(flatten)]
    header: Header,
    #[serde(rename = "@numberOfEventIndicators")]
    event_indicators: u32,
    #[serde(rename = "ModelExchange", skip_serializing_if = "Option::is_none")]
    model_exchange: Option<ModelExch>,
    #[serde(rename = "CoSimulation")]
    co_simulation: CoSim,
    #[serde(flatten)]
    body: Body<Types, ModelVariables, ModelStructure>,
}

/// The elements of `fmiModelDescription` after the interfaces, in both versions' order, each
/// version with its own type definitions `T`, variables `V` and model structure `S`.
#[derive(Serialize)]
pub(super) struct Body<T: Serialize + Empty, V: Serialize, S: Serialize> {
    #[serde(rename = "UnitDefinitions")]
    pub units: Units,
    #[serde(rename = "TypeDefinitions", skip_serializing_if = "Empty::is_empty")]
    pub types: T,
    #[serde(rename = "LogCategories")]
    pub log_categories: LogCats,
    #[serde(rename = "DefaultExperiment")]
    pub experiment: DefaultExperiment,
    #[serde(rename = "ModelVariables")]
    pub variables: V,
    #[serde(rename = "ModelStructure")]
    pub structure: S,
}

impl<T: Serialize + Empty, V: Serialize, S: Serialize> Body<T, V, S> {
    /// What both versions state alike (units, log categories, experiment) with the version's
    /// types, variables and structure.
    pub(super) fn new(
        info: &ModelInfo,
        vars: &[(u32, &Var)],
        types: T,
        variables: V,
        structure: S,
    ) -> Self {
        Body {
            units: units_of(vars),
            types,
            log_categories: log_categories(),
            experiment: default_experiment(info),
            variables,
            structure,
        }
    }
}

/// Type definitions that may have nothing to declare (the element is then left out).
pub(super) trait Empty {
    fn is_empty(&self) -> bool;
}

/// The attributes of `fmiModelDescription` after the model's name and GUID, the same in FMI 2.0
/// and FMI 3.0 ([`super::xml3`]).
#[derive(Serialize)]
pub(super) struct Header {
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
    #[serde(rename = "@generationDateAndTime")]
    generation_date: &'static str,
    #[serde(rename = "@variableNamingConvention")]
    naming: &'static str,
}

/// [`Header`] of a model, dated [`VERSION_DATE`].
pub(super) fn header(info: &ModelInfo) -> Header {
    Header {
        description: info.description.to_string(),
        author: AUTHOR,
        version: env!("CARGO_PKG_VERSION"),
        copyright: COPYRIGHT,
        license: LICENSE,
        generation_tool: format!("bindery-fmu {}", env!("CARGO_PKG_VERSION")),
        generation_date: VERSION_DATE,
        naming: "structured",
    }
}

/// The capability flags both interfaces state, the same for both.
#[derive(Serialize)]
struct Capabilities {
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

impl Capabilities {
    fn of(info: &ModelInfo) -> Self {
        Capabilities {
            once_per_process: false,
            no_memory_functions: true,
            get_set_state: true,
            serialize_state: true,
            directional_derivative: info.partials,
        }
    }
}

#[derive(Serialize)]
struct ModelExch {
    #[serde(rename = "@modelIdentifier")]
    model_identifier: String,
    #[serde(rename = "@needsExecutionTool")]
    needs_execution_tool: bool,
    #[serde(rename = "@completedIntegratorStepNotNeeded")]
    completed_step_not_needed: bool,
    #[serde(flatten)]
    capabilities: Capabilities,
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
    #[serde(flatten)]
    capabilities: Capabilities,
}

#[derive(Serialize)]
pub(super) struct Units {
    #[serde(rename = "Unit")]
    unit: Vec<Unit>,
}

#[derive(Serialize)]
pub(super) struct Unit {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "BaseUnit")]
    base: BaseUnit,
    #[serde(rename = "DisplayUnit", skip_serializing_if = "Vec::is_empty")]
    display: Vec<DisplayUnit>,
}

#[derive(Serialize)]
pub(super) struct BaseUnit {
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
pub(super) struct DisplayUnit {
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

impl Empty for Types {
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

/// An item of an enumeration type, in both versions.
#[derive(Serialize)]
pub(super) struct Item {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "@value")]
    value: i64,
    #[serde(rename = "@description")]
    description: &'static str,
}

/// The items of an enumeration type, valued 1, 2, … in their order.
pub(super) fn items(t: &EnumType) -> Vec<Item> {
    (t.items.iter().enumerate())
        .map(|(i, (n, d))| Item {
            name: n,
            value: i as i64 + 1,
            description: d,
        })
        .collect()
}

#[derive(Serialize)]
pub(super) struct LogCats {
    #[serde(rename = "Category")]
    category: Vec<Category>,
}

#[derive(Serialize)]
pub(super) struct Category {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "@description")]
    description: &'static str,
}

#[derive(Serialize)]
pub(super) struct DefaultExperiment {
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
    #[serde(flatten)]
    head: VarHead,
    #[serde(rename = "$value")]
    ty: TypeElement,
}

/// The attributes a variable's element begins with, the same in FMI 2.0 and FMI 3.0
/// ([`super::xml3`]).
#[derive(Serialize)]
pub(super) struct VarHead {
    #[serde(rename = "@name")]
    pub name: String,
    #[serde(rename = "@valueReference")]
    pub vr: u32,
    #[serde(rename = "@description", skip_serializing_if = "str::is_empty")]
    pub description: &'static str,
    #[serde(rename = "@causality")]
    pub causality: &'static str,
    #[serde(rename = "@variability")]
    pub variability: &'static str,
    #[serde(rename = "@initial", skip_serializing_if = "Option::is_none")]
    pub initial: Option<&'static str>,
}

impl VarHead {
    /// The head of the declaration `v`, with value reference `vr`.
    pub(super) fn of(vr: u32, v: &Var) -> Self {
        VarHead {
            name: v.name.to_string(),
            vr,
            description: v.description,
            causality: causality_str(v.causality),
            variability: variability_str(v.variability),
            initial: v.initial.map(initial_str),
        }
    }
}

#[derive(Serialize)]
enum TypeElement {
    Real(RealAttrs),
    Integer(Bounds),
    Boolean(BoolAttrs),
    Enumeration(EnumAttrs),
}

#[derive(Serialize)]
struct RealAttrs {
    #[serde(rename = "@unit", skip_serializing_if = "Option::is_none")]
    unit: Option<&'static str>,
    #[serde(rename = "@displayUnit", skip_serializing_if = "Option::is_none")]
    display_unit: Option<&'static str>,
    #[serde(flatten)]
    bounds: Bounds,
    #[serde(rename = "@derivative", skip_serializing_if = "Option::is_none")]
    derivative: Option<usize>,
}

/// A variable's `min`, `max` and `start`, written alike in FMI 2.0 and FMI 3.0: a Real's as
/// [`fmt_real`] writes it, an Integer's as an integer.
#[derive(Serialize, Default)]
pub(super) struct Bounds {
    #[serde(rename = "@min", skip_serializing_if = "Option::is_none")]
    pub min: Option<String>,
    #[serde(rename = "@max", skip_serializing_if = "Option::is_none")]
    pub max: Option<String>,
    #[serde(rename = "@start", skip_serializing_if = "Option::is_none")]
    pub start: Option<String>,
}

/// A declared value (a bound or start) of an Integer or Enumeration variable, as an integer.
pub(super) fn integer(x: Option<f64>) -> Option<String> {
    x.map(|x| (x as i64).to_string())
}

impl Bounds {
    /// Those of the Real variable `v`.
    pub(super) fn real(v: &Var) -> Self {
        Bounds {
            min: v.min.map(fmt_real),
            max: v.max.map(fmt_real),
            start: v.start.map(fmt_real),
        }
    }

    /// Those of the Integer variable `v`.
    pub(super) fn integer(v: &Var) -> Self {
        Bounds {
            min: integer(v.min),
            max: integer(v.max),
            start: integer(v.start),
        }
    }
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
    start: Option<String>,
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

/// The enumeration types the variables declare, each once, in the order they first appear.
pub(super) fn enum_types(vars: &[(u32, &Var)]) -> Vec<&'static EnumType> {
    let mut out: Vec<&'static EnumType> = Vec::new();
    for (_, v) in vars {
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
            bounds: Bounds::real(v),
            derivative: v.derivative.and_then(index_of),
        }),
        VarType::Integer => TypeElement::Integer(Bounds::integer(v)),
        VarType::Boolean => TypeElement::Boolean(BoolAttrs {
            start: v.start.map(|x| x != 0.0),
        }),
        VarType::Enumeration(t) => TypeElement::Enumeration(EnumAttrs {
            declared_type: t.name,
            start: integer(v.start),
        }),
    };
    ScalarVariable {
        head: VarHead::of(vr, v),
        ty,
    }
}

/// The units the variables use, each with its display units.
pub(super) fn units_of(vars: &[(u32, &Var)]) -> Units {
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
    Units { unit: units }
}

/// The log categories of every description.
pub(super) fn log_categories() -> LogCats {
    LogCats {
        category: LOG_CATEGORIES
            .iter()
            .map(|(n, d)| Category {
                name: n,
                description: d,
            })
            .collect(),
    }
}

/// The default experiment of a model.
pub(super) fn default_experiment(info: &ModelInfo) -> DefaultExperiment {
    let e = info.experiment;
    DefaultExperiment {
        start: fmt_real(e.start),
        stop: fmt_real(e.stop),
        tolerance: e.tolerance.map(fmt_real),
        step: fmt_real(e.step),
    }
}

/// The model structure the declarations give, as positions in the listed variables: both
/// versions write it, FMI 2.0 by 1-based index, FMI 3.0 by value reference.
pub(super) struct Structure {
    /// Each output, with the variables it depends on (those listed, in declaration order).
    pub outputs: Vec<(usize, Vec<usize>)>,
    /// The state derivatives of Model Exchange (their dependencies are not declared: any
    /// state, any input).
    pub derivatives: Vec<usize>,
    /// What initialization computes: outputs and locals with an approximate or calculated
    /// start, and the calculated parameters.
    pub initial: Vec<usize>,
}

impl Structure {
    /// The structure of the listed variables.
    pub(super) fn of(vars: &[(u32, &Var)]) -> Structure {
        let position = |vr: u32| vars.iter().position(|(r, _)| *r == vr);
        let positions = |keep: &dyn Fn(&Var) -> bool| -> Vec<usize> {
            (0..vars.len()).filter(|&i| keep(vars[i].1)).collect()
        };
        Structure {
            outputs: positions(&|v| v.causality == Causality::Output)
                .into_iter()
                .map(|i| {
                    (
                        i,
                        vars[i]
                            .1
                            .depends
                            .iter()
                            .filter_map(|&d| position(d))
                            .collect(),
                    )
                })
                .collect(),
            derivatives: positions(&|v| v.derivative.is_some()),
            initial: positions(&|v| {
                (matches!(v.causality, Causality::Output | Causality::Local)
                    && matches!(v.initial, Some(Initial::Approx | Initial::Calculated)))
                    || v.causality == Causality::CalculatedParameter
            }),
        }
    }

    /// The outputs, the derivatives and the initial unknowns, each made by `unknown` from the
    /// reference of its variable (`reference` of its position: FMI 2.0 its index, FMI 3.0 its
    /// value reference) and, for an output, the references of those it depends on.
    pub(super) fn unknowns<R: ToString, U>(
        &self,
        reference: impl Fn(usize) -> R,
        unknown: impl Fn(R, Option<String>) -> U,
    ) -> [Vec<U>; 3] {
        let outputs = (self.outputs.iter())
            .map(|(i, deps)| {
                let deps: Vec<String> = deps.iter().map(|&k| reference(k).to_string()).collect();
                unknown(reference(*i), Some(deps.join(" ")))
            })
            .collect();
        let others = |positions: &[usize]| -> Vec<U> {
            (positions.iter())
                .map(|&i| unknown(reference(i), None))
                .collect()
        };
        [outputs, others(&self.derivatives), others(&self.initial)]
    }
}

/// The description with this GUID, dated [`VERSION_DATE`] ([`stamp`] sets a build's date).
fn build(info: &ModelInfo, vars: &[(u32, &Var)], guid: &str) -> Fmd {
    // Value reference -> 1-based index in ModelVariables.
    let index_of = |vr: u32| vars.iter().position(|(r, _)| *r == vr).map(|p| p + 1);
    let types = enum_types(vars)
        .into_iter()
        .map(|t| SimpleType {
            name: t.name,
            description: t.description,
            enumeration: EnumItems { item: items(t) },
        })
        .collect();
    let [outputs, derivatives, initial] = Structure::of(vars).unknowns(
        |i| i + 1,
        |index, dependencies| Unknown {
            index,
            dependencies,
        },
    );
    Fmd {
        fmi_version: "2.0",
        model_name: info.model_name.to_string(),
        guid: guid.to_string(),
        header: header(info),
        event_indicators: if derivatives.is_empty() {
            0
        } else {
            info.event_indicators
        },
        model_exchange: (!derivatives.is_empty()).then(|| ModelExch {
            model_identifier: info.identifier.to_string(),
            needs_execution_tool: false,
            completed_step_not_needed: false,
            capabilities: Capabilities::of(info),
        }),
        co_simulation: CoSim {
            model_identifier: info.identifier.to_string(),
            needs_execution_tool: false,
            variable_step: true,
            interpolate_inputs: info.can_interpolate_inputs,
            max_output_derivative_order: 0,
            async_run: false,
            capabilities: Capabilities::of(info),
        },
        body: Body::new(
            info,
            vars,
            Types { simple: types },
            ModelVariables {
                vars: (vars.iter())
                    .map(|(vr, v)| scalar_variable(*vr, v, index_of))
                    .collect(),
            },
            ModelStructure {
                outputs: Unknowns { unknown: outputs },
                derivatives: (!derivatives.is_empty()).then_some(Unknowns {
                    unknown: derivatives,
                }),
                initial: Unknowns { unknown: initial },
            },
        ),
    }
}

/// The XML document of a description (either version's), indented by two spaces.
pub(super) fn to_xml(fmd: &impl Serialize) -> String {
    let mut body = String::new();
    let mut ser = quick_xml::se::Serializer::with_root(&mut body, Some("fmiModelDescription"))
        .expect("a valid root name");
    ser.indent(' ', 2);
    fmd.serialize(ser).expect("model description serializes");
    format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n{body}\n")
}

/// The model description of the given variables (by value reference) and its GUID
/// ([`guid`]: the hash of what the description states).
pub fn describe_vars(info: &ModelInfo, vars: &[(u32, &Var)]) -> (String, String) {
    let guid = guid(info, vars);
    (to_xml(&build(info, vars, &guid)), guid)
}

/// The full model description of a model type, and its GUID.
pub fn describe<M: Model>() -> (String, String) {
    describe_vars(&ModelInfo::of::<M>(), &crate::model::variables_of::<M>())
}
