//! The skeleton of a mechanism's elastodynamic level (`../shared/spec/dynamics.md`): a compliant
//! chain between the rigid motion φ(t) of the shaft and one body, integrated by [`Integrator`]
//! inside `fmi2DoStep` (Co-Simulation) or handed to the host as three continuous states (Model
//! Exchange).
//!
//! A mechanism implements [`ChainModel`]: its ODE (an [`OdeSystem`] that carries its
//! bookkeeping, peaks of the chain force, K_d, contact counters..., in a `Cell`), how that
//! bookkeeping (the [`ChainModel::Memory`]) starts, is read back from the ODE and is laid out in
//! the FMU state snapshot, and what it does at events and steps where the common pattern does not
//! fit. [`Chain`] holds what every mechanism carries between steps (integrator, states, initial
//! energy, Model Exchange indicators); the free functions of this module are the hooks of
//! [`crate::model::Model`] (`do_step`, `me_*`, `save_state`/`restore_state`) for a model with an
//! `Option<Chain<_>>` (`None` below the elastodynamic level), each a one-line call, which
//! [`crate::chain_hooks!`] writes into the model's `impl Model`.
//!
//! The states are always `y = [x, ẋ, W]`: the chain's free coordinate, its rate and the work `W`
//! done on the chain by everything but its spring, for the energy balance `E − E0 − W`.
//!
//! A new mechanism with a compliant chain:
//! 1. its ODE in `elastic.rs`: an [`OdeSystem`] on `y` with its bookkeeping in a `Cell` (a
//!    dynamic factor: [`Peaks::track`] in `on_step`, [`Peaks`] in the memory);
//! 2. a struct of the chain's constants implementing [`ChainModel`]: the ODE from them and the
//!    memory, how the memory starts and is read back and how many numbers it takes in the
//!    snapshot ([`Saved`], [`crate::chain_memory!`]), the hooks that differ from the defaults;
//! 3. in the model, `Option<Chain<_>>` built at `prepare` with [`Chain::new`] (its integrator
//!    from the [`solver_settings`]), the hooks by [`crate::chain_hooks!`], and in
//!    `evaluate` the outputs at [`Chain::held_state`] ([`write_states`], [`Peaks::dyn_factor`]).

use super::{Integrator, Memory, Method, OdeSystem, Settings, ShaftPath};
use num_dual::Dual64;

mod kept;
mod macros;
mod memory;
use crate::model::shaft;
use crate::model::{Log, Values, VarSet};
pub use kept::{LAST_AT, LastAt, LastPoint};
pub use memory::{Peaks, Saved};
use std::fmt::Debug;

/// Where the elastodynamic level takes what it tracks over steps (peaks, turn minima, impact
/// forces), in the words of a variable's description (use it in `concat!`): the same in both
/// interfaces, on the points of whichever integration runs.
#[macro_export]
macro_rules! at_accepted_steps {
    () => {
        "at the accepted integration steps: the FMU's integrator's inside fmi2DoStep in Co-Simulation, the host's completed integrator steps in Model Exchange"
    };
}

/// The ODE of a compliant chain on `y = [x, ẋ, W]`: an [`OdeSystem`] that also knows where the
/// integration starts and the chain's energy.
pub trait ChainOde: OdeSystem {
    /// The chain at one instant: positions, forces, the acceleration `ẍ` and the power `Ẇ`.
    type Point: Copy;
    /// The chain at `(t, y)`.
    fn point(&self, t: f64, y: &[f64]) -> Self::Point;
    /// Where the last point computed is kept ([`LastPoint`]); `None`: nothing is kept.
    fn last_point(&self) -> Option<&LastPoint<Self::Point>> {
        None
    }
    /// The chain at `(t, y)`, the kept one if it is the last computed, at these very values
    /// ([`ChainOde::last_point`]): the right-hand side and the checks after a step meet the
    /// step's end one after the other.
    fn point_kept(&self, t: f64, y: &[f64]) -> Self::Point {
        match self.last_point() {
            Some(kept) => kept.get_or(t, y, || self.point(t, y)),
            None => self.point(t, y),
        }
    }
    /// The chain's energy (kinetic plus spring) at a point.
    fn energy(&self, pt: &Self::Point) -> f64;
    /// The chain's natural angular frequency √(k/m), rad/s ([`rate_tolerance`]).
    fn natural_frequency(&self) -> f64;
    /// The states at the start of the integration, time `t` (equilibrium on the rigid motion).
    fn initial_state(&self, t: f64) -> [f64; 3];
    /// The chain's energy at `(t, y)`.
    fn energy_at(&self, t: f64, y: &[f64; 3]) -> f64 {
        self.energy(&self.point(t, y))
    }
}

