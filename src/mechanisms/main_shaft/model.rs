//! The MainShaft FMU: its variables, declared once, and the glue from them to
//! [`super::physics`]. It drives the shaft the mechanism FMUs are driven by: `shaft.phi`,
//! `shaft.w`, `shaft.a` are its outputs, the load its inputs.

use super::physics::{Load, Motor, Params};
use crate::model::partials::{Put, Scalar, Seeded};
use crate::model::shaft::Terminal;
use crate::model::{Dynamics, Experiment, Log, Model, Outcome, ParamError, Values};
use crate::solver::{Integrator, Memory, Method, OdeSystem, Settings};
use std::f64::consts::PI;

const RPM: f64 = PI / 30.0;

crate::model_variables! {
    pub enum V (standalone) {
        // ---- outputs: the shaft (states phi and w)
        shaft_phi = Var::output("shaft.phi", "rad", "Main-shaft angle (state): connect to the mechanisms' shaft.phi").depends(&[]),
        shaft_w = Var::output("shaft.w", "rad/s", "Main-shaft speed (state): connect to the mechanisms' shaft.w").depends(&[]).derivative_of(V::shaft_phi as u32),
        shaft_a = Var::output("shaft.a", "rad/s2", "Main-shaft acceleration, solved with the loads' reduced inertia: (fly.J + gear.i^2*motor.J + sum load*.J_red)*shaft.a = gear.i*motor.tau - bearing.tau - load.tau - sum load*.tau0; connect to the mechanisms' shaft.a").depends(LOADS).derivative_of(V::shaft_w as u32),
        shaft_tau_load = Var::output("shaft.tau_load", "N.m", "Torque of the loads at the main shaft, load.tau + sum (load*.tau0 + load*.J_red*shaft.a)").depends(LOADS),
        motor_tau = Var::output("motor.tau", "N.m", "Motor torque at the motor shaft (Kloss's formula)").depends(&[]),
        motor_w = Var::output("motor.w", "rad/s", "Motor speed gear.i*shaft.w").depends(&[]),
        motor_s = Var::output("motor.s", "", "Motor slip (motor.n_sync - motor.w)/motor.n_sync").depends(&[]),
        motor_P = Var::output("motor.P", "W", "Mechanical power of the motor motor.tau*motor.w").depends(&[]),
        bearing_tau = Var::output("bearing.tau", "N.m", "Friction torque of the main shaft's bearings").depends(&[]),
        @with crate::chain_variables { steps },
        // ---- inputs: the loads
        load_tau = Var::input("load.tau", 0.0, "N.m", "Load torque given as a whole (plain torque coupling: a mechanism's shaft.tau; its inertia then acts one communication step late)"),
        load1_J_red = Var::input("load1.J_red", 0.0, "kg.m2", "Reduced moment of inertia of mechanism 1 (its shaft.J_red; 0 if none)"),
        load1_tau0 = Var::input("load1.tau0", 0.0, "N.m", "Torque of mechanism 1 at zero shaft acceleration (its shaft.tau0; 0 if none)"),
        load2_J_red = Var::input("load2.J_red", 0.0, "kg.m2", "Reduced moment of inertia of mechanism 2 (its shaft.J_red; 0 if none)"),
        load2_tau0 = Var::input("load2.tau0", 0.0, "N.m", "Torque of mechanism 2 at zero shaft acceleration (its shaft.tau0; 0 if none)"),
        load3_J_red = Var::input("load3.J_red", 0.0, "kg.m2", "Reduced moment of inertia of mechanism 3 (its shaft.J_red; 0 if none)"),
        load3_tau0 = Var::input("load3.tau0", 0.0, "N.m", "Torque of mechanism 3 at zero shaft acceleration (its shaft.tau0; 0 if none)"),
        // ---- parameters (assumptions: the papers give no drive data)
        motor_P_rated = Var::parameter("motor.P_rated", 1100.0, "W", "Rated power of the induction motor (assumption: 1.1 kW, four-pole, 50 Hz)").min(0.0),
        motor_n_rated = Var::parameter("motor.n_rated", 1400.0 * RPM, "rad/s", "Rated speed of the motor (assumption: 1400 rpm)").min(0.0),
        motor_s_rated = Var::parameter("motor.s_rated", 1.0 / 15.0, "", "Rated slip of the motor; synchronous speed motor.n_rated/(1 - motor.s_rated) (assumption: 1/15, 1500 rpm synchronous)").min(0.0).max(1.0),
        motor_lambda = Var::parameter("motor.lambda", 2.2, "", "Breakdown-torque ratio M_k/M_n of the motor (assumption: 2.2, catalogue value)").min(1.0),
        motor_J = Var::parameter("motor.J", 0.0035, "kg.m2", "Rotor moment of inertia (assumption: catalogue value of a 1.1 kW motor)").min(0.0),
        gear_i = Var::parameter("gear.i", 15.0, "", "Gear ratio motor speed / main-shaft speed, lossless (assumption: 15, 100 rpm synchronous at the main shaft, the thread-sewing machine)").min(0.0),
        fly_J = Var::parameter("fly.J", 2.0, "kg.m2", "Flywheel and every rotating part on the main shaft outside the mechanism FMUs (assumption)").min(0.0),
        bearing_tau_c = Var::parameter("bearing.tau_c", 2.0, "N.m", "Coulomb friction torque of the main shaft's bearings and gear, smoothed as tau_c*tanh(w/w_s) (assumption)").min(0.0),
        bearing_c = Var::parameter("bearing.c", 0.05, "N.m.s/rad", "Viscous friction coefficient of the main shaft's bearings and gear (assumption)").min(0.0),
        bearing_w_s = Var::parameter("bearing.w_s", 0.01, "rad/s", "Speed over which the Coulomb friction is smoothed (numerical, assumption)").min(0.0),
        init_phi = Var::parameter("init.phi", 0.0, "rad", "Main-shaft angle at the start time"),
        init_w = Var::parameter("init.w", 0.0, "rad/s", "Main-shaft speed at the start time (0: start-up from rest)"),
        @with crate::chain_variables { solver() },
        // ---- calculated parameters
        motor_n_sync = Var::calculated("motor.n_sync", "rad/s", "Synchronous speed of the motor motor.n_rated/(1 - motor.s_rated)"),
        motor_tau_rated = Var::calculated("motor.tau_rated", "N.m", "Rated torque motor.P_rated/motor.n_rated"),
        motor_tau_break = Var::calculated("motor.tau_break", "N.m", "Breakdown torque motor.lambda*motor.tau_rated"),
        motor_s_break = Var::calculated("motor.s_break", "", "Breakdown slip s_n*(lambda + sqrt(lambda^2 - 1)) (Kloss's formula at the rated point)"),
        shaft_n_sync = Var::calculated("shaft.n_sync", "rad/s", "Synchronous speed at the main shaft motor.n_sync/gear.i"),
        drive_J = Var::calculated("drive.J", "kg.m2", "Moment of inertia of the drive at the main shaft fly.J + gear.i^2*motor.J"),
    }
}

