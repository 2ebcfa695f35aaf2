//! Everything an integrator carries from one step to the next, as one value ([`Memory`]) and as
//! the numbers of the FMU state, checked when a host hands them back.

use super::{MAX_DIM, MAX_EVENTS};

/// Counters of one or more `integrate` calls (they do not depend on the machine or its load).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected attempts: by the error estimate, or a Newton iteration that failed.
    pub rejected: usize,
    pub rhs_evals: usize,
    pub jac_evals: usize,
    /// LU factorizations of Radau IIA's Newton matrices (a real and a complex one each).
    pub decomps: usize,
    pub events: usize,
    /// Changes of `auto` between the explicit and the implicit method.
    pub switches: usize,
    /// Explicit attempts Radau IIA made where its Newton iteration failed twice in a row (the
    /// step halved between): a state-dependent jump of the right-hand side that no event marks.
    pub fallbacks: usize,
}

impl Stats {
    /// The work counted against a call's budget ([`super::work_budget`]) and weighed by
    /// `auto`: right-hand sides, Jacobians and LU factorizations alike.
    pub fn work(&self) -> f64 {
        (self.rhs_evals + self.jac_evals + self.decomps) as f64
    }

    pub(super) fn add(&mut self, o: &Stats) {
        self.steps += o.steps;
        self.rejected += o.rejected;
        self.rhs_evals += o.rhs_evals;
        self.jac_evals += o.jac_evals;
        self.decomps += o.decomps;
        self.events += o.events;
        self.switches += o.switches;
        self.fallbacks += o.fallbacks;
    }
}

/// What Radau IIA carries from step to step (Hairer's `RADCOR`): the Jacobian in use and the
/// step size its Newton matrices are factorized for, the last step's collocation polynomial
/// (the Newton iteration's starting values), the Newton contraction, and the predictive step
/// controller's last accepted step. The factors themselves are a function of `jac` and `lu_h`,
/// recomputed bit for bit where they are not at hand (after a restore).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadauMemory {
    /// `∂f/∂y`, row-major `n×n`.
    pub jac: [f64; MAX_DIM * MAX_DIM],
    /// `jac` holds a Jacobian.
    pub has_jac: bool,
    /// It was evaluated at the start of the current step (Hairer's `CALJAC`): a step that fails
    /// with it is not the Jacobian's fault, only the step size's.
    pub jac_fresh: bool,
    /// The next step evaluates a new Jacobian (the Newton iteration converged slowly).
    pub need_jac: bool,
    /// The step size the Newton matrices are factorized for (0: none).
    pub lu_h: f64,
    /// The collocation polynomial of the last accepted step (Hairer's `CONT(N+1..4N)`).
    pub cont: [f64; 3 * MAX_DIM],
    /// That step's size; 0: no polynomial to start from (the first step, after an event or an
    /// explicit step).
    pub h_old: f64,
    /// Newton contraction of the last iteration (Hairer's `THETA`) and its `FACCON`.
    pub theta: f64,
    pub faccon: f64,
    /// Gustafsson's predictive controller: the last accepted step and its error (0: none).
    pub h_acc: f64,
    pub err_acc: f64,
}

impl Default for RadauMemory {
    fn default() -> Self {
        RadauMemory {
            jac: [0.0; MAX_DIM * MAX_DIM],
            has_jac: false,
            jac_fresh: false,
            need_jac: false,
            lu_h: 0.0,
            cont: [0.0; 3 * MAX_DIM],
            h_old: 0.0,
            theta: 0.0,
            faccon: 1.0,
            h_acc: 0.0,
            err_acc: 0.0,
        }
    }
}

/// Everything an integrator carries from one `integrate` call to the next: the step size to
/// try, `auto`'s mode and the counters that decide its switches, each method's controller
/// memory, the statistics. One value, saved and restored as a unit (`fmi2GetFMUstate`, a
/// refused step), so a restored integrator replays every step bit for bit under every method.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Memory {
    /// Step size to try next (0: choose one).
    pub h_next: f64,
    /// `auto` is in its stiff (implicit) mode.
    pub stiff: bool,
    /// Dormand–Prince steps with h·|λ| > 3.25 (Hairer's `IASTI`), reset after six without.
    pub stiff_count: u32,
    /// Dormand–Prince steps without since the last with (Hairer's `NONSTI`); in the stiff mode
    /// of `auto`, consecutive checks that found the explicit method stable.
    pub nonstiff_count: u32,
    /// Dormand–Prince's PI controller: the error of the last accepted step (Hairer's `FACOLD`).
    pub err_old: f64,
    /// The last attempt was rejected: the next accepted step may not grow (Hairer's `REJECT`).
    pub rejected: bool,
    /// `auto`'s cost window: where it began (time, work) and its accepted steps.
    pub window_t0: f64,
    pub window_work0: f64,
    pub window_steps: u32,
    /// `auto`: the work per simulated second of each method when last measured (0: not yet),
    /// and whether the implicit method runs as a trial against the explicit one.
    pub rate_explicit: f64,
    pub rate_implicit: f64,
    pub trial: bool,
    /// The sign of each event function where the last call ended (0: none yet), so that one
    /// resting at zero at the start of the next call holds it ([`super::hold_signs`]).
    pub event_signs: [f64; MAX_EVENTS],
    pub radau: RadauMemory,
    /// Counters since creation.
    pub stats: Stats,
}

