//! Integrators for the elastodynamic level (`../shared/spec/dynamics.md`, "Solver inside
//! fmi2DoStep"). Knows no mechanism: a mechanism hands an [`OdeSystem`] (right-hand side,
//! analytic Jacobian, event functions) and the integrator advances it over one communication
//! step.
//!
//! Methods ([`Method`], the FMU parameter `solver.method`):
//! - `dopri5`: explicit Dormand–Prince 5(4), adaptive, with Hairer's stiffness detection;
//! - `radau5`: implicit Radau IIA of order 5 (3 stages, L-stable, stiffly accurate) with the
//!   analytic Jacobian and a simplified Newton iteration on the full 3n×3n system (the systems
//!   are 2–6 states, so a dense LU of at most 18×18 is cheaper than the complex transformation),
//!   and Hairer's embedded error estimate (`radau5.f`, ESTRAD);
//! - `rk4`: classical fixed-step Runge–Kutta, step `solver.max_step`, for comparison;
//! - `auto` (default): Dormand–Prince while the step the accuracy asks for is within its
//!   stability region, Radau IIA when the spectral radius of the Jacobian times that step would
//!   leave it (and when Hairer's stiffness test fires), switching back when the stiffness goes:
//!   the LSODA idea.
//!
//! Events: every step is checked for sign changes of the system's event functions; the earliest
//! is located (a root of the Hermite interpolant, then confirmed with real steps to a bracket of
//! `1e-10` of the step) and the step ends just after it, so a discontinuity of the right-hand
//! side is never stepped over. An event function that rests at exactly zero over an interval (a
//! rigid velocity in a dwell) keeps the sign it had before ([`hold_signs`]), so that a Model
//! Exchange host's root finder (CVODE) sees an event where one takes the other sign and none
//! while it rests; the integrators here see the same functions with their own test
//! ([`event_between`]).
//!
//! Failure is an `Err` with the reason (step-size collapse, step budget, non-finite state, an
//! explicit method out of its stability region): the caller returns `fmi2Discard` and keeps the
//! state before the step.

use crate::model::Var;
use nalgebra::DMatrix;

pub mod chain;
mod dopri;
mod radau;

/// The shaft's path in a step (the shaft connector's, [`crate::model::shaft`]).
pub use crate::model::shaft::ShaftPath;
use dopri::hermite;
pub use radau::spectral_radius;

/// The largest system the integrators take.
pub const MAX_DIM: usize = 8;

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
/// and `b` later in it, as it has always been on the functions themselves: from a value off zero,
/// a change of sign or reaching zero (`b` held). Reaching a rest ends a step where a rigid
/// velocity comes to a dwell, a kink of the right-hand side; leaving a rest is no event here (a
/// Model Exchange host sees one where the sign changes): the dwells of these mechanisms end at
/// their phase events.
fn event_between(a: f64, b: f64) -> bool {
    a.abs() != HELD && ((a < 0.0 && b > 0.0) || (a > 0.0 && b < 0.0) || b.abs() == HELD)
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

/// The solver parameters every elastodynamic model declares (once, here).
pub mod vars {
    use super::*;
    /// `solver.method`.
    pub fn method() -> Var {
        Var::enum_parameter(
            "solver.method",
            &Method::FMI,
            "auto",
            "Integrator of the elastodynamic level inside fmi2DoStep",
        )
    }
    /// `solver.rtol`.
    pub fn rtol() -> Var {
        Var::parameter(
            "solver.rtol",
            1e-6,
            "",
            "Relative tolerance of the adaptive integrators (elastodynamic level)",
        )
        .min(1e-14)
        .max(1.0)
    }
    /// `solver.atol`.
    pub fn atol() -> Var {
        Var::parameter(
            "solver.atol",
            1e-9,
            "",
            "Absolute tolerance of the adaptive integrators, in the states' SI units (elastodynamic level)",
        )
        .min(1e-20)
        .max(1.0)
    }
    /// `solver.max_step`.
    pub fn max_step() -> Var {
        Var::parameter(
            "solver.max_step",
            1e-3,
            "s",
            "Largest internal step; the fixed step of rk4 (elastodynamic level)",
        )
        .min(1e-9)
    }
    /// `solver.steps` (Integer output).
    pub fn steps() -> Var {
        Var::int_output(
            "solver.steps",
            "Accepted integration steps since initialization: in Co-Simulation those of the FMU's integrator inside fmi2DoStep, in Model Exchange the host's (its fmi2CompletedIntegratorStep calls); 0 where nothing is integrated (below the elastodynamic level)",
        )
    }
    /// `elastic.E_residual`.
    pub fn e_residual() -> Var {
        Var::output(
            "elastic.E_residual",
            "J",
            "Energy-balance residual E - E0 - W of the integration, W a state: of the FMU's integrator in Co-Simulation, of the host's in Model Exchange (elastodynamic level)",
        )
    }
}

/// Solver settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    pub method: Method,
    pub rtol: f64,
    pub atol: f64,
    pub max_step: f64,
    /// Step budget of one `integrate` call.
    pub max_steps: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            method: Method::Auto,
            rtol: 1e-6,
            atol: 1e-9,
            max_step: 1e-3,
            max_steps: 200_000,
        }
    }
}

