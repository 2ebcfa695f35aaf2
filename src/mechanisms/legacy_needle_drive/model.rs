//! The LegacyNeedleDrive FMU: its variables, declared once, and the glue from them to
//! [`super::physics`] (`../shared/spec/legacy-needle-drive.md`).
//!
//! The needle motion, the piercing load and the names of the shared parameters are the
//! Perforators' (`cycle.*`, `law.*`, `travel.rise_fraction`, `pierce.*`, `perf.m`, `guide.mu`,
//! `joint.*`), so the two FMUs set alike move their needles alike. The cam force is watched over
//! each step as the Perforators' ramp force is ([`ContactWatch`]): with a spring-closed cam a
//! pull is a lift-off, flagged and warned once per turn.

use super::physics::{Closure, Drive, Forces, Kinematics, Params, Timing};
use crate::digest::TurnDigest;
use crate::mechanics::hertz::Roller;
use crate::mechanics::{min_of, wrap_angle};
use crate::mechanisms::contact_watch::{ContactWatch, WatchedContact, times};
use crate::mechanisms::perforators::needles;
use crate::mechanisms::sewing_table::model::{MOTION_LAW, motion_law};
use crate::mechanisms::sewing_table::physics::{Kind, Params as TableParams};
use crate::model::partials::{Put, Scalar, Seeded, put_zero};
use crate::model::shaft::{self, Fidelity, ON_ALL, ON_PHI, ON_PHI_W, ShaftState};
use crate::model::{Dynamics, Experiment, Log, Model, Outcome, ParamError, Stage, Values};

crate::stages! {
    FORCES = Stage::new("forces", "Kinetostatic force chain of paper 002, eqs. (1)-(7): load of a branch, rod, bell cranks, coupler, cam-roller force with guide and hinge friction, shaft torque", Fidelity::WITH_FORCES),
    HERTZ = Stage::new("hertz", "Hertz contact stress cam - roller (paper 002, eq. 8)", Fidelity::WITH_FORCES).requires(stage::FORCES),
    WATCH = Stage::new("contact_watch", "Over each step (inside fmi2DoStep), the cam force sampled every 0.25 deg of shaft angle: with a spring-closed cam lift-off detection and warning; the smallest force per turn", Fidelity::WITH_FORCES).requires(stage::FORCES).guards(),
    SYNTHESIS = Stage::new("synthesis", "The chain's derived sizes and angles reported as calculated parameters", Fidelity::ALL);
    /// What the loads, masses and friction feed.
    LOADS = FORCES.or(HERTZ).or(WATCH),
}

