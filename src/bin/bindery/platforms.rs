//! The binaries of every platform an FMU carries ([`Platform`]): which toolchain builds which,
//! what is installed, and, for a platform whose toolchain is missing, the one command that
//! installs it.
//!
//! | platform | Rust target | linked by |
//! | --- | --- | --- |
//! | `linux64` | `x86_64-unknown-linux-gnu`, glibc 2.17 | `cargo zigbuild` (zig) |
//! | `aarch64-linux` | `aarch64-unknown-linux-gnu`, glibc 2.17 | `cargo zigbuild` (zig) |
//! | `win64` | `x86_64-pc-windows-gnu` | MinGW-w64's gcc |
//! | `darwin64` | `x86_64-apple-darwin` (macOS 10.12) and `aarch64-apple-darwin` (macOS 11), merged into one universal binary | `rust-lld` (Rust's own LLVM linker, ld64 flavour) |
//!
//! Every one is built with the profile `dist` (the release profile, stripped) into
//! `target/<triple>/dist/`. zig links against the glibc 2.17 of its own headers and stubs
//! (manylinux2014), so the Linux binaries load on every glibc since 2013. Without zig, `linux64`
//! is the native release build (`target/release/`) and needs this machine's glibc or newer.
//!
//! macOS needs no Apple SDK: `rust-lld` links against the text stub of the system library
//! (`libSystem.tbd`) that zig carries, in a stand-in SDK `target/macos-sdk`, honours the
//! export list (only the FMI functions; zig's Mach-O linker exports every symbol, which also
//! keeps all of them from dead-stripping: twice the size) and signs the arm64 slice ad hoc, as
//! Apple silicon requires of all code.

use bindery_fmu::package::{Binaries, Platform, universal_macho};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The build tools from PyPI (`pip install -r` this file): zig and cargo-zigbuild, pinned.
pub const ZIG_REQUIREMENTS: &str = include_str!("../../../tools/requirements.txt");

/// One Rust target of a platform: its triple (for cargo-zigbuild with the glibc version), the
/// environment its build needs, and the file name of a crate `lib` (`{}` = the library name).
struct Target {
    triple: &'static str,
    env: &'static [(&'static str, &'static str)],
    file: &'static str,
}

/// Who links a platform's binaries.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Linker {
    /// `cargo zigbuild`: zig cc.
    Zig,
    /// `cargo build` with the target's default linker, MinGW-w64's gcc.
    Mingw,
    /// `cargo build` with `rust-lld -flavor darwin` and zig's `libSystem.tbd`.
    RustLld,
}

/// How one platform is built.
struct Route {
    platform: Platform,
    /// One target, or two merged into a universal binary (darwin64).
    targets: &'static [Target],
    linker: Linker,
}

const ROUTES: [Route; 4] = [
    Route {
        platform: Platform::Linux64,
        targets: &[Target {
            triple: "x86_64-unknown-linux-gnu.2.17",
            env: &[],
            file: "lib{}.so",
        }],
        linker: Linker::Zig,
    },
    Route {
        platform: Platform::Aarch64Linux,
        targets: &[Target {
            triple: "aarch64-unknown-linux-gnu.2.17",
            env: &[],
            file: "lib{}.so",
        }],
        linker: Linker::Zig,
    },
    Route {
        platform: Platform::Win64,
        targets: &[Target {
            triple: "x86_64-pc-windows-gnu",
            env: &[],
            file: "{}.dll",
        }],
        linker: Linker::Mingw,
    },
    Route {
        platform: Platform::Darwin64,
        targets: &[
            Target {
                triple: "x86_64-apple-darwin",
                env: &[("MACOSX_DEPLOYMENT_TARGET", "10.12")],
                file: "lib{}.dylib",
            },
            Target {
                triple: "aarch64-apple-darwin",
                env: &[("MACOSX_DEPLOYMENT_TARGET", "11.0")],
                file: "lib{}.dylib",
            },
        ],
        linker: Linker::RustLld,
    },
];

/// The MinGW-w64 C compiler that links `x86_64-pc-windows-gnu` (Rust's default linker for it).
const MINGW_GCC: &str = "x86_64-w64-mingw32-gcc";

/// The text stub of macOS's system library in zig's library folder.
const LIBSYSTEM_TBD: &str = "libc/darwin/libSystem.tbd";

/// The Rust target without cargo-zigbuild's glibc suffix.
fn rust_triple(t: &str) -> &str {
    t.split_once(".2.").map_or(t, |(a, _)| a)
}

