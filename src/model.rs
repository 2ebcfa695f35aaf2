//! The narrow interface every mechanism implements, and the variables it declares once.
//!
//! A model declares each of its variables exactly once, with [`model_variables!`]: name,
//! causality, variability, initial, start, unit, bounds, description and, for outputs, their
//! dependencies on the shaft inputs. From that one declaration
//! - the runtime ([`crate::fmi2`]) knows value references, types and which calls may set what;
//! - the exporter ([`crate::md`]) writes `modelDescription.xml` and derives the GUID;
//! - the model's own code reads and writes values by the generated enum (`values[V::knife_s]`).
//!
//! The shaft connector and the drive/fidelity parameters common to every mechanism
//! (`../shared/spec/interface.md`) are prepended by the macro, so every model has them at the
//! same value references ([`shaft`]). A model that drives the shaft instead (MainShaft) is
//! declared `standalone`: none of those are prepended, and the [`shaft`] helpers that read them
//! do not apply to it.
//!
//! Nothing here knows FFI: a model is plain Rust and is tested as such.

use std::marker::PhantomData;
use std::ops::{Index, IndexMut};

/// `causality` of an FMI 2.0 ScalarVariable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    Input,
    Output,
    Local,
}

/// `variability` of an FMI 2.0 ScalarVariable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    Constant,
    Fixed,
    Tunable,
    Discrete,
    Continuous,
}

/// `initial` of an FMI 2.0 ScalarVariable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Initial {
    Exact,
    Approx,
    Calculated,
}

/// An enumeration type: written to `TypeDefinitions`, referenced by `declaredType`.
#[derive(Debug, PartialEq)]
pub struct EnumType {
    pub name: &'static str,
    pub description: &'static str,
    /// `(item name, description)`; item values are 1, 2, ... in this order.
    pub items: &'static [(&'static str, &'static str)],
}

impl EnumType {
    /// The item with this value, if any.
    pub fn item(&self, value: i32) -> Option<&'static str> {
        usize::try_from(value - 1)
            .ok()
            .and_then(|i| self.items.get(i))
            .map(|it| it.0)
    }
}

/// The FMI base type of a variable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VarType {
    Real,
    Integer,
    Boolean,
    Enumeration(&'static EnumType),
}

impl VarType {
    /// Integer-valued types are read and written with `fmi2Get/SetInteger`.
    pub fn is_integer_like(self) -> bool {
        matches!(self, VarType::Integer | VarType::Enumeration(_))
    }
}

/// One declared variable. Built with the constructors below and refined with the builder
/// methods, e.g. `Var::parameter("crank.r", 0.07, "m", "...").min(0.0)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Var {
    pub name: &'static str,
    pub ty: VarType,
    pub causality: Causality,
    pub variability: Variability,
    pub initial: Option<Initial>,
    /// Start value (Integer, Boolean and Enumeration values are stored as exact `f64`).
    pub start: Option<f64>,
    pub unit: Option<&'static str>,
    pub display_unit: Option<&'static str>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    pub description: &'static str,
    /// For outputs: value references of the inputs the output depends on.
    pub depends: &'static [u32],
    /// For a state derivative (Model Exchange): the value reference of its state.
    pub derivative: Option<u32>,
    /// For outputs and locals: the computation stages ([`Model::STAGES`]) that produce it,
    /// beyond what always runs. A scene that does not ask for it may skip them (`scenes.md`).
    pub needs: Stages,
    /// For parameters: the stages whose results it influences ([`Stages::ALL`]: everything,
    /// the default). A scene keeps a parameter only if it feeds a stage the scene needs.
    pub feeds: Stages,
}

/// Units and their FMI display units (`interface.md`: deg for rad, mm for m, rpm for rad/s,
/// MPa for Pa).
pub fn default_display_unit(unit: &str) -> Option<&'static str> {
    match unit {
        "rad" => Some("deg"),
        "m" => Some("mm"),
        "rad/s" => Some("rpm"),
        "Pa" => Some("MPa"),
        _ => None,
    }
}

impl Var {
    fn base(
        name: &'static str,
        ty: VarType,
        causality: Causality,
        variability: Variability,
    ) -> Self {
        Var {
            name,
            ty,
            causality,
            variability,
            initial: None,
            start: None,
            unit: None,
            display_unit: None,
            min: None,
            max: None,
            description: "",
            depends: &[],
            derivative: None,
            needs: Stages::NONE,
            feeds: Stages::ALL,
        }
    }

    fn with_unit(mut self, unit: &'static str) -> Self {
        if !unit.is_empty() {
            self.unit = Some(unit);
            self.display_unit = default_display_unit(unit);
        }
        self
    }

    /// A fixed Real parameter with its default; `desc` says where the value comes from
    /// (a paper, or "assumption").
    pub fn parameter(
        name: &'static str,
        start: f64,
        unit: &'static str,
        desc: &'static str,
    ) -> Self {
        let mut v = Self::base(
            name,
            VarType::Real,
            Causality::Parameter,
            Variability::Fixed,
        )
        .with_unit(unit);
        v.start = Some(start);
        v.description = desc;
        v
    }

    /// A fixed Integer parameter.
    pub fn int_parameter(name: &'static str, start: i32, desc: &'static str) -> Self {
        let mut v = Self::base(
            name,
            VarType::Integer,
            Causality::Parameter,
            Variability::Fixed,
        );
        v.start = Some(start as f64);
        v.description = desc;
        v
    }

    /// A fixed Boolean parameter.
    pub fn bool_parameter(name: &'static str, start: bool, desc: &'static str) -> Self {
        let mut v = Self::base(
            name,
            VarType::Boolean,
            Causality::Parameter,
            Variability::Fixed,
        );
        v.start = Some(start as i32 as f64);
        v.description = desc;
        v
    }