/// How many roundings of the coordinate `x` the rate's absolute tolerance spans at least
/// ([`rate_tolerance`]).
pub const RATE_ROUNDINGS: f64 = 1000.0;

/// The absolute tolerance of a chain's state `i` of `y = [x, ẋ, W]`: `atol`, but for the rate
/// `ẋ` never below `RATE_ROUNDINGS·ε·|x|·ω` (ω [`ChainOde::natural_frequency`]), the rate of an
/// oscillation whose amplitude is that many roundings of `x`. A rounding of `x` changes the
/// spring force by `k·ε·|x|` and so `ẋ` by about `h·ω²·ε·|x|` over a step `h`: a stiff chain
/// (1e12 N/m) with `atol` at the force of a few newtons (3/k) asked `ẋ` for less than that
/// noise at rest in a dwell, where `ẋ` is 0 and the relative tolerance gives nothing, and Radau
/// IIA's Newton iteration stalled on the noise (contraction 0.5–0.9) at steps of a few
/// microseconds.
pub fn rate_tolerance<O: ChainOde + ?Sized>(o: &O, i: usize, atol: f64, y: &[f64]) -> f64 {
    let floor = RATE_ROUNDINGS * f64::EPSILON * y[0].abs() * o.natural_frequency();
    if i == 1 && floor.is_finite() {
        atol.max(floor)
    } else {
        atol
    }
}

/// The Jacobian of a chain's right-hand side on `y = [x, ẋ, W]` (row-major 3×3) from the
/// acceleration and the power as functions of `(x, ẋ)` on dual numbers (the same source as the
/// right-hand side, so exact in every branch it takes): `ẋ' = ẋ`, W enters nothing.
pub fn dual_jacobian(y: &[f64], j: &mut [f64], f: impl Fn(Dual64, Dual64) -> (Dual64, Dual64)) {
    let (ax, px) = f(Dual64::new(y[0], 1.0), Dual64::from(y[1]));
    let (av, pv) = f(Dual64::from(y[0]), Dual64::new(y[1], 1.0));
    j.copy_from_slice(&[0.0, 1.0, 0.0, ax.eps, av.eps, 0.0, px.eps, pv.eps, 0.0]);
}

/// For the chains' unit tests: the Jacobian of `o` at `(t, y)` against central differences of
/// its right-hand side with steps `h` in `x` and `ẋ`, rows `ẍ` and `Ẇ`, to 1e-4 relative.
#[cfg(test)]
pub fn assert_jacobian_at(o: &dyn OdeSystem, t: f64, y: [f64; 3], h: [f64; 2]) {
    let mut jac = [0.0; 9];
    o.jacobian(t, &y, &mut jac);
    for (col, h) in h.into_iter().enumerate() {
        let (mut fp, mut fm) = ([0.0; 3], [0.0; 3]);
        let (mut yp, mut ym) = (y, y);
        yp[col] += h;
        ym[col] -= h;
        o.rhs(t, &yp, &mut fp);
        o.rhs(t, &ym, &mut fm);
        for row in 1..3 {
            let fd = (fp[row] - fm[row]) / (2.0 * h);
            let an = jac[row * 3 + col];
            assert!(
                (fd - an).abs() <= 1e-4 * (1.0 + an.abs()),
                "t {t} y {y:?} row {row} col {col}: {an} vs {fd}"
            );
        }
    }
}

/// What a mechanism supplies for its compliant chain. Implemented by the chain's constants
/// (stiffness, damping, play...), fixed at `prepare`.
pub trait ChainModel: Clone + Debug {
    /// The variables of the mechanism's FMU.
    type Var: VarSet;
    /// The mechanism's physics the ODE borrows.
    type Physics: 'static;
    /// What the ODE tracks between steps besides the states (peaks, K_d, contact counters),
    /// copied into the ODE's `Cell` and read back from it ([`ChainModel::absorb`]).
    /// It is saved in the FMU state as its [`Saved`] numbers.
    type Memory: Clone + Debug + PartialEq + Saved;
    /// The ODE of one communication step (or of one Model Exchange call).
    type Ode<'a>: ChainOde;

    /// Event indicators appended to the snapshot (the last event's or step's, so that Model
    /// Exchange transitions are counted after a restore too); 0: none. A snapshot without them
    /// (Co-Simulation) restores as well. A chain whose events count or switch anything (its
    /// `on_event` compares with the last indicators) must save all of them: without, the first
    /// event after a restore is missed (Perforators' lift-offs, `tests/me_state_replay.rs`); so
    /// must one with an indicator that can rest at zero, whose held sign they are
    /// ([`crate::solver::hold_signs`]).
    const SAVED_INDICATORS: usize = 0;
    /// How a wrong snapshot is named in the error.
    const STATE_NAME: &'static str = "elastodynamic state";
    /// Model Exchange: the indicators are taken again after a transition (the default hooks'
    /// [`transitions`]), for an ODE whose events switch a mode its indicators depend on.
    const REEVALUATE_INDICATORS: bool = false;