/// How a number of the memory is checked when a host hands it back.
#[derive(Clone, Copy)]
enum Kind {
    /// Finite, of either sign.
    Finite,
    /// Finite and not negative.
    Size,
    /// 0 or 1.
    Flag,
    /// A whole number from 0 to the limit.
    Count(f64),
    /// −1, 0 or 1.
    Sign,
}

/// The numbers of [`Memory`] in order: name, how many, kind.
const LAYOUT: [(&str, usize, Kind); 33] = [
    ("next step size", 1, Kind::Size),
    ("stiff mode", 1, Kind::Flag),
    ("stiffness count", 1, Kind::Count(u32::MAX as f64)),
    ("non-stiffness count", 1, Kind::Count(u32::MAX as f64)),
    ("last error", 1, Kind::Size),
    ("rejection flag", 1, Kind::Flag),
    ("cost window start", 1, Kind::Finite),
    ("cost window work", 1, Kind::Count(COUNT_LIMIT)),
    ("cost window steps", 1, Kind::Count(u32::MAX as f64)),
    ("explicit method's cost", 1, Kind::Size),
    ("implicit method's cost", 1, Kind::Size),
    ("trial flag", 1, Kind::Flag),
    ("event signs", MAX_EVENTS, Kind::Sign),
    ("Jacobian", MAX_DIM * MAX_DIM, Kind::Finite),
    ("Jacobian flag", 1, Kind::Flag),
    ("fresh-Jacobian flag", 1, Kind::Flag),
    ("new-Jacobian flag", 1, Kind::Flag),
    ("factorized step size", 1, Kind::Size),
    ("collocation polynomial", 3 * MAX_DIM, Kind::Finite),
    ("last Radau step size", 1, Kind::Size),
    ("Newton contraction", 1, Kind::Size),
    ("Newton convergence factor", 1, Kind::Size),
    ("last accepted step size", 1, Kind::Size),
    ("last accepted error", 1, Kind::Size),
    ("steps", 1, Kind::Count(COUNT_LIMIT)),
    ("rejected steps", 1, Kind::Count(COUNT_LIMIT)),
    ("right-hand side evaluations", 1, Kind::Count(COUNT_LIMIT)),
    ("Jacobian evaluations", 1, Kind::Count(COUNT_LIMIT)),
    ("LU factorizations", 1, Kind::Count(COUNT_LIMIT)),
    ("events", 1, Kind::Count(COUNT_LIMIT)),
    ("method switches", 1, Kind::Count(COUNT_LIMIT)),
    ("explicit fallbacks", 1, Kind::Count(COUNT_LIMIT)),
    ("(end)", 0, Kind::Finite),
];

/// Counters are exact in an `f64` up to 2^53.
const COUNT_LIMIT: f64 = 9007199254740992.0;

const fn layout_len() -> usize {
    let mut n = 0;
    let mut i = 0;
    while i < LAYOUT.len() {
        n += LAYOUT[i].1;
        i += 1;
    }
    n
}

impl Memory {
    /// Numbers of [`Memory::to_numbers`].
    pub const LEN: usize = layout_len();

    /// The memory as numbers, in the order of its fields.
    pub fn to_numbers(&self) -> [f64; Memory::LEN] {
        let (r, s) = (&self.radau, &self.stats);
        let flag = |b: bool| f64::from(u8::from(b));
        let mut out = [0.0; Memory::LEN];
        let mut at = 0;
        let mut put = |xs: &[f64]| {
            out[at..at + xs.len()].copy_from_slice(xs);
            at += xs.len();
        };
        put(&[
            self.h_next,
            flag(self.stiff),
            f64::from(self.stiff_count),
            f64::from(self.nonstiff_count),
            self.err_old,
            flag(self.rejected),
            self.window_t0,
            self.window_work0,
            f64::from(self.window_steps),
            self.rate_explicit,
            self.rate_implicit,
            flag(self.trial),
        ]);
        put(&self.event_signs);
        put(&r.jac);
        put(&[flag(r.has_jac), flag(r.jac_fresh), flag(r.need_jac), r.lu_h]);
        put(&r.cont);
        put(&[r.h_old, r.theta, r.faccon, r.h_acc, r.err_acc]);
        put(&[
            s.steps,
            s.rejected,
            s.rhs_evals,
            s.jac_evals,
            s.decomps,
            s.events,
            s.switches,
            s.fallbacks,
        ]
        .map(|c| c as f64));
        out
    }

