//! The FMU tailored to a scene ([`fn@tailor`]): which variables it lists, which stages run, its
//! start values and GUID; computed by the CLI when it packages the FMU and by the FMU's binary
//! from `resources/scene.toml` at instantiation ([`cached`]).

use super::*;

/// The FMU tailored to a scene, for one mechanism.
#[derive(Clone, Debug)]
pub struct Tailored {
    pub scene: Scene,
    /// `modelIdentifier`: mechanism + the scene name's suffix.
    pub identifier: String,
    pub info: ModelInfo,
    /// Every variable of the mechanism, by value reference: exposed in this FMU?
    pub exposed: Vec<bool>,
    /// Start values of every variable (the scene's parameters, drive and fidelity applied).
    pub start: Vec<f64>,
    /// Start values of the exposed variables as written in the description.
    pub variables: Vec<(u32, Var)>,
    /// The stages that run.
    pub stages: Stages,
    /// The GUID of its model description ([`Tailored::model_description`]).
    pub guid: String,
}

impl Tailored {
    /// The variables the FMU lists, by value reference.
    pub fn refs(&self) -> Vec<(u32, &Var)> {
        self.variables.iter().map(|(vr, v)| (*vr, v)).collect()
    }

    /// Its model description (with [`Tailored::guid`]).
    #[cfg(feature = "tools")]
    pub fn model_description(&self) -> String {
        md::describe_vars(&self.info, &self.refs()).0
    }

    /// Its FMI 3.0 model description (the same variables; [`Tailored::guid`] as the
    /// instantiation token).
    #[cfg(feature = "tools")]
    pub fn model_description3(&self) -> String {
        md::describe3_vars(&self.info, &self.refs()).0
    }
}

/// `modelIdentifier` of a scene's FMU: the mechanism's, `_`, the scene name with `-` as `_`
/// (a C identifier: the binary is `binaries/linux64/<it>.so`).
pub fn identifier(mechanism: &str, scene_name: &str) -> String {
    format!("{mechanism}_{}", scene_name.replace('-', "_"))
}

/// Every stage `s` needs, with the stages they require, closed.
pub fn closure(stages: &[Stage], s: Stages) -> Stages {
    let mut out = s;
    loop {
        let mut next = out;
        for i in out.indices(stages.len()) {
            next = next.or(stages[i].requires);
        }
        if next == out {
            return out;
        }
        out = next;
    }
}

/// The fidelity levels at which every stage of `needs` is computed.
pub fn levels_of(stages: &[Stage], needs: Stages) -> Vec<Fidelity> {
    let needs = closure(stages, needs);
    FIDELITIES
        .iter()
        .map(|f| f.1)
        .filter(|f| {
            needs
                .indices(stages.len())
                .all(|i| stages[i].levels.contains(f))
        })
        .collect()
}

/// The stages that run at `fidelity` whatever the outputs ([`Stage::always`]).
fn always(stages: &[Stage], fidelity: Fidelity) -> Stages {
    stages
        .iter()
        .enumerate()
        .filter(|(_, s)| s.always && s.levels.contains(&fidelity))
        .fold(Stages::NONE, |acc, (i, _)| acc.or(Stages::bit(i as u32)))
}

/// Is this parameter set by the scene's own keys (`fidelity`, `[drive]`) rather than
/// `[parameters]`?
fn structural(vr: u32) -> bool {
    matches!(vr, shaft::MODE | shaft::N | shaft::PHI0 | shaft::FIDELITY)
}

/// The scene's value for a parameter declaration, type-checked.
pub(crate) fn value_of(v: &Var, x: &Value) -> Result<f64, String> {
    match (v.ty, x) {
        (VarType::Real, Value::Float(f)) => Ok(*f),
        (VarType::Real, Value::Int(i)) => Ok(*i as f64),
        (VarType::Integer, Value::Int(i)) => i32::try_from(*i)
            .map(f64::from)
            .map_err(|_| format!("{i} does not fit a 32-bit Integer")),
        (VarType::Boolean, Value::Bool(b)) => Ok(f64::from(u8::from(*b))),
        (VarType::Enumeration(t), Value::Text(s)) => t
            .items
            .iter()
            .position(|it| it.0 == s.as_str())
            .map(|p| (p + 1) as f64)
            .ok_or_else(|| {
                format!(
                    "{s:?} is not an item of {}; valid: {}",
                    t.name,
                    t.items.iter().map(|i| i.0).collect::<Vec<_>>().join(", ")
                )
            }),
        (ty, x) => Err(format!(
            "{x} is not a value of type {}",
            match ty {
                VarType::Real => "Real (a number)".to_string(),
                VarType::Integer => "Integer (a whole number)".to_string(),
                VarType::Boolean => "Boolean (true or false)".to_string(),
                VarType::Enumeration(t) => format!(
                    "{} (one of {})",
                    t.name,
                    t.items.iter().map(|i| i.0).collect::<Vec<_>>().join(", ")
                ),
            }
        )),
    }
}

