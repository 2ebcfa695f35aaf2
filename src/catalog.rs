//! Every FMU the project builds: what the CLI, the packager and the tests iterate over.
//! Adding a mechanism is one entry here, its folder under `src/mechanisms/` and a small crate
//! under `fmus/`; the FMI layer does not change.

use crate::md::ModelInfo;
use crate::model::{Model, Var};
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
    /// The full FMI 3.0 model description and its instantiation token (the same GUID).
    pub describe3: fn() -> (String, String),
    /// The full FMI 3.0 FMU's `terminalsAndIcons.xml`.
    pub terminals3: fn() -> String,
    /// The outputs of a cross-check experiment, run natively (the reference results inside
    /// the FMU: [`crate::reference`]).
    pub reference: fn(&crate::reference::Experiment) -> Result<String, String>,
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
    /// A sweep file of this model (with the text of the scene it starts from), checked.
    pub sweep: fn(&str, Option<&str>) -> Result<crate::sweep::Plan, SceneError>,
}

impl Entry {
    /// The entry of model `M`, built by the cdylib `package`, with its `documentation`.
    pub fn of<M: Model>(
        package: &'static str,
        documentation: fn() -> Result<Documentation, String>,
    ) -> Entry {
        Entry {
            identifier: M::IDENTIFIER,
            package,
            describe: crate::md::describe::<M>,
            describe3: crate::md::describe3::<M>,
            terminals3: crate::md::terminals::of::<M>,
            reference: crate::reference::run::<M>,
            info: ModelInfo::of::<M>,
            variables: variables_of::<M>,
            documentation,
            tailor: crate::scene::tailor::<M>,
            scene_documentation: crate::docs::scene::documentation::<M>,
            sweep: crate::sweep::file::parse::<M>,
        }
    }
}

/// Every FMU, in the order they are built.
pub fn all() -> Vec<Entry> {
    use crate::mechanisms::{
        disc_knife_drive, geneva_knife_drive, legacy_needle_drive, main_shaft,
    };
    use crate::mechanisms::{perforators, sewing_table};
    vec![
        Entry::of::<geneva_knife_drive::GenevaKnifeDrive>(
            "geneva-knife-drive-fmu",
            geneva_knife_drive::docs::documentation,
        ),
        Entry::of::<sewing_table::SewingTable>(
            "sewing-table-fmu",
            sewing_table::docs::documentation,
        ),
        Entry::of::<perforators::Perforators>("perforators-fmu", perforators::docs::documentation),
        Entry::of::<disc_knife_drive::DiscKnifeDrive>(
            "disc-knife-drive-fmu",
            disc_knife_drive::docs::documentation,
        ),
        Entry::of::<main_shaft::MainShaft>("main-shaft-fmu", main_shaft::docs::documentation),
        Entry::of::<legacy_needle_drive::LegacyNeedleDrive>(
            "legacy-needle-drive-fmu",
            legacy_needle_drive::docs::documentation,
        ),
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
/// description of FMI version `fmi` and documentation, and the scene in `resources/scene.toml`,
/// which the binary reads at instantiation; with its reference results (FMI-LS-REF) if
/// `inputs` gives the mechanism's cross-check inputs (`<Model>_in.csv`): the scene's default
/// experiment on the inputs the scene lists ([`scene_reference`]).
pub fn scene_fmu_of(
    text: &str,
    binaries: &dyn Fn(&str) -> Result<crate::package::Binaries, String>,
    date: &str,
    fmi: crate::package::Fmi,
    inputs: Option<&str>,
) -> Result<(String, Vec<u8>), String> {
    let scene = Scene::parse(text).map_err(|e| e.to_string())?;
    let (entry, t) = tailor(&scene).map_err(|e| e.to_string())?;
    let extra = match inputs {
        Some(csv) => scene_reference(&entry, &t, csv)?,
        None => vec![],
    };
    let fmu = crate::package::FmuContents {
        identifier: t.identifier.clone(),
        model_description: crate::md::stamp(
            &match fmi {
                crate::package::Fmi::V2 => t.model_description(),
                crate::package::Fmi::V3 => t.model_description3(),
            },
            date,
        ),
        binaries: binaries(entry.identifier)?,
        documentation: (entry.scene_documentation)(&t)?,
        icon: crate::docs::icon_png("Scene")?,
        resources: vec![(crate::scene::RESOURCE_NAME.to_string(), text.into())],
        terminals: (fmi == crate::package::Fmi::V3)
            .then(|| crate::md::terminals::terminals_and_icons(t.info.terminals, &t.refs())),
        fmi,
        extra,
    };
    Ok((t.identifier, fmu.to_zip()?))
}

/// The reference results of a scene's FMU: the mechanism run natively with the scene's start
/// values and stages over the scene's default experiment, on the columns of the cross-check
/// inputs `csv` that the scene lists (none for a constant-speed drive), every Real output the
/// scene lists recorded.
pub fn scene_reference(
    entry: &Entry,
    t: &Tailored,
    csv: &str,
) -> Result<Vec<(String, Vec<u8>)>, String> {
    use crate::model::Causality;
    let listed = |c: Causality| -> Vec<&str> {
        (t.variables.iter())
            .filter(|(_, v)| v.causality == c && v.ty == crate::model::VarType::Real)
            .map(|(_, v)| v.name)
            .collect()
    };
    let input = crate::reference::columns(csv, &listed(Causality::Input));
    let outputs: Vec<String> = (listed(Causality::Output).into_iter())
        .map(String::from)
        .collect();
    let e = t.info.experiment;
    let x = crate::reference::Experiment {
        input_csv: &input,
        start: e.start,
        stop: e.stop,
        step: e.step,
        outputs: &outputs,
        tailored: Some((&t.start, t.stages)),
    };
    let out = (entry.reference)(&x).map_err(|err| format!("{}: {err}", t.identifier))?;
    Ok(crate::reference::files(&t.identifier, &x, out))
}
