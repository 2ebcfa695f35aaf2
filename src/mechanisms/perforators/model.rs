//! The Perforators FMU: its variables, declared once, and the glue from them to
//! [`super::physics`] (`../shared/spec/perforators.md`).
//!
//! Per-cycle quantities live in the model's state, advanced in `do_step`: the smallest ramp
//! contact force of the current and of the last completed shaft turn (`roller.F_margin`), and
//! whether the roller lost contact during the last communication step (`roller.lost_contact`,
//! with a `logWarning` naming the shaft angle where it starts). The step is sampled at most
//! 0.25° of shaft angle apart, the shaft extrapolated from its inputs (`φ + ω·τ + ε·τ²/2`).

use super::physics::{Drive, Mode, Params};
use crate::mechanics::cyclogram::Phase;
use crate::mechanisms::sewing_table::model::{MOTION_LAW, motion_law};
use crate::mechanisms::sewing_table::physics::{Kind, Params as TableParams};
use crate::model::shaft::{self, Fidelity, ON_ALL, ON_PHI, ON_PHI_W};
use crate::model::{EnumType, Experiment, Log, Model, ParamError, Severity, Stage, Stages, Values};
use std::f64::consts::TAU;

/// `synth.mode`.
pub static SYNTH_MODE: EnumType = EnumType {
    name: "SynthMode",
    description: "Which lever swing the ramp is built for (perforators.md)",
    items: &[
        (
            "paper",
            "paper 000's gamma_sum of eq. (3); the carriage then travels 2.3 % more than lambda_S",
        ),
        ("exact", "the swing that gives exactly lambda_S"),
    ],
};

/// The computations a scene may leave out (`scenes.md`); the variables below say which they
/// need (`.needs`) or feed (`.feeds`). The kinematics always run.
pub mod stage {
    use crate::model::Stages;
    /// [`super::STAGES`]`[0]`.
    pub const FORCES: Stages = Stages::bit(0);
    /// [`super::STAGES`]`[1]`.
    pub const HERTZ: Stages = Stages::bit(1);
    /// [`super::STAGES`]`[2]`.
    pub const WATCH: Stages = Stages::bit(2);
    /// [`super::STAGES`]`[3]`.
    pub const SYNTHESIS: Stages = Stages::bit(3);
    /// What the loads, masses and spring feed.
    pub const LOADS: Stages = FORCES.or(HERTZ).or(WATCH);
}

/// The stages of [`stage`], in bit order.
pub static STAGES: &[Stage] = &[
    Stage {
        name: "forces",
        description: "Kinetostatic force analysis: piercing load, carriage inertia and guide friction, rod, lever with spring and hinge friction, ramp contact force, table reaction, shaft torque",
        levels: &[Fidelity::Kinetostatic],
        requires: Stages::NONE,
        always: false,
    },
    Stage {
        name: "hertz",
        description: "Hertz contact stress roller - ramp (paper 002 eq. 8)",
        levels: &[Fidelity::Kinetostatic],
        requires: stage::FORCES,
        always: false,
    },
    Stage {
        name: "contact_watch",
        description: "Inside fmi2DoStep, the ramp contact force sampled every 0.25 deg of shaft angle: lift-off detection and warning, smallest force per turn",
        levels: &[Fidelity::Kinetostatic],
        requires: stage::FORCES,
        always: false,
    },
    Stage {
        name: "synthesis",
        description: "Paper 000's linkage synthesis reported as calculated parameters (rewritten at every evaluation)",
        levels: &[
            Fidelity::Kinematic,
            Fidelity::Kinetostatic,
            Fidelity::Elastodynamic,
        ],
        requires: Stages::NONE,
        always: false,
    },
];

