//! Every FMU the build wrote (full, tailored scenes, and those inside the SSP files) carries a
//! binary for every platform (`Platform::ALL`), and each binary is what its platform's hosts need,
//! read from the binary itself (the `object` crate; issue 15):
//! - `linux64`, `aarch64-linux`: ELF of the right machine, needing only glibc's own libraries
//!   and no symbol version newer than GLIBC_2.17 (manylinux2014), stripped;
//! - `win64`: a PE32+ DLL for x86-64 importing only Windows 10's system DLLs, stripped;
//! - `darwin64`: one universal binary with an x86-64 slice (macOS 10.12) and an arm64 slice
//!   (macOS 11, code-signed as Apple silicon requires), install name `@rpath/<id>.dylib`,
//!   linking only libSystem;
//!
//! and all export every FMI 2.0 co-simulation function. Panics are caught on every platform that
//! runs here: the panic probe built by each route runs natively (x86-64, glibc 2.17 route),
//! under qemu-user (aarch64) and under Wine (win64).
//!
//! Needs the binaries of every platform: `tests/run` installs the toolchains and builds with
//! `--require-all`; a build that skipped a platform fails here, naming it.

mod common;

use bindery_fmu::catalog;
use bindery_fmu::package::Platform;
use common::{FMI2_CS_FUNCTIONS, probe};
use object::macho;
use object::read::macho::{FatArch, MachOFatFile32, MachOFile64};
use object::{Architecture, Endianness, Object};
use std::io::Read;
use std::path::{Path, PathBuf};

fn out(dir: &str) -> PathBuf {
    probe::root().join("out").join(dir)
}

fn files(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    v.retain(|p| p.extension().is_some_and(|x| x == ext));
    v.sort();
    v
}

fn entry(zip: &mut zip::ZipArchive<std::io::Cursor<Vec<u8>>>, name: &str) -> Option<Vec<u8>> {
    let mut f = zip.by_name(name).ok()?;
    let mut b = Vec::new();
    f.read_to_end(&mut b).unwrap();
    Some(b)
}

/// An FMU: where it is (for messages), its modelIdentifier, and its archive.
struct Fmu {
    name: String,
    id: String,
    zip: zip::ZipArchive<std::io::Cursor<Vec<u8>>>,
}

impl Fmu {
    fn of(name: String, bytes: Vec<u8>) -> Fmu {
        let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
        let md = String::from_utf8(entry(&mut zip, "modelDescription.xml").unwrap()).unwrap();
        let at = md.find("modelIdentifier=\"").expect("modelIdentifier") + 17;
        let id = md[at..at + md[at..].find('"').unwrap()].to_string();
        Fmu { name, id, zip }
    }

    fn binary(&mut self, p: Platform) -> Vec<u8> {
        let path = p.path(&self.id);
        entry(&mut self.zip, &path).unwrap_or_else(|| {
            panic!(
                "{}: no {path} (build every platform: tests/run installs the toolchains)",
                self.name
            )
        })
    }
}

