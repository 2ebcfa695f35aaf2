//! The machines of [`crate::ssp`] simulated in this process on the plain Rust models, with the
//! same fixed-step master as FMPy's `simulate_ssp` (every component steps with the inputs of the
//! previous communication point, then the connections are applied), and the figures a machine
//! designer asks for: the coefficient of speed fluctuation δ = (ω_max − ω_min)/ω_mean, the
//! flywheel that brings it below a target, peak and RMS motor torque, start-up time.

pub mod sweep;

use crate::mechanisms::{
    disc_knife_drive::DiscKnifeDrive, geneva_knife_drive::GenevaKnifeDrive,
    legacy_needle_drive::LegacyNeedleDrive, main_shaft::MainShaft, perforators::Perforators,
    sewing_table::SewingTable,
};
use crate::model::{Model, NoLog, Values, VarSet};
use crate::ssp::Machine;

/// One FMU instance behind names (what a host sees).
trait Instance {
    fn set(&mut self, name: &str, x: f64) -> Result<(), String>;
    fn get(&self, name: &str) -> Result<f64, String>;
    fn init(&mut self) -> Result<(), String>;
    /// Steps from `t` over `h` with the inputs set, then evaluates the outputs at `t + h`.
    fn step(&mut self, t: f64, h: f64) -> Result<(), String>;
}

struct Inst<M: Model> {
    v: Values<M::Var>,
    m: Option<M>,
    id: &'static str,
}

fn vr_of<V: VarSet>(id: &str, name: &str) -> Result<usize, String> {
    V::table()
        .iter()
        .position(|v| v.name == name)
        .ok_or_else(|| format!("{id} has no variable {name}"))
}

impl<M: Model> Instance for Inst<M> {
    fn set(&mut self, name: &str, x: f64) -> Result<(), String> {
        let i = vr_of::<M::Var>(self.id, name)?;
        self.v.raw_mut()[i] = x;
        Ok(())
    }
    fn get(&self, name: &str) -> Result<f64, String> {
        Ok(self.v.raw()[vr_of::<M::Var>(self.id, name)?])
    }
    fn init(&mut self) -> Result<(), String> {
        let m = M::prepare(&self.v).map_err(|e| format!("{}: {e}", self.id))?;
        m.calculated_parameters(&mut self.v);
        self.m = Some(m);
        let m = self.m.as_mut().expect("prepared");
        m.evaluate(&mut self.v, 0.0, &mut NoLog);
        Ok(())
    }
    fn step(&mut self, t: f64, h: f64) -> Result<(), String> {
        let m = self.m.as_mut().ok_or("not initialized")?;
        m.step(&mut self.v, t, h, &mut NoLog)
            .map_err(|e| format!("{}: {e}", self.id))?;
        m.evaluate(&mut self.v, t + h, &mut NoLog);
        Ok(())
    }
}

fn instance(id: &'static str) -> Result<Box<dyn Instance>, String> {
    fn make<M: Model>(id: &'static str) -> Box<dyn Instance> {
        Box::new(Inst::<M> {
            v: Values::start(),
            m: None,
            id,
        })
    }
    Ok(match id {
        "MainShaft" => make::<MainShaft>(id),
        "GenevaKnifeDrive" => make::<GenevaKnifeDrive>(id),
        "SewingTable" => make::<SewingTable>(id),
        "Perforators" => make::<Perforators>(id),
        "DiscKnifeDrive" => make::<DiscKnifeDrive>(id),
        "LegacyNeedleDrive" => make::<LegacyNeedleDrive>(id),
        _ => return Err(format!("no model {id}")),
    })
}

/// The variables of the catalog model `id` a machine's component is made of (`None`: no such
/// model).
pub fn variables_of(id: &str) -> Option<&'static [crate::model::Var]> {
    fn table<M: Model>() -> &'static [crate::model::Var] {
        <M::Var as VarSet>::table()
    }
    Some(match id {
        "MainShaft" => table::<MainShaft>(),
        "GenevaKnifeDrive" => table::<GenevaKnifeDrive>(),
        "SewingTable" => table::<SewingTable>(),
        "Perforators" => table::<Perforators>(),
        "DiscKnifeDrive" => table::<DiscKnifeDrive>(),
        "LegacyNeedleDrive" => table::<LegacyNeedleDrive>(),
        _ => return None,
    })
}

/// A run's record on the communication grid.
#[derive(Clone, Debug, Default)]
pub struct Trace {
    pub t: Vec<f64>,
    /// Main-shaft speed, rad/s.
    pub w: Vec<f64>,
    /// Main-shaft angle, rad.
    pub phi: Vec<f64>,
    /// Motor torque at the motor shaft, N·m.
    pub motor_tau: Vec<f64>,
}

