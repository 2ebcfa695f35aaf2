//! Tests of scene files and tailoring: every example scene in `scenes/` tailors, its outputs equal
//! the full model's bit for bit, and bad scenes are refused naming the key, its line and the
//! valid choices.

use super::*;
use crate::catalog;
use crate::docs::scene as docs;
use crate::mechanisms::disc_knife_drive::DiscKnifeDrive;
use crate::mechanisms::geneva_knife_drive::GenevaKnifeDrive;
use crate::mechanisms::legacy_needle_drive::LegacyNeedleDrive;
use crate::mechanisms::perforators::Perforators;
use crate::mechanisms::sewing_table::SewingTable;
use crate::model::Dynamics;
use crate::model::NoLog;
use std::path::PathBuf;

fn examples() -> Vec<(PathBuf, String)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("scenes/")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let t = std::fs::read_to_string(&p).unwrap();
            (p, t)
        })
        .collect()
}

/// The text of `scenes/<file>`.
fn example(file: &str) -> String {
    examples()
        .into_iter()
        .find(|(p, _)| p.file_name().unwrap() == file)
        .unwrap_or_else(|| panic!("scenes/{file}"))
        .1
}

const GENEVA: &str = r#"name = "t"
mechanism = "GenevaKnifeDrive"
fidelity = "kinematic"
outputs = ["knife.s"]
"#;

