//! The Perforators FMU: its variables, declared once, and the glue from them to
//! [`super::physics`] (`../shared/spec/perforators.md`).
//!
//! Per-cycle quantities of the kinetostatic level live in the model's state ([`ContactWatch`]): the
//! smallest ramp contact force of the current and of the last completed shaft turn
//! (`roller.F_margin`), and whether the roller lost contact during the last step
//! (`roller.lost_contact`, with a `logWarning` naming the shaft angle where it starts). A step's
//! span is watched along the shaft's path, sampled at most 0.25° of shaft angle apart, the shaft
//! extrapolated from its state at the step's start (`φ + ω·τ + ε·τ²/2`, as the step moves it): in
//! Co-Simulation each communication step, in Model Exchange the span since the last completed
//! integrator step (the same samples for the same steps, so the outputs mean the same).

use super::elastic::{Contact, ContactLaw, LeverOde, N_EVENTS, Track};
use super::needles;
use super::physics::{Drive, Kinematics, Made, Mode, Params};
use crate::digest::TurnDigest;
use crate::mechanics::cyclogram::Phase;
use crate::mechanics::hertz::Roller;
use crate::mechanics::{clamp_of, max_of, min_of};
use crate::mechanisms::contact_watch::{ContactWatch, WatchedContact, times};
use crate::mechanisms::sewing_table::model::{MOTION_LAW, table_params};
use crate::model::partials::{Dual64, Put, Scalar, Seeded, put_zero};
use crate::model::shaft::{self, Fidelity, ON_ALL, ON_PHI, ON_PHI_W, ShaftState};
use crate::model::{Dynamics, Experiment, Log, Model, Outcome, ParamError, Stage, Values};
use crate::solver::chain::{self, Chain, ChainModel, Saved};
use crate::solver::{OdeSystem, ShaftPath};
use std::cell::Cell;
use std::f64::consts::TAU;

#[path = "model/lever.rs"]
mod lever;
use lever::{Dynamic, LeverChain, LeverMemory, Lost, bounce_report};

crate::stages! {
    FORCES = Stage::new("forces", "Kinetostatic force analysis: piercing load, carriage inertia and guide friction, rod, lever with spring and hinge friction, ramp contact force, table reaction, shaft torque", Fidelity::WITH_FORCES),
    HERTZ = Stage::new("hertz", "Hertz contact stress roller - ramp (paper 002 eq. 8)", Fidelity::WITH_FORCES).requires(stage::FORCES),
    WATCH = Stage::new("contact_watch", "Over each step (inside fmi2DoStep; in Model Exchange between completed integrator steps), the ramp contact force sampled every 0.25 deg of shaft angle: lift-off detection and warning, smallest force per turn", Fidelity::WITH_FORCES).requires(stage::FORCES).guards(),
    SYNTHESIS = Stage::new("synthesis", "Paper 000's linkage synthesis reported as calculated parameters (rewritten at every evaluation)", Fidelity::ALL),
    ELASTIC = Stage::new("elastic", "The ODE of the lever on the ramp through the unilateral contact (lift-off and landing), integrated inside fmi2DoStep", Fidelity::DYNAMIC).always();
    /// What the loads, masses and spring feed.
    LOADS = FORCES.or(HERTZ).or(WATCH).or(ELASTIC),
}

