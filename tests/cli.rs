//! The CLI as a new user meets it (issue 16): it works in the checkout of the current folder (or
//! `--root`), never in the folder it was compiled in; relative `--out` paths are the current
//! folder's; every name is checked against the catalog with the valid ones listed; a log that is
//! not a terminal names each file written; `liftoff` takes any parameter in display units and
//! says which case holds; bad values are refused naming the bounds.

use bindery_fmu::catalog;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs `bindery args` in `dir` (stdout and stderr are pipes, not a terminal): (success, stdout,
/// stderr).
fn bindery(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_bindery"))
        .current_dir(dir)
        .args(args)
        .envs(env.iter().copied())
        .output()
        .expect("run bindery");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A fresh, empty folder of this test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bindery-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A folder that looks like a checkout (`Cargo.toml`, `modelDescription/`), with `sub/deeper/`.
fn fake_checkout(name: &str) -> PathBuf {
    let dir = scratch(name);
    std::fs::write(dir.join("Cargo.toml"), "").unwrap();
    std::fs::create_dir_all(dir.join("modelDescription")).unwrap();
    std::fs::create_dir_all(dir.join("sub/deeper")).unwrap();
    dir
}

#[test]
fn the_checkout_is_found_from_the_current_folder() {
    let root = fake_checkout("root");
    let (ok, _, err) = bindery(&root.join("sub/deeper"), &["describe"], &[]);
    assert!(ok, "{err}");
    for e in catalog::all() {
        let path = root
            .join("modelDescription")
            .join(format!("{}.xml", e.identifier));
        let written = std::fs::read_to_string(&path).unwrap_or_else(|_| {
            panic!(
                "{} not written (the compile-time checkout instead?): {err}",
                path.display()
            )
        });
        assert_eq!(written, (e.describe)().0);
        assert!(err.contains(&format!("wrote {}", path.display())), "{err}");
    }
    // the same folder through --root, from a folder outside any checkout
    let outside = scratch("outside");
    let (ok, _, err) = bindery(&outside, &["describe", "--check"], &[]);
    assert!(
        !ok && err.contains("not inside a bindery-fmu checkout") && err.contains("--root"),
        "{err}"
    );
    let r = root.to_str().unwrap();
    let (ok, _, err) = bindery(&outside, &["--root", r, "describe", "--check"], &[]);
    assert!(ok, "{err}");
    let (ok, _, err) = bindery(
        &outside,
        &["describe", "--check", "--root", outside.to_str().unwrap()],
        &[],
    );
    assert!(!ok && err.contains("not a bindery-fmu checkout"), "{err}");
}

#[test]
fn relative_out_is_the_current_folders_and_the_default_the_checkouts() {
    let root = fake_checkout("out");
    let here = root.join("sub");
    let (ok, _, err) = bindery(&here, &["docs", "--out", "pages"], &[]);
    assert!(ok, "{err}");
    let page = here.join("pages/GenevaKnifeDrive/index.html");
    assert!(page.is_file(), "{} missing: {err}", page.display());
    assert!(
        err.contains(&format!(
            "wrote {}",
            here.join("pages/GenevaKnifeDrive").display()
        )),
        "{err}"
    );
    let (ok, _, err) = bindery(&root.join("sub/deeper"), &["docs"], &[]);
    assert!(ok, "{err}");
    assert!(
        root.join("out/docs/MainShaft/index.html").is_file(),
        "{err}"
    );
    // outside a checkout, the default needs one; an --out does not
    let outside = scratch("out-outside");
    let (ok, _, err) = bindery(&outside, &["docs"], &[]);
    assert!(!ok && err.contains("--out"), "{err}");
}

#[test]
fn build_names_each_fmu_it_writes_with_its_size() {
    // the FMU binaries are those already built (`cargo run --release -- build`); `CARGO=true`
    // stands in for the compile step
    let here = scratch("build");
    let root = env!("CARGO_MANIFEST_DIR");
    let (ok, _, err) = bindery(
        &here,
        &[
            "--root",
            root,
            "build",
            "GenevaKnifeDrive",
            "MainShaft",
            "--out",
            "fmus",
        ],
        &[("CARGO", "true")],
    );
    assert!(ok, "{err}");
    for id in ["GenevaKnifeDrive", "MainShaft"] {
        let path = here.join("fmus").join(format!("{id}.fmu"));
        let size = std::fs::metadata(&path)
            .unwrap_or_else(|e| panic!("{}: {e}; {err}", path.display()))
            .len();
        let line = format!("wrote {} ({size} bytes)", path.display());
        assert!(err.contains(&line), "{line:?} not in {err}");
    }
    assert!(!here.join("fmus/SewingTable.fmu").exists());
}

/// The `modelDescription.xml` inside an `.fmu`.
fn packaged_description(fmu: &Path) -> String {
    use std::io::Read;
    let file = std::fs::File::open(fmu).unwrap();
    let mut zip = zip::ZipArchive::new(file).unwrap();
    let mut xml = String::new();
    zip.by_name("modelDescription.xml")
        .unwrap()
        .read_to_string(&mut xml)
        .unwrap();
    xml
}

#[test]
fn a_build_is_dated_by_its_commit_and_reproducible() {
    let here = scratch("dated");
    let root = env!("CARGO_MANIFEST_DIR");
    let build = |out: &str, env: &[(&str, &str)]| {
        let mut all = vec![("CARGO", "true")];
        all.extend_from_slice(env);
        let (ok, _, err) = bindery(
            &here,
            &["--root", root, "build", "MainShaft", "--out", out],
            &all,
        );
        assert!(ok, "{err}");
        (
            std::fs::read(here.join(out).join("MainShaft.fmu")).unwrap(),
            err,
        )
    };
    let epoch = [("SOURCE_DATE_EPOCH", "1700000000")];
    let (a, err) = build("a", &epoch);
    let (b, _) = build("b", &epoch);
    assert!(a == b, "same commit date, same bytes");
    assert!(
        err.contains("generationDateAndTime 2023-11-14T22:13:20Z (SOURCE_DATE_EPOCH)"),
        "{err}"
    );
    let xml = packaged_description(&here.join("a/MainShaft.fmu"));
    let (committed, guid) =
        bindery_fmu::md::describe::<bindery_fmu::mechanisms::main_shaft::MainShaft>();
    assert_eq!(
        xml,
        bindery_fmu::md::stamp(&committed, "2023-11-14T22:13:20Z")
    );
    assert!(xml.contains(&format!("guid=\"{guid}\"")));
    // without SOURCE_DATE_EPOCH: the checkout's commit, as git tells it
    let git = Command::new("git")
        .args(["-C", root, "log", "-1", "--format=%ct"])
        .output()
        .expect("git");
    let secs: i64 = String::from_utf8_lossy(&git.stdout)
        .trim()
        .parse()
        .expect("a commit");
    let (_, err) = build("c", &[]);
    let date = bindery_fmu::md::date_time(secs);
    assert!(
        err.contains(&format!(
            "generationDateAndTime {date} (the date of commit "
        )),
        "{err}"
    );
    assert!(
        packaged_description(&here.join("c/MainShaft.fmu"))
            .contains(&format!("generationDateAndTime=\"{date}\""))
    );
}

#[test]
fn names_are_checked_against_the_catalog() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mechanisms = "GenevaKnifeDrive, SewingTable, Perforators, DiscKnifeDrive";
    for (args, want) in [
        (
            vec!["build", "Geneva"],
            vec!["unknown model \"Geneva\"", mechanisms, "MainShaft"],
        ),
        (
            vec!["report", "--only", "Geneva"],
            vec!["unknown mechanism \"Geneva\"", mechanisms],
        ),
        (
            vec!["report", "--only", "GenevaKnifeDrive,MainShaft"],
            vec!["MainShaft has no elastodynamic level", mechanisms],
        ),
        (
            vec!["scene", "geneva-cut-force"],
            vec![
                "no such scene file",
                "geneva-cut-forces, geneva-side-knife-kinematics",
            ],
        ),
        (
            vec!["machines", "--machine", "Trimmer"],
            vec![
                "unknown machine \"Trimmer\"",
                "ThreadSewingMachine, ThreeKnifeTrimmer, ThreadSewingMachineLegacy",
            ],
        ),
    ] {
        let (ok, _, err) = bindery(root, &args, &[("CARGO", "false")]);
        assert!(!ok, "{args:?} accepted");
        for w in want {
            assert!(err.contains(w), "{args:?}: {w:?} not in {err}");
        }
        assert!(
            !err.contains("compiling"),
            "{args:?}: refused before compiling: {err}"
        );
    }
}

/// `bindery liftoff args`: (success, stdout, stderr), run outside any checkout.
fn liftoff(args: &[&str]) -> (bool, String, String) {
    let mut all = vec!["liftoff"];
    all.extend_from_slice(args);
    bindery(&std::env::temp_dir(), &all, &[])
}

/// The threshold speed `liftoff` prints, rpm.
fn threshold(stdout: &str) -> f64 {
    stdout
        .split("lifts off the ramp above ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no threshold in {stdout:?}"))
}

