//! The FMU-state calls: get, set, free, serialize, deserialize (of FMI 2.0 and FMI 3.0: `call`
//! names the one the host made).

use super::*;

/// `fmi2GetFMUstate`.
///
/// # Safety
/// As [`entry`]; `state` points to an `fmi2FMUstate`.
pub unsafe fn get_fmu_state<M: Model, C: Api>(
    c: Component,
    call: C,
    state: *mut FMUstate,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            if state.is_null() {
                return Err("FMUstate pointer is NULL".into());
            }
            let snap = inst.snapshot();
            inst.store_snapshot(state, snap)
        })
    }
}

/// `fmi2SetFMUstate`.
///
/// # Safety
/// As [`entry`].
pub unsafe fn set_fmu_state<M: Model, C: Api>(c: Component, call: C, state: FMUstate) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            let p = inst.own_snapshot(state)?;
            let snap = (*p).clone();
            inst.restore(&snap)
        })
    }
}

/// `fmi2FreeFMUstate`.
///
/// # Safety
/// As [`entry`]; `state` points to an `fmi2FMUstate`.
pub unsafe fn free_fmu_state<M: Model, C: Api>(
    c: Component,
    call: C,
    state: *mut FMUstate,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            if state.is_null() || (*state).is_null() {
                return Ok(Status::Ok);
            }
            let p = inst.own_snapshot(*state)?;
            inst.snapshots.retain(|&q| q != p);
            drop(Box::from_raw(p));
            *state = std::ptr::null_mut();
            Ok(Status::Ok)
        })
    }
}

/// `fmi2SerializedFMUstateSize`.
///
/// # Safety
/// As [`entry`].
pub unsafe fn serialized_fmu_state_size<M: Model, C: Api>(
    c: Component,
    call: C,
    state: FMUstate,
    size: *mut usize,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            let p = inst.own_snapshot(state)?;
            if size.is_null() {
                return Err("size pointer is NULL".into());
            }
            *size = (*p).to_bytes(inst.guid_hash).len();
            Ok(Status::Ok)
        })
    }
}

/// `fmi2SerializeFMUstate`.
///
/// # Safety
/// As [`entry`]; `bytes` holds `size` bytes.
pub unsafe fn serialize_fmu_state<M: Model, C: Api>(
    c: Component,
    call: C,
    state: FMUstate,
    bytes: *mut Byte,
    size: usize,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            let p = inst.own_snapshot(state)?;
            let data = (*p).to_bytes(inst.guid_hash);
            if size < data.len() {
                return Err(format!(
                    "buffer of {size} bytes is too small for {} bytes",
                    data.len()
                ));
            }
            let out = slice_mut(bytes as *mut u8, data.len(), "serializedState")?;
            out.copy_from_slice(&data);
            Ok(Status::Ok)
        })
    }
}

/// `fmi2DeSerializeFMUstate`: refuses bytes that are truncated, from another FMU or corrupt.
///
/// # Safety
/// As [`entry`]; `bytes` holds `size` bytes; `state` points to an `fmi2FMUstate`.
pub unsafe fn deserialize_fmu_state<M: Model, C: Api>(
    c: Component,
    call: C,
    bytes: *const Byte,
    size: usize,
    state: *mut FMUstate,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            if state.is_null() {
                return Err("FMUstate pointer is NULL".into());
            }
            let data = slice(bytes as *const u8, size, "serializedState")?;
            let snap = Snapshot::from_bytes(data, inst.guid_hash, inst.values.raw().len())?;
            inst.store_snapshot(state, snap)
        })
    }
}