/// The error of `text` held against its mechanism.
fn refusal(text: &str) -> SceneError {
    let scene = match Scene::parse(text) {
        Ok(s) => s,
        Err(e) => return e,
    };
    match catalog::tailor(&scene) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

/// `refused!(scene text => "key", line N: "part of the message", ..)`: the scene is refused
/// naming that key at that line, with every part in the message.
macro_rules! refused {
    ($text:expr => $key:literal, line $line:literal $(: $($part:literal),+)?) => {
        assert_refused(&$text, $key, $line, &[$($($part),+)?])
    };
}

#[track_caller]
fn assert_refused(text: &str, key: &str, line: usize, parts: &[&str]) {
    let e = refusal(text);
    assert_eq!(e.key, key, "{e}");
    assert_eq!(e.line, Some(line), "{e}");
    for p in parts {
        assert!(e.message.contains(p), "{p:?} not in: {e}");
    }
}

#[test]
fn every_example_scene_tailors_and_covers_every_level() {
    let ex = examples();
    let mut covered = Vec::new();
    for (path, text) in &ex {
        let scene = Scene::parse(text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let (entry, t) =
            catalog::tailor(&scene).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(t.identifier, identifier(entry.identifier, &scene.name));
        // what the description lists: the scene's outputs, nothing else of causality output
        let outs: Vec<&str> = t
            .variables
            .iter()
            .filter(|(_, v)| v.causality == Causality::Output)
            .map(|(_, v)| v.name)
            .collect();
        let mut asked: Vec<&str> = scene.outputs.iter().map(|o| o.0.as_str()).collect();
        asked.sort();
        let mut outs_sorted = outs.clone();
        outs_sorted.sort();
        assert_eq!(outs_sorted, asked, "{}", path.display());
        assert!(t.model_description().contains(&t.guid));
        assert!(
            t.model_description()
                .contains(&format!("modelIdentifier=\"{}\"", t.identifier))
        );
        covered.push((scene.mechanism.clone(), scene.fidelity));
    }
    for (m, levels) in [
        ("GenevaKnifeDrive", FIDELITIES),
        ("SewingTable", FIDELITIES),
        ("Perforators", FIDELITIES),
        ("DiscKnifeDrive", FIDELITIES),
    ] {
        for (n, f) in levels {
            assert!(
                covered.contains(&(m.to_string(), Some(*f))),
                "no example scene of {m} at {n}"
            );
        }
    }
}

#[test]
fn the_tailored_description_is_the_one_the_binary_computes() {
    // the CLI writes the description, the binary computes the GUID from the same tailoring
    let t = tailor_text::<GenevaKnifeDrive>(&example("geneva-chain-dynamics.toml")).unwrap();
    let (xml, guid) = md::describe_vars(&t.info, &t.refs());
    assert_eq!(guid, t.guid);
    assert!(xml.contains(&format!("guid=\"{}\"", t.guid)));
    assert_eq!(xml, t.model_description());
    assert_ne!(t.guid, md::describe::<GenevaKnifeDrive>().1);
}

#[test]
fn a_kinematic_scene_with_its_own_drive_leaves_out_forces_inputs_and_loads() {
    let t = tailor_text::<GenevaKnifeDrive>(
        &(GENEVA.to_string() + "[drive]\nmode = \"constant_speed\"\nn = 30\n"),
    )
    .unwrap();
    assert_lists(
        &t,
        &[
            "knife.s",
            "crank.r",
            "rod.l",
            "geneva.Z",
            "drive.n",
            "drive.phi0",
        ],
        &[
            "shaft.phi",
            "shaft.w",
            "shaft.a",
            "shaft.tau",
            "knife.m",
            "cut.F_max",
            "elastic.k",
            "solver.rtol",
            "drive.mode",
            "model.fidelity",
            "knife.F_cut",
            "elastic.x",
        ],
    );
    assert_eq!(t.stages, Stages::NONE, "no force analysis, no ODE");
    assert!(!t.model_description().contains("<ModelExchange"));
    // the drive and the level are start values inside
    assert_eq!(t.start[shaft::MODE as usize], 2.0);
    assert_eq!(t.start[shaft::FIDELITY as usize], 1.0);
    assert_eq!(t.start[shaft::N as usize], std::f64::consts::PI);
}

#[test]
fn an_input_driven_scene_lists_the_inputs_its_outputs_depend_on() {
    let t = tailor_text::<GenevaKnifeDrive>(GENEVA).unwrap();
    let inputs = names_of(&t, |v| v.causality == Causality::Input);
    assert_eq!(
        inputs,
        ["shaft.phi", "shaft.w", "shaft.a"],
        "a position depends on the angle only, but a step moves the angle with all three"
    );
    let t = tailor_text::<SewingTable>(
        "name = \"f\"\nmechanism = \"SewingTable\"\nfidelity = \"kinetostatic\"\noutputs = [\"cam.F\"]\n",
    )
    .unwrap();
    let inputs = names_of(&t, |v| v.causality == Causality::Input);
    assert_eq!(inputs, ["shaft.phi", "shaft.w", "shaft.a", "table.F_ext"]);
    // Hertz stress and the rocking table are skipped; its moduli are left out
    let names = names_of(&t, |_| true);
    assert!(!names.contains(&"cam.E") && !names.contains(&"roller.b"));
    // rocking.J feeds the torque of the rocking kind (a parameter's value): kept, conservatively
    assert!(names.contains(&"rocking.J"));
    assert!(names.contains(&"table.m") && names.contains(&"guide.f"));
    use crate::mechanisms::sewing_table::model::stage;
    assert_eq!(t.stages, stage::FORCES);
}

#[test]
fn an_elastodynamic_scene_keeps_its_states_and_model_exchange() {
    let t = tailor_text::<GenevaKnifeDrive>(
        "name = \"e\"\nmechanism = \"GenevaKnifeDrive\"\nfidelity = \"elastodynamic\"\noutputs = [\"knife.s\"]\n",
    )
    .unwrap();
    assert_lists(
        &t,
        &[
            "elastic.x",
            "der(elastic.x)",
            "elastic.k",
            "solver.method",
            "knife.m",
            "shaft.w",
        ],
        &[],
    );
    assert!(t.model_description().contains("<ModelExchange"));
}

/// The names of the scene's variables that pass `keep`, in order.
fn names_of(t: &Tailored, keep: impl Fn(&Var) -> bool) -> Vec<&'static str> {
    t.variables
        .iter()
        .filter(|(_, v)| keep(v))
        .map(|(_, v)| v.name)
        .collect()
}

/// The scene lists every variable of `kept` and none of `gone`.
#[track_caller]
fn assert_lists(t: &Tailored, kept: &[&str], gone: &[&str]) {
    let names = names_of(t, |_| true);
    for k in kept {
        assert!(names.contains(k), "{k} missing from {names:?}");
    }
    for g in gone {
        assert!(!names.contains(g), "{g} listed: {names:?}");
    }
}

/// Runs the full model and the tailored one side by side (prepare, steps, evaluate) and
/// compares the scene's outputs bit for bit.
fn same_outputs<M: Model>(t: &Tailored) {
    let mut full = Values::<M::Var>::start();
    full.raw_mut().copy_from_slice(&t.start);
    let mut tail = full.clone();
    tail.stages = t.stages;
    let mut mf = M::prepare(&full).unwrap();
    let mut mt = M::prepare(&tail).unwrap();
    mf.calculated_parameters(&mut full);
    mt.calculated_parameters(&mut tail);
    let outs: Vec<usize> = t
        .variables
        .iter()
        .filter(|(_, v)| {
            matches!(
                v.causality,
                Causality::Output | Causality::CalculatedParameter
            )
        })
        .map(|(vr, _)| *vr as usize)
        .collect();
    let h = 1e-3;
    for k in 0..300 {
        let time = k as f64 * h;
        // inputs (ignored with a constant_speed drive)
        for v in [&mut full, &mut tail] {
            v.raw_mut()[shaft::PHI as usize] = 0.9 + 7.0 * time;
            v.raw_mut()[shaft::W as usize] = 7.0;
            v.raw_mut()[shaft::A as usize] = 0.5;
        }
        mf.evaluate(&mut full, time, &mut NoLog);
        mt.evaluate(&mut tail, time, &mut NoLog);
        for &vr in &outs {
            assert_eq!(
                full.raw()[vr].to_bits(),
                tail.raw()[vr].to_bits(),
                "{} {} at step {k}: full {} tailored {}",
                t.identifier,
                <M::Var as VarSet>::table()[vr].name,
                full.raw()[vr],
                tail.raw()[vr]
            );
        }
        mf.step(&mut full, time, h, &mut NoLog).unwrap();
        mt.step(&mut tail, time, h, &mut NoLog).unwrap();
    }
}

#[test]
fn tailored_outputs_equal_the_full_models_bit_for_bit() {
    for (path, text) in examples() {
        let scene = Scene::parse(&text).unwrap();
        match scene.mechanism.as_str() {
            "GenevaKnifeDrive" => {
                same_outputs::<GenevaKnifeDrive>(&tailor::<GenevaKnifeDrive>(&scene).unwrap())
            }
            "SewingTable" => same_outputs::<SewingTable>(&tailor::<SewingTable>(&scene).unwrap()),
            "Perforators" => same_outputs::<Perforators>(&tailor::<Perforators>(&scene).unwrap()),
            "DiscKnifeDrive" => {
                same_outputs::<DiscKnifeDrive>(&tailor::<DiscKnifeDrive>(&scene).unwrap())
            }
            "LegacyNeedleDrive" => {
                same_outputs::<LegacyNeedleDrive>(&tailor::<LegacyNeedleDrive>(&scene).unwrap())
            }
            m => panic!("{}: mechanism {m} not covered by this test", path.display()),
        }
    }
}

#[test]
fn the_documentation_says_what_is_left_out_and_why() {
    let t = tailor_text::<GenevaKnifeDrive>(&example("geneva-side-knife-kinematics.toml")).unwrap();
    let r = docs::report::<GenevaKnifeDrive>(&t);
    let why = |items: &[docs::LeftOut], name: &str| {
        items
            .iter()
            .find(|i| i.name == name)
            .unwrap_or_else(|| panic!("{name} not reported"))
            .why
            .clone()
    };
    assert!(why(&r.stages, "forces").contains("not part of the kinematic level"));
    assert!(why(&r.stages, "elastic").contains("not part of the kinematic level"));
    assert!(why(&r.outputs, "knife.F_cut").contains("not computed at the kinematic level"));
    assert!(why(&r.outputs, "crank.theta").contains("not among the scene's outputs"));
    assert!(why(&r.parameters, "knife.m").contains("influences only forces, elastic"));
    assert!(why(&r.parameters, "model.fidelity").contains("kinematic"));
    assert!(why(&r.inputs, "shaft.phi").contains("30 rpm"));
    let html = String::from_utf8(
        docs::documentation::<GenevaKnifeDrive>(&t).unwrap()[0]
            .1
            .clone(),
    )
    .unwrap();
    assert!(html.contains("What this FMU leaves out") && html.contains("knife.F_cut"));
    // a kinetostatic scene that does not ask for the stress: Hertz skipped, and said why
    let t = tailor_text::<SewingTable>(
        "name = \"f\"\nmechanism = \"SewingTable\"\nfidelity = \"kinetostatic\"\noutputs = [\"cam.F\"]\n",
    )
    .unwrap();
    let r = docs::report::<SewingTable>(&t);
    assert!(
        why(&r.stages, "hertz")
            .contains("no output of the scene needs it (it computes cam.sigma_H)")
    );
}

// ---- refusals: each names the key, its line and the valid choices

#[test]
fn syntax_and_unknown_keys() {
    refused!("name = \"a\"\nmechanism = = 3\n" => "", line 2);
    refused!((GENEVA.to_string() + "colour = \"red\"\n") => "colour", line 5: "unknown key", "valid: name, mechanism, fidelity, outputs, parameters, experiment, drive");
    refused!((GENEVA.to_string() + "[experiment]\nstop = 1.0\nstep = 1e-3\nend = 2\n") => "experiment.end", line 8: "unknown key", "valid: start, stop, step, tolerance");
    refused!((GENEVA.to_string() + "[experiment]\nstop = \"1 s\"\nstep = 1e-3\n") => "experiment.stop", line 6: "must be a number, not a string");
    refused!(GENEVA.replace("outputs = [\"knife.s\"]", "outputs = \"knife.s\"") => "outputs", line 4: "must be an array of output names, not a string");
    refused!(GENEVA.replace("outputs = [\"knife.s\"]", "outputs = [\"knife.s\", 3]") => "outputs[1]", line 4: "must be a string, not an integer");
    // a missing key
    let e = refusal("name = \"a\"\nmechanism = \"SewingTable\"\nfidelity = \"kinematic\"\n");
    assert_eq!(e.key, "outputs");
    assert!(e.message.contains("missing"), "{e}");
}

#[test]
fn unknown_mechanism_lists_the_mechanisms() {
    refused!(GENEVA.replace("GenevaKnifeDrive", "GenevaDrive") => "mechanism", line 2: "GenevaDrive", "GenevaKnifeDrive, SewingTable, Perforators, DiscKnifeDrive");
}

#[test]
fn bad_name_fidelity_and_drive() {
    refused!(GENEVA.replace("\"t\"", "\"a b\"") => "name", line 1: "modelIdentifier");
    refused!(GENEVA.replace("kinematic", "static") => "fidelity", line 3: "kinematic, kinetostatic, elastodynamic");
    refused!((GENEVA.to_string() + "[drive]\nmode = \"constant\"\n") => "drive.mode", line 6: "input, constant_speed");
    refused!((GENEVA.to_string() + "[drive]\nmode = \"constant_speed\"\n") => "drive.n", line 6: "needs the speed n");
    refused!((GENEVA.to_string() + "[experiment]\nstop = 1.0\nstep = 2.0\n") => "experiment.step", line 7: "at most stop - start");
}

#[test]
fn unknown_output_gives_the_nearest_names() {
    refused!(GENEVA.replace("[\"knife.s\"]", "[\"knife.s\", \"knife.vel\"]") => "outputs[1]", line 4: "no output \"knife.vel\"", "knife.v");
    refused!(GENEVA.replace("[\"knife.s\"]", "[\"knife.s\",\n  \"crank.r\"]") => "outputs[1]", line 5: "is a parameter, not an output", "[parameters]");
    refused!(GENEVA.replace("[\"knife.s\"]", "[\"knife.s\", \"knife.s\"]") => "outputs[1]", line 4: "listed twice");
}

#[test]
fn output_not_at_this_fidelity_names_the_levels_that_have_it() {
    refused!(GENEVA.replace("[\"knife.s\"]", "[\"knife.s\", \"rod.F\"]") => "outputs[1]", line 4: "not computed at fidelity \"kinematic\"", "it is at: kinetostatic, elastodynamic");
    refused!(GENEVA.replace("[\"knife.s\"]", "[\"dyn.factor\"]").replace("kinematic", "kinetostatic") => "outputs[0]", line 4: "it is at: elastodynamic");
    refused!("name = \"t\"\nmechanism = \"SewingTable\"\nfidelity = \"kinematic\"\noutputs = [\"cam.rho\", \"cam.sigma_H\"]\n" => "outputs[1]", line 4: "it is at: kinetostatic, elastodynamic");
}

#[test]
fn an_elastodynamic_disc_knife_scene_lists_its_dynamic_outputs_and_states() {
    // (every mechanism now has all three levels: no level is left to refuse)
    let scene = Scene::parse(
        "name = \"t\"\nmechanism = \"DiscKnifeDrive\"\nfidelity = \"elastodynamic\"\noutputs = [\"knife.x\", \"elastic.F\"]\n",
    )
    .unwrap();
    let (_, t) = catalog::tailor(&scene).unwrap();
    for name in [
        "knife.x",
        "elastic.F",
        "elastic.k",
        "elastic.x",
        "der(elastic.x)",
    ] {
        assert!(
            t.variables.iter().any(|(_, v)| v.name == name),
            "{name} missing"
        );
    }
    // a kinematic scene cannot ask for the dynamic force
    refused!("name = \"t\"\nmechanism = \"DiscKnifeDrive\"\nfidelity = \"kinematic\"\noutputs = [\"elastic.F\"]\n" => "outputs[0]", line 4: "not computed at fidelity \"kinematic\"", "elastodynamic");
}

#[test]
fn bad_parameters_are_named() {
    /// The Geneva scene with `"name" = value` among its parameters is refused naming the
    /// parameter, on its line, with every one of `parts` in the message.
    #[track_caller]
    fn refused(name: &str, value: &str, parts: &[&str]) {
        let text = format!("{GENEVA}[parameters]\n\"{name}\" = {value}\n");
        assert_refused(&text, &format!("parameters.\"{name}\""), 6, parts);
    }
    refused("crank.radius", "0.07", &["no parameter", "crank.r"]);
    refused("knife.s", "0.07", &["not a parameter", "outputs"]);
    refused("model.fidelity", "2", &["`fidelity`"]);
    refused("drive.n", "2.0", &["[drive]"]);
    refused("crank.r", "\"long\"", &["Real"]);
    refused("geneva.Z", "4.5", &["Integer"]);
    refused("crank.r", "-0.07", &["crank.r", "at least 0"]);
    refused("geneva.Z", "2", &["geneva.Z"]);
    // the mechanism cannot assemble: rod shorter than the crank
    refused("crank.r", "0.5", &["refused by GenevaKnifeDrive"]);
    let sew = "name = \"t\"\nmechanism = \"SewingTable\"\nfidelity = \"kinematic\"\noutputs = [\"table.x\"]\n[parameters]\n\"law.forward\" = \"sine\"\n";
    refused!(sew => "parameters.\"law.forward\"", line 6: "cycloidal, harmonic, poly345");
}

const DRIVE: &str = r#"name = "d"
mechanism = "MainShaft"
outputs = ["shaft.phi", "shaft.w", "shaft.a", "motor.tau"]
[parameters]
"fly.J" = 30.0
"gear.i" = 50.0
"init.w" = 3.0
"#;

#[test]
fn a_drive_scene_sets_its_start_values_and_has_no_level_or_drive() {
    use crate::mechanisms::main_shaft::MainShaft;
    let t = tailor_text::<MainShaft>(DRIVE).unwrap();
    assert_eq!(t.identifier, "MainShaft_d");
    let start = |name: &str| {
        t.variables
            .iter()
            .find(|(_, v)| v.name == name)
            .and_then(|(_, v)| v.start)
    };
    assert_eq!(start("fly.J"), Some(30.0));
    assert_eq!(start("gear.i"), Some(50.0));
    assert_eq!(start("init.w"), Some(3.0));
    // untouched parameters keep the model's defaults: the drive's own common variables are not
    // overwritten by a level or a drive mode (it has none)
    let full = Values::<<MainShaft as Model>::Var>::start();
    for (vr, v) in &t.variables {
        if !["fly.J", "gear.i", "init.w"].contains(&v.name) {
            assert_eq!(
                t.start[*vr as usize],
                full.raw()[*vr as usize],
                "{}",
                v.name
            );
        }
    }
    // shaft.a depends on the loads: all load inputs are listed; the load of a plain coupling too
    let inputs = names_of(&t, |v| v.causality == Causality::Input);
    assert_eq!(inputs.len(), 7, "{inputs:?}");
    assert!(!t.info.description.contains("level"));
    assert!(t.model_description().contains("<ModelExchange"));
    // its outputs equal the full model's, bit for bit, over a start-up under a load
    let mut full = Values::<<MainShaft as Model>::Var>::start();
    full.raw_mut().copy_from_slice(&t.start);
    let mut tail = full.clone();
    tail.stages = t.stages;
    let (mut mf, mut mt) = (
        MainShaft::prepare(&full).unwrap(),
        MainShaft::prepare(&tail).unwrap(),
    );
    let tau0 = vr_named::<MainShaft>("load1.tau0");
    for k in 0..200 {
        let time = k as f64 * 1e-3;
        for v in [&mut full, &mut tail] {
            v.raw_mut()[tau0] = 50.0 * (7.0 * time).sin();
        }
        mf.evaluate(&mut full, time, &mut NoLog);
        mt.evaluate(&mut tail, time, &mut NoLog);
        for (vr, _) in &t.variables {
            let i = *vr as usize;
            assert_eq!(full.raw()[i].to_bits(), tail.raw()[i].to_bits());
        }
        mf.do_step(&mut full, time, 1e-3, &mut NoLog).unwrap();
        mt.do_step(&mut tail, time, 1e-3, &mut NoLog).unwrap();
    }
}

fn vr_named<M: Model>(name: &str) -> usize {
    <M::Var as VarSet>::table()
        .iter()
        .position(|v| v.name == name)
        .unwrap()
}

#[test]
fn an_input_driven_scene_can_set_its_phase_on_the_shaft() {
    let t = tailor_text::<GenevaKnifeDrive>(
        &(GENEVA.to_string() + "[drive]\nmode = \"input\"\nphi0 = 3.0\n"),
    )
    .unwrap();
    let phi0 = t.variables.iter().find(|(_, v)| v.name == "drive.phi0");
    assert_eq!(phi0.and_then(|(_, v)| v.start), Some(3.0));
    assert_eq!(
        t.start[shaft::MODE as usize],
        1.0,
        "still driven by the inputs"
    );
    assert!(t.variables.iter().any(|(_, v)| v.name == "shaft.phi"));
    assert!(!t.variables.iter().any(|(_, v)| v.name == "drive.n"));
    same_outputs::<GenevaKnifeDrive>(&t);
    // the knife is where an unshifted one is 3 rad further on
    let knife_s = |phi0: f64, phi: f64| {
        let mut v = Values::<<GenevaKnifeDrive as Model>::Var>::start();
        v.raw_mut().copy_from_slice(&t.start);
        v.raw_mut()[shaft::PHI0 as usize] = phi0;
        v.raw_mut()[shaft::PHI as usize] = phi;
        let mut m = GenevaKnifeDrive::prepare(&v).unwrap();
        m.evaluate(&mut v, 0.0, &mut NoLog);
        v.raw()[vr_named::<GenevaKnifeDrive>("knife.s")]
    };
    assert!((knife_s(3.0, 0.5) - knife_s(0.0, 3.5)).abs() < 1e-12);
    assert!((knife_s(3.0, 0.5) - knife_s(0.0, 0.5)).abs() > 1e-3);
    // without a phase, drive.phi0 is not listed (as before)
    let t = tailor_text::<GenevaKnifeDrive>(GENEVA).unwrap();
    assert!(!t.variables.iter().any(|(_, v)| v.name == "drive.phi0"));
}

#[test]
fn levels_and_drives_belong_to_mechanisms() {
    let e = refusal(&GENEVA.replace("fidelity = \"kinematic\"\n", ""));
    assert_eq!(e.key, "fidelity");
    assert!(
        e.message.contains("missing") && e.message.contains("GenevaKnifeDrive"),
        "{e}"
    );
    refused!(DRIVE.replace("outputs", "fidelity = \"kinematic\"\noutputs") => "fidelity", line 3: "MainShaft has no fidelity levels");
    refused!((DRIVE.to_string() + "[drive]\nmode = \"input\"\n") => "drive", line 8: "MainShaft drives the shaft itself");
    refused!((GENEVA.to_string() + "[drive]\nmode = \"input\"\nn = 30\n") => "drive.n", line 7: "constant_speed");
    refused!((GENEVA.to_string() + "[drive]\nmode = \"input\"\nphi0 = inf\n") => "drive.phi0", line 7: "finite");
}
