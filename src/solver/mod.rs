//! Integrators for the elastodynamic level (`../shared/spec/dynamics.md`, "Solver inside
//! fmi2DoStep"). Knows no mechanism: a mechanism hands an [`OdeSystem`] (right-hand side,
//! analytic Jacobian, event functions) and the integrator advances it over one communication
//! step.
//!
//! Methods ([`Method`], the FMU parameter `solver.method`), to the standard of Hairer's codes:
//! - `dopri5`: explicit Dormand–Prince 5(4) (DOPRI5): the PI step controller, no growth right
//!   after a rejection, Hairer's stiffness detection, its continuous extension of order 4;
//! - `radau5`: implicit Radau IIA of order 5 (3 stages, L-stable, stiffly accurate) as RADAU5:
//!   the simplified Newton iteration on the transformed system (a real and a complex `n×n`
//!   matrix, factorized on the stack, `lu.rs`), started from the last step's collocation
//!   polynomial, stopped early when its contraction says it cannot converge (the step shrinks;
//!   the method does not change behind the user's choice, but for single explicit attempts,
//!   counted in [`Stats::fallbacks`], where no Newton iteration converges across a jump of the
//!   right-hand side); the Jacobian and the factorizations
//!   kept while the iteration converges fast; the embedded error estimate (ESTRAD), the step
//!   controller with Gustafsson's prediction and the tolerance transformation
//!   (`rtol' = 0.1·rtol^(2/3)`);
//! - `rk4`: classical fixed-step Runge–Kutta, step `solver.max_step`, for comparison;
//! - `auto` (default): whichever of the two costs less work per simulated second, measured over
//!   windows of steps; with the explicit method's stiffness test and the held Jacobian's
//!   stability check as in LSODA. No Jacobian is evaluated while the explicit method runs.
//!
//! Everything carried between steps is one [`Memory`], saved and restored as a unit.
//!
//! Events: every step is checked for sign changes of the system's event functions; the earliest
//! is located (a root of the method's dense output, then confirmed with real steps to a bracket of
//! `1e-10` of the step, placed by regula falsi on their values) and the step ends just after it,
//! so a discontinuity of the right-hand side is never stepped over. After an event Radau IIA
//! starts its Newton iteration afresh and takes a new Jacobian (the old side's would misjudge the
//! error); a step sized to end past a crossing that its Newton iteration cannot pass (a sticking
//! band) is taken explicitly. An event function that rests at exactly zero over an interval (a
//! rigid velocity in a dwell) keeps the sign it had before ([`hold_signs`]), so that a Model
//! Exchange host's root finder (CVODE) sees an event where one takes the other sign and none
//! while it rests; the integrators here see the same functions with their own test
//! ([`event_between`]).
//!
//! Work budget ([`work_budget`]): one call does at most [`WORK_BASE`] + [`WORK_RATE`]·(t1 − t0)
//! units of work, and never more than [`WORK_MAX`] (right-hand sides, Jacobians and LU
//! factorizations, as `auto` weighs them: about a microsecond each on the mechanisms' chains),
//! so a call's cost is bounded and grows with the step a host requests, whatever the
//! parameters. A request that cannot fit is refused before any work: the fewest steps
//! `solver.max_step` allows, or `auto`'s measured work per simulated second, already exceed its
//! budget. One that turns out not to fit is refused as soon as a tenth of the budget is spent
//! and the work per simulated second so far, extrapolated to the whole step, exceeds twice the
//! budget. The reasons name the longest communication step that fits.
//!
//! Failure is an `Err` with the reason (step-size collapse, work budget, non-finite state, an
//! explicit method out of its stability region): the caller returns `fmi2Discard` and keeps the
//! state before the step.

use nalgebra::DMatrix;

mod auto;
pub mod chain;
mod dopri;
mod events;
#[cfg(feature = "tools")]
pub mod library;
mod lu;
mod memory;
mod norm;
mod radau;
pub mod vars;

pub use memory::{Memory, RadauMemory, Stats};

/// The shaft's path in a step (the shaft connector's, [`crate::model::shaft`]).
pub use crate::model::shaft::ShaftPath;
use dopri::hermite;
use norm::Scale;
pub use radau::spectral_radius;

/// The largest system the integrators take.
pub const MAX_DIM: usize = 8;

