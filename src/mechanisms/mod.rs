//! One module per mechanism: its physics (pure math, no FFI) and its FMU model.

pub mod contact_watch;
pub mod disc_knife_drive;
pub mod geneva_knife_drive;
pub mod legacy_needle_drive;
pub mod main_shaft;
pub mod perforators;
pub mod sewing_table;

use crate::model::{Stages, Var};

/// `cam.E`: the Young's modulus of a steel cam, the track of its roller's Hertz line contact
/// ([`crate::mechanics::hertz::Roller`]), feeding the stage `hertz` of the Hertz stress.
pub(crate) fn cam_e(hertz: Stages) -> Var {
    Var::parameter(
        "cam.E",
        2.1e11,
        "Pa",
        "Young's modulus of the cam (assumption: steel)",
    )
    .min(0.0)
    .feeds(hertz)
}

/// `roller.E`: the Young's modulus of a steel cam or ramp roller in its Hertz line contact
/// ([`crate::mechanics::hertz::Roller`]), feeding the stage `hertz` of the Hertz stress.
pub(crate) fn roller_e(hertz: Stages) -> Var {
    Var::parameter(
        "roller.E",
        2.1e11,
        "Pa",
        "Young's modulus of the roller (assumption: steel)",
    )
    .min(0.0)
    .feeds(hertz)
}

/// Asserts `x` equals the printed reference `reference` to the digits printed:
/// |x − reference| ≤ half a unit of the last printed decimal (`decimals` after the point).
/// The knife drives' physics tests check the papers' printed tables with it.
#[cfg(test)]
#[track_caller]
pub(crate) fn assert_printed(x: f64, reference: f64, decimals: i32) {
    let tol = 0.5 * 10f64.powi(-decimals) * (1.0 + 1e-9);
    assert!(
        (x - reference).abs() <= tol,
        "{x} does not print as {reference} ({decimals} decimals)"
    );
}
