//! The legacy needle drive against the Perforators (the new drive) at equal needle motion: what
//! a designer compares over one shaft turn at constant speed, kinetostatic level.

use super::physics::Drive;
use crate::mechanisms::perforators::physics::Drive as NewDrive;
use std::f64::consts::TAU;

/// One drive over a turn: the traces (shaft angle in degrees) and their peaks.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Turn {
    /// `perforators.s` (m), `roller.F` (N, one cam or ramp), `roller.sigma_H` (Pa), `shaft.tau`
    /// (N·m), each `(phi in deg, value)`.
    pub s: Vec<(f64, f64)>,
    pub roller_f: Vec<(f64, f64)>,
    pub sigma_h: Vec<(f64, f64)>,
    pub tau: Vec<(f64, f64)>,
}

impl Turn {
    /// The largest magnitude of a trace.
    pub fn peak(trace: &[(f64, f64)]) -> f64 {
        trace.iter().map(|p| p.1.abs()).fold(0.0, f64::max)
    }
    /// The RMS of a trace sampled evenly over the turn (the last sample, 360°, left out).
    pub fn rms(trace: &[(f64, f64)]) -> f64 {
        let n = trace.len().saturating_sub(1).max(1);
        (trace[..n].iter().map(|p| p.1 * p.1).sum::<f64>() / n as f64).sqrt()
    }
    /// The mean of a trace over the turn (the shaft torque's: the mean power over ω).
    pub fn mean(trace: &[(f64, f64)]) -> f64 {
        let n = trace.len().saturating_sub(1).max(1);
        trace[..n].iter().map(|p| p.1).sum::<f64>() / n as f64
    }
}

/// `samples` + 1 points of a turn at speed `w` (rad/s), for the legacy drive.
pub fn legacy_turn(d: &Drive, w: f64, samples: usize) -> Turn {
    turn(samples, |phi| {
        let k = d.kinematics(phi, w, 0.0);
        let f = d.forces(&k, 0.0, true);
        [k.s, f.p_kr, f.sigma_h, f.tau]
    })
}

/// The same for the Perforators.
pub fn new_turn(d: &NewDrive, w: f64, samples: usize) -> Turn {
    turn(samples, |phi| {
        let k = d.kinematics(phi, w, 0.0);
        let f = d.forces(&k);
        [k.s, f.roller_f, f.sigma_h, f.tau]
    })
}

fn turn(samples: usize, at: impl Fn(f64) -> [f64; 4]) -> Turn {
    let mut t = Turn::default();
    for k in 0..=samples {
        let phi = TAU * k as f64 / samples as f64;
        let [s, f, sigma, tau] = at(phi);
        let deg = phi.to_degrees();
        t.s.push((deg, s));
        t.roller_f.push((deg, f));
        t.sigma_h.push((deg, sigma));
        t.tau.push((deg, tau));
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanisms::legacy_needle_drive::physics::{Params, Timing};
    use crate::mechanisms::perforators::physics::Params as NewParams;

    #[test]
    fn equal_needle_motion_on_the_forward_travel_and_energy_per_turn() {
        let w = 100.0 * TAU / 60.0;
        let legacy = Params {
            timing: Timing::Perforators,
            ..Params::default()
        }
        .drive()
        .unwrap();
        let new = NewParams::default().drive().unwrap();
        let (a, b) = (legacy_turn(&legacy, w, 1440), new_turn(&new, w, 1440));
        // the first 82 deg: the table's forward travel, equal needle motion
        for (p, q) in a.s.iter().zip(&b.s).take_while(|p| p.0.0 < 82.0) {
            assert!((p.1 - q.1).abs() <= 1e-12, "{p:?} {q:?}");
        }
        // both drives do work on the needles over a turn (piercing, friction): mean torque > 0
        assert!(Turn::mean(&a.tau) > 0.0 && Turn::mean(&b.tau) > 0.0);
        assert!(Turn::peak(&a.roller_f) > 0.0 && Turn::rms(&a.tau) > 0.0);
    }
}