/// Work one call may do whatever its length: right-hand sides, Jacobians and LU
/// factorizations counted alike. Enough for the stiffest stretch of the mechanisms (a located
/// event costs some 30 attempts; the disc drive's jamming band a few thousand right-hand sides
/// in a millisecond).
pub const WORK_BASE: f64 = 1e5;

/// Work per simulated second a call may add to [`WORK_BASE`]: some ten times what `auto` and
/// `radau5` need on the stiffest chains (1e12 N/m: 2e5 per simulated second at rtol 1e-8), and
/// what `dopri5` on such a chain exceeds (its steps are stability-bound: there the reason says
/// to choose `auto` or `radau5`).
pub const WORK_RATE: f64 = 2e6;

/// The most work one call may do however long it is: a second or two of this machine.
pub const WORK_MAX: f64 = 2e6;

/// The work budget of a call over `span` seconds ([`WORK_BASE`], [`WORK_RATE`],
/// [`WORK_MAX`]).
pub fn work_budget(span: f64) -> f64 {
    (WORK_BASE + WORK_RATE * span).min(WORK_MAX)
}

/// The longest span whose work `per_second`·span fits its budget.
fn longest_fitting(per_second: f64) -> f64 {
    // per_second·h <= WORK_BASE + WORK_RATE·h, and per_second·h <= WORK_MAX
    let scaled = WORK_BASE / (per_second - WORK_RATE).max(f64::MIN_POSITIVE);
    scaled.min(WORK_MAX / per_second)
}
/// The most event functions a system may have.
pub const MAX_EVENTS: usize = 16;

/// An ODE `y' = f(t, y)` with event functions.
pub trait OdeSystem {
    /// Number of states.
    fn dim(&self) -> usize;
    /// `dy = f(t, y)`.
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]);
    /// `jac[i*n + j] = ∂f_i/∂y_j` (row-major). The default is a forward difference.
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut [f64]) {
        let n = self.dim();
        let mut f0 = vec![0.0; n];
        let mut f1 = vec![0.0; n];
        let mut yp = y.to_vec();
        self.rhs(t, y, &mut f0);
        for j in 0..n {
            let d = 1e-7 * y[j].abs().max(1e-5);
            yp[j] = y[j] + d;
            self.rhs(t, &yp, &mut f1);
            yp[j] = y[j];
            for i in 0..n {
                jac[i * n + j] = (f1[i] - f0[i]) / d;
            }
        }
    }
    /// Number of event functions.
    fn n_events(&self) -> usize {
        0
    }
    /// Event functions: an event is a strict sign change of one of them. One may be exactly zero
    /// over an interval (a rigid velocity in a dwell); the integrators and the Model Exchange
    /// hooks take them through [`OdeSystem::events_held`].
    fn events(&self, _t: f64, _y: &[f64], _g: &mut [f64]) {}
    /// The event functions as the integrators and a Model Exchange host see them: [`events`]
    /// with each one that is exactly zero holding the sign it had in `last` (the event
    /// functions at the last step or event; [`hold_signs`]).
    ///
    /// [`events`]: OdeSystem::events
    fn events_held(&self, t: f64, y: &[f64], last: &[f64], g: &mut [f64]) {
        self.events(t, y, g);
        hold_signs(g, last);
    }
    /// Called after every accepted step (for peak tracking with interior mutability).
    fn on_step(&self, _t: f64, _y: &[f64]) {}
    /// Called when a step ends just after a located event, with the event functions before
    /// and after it as [`OdeSystem::events`] gives them (a held zero is zero again): a system
    /// may switch a discrete mode here (interior mutability).
    fn on_event(&self, _t: f64, _y: &[f64], _g_before: &[f64], _g_after: &[f64]) {}
    /// [`OdeSystem::on_event`] for held event functions ([`OdeSystem::events_held`]), as the
    /// integrators and the Model Exchange hooks keep them.
    fn on_event_held(&self, t: f64, y: &[f64], before: &[f64], after: &[f64]) {
        let raw = |g: &[f64]| -> Vec<f64> {
            g.iter()
                .map(|x| if x.abs() == HELD { 0.0 } else { *x })
                .collect()
        };
        self.on_event(t, y, &raw(before), &raw(after));
    }
    /// Discrete modes of the system (saved with the state), and their restoration.
    fn modes(&self) -> Vec<f64> {
        Vec::new()
    }
    /// Which states the error norm leaves out (e.g. a work integral kept for the energy
    /// balance); default none.
    fn error_weight(&self, _i: usize) -> f64 {
        1.0
    }
    /// The absolute tolerance of state `i` at `y` for [`Settings::atol`] `atol`: `atol` itself
    /// unless the arithmetic cannot resolve it (a chain's rate,
    /// [`crate::solver::chain::rate_tolerance`]).
    fn abs_tol(&self, _i: usize, atol: f64, _y: &[f64]) -> f64 {
        atol
    }
}