    /// The ODE on the shaft path `path` with the inputs in `v`, its bookkeeping from `memory`.
    fn ode<'a>(
        &self,
        p: &'a Self::Physics,
        path: ShaftPath,
        v: &Values<Self::Var>,
        memory: &Self::Memory,
    ) -> Self::Ode<'a>;
    /// The memory at the start of the integration on `path`.
    fn start(ode: &Self::Ode<'_>, path: &ShaftPath, memory: &mut Self::Memory);
    /// Reads the memory back from the ODE after a step, an event or a completed step.
    fn absorb(ode: &Self::Ode<'_>, memory: &mut Self::Memory);

    /// Co-Simulation: after an accepted communication step from `t` over `h`, before
    /// [`ChainModel::absorb`] (`memory` still holds the memory before the step: what changed
    /// can be reported). Default: nothing.
    fn after_step(
        &self,
        _ode: &Self::Ode<'_>,
        _memory: &mut Self::Memory,
        _t: f64,
        _h: f64,
        _log: &mut dyn Log,
    ) {
    }
    /// Co-Simulation: why the state `y` at `t` after an accepted step is not a physical one
    /// (a chain so soft that its deflection exceeds what the mechanism can move), which refuses
    /// the step with that reason; None: physical. Default: None.
    fn non_physical(&self, _ode: &Self::Ode<'_>, _t: f64, _y: &[f64; 3]) -> Option<String> {
        None
    }
    /// Co-Simulation: the error of a refused step, from the solver's `why` and the partial
    /// state `y`. Default: `why`.
    fn step_failed(&self, _ode: &Self::Ode<'_>, _y: &[f64; 3], why: String) -> String {
        why
    }
    /// Model Exchange: an event at `t`, before [`ChainModel::absorb`] (`memory` is the memory
    /// before it). Default: the [`transitions`] of the indicators since the last call.
    fn me_event(
        &self,
        ode: &Self::Ode<'_>,
        t: f64,
        y: &[f64; 3],
        g_prev: &mut Vec<f64>,
        _memory: &Self::Memory,
        _log: &mut dyn Log,
    ) {
        transitions(ode, t, y, g_prev, Self::REEVALUATE_INDICATORS);
    }
    /// Model Exchange: the host completed an integrator step at `t`, before
    /// [`ChainModel::absorb`]. Default: the [`transitions`] since the last call (hosts such as
    /// FMPy call `fmi2CompletedIntegratorStep` at the event instant before they enter event
    /// mode, so the event alone would find nothing changed), then the ODE's `on_step`.
    fn me_completed_step(&self, ode: &Self::Ode<'_>, t: f64, y: &[f64; 3], g_prev: &mut Vec<f64>) {
        transitions(ode, t, y, g_prev, Self::REEVALUATE_INDICATORS);
        ode.on_step(t, y);
    }
}

/// Model Exchange: the event indicators at `(t, y)` (those resting at zero holding their sign in
/// `g_prev`, [`OdeSystem::events_held`]); if those of the last call are known, a transition from
/// them is applied (`on_event`), and with `reevaluate` the indicators are taken again after it
/// (where the event changes a mode they depend on). They become `g_prev`.
pub fn transitions<O: OdeSystem>(
    ode: &O,
    t: f64,
    y: &[f64; 3],
    g_prev: &mut Vec<f64>,
    reevaluate: bool,
) {
    let mut g = vec![0.0; ode.n_events()];
    ode.events_held(t, y, g_prev, &mut g);
    if g_prev.len() == g.len() {
        ode.on_event_held(t, y, g_prev, &g);
        if reevaluate {
            ode.events_held(t, y, g_prev, &mut g);
        }
    }
    *g_prev = g;
}

/// [`ChainModel::non_physical`] of a chain whose deflection `delta` at `t` must stay within the
/// travel `travel` of the member it drives: beyond it the spring `k` (`elastic.k`) is too soft.
/// `names`: the chain, the travel, the member (e.g. "drive chain", "knife's stroke", "knife").
pub fn beyond_travel(
    delta: f64,
    travel: f64,
    t: f64,
    k: f64,
    [chain, what, member]: [&str; 3],
) -> Option<String> {
    (delta.abs() > travel).then(|| {
        format!(
            "the {chain} deflects by {:.4} m at t = {t:.6} s, more than the {what} {travel:.4} m: elastic.k = {k} N/m is too soft to drive the {member}",
            delta.abs(),
        )
    })
}

/// What the elastodynamic level carries between steps.
#[derive(Clone, Debug)]
pub struct Chain<C: ChainModel> {
    /// The chain's constants.
    pub model: C,
    /// The integrator with its memory between steps ([`crate::solver::Memory`]).
    pub integ: Integrator,
    /// The states have been initialized ([`Chain::start`]).
    pub started: bool,
    /// `[x, ẋ, W]`.
    pub y: [f64; 3],
    /// Energy at the start, for the balance `E − E0 − W`.
    pub e0: f64,
    /// The mechanism's bookkeeping.
    pub memory: C::Memory,
    /// Model Exchange: the event indicators at the last event or completed integrator step
    /// (empty: none yet); an indicator resting at zero holds its sign in them
    /// ([`crate::solver::hold_signs`]).
    pub g_prev: Vec<f64>,
}

impl<C: ChainModel> Chain<C> {
    /// Numbers of the FMU state snapshot (without Model Exchange indicators): `[started, x, ẋ,
    /// W, e0]`, the integrator's whole [`Memory`], the mechanism's memory.
    pub const STATE_LEN: usize = 5 + Memory::LEN + <C::Memory as Saved>::LEN;

    /// A chain not started yet, with its initial memory, integrated as the `solver.*`
    /// parameters among `v` say ([`solver_settings`]).
    pub fn new(model: C, v: &Values<C::Var>, memory: C::Memory) -> Self {
        Chain {
            model,
            integ: Integrator::new(solver_settings(v)),
            started: false,
            y: [0.0; 3],
            e0: 0.0,
            memory,
            g_prev: Vec::new(),
        }
    }

    /// The ODE on `path` with the inputs in `v`.
    pub fn ode<'a>(&self, p: &'a C::Physics, path: ShaftPath, v: &Values<C::Var>) -> C::Ode<'a> {
        self.model.ode(p, path, v, &self.memory)
    }

    /// Starts the integration at `path.t0`: the states in equilibrium on the rigid motion, their
    /// energy, the memory's start.
    pub fn start(&mut self, p: &C::Physics, path: ShaftPath, v: &Values<C::Var>) {
        let ode = self.ode(p, path, v);
        self.y = ode.initial_state(path.t0);
        self.e0 = ode.energy_at(path.t0, &self.y);
        C::start(&ode, &path, &mut self.memory);
        self.started = true;
    }

    /// The states to report at `t`: the integrated ones, or before the start those the
    /// integration will start from.
    pub fn held_state(&self, ode: &C::Ode<'_>, t: f64) -> [f64; 3] {
        if self.started {
            self.y
        } else {
            ode.initial_state(t)
        }
    }

    /// The FMU state snapshot: `[started, x, ẋ, W, e0]`, the integrator's [`Memory`], the
    /// mechanism's memory, then the Model Exchange indicators if the mechanism saves them.
    pub fn save(&self) -> Vec<f64> {
        let mut s = Vec::with_capacity(Self::STATE_LEN + self.g_prev.len());
        s.extend([
            f64::from(u8::from(self.started)),
            self.y[0],
            self.y[1],
            self.y[2],
            self.e0,
        ]);
        s.extend(self.integ.save().to_numbers());
        self.memory.save(&mut s);
        debug_assert_eq!(s.len(), Self::STATE_LEN);
        if C::SAVED_INDICATORS > 0 {
            s.extend_from_slice(&self.g_prev);
        }
        s
    }

    /// Restores [`Chain::save`]; a snapshot a host has altered is refused whole.
    pub fn restore(&mut self, s: &[f64]) -> Result<(), String> {
        let n = Self::STATE_LEN;
        let n_ind = C::SAVED_INDICATORS;
        let with_signs = [n, n + n_ind];
        crate::model::saved::expect_len(
            C::STATE_NAME,
            s,
            &with_signs[..1 + usize::from(n_ind > 0)],
        )?;
        // a snapshot is data a host may have altered: no model runs on non-finite states
        let names = crate::model::state_names::<C::Var>();
        if let Some(i) = (0..3).find(|&i| !s[1 + i].is_finite()) {
            return Err(format!(
                "{} refused: {} = {} is not finite",
                C::STATE_NAME,
                names.get(i).map_or(format!("state {i}"), |n| n.to_string()),
                s[1 + i]
            ));
        }
        if !(s[0] == 0.0 || s[0] == 1.0) || !s[4].is_finite() {
            return Err(format!(
                "{} refused: started = {}, E0 = {} (0 or 1, and a finite energy expected)",
                C::STATE_NAME,
                s[0],
                s[4]
            ));
        }
        let integ = Memory::from_numbers(&s[5..5 + Memory::LEN])
            .map_err(|e| format!("{} refused: {e}", C::STATE_NAME))?;
        let memory = C::Memory::restore(&s[5 + Memory::LEN..n])
            .map_err(|e| format!("{} refused: {e}", C::STATE_NAME))?;
        if let Some(g) = s[n..].iter().find(|g| !g.is_finite()) {
            return Err(format!(
                "{} refused: an event indicator of {g}, not finite",
                C::STATE_NAME
            ));
        }
        self.g_prev = s[n..].to_vec();
        self.started = s[0] != 0.0;
        self.y = [s[1], s[2], s[3]];
        self.e0 = s[4];
        self.integ.restore(integ);
        self.memory = memory;
        Ok(())
    }
}

