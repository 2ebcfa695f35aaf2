//! The DiscKnifeDrive FMU: its variables, declared once, and the glue from them to
//! [`super::physics`] (`../shared/spec/disc-knife-drive.md`).

use super::elastic::{Point, RodOde, dead_point_threshold, least_reduced_mass};
use super::physics::{Forces, Kinematics, LinScalar, Params, norm};
use crate::mechanics::{SpringDamper, hypot};
use crate::model::partials::{Put, Seeded, put_zero};
use crate::model::shaft::{self, Fidelity, ON_ALL, ON_PHI, ON_PHI_W, ShaftState};
use crate::model::{Dynamics, Experiment, Log, Model, ParamError, Severity, Stage, Values};
use crate::solver::ShaftPath;
use crate::solver::chain::{Chain, ChainModel, Peaks};

crate::stages! {
    FORCES = Stage::new("forces", "Kinetostatic force analysis: cutting force, inertia of holder and sliders, Coulomb friction in both guides (with the self-locking check), rod and hinge forces, shaft torque", Fidelity::WITH_FORCES),
    ELASTIC = Stage::new("elastic", "The ODE of the compliant rod 4 (slider 5 as the degree of freedom, the 7x7 system per evaluation), integrated inside fmi2DoStep", Fidelity::DYNAMIC).always();
    /// What the masses, friction and cutting force feed.
    LOADS = FORCES.or(ELASTIC),
}

