//! Coverage-guided fuzz target: FMI call sequences on the Perforators FMU, its FMI functions
//! exported from this program (`export_fmu!`, as the FMU binary does) and called through them.
#![no_main]
#![allow(non_snake_case)]

bindery_fmu::export_fmu!(bindery_fmu::mechanisms::perforators::Perforators);

libfuzzer_sys::fuzz_target!(|data: &[u8]| bindery_fmu_fuzz::run("Perforators", data));
