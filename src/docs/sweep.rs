//! The numbers a documentation page states "at the defaults": every output of a mechanism over
//! a shaft turn at its nominal speed `drive.n`, computed from the model when the page is made,
//! so the page cannot go stale against the model. Generic over [`Model`]: it drives the shaft
//! inputs `shaft.phi`, `shaft.w`, `shaft.a` by name.

use super::number;
use crate::md::display_factor;
use crate::model::{Causality, Model, NoLog, Values, Var, VarSet, VarType, shaft::Fidelity};
use std::f64::consts::TAU;

/// Samples per shaft turn.
const SAMPLES: usize = 720;

/// One output over the turn: extremes with the shaft angle (deg) where they occur, RMS and,
/// for a Boolean, the fraction of the turn it is true.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stat {
    pub min: f64,
    pub min_at: f64,
    pub max: f64,
    pub max_at: f64,
    pub rms: f64,
    pub true_fraction: f64,
}

/// Every output of a model over its second turn at the nominal speed, default parameters; an
/// output the default level does not compute comes from a turn at the elastodynamic level.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The nominal speed, rpm.
    pub rpm: f64,
    vars: Vec<&'static Var>,
    stats: Vec<Option<Stat>>,
    /// The level each output's numbers come from.
    levels: Vec<Option<Fidelity>>,
    /// Every value after initialization at the default level (parameters, calculated ones).
    initial: Vec<f64>,
}

fn index(table: &[Var], name: &str) -> Result<usize, String> {
    table
        .iter()
        .position(|v| v.name == name)
        .ok_or_else(|| format!("no variable {name}"))
}

/// Two turns of `M` at `fidelity` with the shaft at the nominal speed: the statistics of every
/// variable over the second, and the values after initialization.
fn run<M: Model>(fidelity: Fidelity) -> Result<(Vec<Stat>, Vec<f64>), String> {
    let table = <M::Var as VarSet>::table();
    let (phi, w, a) = (
        index(table, "shaft.phi")?,
        index(table, "shaft.w")?,
        index(table, "shaft.a")?,
    );
    let mut v = Values::<M::Var>::start();
    if let Ok(i) = index(table, "model.fidelity") {
        v.raw_mut()[i] = fidelity as i32 as f64;
    }
    let speed = v.raw()[index(table, "drive.n")?];
    let h = TAU / speed / SAMPLES as f64;
    let set = |v: &mut Values<M::Var>, t: f64| {
        let raw = v.raw_mut();
        (raw[phi], raw[w], raw[a]) = (speed * t, speed, 0.0);
    };
    set(&mut v, 0.0);
    let id = M::IDENTIFIER;
    let mut m = M::prepare(&v).map_err(|e| format!("{id}: defaults refused: {e}"))?;
    m.calculated_parameters(&mut v);
    m.evaluate(&mut v, 0.0, &mut NoLog);
    let initial = v.raw().to_vec();
    let mut stats = vec![
        Stat {
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
            ..Stat::default()
        };
        table.len()
    ];
    for k in 0..2 * SAMPLES {
        let t = k as f64 * h;
        set(&mut v, t);
        m.step(&mut v, t, h, &mut NoLog)
            .map_err(|e| format!("{id} at {t} s: {e}"))?;
        set(&mut v, t + h);
        m.evaluate(&mut v, t + h, &mut NoLog);
        if k < SAMPLES {
            continue;
        }
        let deg = 360.0 * (k + 1 - SAMPLES) as f64 / SAMPLES as f64;
        for (s, &x) in stats.iter_mut().zip(v.raw()) {
            if x < s.min {
                (s.min, s.min_at) = (x, deg);
            }
            if x > s.max {
                (s.max, s.max_at) = (x, deg);
            }
            s.rms += x * x / SAMPLES as f64;
            s.true_fraction += f64::from(x != 0.0) / SAMPLES as f64;
        }
    }
    for s in &mut stats {
        s.rms = s.rms.sqrt();
    }
    Ok((stats, initial))
}

/// The sweep of `M`'s outputs (see [`Sweep`]).
pub fn sweep<M: Model>() -> Result<Sweep, String> {
    let table = <M::Var as VarSet>::table();
    let default = index(table, "model.fidelity")
        .ok()
        .and_then(|i| table[i].start)
        .map_or(Fidelity::Kinetostatic, |x| match x as i32 {
            1 => Fidelity::Kinematic,
            3 => Fidelity::Elastodynamic,
            _ => Fidelity::Kinetostatic,
        });
    let (base, initial) = run::<M>(default)?;
    let at = |v: &Var| crate::scene::levels_of(M::STAGES, v.needs);
    let elastic = table
        .iter()
        .any(|v| v.causality == Causality::Output && !at(v).contains(&default))
        .then(|| run::<M>(Fidelity::Elastodynamic))
        .transpose()?;
    let mut stats = Vec::with_capacity(table.len());
    let mut levels = Vec::with_capacity(table.len());
    for (i, v) in table.iter().enumerate() {
        let levels_of_v = at(v);
        let pick = if v.causality != Causality::Output {
            None
        } else if levels_of_v.contains(&default) {
            Some((base[i], default))
        } else {
            (elastic.as_ref())
                .filter(|_| levels_of_v.contains(&Fidelity::Elastodynamic))
                .map(|(e, _)| (e[i], Fidelity::Elastodynamic))
        };
        stats.push(pick.map(|p| p.0));
        levels.push(pick.map(|p| p.1));
    }
    let rpm = initial[index(table, "drive.n")?] * 30.0 / std::f64::consts::PI;
    Ok(Sweep {
        rpm,
        vars: table.iter().collect(),
        stats,
        levels,
        initial,
    })
}

