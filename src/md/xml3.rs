//! The FMI 3.0 `modelDescription.xml` (quick-xml and serde) from the same declarations as the
//! FMI 2.0 one ([`super::xml`]): the same variables, value references, units, display units,
//! log categories and experiment, written in FMI 3.0's shape (a typed element per variable,
//! `EnumerationType`, value references in `ModelStructure`, the independent variable `time`),
//! and the same GUID as its `instantiationToken`. Elements follow `fmi3ModelDescription.xsd`.

use super::ModelInfo;
use super::guid::guid;
use super::xml::{
    Body, Bounds, Empty, Header, Item, Structure, VarHead, enum_types, header, integer, items,
    to_xml,
};
use crate::model::{Model, Var, VarType};
use serde::Serialize;

#[derive(Serialize)]
#[serde(rename = "fmiModelDescription")]
struct Fmd {
    #[serde(rename = "@fmiVersion")]
    fmi_version: &'static str,
    #[serde(rename = "@modelName")]
    model_name: &'static str,
    #[serde(rename = "@instantiationToken")]
    token: String,
    #[serde(flatten)]
    header: Header,
    #[serde(rename = "ModelExchange", skip_serializing_if = "Option::is_none")]
    model_exchange: Option<ModelExch>,
    #[serde(rename = "CoSimulation")]
    co_simulation: CoSim,
    #[serde(flatten)]
    body: Body<Types, ModelVariables, ModelStructure>,
}

/// The Co-Simulation interface: variable steps, FMU state, Event Mode, and a step that may
/// return early at the mechanism's events (its discrete outputs marked as events); no
/// intermediate update or derivatives (yet).
#[derive(Serialize)]
struct CoSim {
    #[serde(flatten)]
    common: Interface,
    #[serde(rename = "@canHandleVariableCommunicationStepSize")]
    variable_step: bool,
    #[serde(rename = "@maxOutputDerivativeOrder")]
    max_output_derivative_order: u32,
    #[serde(rename = "@providesIntermediateUpdate")]
    intermediate_update: bool,
    #[serde(rename = "@mightReturnEarlyFromDoStep")]
    might_return_early: bool,
    #[serde(rename = "@canReturnEarlyAfterIntermediateUpdate")]
    early_return: bool,
    #[serde(rename = "@hasEventMode")]
    event_mode: bool,
}

/// What both interfaces state, the same for both.
#[derive(Serialize)]
struct Interface {
    #[serde(rename = "@modelIdentifier")]
    model_identifier: &'static str,
    #[serde(rename = "@needsExecutionTool")]
    needs_execution_tool: bool,
    #[serde(rename = "@canBeInstantiatedOnlyOncePerProcess")]
    once_per_process: bool,
    #[serde(rename = "@canGetAndSetFMUState")]
    get_set_state: bool,
    #[serde(rename = "@canSerializeFMUState")]
    serialize_state: bool,
    #[serde(rename = "@providesDirectionalDerivatives")]
    directional: bool,
    #[serde(rename = "@providesAdjointDerivatives")]
    adjoint: bool,
}

impl Interface {
    fn of(info: &ModelInfo) -> Self {
        Interface {
            model_identifier: info.identifier,
            needs_execution_tool: false,
            once_per_process: false,
            get_set_state: true,
            serialize_state: true,
            directional: info.partials,
            adjoint: info.partials,
        }
    }
}

/// The Model Exchange interface, where the model has continuous states (as in FMI 2.0).
#[derive(Serialize)]
struct ModelExch {
    #[serde(flatten)]
    common: Interface,
    #[serde(rename = "@needsCompletedIntegratorStep")]
    completed_step: bool,
    #[serde(rename = "@providesEvaluateDiscreteStates")]
    evaluate_discrete_states: bool,
}

#[derive(Serialize)]
struct Types {
    #[serde(rename = "Float64Type")]
    floats: Vec<Float64Type>,
    #[serde(rename = "EnumerationType")]
    enumerations: Vec<EnumerationType>,
}

impl Empty for Types {
    fn is_empty(&self) -> bool {
        self.floats.is_empty() && self.enumerations.is_empty()
    }
}

/// A unit with its display unit, as a type the Float64 variables declare (as the Reference
/// FMUs do: a variable element then carries no unit of its own, which every FMI 3.0 reader
/// accepts, fmi-sim's too).
#[derive(Serialize)]
struct Float64Type {
    #[serde(rename = "@name")]
    name: String,
    #[serde(rename = "@unit")]
    unit: &'static str,
    #[serde(rename = "@displayUnit", skip_serializing_if = "Option::is_none")]
    display_unit: Option<&'static str>,
}

/// The name of the type of a unit and display unit: the unit, and the display unit after it.
fn type_name(unit: &str, display: Option<&str>) -> String {
    match display {
        Some(d) => format!("{unit} in {d}"),
        None => unit.to_string(),
    }
}

#[derive(Serialize)]
struct EnumerationType {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "@description")]
    description: &'static str,
    #[serde(rename = "Item")]
    items: Vec<Item>,
}

#[derive(Serialize)]
struct ModelVariables {
    #[serde(rename = "$value")]
    vars: Vec<Variable>,
}

/// One variable: the element names its type.
#[derive(Serialize)]
enum Variable {
    Float64(Attrs),
    Int32(Attrs),
    Boolean(Attrs),
    Enumeration(Attrs),
}

/// The attributes of a variable element (those of another type are left out).
#[derive(Serialize)]
struct Attrs {
    #[serde(flatten)]
    head: VarHead,
    #[serde(rename = "@declaredType", skip_serializing_if = "Option::is_none")]
    declared_type: Option<String>,
    #[serde(flatten)]
    bounds: Bounds,
    #[serde(rename = "@derivative", skip_serializing_if = "Option::is_none")]
    derivative: Option<u32>,
}

