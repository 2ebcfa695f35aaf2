//! One of our 3-state ODE systems (every chain's `[x, ẋ, W]`) as an ODE of a kept library,
//! `differential-equations`, with our analytic Jacobian: for the report's anchor lines and the
//! tests that check our integrators against it (the CLI's `tools` feature; not in the FMUs).

use super::OdeSystem;
use differential_equations::prelude::*;

/// `sys` as a `differential-equations` ODE.
pub struct Library<'a>(pub &'a dyn OdeSystem);

impl ODE<f64, [f64; 3]> for Library<'_> {
    fn diff(&self, t: f64, y: &[f64; 3], dydt: &mut [f64; 3]) {
        self.0.rhs(t, y, dydt);
    }
    fn jacobian(&self, t: f64, y: &[f64; 3], j: &mut Matrix<f64>) {
        let mut a = [0.0; 9];
        self.0.jacobian(t, y, &mut a);
        for r in 0..3 {
            for c in 0..3 {
                j[(r, c)] = a[r * 3 + c];
            }
        }
    }
}
