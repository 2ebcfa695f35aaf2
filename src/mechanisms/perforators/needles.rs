//! The needle parameters the Perforators share with the LegacyNeedleDrive, the drive they
//! replace: the same names, meanings, defaults and bounds, declared once here; each model lists
//! them in its `model_variables!` block (`loads`: the stages a load parameter feeds), so two
//! FMUs set alike move their needles alike and carry the same piercing load.

use super::physics::Params;
use crate::mechanisms::sewing_table::model::{MOTION_LAW, motion_law};
use crate::mechanisms::sewing_table::physics::Params as TableParams;
use crate::model::{Stages, Values, Var, VarSet};

/// The needle parameters from the variables declared here (read by name: each needle model
/// declares them in its own enum) and `synth.unit`, the needles moving with the table `table`;
/// the rest of the linkage at its defaults.
pub fn params<V: VarSet>(v: &Values<V>, table: TableParams) -> Params {
    let x = |name| v.named(name);
    let law = |name| motion_law(x(name) as i32);
    Params {
        unit: x("synth.unit"),
        table,
        rise_fraction: x("travel.rise_fraction"),
        law_rise: law("law.rise"),
        law_fall: law("law.fall"),
        pierce_q: x("pierce.Q"),
        pierce_s_in: x("pierce.s_in"),
        pierce_s_out: x("pierce.s_out"),
        pierce_k_f: x("pierce.k_f"),
        perf_m: x("perf.m"),
        guide_mu: x("guide.mu"),
        joint_f: x("joint.f"),
        joint_r: x("joint.r"),
        ..Params::default()
    }
}

/// For `@with crate::needle_variables { law_and_loads(LOADS) }` in a `model_variables!` block:
/// the needle curve over the travel (`travel.rise_fraction`, `law.rise`, `law.fall`) and the
/// piercing load and the needles' mass (`pierce.*`, `perf.m`, feeding the stages `LOADS`), in
/// this order: the run of declarations both needle models list alike.
#[macro_export]
macro_rules! needle_variables {
    (@callback $head:tt [ $( $done:tt )* ] { law_and_loads($loads:expr) } $( $rest:tt )*) => {
        $crate::model_variables!(@munch $head [ $( $done )*
            (travel_rise_fraction = $crate::mechanisms::perforators::needles::rise_fraction())
            (law_rise = $crate::mechanisms::perforators::needles::law_rise())
            (law_fall = $crate::mechanisms::perforators::needles::law_fall())
            (pierce_Q = $crate::mechanisms::perforators::needles::pierce_q($loads))
            (pierce_s_in = $crate::mechanisms::perforators::needles::pierce_s_in($loads))
            (pierce_s_out = $crate::mechanisms::perforators::needles::pierce_s_out($loads))
            (pierce_k_f = $crate::mechanisms::perforators::needles::pierce_k_f($loads))
            (perf_m = $crate::mechanisms::perforators::needles::perf_m($loads))
        ] $( $rest )*);
    };
}

/// `cycle.forward`.
pub fn cycle_forward() -> Var {
    Var::parameter(
        "cycle.forward",
        82f64.to_radians(),
        "rad",
        "Shaft angle of the table's forward travel (as SewingTable)",
    )
    .min(0.0)
}
/// `cycle.phi0`.
pub fn cycle_phi0() -> Var {
    Var::parameter(
        "cycle.phi0",
        0.0,
        "rad",
        "Shaft angle where the forward travel starts (as SewingTable)",
    )
}
/// `law.forward`.
pub fn law_forward() -> Var {
    Var::enum_parameter(
        "law.forward",
        &MOTION_LAW,
        "cycloidal",
        "Table law of the forward travel (as SewingTable)",
    )
}
/// `travel.rise_fraction`.
pub fn rise_fraction() -> Var {
    Var::parameter(
        "travel.rise_fraction",
        0.5,
        "",
        "Fraction of the table travel over which the perforators rise (paper 000: half)",
    )
    .min(0.0)
    .max(1.0)
}
/// `law.rise`.
pub fn law_rise() -> Var {
    Var::enum_parameter(
        "law.rise",
        &MOTION_LAW,
        "cycloidal",
        "Needle law of the rise over the table position (paper 002: 'Co' on the working stroke)",
    )
}
/// `law.fall`.
pub fn law_fall() -> Var {
    Var::enum_parameter(
        "law.fall",
        &MOTION_LAW,
        "cycloidal",
        "Needle law of the fall over the table position",
    )
}
/// `pierce.Q`.
pub fn pierce_q(loads: Stages) -> Var {
    Var::parameter(
        "pierce.Q",
        22.0 * crate::mechanics::STANDARD_GRAVITY,
        "N",
        "Piercing load of 12 needles in a 16-page signature of paper No. 2: 22 kgf (paper 002)",
    )
    .min(0.0)
    .feeds(loads)
}
/// `pierce.s_in`.
pub fn pierce_s_in(loads: Stages) -> Var {
    Var::parameter(
        "pierce.s_in",
        0.55,
        "",
        "Fraction of the stroke where the needles meet the fold (assumption)",
    )
    .min(0.0)
    .max(1.0)
    .feeds(loads)
}
/// `pierce.s_out`.
pub fn pierce_s_out(loads: Stages) -> Var {
    Var::parameter(
        "pierce.s_out",
        0.75,
        "",
        "Fraction of the stroke where they are through (assumption)",
    )
    .min(0.0)
    .max(1.0)
    .feeds(loads)
}
/// `pierce.k_f`.
pub fn pierce_k_f(loads: Stages) -> Var {
    Var::parameter(
        "pierce.k_f",
        0.15,
        "",
        "Needle friction after piercing, fraction of pierce.Q (assumption)",
    )
    .min(0.0)
    .feeds(loads)
}
/// `perf.m`.
pub fn perf_m(loads: Stages) -> Var {
    Var::parameter(
        "perf.m",
        0.6,
        "kg",
        "Mass of carriage and perforators (assumption)",
    )
    .min(0.0)
    .feeds(loads)
}
/// `guide.mu`.
pub fn guide_mu(loads: Stages) -> Var {
    Var::parameter(
        "guide.mu",
        0.1,
        "",
        "Friction coefficient of the carriage guides (assumption)",
    )
    .min(0.0)
    .feeds(loads)
}
/// `joint.f`.
pub fn joint_f(loads: Stages) -> Var {
    Var::parameter(
        "joint.f",
        0.05,
        "",
        "Friction coefficient of the linkage's hinges, moment f*r*|F| (as paper 002; 0 disables)",
    )
    .min(0.0)
    .feeds(loads)
}
/// `joint.r`.
pub fn joint_r(loads: Stages) -> Var {
    Var::parameter("joint.r", 0.006, "m", "Hinge pin radius (assumption)")
        .min(0.0)
        .feeds(loads)
}