crate::model_variables! {
    pub enum V (nominal_rpm = 100.0, torque_needs = stage::FORCES) {
        // ---- cam-rocker pair (KMK)
        kmk_lk = Var::parameter("kmk.lk", 0.150, "m", "Base distance l_k = O1O2 between the cam shaft and the rocker pivot (assumption)").min(0.0),
        kmk_beta = Var::parameter("kmk.beta", 0.48, "", "beta = L_rocker/l_k, rocker arm over base distance (paper 002: 0.48 on the NSh-6)").min(0.0),
        kmk_theta = Var::parameter("kmk.theta", std::f64::consts::PI, "rad", "Direction of O1 -> O2 from +x (assumption)"),
        kmk_kappa = Var::parameter("kmk.kappa", 120f64.to_radians(), "rad", "Angle kappa from the rocker arm O2K to the crank O2A, counter-clockwise (one bell crank; assumption)"),
        // ---- four-bar (ChShRM)
        fb_R = Var::parameter("fb.R", 0.100, "m", "Crank O2A, R (assumption)").min(0.0).feeds(stage::LOADS),
        fb_c = Var::parameter("fb.c", 0.300, "m", "Coupler AB (assumption)").min(0.0),
        fb_b = Var::parameter("fb.b", 0.070, "m", "Rocker O3B, b (assumption)").min(0.0).feeds(stage::LOADS),
        fb_O3x = Var::parameter("fb.O3x", -0.180, "m", "x of the pivot O3 (assumption)"),
        fb_O3y = Var::parameter("fb.O3y", 0.300, "m", "y of the pivot O3 (assumption)"),
        fb_branch = Var::int_parameter("fb.branch", 1, "Assembly branch of the four-bar: A left (+1) or right (-1) of O2 -> B (0 is refused)").min(-1.0).max(1.0),
        // ---- rocker-slider (KPM) and the needle bar
        kpm_chi = Var::parameter("kpm.chi", std::f64::consts::PI, "rad", "Angle chi from the rocker O3B to the arm O3C, counter-clockwise (one bell crank; assumption)"),
        kpm_Rk = Var::parameter("kpm.Rk", 0.060, "m", "Arm O3C, R_k (assumption)").min(0.0).feeds(stage::LOADS),
        kpm_l = Var::parameter("kpm.l", 0.100, "m", "Rod CD to the needle bar (assumption)").min(0.0),
        kpm_branch = Var::int_parameter("kpm.branch", -1, "Assembly branch of the rocker-slider: C left (+1) or right (-1) of O3 -> D (0 is refused)").min(-1.0).max(1.0),
        bar_dir = Var::parameter("bar.dir", std::f64::consts::FRAC_PI_2, "rad", "Direction u_g of the needle bar's guide from +x; the needles rise along it (assumption: vertical)"),
        bar_D0x = Var::parameter("bar.D0x", -0.120, "m", "x of the rod's joint D on the bar with the needles lowest (assumption)"),
        bar_D0y = Var::parameter("bar.D0y", 0.385, "m", "y of D with the needles lowest (assumption)"),
        legacy_branches = Var::int_parameter("legacy.branches", 2, "Cams and lever branches driving the bar, sharing its load equally (paper 002: two)").min(1.0).max(8.0).feeds(stage::LOADS),
        // ---- the needle law the cam is made for
        needle_timing = Var::enum_parameter("needle.timing", &Timing::FMI, "perforators", "perforators: the Perforators' needle curve (equal needle motion); own: paper 002's cycloidal rise and harmonic fall"),
        needle_phi_start = Var::parameter("needle.phi_start", 61f64.to_radians(), "rad", "own timing: shaft angle after cycle.phi0 where the needles start to rise (assumption)"),
        needle_Phi_rise = Var::parameter("needle.Phi_rise", 41f64.to_radians(), "rad", "own timing: shaft angle of the rise (assumption)").min(0.0),
        needle_Phi_top = Var::parameter("needle.Phi_top", 0.0, "rad", "own timing: dwell at the top (assumption)").min(0.0),
        needle_Phi_fall = Var::parameter("needle.Phi_fall", 41f64.to_radians(), "rad", "own timing: shaft angle of the fall (assumption)").min(0.0),
        needle_law_rise = Var::enum_parameter("needle.law_rise", &MOTION_LAW, "cycloidal", "own timing: law of the rise (paper 002's 'Co' on the working stroke)"),
        needle_law_fall = Var::enum_parameter("needle.law_fall", &MOTION_LAW, "harmonic", "own timing: law of the fall (paper 002's 'K' on the idle stroke)"),
        // ---- shared with Perforators: the table cycle and the needle curve on it
        synth_unit = Var::parameter("synth.unit", 0.030, "m", "Needle stroke S (as Perforators' synth.unit with its exact swing: 30 mm)").min(0.0),
        cycle_forward = needles::cycle_forward(),
        cycle_phi0 = needles::cycle_phi0(),
        law_forward = needles::law_forward(),
        // the needle curve over the travel, the piercing load and the needles' mass (eq. 1)
        @with crate::needle_variables { law_and_loads(stage::LOADS) },
        // ---- further loads (eq. 1) and friction
        load_Kd = Var::parameter("load.Kd", 1.0, "", "Dynamic factor K_d on the bar's inertia force, eq. (1) (assumption)").min(0.0).feeds(stage::LOADS),
        load_F = Var::parameter("load.F", 0.0, "N", "Further friction load on the bar against its rise, eq. (1) (assumption)").feeds(stage::LOADS),
        load_P_spring = Var::parameter("load.P_spring", 0.0, "N", "Spring load on the bar against its rise, eq. (1) (assumption)").feeds(stage::LOADS),
        guide_mu = needles::guide_mu(stage::LOADS),
        joint_f = needles::joint_f(stage::LOADS),
        joint_r = needles::joint_r(stage::LOADS),
        // ---- cam and roller
        cam_closure = Var::enum_parameter("cam.closure", &Closure::FMI, "groove", "groove: either flank pushes; spring: the roller is held on the raising flank and lifts off where the cam would have to pull").feeds(stage::LOADS),
        roller_r = Var::parameter("roller.r", 0.015, "m", "Cam roller radius r_r (assumption)").min(0.0),
        roller_b = Var::parameter("roller.b", 0.015, "m", "Cam roller contact length B (assumption)").min(0.0).feeds(stage::HERTZ),
        cam_E = crate::mechanisms::cam_e(stage::HERTZ),
        roller_E = crate::mechanisms::roller_e(stage::HERTZ),
        cam_J = Var::parameter("cam.J", 0.0, "kg.m2", "Moment of inertia of the cams on the shaft (assumption)").min(0.0).feeds(stage::LOADS),
        // ---- calculated parameters
        kmk_L = Var::calculated("kmk.L", "m", "Rocker arm O2K, L = beta*l_k").needs(stage::SYNTHESIS),
        kmk_psi_low = Var::calculated("kmk.psi_low", "rad", "Rocker angle psi1 with the needles lowest").needs(stage::SYNTHESIS),
        kmk_psi_high = Var::calculated("kmk.psi_high", "rad", "Rocker angle psi1 with the needles highest").needs(stage::SYNTHESIS),
        cam_r0 = Var::calculated("cam.r0", "m", "Radius |O1K| of the pitch curve with the needles lowest").needs(stage::SYNTHESIS),
        perforators_stroke = Var::calculated("perforators.stroke", "m", "Needle stroke S (the Perforators' stroke)").needs(stage::SYNTHESIS),
        // ---- outputs
        perforators_s = Var::output("perforators.s", "m", "Needle displacement s from the lowest position, along the bar's guide").depends(ON_PHI),
        perforators_v = Var::output("perforators.v", "m/s", "Needle velocity").depends(ON_PHI_W),
        perforators_a = Var::output("perforators.a", "m/s2", "Needle acceleration").depends(ON_ALL),
        rocker_psi = Var::output("rocker.psi", "rad", "Rocker angle psi1 from the centre line O2 -> O1, counter-clockwise").depends(ON_PHI),
        rocker_w = Var::output("rocker.w", "rad/s", "Rocker angular velocity").depends(ON_PHI_W),
        rocker_a = Var::output("rocker.a", "rad/s2", "Rocker angular acceleration").depends(ON_ALL),
        lever3_theta = Var::output("lever3.theta", "rad", "Direction theta_C of the arm O3C from +x").depends(ON_PHI),
        rod_alpha = Var::output("rod.alpha", "rad", "alpha_sh: the rod CD against the bar's guide (pressure angle of the rocker-slider)").depends(ON_PHI),
        fb_mu = Var::output("fb.mu", "rad", "Transmission angle mu of the coupler AB on the rocker O3B (as asin |e_AB x e_O3B|, 90 deg best)").depends(ON_PHI),
        fb_delta_psi = Var::output("fb.delta_psi", "rad", "delta - psi: the coupler AB against the crank O2A (as asin |e_O2A x e_AB|; 0: crank and coupler in line)").depends(ON_PHI),
        cam_theta = Var::output("cam.theta", "rad", "Pressure angle alpha of the cam on the roller; < 0 while the rocker turns with the cam").depends(ON_PHI),
        cam_rho = Var::output("cam.rho", "m", "Curvature radius rho_p of the cam's pitch curve, + convex").depends(ON_PHI),
        load_Q = Var::output("load.Q", "N", "Load Q_b one branch carries along the guide against the rise, eq. (1) over legacy.branches (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        pierce_Q_out = Var::output("pierce.Q_T", "N", "Piercing load on the needles while they rise (kinetostatic level)").depends(ON_PHI_W).needs(stage::FORCES),
        perforators_F_inertia = Var::output("perforators.F_inertia", "N", "Inertia force of the bar along its guide, -load.Kd*perf.m*a (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        rod_F = Var::output("rod.F", "N", "Force P_sh1 in the rod CD, eq. (2) (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        lever3_P_C = Var::output("lever3.P_C", "N", "Force at C normal to O3C, eq. (3) (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        lever3_P_B = Var::output("lever3.P_B", "N", "Force at B normal to O3B, eq. (4) (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        fb_F = Var::output("fb.F", "N", "Force P_sh2 along the coupler AB, eq. (5) (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        rocker_P_A = Var::output("rocker.P_A", "N", "Force at A normal to O2A, eq. (6) (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        roller_F = Var::output("roller.F", "N", "Cam-roller force P_kr of one branch, eq. (7): > 0 the cam pushes on the flank that raises the needles (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        roller_sigma_H = Var::output("roller.sigma_H", "Pa", "Hertz stress cam - roller on the loaded flank, paper 002 eq. 8 (kinetostatic level)").depends(ON_ALL).needs(stage::HERTZ),
        cam_rho_red = Var::output("cam.rho_red", "m", "Reduced curvature radius of the contact on the loaded flank, 1/rho = 1/roller.r + 1/rho_flank (kinetostatic level)").depends(ON_ALL).needs(stage::HERTZ),
        cam_flank = Var::int_output("cam.flank", "Loaded flank: +1 the one that raises the needles, -1 the other (a groove; kinetostatic level)").depends(ON_ALL).needs(stage::FORCES).event(),
        roller_lost_contact = Var::bool_output("roller.lost_contact", "True with a spring-closed cam if it would have to pull the roller now or did during the last communication step, the shaft's path over it sampled at most 0.25 deg apart (kinetostatic level)").depends(ON_ALL).needs(stage::WATCH),
        roller_F_margin = Var::output("roller.F_margin", "N", "Smallest cam force over the last completed shaft turn (during the first turn: so far, and now), along the shaft's path over each communication step sampled at most 0.25 deg apart; a groove: of |roller.F|, the loaded flank's (kinetostatic level)").depends(ON_ALL).needs(stage::WATCH),
    }
}

/// Where the legacy drive's cam force is watched ([`ContactWatch`]): the force of one branch;
/// with a groove the loaded flank's, which never pulls.
impl WatchedContact for Drive {
    fn contact_force(&self, phi: f64, w: f64, a: f64) -> f64 {
        Drive::contact_force(self, phi, w, a)
    }
    fn turn_start(&self) -> f64 {
        self.p.needles.table.phi0
    }
    fn liftoff_report(&self, g: &TurnDigest<4>) -> String {
        let [pull, phi, t, w] = g.worst;
        format!(
            "roller lifts off the cam {} in the shaft turn {}: worst at shaft angle {:.2} deg ({:.2} deg into the turn) at t = {t:.6} s, {:.1} rpm, where the cam would have to pull with {pull:.2} N; a spring-closed cam needs a spring load (load.P_spring) that holds the roller on, or a groove (cam.closure)",
            times(g.count),
            g.turn,
            phi.to_degrees(),
            wrap_angle(phi - self.turn_start()).to_degrees(),
            w * 30.0 / std::f64::consts::PI,
        )
    }
}

/// The legacy needle drive of paper 002 as an FMU model.
pub struct LegacyNeedleDrive {
    drive: Drive,
    state: ContactWatch,
}

impl LegacyNeedleDrive {
    /// The physics parameters from the variables.
    pub fn params(v: &Values<V>) -> Params {
        let table = TableParams {
            forward: v[V::cycle_forward],
            phi0: v[V::cycle_phi0],
            law_forward: motion_law(v.int(V::law_forward)),
            kind: Kind::Translating,
            ..TableParams::default()
        };
        let needles = needles::params(v, table);
        Params {
            l_k: v[V::kmk_lk],
            beta: v[V::kmk_beta],
            theta12: v[V::kmk_theta],
            kappa: v[V::kmk_kappa],
            r: v[V::fb_R],
            c: v[V::fb_c],
            b: v[V::fb_b],
            o3: [v[V::fb_O3x], v[V::fb_O3y]],
            chi: v[V::kpm_chi],
            r_k: v[V::kpm_Rk],
            l_rod: v[V::kpm_l],
            bar_dir: v[V::bar_dir],
            d0: [v[V::bar_D0x], v[V::bar_D0y]],
            fb_branch: f64::from(v.int(V::fb_branch)),
            kpm_branch: f64::from(v.int(V::kpm_branch)),
            n: f64::from(v.int(V::legacy_branches)),
            k_d: v[V::load_Kd],
            load_f: v[V::load_F],
            p_spring: v[V::load_P_spring],
            closure: Closure::from_item(v.int(V::cam_closure)).unwrap_or(Closure::Groove),
            roller: Roller::new(v[V::roller_r], v[V::roller_b], v[V::cam_E], v[V::roller_E]),
            cam_j: v[V::cam_J],
            timing: Timing::from_item(v.int(V::needle_timing)).unwrap_or(Timing::Perforators),
            phi_start: v[V::needle_phi_start],
            phi_rise: v[V::needle_Phi_rise],
            phi_top: v[V::needle_Phi_top],
            phi_fall: v[V::needle_Phi_fall],
            law_rise: motion_law(v.int(V::needle_law_rise)),
            law_fall: motion_law(v.int(V::needle_law_fall)),
            needles,
        }
    }

    /// The physics of this instance.
    pub fn drive(&self) -> &Drive {
        &self.drive
    }

    /// Does the kinetostatic level watch the cam force over the steps ([`ContactWatch`])?
    fn watching(&self, v: &Values<V>) -> bool {
        shaft::fidelity(v) == Fidelity::Kinetostatic && v.wants(stage::WATCH)
    }
}

/// The outputs of the kinetostatic force chain (eqs. 1-8) with their values in `f`: put at the
/// kinetostatic level, held (with `roller.F_margin`) at the kinematic level.
fn force_outputs<T: Scalar>(f: &Forces<T>) -> [(V, T); 11] {
    [
        (V::load_Q, f.q_b),
        (V::pierce_Q_out, f.q_t),
        (V::perforators_F_inertia, f.f_inertia),
        (V::rod_F, f.p_sh1),
        (V::lever3_P_C, f.p_c),
        (V::lever3_P_B, f.p_b),
        (V::fb_F, f.p_sh2),
        (V::rocker_P_A, f.p_a),
        (V::roller_F, f.p_kr),
        (V::roller_sigma_H, f.sigma_h),
        (V::cam_rho_red, f.rho_red),
    ]
}

/// The chain's positions and rates of a [`Kinematics`].
fn write_kinematics<T: Scalar>(k: &Kinematics<T>, put: &mut impl FnMut(V, T)) {
    put(V::perforators_s, k.s);
    put(V::perforators_v, k.v);
    put(V::perforators_a, k.a);
    put(V::rocker_psi, k.psi1);
    put(V::rocker_w, k.psi1_w);
    put(V::rocker_a, k.psi1_a);
    put(V::lever3_theta, k.theta_c);
    put(V::rod_alpha, min_of(k.cos_alpha_sh, 1.0).acos());
    put(V::fb_mu, min_of(k.sin_mu, 1.0).asin());
    put(V::fb_delta_psi, min_of(k.sin_delta_psi, 1.0).asin());
    put(V::cam_theta, k.alpha);
    put(V::cam_rho, k.rho_p);
}

impl LegacyNeedleDrive {
    /// Does the kinetostatic force chain run (the loads), and with the Hertz stress?
    fn loads(v: &Values<V>) -> (bool, bool) {
        (
            shaft::fidelity(v) == Fidelity::Kinetostatic && v.wants(stage::LOADS),
            v.wants(stage::HERTZ),
        )
    }

    /// Every continuous Real output at the shaft state `st`, as `put(variable, value)`: the one
    /// source of the outputs ([`Model::evaluate`], `f64`) and of their exact partial derivatives
    /// ([`Model::partials`], dual numbers). At the kinetostatic level also the forces, which
    /// it returns (the Integer and Boolean outputs are [`Model::evaluate`]'s); at the kinematic
    /// level (`loads` false: [`LegacyNeedleDrive::loads`]) [`force_outputs`] and `roller.F_margin` are not put (held).
    fn outputs<T: Scalar>(
        &self,
        (loads, hertz): (bool, bool),
        st: &ShaftState<T>,
        mut put: impl FnMut(V, T),
    ) -> Option<Forces<T>> {
        let d = &self.drive;
        let k = d.kinematics(st.phi, st.w, st.a);
        write_kinematics(&k, &mut put);
        let forces = if loads {
            let f = d.forces(&k, st.a, hertz);
            for (var, x) in force_outputs(&f) {
                put(var, x);
            }
            put(
                V::roller_F_margin,
                self.state.margin(d.contact_force(st.phi, st.w, st.a)),
            );
            Some(f)
        } else {
            None
        };
        shaft::rigid_torque(
            st,
            forces.map(|f| f.tau),
            |a| d.forces(&d.kinematics(st.phi, st.w, a), a, false).tau,
            &mut put,
        );
        forces
    }
}

impl Model for LegacyNeedleDrive {
    type Var = V;
    const IDENTIFIER: &'static str = "LegacyNeedleDrive";
    const DESCRIPTION: &'static str = "Legacy three-contour needle drive of a thread-sewing automat: cam, rocker, four-bar and rocker-slider to the needle bar (paper 002)";
    const EXPERIMENT: Experiment = Experiment::until(1.2, 1e-3);
    const STAGES: &'static [Stage] = STAGES;

    fn prepare(v: &Values<V>) -> Result<Self, ParamError> {
        shaft::require_level(v, &[Fidelity::Kinematic, Fidelity::Kinetostatic]).map_err(|e| {
            ParamError {
                condition: "LegacyNeedleDrive has the kinematic and kinetostatic levels only: paper 002 gives no compliance of its links for an elastodynamic level".into(),
                ..e
            }
        })?;
        Ok(LegacyNeedleDrive {
            drive: Self::params(v).drive()?,
            state: ContactWatch::default(),
        })
    }

    fn evaluate(&mut self, v: &mut Values<V>, time: f64, _log: &mut dyn Log) {
        let d = &self.drive;
        if v.wants(stage::SYNTHESIS) {
            v[V::kmk_L] = d.l;
            v[V::kmk_psi_low] = d.psi_low;
            v[V::kmk_psi_high] = d.psi_high;
            v[V::cam_r0] = d.r0;
            v[V::perforators_stroke] = d.stroke;
        }
        let st = shaft::state(v, time);
        let forces = self.outputs(Self::loads(v), &st, |var, x| v[var] = x);
        match forces {
            Some(f) => {
                v[V::cam_flank] = f64::from(f.flank);
                v.set_flag(
                    V::roller_lost_contact,
                    self.state.lost_step || f.lost_contact,
                );
            }
            None => v.set_flag(V::roller_lost_contact, false),
        }
    }

    const PARTIALS: bool = true;

    /// [`LegacyNeedleDrive::outputs`] on dual numbers; the knowns: `shaft.phi`, `shaft.w`,
    /// `shaft.a`. Held (the derivative 0): the forces at the kinematic level.
    fn partials(&mut self, at: &Seeded<V>, time: f64, put: Put<V>) -> Result<(), String> {
        let v = at.values();
        let st = at.shaft(time);
        if self.outputs(Self::loads(v), &st, &mut *put).is_none() {
            let held = force_outputs(&Forces::<f64>::default()).map(|(var, _)| var);
            put_zero(put, held.into_iter().chain([V::roller_F_margin]));
        }
        Ok(())
    }

    /// The lift-offs of the unfinished turn are reported.
    fn finish(&mut self, _v: &Values<V>, log: &mut dyn Log) {
        let drive = &self.drive;
        self.state
            .liftoff
            .flush(log, &|g: &TurnDigest<4>| drive.liftoff_report(g));
    }
}

/// Co-Simulation only: the watch of the cam force over each step is its memory.
impl Dynamics<V> for LegacyNeedleDrive {
    fn do_step(&mut self, v: &mut Values<V>, time: f64, h: f64, log: &mut dyn Log) -> Outcome {
        if self.watching(v) {
            self.state
                .watch(&self.drive, shaft::state(v, time), time, h, log);
        }
        Ok(())
    }

    fn save_state(&self) -> Vec<f64> {
        self.state.save()
    }

    fn restore_state(&mut self, state: &[f64]) -> Result<(), String> {
        self.state = ContactWatch::restore(state, "LegacyNeedleDrive")?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::partials::check;

    /// The exact partial derivatives against central differences of `evaluate` at both levels,
    /// both timings, a groove and a spring-closed cam, zero and large shaft accelerations, a
    /// shaft moved on from the inputs' instant and the constant-speed drive (tests/partials.rs
    /// checks the default FMU over the C ABI).
    #[test]
    fn partials_equal_central_differences() {
        for (level, timing, closure, mode, phi, w, a, time) in [
            (2.0, 1.0, 1.0, 1.0, 1.3, 10.0, 0.0, 0.0),
            (2.0, 1.0, 1.0, 1.0, 1.3, 10.0, 3.0, 0.0),
            (2.0, 2.0, 2.0, 1.0, 1.2, 9.0, 0.4, 0.0),
            (2.0, 1.0, 1.0, 1.0, 1.4, 11.0, -2.0, 0.01),
            (1.0, 1.0, 1.0, 1.0, 1.3, 10.0, 0.5, 0.0),
            (2.0, 1.0, 1.0, 2.0, 1.3, 10.0, 0.5, 0.12),
        ] {
            let mut v = Values::<V>::start();
            v[V::model_fidelity] = level;
            v[V::needle_timing] = timing;
            v[V::cam_closure] = closure;
            v[V::drive_mode] = mode;
            let mut m = LegacyNeedleDrive::prepare(&v).unwrap();
            check::set_shaft(&mut v, phi, w, a);
            check::inputs_and_states(
                &mut m,
                &v,
                time,
                &[],
                false,
                check::relative_step,
                1e-14,
                &format!("level {level} timing {timing} closure {closure} mode {mode} a {a}"),
            );
        }
    }
}
