//! The GenevaKnifeDrive FMU: its variables, declared once, and the glue from them to
//! [`super::physics`] (`../shared/spec/geneva-knife-drive.md`).

use super::elastic::{KnifeMemory, KnifeOde, Point};
use super::physics::{Forces, Kinematics, Params};
use crate::mechanics::SpringDamper;
use crate::mechanics::geneva::Geneva;
use crate::model::partials::{Put, Scalar, Seeded, put_zero};
use crate::model::shaft::{self, Fidelity, ON_ALL, ON_PHI, ON_PHI_W, ShaftState};
use crate::model::{Dynamics, Experiment, Log, Model, ParamError, Stage, Values};
use crate::solver::ShaftPath;
use crate::solver::chain::ChainOde;
use crate::solver::chain::{self, Chain, ChainModel, LastAt, LastPoint};
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

/// What the outputs are computed at (`model.fidelity` and the stages wanted).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Level {
    Kinematic,
    Kinetostatic,
    /// The chain's ODE on the shaft's path from now.
    Elastic(ShaftPath),
}

impl KnifeChain {
    /// The chain's ODE on `path` with the memory `m` ([`ChainModel::ode`]: it reads no
    /// variable).
    fn knife_ode<'a>(&self, p: &'a Params, path: ShaftPath, m: &KnifeMemory) -> KnifeOde<'a> {
        KnifeOde {
            p,
            geneva: p.geneva(),
            spring: self.spring,
            path,
            memory: Cell::new(*m),
            rigid: LastAt::default(),
            last: LastPoint::default(),
        }
    }
}

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
        self.knife_ode(p, path, m)
    }
    fn start(ode: &KnifeOde, path: &ShaftPath, m: &mut KnifeMemory) {
        *m = KnifeMemory::new(ode.cycle(path.t0));
    }
    fn absorb(ode: &KnifeOde, m: &mut KnifeMemory) {
        *m = ode.memory.get();
    }
    /// A deflection beyond the knife's stroke: the chain is too soft to drive the knife.
    fn non_physical(&self, ode: &KnifeOde, t: f64, y: &[f64; 3]) -> Option<String> {
        let (delta, k) = (ode.point(t, y).delta, self.spring.k);
        let names = ["drive chain", "knife's stroke", "knife"];
        chain::beyond_travel(delta, ode.p.stroke(), t, k, names).map(|why| {
            let need = ode.p.cut_f_max / k;
            format!("{why} (the cut force alone needs about cut.F_max/elastic.k = {need:.3} m)")
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

    /// What [`GenevaKnifeDrive::outputs`] computes at `time`: the forces (the kinetostatic
    /// level, its stage wanted) or the chain on the shaft's path (the elastodynamic level).
    fn level(&self, v: &Values<V>, time: f64) -> Level {
        if self.dynamic.is_some() {
            Level::Elastic(shaft::path(v, time))
        } else if shaft::fidelity(v) == Fidelity::Kinetostatic && v.wants(stage::FORCES) {
            Level::Kinetostatic
        } else {
            Level::Kinematic
        }
    }

    /// Every continuous Real output at the shaft state `st` (time `time`), as `put(variable,
    /// value)`: the one source of the outputs ([`Model::evaluate`], `f64`) and of their exact
    /// partial derivatives ([`Model::partials`], dual numbers). At the elastodynamic level also
    /// the chain's states and their derivatives (Model Exchange's), the held state `[x, ẋ, W]`
    /// given to `state` (which seeds it where the states are knowns). Returns `knife.dwell` and
    /// `knife.in_stack` (the Boolean outputs are [`Model::evaluate`]'s, as `solver.steps`).
    ///
    /// What is put with a constant (derivative 0): `dyn.factor` (a statistic of past driver
    /// turns; 1 below the elastodynamic level), `elastic.deflection` and `elastic.F` below the
    /// elastodynamic level (0). Not put (held, [`Model::partials`] puts their derivative 0): the
    /// forces at the kinematic level, `elastic.E_residual` below the elastodynamic level.
    #[inline(always)]
    fn outputs<T: Scalar>(
        &self,
        level: Level,
        time: f64,
        st: &ShaftState<T>,
        state: impl FnOnce([f64; 3]) -> [T; 3],
        mut put: impl FnMut(V, T),
    ) -> (bool, bool) {
        let p = &self.params;
        let k = p.kinematics_of(&self.geneva, st.phi, st.w, st.a);
        write_kinematics(&k, &mut put);
        put(V::knife_s_kin, k.s);
        if let (Some(d), Level::Elastic(path)) = (self.dynamic.as_ref(), level) {
            let ode = d.model.knife_ode(p, path, &d.memory);
            let y = state(d.held_state(&ode, time));
            let pt = ode.point_at(&k, &y);
            let states = [V::elastic_x, V::elastic_xd, V::elastic_W];
            let ders = [V::der_elastic_x, V::der_elastic_xd, V::der_elastic_W];
            for (var, x) in states.into_iter().zip(y) {
                put(var, x);
            }
            for (var, x) in ders.into_iter().zip([y[1], pt.xdd, pt.power]) {
                put(var, x);
            }
            let tau = elastic_outputs(p, &k, &pt, st.a, &mut put);
            let r = shaft::reduce_at_rest(tau, st.a, |a| {
                elastic_torques(p, &p.at_shaft_accel(&k, st.w, a), pt.f_el, a)[3]
            });
            put(V::shaft_J_red, r.j_red);
            put(V::shaft_tau0, r.tau0);
            let e = ode.energy_of(&pt);
            let e0 = if d.started { T::from(d.e0) } else { e };
            put(V::elastic_E_residual, e - e0 - y[2]);
            put(V::dyn_factor, T::from(d.memory.peaks.dyn_factor()));
            put(V::shaft_tau, tau);
            put(V::shaft_P, tau * st.w);
            return (k.dwell, pt.f_cut.re() > 0.0);
        }
        put(V::elastic_deflection, T::zero());
        put(V::elastic_F, T::zero());
        put(V::dyn_factor, T::one());
        let forces = (level == Level::Kinetostatic).then(|| p.kinetostatics(&k, st.w, st.a));
        if let Some(f) = &forces {
            for (var, x) in force_outputs(f) {
                put(var, x);
            }
        }
        shaft::rigid_torque(
            st,
            forces.map(|f| f.shaft_tau),
            |a| {
                p.kinetostatics(&p.at_shaft_accel(&k, st.w, a), st.w, a)
                    .shaft_tau
            },
            &mut put,
        );
        (k.dwell, p.in_stack(k.s.re(), k.v.re()))
    }
}

/// The kinematic outputs of a [`Kinematics`] (the elastodynamic level then puts the knife's
/// own motion over `knife.s`, `knife.v`, `knife.a`).
fn write_kinematics<T: Scalar>(k: &Kinematics<T>, put: &mut impl FnMut(V, T)) {
    put(V::cross_gamma, k.gamma);
    put(V::cross_w, k.cross_w);
    put(V::cross_a, k.cross_a);
    put(V::crank_theta, k.theta);
    put(V::crank_w, k.crank_w);
    put(V::crank_a, k.crank_a);
    put(V::rod_nu, k.nu);
    put(V::knife_s, k.s);
    put(V::knife_v, k.v);
    put(V::knife_a, k.a);
}

/// The outputs of the kinetostatic force analysis with their values in `f`: put at the
/// kinetostatic level (the elastodynamic one puts its own), held at the kinematic level.
fn force_outputs<T: Scalar>(f: &Forces<T>) -> [(V, T); 7] {
    [
        (V::knife_F_cut, f.f_cut),
        (V::knife_F_inertia, f.f_inertia),
        (V::rod_F, f.rod_f),
        (V::guide_N, f.guide_n),
        (V::crank_tau, f.crank_tau),
        (V::cross_tau, f.cross_tau),
        (V::geneva_F, f.geneva_f),
    ]
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
        let dynamic = if shaft::fidelity(v) == Fidelity::Elastodynamic {
            SpringDamper::check_mass(
                params.slider_mass(),
                "knife.m",
                params.knife_m,
                "the slider mass knife.m + rod.m/2",
            )?;
            let spring = KnifeOde::spring(&params, v[V::elastic_k], v[V::elastic_zeta]);
            Some(Chain::new(KnifeChain { spring }, v, KnifeMemory::new(0.0)))
        } else {
            None
        };
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
        let st = shaft::state(v, time);
        let level = self.level(v, time);
        let (dwell, in_stack) = self.outputs(level, time, &st, |y| y, |var, x| v[var] = x);
        v.set_flag(V::knife_dwell, dwell);
        v.set_flag(V::knife_in_stack, in_stack);
        if let Some(d) = self.dynamic.as_ref() {
            v[V::solver_steps] = d.integ.mem.stats.steps as f64;
        }
    }

    const PARTIALS: bool = true;

    /// [`GenevaKnifeDrive::outputs`] on dual numbers; the knowns: `shaft.phi`, `shaft.w`,
    /// `shaft.a` and in Model Exchange `elastic.x`, `elastic.xd`, `elastic.W`. Held (the
    /// derivative 0): the forces at the kinematic level; `elastic.E_residual` and the state
    /// derivatives below the elastodynamic level.
    fn partials(&mut self, at: &Seeded<V>, time: f64, put: Put<V>) -> Result<(), String> {
        let v = at.values();
        let st = at.shaft(time);
        let own = |y: [f64; 3]| at.own_all([V::elastic_x, V::elastic_xd, V::elastic_W], y);
        let level = self.level(v, time);
        self.outputs(level, time, &st, own, &mut *put);
        if !matches!(level, Level::Elastic(_)) {
            // no chain: its Model Exchange derivatives are 0 ([`crate::chain_hooks!`])
            let chain = [V::der_elastic_x, V::der_elastic_xd, V::der_elastic_W];
            put_zero(put, chain.into_iter().chain([V::elastic_E_residual]));
            if level == Level::Kinematic {
                put_zero(
                    put,
                    force_outputs(&Forces::<f64>::default()).map(|(var, _)| var),
                );
            }
        }
        Ok(())
    }
}

// Co-Simulation, Model Exchange and the FMU state from solver::chain; Model Exchange also applies
// a transition of the event indicators (cut-through, back above the stack) at a completed step
// ([`KnifeChain`]'s hooks)
crate::chain_dynamics!(GenevaKnifeDrive, dynamic, params, EVENT_INDICATORS = 8);

/// Puts the outputs of the elastodynamic level at one point `pt` on the rigid kinematics `k`
/// (shaft acceleration `eps`); returns the shaft torque (any [`Scalar`]). The chain force replaces the rigid rod force:
/// crank, gear pair, cross and shaft follow the kinetostatic chain (rigid links behind the
/// compliant one).
fn elastic_outputs<T: Scalar>(
    p: &Params,
    k: &Kinematics<T>,
    pt: &Point<T>,
    eps: T,
    put: &mut impl FnMut(V, T),
) -> T {
    put(V::knife_s, pt.x);
    put(V::knife_v, pt.xd);
    put(V::knife_a, pt.xdd);
    put(V::elastic_deflection, pt.delta);
    put(V::elastic_F, pt.f_el);
    put(V::knife_F_cut, pt.f_cut);
    put(V::knife_F_inertia, pt.xdd * (-p.slider_mass()));
    let rod_f = pt.f_el / k.cos_nu;
    put(V::rod_F, rod_f);
    put(V::guide_N, rod_f * k.sin_nu);
    let [crank_tau, cross_tau, geneva_f, shaft_tau] = elastic_torques(p, k, pt.f_el, eps);
    put(V::crank_tau, crank_tau);
    put(V::cross_tau, cross_tau);
    put(V::geneva_F, geneva_f);
    shaft_tau
}

/// `[crank.tau, cross.tau, geneva.F, shaft.tau]` of the elastodynamic level: the chain force
/// `f_el` (a function of the state, not of the shaft acceleration) on the rigid crank, gear pair,
/// cross and driver at kinematics `k` and shaft acceleration `eps` ([`Params::behind_crank`];
/// any [`Scalar`]).
fn elastic_torques<T: Scalar>(p: &Params, k: &Kinematics<T>, f_el: T, eps: T) -> [T; 4] {
    let crank_tau = f_el * k.ds_dtheta + k.crank_a * p.crank_inertia();
    let (cross_tau, geneva_f, shaft_tau) = p.behind_crank(k, crank_tau, eps);
    [crank_tau, cross_tau, geneva_f, shaft_tau]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::NoLog;
    use crate::model::partials::check;

    #[test]
    fn a_massless_slider_is_refused_at_the_elastodynamic_level_naming_knife_m() {
        let mut v = Values::<V>::start();
        v[V::knife_m] = 0.0;
        v[V::rod_m] = 0.0;
        let e = check::refused_only_elastodynamic::<GenevaKnifeDrive>(&mut v, "knife.m");
        assert!(
            e.condition.contains("knife.m + rod.m/2 is 0 kg"),
            "{}",
            e.condition
        );
        // a rod's mass alone carries the chain
        v[V::rod_m] = 1.0;
        assert!(GenevaKnifeDrive::prepare(&v).is_ok());
    }

    /// The exact partial derivatives against central differences of `evaluate` at every level:
    /// the knife before the stack, cutting through it and rising, the cross locked in the dwell,
    /// a shaft moved on from the inputs' instant and the constant-speed drive; at the
    /// elastodynamic level along the inputs (the held state a constant, as in Co-Simulation)
    /// and along the states (Model Exchange's knowns, with the state derivatives), the knife
    /// deflected, cutting and not (tests/partials.rs checks the default FMU over the C ABI).
    #[test]
    fn partials_equal_central_differences() {
        // the phases covered: (level, cutting, in the dwell)
        let mut seen = vec![];
        // (level, drive.mode, phi, w, a, time, deflection and its rate at level 3)
        for (level, mode, phi, w, a, time, dy) in [
            (2.0, 1.0, 0.45, 3.0, 0.0, 0.0, [0.0; 2]),
            (2.0, 1.0, 0.65, 3.0, 2.0, 0.0, [0.0; 2]),
            (2.0, 1.0, 0.95, 2.5, -1.5, 0.0, [0.0; 2]),
            (2.0, 1.0, 3.0, 3.0, 4.0, 0.0, [0.0; 2]),
            (2.0, 1.0, 0.6, 3.0, 0.5, 0.02, [0.0; 2]),
            (2.0, 2.0, 0.6, 3.0, 0.5, 0.13, [0.0; 2]),
            (1.0, 1.0, 0.65, 3.0, 2.0, 0.0, [0.0; 2]),
            (3.0, 1.0, 0.45, 3.0, 0.0, 0.0, [2e-4, -0.05]),
            (3.0, 1.0, 0.66, 3.0, 2.0, 0.0, [2e-4, -0.05]),
            (3.0, 1.0, 0.66, 3.0, 2.0, 0.0, [-1e-4, 0.08]),
            (3.0, 1.0, 0.95, 2.5, -1.5, 0.01, [3e-4, 0.1]),
            (3.0, 1.0, 3.0, 3.0, 4.0, 0.0, [1e-4, 0.02]),
            (3.0, 2.0, 0.6, 3.0, 0.5, 0.13, [2e-4, -0.05]),
        ] {
            let mut v = Values::<V>::start();
            v[V::model_fidelity] = level;
            v[V::drive_mode] = mode;
            check::set_shaft(&mut v, phi, w, a);
            let mut m = GenevaKnifeDrive::prepare(&v).unwrap();
            // the knife off its rigid motion: a started chain with a held state
            let k = m.params.kinematics(shaft::state(&v, time).phi, w, a);
            let y0 = [k.s - dy[0], k.v - dy[1], 0.3];
            let elastic = m.dynamic.is_some();
            if elastic {
                m.me_set_states(&v, time, &y0);
            }
            let mut at0 = v.clone();
            m.evaluate(&mut at0, time, &mut NoLog);
            seen.push((level, at0[V::knife_F_cut] > 0.0, at0.flag(V::knife_dwell)));
            check::inputs_and_states(
                &mut m,
                &v,
                time,
                &[],
                elastic,
                check::relative_step,
                1e-14,
                &format!("level {level} mode {mode} phi {phi} a {a} time {time}"),
            );
        }
        for level in [2.0, 3.0] {
            for phase in [(true, false), (false, false), (false, true)] {
                assert!(
                    seen.contains(&(level, phase.0, phase.1)),
                    "{level} {phase:?}"
                );
            }
        }
    }
}
