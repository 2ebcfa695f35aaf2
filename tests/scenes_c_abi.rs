//! Tailored FMUs through the C ABI (`scenes.md`): the mechanism's own binary, given
//! `resources/scene.toml`, lists only the scene's variables, and its outputs equal the full
//! FMU's at the same parameters, bit for bit. Needs the built binaries
//! (`cargo run --release -- build`).

mod common;

use bindery_fmu::catalog;
use bindery_fmu::fmi2::types::*;
use bindery_fmu::model::{Causality, VarType, shaft};
use bindery_fmu::scene::{Drive, RESOURCE_NAME, Scene, Tailored};
use common::{Fmu, Slave};
use std::ffi::CString;
use std::path::{Path, PathBuf};

fn examples() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> =
        std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "toml"))
            .collect();
    files.sort();
    files
}

/// A temporary folder, removed when dropped.
struct TempDir(PathBuf);

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A resources folder holding `text` as scene.toml (removed when the guard drops), and its
/// file URI.
fn resources(tag: &str, text: &str) -> (TempDir, CString) {
    let dir = std::env::temp_dir().join(format!("bindery-scene-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(RESOURCE_NAME), text).unwrap();
    let uri = CString::new(format!("file://{}/", dir.display())).unwrap();
    (TempDir(dir), uri)
}

/// fmi2Instantiate (co-simulation) with a resource location; panics with the log if refused.
fn instantiate<'a>(fmu: &'a Fmu, guid: &str, uri: &CString) -> Option<Slave<'a>> {
    let (c, env) = fmu.instantiate_at(c"scene", FmuType::CoSimulation, guid, uri);
    if c.is_null() {
        let logs = common::logs_of(env);
        panic!("refused: {logs:?}");
    }
    Some(Slave { fmu, c, env })
}

/// The last error an instantiation with this GUID and scene logs (it must be refused).
fn refusal(fmu: &Fmu, guid: &str, uri: &CString) -> String {
    let (c, env) = fmu.instantiate_at(c"scene", FmuType::CoSimulation, guid, uri);
    assert!(c.is_null(), "instantiated");
    common::logs_of(env)
        .into_iter()
        .rev()
        .find(|l| l.0 == Status::Error)
        .map(|l| l.2)
        .unwrap_or_default()
}

/// Sets every parameter of the full FMU whose start differs from the tailored one's.
fn set_parameters(full: &Slave, t: &Tailored, table: &[bindery_fmu::model::Var]) {
    for (vr, v) in table.iter().enumerate() {
        let x = t.start[vr];
        if v.causality != Causality::Parameter || v.start == Some(x) {
            continue;
        }
        let vrs = [vr as u32];
        let st = match v.ty {
            VarType::Real => full.set_real(&vrs, &[x]),
            VarType::Integer | VarType::Enumeration(_) => full.set_integer(&vrs, &[x as i32]),
            VarType::Boolean => {
                let f: libloading::Symbol<
                    unsafe extern "C" fn(Component, *const u32, usize, *const Boolean) -> Status,
                > = full.fmu.sym("fmi2SetBoolean");
                unsafe { f(full.c, vrs.as_ptr(), 1, &(x as Boolean)) }
            }
        };
        assert_eq!(st, Status::Ok, "{} = {x}", v.name);
    }
}

/// Reads the exposed outputs of both as bit patterns.
fn outputs(s: &Slave, outs: &[(u32, VarType)]) -> Vec<u64> {
    outs.iter()
        .map(|&(vr, ty)| match ty {
            VarType::Real => {
                let (st, x) = s.get_real(&[vr]);
                assert_eq!(st, Status::Ok);
                x[0].to_bits()
            }
            VarType::Boolean => {
                let (st, x) = s.get_boolean(&[vr]);
                assert_eq!(st, Status::Ok);
                x[0] as u64
            }
            _ => {
                let (st, x) = s.get_integer(&[vr]);
                assert_eq!(st, Status::Ok);
                x[0] as u64
            }
        })
        .collect()
}