/// The magnitude an event function reports while it rests at zero ([`hold_signs`]): far below
/// any value an event function of these models takes off its zero (lengths, speeds, forces in SI
/// units), and the square root of the smallest normal number, so that the product of two such
/// values, which some hosts form to compare signs, is not rounded to zero.
pub const HELD: f64 = 1.4916681462400413e-154;

/// An event function exactly zero over an interval is no event indicator for a host's root
/// finder: it cannot tell a crossing from a rest (CVODE finds a root where one reaches zero, and
/// after it aborts in `cvRcheck2`, "Root found at and very near t", when the function is still
/// zero a little later). So each `g[i]` that is exactly zero takes the sign it had in `last`
/// (the event functions at the last step or event; positive where `last` has none), with the
/// magnitude [`HELD`]: resting at zero it keeps its sign, and a root is where it leaves zero to
/// the other side. The sign so held is a discrete memory: in Model Exchange the indicators of
/// the last event or completed step, which travel with the FMU state
/// ([`chain::ChainModel::SAVED_INDICATORS`]).
pub fn hold_signs(g: &mut [f64], last: &[f64]) {
    for (i, gi) in g.iter_mut().enumerate() {
        if *gi == 0.0 {
            *gi = if last.get(i).is_some_and(|l| *l < 0.0) {
                -HELD
            } else {
                HELD
            };
        }
    }
}

/// The integrators' event test between the (held) event function `a` at the start of a step
/// and `b` later in it: a change of sign, the held sign of a function resting at zero counting
/// as its sign (so a step that starts on a zero does not hide the next change, and leaving a
/// rest to the other side is an event, as a Model Exchange host's root finder sees it); or
/// reaching a rest from a value off zero (`b` held), which ends a step where a rigid velocity
/// comes to a dwell, a kink of the right-hand side.
fn event_between(a: f64, b: f64) -> bool {
    (a < 0.0 && b > 0.0) || (a > 0.0 && b < 0.0) || (a.abs() != HELD && b.abs() == HELD)
}

crate::fmi_enum! {
    /// `solver.method`.
    pub enum Method ("SolverMethod", "Integrator of the elastodynamic level inside fmi2DoStep") {
        Auto = 1 ("auto", "Dormand-Prince 5(4), switching to Radau IIA when the problem turns stiff (LSODA idea)"),
        Dopri5 = 2 ("dopri5", "explicit adaptive Dormand-Prince 5(4)"),
        Radau5 = 3 ("radau5", "implicit Radau IIA order 5, L-stable, analytic Jacobian"),
        Rk4 = 4 ("rk4", "classical Runge-Kutta, fixed step solver.max_step"),
    }
}

impl Method {
    /// From the Enumeration value of `solver.method` (`auto` for a value out of range).
    pub fn from_value(v: i32) -> Method {
        Method::from_item(v).unwrap_or(Method::Auto)
    }
    /// Every method, for reports.
    pub const ALL: [Method; 4] = [Method::Auto, Method::Dopri5, Method::Radau5, Method::Rk4];
}

/// Solver settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    pub method: Method,
    pub rtol: f64,
    /// Absolute tolerance, in the states' units ([`OdeSystem::abs_tol`]).
    pub atol: f64,
    pub max_step: f64,
    /// A cap on the accepted steps of one `integrate` call besides its work budget
    /// ([`work_budget`]), for tools that compare methods; the FMUs set none.
    pub max_steps: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            method: Method::Auto,
            rtol: 1e-6,
            atol: 1e-9,
            max_step: 1e-3,
            max_steps: usize::MAX,
        }
    }
}

/// Which stepper a step uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stepper {
    Dopri,
    Radau,
    Rk4,
}