    /// A fixed Enumeration parameter; `start` is the item's name.
    pub fn enum_parameter(
        name: &'static str,
        ty: &'static EnumType,
        start: &str,
        desc: &'static str,
    ) -> Self {
        let mut v = Self::base(
            name,
            VarType::Enumeration(ty),
            Causality::Parameter,
            Variability::Fixed,
        );
        let pos = ty
            .items
            .iter()
            .position(|it| it.0 == start)
            .expect("start item of an enumeration");
        v.start = Some((pos + 1) as f64);
        v.description = desc;
        v
    }

    /// A Real calculated parameter (a derived quantity the paper computes).
    pub fn calculated(name: &'static str, unit: &'static str, desc: &'static str) -> Self {
        let mut v = Self::base(
            name,
            VarType::Real,
            Causality::CalculatedParameter,
            Variability::Fixed,
        )
        .with_unit(unit);
        v.initial = Some(Initial::Calculated);
        v.description = desc;
        v
    }

    /// A continuous Real input with its start value.
    pub fn input(name: &'static str, start: f64, unit: &'static str, desc: &'static str) -> Self {
        let mut v = Self::base(
            name,
            VarType::Real,
            Causality::Input,
            Variability::Continuous,
        )
        .with_unit(unit);
        v.start = Some(start);
        v.description = desc;
        v
    }

    /// A continuous Real output.
    pub fn output(name: &'static str, unit: &'static str, desc: &'static str) -> Self {
        let mut v = Self::base(
            name,
            VarType::Real,
            Causality::Output,
            Variability::Continuous,
        )
        .with_unit(unit);
        v.initial = Some(Initial::Calculated);
        v.description = desc;
        v
    }

    /// A discrete Boolean output (a flag).
    pub fn bool_output(name: &'static str, desc: &'static str) -> Self {
        let mut v = Self::base(
            name,
            VarType::Boolean,
            Causality::Output,
            Variability::Discrete,
        );
        v.initial = Some(Initial::Calculated);
        v.description = desc;
        v
    }

    /// A discrete Integer output.
    pub fn int_output(name: &'static str, desc: &'static str) -> Self {
        let mut v = Self::base(
            name,
            VarType::Integer,
            Causality::Output,
            Variability::Discrete,
        );
        v.initial = Some(Initial::Calculated);
        v.description = desc;
        v
    }

    /// Lower bound (physics, not taste).
    pub fn min(mut self, min: f64) -> Self {
        self.min = Some(min);
        self
    }

    /// Upper bound.
    pub fn max(mut self, max: f64) -> Self {
        self.max = Some(max);
        self
    }

    /// Overrides the display unit.
    pub fn display(mut self, unit: &'static str) -> Self {
        self.display_unit = Some(unit);
        self
    }

    /// A continuous Real local variable: a Model Exchange state or state derivative.
    pub fn local(name: &'static str, unit: &'static str, desc: &'static str) -> Self {
        let mut v = Self::base(
            name,
            VarType::Real,
            Causality::Local,
            Variability::Continuous,
        )
        .with_unit(unit);
        v.initial = Some(Initial::Calculated);
        v.description = desc;
        v
    }

    /// Marks this variable as the derivative of the state with value reference `state`.
    pub fn derivative_of(mut self, state: u32) -> Self {
        self.derivative = Some(state);
        self
    }

    /// An output's dependencies on inputs (value references; see [`shaft::PHI`] etc.).
    pub fn depends(mut self, inputs: &'static [u32]) -> Self {
        self.depends = inputs;
        self
    }

    /// The stages ([`Model::STAGES`]) that compute this output or local (declared once, here,
    /// next to the variable: a scene leaves them out when it does not ask for the variable).
    pub fn needs(mut self, stages: Stages) -> Self {
        self.needs = stages;
        self
    }

    /// The stages this parameter influences (default: all). A scene whose outputs need none of
    /// them leaves the parameter out of its FMU (it keeps its default or scene value inside).
    pub fn feeds(mut self, stages: Stages) -> Self {
        self.feeds = stages;
        self
    }

    /// Is this variable one a host may set in the given phase?
    /// A value of this variable with its unit, and in its display unit where it has one:
    /// "20000 rad/s (190986 rpm)"; a value without a unit as is.
    pub fn quantity(&self, x: f64) -> String {
        let Some(unit) = self.unit.filter(|u| !u.is_empty()) else {
            return format!("{x}");
        };
        let display = self
            .display_unit
            .or_else(|| default_display_unit(unit))
            .and_then(|d| crate::md::display_factor(unit, d).map(|f| (d, f)));
        match display {
            Some((d, f)) if d != unit => format!("{x} {unit} ({} {d})", round_sig(f * x, 6)),
            _ => format!("{x} {unit}"),
        }
    }

    pub fn settable(&self, phase: SetPhase) -> bool {
        match phase {
            SetPhase::Instantiated => {
                self.variability != Variability::Constant
                    && (self.causality == Causality::Input
                        || matches!(
                            self.initial,
                            None | Some(Initial::Exact) | Some(Initial::Approx)
                        ) && matches!(self.causality, Causality::Parameter | Causality::Input))
            }
            SetPhase::Initialization => {
                matches!(self.causality, Causality::Parameter | Causality::Input)
                    && self.variability != Variability::Constant
            }
            SetPhase::Running => {
                self.causality == Causality::Input
                    || (self.causality == Causality::Parameter
                        && self.variability == Variability::Tunable)
            }
            SetPhase::ContinuousTime => self.causality == Causality::Input,
        }
    }
}

/// A set of computation stages of one model: bit `i` is [`Model::STAGES`]`[i]`. What always
/// runs (the kinematics every output rests on) is no stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Stages(pub u32);