/// Simulates a machine (its own parameters, overridden by `set`: `(component, variable,
/// value)`) from 0 to `stop` with communication step `h`. The shaft inputs start at 0 as in
/// FMPy's master.
pub fn simulate(
    m: &Machine,
    set: &[(&str, &str, f64)],
    stop: f64,
    h: f64,
) -> Result<Trace, String> {
    crate::ssp::check(m)?;
    let mut insts = Vec::new();
    for c in &m.components {
        let mut i = instance(c.fmu)?;
        for (p, x) in &c.params {
            i.set(p, *x)?;
        }
        for (comp, p, x) in set {
            if *comp == c.name {
                i.set(p, *x)?;
            }
        }
        i.init()?;
        insts.push(i);
    }
    let idx = |name: &str| {
        m.components
            .iter()
            .position(|c| c.name == name)
            .expect("checked")
    };
    let drive = idx("drive");
    // connector values, all 0 at the start
    let mut values = vec![0.0; m.connections.len()];
    let mut tr = Trace::default();
    let n = (stop / h).round() as usize;
    for k in 0..n {
        let t = k as f64 * h;
        for (ci, inst) in insts.iter_mut().enumerate() {
            for (j, (_, (e2, c2))) in m.connections.iter().enumerate() {
                if idx(e2) == ci {
                    inst.set(c2, values[j])?;
                }
            }
            inst.step(t, h)?;
        }
        for (j, ((e1, c1), _)) in m.connections.iter().enumerate() {
            values[j] = insts[idx(e1)].get(c1)?;
        }
        let d = &insts[drive];
        tr.t.push(t + h);
        tr.w.push(d.get("shaft.w")?);
        tr.phi.push(d.get("shaft.phi")?);
        tr.motor_tau.push(d.get("motor.tau")?);
        if !tr.w.last().is_some_and(|w| w.is_finite()) {
            return Err(format!(
                "{}: the speed is not finite at t = {}",
                m.name,
                t + h
            ));
        }
    }
    Ok(tr)
}

/// The figures of the steady run over the last `turns` whole main-shaft turns of a trace.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Steady {
    pub w_mean: f64,
    pub w_min: f64,
    pub w_max: f64,
    /// δ = (ω_max − ω_min)/ω_mean.
    pub delta: f64,
    pub tau_peak: f64,
    pub tau_rms: f64,
}

/// Index where the last `turns` whole turns of the trace begin.
pub fn last_turns_start(tr: &Trace, turns: f64) -> usize {
    let end = *tr.phi.last().unwrap_or(&0.0);
    let from = end - turns * std::f64::consts::TAU;
    tr.phi.iter().position(|&p| p >= from).unwrap_or(0)
}

/// δ, the mean speed (time average) and the motor torque's peak and RMS over the last `turns`
/// turns of a trace.
pub fn steady(tr: &Trace, turns: f64) -> Steady {
    let i0 = last_turns_start(tr, turns);
    let w = &tr.w[i0..];
    let tau = &tr.motor_tau[i0..];
    let n = w.len().max(1) as f64;
    let w_mean = w.iter().sum::<f64>() / n;
    let w_min = w.iter().copied().fold(f64::INFINITY, f64::min);
    let w_max = w.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Steady {
        w_mean,
        w_min,
        w_max,
        delta: (w_max - w_min) / w_mean,
        tau_peak: tau.iter().fold(0.0f64, |m, x| m.max(x.abs())),
        tau_rms: (tau.iter().map(|x| x * x).sum::<f64>() / n).sqrt(),
    }
}

/// Time at which the speed first reaches `fraction` of `w_ref`.
pub fn startup_time(tr: &Trace, fraction: f64, w_ref: f64) -> Option<f64> {
    tr.w.iter()
        .position(|&w| w >= fraction * w_ref)
        .map(|i| tr.t[i])
}

/// Smallest flywheel `fly.J` (kg·m²) within `rel` for which δ ≤ `target` in a run of `stop`
/// seconds measured over its last `turns` turns: bisection (δ falls as the flywheel grows), from
/// `[lo, hi]`; `None` if even `hi` is not enough.
pub fn flywheel_for(
    m: &Machine,
    target: f64,
    lo: f64,
    hi: f64,
    stop: f64,
    h: f64,
    turns: f64,
) -> Result<Option<f64>, String> {
    let delta = |j: f64| -> Result<f64, String> {
        let tr = simulate(
            m,
            &[("drive", "fly.J", j), ("drive", "init.w", m.nominal_w)],
            stop,
            h,
        )?;
        Ok(steady(&tr, turns).delta)
    };
    if delta(hi)? > target {
        return Ok(None);
    }
    let (mut lo, mut hi) = (lo, hi);
    if delta(lo)? <= target {
        return Ok(Some(lo));
    }
    while hi - lo > 0.01 * hi {
        let mid = 0.5 * (lo + hi);
        if delta(mid)? <= target {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(Some(hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delta_of_a_known_trace() {
        // ω = 10 + sin(φ) over whole turns: δ = 2/10
        let n = 1000;
        let tr = Trace {
            t: (0..=n).map(|k| k as f64).collect(),
            phi: (0..=n)
                .map(|k| 4.0 * std::f64::consts::TAU * k as f64 / n as f64)
                .collect(),
            w: (0..=n)
                .map(|k| 10.0 + (4.0 * std::f64::consts::TAU * k as f64 / n as f64).sin())
                .collect(),
            motor_tau: vec![2.0; n + 1],
        };
        let s = steady(&tr, 2.0);
        assert!((s.delta - 0.2).abs() < 1e-4, "{s:?}");
        assert!((s.w_mean - 10.0).abs() < 1e-2);
        assert_eq!((s.tau_peak, s.tau_rms), (2.0, 2.0));
        // 10 + sin(8πk/1000) first reaches 10.5 at k = 21 (sin ≥ 1/2 from 8πk/1000 ≥ π/6)
        assert_eq!(startup_time(&tr, 0.5, 21.0), Some(tr.t[21]));
    }

    #[test]
    fn sewing_machine_starts_up_and_a_bigger_flywheel_smooths_it() {
        let m = crate::ssp::machines().remove(0);
        let tr = simulate(&m, &[], 3.0, 1e-3).unwrap();
        let s = steady(&tr, 2.0);
        assert!(
            s.w_mean > 0.9 * m.nominal_w && s.w_mean < m.nominal_w,
            "{s:?}"
        );
        let big = simulate(&m, &[("drive", "fly.J", 20.0)], 6.0, 1e-3).unwrap();
        assert!(steady(&big, 2.0).delta < s.delta);
    }
}