/// The inputs `shaft.a` and `shaft.tau_load` depend on.
const LOADS: &[u32] = &[
    V::load_tau as u32,
    V::load1_J_red as u32,
    V::load1_tau0 as u32,
    V::load2_J_red as u32,
    V::load2_tau0 as u32,
    V::load3_J_red as u32,
    V::load3_tau0 as u32,
];

/// The main-shaft drive as an FMU model.
pub struct MainShaft {
    params: Params,
    integ: Integrator,
    /// `[φ, ω]`.
    y: [f64; 2],
}

/// The shaft's equation of motion under a load held over a step.
struct ShaftOde<'a> {
    p: &'a Params,
    load: Load,
}

impl OdeSystem for ShaftOde<'_> {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = self.p.point(y[1], &self.load).map_or(f64::NAN, |pt| pt.eps);
    }
}

impl MainShaft {
    /// The physics parameters from the variables.
    pub fn params(v: &Values<V>) -> Params {
        Params {
            motor: Motor {
                p_rated: v[V::motor_P_rated],
                w_rated: v[V::motor_n_rated],
                s_rated: v[V::motor_s_rated],
                lambda: v[V::motor_lambda],
                j: v[V::motor_J],
            },
            gear_i: v[V::gear_i],
            fly_j: v[V::fly_J],
            bearing_tau_c: v[V::bearing_tau_c],
            bearing_c: v[V::bearing_c],
            bearing_w_s: v[V::bearing_w_s],
        }
    }