crate::model_variables! {
    pub enum V (nominal_rpm = 300.0, torque_needs = stage::FORCES) {
        // ---- parameters (paper 004 where it gives them, else documented assumptions)
        crank_l1 = Var::parameter("crank.l1", 0.019, "m", "Crank length l1 (assumption: paper 004 gives relative sizes only)").min(0.0),
        rod_lambda2 = Var::parameter("rod.lambda2", 2.0, "", "lambda2 = l2/l1, rod over crank (paper 004: 2)").min(1.0),
        crank_e = Var::parameter("crank.e", 0.0, "m", "Eccentricity e of the guide of slider 5 from the crank axis (paper 004: 0)"),
        holder_l4 = Var::parameter("holder.l4", 0.022, "m", "Length l4 of knife holder CD (assumption)").min(0.0),
        holder_lS = Var::parameter("holder.lS", 0.5, "", "Distance C to the knife point S as a fraction of l4 (paper 004's example: 0.5)").min(0.0).max(1.0),
        support_alpha = Var::parameter("support.alpha", std::f64::consts::FRAC_PI_4, "rad", "Angle alpha of the support line EQ from the vertical (paper 004 studies 45..70 deg)").min(-std::f64::consts::FRAC_PI_2).max(std::f64::consts::FRAC_PI_2),
        support_xQ = Var::parameter("support.xQ", 0.060, "m", "x of point Q of the support line EQ (assumption)"),
        support_yQ = Var::parameter("support.yQ", 0.010, "m", "y of point Q of the support line EQ (assumption)"),
        assembly_branch = Var::int_parameter("assembly.branch", 1, "Which of the two holder positions: beta = -alpha + branch*acos(c), +1 or -1").min(-1.0).max(1.0),
        kinematics_series = Var::bool_parameter("kinematics.series", false, "true: slider C by paper 004's series form (1), x_C = l1*(lambda2 + cos(phi) - sin(phi)^2/(2*lambda2)), e = 0 only; false: exact"),
        holder_m = Var::parameter("holder.m", 0.8, "kg", "Mass of the holder with its knives, at S (assumption)").min(0.0).feeds(stage::LOADS),
        holder_J = Var::parameter("holder.J", 0.0, "kg.m2", "Moment of inertia of holder and knives about S (assumption: 0, the holder's mass lumped at S)").min(0.0).feeds(stage::LOADS),
        slider5_m = Var::parameter("slider5.m", 0.3, "kg", "Mass of slider 5 at C (assumption)").min(0.0).feeds(stage::LOADS),
        slider7_m = Var::parameter("slider7.m", 0.2, "kg", "Mass of slider 7 at D (assumption)").min(0.0).feeds(stage::LOADS),
        rod_m = Var::parameter("rod.m", 0.15, "kg", "Rod mass, half lumped at the crank pin and half at C (assumption)").min(0.0).feeds(stage::LOADS),
        crank_J = Var::parameter("crank.J", 2e-4, "kg.m2", "Moment of inertia of the crank about its axis A, centre of mass on A (assumption)").min(0.0).feeds(stage::LOADS),
        guide_mu = Var::parameter("guide.mu", 0.1, "", "Coulomb friction coefficient of slider 5 in its guide (assumption)").min(0.0).feeds(stage::LOADS),
        support_mu = Var::parameter("support.mu", 0.1, "", "Coulomb friction coefficient of slider 7 on EQ (assumption)").min(0.0).feeds(stage::LOADS),
        cut_F = Var::parameter("cut.F", 150.0, "N", "Cutting force at S in the working stroke, against the velocity of S relative to the block (assumption)").min(0.0).feeds(stage::LOADS),
        feed_V = Var::parameter("feed.V", 0.2, "m/s", "Feed speed of the book block, along -y (assumption)").feeds(stage::LOADS),
        gravity_g = Var::parameter("gravity.g", 0.0, "m/s2", "Gravity along -y (assumption: 0, the mechanism works in a horizontal plane; 9.80665 for a vertical one, y up)").feeds(stage::LOADS),
        // ---- calculated parameters
        rod_l2 = Var::calculated("rod.l2", "m", "Rod length l2 = lambda2*l1 (paper 004)"),
        slider_stroke = Var::calculated("slider.stroke", "m", "Stroke of slider 5 (2*l1 for e = 0)"),
        // ---- outputs
        slider_x = Var::output("slider.x", "m", "x_C: position of slider 5 (hinge C) from the crank axis (paper 004, eq. 1)").depends(ON_PHI),
        slider_v = Var::output("slider.v", "m/s", "Velocity of slider 5 along x (eqs. 2-3)").depends(ON_PHI_W),
        slider_a = Var::output("slider.a", "m/s2", "Acceleration of slider 5 along x (eq. 4)").depends(ON_ALL),
        holder_beta = Var::output("holder.beta", "rad", "Angle beta of holder CD from +x (eq. 5)").depends(ON_PHI),
        holder_w = Var::output("holder.w", "rad/s", "Angular velocity of the holder").depends(ON_PHI_W),
        holder_eps = Var::output("holder.eps", "rad/s2", "Angular acceleration of the holder").depends(ON_ALL),
        knife_x = Var::output("knife.x", "m", "x of the knife point S (eq. 8)").depends(ON_PHI),
        knife_y = Var::output("knife.y", "m", "y of the knife point S (eq. 8)").depends(ON_PHI),
        knife_vx = Var::output("knife.vx", "m/s", "Velocity of S, x").depends(ON_PHI_W),
        knife_vy = Var::output("knife.vy", "m/s", "Velocity of S, y").depends(ON_PHI_W),
        knife_ax = Var::output("knife.ax", "m/s2", "Acceleration of S, x").depends(ON_ALL),
        knife_ay = Var::output("knife.ay", "m/s2", "Acceleration of S, y").depends(ON_ALL),
        support_x = Var::output("support.x", "m", "x of hinge D, slider 7 on EQ (eq. 6)").depends(ON_PHI),
        support_y = Var::output("support.y", "m", "y of hinge D, slider 7 on EQ (eq. 6)").depends(ON_PHI),
        knife_working = Var::bool_output("knife.working", "True in the working stroke: slider C moves to +x").depends(ON_PHI_W).event(),
        cut_Fx = Var::output("cut.Fx", "N", "Cutting force on the holder at S, x: cut.F against the velocity of S relative to the block, working stroke only (kinetostatic level)").depends(ON_PHI_W).needs(stage::FORCES),
        cut_Fy = Var::output("cut.Fy", "N", "Cutting force on the holder at S, y (kinetostatic level)").depends(ON_PHI_W).needs(stage::FORCES),
        rod_F = Var::output("rod.F", "N", "Rod force P, compression positive (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        guide_N = Var::output("guide.N", "N", "Normal force of its guide on slider 5, along +y (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        support_N = Var::output("support.N", "N", "Normal force of EQ on slider 7, along (cos(alpha), -sin(alpha)) (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        pinC_F = Var::output("pinC.F", "N", "Magnitude of the hinge force at C, slider 5 - holder (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        pinD_F = Var::output("pinD.F", "N", "Magnitude of the hinge force at D, slider 7 - holder (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        sliders_locked = Var::bool_output("sliders.locked", "True where Coulomb friction self-locks a slider (no unique force solution; slider 7: |tan(beta + alpha)| < support.mu); forces are then computed without friction (kinetostatic level)").depends(ON_PHI_W).needs(stage::FORCES),
        // ---- elastodynamic level (dynamics.md: rod compliance between crank pin and slider 5)
        @with crate::chain_variables { spring(stage::ELASTIC;
            2e8,
            "Axial stiffness of rod 4 between crank pin B and slider 5 with its pin bearings (elastodynamic level; assumption: steel shank of 60 mm2 over l2 = 38 mm, EA/l2 = 3.3e8 N/m, in series with two pin bearings of 1e9 N/m)",
            "Damping ratio of the rod, c = 2*zeta*sqrt(k*M_ref), M_ref the reduced mass of the chain behind the rod at the outer dead centre (elastodynamic level; assumption)",
        ) },
        @with crate::chain_variables { solver(stage::ELASTIC) },
        slider_x_kin = Var::output("slider.x_kin", "m", "Rigid reference position x_C(phi) of slider 5 (elastodynamic level; equals slider.x at the others)").depends(ON_PHI),
        elastic_deflection = Var::output("elastic.deflection", "m", "Shortening of rod 4, rigid rod length - |C - B| (elastodynamic level; 0 at the others)").depends(ON_PHI).needs(stage::ELASTIC),
        elastic_F = Var::output("elastic.F", "N", "Dynamic rod force k*deflection + c*deflection rate, compression positive; rod.F equals it at the elastodynamic level (0 at the others)").depends(ON_PHI_W).needs(stage::ELASTIC),
        rod_F_kin = Var::output("rod.F_kin", "N", "Kinetostatic rod force on the rigid motion, the reference of dyn.factor (elastodynamic level; equals rod.F at kinetostatic, 0 at kinematic)").depends(ON_ALL).needs(stage::FORCES),
        dyn_factor = Var::output("dyn.factor", "", concat!("Dynamic factor K_d: peak |elastic.F| over the peak kinetostatic rod force, of the last complete shaft turn (the running one until a turn is complete), the peaks taken ", crate::at_accepted_steps!(), " (elastodynamic level, 1 at the others)")).needs(stage::ELASTIC),
        @with crate::chain_variables { results(stage::ELASTIC) },
        // ---- Model Exchange states of the elastodynamic level and their derivatives
        @with crate::chain_variables { states(stage::ELASTIC, length;
            "State: position x of slider 5 along its guide (elastodynamic level)",
            "State: velocity of slider 5 (elastodynamic level)",
            "State: work done on the chain behind the rod and on the rod spring by crank pin, cutting, friction, damping and weights (for the energy balance)",
        ) },
    }
}

/// The compliant rod 4 of the elastodynamic level: its constants.
#[derive(Clone, Debug, PartialEq)]
struct RodChain {
    spring: SpringDamper,
    /// [`dead_point_threshold`].
    c_dead: f64,
}

/// What the elastodynamic level carries between steps. The rod's events switch nothing (they
/// end the solver's steps at the kinks of the right-hand side); the indicators of the last event
/// or step travel with the FMU state for the signs of those resting at zero (the rigid speeds
/// with the shaft at a standstill, [`crate::solver::hold_signs`]).
type Dynamic = Chain<RodChain>;

impl ChainModel for RodChain {
    type Var = V;
    type Physics = Params;
    /// Of the shaft turns: peak |P| and peak |P_rigid|, K_d.
    type Memory = Peaks;
    type Ode<'a> = RodOde<'a>;
    const SAVED_INDICATORS: usize = <DiscKnifeDrive as Dynamics<V>>::EVENT_INDICATORS;
    const STATE_NAME: &'static str = "DiscKnifeDrive elastodynamic state";

    fn ode<'a>(&self, p: &'a Params, path: ShaftPath, _: &Values<V>, m: &Peaks) -> RodOde<'a> {
        self.rod_ode(p, path, m)
    }
    fn start(ode: &RodOde, path: &ShaftPath, m: &mut Peaks) {
        *m = Peaks::new(ode.path.cycle(path.t0));
    }
    fn absorb(ode: &RodOde, m: &mut Peaks) {
        *m = ode.peaks.get();
    }

    /// The partial state tells a rod so soft that the slider left the range where the holder
    /// assembles (eq. 5 has no solution there).
    fn step_failed(&self, ode: &RodOde, y: &[f64; 3], why: String) -> String {
        let c = ode.p.assembly_cos(y[0]);
        let near = 1.0 - 2.0 * (1.0 - self.c_dead); // well beyond the rigid range
        if c.is_nan() || c.abs() >= near {
            format!(
                "slider 5 reached x = {:.6} m, the dead point of the holder (|cos(beta + alpha)| = {:.7} -> 1, eq. 5: the holder's reduced mass is unbounded there): the rod (elastic.k = {} N/m) is too soft for this motion; {why}",
                y[0],
                c.abs(),
                self.spring.k
            )
        } else {
            why
        }
    }
}

impl RodChain {
    /// The rod's ODE on `path` with the peaks `m` ([`ChainModel::ode`]: it reads no variable).
    fn rod_ode<'a>(&self, p: &'a Params, path: ShaftPath, m: &Peaks) -> RodOde<'a> {
        RodOde::new(p, self.spring, path, self.c_dead, *m)
    }
}

/// The combined crank-slider drive of disc knives (paper 004) as an FMU model.
pub struct DiscKnifeDrive {
    params: Params,
    /// Whether the previous evaluation was in a self-locking zone (one warning per entry).
    was_locked: bool,
    /// The elastodynamic level's state (that level only).
    dynamic: Option<Dynamic>,
}

impl DiscKnifeDrive {
    /// The physics parameters from the variables.
    pub fn params(v: &Values<V>) -> Params {
        Params {
            crank_l1: v[V::crank_l1],
            rod_lambda2: v[V::rod_lambda2],
            crank_e: v[V::crank_e],
            holder_l4: v[V::holder_l4],
            holder_ls: v[V::holder_lS],
            support_alpha: v[V::support_alpha],
            support_xq: v[V::support_xQ],
            support_yq: v[V::support_yQ],
            branch: v.int(V::assembly_branch),
            series: v.flag(V::kinematics_series),
            holder_m: v[V::holder_m],
            holder_j: v[V::holder_J],
            slider5_m: v[V::slider5_m],
            slider7_m: v[V::slider7_m],
            rod_m: v[V::rod_m],
            crank_j: v[V::crank_J],
            guide_mu: v[V::guide_mu],
            support_mu: v[V::support_mu],
            cut_f: v[V::cut_F],
            feed_v: v[V::feed_V],
            gravity_g: v[V::gravity_g],
            drive_n: v[V::drive_n],
        }
    }

    /// What [`DiscKnifeDrive::outputs`] computes: the forces (the kinetostatic level, its
    /// stage wanted), or the chain (the elastodynamic level).
    fn level(&self, v: &Values<V>) -> Level {
        if self.dynamic.is_some() {
            Level::Elastic
        } else if shaft::fidelity(v) == Fidelity::Kinetostatic && v.wants(stage::FORCES) {
            Level::Kinetostatic
        } else {
            Level::Kinematic
        }
    }

    /// Every continuous Real output at time `time`, as `put(variable, value)`: the one source of
    /// the outputs ([`Model::evaluate`], `f64`) and of their exact partial derivatives
    /// ([`Model::partials`], dual numbers). The shaft inputs as `input` reads them (by value
    /// reference, [`shaft::state_of`]); at the elastodynamic level the chain's states and their
    /// derivatives too, the held state `[x, ẋ, W]` given to `state` (which seeds it where the
    /// states are knowns), the rigid drive on the shaft's path ([`shaft::path_of`]). Returns the
    /// kinematics put (the slider's own at the elastodynamic level) and, where forces are
    /// computed, `sliders.locked` (the Boolean outputs and the warning are [`Model::evaluate`]'s).
    ///
    /// Put with a constant (derivative 0): `dyn.factor` (a statistic of past shaft turns; 1
    /// below the elastodynamic level). Not put (held; [`Model::partials`] puts their derivative
    /// 0): the forces and `rod.F_kin` at the kinematic level, `elastic.deflection`,
    /// `elastic.F` and `elastic.E_residual` below the elastodynamic level.
    fn outputs<T: LinScalar>(
        &self,
        level: Level,
        (s, path): (ShaftState<T>, Option<ShaftPath<T>>),
        time: f64,
        state: impl FnOnce([f64; 3]) -> [T; 3],
        mut put: impl FnMut(V, T),
    ) -> (Kinematics<T>, Option<bool>) {
        let p = &self.params;
        if let (Some(d), Some(path)) = (self.dynamic.as_ref(), path) {
            let values = ShaftPath {
                phi: path.phi.re(),
                w: path.w.re(),
                a: path.a.re(),
                t0: path.t0,
                turns: path.turns,
            };
            let ode = d.model.rod_ode(p, values, &d.memory);
            let y = state(d.held_state(&ode, time));
            let (phi, w, a) = path.at(time);
            let pt = ode.point_on(&ode.rigid_at(phi, w, a), &y);
            let e = ode.energy_of(&pt);
            let e0 = if d.started { T::from(d.e0) } else { e };
            put(V::elastic_E_residual, e - e0 - y[2]);
            put(V::dyn_factor, T::from(d.memory.dyn_factor()));
            let states = [V::elastic_x, V::elastic_xd, V::elastic_W];
            let ders = [V::der_elastic_x, V::der_elastic_xd, V::der_elastic_W];
            for (var, x) in states.into_iter().zip(y) {
                put(var, x);
            }
            for (var, x) in ders.into_iter().zip([y[1], pt.eval.xdd, pt.eval.power]) {
                put(var, x);
            }
            Self::write_elastic(p, &pt, &mut put);
            // the split of shaft.tau at the held state: only the shaft acceleration changes
            let r = shaft::reduce_at_rest(pt.shaft_tau, a, |a| {
                let (phi, w, a) = ShaftPath { a, ..path }.at(time);
                ode.point_on(&ode.rigid_at(phi, w, a), &y).shaft_tau
            });
            put(V::shaft_J_red, r.j_red);
            put(V::shaft_tau0, r.tau0);
            put(V::shaft_tau, pt.shaft_tau);
            put(V::shaft_P, pt.shaft_tau * s.w);
            return (pt.kin, Some(pt.eval.locked));
        }
        let k = p.kinematics(s.phi, s.w, s.a);
        write_kinematics(&k, &mut put);
        put(V::slider_x_kin, k.x_c);
        put(V::dyn_factor, T::one());
        let forces = (level == Level::Kinetostatic).then(|| p.kinetostatics(&k));
        if let Some(f) = &forces {
            for (var, x) in force_outputs(f) {
                put(var, x);
            }
            put(V::rod_F_kin, f.rod_f);
        }
        shaft::rigid_torque(
            &s,
            forces.map(|f| f.shaft_tau),
            |a| p.kinetostatics(&p.kinematics(s.phi, s.w, a)).shaft_tau,
            &mut put,
        );
        (k, forces.map(|f| f.locked))
    }
}

/// What the outputs are computed at (`model.fidelity` and the stages wanted).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Level {
    Kinematic,
    Kinetostatic,
    Elastic,
}