#[test]
fn every_example_scene_equals_the_full_fmu_bit_for_bit() {
    for path in examples() {
        let text = std::fs::read_to_string(&path).unwrap();
        let scene = Scene::parse(&text).unwrap();
        let (entry, t) = catalog::tailor(&scene).unwrap();
        let table: Vec<bindery_fmu::model::Var> = (entry.variables)()
            .into_iter()
            .map(|(_, v)| v.clone())
            .collect();
        let fmu = Fmu::of(&entry);
        let full = fmu.slave("full");
        let (_dir, uri) = resources(&t.identifier, &text);
        let tail = instantiate(&fmu, &t.guid, &uri).unwrap();
        set_parameters(&full, &t, &table);
        let stop = 0.3;
        for s in [&full, &tail] {
            assert_eq!(s.setup(0.0, Some(stop)), Status::Ok);
            assert_eq!(s.init(), Status::Ok, "{}: {}", t.identifier, s.last_error());
        }
        let outs: Vec<(u32, VarType)> = t
            .variables
            .iter()
            .filter(|(_, v)| {
                matches!(
                    v.causality,
                    Causality::Output | Causality::CalculatedParameter
                )
            })
            .map(|(vr, v)| (*vr, v.ty))
            .collect();
        let inputs: Vec<u32> = t
            .variables
            .iter()
            .filter(|(_, v)| v.causality == Causality::Input)
            .map(|(vr, _)| *vr)
            .collect();
        if matches!(scene.drive, Drive::ConstantSpeed { .. }) {
            assert!(
                !inputs
                    .iter()
                    .any(|&i| i == shaft::PHI || i == shaft::W || i == shaft::A),
                "{}: shaft inputs listed with a constant_speed drive",
                t.identifier
            );
        }
        let h = 1e-3;
        let n = (stop / h) as usize;
        for k in 0..n {
            let time = k as f64 * h;
            for &vr in &inputs {
                let x = match vr {
                    shaft::PHI => 0.4 + 11.0 * time + 3.0 * time * time,
                    shaft::W => 11.0 + 6.0 * time,
                    shaft::A => 6.0,
                    _ => 25.0 * (7.0 * time).sin(),
                };
                assert_eq!(full.set_real(&[vr], &[x]), Status::Ok);
                assert_eq!(tail.set_real(&[vr], &[x]), Status::Ok);
            }
            assert_eq!(
                outputs(&full, &outs),
                outputs(&tail, &outs),
                "{} at t = {time}",
                t.identifier
            );
            assert_eq!(full.do_step(time, h), Status::Ok);
            assert_eq!(tail.do_step(time, h), Status::Ok);
        }
        // what the scene leaves out is an unknown value reference of the tailored FMU
        let hidden = (0..table.len() as u32)
            .find(|&vr| !t.exposed[vr as usize] && table[vr as usize].ty == VarType::Real)
            .unwrap();
        let (st, _) = tail.get_real(&[hidden]);
        assert_eq!(st, Status::Error);
        assert!(
            tail.last_error().contains("is left out of")
                && tail.last_error().contains(table[hidden as usize].name),
            "{}",
            tail.last_error()
        );
        let (st, _) = full.get_real(&[hidden]);
        assert_eq!(st, Status::Ok);
    }
}