#[test]
fn liftoff_says_which_case_holds() {
    let (ok, out, err) = liftoff(&["--m0", "3", "--kt", "10"]);
    assert!(ok, "{err}");
    assert!(out.contains("lifts off already at 100 rpm"), "{out}");
    let (ok, out, err) = liftoff(&["--m0", "3", "--kt", "10", "--from", "10"]);
    assert!(ok, "{err}");
    let n = threshold(&out);
    assert!(n > 10.0 && n < 100.0, "{out}");
    let (ok, out, err) = liftoff(&["--to", "110"]);
    assert!(ok, "{err}");
    assert!(out.contains("no lift-off up to 110 rpm"), "{out}");
}

#[test]
fn liftoff_takes_any_parameter_in_its_display_unit() {
    let (_, default, _) = liftoff(&[]);
    // cycle.forward is in rad, displayed in deg: 90 means 90 deg, as does 1.5708 rad
    let (ok, deg, err) = liftoff(&["--set", "cycle.forward=90"]);
    assert!(ok, "{err}");
    let (ok, rad, err) = liftoff(&["--set", "cycle.forward=1.5707963267948966rad"]);
    assert!(ok, "{err}");
    assert!(deg.contains("cycle.forward = 90 deg (1.5708 rad)"), "{deg}");
    assert_eq!(threshold(&deg), threshold(&rad));
    // a longer forward travel is slower: the roller stays on to a higher speed
    assert!(
        threshold(&deg) > threshold(&default) + 1.0,
        "{deg} {default}"
    );
}