/// The kinematic outputs of a [`Kinematics`] (any [`LinScalar`]).
fn write_kinematics<T: LinScalar>(k: &Kinematics<T>, put: &mut impl FnMut(V, T)) {
    put(V::slider_x, k.x_c);
    put(V::slider_v, k.v_c);
    put(V::slider_a, k.a_c);
    put(V::holder_beta, k.beta);
    put(V::holder_w, k.beta_w);
    put(V::holder_eps, k.beta_eps);
    put(V::knife_x, k.s.x);
    put(V::knife_y, k.s.y);
    put(V::knife_vx, k.v_s.x);
    put(V::knife_vy, k.v_s.y);
    put(V::knife_ax, k.a_s.x);
    put(V::knife_ay, k.a_s.y);
    put(V::support_x, k.d.x);
    put(V::support_y, k.d.y);
}

/// The outputs of the kinetostatic force analysis: put at the kinetostatic level (the
/// elastodynamic one puts its own), held at the kinematic level (with `rod.F_kin`).
const FORCE_OUTPUTS: [V; 7] = [
    V::cut_Fx,
    V::cut_Fy,
    V::rod_F,
    V::guide_N,
    V::support_N,
    V::pinC_F,
    V::pinD_F,
];

/// [`FORCE_OUTPUTS`] with their values in `f`.
fn force_outputs<T: LinScalar>(f: &Forces<T>) -> [(V, T); 7] {
    let x = [
        f.cut.x,
        f.cut.y,
        f.rod_f,
        f.guide_n,
        f.support_n,
        norm(f.pin_c),
        norm(f.pin_d),
    ];
    std::array::from_fn(|i| (FORCE_OUTPUTS[i], x[i]))
}

