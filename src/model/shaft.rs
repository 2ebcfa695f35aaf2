//! Which common variable is which: the shaft connector (with its torque split) and the drive and
//! fidelity parameters that [`crate::model_variables!`] puts first in every model (`interface.md`).

use super::{EnumType, Values, Var, VarSet};
use crate::mechanics::Scalar;
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
/// Value reference of `shaft.J_red` ([`Reduced`]).
pub const J_RED: u32 = 9;
/// Value reference of `shaft.tau0` ([`Reduced`]).
pub const TAU0: u32 = 10;
/// How many common variables precede a model's own.
pub const COUNT: usize = 11;

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

pub use super::var::Fidelity;

/// A terminal: variables a host connects as one connector, each under a member name (FMI 3.0's
/// `terminalsAndIcons.xml`, matching rule `plug`: the members of two terminals are connected by
/// name).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Terminal {
    pub name: &'static str,
    pub description: &'static str,
    /// (member name, variable name).
    pub members: &'static [(&'static str, &'static str)],
}

/// The terminal kind of the shaft terminals: a rotational flange as Modelica's
/// `GeneralAngleToTorqueAdaptor` presents it (angle, speed and acceleration one way, the cut
/// torque of the flange, positive into the mechanism, the other).
pub const TERMINAL_KIND: &str = "org.modelica.mechanics.rotational.flange.angle_to_torque";

/// The terminals of every mechanism driven through the shaft connector: the flange (`tau`, the
/// torque the mechanism needs) and the flange with the torque split (`tau0`, `J_red`) for a
/// drive that solves its acceleration with the mechanism's inertia (MainShaft's `load1`..).
pub const TERMINALS: &[Terminal] = &[
    Terminal {
        name: "shaft",
        description: "The driving shaft as a rotational flange: angle, speed and acceleration in, the torque the mechanism needs out (connect to MainShaft's load)",
        members: &[
            ("phi", "shaft.phi"),
            ("w", "shaft.w"),
            ("a", "shaft.a"),
            ("tau", "shaft.tau"),
        ],
    },
    Terminal {
        name: "shaft_reduced",
        description: "The driving shaft with the torque split shaft.tau = tau0 + J_red*a: angle, speed and acceleration in, tau0 and J_red out (connect to one of MainShaft's load1, load2, load3)",
        members: &[
            ("phi", "shaft.phi"),
            ("w", "shaft.w"),
            ("a", "shaft.a"),
            ("tau0", "shaft.tau0"),
            ("J_red", "shaft.J_red"),
        ],
    },
];

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
        j_red_var(),
        tau0_var(),
    ]
}

/// The shaft's state at an instant: angle, speed, acceleration (any [`Scalar`]: `f64`, or dual
/// numbers along the inputs for the partial derivatives).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShaftState<T = f64> {
    pub phi: T,
    pub w: T,
    pub a: T,
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
    state_of(values, time, |vr| values.raw()[vr as usize])
}

