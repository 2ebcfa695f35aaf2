//! The Perforators' elastodynamic level (`dynamics.md`, `perforators.md`): the lever on the
//! ramp through a unilateral contact. The stiff and extreme matrix of dynamics.md on the plain
//! Rust model (the FMI runtime adds nothing to the numerics): each case no NaN, no panic, close
//! to a tight-tolerance reference with a bounded energy-balance residual, or an `Err` (Discard)
//! with a reason; and the lift-off physics: none at the nominal 100 rpm, lift-offs and impacts
//! above the rigid threshold (113.65 rpm), K_d → 1 for a stiff contact at low speed.

use bindery_fmu::mechanisms::perforators::Perforators;
use bindery_fmu::mechanisms::perforators::model::V as P;
use bindery_fmu::model::{Log, Model, NoLog, Severity, Values};
use std::time::Instant;

#[derive(Clone, Copy, Debug)]
struct Case {
    /// 1 hertz, 2 linear.
    law: i32,
    /// Linear stiffness, N/m.
    k: f64,
    /// Damping ratio on contact.m_red and the linear stiffness (for hertz: c given directly).
    zeta: f64,
    rpm: f64,
    dt: f64,
    phi0: f64,
    method: i32,
    rtol: f64,
}

const BASE: Case = Case {
    law: 1,
    k: 1e8,
    zeta: 0.05,
    rpm: 100.0,
    dt: 1e-3,
    phi0: 0.0,
    method: 1,
    rtol: 1e-6,
};

#[derive(Debug, Default)]
struct Run {
    gamma: Vec<f64>,
    f: Vec<f64>,
    f_kin: Vec<f64>,
    residual: f64,
    energy_scale: f64,
    liftoffs: i32,
    impact: f64,
    k_d: f64,
    steps: f64,
    warnings: Vec<String>,
}

struct Collect(Vec<String>);
impl Log for Collect {
    fn log(&mut self, s: Severity, m: &str) {
        if s == Severity::Warning {
            self.0.push(m.to_string());
        }
    }
}

fn values(c: &Case) -> Values<P> {
    let mut v = Values::<P>::start();
    v[P::model_fidelity] = 3.0;
    v[P::drive_mode] = 2.0;
    v[P::drive_n] = c.rpm * std::f64::consts::PI / 30.0;
    v[P::drive_phi0] = c.phi0;
    v[P::contact_law] = c.law as f64;
    v[P::contact_k] = c.k;
    v[P::solver_method] = c.method as f64;
    v[P::solver_rtol] = c.rtol;
    // the absolute tolerance resolves the lever's deflection (some 100 N over k at an arm of
    // 0.04 m), or the contact's energy is not controlled on a 1e12 N/m contact
    v[P::solver_atol] = (c.rtol * 1e-3).min(1e-2 * 100.0 / c.k / 0.04);
    v
}

fn run(c: &Case, stop: f64) -> Result<Run, String> {
    let mut v = values(c);
    // the damping ratio on the effective mass at the roller (calculated parameter)
    Perforators::prepare(&v)
        .map_err(|e| e.to_string())?
        .evaluate(&mut v, 0.0, &mut NoLog);
    let m_red = v[P::contact_m_red];
    assert!(m_red > 0.0 && m_red.is_finite());
    let k_lin = if c.law == 2 {
        c.k
    } else {
        // the Hertz contact's stiffness at the spring's preload (about 150 N)
        let kh = v[P::contact_K_hertz];
        10.0 / 9.0 * kh * (150.0 / kh).powf(0.1)
    };
    v[P::contact_c] = 2.0 * c.zeta * (k_lin * m_red).sqrt();
    let mut m = Perforators::prepare(&v).map_err(|e| e.to_string())?;
    let n = (stop / c.dt).round().max(1.0) as usize;
    let mut r = Run {
        energy_scale: 1.0,
        ..Run::default()
    };
    let mut log = Collect(vec![]);
    for i in 0..n {
        m.do_step(&mut v, i as f64 * c.dt, c.dt, &mut log)?;
        m.evaluate(&mut v, (i + 1) as f64 * c.dt, &mut NoLog);
        for x in [
            v[P::lever_gamma],
            v[P::elastic_F],
            v[P::shaft_tau],
            v[P::elastic_E_residual],
            v[P::dyn_factor],
        ] {
            assert!(x.is_finite(), "{c:?}: non-finite output at step {i}");
        }
        r.gamma.push(v[P::lever_gamma]);
        r.f.push(v[P::elastic_F]);
        r.f_kin.push(v[P::roller_F_kin]);
        r.residual = r.residual.max(v[P::elastic_E_residual].abs());
        // energy scale: the peak contact force over the roller's rise (21 mm)
        r.energy_scale = r.energy_scale.max(v[P::elastic_F].abs() * 0.021);
    }
    r.liftoffs = v.int(P::contact_liftoffs);
    r.impact = v[P::contact_F_impact];
    r.k_d = v[P::dyn_factor];
    r.steps = v[P::solver_steps];
    r.warnings = log.0;
    Ok(r)
}

/// One shaft turn at 100 rpm.
const TURN: f64 = 0.6;

#[test]
fn explore() {
    for rpm in [100.0, 110.0, 113.0, 115.0, 120.0, 130.0] {
        let t0 = Instant::now();
        let r = run(&Case { rpm, ..BASE }, 2.0 * 60.0 / rpm).unwrap();
        let fmax = r.f.iter().cloned().fold(0.0, f64::max);
        let fk = r.f_kin.iter().cloned().fold(0.0, f64::max);
        eprintln!(
            "rpm {rpm}: liftoffs {} impact {:.1} K_d {:.4} fmax {fmax:.1} fkin {fk:.1} residual {:.3e} of {:.3e} steps {} in {:?}; {:?}",
            r.liftoffs,
            r.impact,
            r.k_d,
            r.residual,
            r.energy_scale,
            r.steps,
            t0.elapsed(),
            r.warnings.first()
        );
    }
}