impl Stages {
    /// Nothing beyond what always runs.
    pub const NONE: Stages = Stages(0);
    /// Every stage.
    pub const ALL: Stages = Stages(u32::MAX);
    /// The stage with index `i` in [`Model::STAGES`].
    pub const fn bit(i: u32) -> Stages {
        Stages(1 << i)
    }
    /// Union.
    pub const fn or(self, other: Stages) -> Stages {
        Stages(self.0 | other.0)
    }
    /// Does it share a stage with `other`?
    pub const fn intersects(self, other: Stages) -> bool {
        self.0 & other.0 != 0
    }
    /// Does it hold every stage of `other`?
    pub const fn contains(self, other: Stages) -> bool {
        self.0 & other.0 == other.0
    }
    /// The indices of its stages among `n`.
    pub fn indices(self, n: usize) -> impl Iterator<Item = usize> {
        (0..n.min(32)).filter(move |&i| self.0 & (1 << i) != 0)
    }
}

/// One computation of a model that a scene may leave out (`scenes.md`), e.g. the force analysis.
#[derive(Debug)]
pub struct Stage {
    /// Short name, e.g. `forces`.
    pub name: &'static str,
    /// What it computes and what it costs, for the tailored FMU's documentation.
    pub description: &'static str,
    /// The fidelity levels that compute it (an output that needs it exists only there).
    pub levels: &'static [shaft::Fidelity],
    /// Stages it needs the results of (they run whenever it runs).
    pub requires: Stages,
    /// It runs whenever its level is chosen, whatever the outputs (the level rests on it, as
    /// the elastodynamic level on its ODE).
    pub always: bool,
    /// It guards the user (a lift-off, self-locking or undercut check with its warning): a
    /// scene keeps it whenever the stages it requires run, whatever outputs it leaves out.
    pub guards: bool,
}

/// When a host tries to set a variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SetPhase {
    Instantiated,
    Initialization,
    /// After initialization: Co-Simulation, Model Exchange in event mode.
    Running,
    /// Model Exchange in continuous-time mode: only inputs.
    ContinuousTime,
}

impl SetPhase {
    pub const ALL: [SetPhase; 4] = [
        SetPhase::Instantiated,
        SetPhase::Initialization,
        SetPhase::Running,
        SetPhase::ContinuousTime,
    ];
}

/// The enum generated by [`model_variables!`]: one variant per variable; its discriminant is
/// the value reference.
pub trait VarSet: Copy + 'static {
    /// The model is driven through the shaft connector of [`shaft`] (its common variables come
    /// first); false for a model declared `standalone`, which drives a shaft instead.
    const SHAFT_CONNECTOR: bool;
    /// Every declaration, in value-reference order.
    fn table() -> &'static [Var];
    /// Value reference of this variable.
    fn vr(self) -> u32;
}

/// The names of a model's continuous states (Model Exchange), in the order of
/// `fmi2GetContinuousStates`: the variables its state derivatives are the derivatives of
/// ([`Var::derivative_of`]), in the order of the derivatives (the model description's
/// `<Derivatives>`).
pub fn state_names<V: VarSet>() -> Vec<&'static str> {
    let table = V::table();
    table
        .iter()
        .filter_map(|v| v.derivative)
        .map(|s| table[s as usize].name)
        .collect()
}

/// The current values of a model's variables, indexed by its [`VarSet`].
/// Integer, Boolean and Enumeration values are held as exact `f64`.
#[derive(Clone, Debug, PartialEq)]
pub struct Values<V: VarSet> {
    data: Vec<f64>,
    /// The computation stages the outputs in use need ([`Stages::ALL`] in the full FMU; a
    /// scene's tailored FMU narrows it). [`Model::prepare`] and [`Model::evaluate`] skip what is
    /// not in it.
    pub stages: Stages,
    /// Time derivatives of Real inputs a host set with `fmi2SetRealInputDerivatives`, as
    /// `(value reference, order, value)`, for the next communication step only
    /// ([`shaft::path`] reads those of the shaft; see `interface.md`).
    input_derivatives: Vec<(u32, u32, f64)>,
    /// The time at which the host last set an input (the runtime records it; the start time
    /// until then). An input is the value at that instant: a model may move it on with time
    /// from there ([`shaft::state`]).
    pub inputs_at: f64,
    _v: PhantomData<V>,
}

impl<V: VarSet> Default for Values<V> {
    fn default() -> Self {
        Self::start()
    }
}

impl<V: VarSet> Values<V> {
    /// Every variable at its declared start value (0 where there is none).
    pub fn start() -> Self {
        Values {
            data: V::table().iter().map(|v| v.start.unwrap_or(0.0)).collect(),
            stages: Stages::ALL,
            input_derivatives: Vec::new(),
            inputs_at: 0.0,
            _v: PhantomData,
        }
    }
    /// Is anything that reads the results of these stages in use? (The full FMU: always.)
    #[inline]
    pub fn wants(&self, stages: Stages) -> bool {
        self.stages.intersects(stages)
    }
    /// An Integer or Enumeration value.
    pub fn int(&self, v: V) -> i32 {
        self.data[v.vr() as usize] as i32
    }
    /// A Boolean value.
    pub fn flag(&self, v: V) -> bool {
        self.data[v.vr() as usize] != 0.0
    }
    /// Sets a Boolean value.
    pub fn set_flag(&mut self, v: V, b: bool) {
        self.data[v.vr() as usize] = if b { 1.0 } else { 0.0 };
    }
    /// All values by value reference (for the runtime and state serialization).
    pub fn raw(&self) -> &[f64] {
        &self.data
    }
    /// All values by value reference, mutable.
    pub fn raw_mut(&mut self) -> &mut [f64] {
        &mut self.data
    }
    /// The derivative of order `order` of the input `vr` a host set for the next step, if any.
    pub fn input_derivative(&self, vr: u32, order: u32) -> Option<f64> {
        self.input_derivatives
            .iter()
            .find(|d| d.0 == vr && d.1 == order)
            .map(|d| d.2)
    }
    /// Sets (or replaces) the derivative of order `order` of the input `vr`. The runtime checks
    /// that `vr` is a Real input, `order` in `1..=`[`MAX_INPUT_DERIVATIVE_ORDER`] and `x` finite.
    pub fn set_input_derivative(&mut self, vr: u32, order: u32, x: f64) {
        match self
            .input_derivatives
            .iter_mut()
            .find(|d| d.0 == vr && d.1 == order)
        {
            Some(d) => d.2 = x,
            None => self.input_derivatives.push((vr, order, x)),
        }
    }
    /// Every input derivative set, as `(value reference, order, value)`, in the order set.
    pub fn input_derivatives(&self) -> &[(u32, u32, f64)] {
        &self.input_derivatives
    }
    /// Forgets the input derivatives (they applied to one communication step).
    pub fn clear_input_derivatives(&mut self) {
        self.input_derivatives.clear();
    }
}

