//! `bindery scene` refuses a bad scene file before compiling anything, naming the file, the
//! line, the key and the valid choices.

use std::process::Command;

fn export(name: &str, text: &str) -> (bool, String) {
    // a folder per call (the tests run in parallel), removed after the export
    let dir = std::env::temp_dir().join(format!("bindery-scene-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(name);
    std::fs::write(&file, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_bindery"))
        .args([
            "scene",
            file.to_str().unwrap(),
            "--out",
            dir.join("out").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn unknown_mechanism_is_refused_with_the_mechanisms() {
    let (ok, err) = export(
        "bad-mechanism.toml",
        "name = \"x\"\nmechanism = \"GenevaDrive\"\nfidelity = \"kinematic\"\noutputs = [\"knife.s\"]\n",
    );
    assert!(!ok);
    for part in [
        "bad-mechanism.toml: line 2: `mechanism`",
        "unknown mechanism \"GenevaDrive\"",
        "GenevaKnifeDrive, SewingTable, Perforators, DiscKnifeDrive",
    ] {
        assert!(err.contains(part), "{part:?} not in {err}");
    }
    assert!(
        !err.contains("compiling"),
        "refused before compiling: {err}"
    );
}

#[test]
fn an_output_of_another_level_is_refused_naming_the_level() {
    let (ok, err) = export(
        "bad-output.toml",
        "name = \"x\"\nmechanism = \"DiscKnifeDrive\"\nfidelity = \"kinematic\"\noutputs = [\"knife.x\",\n  \"rod.F\"]\n",
    );
    assert!(!ok);
    assert!(
        err.contains("bad-output.toml: line 5: `outputs[1]`")
            && err.contains("it is at: kinetostatic"),
        "{err}"
    );
}