    /// The load inputs.
    pub fn load(v: &Values<V>) -> Load {
        Self::load_of(|var| v[var])
    }

    /// The load from the inputs as `get` reads them (plain, or seeded for partial derivatives).
    fn load_of<T: Scalar>(get: impl Fn(V) -> T) -> Load<T> {
        Load {
            tau: get(V::load_tau),
            tau0: get(V::load1_tau0) + get(V::load2_tau0) + get(V::load3_tau0),
            j_red: get(V::load1_J_red) + get(V::load2_J_red) + get(V::load3_J_red),
        }
    }

    /// Every output at the state `y = [φ, ω]` under `load`, as `put(variable, value)`: the one
    /// source of the outputs ([`Model::evaluate`], `f64`) and of their exact partial derivatives
    /// ([`Model::partials`], dual numbers). `shaft.w` and `shaft.a` are also the state
    /// derivatives of Model Exchange.
    fn outputs<T: Scalar>(p: &Params, y: [T; 2], load: &Load<T>, mut put: impl FnMut(V, T)) {
        let [phi, w] = y;
        let pt = p.solve(w, load);
        put(V::shaft_phi, phi);
        put(V::shaft_w, w);
        put(V::shaft_a, pt.eps);
        put(V::shaft_tau_load, pt.load_tau);
        put(V::motor_tau, pt.motor_tau);
        put(V::motor_w, pt.motor_w);
        put(V::motor_s, pt.slip);
        put(V::motor_P, pt.motor_tau * pt.motor_w);
        put(V::bearing_tau, pt.friction);
    }

    /// `[φ, ω]` now.
    pub fn state(&self) -> [f64; 2] {
        self.y
    }
}

/// A terminal of the main shaft for a mechanism's torque split (its `shaft_reduced`).
macro_rules! load_terminal {
    ($name:literal, $tau0:literal, $j_red:literal) => {
        Terminal {
            name: $name,
            description: "The main shaft driving a mechanism with its torque split: angle, speed and acceleration out, the mechanism's tau0 and J_red in (connect to a mechanism's shaft_reduced)",
            members: &[
                ("phi", "shaft.phi"),
                ("w", "shaft.w"),
                ("a", "shaft.a"),
                ("tau0", $tau0),
                ("J_red", $j_red),
            ],
        }
    };
}

