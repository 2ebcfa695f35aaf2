//! The LegacyNeedleDrive FMU binary: exports the FMI 2.0 co-simulation API for one model.
#![allow(non_snake_case)]
bindery_fmu::export_fmu!(bindery_fmu::mechanisms::legacy_needle_drive::LegacyNeedleDrive);