/// Highest order of input derivative `fmi2SetRealInputDerivatives` accepts: the shaft angle is
/// extrapolated with a parabola, `phi(t0 + dt) = phi + phi'*dt + phi''*dt^2/2`
/// (`dynamics.md`). FMI 2.0 has no attribute for it in `modelDescription.xml`
/// (`fmi2ModelDescription.xsd` defines `maxOutputDerivativeOrder` only), so a higher order is
/// refused at the call with this number in the message.
pub const MAX_INPUT_DERIVATIVE_ORDER: u32 = 2;

impl<V: VarSet> Index<V> for Values<V> {
    type Output = f64;
    fn index(&self, v: V) -> &f64 {
        &self.data[v.vr() as usize]
    }
}

impl<V: VarSet> IndexMut<V> for Values<V> {
    fn index_mut(&mut self, v: V) -> &mut f64 {
        &mut self.data[v.vr() as usize]
    }
}

/// `DefaultExperiment` of the model description.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Experiment {
    pub start: f64,
    pub stop: f64,
    pub step: f64,
    pub tolerance: Option<f64>,
}

/// A parameter set the mechanism cannot work with (defined with the shared mechanics).
pub use crate::mechanics::ParamError;

/// Checks every parameter against its declared `min`/`max` (and an Enumeration against its
/// items): the first violation, named.
pub fn check_bounds<V: VarSet>(values: &Values<V>) -> Result<(), ParamError> {
    for (v, &x) in V::table().iter().zip(values.raw()) {
        if v.causality != Causality::Parameter {
            continue;
        }
        let fail = |condition: String| {
            Err(ParamError {
                param: v.name,
                value: x,
                condition,
            })
        };
        if !x.is_finite() {
            return fail("must be finite".into());
        }
        if let Some(lo) = v.min
            && x < lo
        {
            return fail(format!(
                "{} must be at least {}",
                v.quantity(x),
                v.quantity(lo)
            ));
        }
        if let Some(hi) = v.max
            && x > hi
        {
            return fail(format!(
                "{} must be at most {}",
                v.quantity(x),
                v.quantity(hi)
            ));
        }
        if let VarType::Enumeration(t) = v.ty
            && t.item(x as i32).is_none()
        {
            return fail(format!(
                "is not an item of {} (1..={})",
                t.name,
                t.items.len()
            ));
        }
    }
    Ok(())
}

/// `x` to `digits` significant digits (for messages).
fn round_sig(x: f64, digits: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

/// Severity of a message a model emits while it runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    Info,
    Warning,
}

/// Where a model sends messages (events, warnings such as a roller lifting off).
pub trait Log {
    fn log(&mut self, severity: Severity, message: &str);
}

/// A sink that drops every message (for plain-Rust use of a model).
pub struct NoLog;
impl Log for NoLog {
    fn log(&mut self, _: Severity, _: &str) {}
}