crate::model_variables! {
    pub enum V (nominal_rpm = 100.0, torque_needs = stage::FORCES) {
        // ---- coupling to a main-shaft drive (MainShaft: load*.J_red, load*.tau0)
        shaft_J_red = shaft::j_red_var(ON_PHI_W).needs(stage::FORCES),
        shaft_tau0 = shaft::tau0_var(ON_PHI_W).needs(stage::FORCES),
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
        synth_mode = Var::enum_parameter("synth.mode", &SYNTH_MODE, "exact", "paper: ramp built for the paper's swing (eq. 3); exact: for the swing giving lambda_S"),
        // ---- the table it rides on (same as SewingTable)
        synth_l1 = Var::parameter("synth.l1", 1.0, "", "Table synthesis l1, relative (paper 000: 1.0; as SewingTable)").min(0.0),
        synth_R = Var::parameter("synth.R", 11.0, "", "Table synthesis R, relative (paper 000: 11.0; as SewingTable)").min(0.0),
        synth_alpha2 = Var::parameter("synth.alpha2", 20f64.to_radians(), "rad", "Swing of the rocking table the travel is synthesized from (paper 000: 20 deg; as SewingTable)").min(0.0).max(std::f64::consts::FRAC_PI_2),
        cycle_forward = Var::parameter("cycle.forward", 82f64.to_radians(), "rad", "Shaft angle of the table's forward travel (as SewingTable)").min(0.0),
        cycle_dwell_sew = Var::parameter("cycle.dwell_sew", 110f64.to_radians(), "rad", "Table dwell at sewing (as SewingTable; assumption)").min(0.0),
        cycle_return = Var::parameter("cycle.return", 90f64.to_radians(), "rad", "Shaft angle of the table's return (as SewingTable; assumption)").min(0.0),
        cycle_phi0 = Var::parameter("cycle.phi0", 0.0, "rad", "Shaft angle where the forward travel starts (as SewingTable)"),
        law_forward = Var::enum_parameter("law.forward", &MOTION_LAW, "cycloidal", "Table law of the forward travel (as SewingTable)"),
        law_return = Var::enum_parameter("law.return", &MOTION_LAW, "cycloidal", "Table law of the return travel (as SewingTable)"),
        // ---- needle law over the travel
        travel_rise_fraction = Var::parameter("travel.rise_fraction", 0.5, "", "Fraction of the table travel over which the perforators rise (paper 000: half)").min(0.0).max(1.0),
        law_rise = Var::enum_parameter("law.rise", &MOTION_LAW, "cycloidal", "Needle law of the rise over the table position (paper 002: 'Co' on the working stroke)"),
        law_fall = Var::enum_parameter("law.fall", &MOTION_LAW, "cycloidal", "Needle law of the fall over the table position"),
        // ---- loads and masses
        pierce_Q = Var::parameter("pierce.Q", 22.0 * crate::mechanics::STANDARD_GRAVITY, "N", "Piercing load of 12 needles in a 16-page signature of paper No. 2: 22 kgf (paper 002)").min(0.0).feeds(stage::LOADS),
        pierce_s_in = Var::parameter("pierce.s_in", 0.55, "", "Fraction of the stroke where the needles meet the fold (assumption)").min(0.0).max(1.0).feeds(stage::LOADS),
        pierce_s_out = Var::parameter("pierce.s_out", 0.75, "", "Fraction of the stroke where they are through (assumption)").min(0.0).max(1.0).feeds(stage::LOADS),
        pierce_k_f = Var::parameter("pierce.k_f", 0.15, "", "Needle friction after piercing, fraction of pierce.Q (assumption)").min(0.0).feeds(stage::LOADS),
        perf_m = Var::parameter("perf.m", 0.6, "kg", "Mass of carriage and perforators (assumption)").min(0.0).feeds(stage::LOADS),
        guide_mu = Var::parameter("guide.mu", 0.1, "", "Friction coefficient of the carriage guides (assumption)").min(0.0).feeds(stage::LOADS),
        lever_J = Var::parameter("lever.J", 0.002, "kg.m2", "Lever's moment of inertia about its pivot (assumption)").min(0.0).feeds(stage::LOADS),
        spring_M0 = Var::parameter("spring.M0", 6.0, "N.m", "Spring moment on the lever in the lowest position (assumption)").min(0.0).feeds(stage::LOADS),
        spring_kt = Var::parameter("spring.kt", 20.0, "N.m/rad", "Spring rate about the pivot (assumption)").min(0.0).feeds(stage::LOADS),
        joint_f = Var::parameter("joint.f", 0.05, "", "Hinge friction coefficient, moment f*r*|F| in O1, A and B (as paper 002; 0 disables)").min(0.0).feeds(stage::LOADS),
        joint_r = Var::parameter("joint.r", 0.006, "m", "Hinge pin radius (assumption)").min(0.0).feeds(stage::LOADS),
        roller_r = Var::parameter("roller.r", 0.010, "m", "Ramp roller radius (assumption)").min(0.0),
        roller_b = Var::parameter("roller.b", 0.010, "m", "Ramp roller width (assumption)").min(0.0).feeds(stage::HERTZ),
        ramp_E = Var::parameter("ramp.E", 2.1e11, "Pa", "Young's modulus of the ramp (assumption: steel)").min(0.0).feeds(stage::HERTZ),
        roller_E = Var::parameter("roller.E", 2.1e11, "Pa", "Young's modulus of the roller (assumption: steel)").min(0.0).feeds(stage::HERTZ),
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
        roller_F = Var::output("roller.F", "N", "Contact force the ramp must push the roller with; < 0: the spring cannot hold it (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        roller_sigma_H = Var::output("roller.sigma_H", "Pa", "Hertz stress roller - ramp, paper 002 eq. 8 (kinetostatic level)").depends(ON_ALL).needs(stage::HERTZ),
        roller_lost_contact = Var::bool_output("roller.lost_contact", "True if the ramp would have to pull the roller now or during the last communication step (kinetostatic level)").depends(ON_ALL).needs(stage::WATCH),
        roller_F_margin = Var::output("roller.F_margin", "N", "Smallest contact force over the last completed shaft turn (during the first turn: so far) (kinetostatic level)").depends(ON_ALL).needs(stage::WATCH),
        table_x = Var::output("table.x", "m", "Table position x_t: 0 at loading, table.stroke at sewing").depends(ON_PHI),
        table_F = Var::output("table.F", "N", "Force of the perforator drive on the table along +x (towards sewing): wire into SewingTable.table.F_ext").depends(ON_ALL).needs(stage::FORCES),
    }
}

/// Largest curvature radius reported, m: a flat stretch of the ramp is reported as this.
pub const RHO_FLAT: f64 = 1000.0;

/// Per-cycle state advanced by `do_step`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct CycleState {
    /// Index of the shaft turn being sampled (NaN before the first step).
    cycle: f64,
    /// Smallest contact force in that turn so far.
    cur_min: f64,
    /// Smallest contact force of the last completed turn (+inf if none).
    last_min: f64,
    /// A negative contact force during the last step.
    lost_step: bool,
    /// The last sample was negative (to log the onset once).
    prev_negative: bool,
}