/// A chain at a call at `time` outside a Co-Simulation step (the Model Exchange hooks, the
/// report's access to its ODE): started from the inputs at `time` if new, its ODE on the
/// shaft's path from there. The hooks of [`crate::chain_hooks!`] are its methods; below the
/// elastodynamic level (no chain) they do what the macro says instead.
pub struct MeCall<'c, C: ChainModel> {
    d: &'c mut Chain<C>,
    p: &'c C::Physics,
    v: &'c Values<C::Var>,
    time: f64,
}

impl<'c, C: ChainModel> MeCall<'c, C> {
    /// The call on `chain` (`None` below the elastodynamic level).
    pub fn of(
        chain: Option<&'c mut Chain<C>>,
        p: &'c C::Physics,
        v: &'c Values<C::Var>,
        time: f64,
    ) -> Option<Self> {
        let d = chain?;
        if !d.started {
            d.start(p, shaft::path(v, time), v);
        }
        Some(MeCall { d, p, v, time })
    }

    fn ode(&self) -> C::Ode<'c> {
        self.d.ode(self.p, shaft::path(self.v, self.time), self.v)
    }

    /// [`crate::model::Dynamics::me_states`].
    pub fn me_states(self, x: &mut [f64]) {
        x.copy_from_slice(&self.d.y);
    }

    /// [`crate::model::Dynamics::me_set_states`].
    pub fn me_set_states(self, x: &[f64]) {
        self.d.y.copy_from_slice(x);
    }

    /// [`crate::model::Dynamics::me_derivatives`]: the ODE's right-hand side.
    pub fn me_derivatives(self, dx: &mut [f64]) {
        self.ode().rhs(self.time, &self.d.y, dx);
    }

    /// [`crate::model::Dynamics::me_event_indicators`]: the ODE's event functions, those
    /// resting at zero holding the sign they had at the last event or completed step
    /// ([`OdeSystem::events_held`]).
    pub fn me_event_indicators(self, z: &mut [f64]) {
        let d = &*self.d;
        self.ode().events_held(self.time, &d.y, &d.g_prev, z);
    }

    /// [`crate::model::Dynamics::me_event`]: [`ChainModel::me_event`], then the memory read
    /// back.
    pub fn me_event(self, log: &mut dyn Log) {
        let ode = self.ode();
        let d = self.d;
        d.model
            .me_event(&ode, self.time, &d.y, &mut d.g_prev, &d.memory, log);
        C::absorb(&ode, &mut d.memory);
    }

    /// [`crate::model::Dynamics::me_completed_step`]: [`ChainModel::me_completed_step`], then
    /// the memory read back. The host's step is counted with the integrator's accepted steps
    /// (`solver.steps`: the FMU's own steps in Co-Simulation, the host's in Model Exchange).
    pub fn me_completed_step(self, _log: &mut dyn Log) {
        let ode = self.ode();
        let d = self.d;
        d.model
            .me_completed_step(&ode, self.time, &d.y, &mut d.g_prev);
        C::absorb(&ode, &mut d.memory);
        d.integ.mem.stats.steps += 1;
    }

    /// [`ChainAccess::with_chain_ode`].
    pub fn with_chain_ode(self, f: &mut dyn FnMut(&dyn OdeSystem, [f64; 3])) {
        f(&self.ode(), self.d.y);
    }
}

