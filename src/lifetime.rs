//! Heap the library keeps for as long as it is loaded: the caches behind `&'static` references
//! (a model's variable table, its GUID, tailored scenes), freed when the dynamic loader unloads
//! the FMU's binary.
//!
//! Rust runs no destructors for statics, and a host unloads an FMU's binary after
//! `fmi2FreeInstance` (FMPy does at the end of every simulation): without this, each
//! load–instantiate–free–unload cycle would lose the caches (about 11 KB per cycle for
//! GenevaKnifeDrive; `tests/unload.rs`). Every cdylib made by [`crate::export_fmu!`] calls
//! [`release_at_unload`] when it is unloaded:
//! - Linux: from its ELF `.fini_array`, which the loader runs at `dlclose` (and at process exit);
//! - Windows: from `DllMain` at `DLL_PROCESS_DETACH` by `FreeLibrary` (before, only Linux
//!   released them, and each cycle under Windows lost about 12 KB; measured under Wine by
//!   `tests/c_host/unload.c`, `tests/platforms.rs`);
//! - macOS: nothing to do: dyld never unloads an image that has thread-local variables, as
//!   Rust's standard library has, so a second load finds the caches of the first.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A kept allocation and how to free it.
struct Kept {
    ptr: *mut u8,
    drop: unsafe fn(*mut u8),
}

// SAFETY: a Kept is only a pointer to a `Send + Sync` value (see `keep`) and its drop function.
unsafe impl Send for Kept {}

static KEPT: Mutex<Vec<Kept>> = Mutex::new(Vec::new());
static RELEASERS: Mutex<Vec<fn()>> = Mutex::new(Vec::new());
static LIVE: AtomicUsize = AtomicUsize::new(0);

/// Moves `x` to the heap for the rest of the library's lifetime (freed by
/// [`release_at_unload`]): a `&'static` a cache can hand out.
pub fn keep<T: Send + Sync + 'static>(x: T) -> &'static T {
    unsafe fn drop_box<T>(p: *mut u8) {
        // SAFETY: `p` came from `Box::into_raw` of a `Box<T>` in `keep`, and is freed once.
        drop(unsafe { Box::from_raw(p as *mut T) });
    }
    let p = Box::into_raw(Box::new(x));
    KEPT.lock().unwrap_or_else(|e| e.into_inner()).push(Kept {
        ptr: p as *mut u8,
        drop: drop_box::<T>,
    });
    // SAFETY: freed only by `release_at_unload`, after which no code of the library runs.
    unsafe { &*p }
}

/// Registers a function that empties a cache held in a static (its `Vec` buffers), run by
/// [`release_at_unload`] before the kept values are freed. Register it once, when the cache is
/// first filled.
pub fn on_release(f: fn()) {
    RELEASERS.lock().unwrap_or_else(|e| e.into_inner()).push(f);
}

/// One more live FMU instance (the runtime counts them): nothing is released while one lives.
pub fn instance_created() {
    LIVE.fetch_add(1, Ordering::SeqCst);
}

/// One live FMU instance fewer.
pub fn instance_freed() {
    LIVE.fetch_sub(1, Ordering::SeqCst);
}

/// Frees every cache, for the loader at unload. Does nothing while an instance is alive (a
/// host that exits without freeing its instances, possibly with another thread still in a
/// call): the process's end frees the memory then.
///
/// # Safety
/// No code of this library may run afterwards (the loader's `.fini_array` and `DllMain`
/// contract), since the
/// `&'static` references [`keep`] gave out dangle.
pub unsafe extern "C" fn release_at_unload() {
    if LIVE.load(Ordering::SeqCst) != 0 {
        return;
    }
    let releasers = std::mem::take(&mut *RELEASERS.lock().unwrap_or_else(|e| e.into_inner()));
    for f in releasers {
        f();
    }
    let kept = std::mem::take(&mut *KEPT.lock().unwrap_or_else(|e| e.into_inner()));
    for k in kept {
        // SAFETY: each pointer was kept once, by `keep`, with its own drop function.
        unsafe { (k.drop)(k.ptr) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kept_values_stay_readable() {
        let a = keep(vec![1.0, 2.0]);
        let s = keep(String::from("guid"));
        assert_eq!(a.as_slice(), &[1.0, 2.0]);
        assert_eq!(s.as_str(), "guid");
    }
}