impl Model for DiscKnifeDrive {
    type Var = V;
    const IDENTIFIER: &'static str = "DiscKnifeDrive";
    const DESCRIPTION: &'static str =
        "Combined crank-slider drive of the disc knives that trim a book-block spine (paper 004)";
    const EXPERIMENT: Experiment = Experiment::until(0.4, 1e-3);
    const STAGES: &'static [Stage] = STAGES;

    fn prepare(v: &Values<V>) -> Result<Self, ParamError> {
        let params = Self::params(v);
        params.validate()?;
        let dynamic = if shaft::fidelity(v) == Fidelity::Elastodynamic {
            SpringDamper::check_mass(
                least_reduced_mass(&params),
                "slider5.m",
                params.slider5_m,
                "the least reduced mass of the chain behind the rod over a turn (slider5.m + rod.m/2 + slider7.m*|D'|^2 + holder.m*|S'|^2 + holder.J*beta'^2)",
            )?;
            let model = RodChain {
                spring: RodOde::spring(&params, v[V::elastic_k], v[V::elastic_zeta]),
                c_dead: dead_point_threshold(&params),
            };
            Some(Chain::new(model, v, Peaks::new(0.0)))
        } else {
            None
        };
        Ok(DiscKnifeDrive {
            params,
            was_locked: false,
            dynamic,
        })
    }

