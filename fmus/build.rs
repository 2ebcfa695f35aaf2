//! Build script shared by every FMU crate (`build = "../build.rs"`): links libgcc's unwinder
//! statically, so the FMU binary needs only the C library, libm and the dynamic loader
//! (`interface.md`: "nothing that links beyond the C library and libm").
//!
//! Rust's std asks the linker for `-lgcc_s` itself, so `-static-libgcc` alone does not remove
//! it. Instead a directory holding `libgcc_s.a` (a copy of gcc's static `libgcc_eh.a`, the same
//! unwinder) is put first on the library search path: `-lgcc_s` then resolves to the archive and
//! the unwinder (panic catching at the FMI boundary) is linked into the binary, not loaded.
//! `tests/static_link.rs` checks the result with `readelf -d` and a caught panic.
use std::path::PathBuf;
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=../build.rs");
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    let env = std::env::var("CARGO_CFG_TARGET_ENV").unwrap_or_default();
    if os != "linux" || env != "gnu" {
        return;
    }
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let Ok(out) = Command::new(&cc)
        .arg("-print-file-name=libgcc_eh.a")
        .output()
    else {
        println!("cargo:warning=cannot run {cc}: the FMU binary will need libgcc_s.so.1");
        return;
    };
    let eh = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    if !eh.is_absolute() || !eh.exists() {
        println!("cargo:warning=libgcc_eh.a not found: the FMU binary will need libgcc_s.so.1");
        return;
    }
    let dir = PathBuf::from(std::env::var("OUT_DIR").expect("OUT_DIR")).join("static-libgcc");
    std::fs::create_dir_all(&dir).expect("create OUT_DIR/static-libgcc");
    std::fs::copy(&eh, dir.join("libgcc_s.a")).expect("copy libgcc_eh.a");
    println!("cargo:rustc-link-search=native={}", dir.display());
    println!("cargo:rustc-cdylib-link-arg=-static-libgcc");
}
