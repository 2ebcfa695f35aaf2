//! A host that loads an FMU's binary, instantiates, steps, frees and unloads it again and again
//! (FMPy unloads the binary at the end of every simulation) loses no memory: the caches the
//! binary keeps behind `&'static` references (variable table, GUID) are freed at unload
//! (`bindery_fmu::lifetime`, the `.fini_array` entry of `export_fmu!`). Before, each cycle lost
//! about 11 KB (GenevaKnifeDrive).

#![cfg(target_os = "linux")]

mod common;

use bindery_fmu::catalog;
use common::*;

/// One load–instantiate–step–free–unload cycle of the FMU `e`.
fn cycle(e: &catalog::Entry) {
    let f = Fmu::of(e);
    let s = f.initialized("unload");
    s.ok(s.do_step(0.0, 0.01), "fmi2DoStep");
    let (st, _) = s.get_real(&real_outputs_of(e));
    s.ok(st, "fmi2GetReal");
    drop(s); // fmi2FreeInstance
    drop(f); // dlclose
}

#[test]
fn loading_and_unloading_an_fmu_loses_no_memory() {
    const CYCLES: usize = 200;
    for e in catalog::all() {
        // warm-up: the test's own one-time allocations (log buffers, the catalog's tables)
        for _ in 0..5 {
            cycle(&e);
        }
        let before = heap::in_use();
        for _ in 0..CYCLES {
            cycle(&e);
        }
        let per_cycle = (heap::in_use() - before).max(0) as f64 / CYCLES as f64;
        // the caches were 11-12 KB per cycle; what the host itself keeps (its log records of
        // every instance) and glibc's own bookkeeping of dlopen stay well under 1 KB
        assert!(
            per_cycle < 1024.0,
            "{}: {per_cycle:.0} bytes per load/unload cycle stay allocated",
            e.identifier
        );
    }
}
