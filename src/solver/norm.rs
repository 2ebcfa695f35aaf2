//! The error norms of the integrators (Hairer's weighted RMS norms) and what they weigh a
//! state by, taken once per step attempt.

use super::{Integrator, MAX_DIM, OdeSystem, Stepper};

/// Per state, at an attempt's start `y`: its weight in the error norms
/// ([`OdeSystem::error_weight`]) and its absolute tolerance ([`OdeSystem::abs_tol`]), asked of
/// the system once per attempt rather than in every norm; for a Radau IIA attempt also Hairer's
/// transformed tolerances ([`Integrator::radau_tolerances`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Scale {
    w: [f64; MAX_DIM],
    atol: [f64; MAX_DIM],
    pub(super) rtol_radau: f64,
    atol_radau: [f64; MAX_DIM],
}

impl Integrator {
    /// [`Scale`] at `y` for an attempt of `stepper`.
    pub(super) fn scale_at(&mut self, sys: &dyn OdeSystem, y: &[f64], stepper: Stepper) {
        for i in 0..y.len() {
            self.scale.w[i] = sys.error_weight(i);
            self.scale.atol[i] = sys.abs_tol(i, self.settings.atol, y);
        }
        if stepper == Stepper::Radau {
            let (rtol, atol) = self.radau_tolerances();
            self.scale.rtol_radau = rtol;
            for i in 0..y.len() {
                self.scale.atol_radau[i] = sys.abs_tol(i, atol, y);
            }
        }
    }

    /// The weighted RMS norm of `e` over a step from `y0` to `y1` ([`Scale`] of the attempt).
    pub(super) fn norm(&self, e: &[f64], y0: &[f64], y1: &[f64]) -> f64 {
        let rtol = self.settings.rtol;
        self.weighted_rms(e, |i| {
            self.scale.atol[i] + rtol * y0[i].abs().max(y1[i].abs())
        })
    }

    /// `√(Σ wᵢ·(eᵢ/scᵢ)² / Σ wᵢ)` with the attempt's weights, components of weight 0 left out
    /// (0 if all are): the one formula of both norms.
    fn weighted_rms(&self, e: &[f64], sc: impl Fn(usize) -> f64) -> f64 {
        let (mut s, mut m) = (0.0, 0.0);
        for (i, ei) in e.iter().enumerate() {
            let w = self.scale.w[i];
            if w != 0.0 {
                let r = ei / sc(i);
                s += w * r * r;
                m += w;
            }
        }
        if m == 0.0 { 0.0 } else { (s / m).sqrt() }
    }

    /// Hairer's tolerance transformation for Radau IIA: `rtol' = 0.1·rtol^(2/3)` and `atol'` in
    /// the same ratio to it, so that the error the estimate controls matches the tolerance.
    pub(super) fn radau_tolerances(&self) -> (f64, f64) {
        let s = self.settings;
        let rtol = 0.1 * s.rtol.powf(2.0 / 3.0);
        (rtol, rtol * (s.atol / s.rtol))
    }

    /// The weighted RMS norm of `e` with the transformed tolerances, scaled at `y` (Hairer's
    /// `SCAL`; the attempt's [`Scale`]); components of weight 0 left out.
    pub(super) fn radau_norm(&self, e: &[f64], y: &[f64]) -> f64 {
        let rtol = self.scale.rtol_radau;
        self.weighted_rms(e, |i| self.scale.atol_radau[i] + rtol * y[i].abs())
    }
}