/// Every FMU the build wrote: out/fmus, out/scenes, and the FMUs inside out/ssp/*.ssp.
fn all_fmus() -> Vec<Fmu> {
    let mut v = Vec::new();
    for dir in ["fmus", "scenes"] {
        for p in files(&out(dir), "fmu") {
            v.push(Fmu::of(p.display().to_string(), std::fs::read(&p).unwrap()));
        }
    }
    let full = v.len();
    for ssp in files(&out("ssp"), "ssp") {
        let mut z =
            zip::ZipArchive::new(std::io::Cursor::new(std::fs::read(&ssp).unwrap())).unwrap();
        let names: Vec<String> = (0..z.len())
            .map(|i| z.by_index(i).unwrap().name().unwrap().to_string())
            .collect();
        for n in names.iter().filter(|n| n.ends_with(".fmu")) {
            let bytes = entry(&mut z, n).unwrap();
            v.push(Fmu::of(format!("{}!{n}", ssp.display()), bytes));
        }
    }
    let catalog = catalog::all().len();
    assert!(
        full > catalog && v.len() > full,
        "want the full FMUs, the scenes and the SSP files built (tests/run): found {full} FMUs, {} \
         inside SSP files",
        v.len() - full
    );
    v
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// The exported names, without Mach-O's leading underscore.
fn exports(file: &object::File) -> Vec<String> {
    let underscore = file.format() == object::BinaryFormat::MachO;
    file.exports()
        .unwrap()
        .filter_map(|e| match e.unwrap().name() {
            object::read::NameOrOrdinal::Name(n) => Some(text(n)),
            object::read::NameOrOrdinal::Ordinal(_) => None,
        })
        .map(|n| match n.strip_prefix('_') {
            Some(rest) if underscore => rest.to_string(),
            _ => n,
        })
        .collect()
}

fn assert_exports_fmi(what: &str, file: &object::File) {
    let names = exports(file);
    for f in FMI2_CS_FUNCTIONS {
        assert!(names.iter().any(|n| n == f), "{what}: {f} not exported");
    }
}

fn libraries(file: &object::File) -> Vec<String> {
    file.import_libraries()
        .unwrap()
        .map(|l| text(l.unwrap().name()))
        .collect()
}

/// `GLIBC_2.x[.y]` as (2, x, y).
fn glibc_version(v: &str) -> Option<(u32, u32, u32)> {
    let mut it = v.strip_prefix("GLIBC_")?.split('.').map(|x| x.parse().ok());
    Some((it.next()??, it.next()??, it.next().flatten().unwrap_or(0)))
}

#[test]
fn every_fmu_carries_every_platform_and_its_documentation_says_so() {
    for mut fmu in all_fmus() {
        for p in Platform::ALL {
            assert!(!fmu.binary(p).is_empty());
        }
        let page = text(&entry(&mut fmu.zip, "documentation/index.html").unwrap());
        for p in Platform::ALL {
            assert!(
                page.contains(&format!("<code>binaries/{}</code>", p.folder())),
                "{}: documentation/index.html does not name binaries/{}",
                fmu.name,
                p.folder()
            );
        }
    }
}

#[test]
fn linux_binaries_need_only_glibc_2_17() {
    for mut fmu in all_fmus() {
        for (p, arch, loader) in [
            (
                Platform::Linux64,
                Architecture::X86_64,
                "ld-linux-x86-64.so.2",
            ),
            (
                Platform::Aarch64Linux,
                Architecture::Aarch64,
                "ld-linux-aarch64.so.1",
            ),
        ] {
            let bytes = fmu.binary(p);
            let what = format!("{}: {}", fmu.name, p.path(&fmu.id));
            let file = object::File::parse(&*bytes).unwrap();
            assert_eq!(file.format(), object::BinaryFormat::Elf, "{what}");
            assert_eq!(file.architecture(), arch, "{what}");
            // glibc's own libraries (before 2.34, pthread and dl were separate ones)
            let allowed = [
                "libc.so.6",
                "libm.so.6",
                "libpthread.so.0",
                "libdl.so.2",
                loader,
            ];
            let libs = libraries(&file);
            assert!(libs.contains(&"libc.so.6".to_string()), "{what}: {libs:?}");
            for l in &libs {
                assert!(allowed.contains(&l.as_str()), "{what} needs {l}");
            }
            let mut newest = (0, 0, 0);
            for i in file.imports().unwrap() {
                let i = i.unwrap();
                if let object::read::ImportFlags::Elf {
                    version: Some(v), ..
                } = i.flags()
                {
                    let v = text(v);
                    let parsed = glibc_version(&v)
                        .unwrap_or_else(|| panic!("{what}: symbol version {v} is not glibc's"));
                    newest = newest.max(parsed);
                }
            }
            assert!(
                newest <= (2, 17, 0),
                "{what}: needs GLIBC_{}.{}.{} (> 2.17)",
                newest.0,
                newest.1,
                newest.2
            );
            assert_exports_fmi(&what, &file);
            assert!(
                file.section_by_name(".symtab").is_none() && !file.has_debug_symbols(),
                "{what}: not stripped"
            );
        }
    }
}

#[test]
fn win64_dll_needs_only_windows_system_dlls() {
    // Windows 10's own DLLs (bcryptprimitives.dll: ProcessPrng, Windows 10 and later;
    // api-ms-win-core-synch: WaitOnAddress, Windows 8 and later)
    const SYSTEM: [&str; 8] = [
        "kernel32.dll",
        "ntdll.dll",
        "msvcrt.dll",
        "userenv.dll",
        "ws2_32.dll",
        "advapi32.dll",
        "bcryptprimitives.dll",
        "api-ms-win-core-synch-l1-2-0.dll",
    ];
    for mut fmu in all_fmus() {
        let bytes = fmu.binary(Platform::Win64);
        let what = format!("{}: {}", fmu.name, Platform::Win64.path(&fmu.id));
        let file = object::File::parse(&*bytes).unwrap();
        assert_eq!(file.format(), object::BinaryFormat::Pe, "{what}");
        assert_eq!(file.architecture(), Architecture::X86_64, "{what}");
        assert!(file.is_64(), "{what}: PE32+");
        for l in libraries(&file) {
            assert!(
                SYSTEM.contains(&l.to_ascii_lowercase().as_str()),
                "{what} imports {l}, not a Windows system DLL"
            );
        }
        assert_exports_fmi(&what, &file);
        assert!(
            file.symbols().next().is_none() && !file.has_debug_symbols(),
            "{what}: not stripped"
        );
    }
}

#[test]
fn darwin_binary_is_universal_for_intel_and_apple_silicon() {
    let mechanisms: Vec<&str> = catalog::all().iter().map(|e| e.identifier).collect();
    for mut fmu in all_fmus() {
        let bytes = fmu.binary(Platform::Darwin64);
        let what = format!("{}: {}", fmu.name, Platform::Darwin64.path(&fmu.id));
        let fat = MachOFatFile32::parse(&*bytes)
            .unwrap_or_else(|e| panic!("{what}: not a universal binary: {e}"));
        let arches: Vec<Architecture> = fat.arches().iter().map(|a| a.architecture()).collect();
        assert_eq!(
            arches,
            [Architecture::X86_64, Architecture::Aarch64],
            "{what}"
        );
        let mut install_names = Vec::new();
        for a in fat.arches() {
            let slice = a.data(&*bytes).unwrap();
            let what = format!("{what} ({:?})", a.architecture());
            let file = object::File::parse(slice).unwrap();
            assert_eq!(file.architecture(), a.architecture(), "{what}");
            assert_exports_fmi(&what, &file);
            assert_eq!(
                libraries(&file),
                ["/usr/lib/libSystem.B.dylib"],
                "{what}: links only the C library"
            );
            assert!(!file.has_debug_symbols(), "{what}: not stripped");
            let m = MachOFile64::<Endianness>::parse(slice).unwrap();
            let e = m.endian();
            assert_eq!(
                m.macho_header().filetype.get(e),
                macho::MH_DYLIB,
                "{what}: a dylib"
            );
            let (mut minos, mut signed) = (None, false);
            let mut commands = m.macho_load_commands().unwrap();
            while let Some(c) = commands.next().unwrap() {
                match c.variant().unwrap() {
                    object::read::macho::LoadCommandVariant::IdDylib(d) => {
                        install_names.push(text(c.string(e, d.dylib.name).unwrap()));
                    }
                    object::read::macho::LoadCommandVariant::BuildVersion(b, _) => {
                        minos = Some(b.minos.get(e).0);
                    }
                    object::read::macho::LoadCommandVariant::VersionMin(v) => {
                        minos = Some(v.version.get(e).0);
                    }
                    _ if c.cmd() == macho::LC_CODE_SIGNATURE => signed = true,
                    _ => {}
                }
            }
            // xxxx.yy.zz in nibbles: 10.12 (Rust's minimum for Intel Macs), 11.0 (the first
            // macOS on Apple silicon)
            let want = match a.architecture() {
                Architecture::X86_64 => 0x000a_0c00,
                _ => 0x000b_0000,
            };
            assert_eq!(minos, Some(want), "{what}: minimum macOS version");
            if a.architecture() == Architecture::Aarch64 {
                assert!(signed, "{what}: Apple silicon loads only signed code");
            }
        }
        // the mechanism's binary (a scene's is renamed to the scene's identifier)
        assert_eq!(install_names.len(), 2, "{what}");
        for n in &install_names {
            let id = n
                .strip_prefix("@rpath/")
                .and_then(|n| n.strip_suffix(".dylib"))
                .unwrap_or_else(|| panic!("{what}: install name {n}"));
            assert!(mechanisms.contains(&id), "{what}: install name {n}");
            if mechanisms.contains(&fmu.id.as_str()) {
                assert_eq!(id, fmu.id, "{what}");
            }
        }
    }
}

/// The panic probe built by the route of `linux64` (cargo-zigbuild, glibc 2.17) catches its panic.
#[test]
fn panics_are_caught_on_linux64_built_for_glibc_2_17() {
    let so = probe::build(
        "x86_64-zig",
        &probe::Route {
            subcommand: "zigbuild",
            target: Some("x86_64-unknown-linux-gnu.2.17"),
            env: &[],
        },
    );
    let host = so.with_file_name("probe-host");
    probe::compile_c("cc", "probe.c", &host, &["-ldl"]);
    let out = probe::run(&[], &host, &[so.to_str().unwrap()]);
    assert_eq!(out.trim(), "0 -1 -1", "probe(0), probe(1), probe(2)");
}

/// The route of `aarch64-linux` (cargo-zigbuild, glibc 2.17), run under qemu-user.
#[test]
fn panics_are_caught_on_aarch64_linux() {
    let so = probe::build(
        "aarch64-zig",
        &probe::Route {
            subcommand: "zigbuild",
            target: Some("aarch64-unknown-linux-gnu.2.17"),
            env: &[],
        },
    );
    let host = so.with_file_name("probe-host");
    probe::compile_c("aarch64-linux-gnu-gcc", "probe.c", &host, &["-ldl"]);
    let out = probe::run(&probe::qemu_aarch64(), &host, &[so.to_str().unwrap()]);
    assert_eq!(
        out.trim(),
        "0 -1 -1",
        "probe(0), probe(1), probe(2) on aarch64"
    );
}

/// The route of `win64` (MinGW-w64), run under Wine.
#[test]
fn panics_are_caught_on_win64() {
    let dll = probe::build(
        "win64",
        &probe::Route {
            subcommand: "build",
            target: Some("x86_64-pc-windows-gnu"),
            env: &[],
        },
    );
    let host = dll.with_file_name("probe-host.exe");
    probe::compile_c("x86_64-w64-mingw32-gcc", "probe.c", &host, &[]);
    let out = probe::run(&probe::wine(), &host, &[&probe::wine_path(&dll)]);
    assert_eq!(
        out.trim(),
        "0 -1 -1",
        "probe(0), probe(1), probe(2) on win64"
    );
}

/// Every FMI 3.0 FMU (out/fmus/fmi3, out/scenes/fmi3) carries its FMI 2.0 twin's binaries, byte
/// for byte, in FMI 3.0's platform folders (the universal macOS binary in both of macOS's), and
/// nothing in FMI 2.0's folders; every platform of the twin is there.
#[test]
fn every_fmi3_fmu_carries_its_twins_binaries_under_fmi3_platform_names() {
    let mut checked = 0;
    for dir in ["fmus", "scenes"] {
        for p in files(&out(dir).join("fmi3"), "fmu") {
            let twin = out(dir).join(p.file_name().unwrap());
            let mut three = Fmu::of(p.display().to_string(), std::fs::read(&p).unwrap());
            let mut two = Fmu::of(twin.display().to_string(), std::fs::read(&twin).unwrap());
            let names: Vec<String> = (0..three.zip.len())
                .map(|i| three.zip.by_index(i).unwrap().name().unwrap().to_string())
                .collect();
            for platform in Platform::ALL {
                let b2 = two.binary(platform);
                for folder in platform.folders3() {
                    let path = format!("binaries/{folder}/{}.{}", three.id, platform.extension());
                    let b3 = entry(&mut three.zip, &path)
                        .unwrap_or_else(|| panic!("{}: no {path}", three.name));
                    assert!(b2 == b3, "{}: {path} differs from {}", three.name, two.name);
                }
                let old = format!("binaries/{}/", platform.folder());
                assert!(
                    platform.folders3().contains(&platform.folder())
                        || !names.iter().any(|n| n.starts_with(&old)),
                    "{}: an FMI 2.0 folder {old}",
                    three.name
                );
            }
            checked += 1;
        }
    }
    assert!(
        checked > catalog::all().len(),
        "want the FMI 3.0 FMUs and scenes built (tests/run): found {checked}"
    );
}