/// The narrow interface a mechanism implements to become an FMU.
///
/// The runtime calls [`Model::prepare`] once parameters are final (exit of initialization
/// mode, or lazily during it) and [`Model::evaluate`] whenever an output is read after an
/// input, the time or a parameter changed (lazy outputs).
pub trait Model: Sized + Send + 'static {
    /// The variable enum generated by [`model_variables!`].
    type Var: VarSet;
    /// `modelIdentifier`, also the binary's name.
    const IDENTIFIER: &'static str;
    /// `modelName` attribute.
    const MODEL_NAME: &'static str;
    /// `description` attribute: one sentence on what the mechanism is, and its paper.
    const DESCRIPTION: &'static str;
    /// `DefaultExperiment`.
    const EXPERIMENT: Experiment;

    /// The computations a scene may leave out, in bit order of [`Stages`] (`scenes.md`); the
    /// variables say which they need ([`Var::needs`]) or feed ([`Var::feeds`]). None: every
    /// output is computed whenever the fidelity level computes it.
    const STAGES: &'static [Stage] = &[];

    /// Checks the parameters and derives what stays fixed during a run.
    fn prepare(values: &Values<Self::Var>) -> Result<Self, ParamError>;

    /// Computes calculated parameters and every output at time `time` from the inputs.
    fn evaluate(&mut self, values: &mut Values<Self::Var>, time: f64, log: &mut dyn Log);

    /// Writes the calculated parameters, once after each [`Model::prepare`] (they depend on the
    /// parameters only). A model that writes them here need not repeat them in every
    /// [`Model::evaluate`], which is on the per-step path.
    fn calculated_parameters(&self, _values: &mut Values<Self::Var>) {}

    /// Advances internal state (if any) from `time` over `h`, the shaft following
    /// [`shaft::path`] from the inputs at `time`; algebraic models need nothing. A host calls
    /// [`Model::step`], which also brings the inputs to the end of the step.
    fn do_step(
        &mut self,
        _values: &mut Values<Self::Var>,
        _time: f64,
        _h: f64,
        _log: &mut dyn Log,
    ) -> Result<(), String> {
        Ok(())
    }

    /// One Co-Simulation communication step from `time` over `h`, what `fmi2DoStep` does at
    /// every fidelity level: [`Model::do_step`], then the inputs at the end of the step, until
    /// the host sets them. For a model driven through the shaft connector the shaft has moved
    /// along the path the step followed ([`shaft::end_of_step`]), so the outputs evaluated at
    /// `time + h` are those of the end of the step, as a Model Exchange host that sets the
    /// inputs at `time + h` sees them; a model that drives the shaft itself (`standalone`)
    /// holds its inputs. A path that leaves the finite numbers refuses the step before it is
    /// taken.
    fn step(
        &mut self,
        values: &mut Values<Self::Var>,
        time: f64,
        h: f64,
        log: &mut dyn Log,
    ) -> Result<(), String> {
        let end = if <Self::Var as VarSet>::SHAFT_CONNECTOR {
            shaft::end_of_step(values, time, h)?
        } else {
            None
        };
        self.do_step(values, time, h, log)?;
        if let Some(end) = end {
            shaft::set_inputs(values, end, time + h);
        }
        Ok(())
    }

    /// Model Exchange: number of continuous states (their derivatives are declared with
    /// [`Var::derivative_of`], in the order of the states). 0: no Model Exchange interface.
    const STATES: usize = 0;
    /// Model Exchange: number of event indicators.
    const EVENT_INDICATORS: usize = 0;

    /// `canInterpolateInputs`: `fmi2SetRealInputDerivatives` has an effect: every fidelity
    /// level moves the shaft over a step along [`shaft::path`], which takes them, and ends the
    /// step where it leads ([`Model::step`]). By default the models driven through the shaft
    /// connector; not a `standalone` one, whose inputs are held over a step.
    const CAN_INTERPOLATE_INPUTS: bool = <Self::Var as VarSet>::SHAFT_CONNECTOR;

    /// Does a step use the derivative of order `order` of the input `vr` a host set with
    /// `fmi2SetRealInputDerivatives`? `None`: yes; else why it is kept but not used (the
    /// runtime warns with it). By default those the shaft's path takes
    /// ([`shaft::uses_input_derivative`]).
    fn unused_input_derivative(vr: u32, order: u32) -> Option<&'static str> {
        (!shaft::uses_input_derivative(vr, order)).then_some(
            "inside a step the shaft angle follows a parabola from shaft.phi and the derivatives of shaft.phi (orders 1, 2) and shaft.w (order 1); other inputs are held",
        )
    }

    /// Model Exchange: the continuous states at `time`.
    fn me_states(&mut self, _values: &Values<Self::Var>, _time: f64, _x: &mut [f64]) {}

    /// Model Exchange: sets the continuous states.
    fn me_set_states(&mut self, _values: &Values<Self::Var>, _time: f64, _x: &[f64]) {}

    /// Model Exchange: the state derivatives at `time` for the current states and inputs.
    fn me_derivatives(&mut self, _values: &Values<Self::Var>, _time: f64, _dx: &mut [f64]) {}

    /// Model Exchange: the event indicators (an event is a sign change of one of them).
    fn me_event_indicators(&mut self, _values: &Values<Self::Var>, _time: f64, _z: &mut [f64]) {}

    /// Model Exchange: an event at `time` (discrete modes switch here).
    fn me_event(&mut self, _values: &Values<Self::Var>, _time: f64, _log: &mut dyn Log) {}

    /// Model Exchange: the host completed an integrator step at `time`. What a Co-Simulation
    /// step tracks over its span (turn statistics, step counters, what happened during the
    /// step) a model tracks here over the span since the last completed step, so that an output
    /// means the same in both interfaces.
    fn me_completed_step(&mut self, _values: &Values<Self::Var>, _time: f64, _log: &mut dyn Log) {}
    /// The run ends (`fmi2Terminate`): what the model gathered and has not reported yet (the
    /// warnings of an unfinished shaft turn) is logged. Default: nothing.
    fn finish(&mut self, _values: &Values<Self::Var>, _log: &mut dyn Log) {}

    /// Internal state beyond the variables, for `fmi2GetFMUstate` and serialization.
    fn save_state(&self) -> Vec<f64> {
        Vec::new()
    }

    /// Restores what [`Model::save_state`] returned.
    fn restore_state(&mut self, _state: &[f64]) -> Result<(), String> {
        Ok(())
    }
}

/// Which common variable is which: the shaft connector and the drive and fidelity parameters
/// that [`model_variables!`] puts first in every model (`interface.md`).
pub mod shaft {
    use super::{EnumType, Values, Var, VarSet};
    use std::f64::consts::PI;

    /// Value reference of `shaft.phi`.
    pub const PHI: u32 = 0;
    /// Value reference of `shaft.w`.
    pub const W: u32 = 1;
    /// Value reference of `shaft.a`.
    pub const A: u32 = 2;
    /// Value reference of `shaft.tau`.
    pub const TAU: u32 = 3;
    /// Value reference of `shaft.P`.
    pub const P: u32 = 4;
    /// Value reference of `drive.mode`.
    pub const MODE: u32 = 5;
    /// Value reference of `drive.n`.
    pub const N: u32 = 6;
    /// Value reference of `drive.phi0`.
    pub const PHI0: u32 = 7;
    /// Value reference of `model.fidelity`.
    pub const FIDELITY: u32 = 8;
    /// How many common variables precede a model's own.
    pub const COUNT: usize = 9;

    /// Is `V` driven through the shaft connector, with the common variables at these value
    /// references (a mechanism), rather than declared `standalone` (a drive such as MainShaft)?
    pub fn is_driven<V: VarSet>() -> bool {
        V::table()
            .get(FIDELITY as usize)
            .is_some_and(|v| v.name == "model.fidelity")
    }

    /// Dependencies of a position: the angle only.
    pub const ON_PHI: &[u32] = &[PHI];
    /// Dependencies of a velocity.
    pub const ON_PHI_W: &[u32] = &[PHI, W];
    /// Dependencies of an acceleration, force or torque.
    pub const ON_ALL: &[u32] = &[PHI, W, A];

    /// `drive.mode`.
    pub static DRIVE_MODE: EnumType = EnumType {
        name: "DriveMode",
        description: "What drives the mechanism's shaft",
        items: &[
            ("input", "the inputs shaft.phi, shaft.w, shaft.a"),
            (
                "constant_speed",
                "the FMU itself, at drive.n from drive.phi0; the inputs are ignored",
            ),
        ],
    };

