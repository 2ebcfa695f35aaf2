//! One module per mechanism: its physics (pure math, no FFI) and its FMU model.

pub mod contact_watch;
pub mod disc_knife_drive;
pub mod geneva_knife_drive;
pub mod legacy_needle_drive;
pub mod main_shaft;
pub mod perforators;
pub mod sewing_table;

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