    fn evaluate(&mut self, v: &mut Values<V>, time: f64, log: &mut dyn Log) {
        let p = &self.params;
        v[V::rod_l2] = p.rod_l2();
        v[V::slider_stroke] = p.stroke();
        let level = self.level(v);
        let shaft = (
            shaft::state(v, time),
            (level == Level::Elastic).then(|| shaft::path(v, time)),
        );
        let (k, locked) = self.outputs(level, shaft, time, |y| y, |var, x| v[var] = x);
        v.set_flag(V::knife_working, k.working);
        if let Some(locked) = locked {
            v.set_flag(V::sliders_locked, locked);
            self.warn_locked(locked, &k, time, log);
        }
        if let Some(d) = self.dynamic.as_ref() {
            v[V::solver_steps] = d.integ.mem.stats.steps as f64;
        }
    }

    const PARTIALS: bool = true;

    /// [`DiscKnifeDrive::outputs`] on dual numbers; the knowns: `shaft.phi`, `shaft.w`,
    /// `shaft.a` and in Model Exchange `elastic.x`, `elastic.xd`, `elastic.W`. Held (the
    /// derivative 0): the forces and `rod.F_kin` at the kinematic level; `elastic.deflection`,
    /// `elastic.F`, `elastic.E_residual` and the state derivatives below the elastodynamic
    /// level.
    fn partials(&mut self, at: &Seeded<V>, time: f64, put: Put<V>) -> Result<(), String> {
        let v = at.values();
        let own = |y: [f64; 3]| at.own_all([V::elastic_x, V::elastic_xd, V::elastic_W], y);
        let level = self.level(v);
        let input = |vr| at.get_vr(vr);
        let shaft = (
            shaft::state_of(v, time, input),
            (level == Level::Elastic).then(|| shaft::path_of(v, time, &input)),
        );
        self.outputs(level, shaft, time, own, &mut *put);
        if level != Level::Elastic {
            let chain = [V::der_elastic_x, V::der_elastic_xd, V::der_elastic_W];
            let held = [V::elastic_E_residual, V::elastic_deflection, V::elastic_F];
            put_zero(put, chain.into_iter().chain(held));
        }
        if level == Level::Kinematic {
            put_zero(put, FORCE_OUTPUTS.into_iter().chain([V::rod_F_kin]));
        }
        Ok(())
    }
}