fn output(program: &str, args: &[&str]) -> Option<String> {
    let o = Command::new(program).args(args).output().ok()?;
    o.status
        .success()
        .then(|| String::from_utf8_lossy(&o.stdout).trim().to_string())
}

/// zig's library folder, from `zig env` (ZON since zig 0.15, JSON before).
fn zig_lib_dir() -> Option<PathBuf> {
    let env = output("zig", &["env"]).or_else(|| output("python3", &["-m", "ziglang", "env"]))?;
    let rest = &env[env.find("lib_dir")?..];
    let start = rest.find('"')? + 1;
    let end = start + rest[start..].find('"')?;
    Some(PathBuf::from(&rest[start..end]))
}

/// What this machine has for building each platform.
pub struct Toolchains {
    installed_targets: Vec<String>,
    /// zig's library folder (it holds `libc/darwin/libSystem.tbd`), when zig is here.
    zig_lib: Option<PathBuf>,
    cargo_zigbuild: bool,
    mingw: bool,
    /// Rust's own linker (rustup installs it with the toolchain).
    rust_lld: Option<PathBuf>,
}

impl Toolchains {
    pub fn probe() -> Toolchains {
        let sysroot = output("rustc", &["--print", "sysroot"]).map(PathBuf::from);
        let host = output("rustc", &["--print", "host-tuple"]).unwrap_or_default();
        let installed_targets = ROUTES
            .iter()
            .flat_map(|r| r.targets.iter().map(|t| rust_triple(t.triple)))
            .filter(|t| {
                sysroot
                    .as_ref()
                    .is_some_and(|s| s.join("lib/rustlib").join(t).join("lib").is_dir())
            })
            .map(String::from)
            .collect();
        let rust_lld = sysroot
            .as_ref()
            .map(|s| s.join("lib/rustlib").join(&host).join("bin/rust-lld"))
            .filter(|p| p.is_file());
        Toolchains {
            installed_targets,
            zig_lib: zig_lib_dir().filter(|d| d.join(LIBSYSTEM_TBD).is_file()),
            cargo_zigbuild: output("cargo-zigbuild", &["--version"]).is_some(),
            mingw: std::env::var_os("CARGO_TARGET_X86_64_PC_WINDOWS_GNU_LINKER").is_some()
                || output(MINGW_GCC, &["--version"]).is_some(),
            rust_lld,
        }
    }

    /// The one command that installs what `route` lacks, or None when it can be built.
    fn missing(&self, route: &Route) -> Option<String> {
        let mut steps = Vec::new();
        let targets: Vec<&str> = route
            .targets
            .iter()
            .map(|t| rust_triple(t.triple))
            .filter(|t| !self.installed_targets.iter().any(|i| i == t))
            .collect();
        if !targets.is_empty() {
            steps.push(format!("rustup target add {}", targets.join(" ")));
        }
        let zig_missing = match route.linker {
            Linker::Zig => self.zig_lib.is_none() || !self.cargo_zigbuild,
            Linker::RustLld => self.zig_lib.is_none(),
            Linker::Mingw => false,
        };
        if zig_missing {
            let pins: Vec<&str> = ZIG_REQUIREMENTS
                .lines()
                .map(str::trim)
                .filter(|l| !l.is_empty() && !l.starts_with('#'))
                .collect();
            steps.push(format!("pip install {}", pins.join(" ")));
        }
        if route.linker == Linker::Mingw && !self.mingw {
            steps.push("apt-get install gcc-mingw-w64-x86-64".into());
        }
        if route.linker == Linker::RustLld && self.rust_lld.is_none() {
            // rust-lld is part of every toolchain rustup installs
            steps.push("rustup toolchain install stable".into());
        }
        (!steps.is_empty()).then(|| steps.join(" && "))
    }
}

/// The platforms built by [`build`]: where each one's binaries are.
pub struct Built {
    target_dir: PathBuf,
    platforms: Vec<Platform>,
    /// `linux64` is the native release build (no zig here).
    native_linux64: bool,
}

