//! bindery-fmu: mechanisms of bookbinding machines as FMI 2.0 co-simulation FMUs.
//!
//! Layers, each knowing only the ones below it:
//! - [`mechanics`]: shared mechanics (motion laws, slider-crank, Geneva pair, Hertz contact, ...).
//! - [`mechanisms`]: one folder per mechanism: its physics (pure math) and its FMU model
//!   (variables declared once, see [`model`]).
//! - [`model`]: the narrow interface every mechanism implements, and the variable declarations.
//! - [`solver`]: the integrators of the elastodynamic level (inside `fmi2DoStep`); know no mechanism.
//! - [`md`]: the modelDescription.xml writer and GUID, generated from those declarations.
//! - [`fmi2`]: the FMI 2.0 C ABI runtime; knows no mechanism.
//! - [`fmi3`]: the FMI 3.0 C ABI over the same runtime.
//! - `ssp` (feature `tools`): the machines as SSP 1.0 systems of these FMUs.
//! - [`scene`]: scene files and the FMU tailored to one (`scenes.md`); knows no mechanism.
//! - `sweep` (feature `tools`): design sweeps, every run native and in this process.
//! - `docs` (feature `tools`): the FMU's `documentation/` page, figures and icon; knows no mechanism.
// The documentation is for those who work on the crate (`cargo doc --document-private-items`):
// it links to private items where they say how a public one works.
#![allow(rustdoc::private_intra_doc_links)]
// model_variables! reads a model's list one variable per expansion step (about 100 in a
// mechanism); the default limit of 128 is too close.
#![recursion_limit = "256"]
/// The crate under its own name, for test code shared with the integration tests.
#[cfg(test)]
extern crate self as bindery_fmu;

#[cfg(feature = "tools")]
pub mod catalog;
pub mod digest;
#[cfg(feature = "tools")]
pub mod docs;
pub mod fmi2;
pub mod fmi3;
pub mod lifetime;
#[cfg(feature = "tools")]
pub mod machines;
pub mod md;
pub mod mechanics;
pub mod mechanisms;
pub mod model;
#[cfg(feature = "tools")]
pub mod package;
#[cfg(feature = "tools")]
pub mod reference;
pub mod scene;
pub mod solver;
#[cfg(feature = "tools")]
pub mod ssp;
#[cfg(feature = "tools")]
pub mod sweep;
