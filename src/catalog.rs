//! Every FMU the project builds: what the CLI, the packager and the tests iterate over.
//! Adding a mechanism is one entry here, its folder under `src/mechanisms/` and a small crate
//! under `fmus/`; the FMI layer does not change.

use crate::md::ModelInfo;
use crate::model::{Model, Var, VarSet};

/// An FMU's `documentation/` files (index.html first, then figures) and its `model.png` icon.
pub type Documentation = (Vec<(String, Vec<u8>)>, Vec<u8>);

/// One FMU of the catalog.
pub struct Entry {
    /// `modelIdentifier`, also the folder `fmus/<identifier>/`.
    pub identifier: &'static str,
    /// Cargo package of its cdylib.
    pub package: &'static str,
    /// The full model description and its GUID.
    pub describe: fn() -> (String, String),
    /// Model info and variables (for the documentation's table).
    pub info: fn() -> ModelInfo,
    /// Every variable, by value reference.
    pub variables: fn() -> Vec<(u32, &'static Var)>,
    /// `documentation/` files (index.html and figures) and the `model.png` icon.
    pub documentation: fn() -> Result<Documentation, String>,
}

/// The variables of a model type, by value reference.
pub fn variables_of<M: Model>() -> Vec<(u32, &'static Var)> {
    <M::Var as VarSet>::table()
        .iter()
        .enumerate()
        .map(|(i, v)| (i as u32, v))
        .collect()
}

/// Every FMU, in the order they are built.
pub fn all() -> Vec<Entry> {
    use crate::mechanisms::geneva_knife_drive as geneva;
    vec![
        Entry {
            identifier: "GenevaKnifeDrive",
            package: "geneva-knife-drive-fmu",
            describe: crate::md::describe::<geneva::GenevaKnifeDrive>,
            info: ModelInfo::of::<geneva::GenevaKnifeDrive>,
            variables: variables_of::<geneva::GenevaKnifeDrive>,
            documentation: geneva::docs::documentation,
        },
        Entry {
            identifier: "SewingTable",
            package: "sewing-table-fmu",
            describe: crate::md::describe::<crate::mechanisms::sewing_table::SewingTable>,
            info: ModelInfo::of::<crate::mechanisms::sewing_table::SewingTable>,
            variables: variables_of::<crate::mechanisms::sewing_table::SewingTable>,
            documentation: crate::mechanisms::sewing_table::docs::documentation,
        },
        Entry {
            identifier: "Perforators",
            package: "perforators-fmu",
            describe: crate::md::describe::<crate::mechanisms::perforators::Perforators>,
            info: ModelInfo::of::<crate::mechanisms::perforators::Perforators>,
            variables: variables_of::<crate::mechanisms::perforators::Perforators>,
            documentation: crate::mechanisms::perforators::docs::documentation,
        },
        Entry {
            identifier: "DiscKnifeDrive",
            package: "disc-knife-drive-fmu",
            describe: crate::md::describe::<crate::mechanisms::disc_knife_drive::DiscKnifeDrive>,
            info: ModelInfo::of::<crate::mechanisms::disc_knife_drive::DiscKnifeDrive>,
            variables: variables_of::<crate::mechanisms::disc_knife_drive::DiscKnifeDrive>,
            documentation: crate::mechanisms::disc_knife_drive::docs::documentation,
        },
        Entry {
            identifier: "MainShaft",
            package: "main-shaft-fmu",
            describe: crate::md::describe::<crate::mechanisms::main_shaft::MainShaft>,
            info: ModelInfo::of::<crate::mechanisms::main_shaft::MainShaft>,
            variables: variables_of::<crate::mechanisms::main_shaft::MainShaft>,
            documentation: crate::mechanisms::main_shaft::docs::documentation,
        },
    ]
}
