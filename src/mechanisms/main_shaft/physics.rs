//! The main-shaft drive of a bookbinding machine: an induction motor (Kloss's formula), a gear
//! pair to the main shaft, a flywheel and the shaft's bearings, loaded by the mechanisms on the
//! shaft. Pure math, no FFI.
//!
//! Equation of motion of the main shaft (angle φ, speed ω, acceleration ε), with the motor
//! reduced to it through the gear ratio `i = ω_motor/ω`:
//!
//! `(J_fly + i²·J_motor + Σ J_red,k)·ε = i·M(i·ω) − M_f(ω) − τ_load − Σ τ0,k`
//!
//! where each mechanism k on the shaft needs `τ_k = τ0,k + J_red,k·ε` (its torque at zero shaft
//! acceleration plus its reduced moment of inertia times the acceleration; `model.rs`,
//! `shaft::reduce`) and `τ_load` is a load torque given as a whole (the plain coupling, or an
//! external load). Moving the mechanisms' inertia to the left-hand side is what keeps the
//! co-simulation stable when their inertia is large against the flywheel's: the plain coupling
//! `J·ε_{n+1} = M − τ(ε_n)` has the loop gain `−J_red/J` whatever the step.

use crate::mechanics::{ParamError, Scalar, check_positive};

/// Induction motor data (rated values from a catalogue; every default is an assumption).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motor {
    /// Rated (output) power `P_n`, W.
    pub p_rated: f64,
    /// Rated speed `ω_n`, rad/s.
    pub w_rated: f64,
    /// Rated slip `s_n`.
    pub s_rated: f64,
    /// Breakdown-torque ratio `λ = M_k/M_n`.
    pub lambda: f64,
    /// Rotor moment of inertia, kg·m².
    pub j: f64,
}

impl Default for Motor {
    /// A 1.1 kW four-pole 50 Hz motor: 1400 rpm rated, slip 1/15 (synchronous 1500 rpm),
    /// breakdown torque 2.2 times the rated one, rotor 0.0035 kg·m² (assumption: catalogue values
    /// of that size).
    fn default() -> Self {
        Motor {
            p_rated: 1100.0,
            w_rated: 1400.0 * std::f64::consts::PI / 30.0,
            s_rated: 1.0 / 15.0,
            lambda: 2.2,
            j: 0.0035,
        }
    }
}

impl Motor {
    /// Synchronous speed `ω_0 = ω_n/(1 − s_n)` (the slip's definition `s = (ω_0 − ω)/ω_0` at the
    /// rated point), rad/s.
    pub fn w_sync(&self) -> f64 {
        self.w_rated / (1.0 - self.s_rated)
    }

    /// Rated torque `M_n = P_n/ω_n`, N·m.
    pub fn tau_rated(&self) -> f64 {
        self.p_rated / self.w_rated
    }

    /// Breakdown (pull-out) torque `M_k = λ·M_n`, N·m.
    pub fn tau_break(&self) -> f64 {
        self.lambda * self.tau_rated()
    }

    /// Breakdown slip `s_k = s_n·(λ + √(λ² − 1))`: Kloss's formula at the rated point,
    /// `M_n/M_k = 2/(s_n/s_k + s_k/s_n) = 1/λ`, solved for `s_k` (the root above `s_n`).
    pub fn s_break(&self) -> f64 {
        self.s_rated * (self.lambda + (self.lambda * self.lambda - 1.0).sqrt())
    }

    /// Slip at motor speed `w`: `s = (ω_0 − ω)/ω_0`.
    pub fn slip<T: Scalar>(&self, w: T) -> T {
        let w0 = self.w_sync();
        (T::from(w0) - w) / w0
    }

    /// Motor torque at motor speed `w`, N·m: Kloss's formula
    /// `M = 2·M_k/(s/s_k + s_k/s) = 2·M_k·s·s_k/(s² + s_k²)` (steady-state torque–speed
    /// characteristic of an induction motor with the stator resistance neglected; it holds for
    /// any slip, also generating `s < 0` and braking `s > 1`).
    pub fn torque<T: Scalar>(&self, w: T) -> T {
        let s = self.slip(w);
        let sk = self.s_break();
        T::from(2.0 * self.tau_break()) * s * sk / (s * s + sk * sk)
    }

    /// Checks the data.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_positive("motor.P_rated", self.p_rated, "must be positive")?;
        check_positive("motor.n_rated", self.w_rated, "must be positive")?;
        crate::require!(
            self.s_rated > 0.0 && self.s_rated < 1.0,
            "motor.s_rated",
            self.s_rated,
            "the rated slip must lie in (0, 1)"
        );
        crate::require!(
            self.lambda > 1.0 && self.lambda.is_finite(),
            "motor.lambda",
            self.lambda,
            "the breakdown torque must exceed the rated torque (lambda > 1)"
        );
        crate::require!(self.j >= 0.0, "motor.J", self.j, "must not be negative");
        Ok(())
    }
}

/// The drive: motor, gear, flywheel, bearings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    pub motor: Motor,
    /// Gear ratio `i = ω_motor/ω_shaft` (lossless: the gear's losses are in the bearings'
    /// friction).
    pub gear_i: f64,
    /// Flywheel (and every rotating part on the main shaft not in a mechanism FMU), kg·m².
    pub fly_j: f64,
    /// Coulomb friction torque of the main shaft's bearings, N·m.
    pub bearing_tau_c: f64,
    /// Viscous friction coefficient of the bearings, N·m·s/rad.
    pub bearing_c: f64,
    /// Speed over which the Coulomb friction is smoothed, `M_c·tanh(ω/ω_s)`, rad/s.
    pub bearing_w_s: f64,
}

