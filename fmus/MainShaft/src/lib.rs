//! The MainShaft FMU binary: exports the FMI 2.0 API for the main-shaft drive.
#![allow(non_snake_case)]
bindery_fmu::export_fmu!(bindery_fmu::mechanisms::main_shaft::MainShaft);
