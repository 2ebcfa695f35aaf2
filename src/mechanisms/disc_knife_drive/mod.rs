//! DiscKnifeDrive: combined crank-slider drive of the disc knives that trim a book-block spine
//! (paper 004, spec page `disc-knife-drive.md`): crank 3 → rod 4 → slider 5 carrying knife
//! holder 6, whose angle is set by slider 7 on the support line EQ. [`physics`] is the pure
//! mechanics ([`friction`] its 7×7 system with Coulomb friction); [`elastic`] the elastodynamic
//! level (compliant rod); [`model`] the FMU model.

#[cfg(feature = "tools")]
pub mod docs;
pub mod elastic;
pub mod friction;
pub mod model;
pub mod physics;

pub use model::DiscKnifeDrive;