/// An integrator: its settings (from the model's parameters), its [`Memory`], and what is made
/// from the memory and kept at hand (Radau IIA's factorized Newton matrices).
#[derive(Clone, Debug, PartialEq)]
pub struct Integrator {
    pub settings: Settings,
    pub mem: Memory,
    factors: radau::Factors,
    /// The error norms' weights at the start of the attempt under way (from its state alone:
    /// nothing to save).
    scale: Scale,
}

/// Where a step attempt starts: the system, time, state and its derivative.
#[derive(Clone, Copy)]
struct Start<'a> {
    sys: &'a dyn OdeSystem,
    t: f64,
    y: &'a [f64],
    f0: &'a [f64],
}

/// Outcome of one step attempt that produced a state.
struct Attempt {
    err: f64,
    /// Hairer's stiffness estimate h·|λ| (Dormand–Prince only), else 0.
    hlamb: f64,
    /// Radau IIA: its stages and Newton iterations.
    radau: Option<radau::RadauStep>,
    /// Dormand–Prince: the last coefficient of its continuous extension (Hairer's `RCONT5`).
    dopri_d5: Option<[f64; MAX_DIM]>,
}

/// A step's two ends, what its interpolants start from: the state and its derivative at the
/// start (`y`, `f0`) and at the end (`y1`, `f1`) of a step of `h`.
#[derive(Clone, Copy)]
struct Ends<'a> {
    y: &'a [f64],
    f0: &'a [f64],
    y1: &'a [f64],
    f1: &'a [f64],
    h: f64,
}

impl Attempt {
    /// The state at `t + s`, `s ∈ [0, h]`, on the attempt's interpolant between the step's
    /// ends: Dormand–Prince's continuous extension of order 4 (Hairer's `CONTD5`), Radau IIA's
    /// collocation polynomial (`CONTR5`), else (rk4) the cubic Hermite.
    fn interpolate(&self, e: &Ends, s: f64, out: &mut [f64]) {
        let (y1, h) = (e.y1, e.h);
        match (&self.dopri_d5, &self.radau) {
            (Some(d5), _) => dopri::dense(e, d5, s / h, out),
            (None, Some(r)) => radau::dense(&r.z, y1, s / h, out),
            (None, None) => hermite(e, s, out),
        }
    }
}

/// Radau IIA's Newton iterations that fail in a row (each shrinking the step) before one
/// explicit attempt is made instead ([`Stats::fallbacks`]); one is enough on a step sized to end
/// just past an event's crossing.
const EXPLICIT_AFTER: usize = 2;

/// Dormand–Prince's step controller (Hairer's DOPRI5): PI with `β = 0.04`, `h_new/h` within
/// `[0.2, 10]`, safety factor 0.9.
const DOPRI_BETA: f64 = 0.04;
const DOPRI_EXPO1: f64 = 0.2 - DOPRI_BETA * 0.75;
const DOPRI_SAFE: f64 = 0.9;
const DOPRI_FAC_MIN: f64 = 0.2;
const DOPRI_FAC_MAX: f64 = 10.0;

impl Integrator {
    /// A fresh integrator.
    pub fn new(settings: Settings) -> Self {
        Integrator {
            settings,
            mem: Memory {
                stiff: settings.method == Method::Radau5,
                err_old: 1e-4,
                ..Memory::default()
            },
            factors: radau::Factors::default(),
            scale: Scale::default(),
        }
    }

    /// Its whole memory, for `fmi2GetFMUstate`.
    pub fn save(&self) -> Memory {
        self.mem
    }

    /// Restores [`Integrator::save`].
    pub fn restore(&mut self, m: Memory) {
        self.mem = m;
    }

    /// Advances `y` from `t0` to `t1`. On `Err` the caller keeps its copy of the state before
    /// the call (`y` may hold a partial result).
    pub fn integrate(
        &mut self,
        sys: &dyn OdeSystem,
        t0: f64,
        t1: f64,
        y: &mut [f64],
    ) -> Result<Stats, String> {
        let mut st = Stats::default();
        let r = self.run(sys, t0, t1, y, &mut st);
        self.mem.stats.add(&st);
        r.map(|_| st)
    }