impl Default for CycleState {
    fn default() -> Self {
        Self {
            cycle: f64::NAN,
            cur_min: f64::INFINITY,
            last_min: f64::INFINITY,
            lost_step: false,
            prev_negative: false,
        }
    }
}

/// The perforator drive of paper 000 on the translating table, as an FMU model.
pub struct Perforators {
    drive: Drive,
    state: CycleState,
}

impl Perforators {
    /// The physics parameters from the variables.
    pub fn params(v: &Values<V>) -> Params {
        let table = TableParams {
            l1: v[V::synth_l1],
            r: v[V::synth_R],
            alpha2: v[V::synth_alpha2],
            unit: v[V::synth_unit],
            forward: v[V::cycle_forward],
            dwell_sew: v[V::cycle_dwell_sew],
            ret: v[V::cycle_return],
            phi0: v[V::cycle_phi0],
            law_forward: motion_law(v.int(V::law_forward)),
            law_return: motion_law(v.int(V::law_return)),
            kind: Kind::Translating,
            ..TableParams::default()
        };
        Params {
            lambda_s: v[V::synth_lambda_S],
            lambda1: v[V::synth_lambda1],
            lambda2: v[V::synth_lambda2],
            lambda3: v[V::synth_lambda3],
            lambda4: v[V::synth_lambda4],
            gamma0: v[V::synth_gamma0],
            gamma1: v[V::synth_gamma1],
            alpha: v[V::synth_alpha],
            unit: v[V::synth_unit],
            mode: if v.int(V::synth_mode) == 1 {
                Mode::Paper
            } else {
                Mode::Exact
            },
            table,
            rise_fraction: v[V::travel_rise_fraction],
            law_rise: motion_law(v.int(V::law_rise)),
            law_fall: motion_law(v.int(V::law_fall)),
            pierce_q: v[V::pierce_Q],
            pierce_s_in: v[V::pierce_s_in],
            pierce_s_out: v[V::pierce_s_out],
            pierce_k_f: v[V::pierce_k_f],
            perf_m: v[V::perf_m],
            guide_mu: v[V::guide_mu],
            lever_j: v[V::lever_J],
            spring_m0: v[V::spring_M0],
            spring_kt: v[V::spring_kt],
            joint_f: v[V::joint_f],
            joint_r: v[V::joint_r],
            roller_r: v[V::roller_r],
            roller_b: v[V::roller_b],
            ramp_e_mod: v[V::ramp_E],
            roller_e_mod: v[V::roller_E],
        }
    }

