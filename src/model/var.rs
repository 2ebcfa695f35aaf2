//! The declaration of a variable ([`Var`]: name, type, causality, variability, start, unit,
//! bounds, dependencies, stages) and of a model's set of them ([`VarSet`], written by
//! [`crate::model_variables!`]).

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

use Causality::{CalculatedParameter, Input, Local, Output, Parameter};
use Variability::{Continuous, Discrete, Fixed};

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
        // any i32 a host passes: `value - 1` overflows at i32::MIN
        value
            .checked_sub(1)
            .and_then(|i| usize::try_from(i).ok())
            .and_then(|i| self.items.get(i))
            .map(|it| it.0)
    }
}

/// Declares a Rust enum and its FMI enumeration type once: the variants are the items 1, 2, ...
/// in order (checked at compile time), `FMI` is the [`EnumType`] a variable's `declaredType`
/// names, and `from_item` gives the variant of an item.
///
/// ```ignore
/// crate::fmi_enum! {
///     /// `contact.law`.
///     pub enum ContactLaw ("ContactLaw", "Force law of the ramp contact") {
///         /// Hertz line contact.
///         Hertz = 1 ("hertz", "Hertz line contact K*pen^(10/9)"),
///         Linear = 2 ("linear", "linear spring contact.k*pen"),
///     }
/// }
/// ```
#[macro_export]
macro_rules! fmi_enum {
    (
        $( #[$meta:meta] )*
        $vis:vis enum $name:ident ($fmi_name:literal, $fmi_description:literal) {
            $( $( #[$vmeta:meta] )* $variant:ident = $item:literal ($item_name:literal, $item_description:expr) ),+ $(,)?
        }
    ) => {
        $( #[$meta] )*
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        $vis enum $name {
            $( $( #[$vmeta] )* #[doc = $item_description] $variant = $item ),+
        }

        impl $name {
            /// The FMI enumeration type: item `i` is the variant `= i`.
            pub const FMI: $crate::model::EnumType = $crate::model::EnumType {
                name: $fmi_name,
                description: $fmi_description,
                items: &[$( ($item_name, $item_description) ),+],
            };
            const _ITEMS_IN_ORDER: () = {
                let mut i = 1;
                $(
                    assert!($item == i, "the items are numbered 1, 2, ... in order");
                    i += 1;
                )+
                let _ = i;
            };

            /// The variant of FMI item `item`, if any.
            pub fn from_item(item: i32) -> Option<Self> {
                let () = Self::_ITEMS_IN_ORDER;
                match item {
                    $( $item => Some($name::$variant), )+
                    _ => None,
                }
            }

            /// The item's name.
            pub fn name(self) -> &'static str {
                Self::FMI.items[self as usize - 1].0
            }
        }
    };
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
    /// For outputs and locals: the computation stages ([`super::Model::STAGES`]) that produce it,
    /// beyond what always runs. A scene that does not ask for it may skip them (`scenes.md`).
    pub needs: Stages,
    /// For a discrete output: its change is an event of the mechanism (a phase boundary, the
    /// Geneva roller entering or leaving a slot, a lift-off). An FMI 3.0 Co-Simulation step
    /// that may return early stops where it changes ([`Var::event`]).
    pub event: bool,
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
    /// A variable of this type, causality and variability, described by `desc`. Its `initial`
    /// follows from the causality: `calculated` for outputs, locals and calculated parameters
    /// (the FMU computes them), none for parameters and inputs (their start value is exact).
    fn base(
        name: &'static str,
        desc: &'static str,
        (ty, causality, variability): (VarType, Causality, Variability),
    ) -> Self {
        let computed = matches!(
            causality,
            Causality::Output | Causality::Local | Causality::CalculatedParameter
        );
        Var {
            name,
            ty,
            causality,
            variability,
            initial: computed.then_some(Initial::Calculated),
            start: None,
            unit: None,
            display_unit: None,
            min: None,
            max: None,
            description: desc,
            depends: &[],
            derivative: None,
            needs: Stages::NONE,
            feeds: Stages::ALL,
            event: false,
        }
    }

    fn with_unit(mut self, unit: &'static str) -> Self {
        if !unit.is_empty() {
            self.unit = Some(unit);
            self.display_unit = default_display_unit(unit);
        }
        self
    }

    fn with_start(mut self, start: f64) -> Self {
        self.start = Some(start);
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
        Self::base(name, desc, (VarType::Real, Parameter, Fixed))
            .with_unit(unit)
            .with_start(start)
    }

    /// A fixed Integer parameter.
    pub fn int_parameter(name: &'static str, start: i32, desc: &'static str) -> Self {
        Self::base(name, desc, (VarType::Integer, Parameter, Fixed)).with_start(start as f64)
    }

    /// A fixed Boolean parameter.
    pub fn bool_parameter(name: &'static str, start: bool, desc: &'static str) -> Self {
        Self::base(name, desc, (VarType::Boolean, Parameter, Fixed)).with_start(start as i32 as f64)
    }

    /// A fixed Enumeration parameter; `start` is the item's name.
    pub fn enum_parameter(
        name: &'static str,
        ty: &'static EnumType,
        start: &str,
        desc: &'static str,
    ) -> Self {
        let pos = ty
            .items
            .iter()
            .position(|it| it.0 == start)
            .expect("start item of an enumeration");
        Self::base(name, desc, (VarType::Enumeration(ty), Parameter, Fixed))
            .with_start((pos + 1) as f64)
    }

    /// A Real calculated parameter (a derived quantity the paper computes).
    pub fn calculated(name: &'static str, unit: &'static str, desc: &'static str) -> Self {
        Self::base(name, desc, (VarType::Real, CalculatedParameter, Fixed)).with_unit(unit)
    }

    /// A continuous Real input with its start value.
    pub fn input(name: &'static str, start: f64, unit: &'static str, desc: &'static str) -> Self {
        Self::base(name, desc, (VarType::Real, Input, Continuous))
            .with_unit(unit)
            .with_start(start)
    }

    /// A continuous Real output.
    pub fn output(name: &'static str, unit: &'static str, desc: &'static str) -> Self {
        Self::base(name, desc, (VarType::Real, Output, Continuous)).with_unit(unit)
    }

    /// A discrete Boolean output (a flag).
    pub fn bool_output(name: &'static str, desc: &'static str) -> Self {
        Self::base(name, desc, (VarType::Boolean, Output, Discrete))
    }

    /// A discrete Integer output.
    pub fn int_output(name: &'static str, desc: &'static str) -> Self {
        Self::base(name, desc, (VarType::Integer, Output, Discrete))
    }

    /// A continuous Real local variable: a Model Exchange state or state derivative.
    pub fn local(name: &'static str, unit: &'static str, desc: &'static str) -> Self {
        Self::base(name, desc, (VarType::Real, Local, Continuous)).with_unit(unit)
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

    /// Marks this variable as the derivative of the state with value reference `state`.
    pub fn derivative_of(mut self, state: u32) -> Self {
        self.derivative = Some(state);
        self
    }

    /// An output's dependencies on inputs (value references; see [`super::shaft::PHI`] etc.).
    /// Marks a discrete output whose change is an event of the mechanism ([`Var::event`]).
    pub fn event(mut self) -> Self {
        debug_assert!(
            self.ty != VarType::Real,
            "{}: only a discrete output marks events",
            self.name
        );
        self.event = true;
        self
    }

    pub fn depends(mut self, inputs: &'static [u32]) -> Self {
        self.depends = inputs;
        self
    }

    /// The stages ([`super::Model::STAGES`]) that compute this output or local (declared once,
    /// here, next to the variable: a scene leaves them out when it does not ask for the variable).
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
            .and_then(|d| super::units::display_factor(unit, d).map(|f| (d, f)));
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

/// The fidelity levels, as `model.fidelity` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fidelity {
    Kinematic = 1,
    Kinetostatic = 2,
    Elastodynamic = 3,
}

impl Fidelity {
    /// Every level.
    pub const ALL: &'static [Fidelity] = &[
        Fidelity::Kinematic,
        Fidelity::Kinetostatic,
        Fidelity::Elastodynamic,
    ];
    /// The levels that compute forces.
    pub const WITH_FORCES: &'static [Fidelity] = &[Fidelity::Kinetostatic, Fidelity::Elastodynamic];
    /// The elastodynamic level.
    pub const DYNAMIC: &'static [Fidelity] = &[Fidelity::Elastodynamic];
}

/// A set of computation stages of one model: bit `i` is [`super::Model::STAGES`]`[i]`. What always
/// runs (the kinematics every output rests on) is no stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Stages(pub u32);

impl Stages {
    /// Nothing beyond what always runs.
    pub const NONE: Stages = Stages(0);
    /// Every stage.
    pub const ALL: Stages = Stages(u32::MAX);
    /// The stage with index `i` in [`super::Model::STAGES`].
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
    pub levels: &'static [Fidelity],
    /// Stages it needs the results of (they run whenever it runs).
    pub requires: Stages,
    /// It runs whenever its level is chosen, whatever the outputs (the level rests on it, as
    /// the elastodynamic level on its ODE).
    pub always: bool,
    /// It guards the user (a lift-off, self-locking or undercut check with its warning): a
    /// scene keeps it whenever the stages it requires run, whatever outputs it leaves out.
    pub guards: bool,
}

impl Stage {
    /// A stage computed at `levels`, requiring no other, run only when an output needs it.
    pub const fn new(
        name: &'static str,
        description: &'static str,
        levels: &'static [Fidelity],
    ) -> Stage {
        Stage {
            name,
            description,
            levels,
            requires: Stages::NONE,
            always: false,
            guards: false,
        }
    }
    /// It needs the results of `stages`.
    pub const fn requires(self, stages: Stages) -> Stage {
        Stage {
            requires: stages,
            ..self
        }
    }
    /// It runs whenever its level is chosen ([`Stage::always`]).
    pub const fn always(self) -> Stage {
        Stage {
            always: true,
            ..self
        }
    }
    /// It guards the user ([`Stage::guards`]).
    pub const fn guards(self) -> Stage {
        Stage {
            guards: true,
            ..self
        }
    }
}

/// Declares a model's computation stages once (`scenes.md`): the module `stage` with one
/// [`Stages`] bit per stage, in the order declared, and named unions of them, and the table
/// `STAGES` the model returns as [`super::Model::STAGES`].
///
/// ```ignore
/// stages! {
///     FORCES = Stage::new("forces", "Kinetostatic force analysis", Fidelity::WITH_FORCES),
///     ELASTIC = Stage::new("elastic", "The ODE of the chain", Fidelity::DYNAMIC).always();
///     /// What the loads feed.
///     LOADS = FORCES.or(ELASTIC),
/// }
/// ```
#[macro_export]
macro_rules! stages {
    ( $( $id:ident = $stage:expr ),+ ; $( $(#[$doc:meta])* $union:ident = $value:expr ),* $(,)? ) => {
        /// The computations a scene may leave out (`scenes.md`): one bit per stage of
        /// [`STAGES`], and unions of them; the variables say which they need (`.needs`) or
        /// feed (`.feeds`). The kinematics always run.
        pub mod stage {
            #[allow(unused_imports)]
            use $crate::model::Stages;
            $crate::stages!(@bits 0; $( $id )+);
            $( $(#[$doc])* pub const $union: Stages = $value; )*
        }
        /// The stages of [`stage`], in bit order.
        pub static STAGES: &[$crate::model::Stage] = &[ $( $stage ),+ ];
    };
    (@bits $n:expr; ) => {};
    (@bits $n:expr; $first:ident $( $rest:ident )*) => {
        /// A stage of [`super::STAGES`], in the order declared.
        pub const $first: Stages = Stages::bit($n);
        $crate::stages!(@bits $n + 1; $( $rest )*);
    };
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

/// The enum generated by [`crate::model_variables!`]: one variant per variable; its discriminant is
/// the value reference.
pub trait VarSet: Copy + 'static {
    /// The model is driven through the shaft connector of [`super::shaft`] (its common variables
    /// come first); false for a model declared `standalone`, which drives a shaft instead.
    const SHAFT_CONNECTOR: bool;
    /// Every declaration, in value-reference order.
    fn table() -> &'static [Var];
    /// Value reference of this variable.
    fn vr(self) -> u32;
    /// Every variable, in value-reference order (`ALL[vr]` is the variable of `vr`).
    const ALL: &'static [Self];
}

/// The variables of a model type, by value reference.
pub fn variables_of<M: super::Model>() -> Vec<(u32, &'static Var)> {
    <M::Var as VarSet>::table()
        .iter()
        .enumerate()
        .map(|(i, v)| (i as u32, v))
        .collect()
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

/// `x` to `digits` significant digits (for messages).
fn round_sig(x: f64, digits: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

/// Declares a model's variables once: an enum whose variants are the variables (discriminant =
/// value reference) and the table of their declarations. The shaft connector and the common
/// parameters ([`super::shaft`]) come first.
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
    // ---- the forms a model writes: normalized, then the list is read item by item
    ($vis:vis enum $name:ident (nominal_rpm = $rpm:expr) { $( $body:tt )* }) => {
        $crate::model_variables!(@munch [$vis $name (connector $rpm, $crate::model::shaft::ON_ALL, $crate::model::Stages::NONE)] [] $( $body )*);
    };
    // `torque_needs`: the stages that compute `shaft.tau` and `shaft.P` (`Var::needs`).
    ($vis:vis enum $name:ident (nominal_rpm = $rpm:expr, torque_needs = $needs:expr) { $( $body:tt )* }) => {
        $crate::model_variables!(@munch [$vis $name (connector $rpm, $crate::model::shaft::ON_ALL, $needs)] [] $( $body )*);
    };
    // `torque_depends`: the inputs `shaft.tau` and `shaft.P` depend on, when a model has inputs
    // besides the shaft connector (e.g. an external force on a member).
    ($vis:vis enum $name:ident (nominal_rpm = $rpm:expr, torque_depends = $dep:expr) { $( $body:tt )* }) => {
        $crate::model_variables!(@munch [$vis $name (connector $rpm, $dep, $crate::model::Stages::NONE)] [] $( $body )*);
    };
    ($vis:vis enum $name:ident (nominal_rpm = $rpm:expr, torque_depends = $dep:expr, torque_needs = $needs:expr) { $( $body:tt )* }) => {
        $crate::model_variables!(@munch [$vis $name (connector $rpm, $dep, $needs)] [] $( $body )*);
    };
    // A model that drives a shaft instead of being driven by one (MainShaft): no shaft connector
    // and no drive/fidelity parameters prepended; the helpers of [`shaft`] do not apply to it.
    ($vis:vis enum $name:ident (standalone) { $( $body:tt )* }) => {
        $crate::model_variables!(@munch [$vis $name (standalone)] [] $( $body )*);
    };

    // ---- reading the list: `id = declaration`, or `@with block_macro { ... }`, a block of
    // variables another macro declares (e.g. [`crate::chain_variables!`]): it is called back with
    // what was read so far and hands the list on with its variables added
    (@munch $head:tt [ $( $done:tt )* ]) => {
        $crate::model_variables!(@emit $head $( $done )*);
    };
    (@munch $head:tt [ $( $done:tt )* ] @with $block:path { $( $args:tt )* } $( , $( $rest:tt )* )?) => {
        $block!(@callback $head [ $( $done )* ] { $( $args )* } $( $( $rest )* )?);
    };
    (@munch $head:tt [ $( $done:tt )* ] $id:ident = $decl:expr $( , $( $rest:tt )* )?) => {
        $crate::model_variables!(@munch $head [ $( $done )* ($id = $decl) ] $( $( $rest )* )?);
    };

    // ---- the enum and its table
    (@emit [$vis:vis $name:ident (standalone)] $( ($id:ident = $decl:expr) )*) => {
        $crate::model_variables!(@set $vis $name false [ $( $id, )* ] {
            vec![$( $decl ),*]
        });
    };
    (@emit [$vis:vis $name:ident (connector $rpm:expr, $dep:expr, $needs:expr)] $( ($id:ident = $decl:expr) )*) => {
        $crate::model_variables!(@set $vis $name true [
            shaft_phi, shaft_w, shaft_a, shaft_tau, shaft_P, drive_mode, drive_n, drive_phi0, model_fidelity,
            shaft_J_red, shaft_tau0,
            $( $id, )*
        ] {
            let mut t = shaft::declarations($rpm);
            t.extend([$( $decl ),*]);
            t[shaft::TAU as usize].depends = $dep;
            t[shaft::P as usize].depends = $dep;
            t[shaft::TAU as usize].needs = $needs;
            t[shaft::P as usize].needs = $needs;
            // the torque split: its slope in shaft.a and its value at a = 0 depend on the rest
            let split: Vec<u32> = $dep.iter().copied().filter(|&vr| vr != shaft::A).collect();
            let split = $crate::lifetime::keep(split).as_slice();
            for vr in [shaft::J_RED, shaft::TAU0] {
                t[vr as usize].depends = split;
                t[vr as usize].needs = $needs;
            }
            t
        });
    };
    (@set $vis:vis $name:ident $connector:literal [ $( $id:ident, )* ] { $( $table:tt )* }) => {
        #[allow(non_camel_case_types, dead_code)]
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        #[repr(u32)]
        $vis enum $name {
            $( $id ),*
        }
        impl $crate::model::VarSet for $name {
            const SHAFT_CONNECTOR: bool = $connector;
            const ALL: &'static [Self] = &[$( $name::$id ),*];
            fn table() -> &'static [$crate::model::Var] {
                static TABLE: ::std::sync::OnceLock<&'static [$crate::model::Var]> = ::std::sync::OnceLock::new();
                TABLE.get_or_init(|| {
                    #[allow(unused_imports)]
                    use $crate::model::{Var, shaft};
                    $crate::lifetime::keep({ $( $table )* }).as_slice()
                })
            }
            #[inline]
            fn vr(self) -> u32 {
                self as u32
            }
        }
    };
}