    /// Refuses a call over `span` that cannot fit its work `budget` before any work: the fewest
    /// steps `max_step` allows (right-hand sides per step: 4 for rk4 and Radau IIA's Newton
    /// iteration at best, 6 for Dormand–Prince), or the work per simulated second `auto` last
    /// measured for the method it runs.
    fn fits(&self, span: f64, max_step: f64, budget: f64) -> Result<(), String> {
        let per_step = if self.settings.method == Method::Dopri5 {
            6.0
        } else {
            4.0
        };
        let fewest = (span / max_step).ceil() * per_step;
        let m = &self.mem;
        let rate = if self.settings.method != Method::Auto {
            0.0
        } else if m.stiff {
            m.rate_implicit
        } else {
            m.rate_explicit
        };
        let (need, why, per_second) = if rate * span > fewest {
            (
                rate * span,
                "at the work per simulated second measured so far",
                rate,
            )
        } else {
            (
                fewest,
                "in the fewest steps solver.max_step allows",
                per_step / max_step,
            )
        };
        if need <= budget {
            return Ok(());
        }
        let longest = longest_fitting(per_second);
        Err(format!(
            "a step of {span} s needs about {need:.3e} right-hand sides, Jacobians and factorizations {why}, more than its work budget of {budget:.3e} ({WORK_BASE:e} + {WORK_RATE:e} per simulated second, at most {WORK_MAX:e}): take communication steps of at most {longest:.3e} s{}",
            if per_second == per_step / max_step {
                ", or a larger solver.max_step"
            } else {
                ""
            }
        ))
    }

    /// The next step size after an accepted attempt of `hs` with error `err` (Dormand–Prince's
    /// PI controller; Radau IIA's controller with Gustafsson's prediction, which keeps `hs` and
    /// its factorization where the change would be small), as a factor of `hs`.
    fn accepted_factor(&mut self, stepper: Stepper, n: usize, hs: f64, att: &Attempt) -> f64 {
        let h_new = match (stepper, &att.radau) {
            (Stepper::Rk4, _) => hs,
            (Stepper::Radau, Some(r)) => self.radau_accepted(n, hs, r),
            _ => {
                let fac11 = att.err.powf(DOPRI_EXPO1);
                let fac = (fac11 / self.mem.err_old.powf(DOPRI_BETA) / DOPRI_SAFE)
                    .clamp(1.0 / DOPRI_FAC_MAX, 1.0 / DOPRI_FAC_MIN);
                self.mem.err_old = att.err.max(1e-4);
                let h_new = hs / fac;
                if self.mem.rejected {
                    h_new.min(hs)
                } else {
                    h_new
                }
            }
        };
        self.mem.rejected = false;
        h_new / hs
    }

    /// The step size after a rejected attempt of `hs`: by the error estimate (Hairer's
    /// controllers; Radau IIA's first step one tenth), or by a failed Newton iteration (its
    /// factor). A Radau IIA failure with a Jacobian of an earlier step asks for a new one.
    fn rejected_step(
        &mut self,
        stepper: Stepper,
        hs: f64,
        att: &Result<Attempt, radau::NewtonFailure>,
        first: bool,
    ) -> f64 {
        self.mem.rejected = true;
        if stepper == Stepper::Radau && !self.mem.radau.jac_fresh {
            self.mem.radau.need_jac = true;
        }
        match att {
            Err(f) => hs * f.factor,
            Ok(a) if !a.err.is_finite() => hs * 0.25,
            Ok(_) if stepper == Stepper::Radau && first => hs * 0.1,
            Ok(a) => match &a.radau {
                Some(r) => Integrator::radau_h_new(hs, a.err, r.newt).0,
                None => hs / (1.0 / DOPRI_FAC_MIN).min(a.err.powf(DOPRI_EXPO1) / DOPRI_SAFE),
            },
        }
    }