/// A model whose elastodynamic level is a [`Chain`], for tools that integrate the chain's ODE
/// with other integrators (the report's library anchors): written by [`crate::chain_access!`].
pub trait ChainAccess {
    /// The variables of the model.
    type Var: VarSet;
    /// Hands `f` the chain's ODE on the shaft's path from `time` and its state there (the
    /// chain started from the inputs at `time` if new); `false` below the elastodynamic level.
    fn with_chain_ode(
        &mut self,
        v: &Values<Self::Var>,
        time: f64,
        f: &mut dyn FnMut(&dyn OdeSystem, [f64; 3]),
    ) -> bool;
}

/// [`crate::model::Dynamics::do_step`]: integrates the chain over `[time, time + h]`, the shaft on
/// [`shaft::path`] from the inputs at `time` (after the step [`crate::model::Model::step`] moves
/// the inputs to `time + h` along that path, as at every level). A refused step leaves the chain
/// as it was before it (the caller returns `fmi2Discard`).
pub fn do_step<C: ChainModel>(
    chain: Option<&mut Chain<C>>,
    p: &C::Physics,
    v: &Values<C::Var>,
    time: f64,
    h: f64,
    log: &mut dyn Log,
) -> Result<(), String> {
    let Some(d) = chain else {
        return Ok(());
    };
    let path = shaft::path(v, time);
    // a refused first step leaves the chain unstarted, as it was
    let unstarted = (!d.started).then(|| d.clone());
    if !d.started {
        d.start(p, path, v);
    }
    let ode = d.ode(p, path, v);
    let mut y = d.y;
    let before = d.integ.clone();
    let refused = match d.integ.integrate(&ode, time, time + h, &mut y) {
        Ok(_) => match d.model.non_physical(&ode, time + h, &y) {
            Some(why) => why,
            None => {
                d.y = y;
                d.model.after_step(&ode, &mut d.memory, time, h, log);
                C::absorb(&ode, &mut d.memory);
                return Ok(());
            }
        },
        Err(why) => d.model.step_failed(&ode, &y, why),
    };
    // the state before the step stays intact
    d.integ = before;
    if let Some(u) = unstarted {
        *d = u;
    }
    Err(refused)
}