crate::chain_access!(DiscKnifeDrive, dynamic, params);

impl Dynamics<V> for DiscKnifeDrive {
    const STATES: usize = 3;
    const EVENT_INDICATORS: usize = 5;

    // Co-Simulation and Model Exchange from solver::chain (the FMU state is the model's own:
    // the self-locking flag first)
    crate::chain_hooks!(dynamic, params: do_step, me_states, me_set_states, me_derivatives,
        me_event_indicators, me_event, me_completed_step);

    fn save_state(&self) -> Vec<f64> {
        let mut s = vec![f64::from(u8::from(self.was_locked))];
        if let Some(d) = self.dynamic.as_ref() {
            s.extend(d.save());
        }
        s
    }

    fn restore_state(&mut self, state: &[f64]) -> Result<(), String> {
        let (first, rest) = state.split_first().ok_or("DiscKnifeDrive state: empty")?;
        if *first != 0.0 && *first != 1.0 {
            return Err(format!(
                "DiscKnifeDrive state: expected the self-locking flag 0 or 1 first, got {state:?}"
            ));
        }
        match self.dynamic.as_mut() {
            Some(d) => d.restore(rest)?,
            None if rest.is_empty() => {}
            None => {
                return Err(format!(
                    "DiscKnifeDrive state: {} numbers of the elastodynamic level given to another level",
                    rest.len()
                ));
            }
        }
        self.was_locked = *first == 1.0;
        Ok(())
    }
}

impl DiscKnifeDrive {
    /// One warning per entry into a self-locking zone. A slider position where the holder does
    /// not assemble (a Model Exchange host's state far off the motion: no holder angle, so no
    /// friction criterion either) is named as such, not as a self-locking.
    fn warn_locked(&mut self, locked: bool, k: &Kinematics, time: f64, log: &mut dyn Log) {
        let p = &self.params;
        if locked && !self.was_locked {
            let tan = (k.beta + p.support_alpha).tan().abs();
            let msg = if tan.is_finite() {
                format!(
                    "t = {time}: friction self-locks a slider at crank angle {:.2} deg (|tan(beta + alpha)| = {tan:.4} < support.mu = {}): no unique force solution; forces computed without friction while sliders.locked",
                    k.phi.to_degrees(),
                    p.support_mu
                )
            } else {
                format!(
                    "t = {time}: slider 5 at x = {} m (crank angle {:.2} deg): the holder does not assemble there (eq. 5 has no solution: holder.beta = {}), the chain's kinematics and forces are not defined",
                    k.x_c,
                    k.phi.to_degrees(),
                    k.beta
                )
            };
            log.log(Severity::Warning, &msg);
        }
        self.was_locked = locked;
    }