    fn run(
        &mut self,
        sys: &dyn OdeSystem,
        t0: f64,
        t1: f64,
        y: &mut [f64],
        st: &mut Stats,
    ) -> Result<(), String> {
        let n = sys.dim();
        assert!(n <= MAX_DIM && y.len() == n, "system dimension");
        if y.iter().any(|x| !x.is_finite()) {
            return Err("the state is not finite at the start of the step".into());
        }
        let set = self.settings;
        let span = t1 - t0;
        if span <= 0.0 {
            return Ok(());
        }
        let ne = sys.n_events();
        let mut t = t0;
        // (on the stack: a call is a communication step, thousands per simulated second)
        let [mut f0, mut y1, mut f1, mut yt] = [[0.0; MAX_DIM]; 4];
        let (f0, y1, f1, yt) = (&mut f0[..n], &mut y1[..n], &mut f1[..n], &mut yt[..n]);
        sys.rhs(t, y, f0);
        st.rhs_evals += 1;
        assert!(ne <= MAX_EVENTS, "event functions");
        let [mut g0, mut g1, mut gt] = [[0.0; MAX_EVENTS]; 3];
        let (mut g0, mut g1, gt) = (&mut g0[..ne], &mut g1[..ne], &mut gt[..ne]);
        // one resting at zero holds the sign it had where the last call ended
        sys.events_held(t, y, &self.mem.event_signs[..ne], g0);
        // Radau IIA's Newton iterations that failed since the last accepted step
        let mut newton_failures = 0;
        // each event function's rate over the last accepted step (NaN: none yet, or an event)
        let mut rate = [f64::NAN; MAX_EVENTS];
        let max_step = if set.max_step > 0.0 {
            set.max_step
        } else {
            span
        };
        let fixed = set.method == Method::Rk4;
        let mut h = if fixed {
            max_step
        } else if self.mem.h_next > 0.0 {
            self.mem.h_next
        } else {
            self.initial_step(sys, t, y, f0, max_step, st)
        };
        let hmin = 1e-14 * (t0.abs() + span).max(1e-3);
        let budget = work_budget(span);
        self.fits(span, max_step, budget)?;
        loop {
            let rest = t1 - t;
            if rest <= 1e-13 * t1.abs().max(span) {
                break;
            }
            // the budget, and what the work so far says the whole step would need
            let work = st.work();
            let need = work / (t - t0) * span;
            if work > budget || work > 0.1 * budget && need > 2.0 * budget {
                let what = if work > budget {
                    format!(
                        "exhausted its work budget of {budget:.3e} right-hand sides, Jacobians and factorizations at t = {t}"
                    )
                } else {
                    format!(
                        "does not fit its work budget of {budget:.3e} right-hand sides, Jacobians and factorizations: at t = {t} the work per simulated second so far says it needs about {need:.3e}; communication steps of at most {:.3e} s fit",
                        longest_fitting(work / (t - t0))
                    )
                };
                return Err(format!(
                    "a step of {span} s {what} ({} accepted steps, {} rejected){}",
                    st.steps,
                    st.rejected,
                    if set.method == Method::Dopri5 {
                        "; the problem is probably stiff: choose solver.method = auto or radau5"
                    } else {
                        ""
                    }
                ));
            }
            let mut hs = h.min(max_step);
            let mut last = hs >= rest * (1.0 - 1e-12);
            if last {
                hs = rest;
            }
            // an event function heading for zero may not cross it and come back within one
            // step: an adaptive step ends within twice the time its rate over the last step
            // takes it there (never below a twentieth of the step the error allows)
            let reach = (0..ne)
                .filter(|&i| g0[i].abs() != HELD && g0[i] * rate[i] < 0.0)
                .map(|i| 2.0 * (g0[i] / rate[i]).abs())
                .fold(f64::INFINITY, f64::min);
            let heading = reach < hs && !fixed;
            if heading {
                hs = reach.max(0.05 * hs);
                last = false;
            }
            // every accepted step so far, of this call and the earlier ones (a call of a few
            // steps would otherwise count from 0 at each start)
            let steps = self.mem.stats.steps + st.steps;
            let mut stepper = self.stepper(n, h.min(max_step), steps, st);
            if stepper == Stepper::Radau && newton_failures >= EXPLICIT_AFTER {
                // the Newton iteration failed at this step and at half of it: a right-hand side
                // discontinuous in the state (a stick band) that no event function marks, which
                // no step across it lets converge. One explicit attempt of the reduced size, its
                // error estimate deciding, counted; then Radau IIA again
                stepper = Stepper::Dopri;
                st.fallbacks += 1;
            }
            if stepper == Stepper::Radau && !last && !self.mem.rejected {
                // the rest of the call in equal steps no longer than the one the error allows:
                // the steps of a call, and of the calls after it, then share one factorization
                // (the controller keeps a step it would grow by at most a factor 2), where a
                // shortened last step would need its own and the next call's first another. Not
                // right after a rejection: that step is the controller's retreat, taken as it is
                hs = rest / (rest / hs * (1.0 - 1e-9)).ceil();
            }
            if stepper == Stepper::Rk4 && st.steps.is_multiple_of(20) {
                let mut jac = [0.0; MAX_DIM * MAX_DIM];
                sys.jacobian(t, y, &mut jac[..n * n]);
                st.jac_evals += 1;
                let rho = spectral_radius(n, &jac);
                if hs * rho > 2.78 {
                    return Err(format!(
                        "rk4 with step {hs:.3e} s is unstable here: the stiffest mode has |lambda| = {rho:.3e} 1/s, h*|lambda| = {:.3e} > 2.78; set solver.max_step below {:.3e} s or choose solver.method = auto or radau5",
                        hs * rho,
                        2.78 / rho
                    ));
                }
            }
            let at = Start { sys, t, y, f0 };
            let att = self.attempt(stepper, at, hs, y1, f1, st);
            let accepted = match &att {
                Ok(a) => a.err <= 1.0 && y1.iter().all(|x| x.is_finite()),
                Err(_) => false,
            };
            if !accepted {
                if fixed {
                    return Err(match att {
                        Err(e) => e.reason,
                        Ok(_) => format!("rk4 produced a non-finite state at t = {t}"),
                    });
                }
                st.rejected += 1;
                newton_failures = match (stepper == Stepper::Radau && att.is_err(), heading) {
                    // a step sized to end past an event's crossing: a right-hand side that
                    // changes there (a sticking band) lets no Newton iteration converge across
                    // it, and every smaller step would end short of it again, until the steps
                    // collapse (the Geneva knife at the cut front: tests/elastodynamic.rs, the
                    // undamped 1e4 N/m chain's reference): explicit at once
                    (true, true) => EXPLICIT_AFTER,
                    (true, false) => newton_failures + 1,
                    (false, _) => 0,
                };
                let first = self.mem.stats.steps + st.steps == 0;
                h = self.rejected_step(stepper, hs, &att, first);
                if h < hmin {
                    return Err(format!(
                        "step-size collapse at t = {t}: step {h:.3e} s below {hmin:.3e} s ({}{})",
                        if stepper == Stepper::Radau {
                            "radau5"
                        } else {
                            "dopri5"
                        },
                        match att {
                            Err(e) => format!(": {}", e.reason),
                            Ok(a) => format!(", error estimate {:.3e}", a.err),
                        }
                    ));
                }
                continue;
            }
            let att = att.unwrap_or_else(|_| unreachable!("accepted"));
            newton_failures = 0;
            if stepper == Stepper::Dopri {
                self.stiffness_test(att.hlamb, st);
            }
            // events: a change at the step's end, or a pair of them inside it seen on the
            // interpolant at its middle
            sys.events_held(t + hs, y1, g0, g1);
            let crossed =
                |ga: &[f64], gb: &[f64]| ga.iter().zip(gb).any(|(a, b)| event_between(*a, *b));
            let mut seen = None;
            if ne > 0 {
                if crossed(g0, g1) {
                    seen = Some(hs);
                } else if rate[0].is_nan() {
                    // a first step, without the rates that limit it (or a fixed step, which they
                    // do not limit): the interpolant's middle
                    let ends = Ends {
                        y,
                        f0,
                        y1,
                        f1,
                        h: hs,
                    };
                    att.interpolate(&ends, 0.5 * hs, yt);
                    sys.events_held(t + 0.5 * hs, yt, g0, gt);
                    if crossed(g0, gt) {
                        seen = Some(0.5 * hs);
                    }
                }
            }
            let mut hacc = hs;
            let event = match seen {
                Some(s_seen) => {
                    let at_seen = if s_seen == hs {
                        g1.to_vec()
                    } else {
                        gt.to_vec()
                    };
                    match self.locate_event(
                        stepper,
                        at,
                        &att,
                        hs,
                        s_seen,
                        &at_seen,
                        (&mut *y1, &mut *f1),
                        g0,
                        st,
                    ) {
                        Some(s) => {
                            hacc = s;
                            sys.events_held(t + hacc, y1, g0, g1);
                            sys.on_event_held(t + hacc, y1, g0, g1);
                            sys.events_held(t + hacc, y1, g0, g1);
                            st.events += 1;
                            true
                        }
                        None => false,
                    }
                }
                None => false,
            };
            for i in 0..ne {
                rate[i] = if event {
                    f64::NAN
                } else {
                    (g1[i] - g0[i]) / hacc
                };
            }
            // accept
            let ratio = self.accepted_factor(stepper, n, hs, &att);
            if event {
                // the right-hand side changes at the event: no polynomial reaches across it,
                // and the Jacobian of the other side would misjudge the next steps' error (Radau
                // IIA filters its estimate through it)
                self.mem.radau.h_old = 0.0;
                self.mem.radau.h_acc = 0.0;
                self.mem.radau.need_jac = true;
            }
            let t_end = t + hacc;
            t = if last && hacc == hs { t1 } else { t_end };
            y.copy_from_slice(y1);
            if event || t != t_end {
                sys.rhs(t, y, f0);
                st.rhs_evals += 1;
            } else {
                f0.copy_from_slice(f1);
            }
            std::mem::swap(&mut g0, &mut g1);
            sys.on_step(t, y);
            st.steps += 1;
            self.weigh_methods(t, hs, max_step, st);
            if st.steps > set.max_steps {
                return Err(format!(
                    "step budget of {} steps exhausted at t = {t} of [{t0}, {t1}] (last step {hacc:.3e} s{})",
                    set.max_steps,
                    if stepper == Stepper::Dopri {
                        "; the problem is probably stiff: choose solver.method = auto or radau5"
                    } else {
                        ""
                    }
                ));
            }
            if !fixed {
                // a step cut short of the one the error allowed (the call's end, an event): that
                // one shrinks in proportion to the short step's error, and grows only to what the
                // error allows the short step itself (Hairer's new step after his last). Its small
                // error says little of the longer step's: grown by it, the next call's first
                // attempt failed
                let shortened = (last || hacc < hs) && h > hs;
                h = if shortened {
                    (h * ratio.min(1.0)).max(hs * ratio)
                } else {
                    hs * ratio
                }
                .min(max_step);
                if hacc == hs {
                    self.mem.h_next = h;
                }
            }
        }
        if !fixed {
            self.mem.h_next = h;
        }
        for (s, g) in self.mem.event_signs.iter_mut().zip(g0.iter()) {
            *s = if *g > 0.0 {
                1.0
            } else if *g < 0.0 {
                -1.0
            } else {
                0.0
            };
        }
        Ok(())
    }