/// Builds the `packages` (cdylib crates) for every platform whose toolchain is here. A platform
/// that cannot be built is skipped with the command that installs its toolchain, or, with
/// `require_all`, is an error. `linux64` is always there: without zig it is the native release
/// build (which the caller has made).
pub fn build(
    root: &Path,
    target_dir: &Path,
    packages: &[&str],
    require_all: bool,
) -> Result<Built, String> {
    let tools = Toolchains::probe();
    let mut built = Built {
        target_dir: target_dir.to_path_buf(),
        platforms: vec![],
        native_linux64: false,
    };
    let mut skipped = Vec::new();
    for route in &ROUTES {
        if let Some(install) = tools.missing(route) {
            let what = if route.platform == Platform::Linux64 {
                built.platforms.push(Platform::Linux64);
                built.native_linux64 = true;
                "built natively instead, for this machine's glibc or newer; for glibc 2.17"
            } else {
                "skipped"
            };
            eprintln!(
                "{}: {what}: install its toolchain with\n    {install}",
                route.platform.folder()
            );
            skipped.push(format!("{} ({install})", route.platform.folder()));
            continue;
        }
        for t in route.targets {
            compile(root, target_dir, &tools, route.linker, t, packages)?;
        }
        built.platforms.push(route.platform);
    }
    if require_all && !skipped.is_empty() {
        return Err(format!(
            "no toolchain for {} (--require-all)",
            skipped.join(", ")
        ));
    }
    built.platforms.sort();
    Ok(built)
}

/// A stand-in macOS SDK for `rust-lld`: `usr/lib/libSystem.tbd` from zig (libc and libm are
/// libSystem on macOS, as in Apple's SDK).
fn macos_sdk(target_dir: &Path, zig_lib: &Path) -> Result<PathBuf, String> {
    let sdk = target_dir.join("macos-sdk");
    let lib = sdk.join("usr/lib");
    std::fs::create_dir_all(&lib).map_err(|e| format!("{}: {e}", lib.display()))?;
    let tbd =
        std::fs::read(zig_lib.join(LIBSYSTEM_TBD)).map_err(|e| format!("{LIBSYSTEM_TBD}: {e}"))?;
    for name in ["libSystem.tbd", "libc.tbd", "libm.tbd"] {
        let path = lib.join(name);
        if std::fs::read(&path).ok().as_deref() != Some(tbd.as_slice()) {
            std::fs::write(&path, &tbd).map_err(|e| format!("{}: {e}", path.display()))?;
        }
    }
    Ok(sdk)
}

fn compile(
    root: &Path,
    target_dir: &Path,
    tools: &Toolchains,
    linker: Linker,
    t: &Target,
    packages: &[&str],
) -> Result<(), String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.current_dir(root)
        .arg(if linker == Linker::Zig {
            "zigbuild"
        } else {
            "build"
        })
        .args(["--profile", "dist", "--lib", "--target", t.triple]);
    for p in packages {
        cmd.args(["-p", p]);
    }
    for (k, v) in t.env {
        cmd.env(k, v);
    }
    if linker == Linker::RustLld {
        let (Some(lld), Some(zig_lib)) = (&tools.rust_lld, &tools.zig_lib) else {
            unreachable!("checked by Toolchains::missing")
        };
        let var = rust_triple(t.triple).replace('-', "_").to_uppercase();
        cmd.env(format!("CARGO_TARGET_{var}_LINKER"), lld)
            .env(
                format!("CARGO_TARGET_{var}_RUSTFLAGS"),
                "-C linker-flavor=ld64.lld",
            )
            .env("SDKROOT", macos_sdk(target_dir, zig_lib)?);
    }
    eprintln!(
        "compiling {} FMU binaries for {} (profile dist)...",
        packages.len(),
        t.triple
    );
    let status = cmd.status().map_err(|e| format!("cannot run cargo: {e}"))?;
    if !status.success() {
        return Err(format!(
            "cargo build of the FMU binaries for {} failed",
            t.triple
        ));
    }
    Ok(())
}

impl Built {
    /// Every platform's binary of the cdylib `lib` (its library name, the modelIdentifier).
    pub fn binaries_of(&self, lib: &str) -> Result<Binaries, String> {
        let read = |p: PathBuf| std::fs::read(&p).map_err(|e| format!("{}: {e}", p.display()));
        let mut out = Vec::new();
        for &platform in &self.platforms {
            if platform == Platform::Linux64 && self.native_linux64 {
                let so = self.target_dir.join("release").join(format!("lib{lib}.so"));
                out.push((platform, read(so)?));
                continue;
            }
            let route = ROUTES.iter().find(|r| r.platform == platform).unwrap();
            let files = route
                .targets
                .iter()
                .map(|t| {
                    read(
                        self.target_dir
                            .join(rust_triple(t.triple))
                            .join("dist")
                            .join(t.file.replace("{}", lib)),
                    )
                })
                .collect::<Result<Vec<_>, _>>()?;
            let bytes = if files.len() == 1 {
                files.into_iter().next().unwrap()
            } else {
                let slices: Vec<&[u8]> = files.iter().map(Vec::as_slice).collect();
                universal_macho(&slices)?
            };
            out.push((platform, bytes));
        }
        Ok(out)
    }
}