#[test]
fn a_scene_fmu_refuses_the_full_guid_and_a_bad_scene() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/geneva-side-knife-kinematics.toml"),
    )
    .unwrap();
    let entry = catalog::all()
        .into_iter()
        .find(|e| e.identifier == "GenevaKnifeDrive")
        .unwrap();
    let full_guid = (entry.describe)().1;
    let fmu = Fmu::load("GenevaKnifeDrive", &full_guid);
    let (_d, uri) = resources("guid", &text);
    let why = refusal(&fmu, &full_guid, &uri);
    assert!(
        why.contains("GUID") && why.contains("does not match"),
        "{why}"
    );
    // a scene file that names an output the mechanism does not have
    let bad = text.replace("\"knife.dwell\"", "\"knife.dwel\"");
    let (_d, uri) = resources("bad", &bad);
    let why = refusal(&fmu, &full_guid, &uri);
    assert!(
        why.contains("scene refused")
            && why.contains("line 5")
            && why.contains("outputs[2]")
            && why.contains("knife.dwell"),
        "{why}"
    );
    // a scene of another mechanism
    let other = text.replace("GenevaKnifeDrive", "SewingTable");
    let (_d, uri) = resources("other", &other);
    let why = refusal(&fmu, &full_guid, &uri);
    assert!(
        why.contains("mechanism") && why.contains("GenevaKnifeDrive"),
        "{why}"
    );
    // no scene: the full FMU, as before
    let (dir, uri) = resources("none", "");
    std::fs::remove_file(dir.0.join(RESOURCE_NAME)).unwrap();
    assert!(instantiate(&fmu, &full_guid, &uri).is_some());
}

#[test]
fn reset_and_fmu_states_keep_the_scene() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/perforators-ramp-contact.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let (entry, t) = catalog::tailor(&Scene::parse(&text).unwrap()).unwrap();
    let fmu = Fmu::of(&entry);
    let (_dir, uri) = resources("reset", &text);
    let s = instantiate(&fmu, &t.guid, &uri).unwrap();
    let vr = t
        .variables
        .iter()
        .find(|(_, v)| v.name == "roller.F")
        .map(|(vr, _)| *vr)
        .unwrap();
    let run = |s: &Slave, steps: usize| -> Vec<u64> {
        let mut out = vec![];
        for k in 0..steps {
            assert_eq!(s.do_step(k as f64 * 1e-3, 1e-3), Status::Ok);
            out.push(s.get_real(&[vr]).1[0].to_bits());
        }
        out
    };
    s.setup_and_init(0.0, None);
    let first = run(&s, 50);
    // a saved state restores the scene's run (its stages and start values included)
    let (mut saved, bytes) = s.save_state();
    let later = |s: &Slave| -> Vec<u64> {
        (50..80)
            .map(|k| {
                assert_eq!(s.do_step(k as f64 * 1e-3, 1e-3), Status::Ok);
                s.get_real(&[vr]).1[0].to_bits()
            })
            .collect()
    };
    let a = later(&s);
    assert_eq!(s.set_state(saved), Status::Ok);
    assert_eq!(later(&s), a);
    let mut back = s.deserialized(&bytes);
    assert_eq!(s.set_state(back), Status::Ok);
    assert_eq!(later(&s), a);
    assert_eq!(s.free_state(&mut saved), Status::Ok);
    assert_eq!(s.free_state(&mut back), Status::Ok);
    // reset: the scene's start values again, and still only its variables
    assert_eq!(s.call0("fmi2Reset"), Status::Ok);
    s.setup_and_init(0.0, None);
    assert_eq!(run(&s, 50), first);
    let hidden = shaft::PHI; // constant_speed: the shaft inputs are left out
    assert_eq!(s.set_real(&[hidden], &[1.0]), Status::Error);
    assert!(
        s.last_error()
            .contains("shaft.phi is left out of Perforators_ramp_contact")
    );
}

#[test]
fn a_scene_without_states_refuses_model_exchange() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/geneva-side-knife-kinematics.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let (entry, t) = catalog::tailor(&Scene::parse(&text).unwrap()).unwrap();
    let fmu = Fmu::of(&entry);
    let (_dir, uri) = resources("me", &text);
    let (c, env) = fmu.instantiate_at(c"me", FmuType::ModelExchange, &t.guid, &uri);
    assert!(c.is_null());
    let logs = common::logs_of(env);
    assert!(
        logs.iter()
            .any(|l| l.2.contains("provides Co-Simulation (1) only")),
        "{logs:?}"
    );
}