crate::model_variables! {
    pub enum V (nominal_rpm = 100.0, torque_needs = stage::FORCES) {
        // ---- linkage synthesis (paper 000)
        synth_lambda_S = Var::parameter("synth.lambda_S", 1.0, "", "lambda_S: perforator stroke, the relative unit (paper 000: 1.0)").min(0.0),
        synth_lambda1 = Var::parameter("synth.lambda1", 1.07, "", "lambda1: rod length, relative (paper 000: 1.07)").min(0.0),
        synth_lambda2 = Var::parameter("synth.lambda2", 2.0, "", "lambda2: distance of the carriage line from the lever pivot, relative (paper 000: 2.0)").min(0.0),
        synth_lambda3 = Var::parameter("synth.lambda3", 2.03, "", "lambda3: lever arm to the rod, relative (paper 000: 2.03)").min(0.0),
        synth_lambda4 = Var::parameter("synth.lambda4", 1.6, "", "lambda4: lever arm to the roller, relative (paper 000: 1.6)").min(0.0),
        synth_gamma0 = Var::parameter("synth.gamma0", 6f64.to_radians(), "rad", "gamma0: lever arm lambda3 below the horizontal in the lowest position (paper 000: 6 deg)"),
        synth_gamma1 = Var::parameter("synth.gamma1", 47f64.to_radians(), "rad", "gamma1: roller arm from the downward vertical in the lowest position (paper 000: 47 deg)"),
        synth_alpha = Var::parameter("synth.alpha", 37f64.to_radians(), "rad", "alpha: carriage line from the vertical (paper 000: 37 deg)"),
        synth_unit = Var::parameter("synth.unit", 0.030, "m", "The relative unit: lambda_S = 1 is 30 mm (paper 000, BNSh-6A)").min(0.0),
        synth_mode = Var::enum_parameter("synth.mode", &Mode::FMI, "exact", "paper: ramp built for the paper's swing (eq. 3); exact: for the swing giving lambda_S"),
        // ---- the table it rides on (same as SewingTable)
        synth_l1 = Var::parameter("synth.l1", 1.0, "", "Table synthesis l1, relative (paper 000: 1.0; as SewingTable)").min(0.0),
        synth_R = Var::parameter("synth.R", 11.0, "", "Table synthesis R, relative (paper 000: 11.0; as SewingTable)").min(0.0),
        synth_alpha2 = Var::parameter("synth.alpha2", 20f64.to_radians(), "rad", "Swing of the rocking table the travel is synthesized from (paper 000: 20 deg; as SewingTable)").min(0.0).max(std::f64::consts::FRAC_PI_2),
        cycle_forward = needles::cycle_forward(),
        cycle_dwell_sew = Var::parameter("cycle.dwell_sew", 110f64.to_radians(), "rad", "Table dwell at sewing (as SewingTable; assumption)").min(0.0),
        cycle_return = Var::parameter("cycle.return", 90f64.to_radians(), "rad", "Shaft angle of the table's return (as SewingTable; assumption)").min(0.0),
        cycle_phi0 = needles::cycle_phi0(),
        law_forward = needles::law_forward(),
        law_return = Var::enum_parameter("law.return", &MOTION_LAW, "cycloidal", "Table law of the return travel (as SewingTable)"),
        // ---- needle law over the travel; loads and masses
        @with crate::needle_variables { law_and_loads(stage::LOADS) },
        guide_mu = needles::guide_mu(stage::LOADS),
        lever_J = Var::parameter("lever.J", 0.002, "kg.m2", "Lever's moment of inertia about its pivot (assumption)").min(0.0).feeds(stage::LOADS),
        spring_M0 = Var::parameter("spring.M0", 6.0, "N.m", "Spring moment on the lever in the lowest position (assumption)").min(0.0).feeds(stage::LOADS),
        spring_kt = Var::parameter("spring.kt", 20.0, "N.m/rad", "Spring rate about the pivot (assumption)").min(0.0).feeds(stage::LOADS),
        joint_f = needles::joint_f(stage::LOADS),
        joint_r = needles::joint_r(stage::LOADS),
        roller_r = Var::parameter("roller.r", 0.010, "m", "Ramp roller radius (assumption)").min(0.0),
        roller_b = Var::parameter("roller.b", 0.010, "m", "Ramp roller width (assumption)").min(0.0).feeds(stage::HERTZ),
        ramp_E = Var::parameter("ramp.E", 2.1e11, "Pa", "Young's modulus of the ramp (assumption: steel)").min(0.0).feeds(stage::HERTZ),
        roller_E = crate::mechanisms::roller_e(stage::HERTZ),
        // ---- calculated parameters
        synth_nu = Var::calculated("synth.nu", "rad", "nu: rod to carriage line in the lowest position, eq. (2) (paper 000: 28.79 deg)").needs(stage::SYNTHESIS),
        synth_gamma_paper = Var::calculated("synth.gamma_paper", "rad", "The paper's lever swing gamma_sum, eq. (3) (28.93 deg)").needs(stage::SYNTHESIS),
        synth_gamma_sum = Var::calculated("synth.gamma_sum", "rad", "Lever swing the ramp is built for (synth.mode: paper 28.93 deg, exact 28.27 deg)").needs(stage::SYNTHESIS),
        synth_S_sum = Var::calculated("synth.S_sum", "", "S_sum: vertical rise of the roller over the swing, eq. (4) with the paper's swing (paper 000: 0.7023)").needs(stage::SYNTHESIS),
        synth_stroke_error = Var::calculated("synth.stroke_error", "", "Carriage travel with the paper's swing over lambda_S, minus 1 (+2.3 %)").needs(stage::SYNTHESIS),
        perforators_stroke = Var::calculated("perforators.stroke", "m", "Perforator stroke with the swing chosen by synth.mode").needs(stage::SYNTHESIS),
        table_stroke = Var::calculated("table.stroke", "m", "Table travel h (as SewingTable)").needs(stage::SYNTHESIS),
        // ---- outputs
        perforators_s = Var::output("perforators.s", "m", "Perforator displacement s_p from the lowest position, along the carriage line").depends(ON_PHI),
        perforators_v = Var::output("perforators.v", "m/s", "Perforator velocity").depends(ON_PHI_W),
        perforators_a = Var::output("perforators.a", "m/s2", "Perforator acceleration relative to the table").depends(ON_ALL),
        lever_gamma = Var::output("lever.gamma", "rad", "Lever rotation from the lowest position").depends(ON_PHI),
        lever_w = Var::output("lever.w", "rad/s", "Lever angular velocity").depends(ON_PHI_W),
        lever_a = Var::output("lever.a", "rad/s2", "Lever angular acceleration").depends(ON_ALL),
        rod_nu = Var::output("rod.nu", "rad", "Rod angle to the carriage line").depends(ON_PHI),
        roller_rise = Var::output("roller.rise", "m", "Vertical rise of the roller centre above its lowest position").depends(ON_PHI),
        ramp_theta = Var::output("ramp.theta", "rad", "Pressure angle: ramp normal against the roller centre's direction of motion on the lever").depends(ON_PHI),
        ramp_rho = Var::output("ramp.rho", "m", "Curvature radius of the ramp profile at the contact, + convex, - concave (a flat stretch: 1000 m)").depends(ON_PHI),
        pierce_Q_out = Var::output("pierce.Q_T", "N", "Piercing load on the needles, against their motion (kinetostatic level)").depends(ON_PHI_W).needs(stage::FORCES),
        perforators_F_inertia = Var::output("perforators.F_inertia", "N", "Inertia force of the carriage along its line, incl. the table's acceleration (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        rod_F = Var::output("rod.F", "N", "Rod force, compression positive (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        spring_M = Var::output("spring.M", "N.m", "Spring moment on the lever, -(M0 + kt*gamma) (kinetostatic level)").depends(ON_PHI).needs(stage::FORCES),
        roller_F = Var::output("roller.F", "N", "Contact force the ramp must push the roller with; < 0: the spring cannot hold it (kinetostatic level; at the elastodynamic level the dynamic force elastic.F, >= 0)").depends(ON_ALL).needs(stage::FORCES),
        roller_sigma_H = Var::output("roller.sigma_H", "Pa", "Hertz stress roller - ramp, paper 002 eq. 8 (kinetostatic level)").depends(ON_ALL).needs(stage::HERTZ),
        roller_lost_contact = Var::bool_output("roller.lost_contact", "True if the ramp would have to pull the roller now or did during the last step: the last communication step in Co-Simulation, the span since the previous completed integrator step in Model Exchange (one that ends at an event continues it), the shaft's path over it sampled at most 0.25 deg apart (kinetostatic level); elastodynamic: the roller is off the ramp now or lifted off during that step").depends(ON_ALL).needs(stage::WATCH),
        roller_F_margin = Var::output("roller.F_margin", "N", concat!("Smallest contact force over the last completed shaft turn (during the first turn: so far, and now). Kinetostatic level: along the shaft's path over each step, sampled at most 0.25 deg apart (communication steps in Co-Simulation, the spans between completed integrator steps in Model Exchange: the same samples for the same steps); elastodynamic: of elastic.F ", crate::at_accepted_steps!(), ", 0 when the roller lifted off")).depends(ON_ALL).needs(stage::WATCH),
        table_x = Var::output("table.x", "m", "Table position x_t: 0 at loading, table.stroke at sewing").depends(ON_PHI),
        table_F = Var::output("table.F", "N", "Force of the perforator drive on the table along +x (towards sewing): wire into SewingTable.table.F_ext").depends(ON_ALL).needs(stage::FORCES),
        // ---- elastodynamic level (dynamics.md)
        contact_law = Var::enum_parameter("contact.law", &ContactLaw::FMI, "hertz", "Ramp contact force law of the elastodynamic level: hertz K*pen^(10/9) or linear contact.k*pen, both with damping contact.c and never pulling").feeds(stage::ELASTIC),
        contact_k = Var::parameter("contact.k", 1e8, "N/m", "Stiffness of the linear contact law (elastodynamic level; assumption)").min(1.0).max(1e16).feeds(stage::ELASTIC),
        contact_c = Var::parameter("contact.c", 3400.0, "N.s/m", "Damping of the ramp contact on the penetration rate, c*d(pen)/dt (elastodynamic level; assumption: 5 % of critical, 2*0.05*sqrt(k*m_red), with the Hertz law's stiffness 3.0e8 N/m at the spring's preload of 150 N and m_red = 3.83 kg)").min(0.0).max(1e10).feeds(stage::ELASTIC),
        @with crate::chain_variables { solver(stage::ELASTIC) },
        contact_K_hertz = Var::calculated("contact.K_hertz", "", "K of the Hertz law F = K*pen^(10/9), in N/m^(10/9) (no FMI unit: fractional exponent), from roller.b, ramp.E, roller.E (Palmgren's line contact)"),
        contact_m_red = Var::calculated("contact.m_red", "kg", "Effective mass of lever and carriage at the roller along the ramp normal, lowest position: contact.c = 2*zeta*sqrt(k*m_red) gives a damping ratio zeta"),
        lever_gamma_kin = Var::output("lever.gamma_kin", "rad", "Rigid reference of the lever rotation (equals lever.gamma at the rigid levels)").depends(ON_PHI),
        elastic_deflection = Var::output("elastic.deflection", "rad", "Lever deflection lever.gamma_kin - lever.gamma: > 0 pressed into the ramp, < 0 lifted off (elastodynamic level; a state)").needs(stage::ELASTIC),
        contact_pen = Var::output("contact.penetration", "m", "Penetration of the roller into the ramp along its normal; < 0: the gap of a lifted roller (elastodynamic level)").depends(ON_PHI).needs(stage::ELASTIC),
        elastic_F = Var::output("elastic.F", "N", "Dynamic contact force of the ramp on the roller, >= 0 (elastodynamic level; equals roller.F there)").depends(ON_PHI_W).needs(stage::ELASTIC),
        roller_F_kin = Var::output("roller.F_kin", "N", "Kinetostatic contact force on the rigid motion, the reference of elastic.F (elastodynamic level)").depends(ON_ALL).needs(stage::FORCES),
        dyn_factor = Var::output("dyn.factor", "", concat!("Dynamic factor K_d: peak elastic.F over the peak |kinetostatic contact force| of the last complete shaft turn (the running one until a turn is complete), the peaks taken ", crate::at_accepted_steps!(), " (elastodynamic level)")).needs(stage::ELASTIC),
        @with crate::chain_variables { contact(stage::ELASTIC;
            "Times the roller lifted off the ramp",
            "contact force in the first compression after a landing of the roller",
            "elastodynamic level",
        ) },
        @with crate::chain_variables { results(stage::ELASTIC) },
        // ---- Model Exchange states of the elastodynamic level and their derivatives
        @with crate::chain_variables { states(stage::ELASTIC, angle;
            "State: lever deflection from its rigid rotation, lever.gamma_kin - lever.gamma (elastodynamic level)",
            "State: rate of the lever deflection (elastodynamic level)",
            "State: work of friction, piercing, table inertia, contact damping and the moving ramp (for the energy balance)",
        ) },
        // ---- the linkage as made (tolerance studies): the ramp is cut for the design
        made_d_rod = Var::parameter("made.d_rod", 0.0, "m", "Rod length as made minus its design length synth.lambda1*synth.unit (a manufacturing deviation: the ramp stays cut for the design, the needles' travel follows the made linkage)").min(-0.005).max(0.005),
        made_d_arm = Var::parameter("made.d_arm", 0.0, "m", "Lever arm to the rod as made minus its design length synth.lambda3*synth.unit (a manufacturing deviation, as made.d_rod)").min(-0.005).max(0.005),
        made_d_line = Var::parameter("made.d_line", 0.0, "m", "Distance of the carriage line from the lever pivot as made minus its design synth.lambda2*synth.unit (a manufacturing deviation, as made.d_rod)").min(-0.005).max(0.005),
        // ---- events (FMI 3.0 early return)
        contact_open = Var::bool_output("contact.open", "True while the roller is off the ramp (contact.penetration < 0): it rises at a lift-off, falls at a landing (elastodynamic level; false at the others)").needs(stage::ELASTIC).event(),
    }
}

/// Largest curvature radius reported, m: a flat stretch of the ramp is reported as this.
pub const RHO_FLAT: f64 = 1000.0;

/// The kinetostatic level's watch of the ramp contact ([`ContactWatch`]).
impl WatchedContact for Drive {
    fn contact_force(&self, phi: f64, w: f64, a: f64) -> f64 {
        self.forces(&self.kinematics(phi, w, a)).roller_f
    }
    fn turn_start(&self) -> f64 {
        self.cyc.phi0
    }
    /// The warning of a turn's lift-offs at the kinetostatic level.
    fn liftoff_report(&self, g: &TurnDigest<4>) -> String {
        let d = self;
        let [pull, phi, t, w] = g.worst;
        let psi = crate::mechanics::wrap_angle(phi - d.cyc.phi0);
        format!(
            "roller lifts off the ramp {} in the shaft turn {}: worst at shaft angle {:.2} deg ({:.2} deg into the turn, {}) at t = {t:.6} s, {:.1} rpm, where the ramp would have to pull with {pull:.2} N; spring.M0 = {} N.m, spring.kt = {} N.m/rad are too weak at this speed",
            times(g.count),
            g.turn,
            phi.to_degrees(),
            psi.to_degrees(),
            if d.cyc.at(phi).phase == Phase::Forward {
                "forward travel"
            } else {
                "return travel"
            },
            w * 30.0 / std::f64::consts::PI,
            d.p.spring_m0,
            d.p.spring_kt
        )
    }
}

/// The linkage's positions and rates of a [`Kinematics`] (every level puts them).
fn write_kinematics<T: Scalar>(d: &Drive, k: &Kinematics<T>, put: &mut impl FnMut(V, T)) {
    let (nu, rise, theta) = d.output_angles(k);
    put(V::perforators_s, k.s);
    put(V::perforators_v, k.v);
    put(V::perforators_a, k.a);
    put(V::lever_gamma, k.gamma);
    put(V::lever_w, k.gamma_w);
    put(V::lever_a, k.gamma_a);
    put(V::rod_nu, nu);
    put(V::roller_rise, rise);
    put(V::ramp_theta, theta);
}

/// The kinetostatic level's forces, held at the kinematic level (with `roller.F_margin`).
const RIGID_FORCES: [V; 7] = [
    V::pierce_Q_out,
    V::perforators_F_inertia,
    V::rod_F,
    V::spring_M,
    V::roller_F,
    V::roller_sigma_H,
    V::table_F,
];

/// The elastodynamic level's outputs and the Model Exchange state derivatives, which the rigid
/// levels do not write (held; the derivatives are 0 there, as `fmi2GetDerivatives` gives).
const HELD_BELOW_ELASTIC: [V; 7] = [
    V::elastic_F,
    V::roller_F_kin,
    V::contact_F_impact,
    V::elastic_E_residual,
    V::der_elastic_q,
    V::der_elastic_qd,
    V::der_elastic_W,
];

/// What [`Perforators::outputs`] computes besides the kinematics.
#[derive(Clone, Copy, Debug)]
struct Wants {
    /// The kinetostatic level's forces (and the torque).
    loads: bool,
    /// The Hertz stress.
    hertz: bool,
}

impl Wants {
    fn of(v: &Values<V>) -> Wants {
        Wants {
            loads: shaft::fidelity(v) == Fidelity::Kinetostatic && v.wants(stage::LOADS),
            hertz: v.wants(stage::HERTZ),
        }
    }
}

/// The elastodynamic level's part of [`Perforators::outputs`]: the chain's ODE, its states and
/// the rigid kinematics as a function of the shaft acceleration (at the same angle and speed).
struct Elastic<'a, T> {
    ode: &'a LeverOde<'a>,
    y: [T; 3],
    a: T,
    rigid_at: &'a dyn Fn(T) -> Kinematics<T>,
}

/// What [`Perforators::outputs`] gives `evaluate` for its Boolean outputs.
struct Discrete {
    /// The roller off the ramp or not pressing (elastodynamic), pulled (kinetostatic).
    lost: bool,
    /// The roller off the ramp (`contact.open`).
    open: bool,
}

/// The contact of the elastodynamic level from the `contact.*` parameters.
pub fn contact_of(d: &Drive, v: &Values<V>) -> Contact {
    let law = ContactLaw::from_item(v.int(V::contact_law)).unwrap_or(ContactLaw::Hertz);
    Contact::new(d, law, v[V::contact_k], v[V::contact_c])
}

/// Refuses a contact so soft that the spring's preload alone (the contact force at rest in the
/// loading dwell) presses the roller more than a tenth of its radius into the ramp: the contact
/// laws are laws of small penetrations, and the lever would leave its linkage.
fn check_contact(d: &Drive, v: &Values<V>) -> Result<(), ParamError> {
    let c = contact_of(d, v);
    let f = d.loading_force();
    let pen = c.penetration_of(f);
    let limit = 0.1 * d.p.roller.r;
    if pen > limit {
        let (param, value) = match c.law {
            ContactLaw::Linear => ("contact.k", v[V::contact_k]),
            ContactLaw::Hertz => ("roller.b", d.p.roller.b),
        };
        return Err(ParamError::new(
            param,
            value,
            format!(
                "the spring's preload of {f:.1} N presses the roller {:.3} mm into the ramp, more than a tenth of roller.r ({:.3} mm): the contact is too soft for a small-penetration contact law",
                1000.0 * pen,
                1000.0 * limit
            ),
        ));
    }
    Ok(())
}

/// The perforator drive of paper 000 on the translating table, as an FMU model.
pub struct Perforators {
    drive: Drive,
    state: ContactWatch,
    dynamic: Option<Dynamic>,
}

impl Perforators {
    /// The physics parameters from the variables.
    pub fn params(v: &Values<V>) -> Params {
        Params {
            lambda_s: v[V::synth_lambda_S],
            lambda1: v[V::synth_lambda1],
            lambda2: v[V::synth_lambda2],
            lambda3: v[V::synth_lambda3],
            lambda4: v[V::synth_lambda4],
            gamma0: v[V::synth_gamma0],
            gamma1: v[V::synth_gamma1],
            alpha: v[V::synth_alpha],
            mode: Mode::from_item(v.int(V::synth_mode)).unwrap_or(Mode::Exact),
            lever_j: v[V::lever_J],
            spring_m0: v[V::spring_M0],
            spring_kt: v[V::spring_kt],
            roller: Roller::new(v[V::roller_r], v[V::roller_b], v[V::ramp_E], v[V::roller_E]),
            made: Made {
                d_rod: v[V::made_d_rod],
                d_arm: v[V::made_d_arm],
                d_line: v[V::made_d_line],
            },
            ..needles::params(v, table_params(v))
        }
    }

    /// The physics of this instance.
    pub fn drive(&self) -> &Drive {
        &self.drive
    }

    /// Does the kinetostatic level watch the contact force over the steps ([`ContactWatch`])?
    fn watching(&self, v: &Values<V>) -> bool {
        self.dynamic.is_none()
            && shaft::fidelity(v) == Fidelity::Kinetostatic
            && v.wants(stage::WATCH)
    }

    /// Every continuous Real output at the shaft state `st`, as `put(variable, value)`, and at
    /// the elastodynamic level (`chain`) the state derivatives: the one source of the outputs
    /// ([`Model::evaluate`], `f64`) and of their exact partial derivatives ([`Model::partials`],
    /// dual numbers). What a level does not compute is not put (held: [`RIGID_FORCES`] and
    /// `roller.F_margin` at the kinematic level, [`HELD_BELOW_ELASTIC`] below the elastodynamic
    /// one).
    fn outputs<T: Scalar>(
        &self,
        w: Wants,
        st: &ShaftState<T>,
        chain: Option<Elastic<'_, T>>,
        mut put: impl FnMut(V, T),
    ) -> Discrete {
        let d = &self.drive;
        let k = d.kinematics(st.phi, st.w, st.a);
        put(V::lever_gamma_kin, k.gamma);
        // a flat stretch (the dwells) has an infinite radius: reported as RHO_FLAT
        put(V::ramp_rho, clamp_of(k.rho, -RHO_FLAT, RHO_FLAT));
        put(V::table_x, k.x_t);
        if let (Some(dy), Some(c)) = (self.dynamic.as_ref(), chain) {
            let (tau, discrete) = self.outputs_dynamic(dy, c, &mut put);
            put(V::shaft_tau, tau);
            put(V::shaft_P, tau * st.w);
            return discrete;
        }
        write_kinematics(d, &k, &mut put);
        put(V::elastic_deflection, T::zero());
        put(V::contact_pen, T::zero());
        put(V::dyn_factor, T::one());
        let mut lost = false;
        let tau = if w.loads {
            let f = d.forces_with(&k, w.hertz);
            put(V::pierce_Q_out, f.pierce_q);
            put(V::perforators_F_inertia, f.f_inertia);
            put(V::rod_F, f.rod_f);
            put(V::spring_M, f.spring_m);
            put(V::roller_F, f.roller_f);
            put(V::roller_sigma_H, f.sigma_h);
            put(V::table_F, f.table_f);
            lost = f.roller_f.re() < 0.0;
            put(V::roller_F_margin, self.state.margin(f.roller_f));
            Some(f.tau)
        } else {
            None
        };
        shaft::rigid_torque(
            st,
            tau,
            |a| d.forces_with(&d.kinematics(st.phi, st.w, a), false).tau,
            &mut put,
        );
        Discrete { lost, open: false }
    }

    /// The elastodynamic level's part of [`Perforators::outputs`] (`shaft.J_red`,
    /// `shaft.tau0`: the split at the held state, only the shaft acceleration changing);
    /// returns the shaft torque. `dyn.factor` during the first turn and `roller.F_margin`
    /// before a turn is complete include the force now (their derivative is that of the
    /// current value where it is the extreme); `contact.F_impact` and the figures of completed
    /// turns are constants now (derivative 0).
    fn outputs_dynamic<T: Scalar>(
        &self,
        dy: &Dynamic,
        c: Elastic<'_, T>,
        put: &mut impl FnMut(V, T),
    ) -> (T, Discrete) {
        let Elastic {
            ode,
            y,
            a,
            rigid_at,
        } = c;
        let pt = ode.point_at(&rigid_at(a), &y);
        let k = &pt.kin;
        let f = &pt.forces;
        write_kinematics(&self.drive, k, put);
        put(V::pierce_Q_out, f.pierce_q);
        put(V::perforators_F_inertia, f.f_inertia);
        put(V::rod_F, f.rod_f);
        put(V::spring_M, f.spring_m);
        put(V::roller_F, pt.f_c);
        put(
            V::roller_sigma_H,
            if pt.f_c.re() > 0.0 && f.roller_f.re() > 0.0 {
                // Hertz stress grows with the square root of the force
                f.sigma_h * (pt.f_c / f.roller_f).sqrt()
            } else {
                T::zero()
            },
        );
        put(V::table_F, f.table_f);
        let lost = !(pt.pen.re() > 0.0 && pt.f_pre.re() > 0.0);
        let t = &dy.memory.track;
        put(
            V::roller_F_margin,
            if t.last_min.is_finite() {
                T::from(t.last_min)
            } else {
                min_of(pt.f_c, t.peaks.dyn_min)
            },
        );
        put(V::elastic_deflection, y[0]);
        put(V::contact_pen, pt.pen);
        put(V::elastic_F, pt.f_c);
        let f_rigid = ode.rigid_force(&pt.rigid);
        put(V::roller_F_kin, f_rigid);
        put(
            V::dyn_factor,
            if t.k_d.is_nan() {
                let rigid_max = max_of(f_rigid.abs(), t.peaks.rigid_max);
                if rigid_max.re() > 0.0 {
                    max_of(pt.f_c, t.peaks.dyn_max) / rigid_max
                } else {
                    T::one()
                }
            } else {
                T::from(t.k_d)
            },
        );
        put(V::contact_F_impact, T::from(t.impact));
        put(
            V::elastic_E_residual,
            if dy.started {
                ode.energy_of(&pt) - dy.e0 - y[2]
            } else {
                T::zero()
            },
        );
        put(V::der_elastic_q, y[1]);
        put(V::der_elastic_qd, pt.rigid.gamma_a - k.gamma_a);
        put(V::der_elastic_W, pt.power);
        let r = shaft::reduce_at_rest(f.tau, a, |a| ode.point_at(&rigid_at(a), &y).forces.tau);
        put(V::shaft_J_red, r.j_red);
        put(V::shaft_tau0, r.tau0);
        (
            f.tau,
            Discrete {
                lost: dy.memory.lost.step || lost,
                open: pt.pen.re() < 0.0,
            },
        )
    }
}

impl Model for Perforators {
    type Var = V;
    const IDENTIFIER: &'static str = "Perforators";
    const DESCRIPTION: &'static str = "Perforator (needle) drive riding on the translating table of a thread-sewing machine: fixed ramp, lever, rod, carriage, spring (papers 000 and 002)";
    const EXPERIMENT: Experiment = Experiment::until(1.2, 1e-3);
    const STAGES: &'static [Stage] = STAGES;

    fn prepare(v: &Values<V>) -> Result<Self, ParamError> {
        let drive = Self::params(v).drive()?;
        if shaft::fidelity(v) == Fidelity::Elastodynamic {
            check_contact(&drive, v)?;
        }
        let dynamic = (shaft::fidelity(v) == Fidelity::Elastodynamic).then(|| {
            let model = LeverChain {
                contact: contact_of(&drive, v),
                range: LeverOde::linkage_range(&drive),
            };
            let memory = LeverMemory {
                track: Track::new(0.0),
                lost: Lost::default(),
                liftoff: TurnDigest::default(),
            };
            Chain::new(model, v, memory)
        });
        Ok(Perforators {
            drive,
            state: ContactWatch::default(),
            dynamic,
        })
    }

    fn evaluate(&mut self, v: &mut Values<V>, time: f64, _log: &mut dyn Log) {
        let d = &self.drive;
        if v.wants(stage::SYNTHESIS) {
            let syn = d.p.synthesis();
            v[V::synth_nu] = syn.nu;
            v[V::synth_gamma_paper] = d.gamma_paper;
            v[V::synth_gamma_sum] = d.gamma_sw;
            v[V::synth_S_sum] = syn.s_sum;
            v[V::synth_stroke_error] = d.stroke_error();
            v[V::perforators_stroke] = d.stroke;
            v[V::table_stroke] = d.cyc.h;
        }
        v[V::contact_K_hertz] = d.p.roller.stiffness();
        v[V::contact_m_red] = LeverOde::reduced_mass(d);
        let st = shaft::state(v, time);
        let wants = Wants::of(v);
        let path = shaft::path(v, time);
        let chain = self.dynamic.as_ref().map(|dy| {
            let ode = dy.ode(d, path, v);
            let y = dy.held_state(&ode, time);
            (ode, y)
        });
        // the rigid motion as the ODE's point takes it: on the step's path, its acceleration `a`
        let rigid_at = |a: f64| {
            let (phi, w, a) = ShaftPath { a, ..path }.at(time);
            d.kinematics(phi, w, a)
        };
        let elastic = chain.as_ref().map(|(ode, y)| Elastic {
            ode,
            y: *y,
            a: ode.path.a,
            rigid_at: &rigid_at,
        });
        let out = self.outputs(wants, &st, elastic, |var, x| v[var] = x);
        if let (Some(dy), Some((_, y))) = (self.dynamic.as_ref(), chain.as_ref()) {
            for (s, x) in [V::elastic_q, V::elastic_qd, V::elastic_W]
                .into_iter()
                .zip(y)
            {
                v[s] = *x;
            }
            v[V::contact_liftoffs] = dy.memory.track.liftoffs;
            v[V::solver_steps] = dy.integ.mem.stats.steps as f64;
            v.set_flag(V::roller_lost_contact, out.lost);
        } else {
            v.set_flag(
                V::roller_lost_contact,
                wants.loads && (self.state.lost_step || out.lost),
            );
        }
        v.set_flag(V::contact_open, out.open);
    }

    const PARTIALS: bool = true;

    /// [`Perforators::outputs`] on dual numbers; the knowns: `shaft.phi`, `shaft.w`, `shaft.a`
    /// and in Model Exchange `elastic.q`, `elastic.qd`, `elastic.W`. Before the first step the
    /// chain starts from an equilibrium, a function of the inputs. Held (the derivative 0):
    /// [`HELD_BELOW_ELASTIC`]; [`RIGID_FORCES`] and `roller.F_margin` at the kinematic level.
    fn partials(&mut self, at: &Seeded<V>, time: f64, put: Put<V>) -> Result<(), String> {
        let v = at.values();
        let d = &self.drive;
        let st = at.shaft(time);
        let wants = Wants::of(v);
        let rigid_at = |a: Dual64| d.kinematics(st.phi, st.w, a);
        let chain = self.dynamic.as_ref().map(|dy| {
            let ode = dy.ode(d, shaft::path(v, time), v);
            let y = if dy.started {
                at.own_all([V::elastic_q, V::elastic_qd, V::elastic_W], dy.y)
            } else {
                ode.initial_state_at(&rigid_at(st.a))
            };
            (ode, y)
        });
        let elastic = chain.as_ref().map(|(ode, y)| Elastic {
            ode,
            y: *y,
            a: st.a,
            rigid_at: &rigid_at,
        });
        self.outputs(wants, &st, elastic, &mut *put);
        if chain.is_none() {
            put_zero(put, HELD_BELOW_ELASTIC);
            if !wants.loads {
                put_zero(put, RIGID_FORCES.into_iter().chain([V::roller_F_margin]));
            }
        }
        Ok(())
    }

    /// The lift-offs of the unfinished turn are reported.
    fn finish(&mut self, _v: &Values<V>, log: &mut dyn Log) {
        let drive = &self.drive;
        if let Some(d) = self.dynamic.as_mut() {
            let total = d.memory.track.liftoffs;
            d.memory
                .liftoff
                .flush(log, &|g: &TurnDigest<4>| bounce_report(drive, g, total));
        } else {
            self.state
                .liftoff
                .flush(log, &|g: &TurnDigest<4>| drive.liftoff_report(g));
        }
    }
}

crate::chain_access!(Perforators, dynamic, drive);

impl Dynamics<V> for Perforators {
    fn do_step(&mut self, v: &mut Values<V>, time: f64, h: f64, log: &mut dyn Log) -> Outcome {
        if self.dynamic.is_some() {
            return chain::do_step(self.dynamic.as_mut(), &self.drive, v, time, h, log);
        }
        if self.watching(v) {
            self.state
                .watch(&self.drive, shaft::state(v, time), time, h, log);
        }
        Ok(())
    }

    const STATES: usize = 3;
    const EVENT_INDICATORS: usize = N_EVENTS;

    // Model Exchange from solver::chain ([`LeverChain`]'s hooks)
    crate::chain_hooks!(dynamic, drive: me_states, me_set_states, me_derivatives,
        me_event_indicators);

    /// Elastodynamic: [`LeverChain`]'s hook; a lift-off counted here is reported by the next
    /// completed step ([`Lost`]), as a Co-Simulation step reports one inside it. Kinetostatic:
    /// the first event (after initialization) starts the watched spans.
    fn me_event(&mut self, v: &Values<V>, time: f64, log: &mut dyn Log) {
        if let Some(d) = self.dynamic.as_mut() {
            let before = d.started.then_some(d.memory.track.liftoffs);
            if let Some(call) = chain::MeCall::of(Some(&mut *d), &self.drive, v, time) {
                call.me_event(log);
            }
            let lifted = before.is_some_and(|n| d.memory.track.liftoffs > n);
            d.memory.lost.event(lifted);
            // the turn's lift-offs, reported once the turn is over
            let (drive, tr) = (&self.drive, d.memory.track);
            let report = |g: &TurnDigest<4>| bounce_report(drive, g, tr.liftoffs);
            let turn_of = |phi: f64| ((phi - drive.cyc.phi0) / TAU).floor();
            let now = shaft::state(v, time);
            if lifted {
                let phi = tr.lift_phi;
                d.memory
                    .liftoff
                    .note(turn_of(phi), [0.0, phi, time, now.w], log, &report);
            }
            d.memory.liftoff.at_turn(turn_of(now.phi), log, &report);
        } else if self.state.me_t.is_nan() && self.watching(v) {
            self.state
                .me_watch(&self.drive, shaft::state(v, time), time, log);
        }
    }

    /// Elastodynamic: [`LeverChain`]'s hook, and `roller.lost_contact` of the span since the
    /// last completed step. Kinetostatic: that span watched as a Co-Simulation step over it.
    fn me_completed_step(&mut self, v: &Values<V>, time: f64, log: &mut dyn Log) {
        if let Some(d) = self.dynamic.as_mut() {
            if let Some(call) = chain::MeCall::of(Some(&mut *d), &self.drive, v, time) {
                call.me_completed_step(log);
            }
            d.memory.lost.completed();
        } else if self.watching(v) {
            self.state
                .me_watch(&self.drive, shaft::state(v, time), time, log);
        }
    }

    fn save_state(&self) -> Vec<f64> {
        if let Some(d) = self.dynamic.as_ref() {
            return d.save();
        }
        self.state.save()
    }

    fn restore_state(&mut self, state: &[f64]) -> Result<(), String> {
        if let Some(d) = self.dynamic.as_mut() {
            return d.restore(state);
        }
        self.state = ContactWatch::restore(state, "Perforators")?;
        Ok(())
    }
}

#[cfg(test)]
mod tests;