/// The values of `M` after initialization with the default parameters (calculated parameters
/// included), for a model without shaft inputs: no turn, no statistics.
pub fn defaults<M: Model>() -> Result<Sweep, String> {
    let table = <M::Var as VarSet>::table();
    let mut v = Values::<M::Var>::start();
    let m = M::prepare(&v).map_err(|e| format!("{}: defaults refused: {e}", M::IDENTIFIER))?;
    m.calculated_parameters(&mut v);
    Ok(Sweep {
        rpm: f64::NAN,
        vars: table.iter().collect(),
        stats: vec![None; table.len()],
        levels: vec![None; table.len()],
        initial: v.raw().to_vec(),
    })
}

/// `x` (SI) of `v` as a designer reads it: in the display unit (mm, deg, rpm, MPa), forces
/// from 1 kN up in kN, `sig` significant digits.
pub fn quantity(v: &Var, x: f64, sig: usize) -> String {
    let unit = v.unit.unwrap_or("");
    let (f, u) = match (v.unit, v.display_unit) {
        (Some(u), Some(d)) if d != u => (display_factor(u, d).unwrap_or(1.0), d),
        (Some("N"), _) if x.abs() >= 1000.0 => (1e-3, "kN"),
        _ => (1.0, unit),
    };
    format!("{} {u}", number(x * f, sig)).trim_end().to_string()
}

impl Sweep {
    fn find(&self, name: &str) -> Option<usize> {
        self.vars.iter().position(|v| v.name == name)
    }

    /// The statistics of an output, if computed.
    pub fn stat(&self, name: &str) -> Option<Stat> {
        self.find(name).and_then(|i| self.stats[i])
    }

    /// The level an output's numbers come from.
    pub fn level(&self, name: &str) -> Option<Fidelity> {
        self.find(name).and_then(|i| self.levels[i])
    }

    /// A variable's value after initialization at the defaults (parameters, calculated ones).
    pub fn initial(&self, name: &str) -> Option<f64> {
        self.find(name).map(|i| self.initial[i])
    }

    /// `min … max` of an output, in its display unit ("0 … 140 mm"); a Boolean: the fraction
    /// of the turn it is true.
    pub fn range(&self, name: &str) -> String {
        let (Some(i), Some(s)) = (self.find(name), self.stat(name)) else {
            return "–".into();
        };
        let v = self.vars[i];
        match v.ty {
            VarType::Boolean => match s.true_fraction {
                0.0 => "false all turn".into(),
                1.0 => "true all turn".into(),
                f => format!("true {} % of the turn", number(100.0 * f, 3)),
            },
            VarType::Integer | VarType::Enumeration(_) => {
                if s.min == s.max {
                    number(s.min, 6)
                } else {
                    format!("{} … {}", number(s.min, 6), number(s.max, 6))
                }
            }
            VarType::Real if s.min == s.max => quantity(v, s.min, 4),
            VarType::Real => {
                let lo = quantity(v, s.min, 4);
                let hi = quantity(v, s.max, 4);
                // the unit once, after the upper end
                match (lo.rsplit_once(' '), hi.rsplit_once(' ')) {
                    (Some((l, u1)), Some((_, u2))) if u1 == u2 => format!("{l} … {hi}"),
                    _ => format!("{lo} … {hi}"),
                }
            }
        }
    }

    /// The largest magnitude of an output and the shaft angle where it occurs ("15.6 kN at
    /// 183 deg").
    pub fn peak(&self, name: &str) -> String {
        let (Some(i), Some(s)) = (self.find(name), self.stat(name)) else {
            return "–".into();
        };
        let (x, at) = if s.max.abs() >= s.min.abs() {
            (s.max, s.max_at)
        } else {
            (s.min, s.min_at)
        };
        format!("{} at {} deg", quantity(self.vars[i], x, 3), number(at, 3))
    }

    /// The RMS of an output over the turn.
    pub fn rms(&self, name: &str) -> String {
        match (self.find(name), self.stat(name)) {
            (Some(i), Some(s)) => quantity(self.vars[i], s.rms, 3),
            _ => "–".into(),
        }
    }

    /// A variable's value after initialization, as a designer reads it.
    pub fn value(&self, name: &str) -> String {
        match self.find(name) {
            Some(i) => quantity(self.vars[i], self.initial[i], 4),
            None => "–".into(),
        }
    }
}