impl Model for MainShaft {
    type Var = V;
    const IDENTIFIER: &'static str = "MainShaft";
    const DESCRIPTION: &'static str = "Main-shaft drive of a bookbinding machine: induction motor (Kloss's formula), gear, flywheel and bearing friction, loaded by the mechanisms' reduced inertia and torque";
    const EXPERIMENT: Experiment = Experiment::until(5.0, 1e-3);
    const TERMINALS: &'static [Terminal] = &[
        Terminal {
            name: "load",
            description: "The main shaft as a rotational flange driving a mechanism: angle, speed and acceleration out, the mechanism's torque in (connect to a mechanism's shaft)",
            members: &[
                ("phi", "shaft.phi"),
                ("w", "shaft.w"),
                ("a", "shaft.a"),
                ("tau", "load.tau"),
            ],
        },
        load_terminal!("load1", "load1.tau0", "load1.J_red"),
        load_terminal!("load2", "load2.tau0", "load2.J_red"),
        load_terminal!("load3", "load3.tau0", "load3.J_red"),
    ];

    fn prepare(v: &Values<V>) -> Result<Self, ParamError> {
        let params = Self::params(v);
        params.validate()?;
        let settings = Settings {
            method: Method::from_value(v.int(V::solver_method)),
            rtol: v[V::solver_rtol],
            atol: v[V::solver_atol],
            max_step: v[V::solver_max_step],
            ..Settings::default()
        };
        Ok(MainShaft {
            params,
            integ: Integrator::new(settings),
            y: [v[V::init_phi], v[V::init_w]],
        })
    }

    fn calculated_parameters(&self, v: &mut Values<V>) {
        let p = &self.params;
        v[V::motor_n_sync] = p.motor.w_sync();
        v[V::motor_tau_rated] = p.motor.tau_rated();
        v[V::motor_tau_break] = p.motor.tau_break();
        v[V::motor_s_break] = p.motor.s_break();
        v[V::shaft_n_sync] = p.w_sync_shaft();
        v[V::drive_J] = p.j_drive();
    }

    fn evaluate(&mut self, v: &mut Values<V>, _time: f64, _log: &mut dyn Log) {
        let load = Self::load(v);
        Self::outputs(&self.params, self.y, &load, |var, x| v[var] = x);
        v[V::solver_steps] = self.integ.mem.stats.steps as f64;
    }

    const PARTIALS: bool = true;

    fn partials(&mut self, at: &Seeded<V>, _time: f64, put: Put<V>) -> Result<(), String> {
        let y = at.own_all([V::shaft_phi, V::shaft_w], self.y);
        Self::outputs(&self.params, y, &Self::load_of(|v| at.get(v)), put);
        Ok(())
    }
}

impl Dynamics<V> for MainShaft {
    fn do_step(&mut self, v: &mut Values<V>, time: f64, h: f64, _log: &mut dyn Log) -> Outcome {
        let ode = ShaftOde {
            p: &self.params,
            load: Self::load(v),
        };
        // a non-positive total inertia, named with the inputs that make it
        ode.p.point(self.y[1], &ode.load)?;
        let before = self.integ.clone();
        let mut y = self.y;
        match self.integ.integrate(&ode, time, time + h, &mut y) {
            Ok(_) => {
                self.y = y;
                Ok(())
            }
            Err(why) => {
                self.integ = before;
                Err(why)
            }
        }
    }

    const STATES: usize = 2;
    // standalone: its inputs (load torques and inertias) are held over a step, and it declares
    // no canInterpolateInputs (the default for a standalone model)

    fn me_states(&mut self, _v: &Values<V>, _time: f64, x: &mut [f64]) {
        x.copy_from_slice(&self.y);
    }

    fn me_set_states(&mut self, _v: &Values<V>, _time: f64, x: &[f64]) {
        self.y.copy_from_slice(x);
    }

    fn me_derivatives(&mut self, v: &Values<V>, time: f64, dx: &mut [f64]) {
        ShaftOde {
            p: &self.params,
            load: Self::load(v),
        }
        .rhs(time, &self.y, dx);
    }

    /// The host's accepted step, counted in `solver.steps` as the own integrator's in
    /// Co-Simulation.
    fn me_completed_step(&mut self, _v: &Values<V>, _time: f64, _log: &mut dyn Log) {
        self.integ.mem.stats.steps += 1;
    }

    fn save_state(&self) -> Vec<f64> {
        let mut s = vec![self.y[0], self.y[1]];
        s.extend(self.integ.save().to_numbers());
        s
    }

