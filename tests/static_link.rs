//! The FMU binaries link nothing beyond the C library, libm and the loader (interface.md), and
//! panics are still caught with the unwinder linked statically by `fmus/build.rs` (issue 7).

mod common;

use bindery_fmu::catalog;
use std::path::Path;
use std::process::Command;

const ALLOWED: [&str; 3] = ["libc.so.6", "libm.so.6", "ld-linux-x86-64.so.2"];

/// DT_NEEDED entries, read with `readelf -d`.
fn needed(so: &Path) -> Vec<String> {
    let out = Command::new("readelf")
        .arg("-d")
        .arg(so)
        .output()
        .expect("readelf (binutils) is needed");
    assert!(out.status.success(), "readelf -d {}", so.display());
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter(|l| l.contains("(NEEDED)"))
        .filter_map(|l| Some(l.split('[').nth(1)?.trim_end_matches(']').to_string()))
        .collect()
}

#[test]
fn fmu_binaries_need_only_libc_libm_and_the_loader() {
    for e in catalog::all() {
        let so = common::binary_path(e.identifier);
        let n = needed(&so);
        assert!(!n.is_empty(), "{}: no NEEDED entries?", so.display());
        for lib in &n {
            assert!(
                ALLOWED.contains(&lib.as_str()),
                "{} needs {lib} (only {ALLOWED:?} are allowed)",
                so.display()
            );
        }
    }
}

#[test]
fn every_fmu_crate_uses_the_shared_build_script() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for e in catalog::all() {
        let toml = std::fs::read_to_string(root.join("fmus").join(e.identifier).join("Cargo.toml"))
            .unwrap();
        assert!(
            toml.lines().any(|l| l.trim() == r#"build = "../build.rs""#),
            "fmus/{}/Cargo.toml: add build = \"../build.rs\"",
            e.identifier
        );
    }
}

/// A cdylib built with the same build script catches a panic: the statically linked unwinder
/// works inside a shared library loaded by a host.
#[test]
fn a_panic_is_caught_with_the_static_unwinder() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("bindery-panic-probe-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("src")).unwrap();
    std::fs::write(
        dir.join("Cargo.toml"),
        format!(
            "[package]\nname = \"panic-probe\"\nversion = \"0.1.0\"\nedition = \"2024\"\n\
             build = {:?}\n\n[lib]\ncrate-type = [\"cdylib\"]\n\n[profile.release]\n\
             panic = \"unwind\"\n\n[workspace]\n",
            root.join("fmus/build.rs")
        ),
    )
    .unwrap();
    std::fs::write(
        dir.join("src/lib.rs"),
        "#[unsafe(no_mangle)]\npub extern \"C\" fn probe(x: i32) -> i32 {\n    \
         std::panic::set_hook(Box::new(|_| {}));\n    \
         std::panic::catch_unwind(|| if x > 0 { panic!(\"probe {x}\") } else { x })\
         .unwrap_or(-1)\n}\n",
    )
    .unwrap();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .args(["build", "--release", "--offline", "--quiet"])
        .current_dir(&dir)
        .env("CARGO_TARGET_DIR", dir.join("target"))
        .env_remove("RUSTFLAGS")
        .status()
        .unwrap();
    assert!(status.success(), "building the probe failed");
    let so = dir.join("target/release/libpanic_probe.so");
    let n = needed(&so);
    assert!(!n.iter().any(|l| l.contains("gcc")), "{n:?}");
    // SAFETY: the probe has no constructors; `probe` has this signature.
    unsafe {
        let lib = libloading::Library::new(&so).unwrap();
        let probe: libloading::Symbol<extern "C" fn(i32) -> i32> = lib.get(b"probe").unwrap();
        assert_eq!(probe(0), 0);
        assert_eq!(probe(1), -1, "the panic was caught");
        assert_eq!(probe(2), -1, "and again");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
