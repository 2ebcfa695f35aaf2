//! The tests' FMI logger: `tests/c_host/logger.c`, a real C-variadic `fmi2CallbackLogger`
//! (a Rust function cannot be defined variadic on stable Rust), compiled with the system's C
//! compiler into a shared object once per test process and loaded. It formats the message
//! with its arguments as a host does and hands the text to a Rust sink.
//!
//! Used by `tests/common` and, through `#[path]`, by the runtime's unit tests.

use bindery_fmu::fmi2::types::{CallbackLogger, Status};
use std::ffi::{CStr, c_char, c_int, c_void};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// Where a formatted message goes: (environment, status, instance name, category, text); a
/// NULL string the FMU passed is `None`.
pub type Sink = fn(usize, Status, Option<&str>, Option<&str>, Option<&str>);

static LIB: OnceLock<libloading::Library> = OnceLock::new();
static SINK: OnceLock<Sink> = OnceLock::new();

type CSink = unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);

unsafe extern "C" fn forward(
    env: *mut c_void,
    instance: *const c_char,
    status: c_int,
    category: *const c_char,
    text: *const c_char,
) {
    let s = |p: *const c_char| {
        // SAFETY: NULL or a NUL-terminated string from the C logger, valid for this call.
        (!p.is_null()).then(|| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
    };
    let status = match status {
        0 => Status::Ok,
        1 => Status::Warning,
        2 => Status::Discard,
        3 => Status::Error,
        4 => Status::Fatal,
        _ => Status::Pending,
    };
    if let Some(sink) = SINK.get() {
        let (i, c, t) = (s(instance), s(category), s(text));
        sink(
            env as usize,
            status,
            i.as_deref(),
            c.as_deref(),
            t.as_deref(),
        );
    }
}

/// The shared object, built from the source if it is not there yet (named by the source's
/// hash; written under a temporary name and renamed, so parallel test processes agree).
fn build(out_dir: &Path) -> PathBuf {
    // the checkout: this crate's folder, or the one above it (the fuzz targets' crate)
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = here
        .ancestors()
        .find(|d| d.join("tests/c_host/logger.c").exists())
        .unwrap_or(here);
    let source = root.join("tests/c_host/logger.c");
    let text = std::fs::read(&source).expect("tests/c_host/logger.c");
    let hash = bindery_fmu::md::fnv1a_128(&text);
    let so = out_dir.join(format!("logger-{hash:032x}.so"));
    if so.exists() {
        return so;
    }
    std::fs::create_dir_all(out_dir).unwrap();
    let tmp = out_dir.join(format!("logger-{}.so.tmp", std::process::id()));
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let status = Command::new(&cc)
        .args([
            "-std=c99", "-Wall", "-Wextra", "-Werror", "-O1", "-shared", "-fPIC", "-o",
        ])
        .arg(&tmp)
        .arg(&source)
        .status()
        .unwrap_or_else(|e| panic!("{cc} (builds the tests' C logger): {e}"));
    assert!(status.success(), "{cc} tests/c_host/logger.c failed");
    std::fs::rename(&tmp, &so).unwrap();
    so
}

/// The C logger, its messages going to `sink` (the first sink installed in a process stays).
pub fn logger(sink: Sink) -> CallbackLogger {
    SINK.get_or_init(|| sink);
    let lib = LIB.get_or_init(|| {
        let target = std::env::var_os("CARGO_TARGET_DIR")
            .map(PathBuf::from)
            .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("target"));
        let so = build(&target.join("c-logger"));
        // SAFETY: our own C library, no initialization code.
        let lib = unsafe { libloading::Library::new(&so) }
            .unwrap_or_else(|e| panic!("{}: {e}", so.display()));
        // SAFETY: the C function `void bindery_test_set_sink(bindery_sink)`.
        unsafe {
            let set: libloading::Symbol<unsafe extern "C" fn(CSink)> =
                lib.get(b"bindery_test_set_sink").unwrap();
            set(forward);
        }
        lib
    });
    // SAFETY: the C function has exactly the type of fmi2CallbackLogger (variadic).
    unsafe {
        let f: libloading::Symbol<
            unsafe extern "C" fn(
                *mut c_void,
                *const c_char,
                Status,
                *const c_char,
                *const c_char,
                ...
            ),
        > = lib.get(b"bindery_test_logger").unwrap();
        Some(*f)
    }
}