/// Holds a scene against mechanism `M`: refuses an output or parameter it does not have (with
/// the nearest valid names), an output its fidelity does not compute (naming the levels that
/// do), a value of the wrong type or out of bounds, and a set the mechanism cannot assemble
/// with; otherwise the tailored FMU's variables, start values, stages and description.
pub fn tailor<M: Model>(scene: &Scene) -> Result<Tailored, SceneError> {
    if scene.mechanism != M::IDENTIFIER {
        return Err(scene.unknown_mechanism(&[M::IDENTIFIER]));
    }
    let table = <M::Var as VarSet>::table();
    let stages = M::STAGES;
    let vr_of = |name: &str| table.iter().position(|v| v.name == name);
    // a name the model does not have, with the nearest of the valid ones
    let unknown = |key: String, span: &Range<usize>, what: &str, name: &str, valid: &[&str]| {
        let near = nearest(name, valid);
        scene.error_at(
            key,
            span,
            format!("{} has no {what} {name:?}; {near}", M::IDENTIFIER),
        )
    };
    // a mechanism is driven through the shaft connector and has levels; a drive (MainShaft)
    // turns the shaft itself and has neither
    let driven = shaft::is_driven::<M::Var>();
    let fid = match (driven, scene.fidelity) {
        (true, Some(f)) => Some(f),
        (true, None) => {
            return Err(SceneError {
                key: "fidelity".into(),
                line: None,
                message: format!(
                    "missing: a scene of {} needs `fidelity` (kinematic, kinetostatic or elastodynamic)",
                    M::IDENTIFIER
                ),
            });
        }
        (false, Some(_)) => {
            return Err(scene.error_at(
                "fidelity",
                &scene.spans.fidelity,
                format!(
                    "{} has no fidelity levels (it drives the shaft): leave `fidelity` out",
                    M::IDENTIFIER
                ),
            ));
        }
        (false, None) => None,
    };
    let is_structural = |vr: u32| driven && structural(vr);
    if !driven && !scene.spans.drive.is_empty() {
        return Err(scene.error_at(
            "drive",
            &scene.spans.drive,
            format!(
                "{} drives the shaft itself: a scene of it has no [drive]",
                M::IDENTIFIER
            ),
        ));
    }

    // ---- outputs: exist, are outputs (or calculated parameters), computed at this fidelity
    let output_names: Vec<&str> = table
        .iter()
        .filter(|v| {
            matches!(
                v.causality,
                Causality::Output | Causality::CalculatedParameter
            )
        })
        .map(|v| v.name)
        .collect();
    let mut wanted = vec![false; table.len()];
    for (i, (name, span)) in scene.outputs.iter().enumerate() {
        let key = format!("outputs[{i}]");
        let Some(vr) = vr_of(name) else {
            return Err(unknown(key, span, "output", name, &output_names));
        };
        let v = &table[vr];
        if !matches!(
            v.causality,
            Causality::Output | Causality::CalculatedParameter
        ) {
            return Err(scene.error_at(key, span, misplaced(name, v, "an output")));
        }
        let levels = levels_of(stages, v.needs);
        if let Some(fid) = fid
            && !levels.contains(&fid)
        {
            let names: Vec<&str> = levels.iter().map(|f| fidelity_name(*f)).collect();
            return Err(scene.error_at(
                key,
                span,
                format!(
                    "{name:?} is not computed at fidelity {:?}; {}",
                    fidelity_name(fid),
                    if names.is_empty() {
                        "no fidelity level of this mechanism computes it".to_string()
                    } else {
                        format!("it is at: {}", names.join(", "))
                    }
                ),
            ));
        }
        wanted[vr] = true;
    }

    // ---- the stages that run
    let mut needed = fid.map_or(Stages::NONE, |f| always(stages, f));
    for (vr, v) in table.iter().enumerate() {
        if wanted[vr] {
            needed = needed.or(v.needs);
        }
    }
    let needed = closure(stages, needed);
    // the checks that guard the user stay wherever what they check is computed
    let guards = stages
        .iter()
        .enumerate()
        .filter(|(_, s)| {
            s.guards && fid.is_some_and(|f| s.levels.contains(&f)) && needed.contains(s.requires)
        })
        .fold(Stages::NONE, |acc, (i, _)| acc.or(Stages::bit(i as u32)));
    let needed = closure(stages, needed.or(guards));
    // states and derivatives of the level (Model Exchange) come with the stages they belong to
    let locals: Vec<bool> = table
        .iter()
        .map(|v| {
            v.causality == Causality::Local && v.needs != Stages::NONE && needed.contains(v.needs)
        })
        .collect();

    // ---- start values: the scene's parameters, type- and bound-checked
    let mut values = Values::<M::Var>::start();
    let param_names: Vec<&str> = table
        .iter()
        .enumerate()
        .filter(|(vr, v)| v.causality == Causality::Parameter && !is_structural(*vr as u32))
        .map(|(_, v)| v.name)
        .collect();
    for (name, x, span) in &scene.parameters {
        let key = format!("parameters.{name:?}");
        let Some(vr) = vr_of(name) else {
            return Err(unknown(key, span, "parameter", name, &param_names));
        };
        let v = &table[vr];
        if v.causality != Causality::Parameter {
            return Err(scene.error_at(key, span, misplaced(name, v, "a parameter")));
        }
        if is_structural(vr as u32) {
            return Err(scene.error_at(
                key,
                span,
                format!(
                    "{name:?} is set by the scene's {} key, not under [parameters]",
                    if vr as u32 == shaft::FIDELITY {
                        "`fidelity`"
                    } else {
                        "[drive]"
                    }
                ),
            ));
        }
        let x = value_of(v, x).map_err(|m| scene.error_at(key.clone(), span, m))?;
        values.raw_mut()[vr] = x;
    }
    // the drive's phase: a parameter of the FMU when the scene sets it
    let phi0 = match scene.drive {
        Drive::Input { phi0 } => phi0,
        Drive::ConstantSpeed { phi0, .. } => Some(phi0),
    };
    if let Some(fid) = fid {
        let raw = values.raw_mut();
        raw[shaft::FIDELITY as usize] = fid as i32 as f64;
        if let Drive::ConstantSpeed { rpm, .. } = scene.drive {
            raw[shaft::MODE as usize] = 2.0;
            raw[shaft::N as usize] = std::f64::consts::PI * (rpm / 30.0);
        } else {
            raw[shaft::MODE as usize] = 1.0;
        }
        if let Some(phi0) = phi0 {
            raw[shaft::PHI0 as usize] = phi0;
        }
    }
    values.stages = needed;
    let param_error = |e: crate::model::ParamError| {
        let (key, span) = if e.param == "model.fidelity" {
            ("fidelity".to_string(), scene.spans.fidelity.clone())
        } else if let Some((n, _, s)) =
            scene
                .parameters
                .iter()
                .find(|p| p.0 == e.param)
                .or_else(|| {
                    // the mechanism blames one of its parameters for a condition that names the
                    // scene's (a rod shorter than the crank radius the scene set)
                    scene
                        .parameters
                        .iter()
                        .find(|p| e.condition.contains(p.0.as_str()))
                })
        {
            (format!("parameters.{n:?}"), s.clone())
        } else if e.param.starts_with("drive.") {
            ("drive".to_string(), scene.spans.drive.clone())
        } else {
            // a default the scene did not touch, refused with the scene's other values
            return SceneError {
                key: format!("parameters.{:?}", e.param),
                line: None,
                message: format!("refused by {} with this scene's values: {e}", M::IDENTIFIER),
            };
        };
        scene.error_at(key, &span, format!("refused by {}: {e}", M::IDENTIFIER))
    };
    check_bounds(&values).map_err(param_error)?;
    M::prepare(&values).map_err(param_error)?;

    // ---- which variables the FMU lists
    let constant_speed = matches!(scene.drive, Drive::ConstantSpeed { .. });
    let mut used_inputs = vec![false; table.len()];
    for (vr, v) in table.iter().enumerate() {
        if wanted[vr] {
            for &d in v.depends {
                used_inputs[d as usize] = true;
            }
        }
    }
    if <M::Var as VarSet>::SHAFT_CONNECTOR
        && (fid == Some(Fidelity::Elastodynamic)
            || [shaft::PHI, shaft::W, shaft::A]
                .iter()
                .any(|&i| used_inputs[i as usize]))
    {
        // a step moves the shaft from all three inputs (Model::step, at every level; the ODE
        // of the elastodynamic level on that path): an output of the angle alone at an instant
        // is, after the step, one of the angle, speed and acceleration at the step's start
        for i in [shaft::PHI, shaft::W, shaft::A] {
            used_inputs[i as usize] = true;
        }
    }
    let exposed: Vec<bool> = table
        .iter()
        .enumerate()
        .map(|(vr, v)| {
            let r = vr as u32;
            match v.causality {
                Causality::Output | Causality::CalculatedParameter => wanted[vr],
                Causality::Local => locals[vr],
                Causality::Input => {
                    used_inputs[vr]
                        && !(constant_speed && matches!(r, shaft::PHI | shaft::W | shaft::A))
                }
                Causality::Parameter => {
                    if is_structural(r) {
                        (constant_speed && r == shaft::N) || (phi0.is_some() && r == shaft::PHI0)
                    } else {
                        v.feeds == Stages::ALL || v.feeds.intersects(needed)
                    }
                }
            }
        })
        .collect();
    let start = values.raw().to_vec();
    let variables: Vec<(u32, Var)> = table
        .iter()
        .enumerate()
        .filter(|(vr, _)| exposed[*vr])
        .map(|(vr, v)| {
            let mut v = v.clone();
            if v.start.is_some() {
                v.start = Some(start[vr]);
            }
            (vr as u32, v)
        })
        .collect();
    let identifier = identifier(M::IDENTIFIER, &scene.name);
    let leak = |s: String| -> &'static str { crate::lifetime::keep(s).as_str() };
    let info = ModelInfo {
        identifier: leak(identifier.clone()),
        model_name: leak(identifier.clone()),
        description: leak(format!(
            "{} Tailored to the scene {:?}{}: only its outputs, the parameters and inputs they use.",
            M::DESCRIPTION,
            scene.name,
            fid.map_or(String::new(), |f| format!(" ({} level)", fidelity_name(f)))
        )),
        experiment: scene.experiment.unwrap_or(M::EXPERIMENT),
        event_indicators: M::EVENT_INDICATORS as u32,
        // input derivatives shape the shaft's path over a step at every level, and need the
        // shaft angle as an input (not with a constant-speed drive)
        can_interpolate_inputs: M::CAN_INTERPOLATE_INPUTS && exposed[shaft::PHI as usize],
        terminals: M::TERMINALS,
        variables: <M::Var as crate::model::VarSet>::table().len() as u32,
        partials: M::PARTIALS,
    };
    let refs: Vec<(u32, &Var)> = variables.iter().map(|(vr, v)| (*vr, v)).collect();
    let guid = md::guid::guid(&info, &refs);
    Ok(Tailored {
        scene: scene.clone(),
        identifier,
        info,
        exposed,
        start,
        variables,
        stages: needed,
        guid,
    })
}