    /// The memory [`Memory::to_numbers`] wrote, each number checked (a host may alter a
    /// serialized state): sizes finite and not negative, flags 0 or 1, counters whole numbers
    /// from 0 to their limit, the Jacobian and polynomial finite.
    pub fn from_numbers(x: &[f64]) -> Result<Memory, String> {
        crate::model::saved::expect_len("integrator memory", x, &[Memory::LEN])?;
        let mut at = 0;
        for (name, len, kind) in LAYOUT {
            for (i, &v) in x[at..at + len].iter().enumerate() {
                let ok = match kind {
                    Kind::Finite => v.is_finite(),
                    Kind::Size => v.is_finite() && v >= 0.0,
                    Kind::Flag => v == 0.0 || v == 1.0,
                    Kind::Count(limit) => v >= 0.0 && v <= limit && v.fract() == 0.0,
                    Kind::Sign => v == -1.0 || v == 0.0 || v == 1.0,
                };
                if !ok {
                    let which = if len > 1 {
                        format!("{name}[{i}]")
                    } else {
                        name.into()
                    };
                    let expected = match kind {
                        Kind::Finite => "a finite number".to_string(),
                        Kind::Size => "a finite number >= 0".to_string(),
                        Kind::Flag => "0 or 1".to_string(),
                        Kind::Count(limit) => format!("a whole number from 0 to {limit}"),
                        Kind::Sign => "-1, 0 or 1".to_string(),
                    };
                    return Err(format!(
                        "integrator's {which} = {v:?} refused: {expected} expected"
                    ));
                }
            }
            at += len;
        }
        let mut at = 0;
        let mut take = |n: usize| {
            at += n;
            &x[at - n..at]
        };
        let head = take(12);
        let (h_next, stiff, stiff_count, nonstiff_count, err_old, rejected) = (
            head[0],
            head[1] == 1.0,
            head[2] as u32,
            head[3] as u32,
            head[4],
            head[5] == 1.0,
        );
        let (window_t0, window_work0, window_steps) = (head[6], head[7], head[8] as u32);
        let (rate_explicit, rate_implicit, trial) = (head[9], head[10], head[11] == 1.0);
        let mut event_signs = [0.0; MAX_EVENTS];
        event_signs.copy_from_slice(take(MAX_EVENTS));
        let mut jac = [0.0; MAX_DIM * MAX_DIM];
        jac.copy_from_slice(take(MAX_DIM * MAX_DIM));
        let f = take(4);
        let (has_jac, jac_fresh, need_jac, lu_h) = (f[0] == 1.0, f[1] == 1.0, f[2] == 1.0, f[3]);
        let mut cont = [0.0; 3 * MAX_DIM];
        cont.copy_from_slice(take(3 * MAX_DIM));
        let r = take(5);
        let c = take(8);
        Ok(Memory {
            h_next,
            stiff,
            stiff_count,
            nonstiff_count,
            err_old,
            rejected,
            window_t0,
            window_work0,
            window_steps,
            rate_explicit,
            rate_implicit,
            trial,
            event_signs,
            radau: RadauMemory {
                jac,
                has_jac,
                jac_fresh,
                need_jac,
                lu_h,
                cont,
                h_old: r[0],
                theta: r[1],
                faccon: r[2],
                h_acc: r[3],
                err_acc: r[4],
            },
            stats: Stats {
                steps: c[0] as usize,
                rejected: c[1] as usize,
                rhs_evals: c[2] as usize,
                jac_evals: c[3] as usize,
                decomps: c[4] as usize,
                events: c[5] as usize,
                switches: c[6] as usize,
                fallbacks: c[7] as usize,
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_numbers_round_trip_and_a_damaged_one_is_named() {
        let mut m = Memory {
            h_next: 1e-4,
            stiff: true,
            stiff_count: 3,
            err_old: 0.25,
            ..Memory::default()
        };
        m.radau.jac[4] = -2.5;
        m.radau.cont[7] = 1e-9;
        m.radau.lu_h = 2e-4;
        m.stats.decomps = 12;
        let x = m.to_numbers();
        assert_eq!(Memory::from_numbers(&x), Ok(m));
        let mut bad = x;
        bad[12 + MAX_EVENTS + 4] = f64::NAN;
        let e = Memory::from_numbers(&bad).unwrap_err();
        assert!(e.contains("Jacobian[4]"), "{e}");
        let mut bad = x;
        bad[Memory::LEN - 4] = 2.5;
        let e = Memory::from_numbers(&bad).unwrap_err();
        assert!(e.contains("LU factorizations"), "{e}");
        assert!(Memory::from_numbers(&x[1..]).is_err());
    }
}