#[test]
fn bad_values_are_refused_naming_the_bounds() {
    for (args, want) in [
        (vec!["--m0=-1"], "spring.M0 = -1 is below its minimum 0 N.m"),
        (
            vec!["--m0", "-1"],
            "spring.M0 = -1 is below its minimum 0 N.m",
        ),
        (
            vec!["--set", "spring.kt=stiff"],
            "spring.kt = \"stiff\": not a finite number",
        ),
        (vec!["--set", "spring.kt=nan"], "not a finite number"),
        (
            vec!["--set", "law.rise=smooth"],
            "law.rise = \"smooth\": not one of",
        ),
        (
            vec!["--set", "cycle.forward=90rpm"],
            "rpm is not a unit of cycle.forward; give it in deg or rad",
        ),
        (vec!["--set", "spring"], "want NAME=VALUE"),
        (
            vec!["--set", "roller.F=1"],
            "roller.F is not a parameter of Perforators",
        ),
        (
            vec!["--set", "drive.n=120"],
            "the search sets the speed itself",
        ),
        (vec!["--from", "200", "--to", "100"], "want 0 < from < to"),
    ] {
        let (ok, _, err) = liftoff(&args);
        assert!(!ok, "{args:?} accepted");
        assert!(err.contains(want), "{args:?}: {want:?} not in {err}");
    }
    let outside = std::env::temp_dir();
    for (args, want) in [
        (
            vec!["machines", "--flywheel=-1"],
            "fly.J = -1 is below its minimum 0 kg.m2",
        ),
        (
            vec!["machines", "--rpm", "0"],
            "--rpm 0: want a speed above 0 rpm",
        ),
        (
            vec!["machines", "--set", "motor.s_rated=2"],
            "motor.s_rated = 2 is above its maximum 1",
        ),
    ] {
        let (ok, _, err) = bindery(&outside, &args, &[]);
        assert!(!ok, "{args:?} accepted");
        assert!(err.contains(want), "{args:?}: {want:?} not in {err}");
    }
}

#[test]
fn needles_compares_the_two_drives_at_equal_needle_motion() {
    let dir = scratch("needles");
    let (ok, out, err) = bindery(&dir, &["needles", "--out", "n"], &[]);
    assert!(ok, "{err}");
    // equal needle motion: the same stroke, a ratio of 1
    assert!(
        out.contains("| needle stroke | mm | 30 | 30 | 1 |"),
        "{out}"
    );
    for row in [
        "peak roller force",
        "peak Hertz stress",
        "peak shaft torque",
        "RMS shaft torque",
    ] {
        assert!(out.contains(row), "{row}: {out}");
    }
    assert!(
        out.contains("from 0.48 to 1 lowers the largest Hertz stress"),
        "{out}"
    );
    for f in [
        "needles.md",
        "torque.png",
        "roller_force.png",
        "sigma_H.png",
        "beta_study.png",
    ] {
        assert!(dir.join("n").join(f).is_file(), "{f}: {err}");
    }
    assert!(err.contains("wrote"), "{err}");
    // a spring-closed cam: the pull is said with its shaft angle
    let (ok, out, err) = bindery(
        &dir,
        &["needles", "--out", "n", "--set", "cam.closure=spring"],
        &[],
    );
    assert!(
        ok && out.contains("would have to pull the roller"),
        "{out}{err}"
    );
    // what the comparison sets itself, a bad speed and an undercut cam are refused by name
    for (args, why) in [
        (
            &["needles", "--set", "needle.timing=own"][..],
            "needle.timing",
        ),
        (&["needles", "--rpm", "0"][..], "--rpm"),
        (
            &["needles", "--set", "kmk.beta=1"][..],
            "undercut at shaft angle",
        ),
    ] {
        let (ok, _, err) = bindery(&dir, args, &[]);
        assert!(!ok && err.contains(why), "{args:?}: {err}");
    }
}