    /// The outputs of the elastodynamic level at one point: the chain behind the rod at the
    /// slider's elastic position, the forces of the swapped 7×7 solve, the dynamic rod force
    /// (any [`LinScalar`]).
    fn write_elastic<T: LinScalar>(p: &Params, pt: &Point<T>, put: &mut impl FnMut(V, T)) {
        write_kinematics(&pt.kin, put);
        let ev = &pt.eval;
        put(V::slider_x_kin, pt.rigid.kin.x_c);
        put(V::elastic_deflection, ev.delta);
        put(V::elastic_F, ev.force);
        put(V::rod_F, ev.force);
        put(V::rod_F_kin, p.kinetostatics(&pt.rigid.kin).rod_f);
        put(V::cut_Fx, pt.rigid.load.x);
        put(V::cut_Fy, pt.rigid.load.y);
        put(V::guide_N, ev.z[5]);
        put(V::support_N, ev.z[6]);
        put(V::pinC_F, hypot(ev.z[1], ev.z[2]));
        put(V::pinD_F, hypot(ev.z[3], ev.z[4]));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::partials::check;
    use crate::model::{NoLog, VarSet, check_bounds};

    struct Recorder(Vec<(Severity, String)>);
    impl Log for Recorder {
        fn log(&mut self, s: Severity, m: &str) {
            self.0.push((s, m.to_string()));
        }
    }

    #[test]
    fn a_chain_without_mass_is_refused_at_the_elastodynamic_level_naming_slider5_m() {
        let mut v = Values::<V>::start();
        for x in [V::holder_m, V::slider5_m, V::slider7_m, V::rod_m] {
            v[x] = 0.0;
        }
        // a step used to fail with "step-size collapse ... error estimate inf"
        check::refused_only_elastodynamic::<DiscKnifeDrive>(&mut v, "slider5.m");
        // the holder's mass alone carries the chain wherever it moves with the slider
        v[V::holder_m] = 0.8;
        let mut m = DiscKnifeDrive::prepare(&v).expect("a chain with mass");
        let mut log = Recorder(vec![]);
        m.step(&mut v, 0.0, 1e-3, &mut log).expect("a step");
    }

    #[test]
    fn defaults_are_the_physics_defaults() {
        let v = Values::<V>::start();
        assert_eq!(DiscKnifeDrive::params(&v), Params::default());
        assert_eq!(check_bounds(&v), Ok(()));
        assert!(DiscKnifeDrive::prepare(&v).is_ok());
        // 300 rpm nominal speed.
        assert!((v[V::shaft_w] - 10.0 * std::f64::consts::PI).abs() < 1e-12);
    }

    #[test]
    fn outputs_are_the_physics() {
        let mut v = Values::<V>::start();
        let mut m = DiscKnifeDrive::prepare(&v).unwrap();
        let p = Params::default();
        for j in 0..100 {
            let phi = 0.0731 * j as f64;
            v[V::shaft_phi] = phi;
            v[V::shaft_a] = 12.0;
            m.evaluate(&mut v, 0.0, &mut NoLog);
            let k = p.kinematics(phi, v[V::shaft_w], 12.0);
            let f = p.kinetostatics(&k);
            assert_eq!(v[V::knife_x], k.s.x);
            assert_eq!(v[V::knife_ay], k.a_s.y);
            assert_eq!(v[V::holder_beta], k.beta);
            assert_eq!(v[V::shaft_tau], f.shaft_tau);
            assert_eq!(v[V::shaft_P], f.shaft_tau * v[V::shaft_w]);
            assert_eq!(v[V::pinD_F], f.pin_d.norm());
            assert_eq!(v.flag(V::knife_working), k.working);
            assert_eq!(v.flag(V::sliders_locked), f.locked);
            assert_eq!(v[V::rod_l2], 0.038);
        }
    }

    #[test]
    fn kinematic_level_has_no_forces() {
        let mut v = Values::<V>::start();
        v[V::model_fidelity] = 1.0;
        let mut m = DiscKnifeDrive::prepare(&v).unwrap();
        v[V::shaft_phi] = 4.0;
        m.evaluate(&mut v, 0.0, &mut NoLog);
        assert_eq!(
            (v[V::shaft_tau], v[V::rod_F], v[V::cut_Fx]),
            (0.0, 0.0, 0.0)
        );
        assert!(v[V::knife_x] > 0.02);
    }

    #[test]
    fn one_warning_per_locked_zone() {
        let mut v = Values::<V>::start();
        let mut m = DiscKnifeDrive::prepare(&v).unwrap();
        let mut log = Recorder(vec![]);
        for j in 0..=720 {
            v[V::shaft_phi] = std::f64::consts::TAU * 2.0 * j as f64 / 720.0;
            m.evaluate(&mut v, j as f64, &mut log);
        }
        // Two turns: the zone around 180 deg is entered twice.
        assert_eq!(log.0.len(), 2, "{:?}", log.0);
        assert!(
            log.0
                .iter()
                .all(|(s, m)| *s == Severity::Warning && m.contains("self-locks"))
        );
        let st = m.save_state();
        assert!(m.restore_state(&st).is_ok());
        assert!(m.restore_state(&[0.5]).is_err());
    }

    #[test]
    fn refuses_a_holder_that_cannot_assemble() {
        let mut v = Values::<V>::start();
        v[V::support_xQ] = 0.075;
        let e = DiscKnifeDrive::prepare(&v).err().unwrap();
        assert_eq!(e.param, "holder.l4");
        assert!(e.to_string().contains("crank angles from"), "{e}");
        v[V::support_xQ] = 0.060;
        v[V::assembly_branch] = 0.0;
        assert_eq!(
            DiscKnifeDrive::prepare(&v).err().unwrap().param,
            "assembly.branch"
        );
        assert!(V::table().iter().any(|x| x.name == "sliders.locked"));
    }

    /// The exact partial derivatives against central differences of `evaluate` at every level:
    /// the idle and the working stroke, inside the self-locking zone, the series form, a shaft
    /// moved on from the inputs' instant and the constant-speed drive; at the elastodynamic
    /// level along the inputs (the held state a constant, as in Co-Simulation) and along the
    /// states (Model Exchange's knowns, with the state derivatives), the rod compressed and
    /// stretched (tests/partials.rs checks the default FMU over the C ABI).
    #[test]
    fn partials_equal_central_differences() {
        // the phases covered: (level, working stroke, locked)
        let mut seen = vec![];
        // (level, drive.mode, series, phi, w, a, time, slider off its rigid position and speed)
        for (level, mode, series, phi, w, a, time, dy) in [
            (2.0, 1.0, 0.0, 1.2, 30.0, 0.0, 0.0, [0.0; 2]),
            (2.0, 1.0, 0.0, 4.0, 30.0, 40.0, 0.0, [0.0; 2]),
            (2.0, 1.0, 0.0, 5.5, 25.0, -30.0, 0.0, [0.0; 2]),
            (2.0, 1.0, 0.0, 3.13, 30.0, 5.0, 0.0, [0.0; 2]),
            (2.0, 1.0, 1.0, 4.5, 30.0, 5.0, 0.0, [0.0; 2]),
            (2.0, 1.0, 0.0, 4.0, 30.0, 5.0, 2e-3, [0.0; 2]),
            (2.0, 2.0, 0.0, 4.0, 30.0, 5.0, 0.013, [0.0; 2]),
            (1.0, 1.0, 0.0, 4.0, 30.0, 40.0, 0.0, [0.0; 2]),
            (3.0, 1.0, 0.0, 1.2, 30.0, 0.0, 0.0, [1e-6, 0.01]),
            (3.0, 1.0, 0.0, 4.0, 30.0, 40.0, 0.0, [1e-6, -0.02]),
            (3.0, 1.0, 0.0, 5.5, 25.0, -30.0, 1e-3, [-2e-6, 0.03]),
            (3.0, 2.0, 0.0, 4.0, 30.0, 5.0, 0.013, [1e-6, 0.01]),
        ] {
            let mut v = Values::<V>::start();
            v[V::model_fidelity] = level;
            v[V::drive_mode] = mode;
            v[V::kinematics_series] = series;
            check::set_shaft(&mut v, phi, w, a);
            let mut m = DiscKnifeDrive::prepare(&v).unwrap();
            // a started chain with a held state off the rigid motion
            let s = shaft::state(&v, time);
            let k = m.params.kinematics(s.phi, s.w, s.a);
            let y0 = [k.x_c + dy[0], k.v_c + dy[1], 0.2];
            let elastic = m.dynamic.is_some();
            if elastic {
                m.me_set_states(&v, time, &y0);
            }
            let mut at0 = v.clone();
            m.evaluate(&mut at0, time, &mut NoLog);
            seen.push((
                level,
                at0.flag(V::knife_working),
                at0.flag(V::sliders_locked),
            ));
            check::inputs_and_states(
                &mut m,
                &v,
                time,
                &[],
                elastic,
                // steps short of the stiff chain's curvature in the angle (2e8 N/m), long in
                // the acceleration (the outputs are nearly affine in it, and their rounding
                // is that of the large rod forces), the states within the rod's deflection
                |k, x| {
                    x.abs().max(1.0)
                        * match k {
                            V::shaft_phi => 2e-8,
                            V::shaft_w => 1e-6,
                            V::shaft_a => 1e-3,
                            _ => 1e-9,
                        }
                },
                1e-14,
                &format!("level {level} mode {mode} series {series} phi {phi} a {a} time {time}"),
            );
        }
        for phase in [(2.0, true, false), (2.0, false, false), (2.0, false, true)] {
            assert!(seen.contains(&phase), "{phase:?} in {seen:?}");
        }
        for level in [3.0] {
            for working in [true, false] {
                assert!(
                    seen.iter().any(|s| s.0 == level && s.1 == working),
                    "{seen:?}"
                );
            }
        }
    }
}
