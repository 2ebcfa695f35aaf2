//! LegacyNeedleDrive: the three-contour needle drive of the existing thread-sewing automat
//! (paper 002, spec page `legacy-needle-drive.md`), the drive the Perforators replace: a cam
//! on the main shaft, a cam-rocker pair, a four-bar and a rocker-slider to the needle bar.
//! [`physics`] is the pure mechanics; [`model`] the FMU model; [`compare`] sets it beside the
//! Perforators at equal needle motion.

pub mod compare;
#[cfg(feature = "tools")]
pub mod docs;
pub mod model;
pub mod physics;

pub use model::LegacyNeedleDrive;
