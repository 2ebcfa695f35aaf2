//! The FMU binaries link nothing beyond the C library, libm and the loader (interface.md), and
//! panics are still caught with the unwinder linked statically by `fmus/build.rs` (issue 7), also
//! in a cross build to aarch64 with the GNU toolchain (issue 15).

mod common;

use common::probe;

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
    let so = probe::build(
        "native",
        &probe::Route {
            subcommand: "build",
            target: None,
            env: &[],
        },
    );
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
}

/// A cross build with Debian's GNU toolchain for aarch64 (the linker named the usual way,
/// `CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER`): the build script takes the unwinder of that
/// linker, not the host's `cc`, so the binary needs no `libgcc_s.so.1` (it did: the host's
/// x86-64 archive was skipped as incompatible and the shared library linked instead), and the
/// panic is caught when the library runs on aarch64 (qemu-user).
#[test]
fn a_cross_build_to_aarch64_links_the_unwinder_statically() {
    let so = probe::build(
        "aarch64-gcc",
        &probe::Route {
            subcommand: "build",
            target: Some("aarch64-unknown-linux-gnu"),
            env: &[(
                "CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER",
                "aarch64-linux-gnu-gcc",
            )],
        },
    );
    let n = needed(&so);
    assert!(n.contains(&"libc.so.6".to_string()), "{n:?}");
    assert!(!n.iter().any(|l| l.contains("gcc")), "{n:?}");
    let host = so.with_file_name("probe-host");
    probe::compile_c("aarch64-linux-gnu-gcc", "probe.c", &host, &["-ldl"]);
    let out = probe::run(&probe::qemu_aarch64(), &host, &[so.to_str().unwrap()]);
    assert_eq!(
        out.trim(),
        "0 -1 -1",
        "probe(0), probe(1), probe(2) on aarch64"
    );
}