/// [`crate::model::Dynamics::save_state`] of a model whose only internal state is the chain.
pub fn save_state<C: ChainModel>(chain: Option<&Chain<C>>) -> Vec<f64> {
    chain.map(Chain::save).unwrap_or_default()
}

/// [`crate::model::Dynamics::restore_state`] of a model whose only internal state is the chain.
pub fn restore_state<C: ChainModel>(chain: Option<&mut Chain<C>>, s: &[f64]) -> Result<(), String> {
    match chain {
        Some(d) => d.restore(s),
        None if s.is_empty() => Ok(()),
        None => Err("FMU state of the elastodynamic level given to another level".into()),
    }
}

/// The solver settings from the `solver.*` parameters ([`super::vars`]) among a model's
/// variables.
pub fn solver_settings<V: VarSet>(v: &Values<V>) -> Settings {
    let value = |name: &str| v.named(name);
    Settings {
        method: Method::from_value(value("solver.method") as i32),
        rtol: value("solver.rtol"),
        atol: value("solver.atol"),
        max_step: value("solver.max_step"),
        ..Settings::default()
    }
}

/// Writes the Model Exchange states `y` into the variables `states` and their derivatives
/// `[ẋ, ẍ, Ẇ]` = `[y[1], xdd, power]` into `derivatives` (the locals that show them).
pub fn write_states<V: VarSet>(
    v: &mut Values<V>,
    states: [V; 3],
    derivatives: [V; 3],
    y: &[f64; 3],
    xdd: f64,
    power: f64,
) {
    for (s, x) in states.into_iter().zip(y) {
        v[s] = *x;
    }
    v[derivatives[0]] = y[1];
    v[derivatives[1]] = xdd;
    v[derivatives[2]] = power;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::NoLog;
    use std::cell::Cell;

    crate::model_variables! {
        enum TV (nominal_rpm = 60.0) {
            solver_method = crate::solver::vars::method(),
            solver_rtol = crate::solver::vars::rtol(),
            solver_atol = crate::solver::vars::atol(),
            solver_max_step = crate::solver::vars::max_step(),
        }
    }

    #[test]
    fn beyond_travel_names_the_deflection_and_the_spring() {
        let names = ["drive chain", "knife's stroke", "knife"];
        assert_eq!(beyond_travel(-0.05, 0.05, 0.1, 1e4, names), None);
        let why = beyond_travel(-0.06, 0.05, 0.1, 1e4, names).unwrap();
        assert_eq!(
            why,
            "the drive chain deflects by 0.0600 m at t = 0.100000 s, more than the knife's stroke 0.0500 m: elastic.k = 10000 N/m is too soft to drive the knife"
        );
    }

    /// A mass on a spring of stiffness `k` (unit mass) whose other end follows `sin φ`; counts
    /// the sign changes of x.
    #[derive(Clone, Debug)]
    struct Toy {
        k: f64,
    }

    struct ToyOde {
        k: f64,
        path: ShaftPath,
        crossings: Cell<f64>,
    }

    impl OdeSystem for ToyOde {
        fn dim(&self) -> usize {
            3
        }
        fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
            let f = -self.k * (y[0] - self.path.at(t).0.sin());
            dy.copy_from_slice(&[y[1], f, 0.0]);
        }
        fn n_events(&self) -> usize {
            1
        }
        fn events(&self, _t: f64, y: &[f64], g: &mut [f64]) {
            g[0] = y[0];
        }
        fn on_event(&self, _t: f64, _y: &[f64], before: &[f64], after: &[f64]) {
            if (before[0] > 0.0) != (after[0] > 0.0) {
                self.crossings.set(self.crossings.get() + 1.0);
            }
        }
    }

    impl ChainOde for ToyOde {
        type Point = [f64; 2];
        fn point(&self, _t: f64, y: &[f64]) -> [f64; 2] {
            [y[0], y[1]]
        }
        fn energy(&self, &[x, v]: &[f64; 2]) -> f64 {
            0.5 * v * v + 0.5 * self.k * x * x
        }
        fn natural_frequency(&self) -> f64 {
            self.k.sqrt()
        }
        fn initial_state(&self, t: f64) -> [f64; 3] {
            [self.path.at(t).0.sin(), 0.0, 0.0]
        }
    }

    impl ChainModel for Toy {
        type Var = TV;
        type Physics = ();
        type Memory = f64;
        type Ode<'a> = ToyOde;
        const SAVED_INDICATORS: usize = 1;

        fn ode(&self, _: &(), path: ShaftPath, _: &Values<TV>, m: &f64) -> ToyOde {
            ToyOde {
                k: self.k,
                path,
                crossings: Cell::new(*m),
            }
        }
        fn start(_: &ToyOde, _: &ShaftPath, m: &mut f64) {
            *m = 0.0;
        }
        fn absorb(ode: &ToyOde, m: &mut f64) {
            *m = ode.crossings.get();
        }
    }

    fn toy(v: &Values<TV>, k: f64) -> Chain<Toy> {
        Chain::new(Toy { k }, v, f64::NAN)
    }

    fn bits(s: &[f64]) -> Vec<u64> {
        s.iter().map(|x| x.to_bits()).collect()
    }

    #[test]
    fn co_simulation_steps_save_and_restore() {
        let mut v = Values::<TV>::start();
        let w = v.raw()[shaft::W as usize];
        let mut c = toy(&v, 400.0);
        let h = 0.01;
        for j in 0..100 {
            let t = j as f64 * h;
            let inputs = v.raw()[..3].to_vec();
            do_step(Some(&mut c), &(), &v, t, h, &mut NoLog).unwrap();
            assert_eq!(v.raw()[..3], inputs, "the chain's step leaves the inputs");
            // what Model::step does after it: the inputs where the shaft's path led
            let end = shaft::end_of_step(&v, t, h).unwrap().unwrap();
            shaft::set_inputs(&mut v, end, t + h);
        }
        // one turn of the shaft; the mass crossed zero
        assert!((v.raw()[shaft::PHI as usize] - w).abs() < 1e-9);
        assert!(c.started && c.memory >= 1.0, "{c:?}");
        assert!(c.integ.mem.stats.steps > 0);
        let saved = c.save();
        assert_eq!(saved.len(), Chain::<Toy>::STATE_LEN);
        let mut r = toy(&v, 400.0);
        r.restore(&saved).unwrap();
        assert_eq!(bits(&r.save()), bits(&saved));
        assert_eq!((r.y, r.memory), (c.y, c.memory));
        assert_eq!(
            r.restore(&saved[..3]),
            Err(format!(
                "elastodynamic state has 3 numbers, expected {} or {}",
                Chain::<Toy>::STATE_LEN,
                Chain::<Toy>::STATE_LEN + 1
            ))
        );
        // a snapshot a host altered: a non-finite state is refused, the chain kept
        let mut bad = saved.clone();
        bad[2] = f64::INFINITY;
        assert_eq!(
            r.restore(&bad),
            Err("elastodynamic state refused: state 1 = inf is not finite".into())
        );
        assert_eq!(bits(&r.save()), bits(&saved));
        // ... and so is an integrator memory no integrator has: a fractional counter, a
        // negative step size, a flag that is no flag
        for (i, x, why) in [
            (
                5 + Memory::LEN - 8,
                1e300,
                "integrator's steps = 1e300 refused: a whole number from 0 to 9007199254740992 expected",
            ),
            (
                5 + Memory::LEN - 7,
                2.5,
                "integrator's rejected steps = 2.5 refused: a whole number from 0 to 9007199254740992 expected",
            ),
            (
                5,
                -1.0,
                "integrator's next step size = -1.0 refused: a finite number >= 0 expected",
            ),
            (
                5 + 1,
                0.5,
                "integrator's stiff mode = 0.5 refused: 0 or 1 expected",
            ),
            (
                0,
                2.0,
                "started = 2, E0 = 0 (0 or 1, and a finite energy expected)",
            ),
            // the model's own memory (the toy's crossing count, a finite number)
            (
                5 + Memory::LEN,
                f64::NAN,
                "value = NaN, not a finite number",
            ),
        ] {
            let mut bad = saved.clone();
            bad[i] = x;
            if i == 0 {
                bad[4] = 0.0;
            }
            assert_eq!(
                r.restore(&bad),
                Err(format!("elastodynamic state refused: {why}")),
                "{i}"
            );
            assert_eq!(bits(&r.save()), bits(&saved));
        }
    }

    #[test]
    fn a_refused_step_leaves_the_chain_as_it_was() {
        let mut v = Values::<TV>::start();
        v[TV::solver_method] = 4.0; // rk4 at max_step on a stiff spring: refused
        v[TV::solver_max_step] = 0.01;
        let mut c = toy(&v, 1e8);
        c.start(&(), shaft::path(&v, 0.0), &v);
        let before = c.save();
        assert!(do_step(Some(&mut c), &(), &v, 0.0, 0.01, &mut NoLog).is_err());
        assert_eq!(bits(&c.save()), bits(&before));
        assert_eq!(c.integ.mem.stats, toy(&v, 1e8).integ.mem.stats);
        assert_eq!(do_step::<Toy>(None, &(), &v, 0.0, 0.01, &mut NoLog), Ok(()));
    }

    #[test]
    fn model_exchange_hooks() {
        let v = Values::<TV>::start();
        let mut c = toy(&v, 400.0);
        fn call<'c>(c: &'c mut Chain<Toy>, v: &'c Values<TV>) -> MeCall<'c, Toy> {
            MeCall::of(Some(c), &(), v, 0.0).unwrap()
        }
        let mut x = [0.0; 3];
        call(&mut c, &v).me_states(&mut x);
        assert!(c.started && x == c.y);
        call(&mut c, &v).me_set_states(&[0.5, 0.0, 0.0]);
        let mut dx = [0.0; 3];
        call(&mut c, &v).me_derivatives(&mut dx);
        assert_eq!(dx[1], -400.0 * 0.5);
        call(&mut c, &v).me_event(&mut NoLog);
        assert_eq!(c.g_prev, vec![0.5]);
        // the mass crosses zero: the completed step counts it, and the indicators travel with
        // the FMU state
        call(&mut c, &v).me_set_states(&[-0.5, 0.0, 0.0]);
        call(&mut c, &v).me_completed_step(&mut NoLog);
        assert_eq!(c.memory, 1.0);
        assert_eq!(c.integ.mem.stats.steps, 1, "the host's step is counted");
        let saved = save_state(Some(&c));
        assert_eq!(saved.len(), Chain::<Toy>::STATE_LEN + 1);
        let mut r = toy(&v, 400.0);
        restore_state(Some(&mut r), &saved).unwrap();
        assert_eq!(r.g_prev, vec![-0.5]);
        let mut bad = saved.clone();
        *bad.last_mut().unwrap() = f64::NEG_INFINITY;
        assert_eq!(
            r.restore(&bad),
            Err("elastodynamic state refused: an event indicator of -inf, not finite".into())
        );
        // below the elastodynamic level
        assert!(MeCall::<Toy>::of(None, &(), &v, 0.0).is_none());
        assert_eq!(save_state::<Toy>(None), Vec::<f64>::new());
        assert!(restore_state::<Toy>(None, &[]).is_ok());
        assert!(restore_state::<Toy>(None, &saved).is_err());
    }

    #[test]
    fn peaks_and_dyn_factor() {
        let mut p = Peaks::new(0.0);
        p.track(0.0, 2.0, 1.0);
        p.track(0.0, 1.0, 4.0);
        assert_eq!(p.dyn_factor(), 0.5);
        p.track(1.0, 3.0, 1.0);
        assert_eq!((p.turn, p.k_d, p.dyn_factor()), ((1.0, 3.0, 1.0), 0.5, 0.5));
        let mut saved = Vec::new();
        p.save(&mut saved);
        assert_eq!(saved.len(), <Peaks as Saved>::LEN);
        assert_eq!(Peaks::restore(&saved), Ok(p));
        assert_eq!(Peaks::new(0.0).dyn_factor(), 1.0);
    }
}
