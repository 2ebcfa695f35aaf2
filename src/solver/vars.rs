//! The solver parameters every elastodynamic model declares (once, here).

use super::Method;
use crate::model::Var;

/// `solver.method`.
pub fn method() -> Var {
    Var::enum_parameter(
        "solver.method",
        &Method::FMI,
        "auto",
        "Integrator of the elastodynamic level inside fmi2DoStep",
    )
}
/// `solver.rtol`.
pub fn rtol() -> Var {
    Var::parameter(
        "solver.rtol",
        1e-6,
        "",
        "Relative tolerance of the adaptive integrators (elastodynamic level). Where a compliant chain's coordinate is a position rather than its deflection, a position error e is a force error k*e, so a very stiff chain's force needs a tighter tolerance than its position: at 1e12 N/m about 1e-8 for the force within 0.5 % of its peak; at the default stiffnesses the default 1e-6 gives it within 0.1 %",
    )
    .min(1e-14)
    .max(1.0)
}
/// `solver.atol`.
pub fn atol() -> Var {
    Var::parameter(
        "solver.atol",
        1e-9,
        "",
        "Absolute tolerance of the adaptive integrators, in the states' SI units; a chain's rate is never asked for less than the arithmetic resolves, 1000 roundings of its coordinate times its natural angular frequency sqrt(k/m) (elastodynamic level)",
    )
    .min(1e-20)
    .max(1.0)
}
/// `solver.max_step`.
pub fn max_step() -> Var {
    Var::parameter(
        "solver.max_step",
        1e-3,
        "s",
        "Largest internal step; the fixed step of rk4 (elastodynamic level)",
    )
    .min(1e-9)
}
/// `solver.steps` (Integer output).
pub fn steps() -> Var {
    Var::int_output(
        "solver.steps",
        "Accepted integration steps since initialization: in Co-Simulation those of the FMU's integrator inside fmi2DoStep, in Model Exchange the host's (its fmi2CompletedIntegratorStep calls); 0 where nothing is integrated (below the elastodynamic level)",
    )
}
/// `elastic.k`: the stiffness of a chain that is a spring with viscous damping
/// ([`crate::mechanics::SpringDamper`]), default `k` N/m, what the spring is in `description`.
pub fn stiffness(k: f64, description: &'static str) -> Var {
    Var::parameter("elastic.k", k, "N/m", description)
        .min(1.0)
        .max(1e16)
}
/// `elastic.zeta`: the damping ratio of that spring (default 5 % of critical), its reference
/// mass in `description`.
pub fn damping_ratio(description: &'static str) -> Var {
    Var::parameter("elastic.zeta", 0.05, "", description)
        .min(0.0)
        .max(10.0)
}
/// `elastic.E_residual`.
pub fn e_residual() -> Var {
    Var::output(
        "elastic.E_residual",
        "J",
        "Energy-balance residual E - E0 - W of the integration, W a state: of the FMU's integrator in Co-Simulation, of the host's in Model Exchange (elastodynamic level)",
    )
}