    /// The physics of this instance.
    pub fn drive(&self) -> &Drive {
        &self.drive
    }

    fn contact_force(&self, phi: f64, w: f64, eps: f64) -> f64 {
        self.drive
            .forces(&self.drive.kinematics(phi, w, eps))
            .roller_f
    }
}

impl Model for Perforators {
    type Var = V;
    const IDENTIFIER: &'static str = "Perforators";
    const MODEL_NAME: &'static str = "Perforators";
    const DESCRIPTION: &'static str = "Perforator (needle) drive riding on the translating table of a thread-sewing machine: fixed ramp, lever, rod, carriage, spring (papers 000 and 002)";
    const EXPERIMENT: Experiment = Experiment {
        start: 0.0,
        stop: 1.2,
        step: 1e-3,
        tolerance: None,
    };
    const STAGES: &'static [Stage] = STAGES;

    fn prepare(v: &Values<V>) -> Result<Self, ParamError> {
        shaft::require_level(v, &[Fidelity::Kinematic, Fidelity::Kinetostatic])?;
        let drive = Self::params(v).drive()?;
        Ok(Perforators {
            drive,
            state: CycleState::default(),
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
        let st = shaft::state(v, time);
        let k = d.kinematics(st.phi, st.w, st.a);
        v[V::perforators_s] = k.s;
        v[V::perforators_v] = k.v;
        v[V::perforators_a] = k.a;
        v[V::lever_gamma] = k.gamma;
        v[V::lever_w] = k.gamma_w;
        v[V::lever_a] = k.gamma_a;
        v[V::rod_nu] = k.nu;
        v[V::roller_rise] = k.rise;
        v[V::ramp_theta] = k.theta;
        // a flat stretch (the dwells) has an infinite radius: reported as RHO_FLAT
        v[V::ramp_rho] = k.rho.clamp(-RHO_FLAT, RHO_FLAT);
        v[V::table_x] = k.x_t;
        let tau = if shaft::fidelity(v) == Fidelity::Kinetostatic && v.wants(stage::LOADS) {
            let r = shaft::reduce(|a| d.forces_with(&d.kinematics(st.phi, st.w, a), false).tau);
            shaft::set_reduced(v, V::shaft_J_red, V::shaft_tau0, r);
            let f = d.forces_with(&k, v.wants(stage::HERTZ));
            v[V::pierce_Q_out] = f.pierce_q;
            v[V::perforators_F_inertia] = f.f_inertia;
            v[V::rod_F] = f.rod_f;
            v[V::spring_M] = f.spring_m;
            v[V::roller_F] = f.roller_f;
            v[V::roller_sigma_H] = f.sigma_h;
            v[V::table_F] = f.table_f;
            v.set_flag(
                V::roller_lost_contact,
                self.state.lost_step || f.roller_f < 0.0,
            );
            v[V::roller_F_margin] = if self.state.last_min.is_finite() {
                self.state.last_min
            } else {
                self.state.cur_min.min(f.roller_f)
            };
            f.tau
        } else {
            v.set_flag(V::roller_lost_contact, false);
            shaft::set_reduced(v, V::shaft_J_red, V::shaft_tau0, shaft::Reduced::default());
            0.0
        };
        shaft::set_outputs(v, tau, st.w);
    }

    fn do_step(
        &mut self,
        v: &mut Values<V>,
        time: f64,
        h: f64,
        log: &mut dyn Log,
    ) -> Result<(), String> {
        if shaft::fidelity(v) != Fidelity::Kinetostatic || !v.wants(stage::WATCH) {
            return Ok(());
        }
        let st = shaft::state(v, time);
        let dphi = (st.w * h).abs() + 0.5 * (st.a * h * h).abs();
        let n = ((dphi / 0.25f64.to_radians()).ceil() as usize).clamp(1, 4000);
        let mut s = self.state;
        s.lost_step = false;
        for j in 0..=n {
            let tau = h * j as f64 / n as f64;
            let phi = st.phi + st.w * tau + 0.5 * st.a * tau * tau;
            let w = st.w + st.a * tau;
            let f = self.contact_force(phi, w, st.a);
            let cycle = ((phi - self.drive.cyc.phi0) / TAU).floor();
            if s.cycle.is_nan() {
                s.cycle = cycle;
            } else if cycle != s.cycle {
                s.last_min = s.cur_min;
                s.cur_min = f64::INFINITY;
                s.cycle = cycle;
            }
            s.cur_min = s.cur_min.min(f);
            let negative = f < 0.0;
            if negative {
                s.lost_step = true;
                if !s.prev_negative {
                    let psi = crate::mechanics::wrap_angle(phi - self.drive.cyc.phi0);
                    let phase = self.drive.cyc.at(phi).phase;
                    log.log(
                        Severity::Warning,
                        &format!(
                            "roller lifts off the ramp at shaft angle {:.2} deg ({:.2} deg into the turn, {}) at t = {:.6} s, {:.1} rpm: the ramp would have to pull with {:.2} N; spring.M0 = {} N.m, spring.kt = {} N.m/rad are too weak at this speed",
                            phi.to_degrees(),
                            psi.to_degrees(),
                            if phase == Phase::Forward { "forward travel" } else { "return travel" },
                            time + tau,
                            w * 30.0 / std::f64::consts::PI,
                            -f,
                            self.drive.p.spring_m0,
                            self.drive.p.spring_kt
                        ),
                    );
                }
            }
            s.prev_negative = negative;
        }
        self.state = s;
        Ok(())
    }

    fn save_state(&self) -> Vec<f64> {
        let s = &self.state;
        vec![
            s.cycle,
            s.cur_min,
            s.last_min,
            s.lost_step as u8 as f64,
            s.prev_negative as u8 as f64,
        ]
    }

    fn restore_state(&mut self, state: &[f64]) -> Result<(), String> {
        match *state {
            [] => {
                self.state = CycleState::default();
                Ok(())
            }
            [cycle, cur_min, last_min, lost, prev] => {
                self.state = CycleState {
                    cycle,
                    cur_min,
                    last_min,
                    lost_step: lost != 0.0,
                    prev_negative: prev != 0.0,
                };
                Ok(())
            }
            _ => Err(format!(
                "Perforators state has {} values, expected 5",
                state.len()
            )),
        }
    }
}

#[cfg(test)]
mod tests;
