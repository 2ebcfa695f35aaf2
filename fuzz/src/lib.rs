//! The coverage-guided fuzz targets' runner: the fuzzer's input drives the host of the seeded
//! smoke run (`examples/fuzz_fmi/host.rs`, the same call grammar and checks) on the one FMU the
//! target exports: up to [`host::CALLS`] FMI calls on at most three live instances, every choice
//! drawn from the input's bytes. A finding (a status outside fmi2Status, a call the state
//! machine forbids not refused, an fmi2Error without a log line, a panic caught at the C
//! boundary, a wrong fmi2Instantiate outcome) aborts, as a crash does; so do a crash and a
//! sanitizer's report. `FUZZING.md` says how to run them.
#![allow(clippy::type_complexity)]

#[path = "../../tests/common/c_logger.rs"]
mod c_logger;
#[path = "../../examples/fuzz_fmi/host.rs"]
mod host;

use bindery_fmu::catalog;
use host::Api;

/// The FMI functions of `id` this program exports, found in its own dynamic symbol table.
fn api(id: &str) -> Api {
    let e = catalog::all()
        .into_iter()
        .find(|e| e.identifier == id)
        .unwrap_or_else(|| panic!("{id} is no FMU of the catalog"));
    Api::of(libloading::os::unix::Library::this().into(), &e)
}

/// One input: the calls it chooses on the FMU `id` ([`host::run_input`]); a finding panics.
pub fn run(id: &str, data: &[u8]) {
    let report = host::run_input(api(id), data);
    if !report.findings.is_empty() {
        panic!("{id}: {}", report.findings.join("\n"));
    }
}