impl Default for Params {
    /// The thread-sewing machine's drive (100 rpm nominal, synchronous 1500/15 = 100 rpm at the
    /// main shaft): every value an assumption.
    fn default() -> Self {
        Params {
            motor: Motor::default(),
            gear_i: 15.0,
            fly_j: 2.0,
            bearing_tau_c: 2.0,
            bearing_c: 0.05,
            bearing_w_s: 0.01,
        }
    }
}

/// The loads acting on the shaft during a step (held over it).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Load<T = f64> {
    /// A load torque given as a whole, `τ_load`, N·m.
    pub tau: T,
    /// `Σ τ0,k`, N·m.
    pub tau0: T,
    /// `Σ J_red,k`, kg·m².
    pub j_red: T,
}

/// Everything at one instant.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Point<T = f64> {
    /// Main-shaft acceleration ε, rad/s² (NaN where the total inertia is not positive).
    pub eps: T,
    /// Motor speed, rad/s.
    pub motor_w: T,
    /// Slip.
    pub slip: T,
    /// Motor torque at the motor shaft, N·m.
    pub motor_tau: T,
    /// Bearing friction torque, N·m.
    pub friction: T,
    /// The load's torque at the shaft, `τ_load + Σ τ0,k + Σ J_red,k·ε`, N·m.
    pub load_tau: T,
    /// Moment of inertia the acceleration is solved with, kg·m².
    pub j_total: T,
}

impl Params {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.motor.validate()?;
        check_positive("gear.i", self.gear_i, "must be positive")?;
        for (name, x) in [
            ("fly.J", self.fly_j),
            ("bearing.tau_c", self.bearing_tau_c),
            ("bearing.c", self.bearing_c),
        ] {
            crate::require!(x >= 0.0 && x.is_finite(), name, x, "must not be negative");
        }
        crate::require!(
            self.bearing_w_s > 0.0,
            "bearing.w_s",
            self.bearing_w_s,
            "must be positive"
        );
        crate::require!(
            self.j_drive() > 0.0,
            "fly.J",
            self.fly_j,
            "fly.J + gear.i^2*motor.J must be positive: the shaft needs some inertia"
        );
        Ok(())
    }

    /// Inertia of the drive itself at the main shaft, `J_fly + i²·J_motor`, kg·m².
    pub fn j_drive(&self) -> f64 {
        self.fly_j + self.gear_i * self.gear_i * self.motor.j
    }

    /// Synchronous speed at the main shaft, `ω_0/i`, rad/s.
    pub fn w_sync_shaft(&self) -> f64 {
        self.motor.w_sync() / self.gear_i
    }

    /// Bearing friction at shaft speed `w`: `M_c·tanh(ω/ω_s) + c·ω` (Coulomb, smoothed, and
    /// viscous), N·m.
    pub fn friction<T: Scalar>(&self, w: T) -> T {
        (w / self.bearing_w_s).tanh() * self.bearing_tau_c + w * self.bearing_c
    }

    /// The shaft's acceleration and what goes with it at shaft speed `w` under `load`.
    /// `Err` if the total inertia is not positive (a negative `load*.J_red`).
    pub fn point(&self, w: f64, load: &Load) -> Result<Point, String> {
        let j_total = self.j_drive() + load.j_red;
        if j_total.is_nan() || j_total <= 0.0 {
            return Err(format!(
                "total moment of inertia fly.J + gear.i^2*motor.J + sum of load*.J_red = {j_total} kg.m2 is not positive"
            ));
        }
        Ok(self.solve(w, load))
    }

    /// [`Params::point`] for any [`Scalar`], with a NaN acceleration (and load torque) where
    /// the total inertia is not positive.
    pub fn solve<T: Scalar>(&self, w: T, load: &Load<T>) -> Point<T> {
        let j_total = load.j_red + self.j_drive();
        let motor_w = w * self.gear_i;
        let motor_tau = self.motor.torque(motor_w);
        let friction = self.friction(w);
        let eps = if j_total.re() > 0.0 {
            (motor_tau * self.gear_i - friction - load.tau - load.tau0) / j_total
        } else {
            T::from(f64::NAN)
        };
        Point {
            eps,
            motor_w,
            slip: self.motor.slip(motor_w),
            motor_tau,
            friction,
            load_tau: load.tau + load.tau0 + load.j_red * eps,
            j_total,
        }
    }

    /// Steady speed of the shaft under a constant load torque `tau` (no acceleration):
    /// the root of `i·M(i·ω) = M_f(ω) + τ` on the stable branch (between the breakdown speed and
    /// the synchronous speed), by bisection. `None` if the load exceeds the breakdown torque.
    pub fn steady_speed(&self, tau: f64) -> Option<f64> {
        let net =
            |w: f64| self.gear_i * self.motor.torque(self.gear_i * w) - self.friction(w) - tau;
        let w_break = self.motor.w_sync() * (1.0 - self.motor.s_break()) / self.gear_i;
        let (mut lo, mut hi) = (w_break.max(0.0), self.w_sync_shaft());
        if net(lo) < 0.0 || net(hi) > 0.0 {
            return None;
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if net(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some(0.5 * (lo + hi))
    }
}

#[cfg(test)]
#[path = "physics_tests.rs"]
mod tests;
