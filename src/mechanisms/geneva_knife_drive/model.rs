//! The GenevaKnifeDrive FMU: its variables, declared once, and the glue from them to
//! [`super::physics`] (`../shared/spec/geneva-knife-drive.md`).

use super::physics::{Kinematics, Params};
use crate::model::shaft::{self, Fidelity, ON_ALL, ON_PHI, ON_PHI_W};
use crate::model::{Experiment, Log, Model, ParamError, Values};

crate::model_variables! {
    pub enum V (nominal_rpm = 30.0) {
        // ---- parameters (paper 003 where it gives them, else documented assumptions)
        geneva_Z = Var::int_parameter("geneva.Z", 4, "Number of slots of the Geneva cross Z (paper 003: 4)").min(3.0).max(36.0),
        geneva_r1 = Var::parameter("geneva.r1", 0.08, "m", "Driver radius r1: crank pin (roller) to driver axis (assumption)").min(0.0),
        gear_i = Var::int_parameter("gear.i", 4, "Crank turns per cross turn; a whole multiple of Z so the crank turns 360 deg per index (paper 003: 4)").min(1.0),
        gear_eta = Var::parameter("gear.eta", 0.98, "", "Mesh efficiency of the gear pair 3-4 (assumption)").min(0.0).max(1.0),
        crank_r = Var::parameter("crank.r", 0.07, "m", "Crank radius r2 (assumption)").min(0.0),
        rod_l = Var::parameter("rod.l", 0.35, "m", "Rod length l; paper 003: lambda2 = l/r2 = 5").min(0.0),
        knife_m = Var::parameter("knife.m", 12.0, "kg", "Mass of slider, knife housing and knife (assumption)").min(0.0),
        rod_m = Var::parameter("rod.m", 3.0, "kg", "Rod mass, half at the crank pin and half at the slider (assumption)").min(0.0),
        crank_J = Var::parameter("crank.J", 0.05, "kg.m2", "Moment of inertia of crank 5 and gear 4 (assumption)").min(0.0),
        cross_J = Var::parameter("cross.J", 0.08, "kg.m2", "Moment of inertia of cross 2 and gear 3 (assumption)").min(0.0),
        driver_J = Var::parameter("driver.J", 0.03, "kg.m2", "Moment of inertia of driver 1 (assumption)").min(0.0),
        guide_mu = Var::parameter("guide.mu", 0.1, "", "Coulomb friction coefficient of the slider guides 8 (assumption)").min(0.0),
        cut_F_max = Var::parameter("cut.F_max", 15000.0, "N", "Cutting resistance at full engagement (assumption)").min(0.0),
        cut_s_start = Var::parameter("cut.s_start", 0.070, "m", "Knife position where it meets the stack (assumption: 65 mm stack)").min(0.0),
        cut_s_full = Var::parameter("cut.s_full", 0.075, "m", "Knife position where the cutting force is full (assumption)").min(0.0),
        cut_s_end = Var::parameter("cut.s_end", 0.135, "m", "Knife position where the stack is cut through (assumption)").min(0.0),
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
        knife_dwell = Var::bool_output("knife.dwell", "True while the roller is out of the slots: cross locked, knife stopped at the top").depends(ON_PHI),
        knife_F_cut = Var::output("knife.F_cut", "N", "Cutting resistance on the knife, >= 0, only while descending through the stack (kinetostatic level; 0 at kinematic)").depends(ON_PHI_W),
        knife_F_inertia = Var::output("knife.F_inertia", "N", "Inertia force of the slider mass m_s = knife.m + rod.m/2, -m_s*a, down positive (kinetostatic level)").depends(ON_ALL),
        rod_F = Var::output("rod.F", "N", "Rod force P along the rod, positive when it pulls the knife down towards the crank (tension: with s = r2 + l - x_C the crank lies below the knife, so the spec's P*cos(nu) along +s is a pull) (kinetostatic level)").depends(ON_ALL),
        guide_N = Var::output("guide.N", "N", "Normal force of the guides on the slider, P*sin(nu) (kinetostatic level)").depends(ON_ALL),
        crank_tau = Var::output("crank.tau", "N.m", "Torque on the crank shaft (gear 4) (kinetostatic level)").depends(ON_ALL),
        cross_tau = Var::output("cross.tau", "N.m", "Torque on the cross shaft (gear 3), with mesh losses and cross inertia (kinetostatic level)").depends(ON_ALL),
        geneva_F = Var::output("geneva.F", "N", "Contact force between roller and slot flank, cross.tau/rho (kinetostatic level)").depends(ON_ALL),
    }
}

/// The Geneva-mechanism knife drive of a three-knife trimmer (paper 003) as an FMU model.
pub struct GenevaKnifeDrive {
    params: Params,
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
    const MODEL_NAME: &'static str = "GenevaKnifeDrive";
    const DESCRIPTION: &'static str = "Knife drive of a three-knife trimmer: Geneva cross, gear pair and slider-crank (paper 003)";
    const EXPERIMENT: Experiment = Experiment {
        start: 0.0,
        stop: 4.0,
        step: 1e-3,
        tolerance: None,
    };

    fn prepare(v: &Values<V>) -> Result<Self, ParamError> {
        let params = Self::params(v);
        params.validate()?;
        Ok(GenevaKnifeDrive { params })
    }

    fn evaluate(&mut self, v: &mut Values<V>, time: f64, _log: &mut dyn Log) {
        let p = &self.params;
        v[V::geneva_a] = p.a();
        v[V::geneva_lambda] = p.lambda();
        v[V::rod_lambda2] = p.lambda2();
        v[V::knife_stroke] = p.stroke();
        let s = shaft::state(v, time);
        let k = p.kinematics(s.phi, s.w, s.a);
        Self::write_kinematics(v, &k);
        let tau = if shaft::fidelity(v) == Fidelity::Kinetostatic {
            let f = p.kinetostatics(&k, s.w, s.a);
            v[V::knife_F_cut] = f.f_cut;
            v[V::knife_F_inertia] = f.f_inertia;
            v[V::rod_F] = f.rod_f;
            v[V::guide_N] = f.guide_n;
            v[V::crank_tau] = f.crank_tau;
            v[V::cross_tau] = f.cross_tau;
            v[V::geneva_F] = f.geneva_f;
            f.shaft_tau
        } else {
            0.0
        };
        shaft::set_outputs(v, tau, s.w);
    }
}
