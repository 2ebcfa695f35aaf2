//! One module per mechanism: its physics (pure math, no FFI) and its FMU model.

pub mod disc_knife_drive;
pub mod geneva_knife_drive;
pub mod main_shaft;
pub mod perforators;
pub mod sewing_table;