/// [`fn@tailor`] from the text of a scene file.
pub fn tailor_text<M: Model>(text: &str) -> Result<Tailored, SceneError> {
    tailor::<M>(&Scene::parse(text)?)
}

/// The tailored FMU of the scene text, computed once per text and model type (an FMU's binary
/// reads `resources/scene.toml` at every `fmi2Instantiate`; describing takes milliseconds).
pub fn cached<M: Model>(text: &str) -> Result<std::sync::Arc<Tailored>, SceneError> {
    use std::sync::{Arc, Mutex};
    type Cache = Vec<(std::any::TypeId, u128, Arc<Tailored>)>;
    static CACHE: Mutex<Cache> = Mutex::new(Vec::new());
    let id = std::any::TypeId::of::<M>();
    let h = md::fnv1a_128(text.as_bytes());
    if let Some(t) = CACHE
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .iter()
        .find(|c| c.0 == id && c.1 == h)
    {
        return Ok(t.2.clone());
    }
    let t = Arc::new(tailor_text::<M>(text)?);
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if cache.is_empty() {
        crate::lifetime::on_release(|| {
            *CACHE.lock().unwrap_or_else(|e| e.into_inner()) = Vec::new();
        });
    }
    if cache.len() < 64 {
        cache.push((id, h, t.clone()));
    }
    Ok(t)
}

/// Why `name` cannot stand where the scene put it (`wanted`: "an output", "a parameter"):
/// what it is, and where it belongs if the scene may name it elsewhere.
fn misplaced(name: &str, v: &Var, wanted: &str) -> String {
    let (what, hint) = match v.causality {
        Causality::Parameter => ("a parameter", " (set it under [parameters])"),
        Causality::CalculatedParameter => ("a calculated parameter", " (list it under outputs)"),
        Causality::Output => ("an output", " (list it under outputs)"),
        Causality::Input => ("an input", ""),
        Causality::Local => ("a local variable", ""),
    };
    format!("{name:?} is {what}, not {wanted}{hint}")
}
