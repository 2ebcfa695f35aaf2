//! The panic probe: a cdylib built with the FMUs' build script (`fmus/build.rs`) and their
//! profile (`dist`: release, stripped) for one platform, whose `probe(x)` panics for x > 0 and must catch it, and the
//! tools to build it for another platform and run it there (`tests/c_host/probe.c` loads it the
//! way a host loads an FMU binary): natively, under qemu-user or under Wine.

use std::path::{Path, PathBuf};
use std::process::Command;

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A scratch folder under the system's temp dir, emptied.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bindery-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// How to build for a platform: the cargo subcommand (`build`, or `zigbuild` for cargo-zigbuild),
/// the target (none: native; cargo-zigbuild's may carry a glibc version, `….2.17`) and extra
/// environment (a linker).
pub struct Route<'a> {
    pub subcommand: &'a str,
    pub target: Option<&'a str>,
    pub env: &'a [(&'a str, &'a str)],
}

/// Builds the probe by `route` in its own folder and returns the library's path.
pub fn build(name: &str, route: &Route) -> PathBuf {
    let dir = scratch(&format!("panic-probe-{name}"));
    std::fs::create_dir_all(dir.join("src")).unwrap();
    std::fs::write(
        dir.join("Cargo.toml"),
        format!(
            "[package]\nname = \"panic-probe\"\nversion = \"0.1.0\"\nedition = \"2024\"\n\
             build = {:?}\n\n[lib]\ncrate-type = [\"cdylib\"]\n\n[profile.release]\n\
             panic = \"unwind\"\nstrip = \"symbols\"\n\n[workspace]\n",
            root().join("fmus/build.rs")
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
    let mut cmd = Command::new(cargo);
    cmd.args([route.subcommand, "--release", "--offline", "--quiet"])
        .current_dir(&dir)
        .env("CARGO_TARGET_DIR", dir.join("target"))
        .env_remove("RUSTFLAGS");
    if let Some(t) = route.target {
        cmd.args(["--target", t]);
    }
    for (k, v) in route.env {
        cmd.env(k, v);
    }
    let status = cmd
        .status()
        .unwrap_or_else(|e| panic!("cargo {}: {e}", route.subcommand));
    assert!(status.success(), "building the probe ({name}) failed");
    let triple = route
        .target
        .map(|t| t.split_once(".2").map_or(t, |(a, _)| a));
    let out = match triple {
        Some(t) => dir.join("target").join(t).join("release"),
        None => dir.join("target/release"),
    };
    let file = if triple.is_some_and(|t| t.contains("windows")) {
        "panic_probe.dll"
    } else {
        "libpanic_probe.so"
    };
    out.join(file)
}

/// Compiles `tests/c_host/<source>` with `compiler` (a C99 compiler of the platform) into `exe`.
pub fn compile_c(compiler: &str, source: &str, exe: &Path, libs: &[&str]) {
    let status = Command::new(compiler)
        .args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-O1", "-o"])
        .arg(exe)
        .arg(root().join("tests/c_host").join(source))
        .args(libs)
        .status()
        .unwrap_or_else(|e| panic!("{compiler} (needed to build the test host): {e}"));
    assert!(status.success(), "{compiler} {source} failed");
}

/// Runs `exe args...` through `runner` (empty: natively); returns stdout, asserting success.
pub fn run(runner: &[String], exe: &Path, args: &[&str]) -> String {
    let (program, pre) = match runner.split_first() {
        Some((p, rest)) => (p.clone(), rest.to_vec()),
        None => (exe.display().to_string(), vec![]),
    };
    let mut cmd = Command::new(&program);
    cmd.args(&pre);
    if !runner.is_empty() {
        cmd.arg(exe);
    }
    let out = cmd
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("{program}: {e}"));
    assert!(
        out.status.success(),
        "{program} {} {args:?}: {}\n{}",
        exe.display(),
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// qemu-user for aarch64 with Debian's aarch64 C library as the loader's root.
pub fn qemu_aarch64() -> Vec<String> {
    vec![
        "qemu-aarch64".into(),
        "-L".into(),
        "/usr/aarch64-linux-gnu".into(),
    ]
}

/// Wine with the project's test prefix (`tests/wine/prepare`, made once under `target/wine`).
pub fn wine() -> Vec<String> {
    static PREFIX: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    let dir = PREFIX.get_or_init(|| {
        let dir = root().join("target/wine");
        let out = Command::new(root().join("tests/wine/prepare"))
            .arg(&dir)
            .output()
            .expect("tests/wine/prepare");
        assert!(
            out.status.success(),
            "tests/wine/prepare: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        dir
    });
    vec![dir.join("bin/wine64").display().to_string()]
}

/// `path` as Wine's programs see it (drive Z: is the root of the Linux file system).
pub fn wine_path(path: &Path) -> String {
    format!("Z:{}", path.display()).replace('/', "\\")
}
