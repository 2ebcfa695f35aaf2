//! The GenevaKnifeDrive FMU: its variables, declared once, and the glue from them to
//! [`super::physics`] (`../shared/spec/geneva-knife-drive.md`).

use super::elastic::{KnifeMemory, KnifeOde, Point};
use super::physics::{Kinematics, Params};
use crate::mechanics::SpringDamper;
use crate::mechanics::geneva::Geneva;
use crate::model::shaft::{self, Fidelity, ON_ALL, ON_PHI, ON_PHI_W};
use crate::model::{Dynamics, Experiment, Log, Model, ParamError, Stage, Values};
use crate::solver::chain::ChainOde;
use crate::solver::chain::{self, Chain, ChainModel};
use crate::solver::{Integrator, ShaftPath};
use std::cell::Cell;

crate::stages! {
    FORCES = Stage::new("forces", "Kinetostatic force analysis: Newton-Euler on slider, rod, crank, gear pair, cross and driver, with cutting resistance and guide friction", Fidelity::WITH_FORCES),
    ELASTIC = Stage::new("elastic", "The ODE of the compliant drive chain, integrated inside fmi2DoStep, with its energy balance and dynamic factor", Fidelity::DYNAMIC).always();
    /// What the loads and masses feed.
    LOADS = FORCES.or(ELASTIC),
}