/// Counters of one or more `integrate` calls.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    pub steps: usize,
    pub rejected: usize,
    pub rhs_evals: usize,
    pub jac_evals: usize,
    pub events: usize,
    pub switches: usize,
}

impl Stats {
    fn add(&mut self, o: &Stats) {
        self.steps += o.steps;
        self.rejected += o.rejected;
        self.rhs_evals += o.rhs_evals;
        self.jac_evals += o.jac_evals;
        self.events += o.events;
        self.switches += o.switches;
    }
}

/// Which stepper a step uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stepper {
    Dopri,
    Radau,
    Rk4,
}

/// Everything an integrator carries from one `integrate` call to the next: the step size to
/// try, `auto`'s mode and the counters that decide its switches, the statistics. One value,
/// saved and restored as a unit (`fmi2GetFMUstate`, a refused step), so a restored integrator
/// replays every step bit for bit under every method.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Memory {
    /// Step size to try next (0: choose one).
    pub h_next: f64,
    /// `auto` is in its stiff (implicit) mode.
    pub stiff: bool,
    /// Consecutive Dormand–Prince steps with h·|λ| > 3.25 (Hairer's stiffness test).
    pub stiff_count: u32,
    /// Consecutive checks in the stiff mode that found the explicit method stable.
    pub nonstiff_count: u32,
    /// Counters since creation.
    pub stats: Stats,
}

impl Memory {
    /// Numbers of [`Memory::to_numbers`].
    pub const LEN: usize = 10;

    /// The memory as numbers (counters exact up to 2^53).
    pub fn to_numbers(&self) -> [f64; Memory::LEN] {
        let s = &self.stats;
        [
            self.h_next,
            f64::from(u8::from(self.stiff)),
            f64::from(self.stiff_count),
            f64::from(self.nonstiff_count),
            s.steps as f64,
            s.rejected as f64,
            s.rhs_evals as f64,
            s.jac_evals as f64,
            s.events as f64,
            s.switches as f64,
        ]
    }

    /// The memory [`Memory::to_numbers`] wrote, checked: a step size finite and not negative,
    /// a flag 0 or 1, counters whole numbers from 0 to 2^53 (a host may alter a serialized
    /// state).
    pub fn from_numbers(x: &[f64]) -> Result<Memory, String> {
        const NAMES: [&str; Memory::LEN] = [
            "next step size",
            "stiff mode",
            "stiffness count",
            "non-stiffness count",
            "steps",
            "rejected steps",
            "right-hand side evaluations",
            "Jacobian evaluations",
            "events",
            "method switches",
        ];
        if x.len() != Memory::LEN {
            return Err(format!(
                "integrator memory has {} numbers, expected {}",
                x.len(),
                Memory::LEN
            ));
        }
        if !(x[0].is_finite() && x[0] >= 0.0) {
            return Err(format!("integrator's {} = {:?} refused", NAMES[0], x[0]));
        }
        let limit = |i: usize| {
            if i == 1 {
                1.0
            } else if i < 4 {
                u32::MAX as f64
            } else {
                9007199254740992.0
            }
        };
        if let Some(i) =
            (1..Memory::LEN).find(|&i| !(x[i] >= 0.0 && x[i] <= limit(i) && x[i].fract() == 0.0))
        {
            return Err(format!(
                "integrator's {} = {:?} refused: a whole number from 0 to {} expected",
                NAMES[i],
                x[i],
                limit(i)
            ));
        }
        Ok(Memory {
            h_next: x[0],
            stiff: x[1] == 1.0,
            stiff_count: x[2] as u32,
            nonstiff_count: x[3] as u32,
            stats: Stats {
                steps: x[4] as usize,
                rejected: x[5] as usize,
                rhs_evals: x[6] as usize,
                jac_evals: x[7] as usize,
                events: x[8] as usize,
                switches: x[9] as usize,
            },
        })
    }
}

