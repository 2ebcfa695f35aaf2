//! Every FMU the project builds: what the CLI, the packager and the tests iterate over.
//! Adding a mechanism is one entry here, its folder under `src/mechanisms/` and a small crate
//! under `fmus/`; the FMI layer does not change.

use crate::md::ModelInfo;
use crate::model::Var;
use crate::scene::{Scene, SceneError, Tailored};

pub use crate::docs::{Documentation, Files};
pub use crate::model::variables_of;

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
    /// The FMU tailored to a scene of this mechanism (`scenes.md`).
    pub tailor: fn(&Scene) -> Result<Tailored, SceneError>,
    /// The `documentation/` files of such an FMU (what it leaves out, and why).
    pub scene_documentation: fn(&Tailored) -> Result<Files, String>,
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
            tailor: crate::scene::tailor::<geneva::GenevaKnifeDrive>,
            scene_documentation: crate::docs::scene::documentation::<geneva::GenevaKnifeDrive>,
        },
        Entry {
            identifier: "SewingTable",
            package: "sewing-table-fmu",
            describe: crate::md::describe::<crate::mechanisms::sewing_table::SewingTable>,
            info: ModelInfo::of::<crate::mechanisms::sewing_table::SewingTable>,
            variables: variables_of::<crate::mechanisms::sewing_table::SewingTable>,
            documentation: crate::mechanisms::sewing_table::docs::documentation,
            tailor: crate::scene::tailor::<crate::mechanisms::sewing_table::SewingTable>,
            scene_documentation: crate::docs::scene::documentation::<
                crate::mechanisms::sewing_table::SewingTable,
            >,
        },
        Entry {
            identifier: "Perforators",
            package: "perforators-fmu",
            describe: crate::md::describe::<crate::mechanisms::perforators::Perforators>,
            info: ModelInfo::of::<crate::mechanisms::perforators::Perforators>,
            variables: variables_of::<crate::mechanisms::perforators::Perforators>,
            documentation: crate::mechanisms::perforators::docs::documentation,
            tailor: crate::scene::tailor::<crate::mechanisms::perforators::Perforators>,
            scene_documentation: crate::docs::scene::documentation::<
                crate::mechanisms::perforators::Perforators,
            >,
        },
        Entry {
            identifier: "DiscKnifeDrive",
            package: "disc-knife-drive-fmu",
            describe: crate::md::describe::<crate::mechanisms::disc_knife_drive::DiscKnifeDrive>,
            info: ModelInfo::of::<crate::mechanisms::disc_knife_drive::DiscKnifeDrive>,
            variables: variables_of::<crate::mechanisms::disc_knife_drive::DiscKnifeDrive>,
            documentation: crate::mechanisms::disc_knife_drive::docs::documentation,
            tailor: crate::scene::tailor::<crate::mechanisms::disc_knife_drive::DiscKnifeDrive>,
            scene_documentation: crate::docs::scene::documentation::<
                crate::mechanisms::disc_knife_drive::DiscKnifeDrive,
            >,
        },
        Entry {
            identifier: "MainShaft",
            package: "main-shaft-fmu",
            describe: crate::md::describe::<crate::mechanisms::main_shaft::MainShaft>,
            info: ModelInfo::of::<crate::mechanisms::main_shaft::MainShaft>,
            variables: variables_of::<crate::mechanisms::main_shaft::MainShaft>,
            documentation: crate::mechanisms::main_shaft::docs::documentation,
            tailor: crate::scene::tailor::<crate::mechanisms::main_shaft::MainShaft>,
            scene_documentation: crate::docs::scene::documentation::<
                crate::mechanisms::main_shaft::MainShaft,
            >,
        },
    ]
}

/// The catalog entry of a scene's mechanism and the FMU tailored to the scene; an unknown
/// mechanism is refused with the list of known ones.
pub fn tailor(scene: &Scene) -> Result<(Entry, Tailored), SceneError> {
    let all = all();
    let known: Vec<&str> = all.iter().map(|e| e.identifier).collect();
    let Some(entry) = all.into_iter().find(|e| e.identifier == scene.mechanism) else {
        return Err(scene.unknown_mechanism(&known));
    };
    let t = (entry.tailor)(scene)?;
    Ok((entry, t))
}

/// The `.fmu` (bytes) tailored to a scene text, and its modelIdentifier: the mechanism's own
/// binaries (`binaries(identifier)` gives its cdylib for every platform built), the tailored
/// description and documentation, and the scene in `resources/scene.toml`, which the binary reads at `fmi2Instantiate`.
pub fn scene_fmu(
    text: &str,
    binaries: &dyn Fn(&str) -> Result<crate::package::Binaries, String>,
    date: &str,
) -> Result<(String, Vec<u8>), String> {
    let scene = Scene::parse(text).map_err(|e| e.to_string())?;
    let (entry, t) = tailor(&scene).map_err(|e| e.to_string())?;
    let fmu = crate::package::FmuContents {
        identifier: t.identifier.clone(),
        model_description: crate::md::stamp(&t.model_description(), date),
        binaries: binaries(entry.identifier)?,
        documentation: (entry.scene_documentation)(&t)?,
        icon: crate::docs::icon_png("Scene")?,
        resources: vec![(crate::scene::RESOURCE_NAME.to_string(), text.into())],
    };
    Ok((t.identifier, fmu.to_zip()?))
}
