//! GenevaKnifeDrive: knife drive of a three-knife trimmer on a 4-slot Geneva mechanism
//! (paper 003, spec page `geneva-knife-drive.md`): driver → Geneva cross → gear pair → crank →
//! rod → knife slider. [`physics`] is the pure mechanics; [`model`] the FMU model.

#[cfg(feature = "tools")]
pub mod docs;
pub mod elastic;
pub mod model;
pub mod physics;

pub use model::GenevaKnifeDrive;