/// [`state`] with the inputs `shaft.phi`, `shaft.w`, `shaft.a` as `input` reads them by value
/// reference: plain, or seeded dual numbers whose dual part carries the derivative along the
/// inputs (the exact partial derivatives, [`super::partials`]). The parameters and the input
/// derivatives a host set are constants.
pub fn state_of<V: VarSet, T: Scalar>(
    values: &Values<V>,
    time: f64,
    input: impl Fn(u32) -> T,
) -> ShaftState<T> {
    let raw = values.raw();
    if raw[MODE as usize] == 2.0 {
        let w = T::from(raw[N as usize]);
        ShaftState {
            phi: w * time + raw[PHI0 as usize],
            w,
            a: T::zero(),
        }
    } else if time == values.inputs_at {
        ShaftState {
            phi: input(PHI) + raw[PHI0 as usize],
            w: input(W),
            a: input(A),
        }
    } else {
        let p = inputs_path_of(values, &input);
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
pub fn inputs_path<V: VarSet>(values: &Values<V>) -> ShaftPath {
    inputs_path_of(values, &|vr| values.raw()[vr as usize])
}

/// [`inputs_path`] with the inputs as `input` reads them ([`state_of`]).
fn inputs_path_of<V: VarSet, T: Scalar>(
    values: &Values<V>,
    input: &impl Fn(u32) -> T,
) -> ShaftPath<T> {
    let raw = values.raw();
    let w = values
        .input_derivative(PHI, 1)
        .map_or_else(|| input(W), T::from);
    let a = values
        .input_derivative(PHI, 2)
        .or_else(|| values.input_derivative(W, 1))
        .map_or_else(|| input(A), T::from);
    ShaftPath::new(values.inputs_at, input(PHI) + raw[PHI0 as usize], w, a)
}

/// The shaft's path over a communication step from `time`, for an integration inside
/// `fmi2DoStep` (`dynamics.md`): [`inputs_path`] from `time` on, or in `constant_speed`
/// mode the drive's (the inputs and their derivatives ignored, [`state`]).
pub fn path<V: VarSet>(values: &Values<V>, time: f64) -> ShaftPath {
    path_of(values, time, &|vr| values.raw()[vr as usize])
}

/// [`path`] with the inputs as `input` reads them ([`state_of`]: plain, or seeded dual numbers
/// for the partial derivatives).
pub fn path_of<V: VarSet, T: Scalar>(
    values: &Values<V>,
    time: f64,
    input: &impl Fn(u32) -> T,
) -> ShaftPath<T> {
    if values.raw()[MODE as usize] == 2.0 {
        let s = state_of(values, time, input);
        return ShaftPath::new(time, s.phi, s.w, s.a);
    }
    let p = inputs_path_of(values, input);
    if time == values.inputs_at {
        p
    } else {
        let (_, w, a) = p.at(time);
        ShaftPath::new(time, p.absolute_phi(time), w, a)
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
/// shaft's acceleration with the load's inertia (MainShaft's `load*.J_red`). It depends on
/// what `shaft.tau` depends on less `shaft.a` (it is the torque's slope in `shaft.a`, not a
/// function of it; [`crate::model_variables!`] sets that).
fn j_red_var() -> Var {
    Var::output(
        "shaft.J_red",
        "kg.m2",
        "Moment of inertia reduced to the shaft: shaft.tau = shaft.tau0 + shaft.J_red*shaft.a, the torque's slope in shaft.a between a = 0 and a = 1 rad/s2 (exact where friction does not depend on shaft.a; at the elastodynamic level only the rigid links between the shaft and the compliance)",
    )
}

/// `shaft.tau0`: the torque at zero shaft acceleration (depends: as [`j_red_var`]).
fn tau0_var() -> Var {
    Var::output(
        "shaft.tau0",
        "N.m",
        "Torque the mechanism requires at its shaft with shaft.a = 0 (same angle, speed and state): shaft.tau = shaft.tau0 + shaft.J_red*shaft.a",
    )
}

/// The split `τ(a) = τ0 + J_red·a` of a shaft torque: `τ0` the torque at zero shaft
/// acceleration, `J_red` the reduced moment of inertia (kg·m²).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Reduced<T = f64> {
    pub tau0: T,
    pub j_red: T,
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
pub fn reduce<T: Scalar>(mut torque_at: impl FnMut(T) -> T) -> Reduced<T> {
    let tau0 = torque_at(T::zero());
    Reduced {
        tau0,
        j_red: torque_at(T::one()) - tau0,
    }
}

/// As [`reduce`], given the torque `tau_a` already computed at the actual shaft
/// acceleration `a`: one more evaluation instead of two (none more for `tau0` at `a = 0`, the
/// constant-speed case). For `|a| ≥ 1` rad/s² `J_red` is the secant over `[0, a]`, so
/// `τ0 + J_red·a` is the actual torque exactly even where friction changes regime; below,
/// the secant over `[0, 1]` as in [`reduce`] (no division by a small `a`). Any [`Scalar`]: the
/// shortcut at `a = 0` is `f64`'s; a dual `a` below 1 rad/s² takes the split of [`reduce`],
/// whose `τ0` does not depend on `a`, as the values about `a = 0` do (a dual's `==` compares
/// the values only: `tau_a` seeded along `shaft.a` would give `τ0` the slope `J_red`).
#[inline]
pub fn reduce_at<T: Scalar>(tau_a: T, a: T, mut torque_at: impl FnMut(T) -> T) -> Reduced<T> {
    if a.re().abs() >= 1.0 {
        let tau0 = torque_at(T::zero());
        Reduced {
            tau0,
            j_red: (tau_a - tau0) / a,
        }
    } else {
        reduce_at_rest(tau_a, a, torque_at)
    }
}

/// [`reduce`], given the torque `tau_a` already computed at the actual shaft acceleration `a`:
/// at a constant speed (`a` exactly 0, `f64`) that is `τ0`, and one evaluation remains; else
/// [`reduce`] as it is. The split of the elastodynamic levels, whose `τ0` and `J_red` stay
/// [`reduce`]'s at every `a` (the secant of [`reduce_at`] over `[0, a]` would take the
/// difference of two torques large against `J_red·a` at a large `a`).
#[inline]
pub fn reduce_at_rest<T: Scalar>(tau_a: T, a: T, mut torque_at: impl FnMut(T) -> T) -> Reduced<T> {
    if T::NDERIV == 0 && a.re() == 0.0 {
        Reduced {
            tau0: tau_a,
            j_red: torque_at(T::one()) - tau_a,
        }
    } else {
        reduce(torque_at)
    }
}

/// Writes `shaft.J_red` and `shaft.tau0`.
pub fn set_reduced<V: VarSet>(values: &mut Values<V>, r: Reduced) {
    let raw = values.raw_mut();
    raw[J_RED as usize] = r.j_red;
    raw[TAU0 as usize] = r.tau0;
}

/// The shaft outputs of a rigid level at the shaft state `s`: at the kinetostatic level `tau`,
/// the torque at the actual acceleration, and its split by [`reduce_at`] with `torque_at`, the
/// torque at another acceleration; at the kinematic level (`None`) no torque and no split.
pub fn set_rigid_torque<V: VarSet>(
    values: &mut Values<V>,
    s: &ShaftState,
    tau: Option<f64>,
    torque_at: impl FnMut(f64) -> f64,
) {
    rigid_torque(s, tau, torque_at, |var, x| values[var] = x);
}

/// [`set_rigid_torque`] for any [`Scalar`], as `put(variable, value)`: `shaft.J_red`,
/// `shaft.tau0` ([`reduce_at`]), `shaft.tau` and `shaft.P = shaft.tau*shaft.w` of a model
/// driven through the shaft connector (its common variables at their value references).
#[inline]
pub fn rigid_torque<V: VarSet, T: Scalar>(
    s: &ShaftState<T>,
    tau: Option<T>,
    torque_at: impl FnMut(T) -> T,
    mut put: impl FnMut(V, T),
) {
    let mut put = |vr: u32, x| put(V::ALL[vr as usize], x);
    let r = match tau {
        Some(tau) => reduce_at(tau, s.a, torque_at),
        None => Reduced {
            tau0: T::zero(),
            j_red: T::zero(),
        },
    };
    put(J_RED, r.j_red);
    put(TAU0, r.tau0);
    let tau = tau.unwrap_or(T::zero());
    put(TAU, tau);
    put(P, tau * s.w);
}

/// The shaft's motion inside a communication step, extrapolated from its state at the step's
/// start: `φ(t0 + τ) = φ0 + ω0·τ + ε0·τ²/2` (or the input derivatives a host set, which are the
/// same Taylor coefficients).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShaftPath<T = f64> {
    pub t0: f64,
    /// The angle at `t0` less `turns` whole turns, in `[0, 2π)`: a shaft angle near 1e9 rad
    /// would otherwise add its rounding noise (1e-7 rad) to every stage of the integrator.
    pub phi: T,
    pub w: T,
    pub a: T,
    /// Whole turns taken out of the angle.
    pub turns: f64,
}

impl<T: Scalar> ShaftPath<T> {
    /// The path from the shaft state at `t0`.
    pub fn new(t0: f64, phi: T, w: T, a: T) -> Self {
        let turns = (phi.re() / std::f64::consts::TAU).floor();
        let red = phi - turns * std::f64::consts::TAU;
        ShaftPath {
            t0,
            phi: red,
            w,
            a,
            turns,
        }
    }

    /// Index of the shaft turn at time `t` (`floor(φ/2π)`).
    pub fn cycle(&self, t: f64) -> f64 {
        self.turns + (self.at(t).0.re() / std::f64::consts::TAU).floor()
    }

    /// The absolute angle at `t` (with the whole turns).
    pub fn absolute_phi(&self, t: f64) -> T {
        self.at(t).0 + self.turns * std::f64::consts::TAU
    }

    /// `(φ, ω, ε)` at time `t`.
    #[inline]
    pub fn at(&self, t: f64) -> (T, T, T) {
        let tau = t - self.t0;
        (
            self.phi + self.w * tau + self.a * 0.5 * tau * tau,
            self.w + self.a * tau,
            self.a,
        )
    }
}
