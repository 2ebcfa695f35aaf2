//! MainShaft: the drive of a bookbinding machine's main shaft (induction motor, gear pair,
//! flywheel, bearings), the system-level FMU the mechanism FMUs hang on. [`physics`] is the
//! pure mechanics; [`model`] the FMU model.

#[cfg(feature = "tools")]
pub mod docs;
pub mod model;
pub mod physics;

pub use model::MainShaft;
