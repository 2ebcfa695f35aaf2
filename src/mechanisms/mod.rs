//! One module per mechanism: its physics (pure math, no FFI) and its FMU model.

pub mod geneva_knife_drive;