    fn restore_state(&mut self, s: &[f64]) -> Result<(), String> {
        crate::model::saved::expect_len("MainShaft state", s, &[2 + Memory::LEN])?;
        if let Some(i) = (0..2).find(|&i| !s[i].is_finite()) {
            return Err(format!(
                "MainShaft state refused: {} = {} is not finite",
                crate::model::state_names::<V>()[i],
                s[i]
            ));
        }
        let integ =
            Memory::from_numbers(&s[2..]).map_err(|e| format!("MainShaft state refused: {e}"))?;
        self.y = [s[0], s[1]];
        self.integ.restore(integ);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{NoLog, VarSet, check_bounds};

    fn run(v: &mut Values<V>, m: &mut MainShaft, t_end: f64, h: f64) {
        let mut t = 0.0;
        while t < t_end - 1e-12 {
            m.do_step(v, t, h, &mut NoLog).unwrap();
            t += h;
        }
        m.evaluate(v, t, &mut NoLog);
    }

    #[test]
    fn declarations_are_valid_and_defaults_in_bounds() {
        crate::md::check(V::table()).unwrap();
        let v = Values::<V>::start();
        check_bounds(&v).unwrap();
        assert_eq!(V::shaft_phi.vr(), 0);
    }

    #[test]
    fn starts_up_from_rest_to_the_steady_speed_under_a_constant_load() {
        let mut v = Values::<V>::start();
        v[V::load1_tau0] = 30.0;
        v[V::load1_J_red] = 1.0;
        let mut m = MainShaft::prepare(&v).unwrap();
        m.calculated_parameters(&mut v);
        run(&mut v, &mut m, 8.0, 1e-2);
        let p = MainShaft::params(&v);
        let w_ss = p.steady_speed(30.0).unwrap();
        assert!(
            (v[V::shaft_w] - w_ss).abs() < 1e-6 * w_ss,
            "{} vs {w_ss}",
            v[V::shaft_w]
        );
        assert!(v[V::shaft_a].abs() < 1e-5);
        assert!(v[V::motor_s] > 0.0 && v[V::motor_s] < v[V::motor_s_rated]);
        // the shaft turned: its angle is the integral of the speed
        assert!(v[V::shaft_phi] > 0.5 * w_ss * 8.0);
    }

    #[test]
    fn model_exchange_derivatives_are_the_equation_of_motion() {
        let mut v = Values::<V>::start();
        v[V::load_tau] = 12.0;
        let mut m = MainShaft::prepare(&v).unwrap();
        m.me_set_states(&v, 0.0, &[1.0, 5.0]);
        let mut dx = [0.0; 2];
        m.me_derivatives(&v, 0.0, &mut dx);
        let p = MainShaft::params(&v);
        let expected =
            (p.gear_i * p.motor.torque(p.gear_i * 5.0) - p.friction(5.0) - 12.0) / p.j_drive();
        assert_eq!(dx[0], 5.0);
        assert!((dx[1] - expected).abs() < 1e-12 * expected.abs());
        m.evaluate(&mut v, 0.0, &mut NoLog);
        assert_eq!(v[V::shaft_a], dx[1]);
    }

    #[test]
    fn negative_total_inertia_is_refused_by_the_step() {
        let mut v = Values::<V>::start();
        v[V::load2_J_red] = -100.0;
        let mut m = MainShaft::prepare(&v).unwrap();
        let err = m.do_step(&mut v, 0.0, 1e-3, &mut NoLog).unwrap_err();
        assert!(err.contains("load*.J_red"), "{err}");
        assert_eq!(m.state(), [0.0, 0.0]);
    }

    #[test]
    fn state_round_trip() {
        let mut v = Values::<V>::start();
        let mut m = MainShaft::prepare(&v).unwrap();
        run(&mut v, &mut m, 0.5, 1e-2);
        let s = m.save_state();
        let mut m2 = MainShaft::prepare(&v).unwrap();
        m2.restore_state(&s).unwrap();
        assert_eq!(m2.state(), m.state());
        assert!(m2.restore_state(&[1.0]).is_err());
    }
}