/// An integrator: its settings (from the model's parameters) and its [`Memory`].
#[derive(Clone, Debug, PartialEq)]
pub struct Integrator {
    pub settings: Settings,
    pub mem: Memory,
}

/// Where a step attempt starts: the system, time, state, its derivative and (for Radau IIA) the
/// Jacobian there.
#[derive(Clone, Copy)]
struct Start<'a> {
    sys: &'a dyn OdeSystem,
    t: f64,
    y: &'a [f64],
    f0: &'a [f64],
    jac: &'a [f64],
}

/// Outcome of one step attempt.
struct Attempt {
    err: f64,
    /// Hairer's stiffness estimate h·|λ| (Dormand–Prince only), else 0.
    hlamb: f64,
}

impl Integrator {
    /// A fresh integrator.
    pub fn new(settings: Settings) -> Self {
        Integrator {
            settings,
            mem: Memory {
                stiff: settings.method == Method::Radau5,
                ..Memory::default()
            },
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

    fn norm(&self, sys: &dyn OdeSystem, e: &[f64], y0: &[f64], y1: &[f64]) -> f64 {
        let n = e.len();
        let mut s = 0.0;
        let mut m = 0.0;
        for i in 0..n {
            let w = sys.error_weight(i);
            if w == 0.0 {
                continue;
            }
            let sc = self.settings.atol + self.settings.rtol * y0[i].abs().max(y1[i].abs());
            let r = e[i] / sc;
            s += w * r * r;
            m += w;
        }
        if m == 0.0 { 0.0 } else { (s / m).sqrt() }
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
        let mut f0 = vec![0.0; n];
        sys.rhs(t, y, &mut f0);
        st.rhs_evals += 1;
        let mut g0 = vec![0.0; ne];
        let mut g1 = vec![0.0; ne];
        // (the held signs do not change the integrators' test, [`event_between`]: no memory
        // of them is carried from the last call)
        sys.events_held(t, y, &[], &mut g0);
        let mut y1 = vec![0.0; n];
        let mut f1 = vec![0.0; n];
        let mut yt = vec![0.0; n];
        let mut ft = vec![0.0; n];
        let mut gt = vec![0.0; ne];
        let mut jac = vec![0.0; n * n];
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
            self.initial_step(sys, t, y, &f0, max_step, st)
        };
        let hmin = 1e-14 * (t0.abs() + span).max(1e-3);
        loop {
            let rest = t1 - t;
            if rest <= 1e-13 * t1.abs().max(span) {
                break;
            }
            let mut hs = h.min(max_step);
            let last = hs >= rest * (1.0 - 1e-12);
            if last {
                hs = rest;
            }
            // choose the stepper
            let stepper = match set.method {
                Method::Rk4 => Stepper::Rk4,
                Method::Dopri5 => Stepper::Dopri,
                Method::Radau5 => Stepper::Radau,
                Method::Auto => {
                    if self.mem.stiff {
                        Stepper::Radau
                    } else {
                        Stepper::Dopri
                    }
                }
            };
            if matches!(stepper, Stepper::Radau | Stepper::Rk4) || set.method == Method::Auto {
                sys.jacobian(t, y, &mut jac);
                st.jac_evals += 1;
            }
            // the spectral radius (an eigenvalue problem) only where it decides something
            let check_rho = st.steps.is_multiple_of(20);
            if stepper == Stepper::Rk4 && check_rho {
                let rho = spectral_radius(n, &jac);
                if hs * rho > 2.78 {
                    return Err(format!(
                        "rk4 with step {hs:.3e} s is unstable here: the stiffest mode has |lambda| = {rho:.3e} 1/s, h*|lambda| = {:.3e} > 2.78; set solver.max_step below {:.3e} s or choose solver.method = auto or radau5",
                        hs * rho,
                        2.78 / rho
                    ));
                }
            }
            if set.method == Method::Auto && check_rho {
                // LSODA-like: compare the accuracy step with the explicit stability limit.
                let rho = spectral_radius(n, &jac);
                let h_stab = 3.3 / rho.max(1e-300);
                if !self.mem.stiff && hs > 1.5 * h_stab {
                    self.mem.stiff = true;
                    st.switches += 1;
                } else if self.mem.stiff {
                    if hs < 0.5 * h_stab {
                        self.mem.nonstiff_count += 1;
                        if self.mem.nonstiff_count > 2 {
                            self.mem.stiff = false;
                            self.mem.nonstiff_count = 0;
                            st.switches += 1;
                        }
                    } else {
                        self.mem.nonstiff_count = 0;
                    }
                }
            }
            let stepper = if set.method == Method::Auto {
                if self.mem.stiff {
                    Stepper::Radau
                } else {
                    Stepper::Dopri
                }
            } else {
                stepper
            };
            let at = Start {
                sys,
                t,
                y,
                f0: &f0,
                jac: &jac,
            };
            let att = self.attempt(stepper, at, hs, &mut y1, &mut f1, st);
            let accepted = match &att {
                Ok(a) => a.err <= 1.0 && y1.iter().all(|x| x.is_finite()),
                Err(_) => false,
            };
            if !accepted {
                if fixed {
                    return Err(match att {
                        Err(e) => e,
                        Ok(_) => format!("rk4 produced a non-finite state at t = {t}"),
                    });
                }
                st.rejected += 1;
                let fac = match &att {
                    Ok(a) if a.err.is_finite() => {
                        let p = if stepper == Stepper::Radau { 0.25 } else { 0.2 };
                        (0.9 * a.err.powf(-p)).clamp(0.1, 0.9)
                    }
                    _ => 0.25,
                };
                h = hs * fac;
                if h < hmin {
                    return Err(format!(
                        "step-size collapse at t = {t}: step {h:.3e} s below {hmin:.3e} s ({}{})",
                        if stepper == Stepper::Radau {
                            "radau5"
                        } else {
                            "dopri5"
                        },
                        match att {
                            Err(e) => format!(": {e}"),
                            Ok(a) => format!(", error estimate {:.3e}", a.err),
                        }
                    ));
                }
                continue;
            }
            let att = att.expect("accepted");
            // stiffness detection inside Dormand-Prince (Hairer): h*|lambda| > 3.25 repeatedly
            if stepper == Stepper::Dopri {
                if att.hlamb > 3.25 {
                    self.mem.stiff_count += 1;
                    if self.mem.stiff_count >= 15 {
                        if set.method == Method::Auto {
                            self.mem.stiff = true;
                            st.switches += 1;
                        }
                        self.mem.stiff_count = 0;
                    }
                } else {
                    self.mem.stiff_count = 0;
                }
            }
            // events
            let mut hacc = hs;
            sys.events_held(t + hs, &y1, &g0, &mut g1);
            let crossed =
                |ga: &[f64], gb: &[f64]| ga.iter().zip(gb).any(|(a, b)| event_between(*a, *b));
            if ne > 0 && crossed(&g0, &g1) {
                // earliest root on the interpolant
                let mut s_star = hs;
                for i in 0..ne {
                    if !event_between(g0[i], g1[i]) {
                        continue;
                    }
                    let (mut lo, mut hi) = (0.0, hs);
                    let (mut glo, mut ghi) = (g0[i], g1[i]);
                    for _ in 0..60 {
                        let mid = if ghi != glo {
                            (lo - glo * (hi - lo) / (ghi - glo))
                                .clamp(lo + 0.01 * (hi - lo), hi - 0.01 * (hi - lo))
                        } else {
                            0.5 * (lo + hi)
                        };
                        hermite(y, &f0, &y1, &f1, hs, mid, &mut yt);
                        sys.events_held(t + mid, &yt, &g0, &mut gt);
                        if !event_between(g0[i], gt[i]) {
                            lo = mid;
                            glo = gt[i];
                        } else {
                            hi = mid;
                            ghi = gt[i];
                        }
                        if hi - lo < 1e-12 * hs {
                            break;
                        }
                    }
                    s_star = s_star.min(hi);
                }
                // confirm with real steps: bracket [lo, hi] with the crossing inside
                let tol = (1e-10 * hs).max(4.0 * f64::EPSILON * t.abs().max(1.0));
                let (mut lo, mut hi) = (0.0f64, hs);
                let mut yhi = y1.clone();
                let mut fhi = f1.clone();
                let mut guess = Some((s_star + tol).min(hs));
                let mut second = Some((s_star - tol).max(0.0));
                let mut iter = 0;
                while hi - lo > 2.0 * tol && iter < 80 {
                    iter += 1;
                    let s = if let Some(g) = guess.take() {
                        g
                    } else if let Some(g) = second.take() {
                        g
                    } else {
                        0.5 * (lo + hi)
                    };
                    if s <= lo || s >= hi {
                        continue;
                    }
                    if self.attempt(stepper, at, s, &mut yt, &mut ft, st).is_err() {
                        lo = s; // treat as not yet crossed; bisection continues
                        continue;
                    }
                    sys.events_held(t + s, &yt, &g0, &mut gt);
                    if crossed(&g0, &gt) {
                        hi = s;
                        yhi.copy_from_slice(&yt);
                        fhi.copy_from_slice(&ft);
                    } else {
                        lo = s;
                    }
                }
                hacc = hi;
                y1.copy_from_slice(&yhi);
                f1.copy_from_slice(&fhi);
                sys.events_held(t + hacc, &y1, &g0, &mut g1);
                sys.on_event_held(t + hacc, &y1, &g0, &g1);
                sys.events_held(t + hacc, &y1, &g0, &mut g1);
                st.events += 1;
            }
            // accept
            t = if last && hacc == hs { t1 } else { t + hacc };
            y.copy_from_slice(&y1);
            // after an event the right-hand side changes: evaluate it afresh
            sys.rhs(t, y, &mut f0);
            st.rhs_evals += 1;
            std::mem::swap(&mut g0, &mut g1);
            sys.on_step(t, y);
            st.steps += 1;
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
                let p = if stepper == Stepper::Radau { 0.25 } else { 0.2 };
                let fac = if att.err > 0.0 {
                    (0.9 * att.err.powf(-p)).clamp(0.2, 5.0)
                } else {
                    5.0
                };
                // do not let the last (shortened) step or an event shrink the memory
                let base = if (last || hacc < hs) && h > hs { h } else { hs };
                h = (base * fac).min(max_step);
                if hacc == hs {
                    self.mem.h_next = h;
                }
            }
        }
        if !fixed {
            self.mem.h_next = h;
        }
        Ok(())
    }

    /// One attempt of `stepper` from `at` over `h`: the state `y1` and its derivative `f1`.
    fn attempt(
        &self,
        stepper: Stepper,
        at: Start,
        h: f64,
        y1: &mut [f64],
        f1: &mut [f64],
        st: &mut Stats,
    ) -> Result<Attempt, String> {
        let Start { sys, t, .. } = at;
        match stepper {
            Stepper::Dopri => Ok(self.dopri(at, h, y1, f1, st)),
            Stepper::Rk4 => {
                rk4(at, h, y1, st);
                sys.rhs(t + h, y1, f1);
                st.rhs_evals += 1;
                Ok(Attempt {
                    err: 0.0,
                    hlamb: 0.0,
                })
            }
            Stepper::Radau => match self.radau(at, h, y1, f1, st) {
                // The Newton iteration cannot converge on a step whose stages straddle a
                // discontinuity of the right-hand side (an event surface): the step that crosses
                // it is taken explicitly; its error estimate still decides, and at the short
                // steps near an event the explicit method is well inside its stability region.
                Err(e) => {
                    let a = self.dopri(at, h, y1, f1, st);
                    if a.err <= 1.0 { Ok(a) } else { Err(e) }
                }
                ok => ok,
            },
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