    /// `model.fidelity`.
    pub static FIDELITY_LEVEL: EnumType = EnumType {
        name: "Fidelity",
        description: "Level of physics computed",
        items: &[
            (
                "kinematic",
                "positions, velocities, accelerations: closed form, exact",
            ),
            (
                "kinetostatic",
                "as kinematic, plus forces and torques from Newton-Euler on rigid links",
            ),
            (
                "elastodynamic",
                "compliant drive chain and contacts: an ODE integrated inside fmi2DoStep",
            ),
        ],
    };

    /// The fidelity levels, as `model.fidelity` values.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum Fidelity {
        Kinematic = 1,
        Kinetostatic = 2,
        Elastodynamic = 3,
    }

    /// The common declarations; `nominal_rpm` is the machine's nominal speed.
    pub fn declarations(nominal_rpm: f64) -> Vec<Var> {
        let w0 = PI * (nominal_rpm / 30.0);
        vec![
            Var::input(
                "shaft.phi",
                0.0,
                "rad",
                "Angle of the mechanism's driving shaft at the instant it is set; until set again the shaft turns on at shaft.w and shaft.a (unconnected: from 0 at the nominal speed)",
            ),
            Var::input(
                "shaft.w",
                w0,
                "rad/s",
                "Angular velocity of the driving shaft (start: nominal speed)",
            ),
            Var::input(
                "shaft.a",
                0.0,
                "rad/s2",
                "Angular acceleration of the driving shaft",
            ),
            Var::output(
                "shaft.tau",
                "N.m",
                "Torque the mechanism requires at its shaft",
            )
            .depends(ON_ALL),
            Var::output(
                "shaft.P",
                "W",
                "Power drawn at the shaft, shaft.tau*shaft.w",
            )
            .depends(ON_ALL),
            Var::enum_parameter(
                "drive.mode",
                &DRIVE_MODE,
                "input",
                "input: driven by the shaft inputs; constant_speed: runs alone at drive.n",
            ),
            Var::parameter(
                "drive.n",
                w0,
                "rad/s",
                "Speed in constant_speed mode (assumption: nominal speed of the machine)",
            )
            .min(-1e4)
            .max(1e4),
            Var::parameter(
                "drive.phi0",
                0.0,
                "rad",
                "Phase of the mechanism on its shaft: in constant_speed mode the shaft angle at time 0; in input mode added to shaft.phi (a mechanism mounted phase-shifted on a main shaft)",
            ),
            Var::enum_parameter(
                "model.fidelity",
                &FIDELITY_LEVEL,
                "kinetostatic",
                "Level of physics: kinematic, kinetostatic or elastodynamic",
            ),
        ]
    }

    /// The shaft's state at an instant: angle, speed, acceleration.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct ShaftState {
        pub phi: f64,
        pub w: f64,
        pub a: f64,
    }

    /// The shaft state at `time`. In `input` mode the inputs are the shaft's angle, speed and
    /// acceleration at the instant the host set them ([`Values::inputs_at`]); until it sets
    /// them again the shaft moves on from there along [`inputs_path`] (at that speed and
    /// acceleration, or the input derivatives a host set for a step), in Co-Simulation and
    /// Model Exchange alike: with no input connected the mechanism turns at the start value of
    /// `shaft.w`, its nominal speed. The angle is shifted by `drive.phi0` (the phase the
    /// mechanism is mounted with on a main shaft). In `constant_speed` mode:
    /// `drive.phi0 + drive.n*t`.
    pub fn state<V: VarSet>(values: &Values<V>, time: f64) -> ShaftState {
        let raw = values.raw();
        if raw[MODE as usize] == 2.0 {
            let w = raw[N as usize];
            ShaftState {
                phi: raw[PHI0 as usize] + w * time,
                w,
                a: 0.0,
            }
        } else if time == values.inputs_at {
            ShaftState {
                phi: raw[PHI as usize] + raw[PHI0 as usize],
                w: raw[W as usize],
                a: raw[A as usize],
            }
        } else {
            let p = inputs_path(values);
            let (_, w, a) = p.at(time);
            ShaftState {
                phi: p.absolute_phi(time),
                w,
                a,
            }
        }
    }

    /// The path the shaft inputs describe from the instant they were set (`input` mode):
    /// `phi(t) = phi + phi'*dt + phi''*dt^2/2` (`dt = t - inputs_at`, `phi` with `drive.phi0`),
    /// with `phi'` and `phi''` the input derivatives a host set with
    /// `fmi2SetRealInputDerivatives` (a derivative of order 1 of `shaft.w` is `phi''` too) and
    /// else `shaft.w` and `shaft.a`.
    pub fn inputs_path<V: VarSet>(values: &Values<V>) -> crate::solver::ShaftPath {
        let raw = values.raw();
        let w = values.input_derivative(PHI, 1).unwrap_or(raw[W as usize]);
        let a = values
            .input_derivative(PHI, 2)
            .or_else(|| values.input_derivative(W, 1))
            .unwrap_or(raw[A as usize]);
        crate::solver::ShaftPath::new(
            values.inputs_at,
            raw[PHI as usize] + raw[PHI0 as usize],
            w,
            a,
        )
    }

    /// The shaft's path over a communication step from `time`, for an integration inside
    /// `fmi2DoStep` (`dynamics.md`): [`inputs_path`] from `time` on, or in `constant_speed`
    /// mode the drive's (the inputs and their derivatives ignored, [`state`]).
    pub fn path<V: VarSet>(values: &Values<V>, time: f64) -> crate::solver::ShaftPath {
        if values.raw()[MODE as usize] == 2.0 {
            let s = state(values, time);
            return crate::solver::ShaftPath::new(time, s.phi, s.w, s.a);
        }
        let p = inputs_path(values);
        if time == values.inputs_at {
            p
        } else {
            let (_, w, a) = p.at(time);
            crate::solver::ShaftPath::new(time, p.absolute_phi(time), w, a)
        }
    }

    /// The shaft inputs at the end of a Co-Simulation step from `time` over `h`: where the
    /// step's [`path`] leads at `time + h` (with the input derivatives a host set for the step),
    /// `phi` without `drive.phi0` (the input's meaning; [`state`] adds it). None in
    /// `constant_speed` mode (the inputs are ignored); an error naming the inputs if the path
    /// leaves the finite numbers (a step of 1e300 s).
    pub fn end_of_step<V: VarSet>(
        values: &Values<V>,
        time: f64,
        h: f64,
    ) -> Result<Option<ShaftState>, String> {
        let raw = values.raw();
        if raw[MODE as usize] == 2.0 {
            return Ok(None);
        }
        let p = path(values, time);
        let (_, w, a) = p.at(time + h);
        let phi = p.absolute_phi(time + h) - raw[PHI0 as usize];
        if !(phi.is_finite() && w.is_finite()) {
            return Err(format!(
                "the shaft's path from shaft.phi = {}, shaft.w = {}, shaft.a = {} leads to shaft.phi = {phi}, shaft.w = {w} at the end of the step: take a shorter step",
                raw[PHI as usize], p.w, p.a
            ));
        }
        Ok(Some(ShaftState { phi, w, a }))
    }

    /// Sets the shaft inputs (`phi` without `drive.phi0`) as those of the instant `time`, e.g.
    /// those of [`end_of_step`].
    pub fn set_inputs<V: VarSet>(values: &mut Values<V>, s: ShaftState, time: f64) {
        let raw = values.raw_mut();
        raw[PHI as usize] = s.phi;
        raw[W as usize] = s.w;
        raw[A as usize] = s.a;
        values.inputs_at = time;
    }

    /// Does [`path`] use the derivative of order `order` of the input `vr`? (The others a host
    /// may set are accepted and ignored with a warning: the path is a parabola in time.)
    pub fn uses_input_derivative(vr: u32, order: u32) -> bool {
        matches!((vr, order), (PHI, 1) | (PHI, 2) | (W, 1))
    }

    /// The chosen fidelity level.
    pub fn fidelity<V: VarSet>(values: &Values<V>) -> Fidelity {
        match values.raw()[FIDELITY as usize] as i32 {
            1 => Fidelity::Kinematic,
            3 => Fidelity::Elastodynamic,
            _ => Fidelity::Kinetostatic,
        }
    }

    /// Refuses a fidelity level the mechanism does not implement (yet).
    pub fn require_level<V: VarSet>(
        values: &Values<V>,
        supported: &[Fidelity],
    ) -> Result<(), super::ParamError> {
        let f = fidelity(values);
        if supported.contains(&f) {
            Ok(())
        } else {
            Err(super::ParamError {
                param: "model.fidelity",
                value: values.raw()[FIDELITY as usize],
                condition: format!("the level {f:?} is not implemented for this mechanism"),
            })
        }
    }

    /// Writes the shaft outputs.
    pub fn set_outputs<V: VarSet>(values: &mut Values<V>, tau: f64, w: f64) {
        let raw = values.raw_mut();
        raw[TAU as usize] = tau;
        raw[P as usize] = tau * w;
    }

    /// `shaft.J_red`: the coefficient of `shaft.a` in `shaft.tau`, for a drive that solves its
    /// shaft's acceleration with the load's inertia (MainShaft's `load*.J_red`). `depends`: as
    /// `shaft.tau` less `shaft.a` (it is the torque's slope in `shaft.a`, not a function of it).
    pub fn j_red_var(depends: &'static [u32]) -> Var {
        Var::output(
            "shaft.J_red",
            "kg.m2",
            "Moment of inertia reduced to the shaft: shaft.tau = shaft.tau0 + shaft.J_red*shaft.a, the torque's slope in shaft.a between a = 0 and a = 1 rad/s2 (exact where friction does not depend on shaft.a; at the elastodynamic level only the rigid links between the shaft and the compliance)",
        )
        .depends(depends)
    }

    /// `shaft.tau0`: the torque at zero shaft acceleration (`depends`: as for [`j_red_var`]).
    pub fn tau0_var(depends: &'static [u32]) -> Var {
        Var::output(
            "shaft.tau0",
            "N.m",
            "Torque the mechanism requires at its shaft with shaft.a = 0 (same angle, speed and state): shaft.tau = shaft.tau0 + shaft.J_red*shaft.a",
        )
        .depends(depends)
    }

    /// The split `τ(a) = τ0 + J_red·a` of a shaft torque: `τ0` the torque at zero shaft
    /// acceleration, `J_red` the reduced moment of inertia (kg·m²).
    #[derive(Clone, Copy, Debug, Default, PartialEq)]
    pub struct Reduced {
        pub tau0: f64,
        pub j_red: f64,
    }

    impl Reduced {
        /// `τ0 + J_red·a`.
        pub fn torque(&self, a: f64) -> f64 {
            self.tau0 + self.j_red * a
        }
    }

    /// Splits a shaft torque `τ(a)` (the mechanism's own torque at the same angle, speed and
    /// internal state, as a function of the shaft acceleration) into `τ0 = τ(0)` and
    /// `J_red = τ(1) − τ(0)`. Newton–Euler on rigid links makes every inertia force linear in
    /// the shaft acceleration (`a_x = x''(φ)·ω² + x'(φ)·ε`), so `τ` is affine in `ε` and the split
    /// is exact, except where a Coulomb friction force or a mesh efficiency changes regime
    /// (sign of a normal force or of the power flow) between `ε = 0`, `1` and the actual `ε`:
    /// there `J_red` is the secant of the piecewise-affine `τ(ε)` over `[0, 1]` rad/s².
    #[inline]
    pub fn reduce(mut torque_at: impl FnMut(f64) -> f64) -> Reduced {
        let tau0 = torque_at(0.0);
        Reduced {
            tau0,
            j_red: torque_at(1.0) - tau0,
        }
    }

    /// As [`reduce`], given the torque `tau_a` already computed at the actual shaft
    /// acceleration `a`: one more evaluation instead of two (none more for `tau0` at `a = 0`, the
    /// constant-speed case). For `|a| ≥ 1` rad/s² `J_red` is the secant over `[0, a]`, so
    /// `τ0 + J_red·a` is the actual torque exactly even where friction changes regime; below,
    /// the secant over `[0, 1]` as in [`reduce`] (no division by a small `a`).
    #[inline]
    pub fn reduce_at(tau_a: f64, a: f64, mut torque_at: impl FnMut(f64) -> f64) -> Reduced {
        if a.abs() >= 1.0 {
            let tau0 = torque_at(0.0);
            Reduced {
                tau0,
                j_red: (tau_a - tau0) / a,
            }
        } else if a == 0.0 {
            Reduced {
                tau0: tau_a,
                j_red: torque_at(1.0) - tau_a,
            }
        } else {
            reduce(torque_at)
        }
    }

    /// Writes `shaft.J_red` and `shaft.tau0`.
    pub fn set_reduced<V: VarSet>(values: &mut Values<V>, j_red: V, tau0: V, r: Reduced) {
        values[j_red] = r.j_red;
        values[tau0] = r.tau0;
    }
}