#[derive(Serialize)]
struct ModelStructure {
    #[serde(rename = "Output")]
    outputs: Vec<Unknown>,
    #[serde(rename = "ContinuousStateDerivative")]
    derivatives: Vec<Unknown>,
    #[serde(rename = "InitialUnknown")]
    initial: Vec<Unknown>,
    #[serde(rename = "EventIndicator")]
    event_indicators: Vec<Unknown>,
}

#[derive(Serialize)]
struct Unknown {
    #[serde(rename = "@valueReference")]
    vr: u32,
    #[serde(rename = "@dependencies", skip_serializing_if = "Option::is_none")]
    dependencies: Option<String>,
}

/// The variable element of a declaration.
fn variable(vr: u32, v: &Var) -> Variable {
    let mut a = Attrs {
        head: VarHead::of(vr, v),
        declared_type: None,
        bounds: Bounds::default(),
        derivative: None,
    };
    match v.ty {
        VarType::Real => {
            a.declared_type = v.unit.map(|u| type_name(u, v.display_unit));
            a.bounds = Bounds::real(v);
            a.derivative = v.derivative;
            Variable::Float64(a)
        }
        VarType::Integer => {
            a.bounds = Bounds::integer(v);
            Variable::Int32(a)
        }
        VarType::Boolean => {
            a.bounds.start = v.start.map(|x| (x != 0.0).to_string());
            Variable::Boolean(a)
        }
        VarType::Enumeration(t) => {
            a.declared_type = Some(t.name.to_string());
            a.bounds.start = integer(v.start);
            Variable::Enumeration(a)
        }
    }
}

/// The description with this instantiation token, dated [`crate::md::VERSION_DATE`].
fn build(info: &ModelInfo, vars: &[(u32, &Var)], token: &str) -> Fmd {
    let enumerations = enum_types(vars)
        .into_iter()
        .map(|t| EnumerationType {
            name: t.name,
            description: t.description,
            items: items(t),
        })
        .collect();
    let mut floats: Vec<Float64Type> = Vec::new();
    for (_, v) in vars {
        if let (VarType::Real, Some(unit)) = (v.ty, v.unit) {
            let name = type_name(unit, v.display_unit);
            if !floats.iter().any(|t| t.name == name) {
                floats.push(Float64Type {
                    name,
                    unit,
                    display_unit: v.display_unit,
                });
            }
        }
    }
    floats.sort_by(|a, b| a.name.cmp(&b.name));
    // the independent variable, after every value reference of the model's, and the event
    // indicators of Model Exchange after it
    let time_vr = info
        .variables
        .max(vars.iter().map(|(r, _)| r + 1).max().unwrap_or(0));
    let model_exchange = vars.iter().any(|(_, v)| v.derivative.is_some());
    let indicators = if model_exchange {
        info.event_indicators
    } else {
        0
    };
    let mut variables = vec![Variable::Float64(Attrs {
        head: VarHead {
            name: "time".into(),
            vr: time_vr,
            description: "Simulation time",
            causality: "independent",
            variability: "continuous",
            initial: None,
        },
        declared_type: None,
        bounds: Bounds::default(),
        derivative: None,
    })];
    variables.extend(vars.iter().map(|(vr, v)| variable(*vr, v)));
    for k in 0..indicators {
        variables.push(Variable::Float64(Attrs {
            head: VarHead {
                name: format!("event.indicator_{}", k + 1),
                vr: time_vr + 1 + k,
                description: "Event indicator of Model Exchange: a state event where it changes sign (a contact opening or closing, the knife entering or leaving the stack)",
                causality: "local",
                variability: "continuous",
                initial: Some("calculated"),
            },
            declared_type: None,
            bounds: Bounds::default(),
            derivative: None,
        }));
    }
    let [outputs, derivatives, initial] = Structure::of(vars).unknowns(
        |i| vars[i].0,
        |vr, dependencies| Unknown { vr, dependencies },
    );
    let event_indicators = (0..indicators)
        .map(|k| Unknown {
            vr: time_vr + 1 + k,
            dependencies: None,
        })
        .collect();
    Fmd {
        fmi_version: "3.0",
        model_name: info.model_name,
        token: token.to_string(),
        header: header(info),
        model_exchange: model_exchange.then_some(ModelExch {
            common: Interface::of(info),
            completed_step: true,
            evaluate_discrete_states: false,
        }),
        co_simulation: CoSim {
            common: Interface::of(info),
            variable_step: true,
            max_output_derivative_order: 0,
            intermediate_update: false,
            might_return_early: vars.iter().any(|(_, v)| v.event),
            early_return: false,
            event_mode: true,
        },
        body: Body::new(
            info,
            vars,
            Types {
                floats,
                enumerations,
            },
            ModelVariables { vars: variables },
            ModelStructure {
                outputs,
                derivatives,
                initial,
                event_indicators,
            },
        ),
    }
}

/// The FMI 3.0 model description of the given variables (by value reference), and its
/// instantiation token (the GUID of the FMI 2.0 description of the same variables).
pub fn describe3_vars(info: &ModelInfo, vars: &[(u32, &Var)]) -> (String, String) {
    let token = guid(info, vars);
    (to_xml(&build(info, vars, &token)), token)
}

/// The full FMI 3.0 model description of a model type, and its instantiation token.
pub fn describe3<M: Model>() -> (String, String) {
    describe3_vars(&ModelInfo::of::<M>(), &crate::model::variables_of::<M>())
}
