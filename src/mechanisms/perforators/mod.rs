//! Perforators: needle drive riding on the translating sewing table (papers 000 and 002, spec
//! page `perforators.md`): fixed ramp, lever, rod, carriage, closing spring. [`physics`] is the
//! pure mechanics; [`model`] the FMU model.

#[cfg(feature = "tools")]
pub mod docs;
pub mod elastic;
pub mod model;
pub mod needles;
pub mod physics;

pub use model::Perforators;