/// Declares a model's variables once: an enum whose variants are the variables (discriminant =
/// value reference) and the table of their declarations. The shaft connector and the common
/// parameters ([`shaft`]) come first.
///
/// ```ignore
/// model_variables! {
///     pub enum V (nominal_rpm = 30.0) {
///         crank_r = Var::parameter("crank.r", 0.07, "m", "crank radius r2 (assumption)").min(0.0),
///         knife_s = Var::output("knife.s", "m", "knife displacement from the top").depends(shaft::ON_PHI),
///     }
/// }
/// ```
#[macro_export]
macro_rules! model_variables {
    ($vis:vis enum $name:ident (nominal_rpm = $rpm:expr) { $( $id:ident = $decl:expr ),* $(,)? }) => {
        $crate::model_variables! {
            $vis enum $name (nominal_rpm = $rpm, torque_depends = $crate::model::shaft::ON_ALL, torque_needs = $crate::model::Stages::NONE) { $( $id = $decl ),* }
        }
    };
    // `torque_needs`: the stages that compute `shaft.tau` and `shaft.P` (`Var::needs`).
    ($vis:vis enum $name:ident (nominal_rpm = $rpm:expr, torque_needs = $needs:expr) { $( $id:ident = $decl:expr ),* $(,)? }) => {
        $crate::model_variables! {
            $vis enum $name (nominal_rpm = $rpm, torque_depends = $crate::model::shaft::ON_ALL, torque_needs = $needs) { $( $id = $decl ),* }
        }
    };
    ($vis:vis enum $name:ident (nominal_rpm = $rpm:expr, torque_depends = $dep:expr) { $( $id:ident = $decl:expr ),* $(,)? }) => {
        $crate::model_variables! {
            $vis enum $name (nominal_rpm = $rpm, torque_depends = $dep, torque_needs = $crate::model::Stages::NONE) { $( $id = $decl ),* }
        }
    };
    // A model that drives a shaft instead of being driven by one (MainShaft): no shaft connector
    // and no drive/fidelity parameters prepended; the helpers of [`shaft`] do not apply to it.
    ($vis:vis enum $name:ident (standalone) { $( $id:ident = $decl:expr ),* $(,)? }) => {
        #[allow(non_camel_case_types, dead_code)]
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        #[repr(u32)]
        $vis enum $name {
            $( $id ),*
        }
        impl $crate::model::VarSet for $name {
            const SHAFT_CONNECTOR: bool = false;
            fn table() -> &'static [$crate::model::Var] {
                static TABLE: ::std::sync::OnceLock<&'static [$crate::model::Var]> = ::std::sync::OnceLock::new();
                TABLE.get_or_init(|| {
                    #[allow(unused_imports)]
                    use $crate::model::{Var, shaft};
                    $crate::lifetime::keep(vec![$( $decl ),*]).as_slice()
                })
            }
            #[inline]
            fn vr(self) -> u32 {
                self as u32
            }
        }
    };
    // `torque_depends`: the inputs `shaft.tau` and `shaft.P` depend on, when a model has inputs
    // besides the shaft connector (e.g. an external force on a member).
    ($vis:vis enum $name:ident (nominal_rpm = $rpm:expr, torque_depends = $dep:expr, torque_needs = $needs:expr) { $( $id:ident = $decl:expr ),* $(,)? }) => {
        #[allow(non_camel_case_types, dead_code)]
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        #[repr(u32)]
        $vis enum $name {
            shaft_phi, shaft_w, shaft_a, shaft_tau, shaft_P, drive_mode, drive_n, drive_phi0, model_fidelity,
            $( $id ),*
        }
        impl $crate::model::VarSet for $name {
            const SHAFT_CONNECTOR: bool = true;
            fn table() -> &'static [$crate::model::Var] {
                static TABLE: ::std::sync::OnceLock<&'static [$crate::model::Var]> = ::std::sync::OnceLock::new();
                TABLE.get_or_init(|| {
                    #[allow(unused_imports)]
                    use $crate::model::{Var, shaft};
                    let mut t = shaft::declarations($rpm);
                    t.extend([$( $decl ),*]);
                    t[shaft::TAU as usize].depends = $dep;
                    t[shaft::P as usize].depends = $dep;
                    t[shaft::TAU as usize].needs = $needs;
                    t[shaft::P as usize].needs = $needs;
                    $crate::lifetime::keep(t).as_slice()
                })
            }
            #[inline]
            fn vr(self) -> u32 {
                self as u32
            }
        }
    };
}

#[cfg(test)]
#[path = "model_tests.rs"]
mod tests;
