//! Build script shared by every FMU crate (`build = "../build.rs"`).
//!
//! **Linux (GNU):** links libgcc's unwinder statically, so the FMU binary needs only the C
//! library, libm and the dynamic loader (`interface.md`: "nothing that links beyond the C
//! library and libm"). Rust's std asks the linker for `-lgcc_s` itself, so `-static-libgcc`
//! alone does not remove it. Instead a directory holding `libgcc_s.a` (a copy of gcc's static
//! `libgcc_eh.a`, the same unwinder) is put first on the library search path: `-lgcc_s` then
//! resolves to the archive and the unwinder (panic catching at the FMI boundary) is linked into
//! the binary, not loaded.
//!
//! The archive must come from the compiler that links *this target*: the linker cargo resolved
//! (`RUSTC_LINKER`, from `CARGO_TARGET_<TRIPLE>_LINKER` or `.cargo/config.toml`), else the
//! target's C compiler named the way the `cc` crate names it (`CC_<triple>`, `TARGET_CC`; `CC`
//! only for a native build), else `<arch>-linux-gnu-gcc` for a cross build and `cc` for a native
//! one. A host compiler's archive on a cross build's search path is skipped by the cross linker
//! as incompatible, which silently linked `libgcc_s.so.1` dynamically (issue 15); a compiler
//! that targets another architecture is now refused with a warning naming it.
//!
//! `cargo zigbuild` (the route `bindery build` takes for old-glibc Linux) links through `zig cc`,
//! which resolves `-lgcc_s` to zig's own static libunwind: nothing to do there.
//!
//! **macOS:** sets the dylib's install name to `@rpath/<modelIdentifier>.dylib` instead of the
//! absolute path of the build folder (hosts load the binary by its path; the name only must not
//! leak the build machine's folders).
//!
//! `tests/static_link.rs` checks the result with the binaries' link dependencies and a caught
//! panic, natively and for a cross build to aarch64.
use std::path::{Path, PathBuf};
use std::process::Command;

fn env(name: &str) -> Option<String> {
    println!("cargo:rerun-if-env-changed={name}");
    std::env::var(name).ok().filter(|v| !v.is_empty())
}

fn main() {
    println!("cargo:rerun-if-changed=../build.rs");
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    let target_env = std::env::var("CARGO_CFG_TARGET_ENV").unwrap_or_default();
    match (os.as_str(), target_env.as_str()) {
        ("linux", "gnu") => static_unwinder(),
        ("macos", _) => install_name(),
        _ => {}
    }
}

/// The FMU's modelIdentifier: its crate folder's name (`fmus/<modelIdentifier>/`).
fn model_identifier() -> Option<String> {
    let dir = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").ok()?);
    Some(dir.file_name()?.to_str()?.to_string())
}

fn install_name() {
    let Some(id) = model_identifier() else {
        return;
    };
    // the linker itself (`-C linker-flavor=ld64.lld`, as `bindery build` links) takes the
    // option as two arguments; a C compiler driver as one -Wl, argument
    let flags = std::env::var("CARGO_ENCODED_RUSTFLAGS").unwrap_or_default();
    if flags.contains("linker-flavor=ld64.lld") || flags.contains("linker-flavor=darwin-lld") {
        println!("cargo:rustc-cdylib-link-arg=-install_name");
        println!("cargo:rustc-cdylib-link-arg=@rpath/{id}.dylib");
    } else {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-install_name,@rpath/{id}.dylib");
    }
}

/// The C compiler that links this target (see the module documentation).
fn target_compiler() -> String {
    let target = std::env::var("TARGET").unwrap_or_default();
    let host = std::env::var("HOST").unwrap_or_default();
    let named = [
        "RUSTC_LINKER".to_string(),
        format!("CC_{target}"),
        format!("CC_{}", target.replace('-', "_")),
        "TARGET_CC".to_string(),
    ];
    if let Some(cc) = named.iter().find_map(|v| env(v)) {
        return cc;
    }
    if target == host {
        env("CC").unwrap_or_else(|| "cc".into())
    } else {
        let arch = std::env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
        format!("{arch}-linux-gnu-gcc")
    }
}

fn output(cc: &str, arg: &str) -> Option<String> {
    let out = Command::new(cc).arg(arg).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn static_unwinder() {
    let cc = target_compiler();
    let name = Path::new(&cc)
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    if name.contains("zig") {
        return; // zig cc links its static libunwind for -lgcc_s
    }
    let arch = std::env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let Some(machine) = output(&cc, "-dumpmachine") else {
        println!("cargo:warning=cannot run {cc}: the FMU binary will need libgcc_s.so.1");
        return;
    };
    if !machine.starts_with(&format!("{arch}-")) {
        println!(
            "cargo:warning={cc} targets {machine}, not {arch}: its static unwinder cannot be \
             linked and the FMU binary would need libgcc_s.so.1; name the target's linker with \
             CARGO_TARGET_<TRIPLE>_LINKER (e.g. {arch}-linux-gnu-gcc)"
        );
        return;
    }
    let eh = PathBuf::from(output(&cc, "-print-file-name=libgcc_eh.a").unwrap_or_default());
    if !eh.is_absolute() || !eh.exists() {
        println!(
            "cargo:warning={cc}: libgcc_eh.a not found: the FMU binary will need libgcc_s.so.1"
        );
        return;
    }
    let dir = PathBuf::from(std::env::var("OUT_DIR").expect("OUT_DIR")).join("static-libgcc");
    std::fs::create_dir_all(&dir).expect("create OUT_DIR/static-libgcc");
    std::fs::copy(&eh, dir.join("libgcc_s.a")).expect("copy libgcc_eh.a");
    println!("cargo:rustc-link-search=native={}", dir.display());
    println!("cargo:rustc-cdylib-link-arg=-static-libgcc");
}