    /// One attempt of `stepper` from `at` over `h`: the state `y1` and its derivative `f1`, or
    /// the reason Radau IIA's Newton iteration failed (the caller shrinks the step; it never
    /// changes the method behind a user's choice).
    fn attempt(
        &mut self,
        stepper: Stepper,
        at: Start,
        h: f64,
        y1: &mut [f64],
        f1: &mut [f64],
        st: &mut Stats,
    ) -> Result<Attempt, radau::NewtonFailure> {
        let Start { sys, t, y, .. } = at;
        self.scale_at(sys, y, stepper);
        match stepper {
            Stepper::Dopri => Ok(self.dopri(at, h, y1, f1, st)),
            Stepper::Rk4 => {
                rk4(at, h, y1, st);
                sys.rhs(t + h, y1, f1);
                st.rhs_evals += 1;
                Ok(Attempt {
                    err: 0.0,
                    hlamb: 0.0,
                    radau: None,
                    dopri_d5: None,
                })
            }
            Stepper::Radau => {
                self.radau_prepare(sys, t, y, h, st);
                let r = self.radau(at, h, y1, f1, st)?;
                Ok(Attempt {
                    err: r.err,
                    hlamb: 0.0,
                    radau: Some(r),
                    dopri_d5: None,
                })
            }
        }
    }
}

fn rk4(at: Start, h: f64, y1: &mut [f64], st: &mut Stats) {
    let Start {
        sys, t, y, f0: k1, ..
    } = at;
    let n = y.len();
    let [mut k2, mut k3, mut k4, mut ys] = [[0.0; MAX_DIM]; 4];
    for i in 0..n {
        ys[i] = y[i] + 0.5 * h * k1[i];
    }
    sys.rhs(t + 0.5 * h, &ys[..n], &mut k2[..n]);
    for i in 0..n {
        ys[i] = y[i] + 0.5 * h * k2[i];
    }
    sys.rhs(t + 0.5 * h, &ys[..n], &mut k3[..n]);
    for i in 0..n {
        ys[i] = y[i] + h * k3[i];
    }
    sys.rhs(t + h, &ys[..n], &mut k4[..n]);
    st.rhs_evals += 3;
    for i in 0..n {
        y1[i] = y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
}

#[cfg(test)]
mod tests;