crate::model_variables! {
    pub enum V (nominal_rpm = 30.0, torque_needs = stage::FORCES) {
        // ---- parameters (paper 003 where it gives them, else documented assumptions)
        geneva_Z = Var::int_parameter("geneva.Z", 4, "Number of slots of the Geneva cross Z (paper 003: 4)").min(3.0).max(36.0),
        geneva_r1 = Var::parameter("geneva.r1", 0.08, "m", "Driver radius r1: crank pin (roller) to driver axis (assumption)").min(0.0),
        gear_i = Var::int_parameter("gear.i", 4, "Crank turns per cross turn; a whole multiple of Z so the crank turns 360 deg per index (paper 003: 4)").min(1.0),
        gear_eta = Var::parameter("gear.eta", 0.98, "", "Mesh efficiency of the gear pair 3-4 (assumption)").min(0.0).max(1.0).feeds(stage::LOADS),
        crank_r = Var::parameter("crank.r", 0.07, "m", "Crank radius r2 (assumption)").min(0.0),
        rod_l = Var::parameter("rod.l", 0.35, "m", "Rod length l; paper 003: lambda2 = l/r2 = 5").min(0.0),
        knife_m = Var::parameter("knife.m", 12.0, "kg", "Mass of slider, knife housing and knife (assumption)").min(0.0).feeds(stage::LOADS),
        rod_m = Var::parameter("rod.m", 3.0, "kg", "Rod mass, half at the crank pin and half at the slider (assumption)").min(0.0).feeds(stage::LOADS),
        crank_J = Var::parameter("crank.J", 0.05, "kg.m2", "Moment of inertia of crank 5 and gear 4 (assumption)").min(0.0).feeds(stage::LOADS),
        cross_J = Var::parameter("cross.J", 0.08, "kg.m2", "Moment of inertia of cross 2 and gear 3 (assumption)").min(0.0).feeds(stage::LOADS),
        driver_J = Var::parameter("driver.J", 0.03, "kg.m2", "Moment of inertia of driver 1 (assumption)").min(0.0).feeds(stage::LOADS),
        guide_mu = Var::parameter("guide.mu", 0.1, "", "Coulomb friction coefficient of the slider guides 8 (assumption)").min(0.0).feeds(stage::LOADS),
        cut_F_max = Var::parameter("cut.F_max", 15000.0, "N", "Cutting resistance at full engagement (assumption)").min(0.0).feeds(stage::LOADS),
        cut_s_start = Var::parameter("cut.s_start", 0.070, "m", "Knife position where it meets the stack (assumption: 65 mm stack)").min(0.0).feeds(stage::LOADS),
        cut_s_full = Var::parameter("cut.s_full", 0.075, "m", "Knife position where the cutting force is full (assumption)").min(0.0).feeds(stage::LOADS),
        cut_s_end = Var::parameter("cut.s_end", 0.135, "m", "Knife position where the stack is cut through (assumption)").min(0.0).feeds(stage::LOADS),
        // ---- calculated parameters
        geneva_a = Var::calculated("geneva.a", "m", "Centre distance a = r1/sin(pi/Z) (paper 003: lambda = a/r1 = 1.414 for Z = 4)"),
        geneva_lambda = Var::calculated("geneva.lambda", "", "lambda = a/r1 = 1/sin(pi/Z) (paper 003)"),
        rod_lambda2 = Var::calculated("rod.lambda2", "", "lambda2 = l/r2 (paper 003: 5)"),
        knife_stroke = Var::calculated("knife.stroke", "m", "Knife stroke S = 2*r2 (paper 003)"),
        // ---- outputs
        cross_gamma = Var::output("cross.gamma", "rad", "Cross angle within the current index, 0 .. 2*pi/Z (paper 003)").depends(ON_PHI),
        cross_w = Var::output("cross.w", "rad/s", "Cross angular velocity").depends(ON_PHI_W),
        cross_a = Var::output("cross.a", "rad/s2", "Cross angular acceleration").depends(ON_ALL),
        crank_theta = Var::output("crank.theta", "rad", "Crank angle theta = i*gamma (mod 2*pi), 0 at the knife's top").depends(ON_PHI),
        crank_w = Var::output("crank.w", "rad/s", "Crank angular velocity i*gamma'*w").depends(ON_PHI_W),
        crank_a = Var::output("crank.a", "rad/s2", "Crank angular acceleration").depends(ON_ALL),
        rod_nu = Var::output("rod.nu", "rad", "Rod angle nu from the slider line, sin(nu) = sin(theta)/lambda2").depends(ON_PHI),
        knife_s = Var::output("knife.s", "m", "Knife displacement from its top position, down positive").depends(ON_PHI),
        knife_v = Var::output("knife.v", "m/s", "Knife velocity, down positive").depends(ON_PHI_W),
        knife_a = Var::output("knife.a", "m/s2", "Knife acceleration, down positive").depends(ON_ALL),
        knife_dwell = Var::bool_output("knife.dwell", "True while the roller is out of the slots: cross locked, knife stopped at the top").depends(ON_PHI).event(),
        knife_F_cut = Var::output("knife.F_cut", "N", "Cutting resistance on the knife, >= 0, only while descending through the stack (kinetostatic level; 0 at kinematic)").depends(ON_PHI_W).needs(stage::FORCES),
        knife_F_inertia = Var::output("knife.F_inertia", "N", "Inertia force of the slider mass m_s = knife.m + rod.m/2, -m_s*a, down positive (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        rod_F = Var::output("rod.F", "N", "Rod force P along the rod, positive when it pulls the knife down towards the crank (tension: with s = r2 + l - x_C the crank lies below the knife, so P*cos(nu) along +s is a pull) (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        guide_N = Var::output("guide.N", "N", "Normal force of the guides on the slider, P*sin(nu) (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        crank_tau = Var::output("crank.tau", "N.m", "Torque on the crank shaft (gear 4) (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        cross_tau = Var::output("cross.tau", "N.m", "Torque on the cross shaft (gear 3), with mesh losses and cross inertia (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        geneva_F = Var::output("geneva.F", "N", "Contact force between roller and slot flank, cross.tau/rho (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        // ---- elastodynamic level (dynamics.md)
        @with crate::chain_variables { spring(stage::ELASTIC;
            5e7,
            "Stiffness of the drive chain between the rigid knife position and the knife (elastodynamic level; assumption)",
            "Damping ratio of the drive chain, c = 2*zeta*sqrt(k*m_s) (elastodynamic level; assumption)",
        ) },
        @with crate::chain_variables { solver(stage::ELASTIC) },
        knife_s_kin = Var::output("knife.s_kin", "m", "Rigid reference position of the knife s(phi) (elastodynamic level; equals knife.s at the others)").depends(ON_PHI),
        elastic_deflection = Var::output("elastic.deflection", "m", "Deflection of the drive chain knife.s_kin - knife.s (elastodynamic level)").depends(ON_PHI).needs(stage::ELASTIC),
        elastic_F = Var::output("elastic.F", "N", "Dynamic chain force on the knife along s, k*deflection + c*deflection rate (elastodynamic level)").depends(ON_PHI_W).needs(stage::ELASTIC),
        dyn_factor = Var::output("dyn.factor", "", concat!("Dynamic factor K_d: peak |elastic.F| over the peak rigid (kinetostatic) chain force, of the last complete driver turn (the running one until a turn is complete), the peaks taken ", crate::at_accepted_steps!(), " (elastodynamic level)")).needs(stage::ELASTIC),
        @with crate::chain_variables { results(stage::ELASTIC) },
        // ---- Model Exchange states of the elastodynamic level and their derivatives
        @with crate::chain_variables { states(stage::ELASTIC, length;
            "State: knife position x, down positive (elastodynamic level)",
            "State: knife velocity (elastodynamic level)",
            "State: work done on knife and chain spring by drive, gravity, cutting, friction and damping (for the energy balance)",
        ) },
        // ---- events (FMI 3.0 early return)
        knife_in_stack = Var::bool_output("knife.in_stack", "True while the knife cuts: descending through the stack, cut.s_start <= knife.s <= cut.s_end (elastodynamic level: while the stack resists, knife.F_cut > 0): it rises at the cut's start and falls at the cut-through").depends(ON_PHI_W).event(),
    }
}

/// The Geneva-mechanism knife drive of a three-knife trimmer (paper 003) as an FMU model.
pub struct GenevaKnifeDrive {
    params: Params,
    /// The Geneva pair of `params`, built once per prepare.
    geneva: Geneva,
    dynamic: Option<Dynamic>,
}

/// The compliant drive chain of the elastodynamic level: its constants.
#[derive(Clone, Debug, PartialEq)]
struct KnifeChain {
    spring: SpringDamper,
}

/// What the elastodynamic level carries between steps.
type Dynamic = Chain<KnifeChain>;

impl ChainModel for KnifeChain {
    type Var = V;
    type Physics = Params;
    type Memory = KnifeMemory;
    type Ode<'a> = KnifeOde<'a>;
    const SAVED_INDICATORS: usize = <GenevaKnifeDrive as Dynamics<V>>::EVENT_INDICATORS;
    /// A cut-through or the knife back above the stack changes the indicators of the stack.
    const REEVALUATE_INDICATORS: bool = true;

    fn ode<'a>(
        &self,
        p: &'a Params,
        path: ShaftPath,
        _: &Values<V>,
        m: &KnifeMemory,
    ) -> KnifeOde<'a> {
        KnifeOde {
            p,
            geneva: p.geneva(),
            spring: self.spring,
            path,
            memory: Cell::new(*m),
        }
    }
    fn start(ode: &KnifeOde, path: &ShaftPath, m: &mut KnifeMemory) {
        *m = KnifeMemory::new(ode.cycle(path.t0));
    }
    fn absorb(ode: &KnifeOde, m: &mut KnifeMemory) {
        *m = ode.memory.get();
    }
    /// A deflection beyond the knife's stroke: the chain is too soft to drive the knife.
    fn non_physical(&self, ode: &KnifeOde, t: f64, y: &[f64; 3]) -> Option<String> {
        let stroke = ode.p.stroke();
        let delta = ode.point(t, y).delta;
        (delta.abs() > stroke).then(|| {
            format!(
                "the drive chain deflects by {:.4} m at t = {t:.6} s, more than the knife's stroke {stroke:.4} m: elastic.k = {} N/m is too soft to drive the knife (the cut force alone needs about cut.F_max/elastic.k = {:.3} m)",
                delta.abs(),
                self.spring.k,
                ode.p.cut_f_max / self.spring.k
            )
        })
    }
}

impl GenevaKnifeDrive {
    /// The physics parameters from the variables.
    pub fn params(v: &Values<V>) -> Params {
        Params {
            geneva_z: v.int(V::geneva_Z).max(0) as u32,
            geneva_r1: v[V::geneva_r1],
            gear_i: v.int(V::gear_i).max(0) as u32,
            gear_eta: v[V::gear_eta],
            crank_r: v[V::crank_r],
            rod_l: v[V::rod_l],
            knife_m: v[V::knife_m],
            rod_m: v[V::rod_m],
            crank_j: v[V::crank_J],
            cross_j: v[V::cross_J],
            driver_j: v[V::driver_J],
            guide_mu: v[V::guide_mu],
            cut_f_max: v[V::cut_F_max],
            cut_s_start: v[V::cut_s_start],
            cut_s_full: v[V::cut_s_full],
            cut_s_end: v[V::cut_s_end],
            drive_n: v[V::drive_n],
        }
    }

    fn write_kinematics(v: &mut Values<V>, k: &Kinematics) {
        v[V::cross_gamma] = k.gamma;
        v[V::cross_w] = k.cross_w;
        v[V::cross_a] = k.cross_a;
        v[V::crank_theta] = k.theta;
        v[V::crank_w] = k.crank_w;
        v[V::crank_a] = k.crank_a;
        v[V::rod_nu] = k.nu;
        v[V::knife_s] = k.s;
        v[V::knife_v] = k.v;
        v[V::knife_a] = k.a;
        v.set_flag(V::knife_dwell, k.dwell);
    }
}

impl Model for GenevaKnifeDrive {
    type Var = V;
    const IDENTIFIER: &'static str = "GenevaKnifeDrive";
    const DESCRIPTION: &'static str = "Knife drive of a three-knife trimmer: Geneva cross, gear pair and slider-crank (paper 003)";
    const EXPERIMENT: Experiment = Experiment::until(4.0, 1e-3);
    const STAGES: &'static [Stage] = STAGES;

    fn prepare(v: &Values<V>) -> Result<Self, ParamError> {
        let params = Self::params(v);
        params.validate()?;
        let dynamic = (shaft::fidelity(v) == Fidelity::Elastodynamic).then(|| {
            let spring = KnifeOde::spring(&params, v[V::elastic_k], v[V::elastic_zeta]);
            Chain::new(
                KnifeChain { spring },
                Integrator::new(chain::solver_settings(v)),
                KnifeMemory::new(0.0),
            )
        });
        Ok(GenevaKnifeDrive {
            geneva: params.geneva(),
            params,
            dynamic,
        })
    }

    fn calculated_parameters(&self, v: &mut Values<V>) {
        let p = &self.params;
        v[V::geneva_a] = p.a();
        v[V::geneva_lambda] = p.lambda();
        v[V::rod_lambda2] = p.lambda2();
        v[V::knife_stroke] = p.stroke();
    }

    fn evaluate(&mut self, v: &mut Values<V>, time: f64, _log: &mut dyn Log) {
        let p = &self.params;
        let s = shaft::state(v, time);
        let k = p.kinematics_of(&self.geneva, s.phi, s.w, s.a);
        Self::write_kinematics(v, &k);
        v[V::knife_s_kin] = k.s;
        v.set_flag(V::knife_in_stack, p.in_stack(k.s, k.v));
        if let Some(d) = self.dynamic.as_ref() {
            let path = shaft::path(v, time);
            let ode = d.ode(p, path, v);
            let y = d.held_state(&ode, time);
            let pt = ode.point_at(&k, &y);
            let states = [V::elastic_x, V::elastic_xd, V::elastic_W];
            let ders = [V::der_elastic_x, V::der_elastic_xd, V::der_elastic_W];
            chain::write_states(v, states, ders, &y, pt.xdd, pt.power);
            let tau = elastic_outputs(p, v, &pt, s.w, s.a);
            let r =
                shaft::reduce(|a| elastic_torques(p, &p.at_shaft_accel(&k, s.w, a), pt.f_el, a)[3]);
            shaft::set_reduced(v, r);
            v[V::elastic_E_residual] =
                ode.energy(&pt) - if d.started { d.e0 } else { ode.energy(&pt) } - y[2];
            v[V::dyn_factor] = d.memory.peaks.dyn_factor();
            v[V::solver_steps] = d.integ.mem.stats.steps as f64;
            shaft::set_outputs(v, tau, s.w);
            return;
        }
        v[V::elastic_deflection] = 0.0;
        v[V::elastic_F] = 0.0;
        v[V::dyn_factor] = 1.0;
        let kinetostatic = shaft::fidelity(v) == Fidelity::Kinetostatic && v.wants(stage::FORCES);
        let tau = kinetostatic.then(|| {
            let f = p.kinetostatics(&k, s.w, s.a);
            v[V::knife_F_cut] = f.f_cut;
            v[V::knife_F_inertia] = f.f_inertia;
            v[V::rod_F] = f.rod_f;
            v[V::guide_N] = f.guide_n;
            v[V::crank_tau] = f.crank_tau;
            v[V::cross_tau] = f.cross_tau;
            v[V::geneva_F] = f.geneva_f;
            f.shaft_tau
        });
        shaft::set_rigid_torque(v, &s, tau, |a| {
            p.kinetostatics(&p.at_shaft_accel(&k, s.w, a), s.w, a)
                .shaft_tau
        });
    }
}

crate::chain_access!(GenevaKnifeDrive, dynamic, params);

impl Dynamics<V> for GenevaKnifeDrive {
    const STATES: usize = 3;
    const EVENT_INDICATORS: usize = 8;

    // Co-Simulation, Model Exchange and the FMU state from solver::chain; Model Exchange also
    // applies a transition of the event indicators (cut-through, back above the stack) at a
    // completed step ([`KnifeChain`]'s hooks)
    crate::chain_hooks!(dynamic, params: do_step, me_states, me_set_states, me_derivatives,
        me_event_indicators, me_event, me_completed_step, save_state, restore_state);
}

/// Writes the outputs of the elastodynamic level at one point; returns the shaft torque. The
/// chain force replaces the rigid rod force: crank, gear pair, cross and shaft follow the
/// kinetostatic chain (rigid links behind the compliant one).
fn elastic_outputs(p: &Params, v: &mut Values<V>, pt: &Point, w: f64, eps: f64) -> f64 {
    let k = &pt.kin;
    v[V::knife_s] = pt.x;
    v[V::knife_v] = pt.xd;
    v[V::knife_a] = pt.xdd;
    v[V::elastic_deflection] = pt.delta;
    v[V::elastic_F] = pt.f_el;
    v[V::knife_F_cut] = pt.f_cut;
    v.set_flag(V::knife_in_stack, pt.f_cut > 0.0);
    v[V::knife_F_inertia] = -p.slider_mass() * pt.xdd;
    let rod_f = pt.f_el / k.cos_nu;
    v[V::rod_F] = rod_f;
    v[V::guide_N] = rod_f * k.sin_nu;
    let [crank_tau, cross_tau, geneva_f, shaft_tau] = elastic_torques(p, k, pt.f_el, eps);
    v[V::crank_tau] = crank_tau;
    v[V::cross_tau] = cross_tau;
    v[V::geneva_F] = geneva_f;
    let _ = w;
    shaft_tau
}

/// `[crank.tau, cross.tau, geneva.F, shaft.tau]` of the elastodynamic level: the chain force
/// `f_el` (a function of the state, not of the shaft acceleration) on the rigid crank, gear pair,
/// cross and driver at kinematics `k` and shaft acceleration `eps`.
fn elastic_torques(p: &Params, k: &Kinematics, f_el: f64, eps: f64) -> [f64; 4] {
    let crank_tau = f_el * k.ds_dtheta + p.crank_inertia() * k.crank_a;
    let i = f64::from(p.gear_i);
    let gear = if crank_tau * k.crank_w >= 0.0 {
        i * crank_tau / p.gear_eta
    } else {
        i * crank_tau * p.gear_eta
    };
    if k.engaged {
        let cross_tau = gear + p.cross_j * k.cross_a;
        [
            crank_tau,
            cross_tau,
            cross_tau / k.rho,
            cross_tau * k.gamma_d + p.driver_j * eps,
        ]
    } else {
        [crank_tau, 0.0, 0.0, p.driver_j * eps]
    }
}
