//! SewingTable: cam-driven translating table of a thread-sewing machine (paper 000, spec page
//! `sewing-table.md`), with the rocking table it replaces as a variant. [`physics`] is the pure
//! mechanics; [`model`] the FMU model.

#[cfg(feature = "tools")]
pub mod docs;
pub mod elastic;
pub mod model;
pub mod physics;

pub use model::SewingTable;
