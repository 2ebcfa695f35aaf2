//! The FMU-state calls: get, set, free, serialize, deserialize (of FMI 2.0 and FMI 3.0: the
//! export macros run each through the entry wrapper as the call the host made).

use super::*;

impl<M: Model> Instance<M> {
    /// `fmi2GetFMUstate`.
    ///
    /// # Safety
    /// `state` points to an `fmi2FMUstate`.
    pub unsafe fn get_fmu_state(&mut self, state: *mut FMUstate) -> Outcome {
        if state.is_null() {
            return Err("FMUstate pointer is NULL".into());
        }
        let snap = self.snapshot();
        // SAFETY: as this function.
        unsafe { self.store_snapshot(state, snap) }
    }

    /// `fmi2SetFMUstate`.
    ///
    /// # Safety
    /// None beyond the entry wrapper's: `state` is checked to be one of this instance's.
    pub unsafe fn set_fmu_state(&mut self, state: FMUstate) -> Outcome {
        let p = self.own_snapshot(state)?;
        // SAFETY: a live snapshot of this instance.
        let snap = unsafe { (*p).clone() };
        self.restore(&snap)
    }

    /// `fmi2FreeFMUstate`.
    ///
    /// # Safety
    /// `state` points to an `fmi2FMUstate`.
    pub unsafe fn free_fmu_state(&mut self, state: *mut FMUstate) -> Outcome {
        // SAFETY: as this function.
        if state.is_null() || unsafe { (*state).is_null() } {
            return Ok(Status::Ok);
        }
        // SAFETY: as this function; own_snapshot checks it is one of ours, still live.
        unsafe {
            let p = self.own_snapshot(*state)?;
            self.snapshots.retain(|&q| q != p);
            drop(Box::from_raw(p));
            *state = std::ptr::null_mut();
        }
        Ok(Status::Ok)
    }

    /// `fmi2SerializedFMUstateSize`.
    ///
    /// # Safety
    /// `size` points to a `size_t` (checked for NULL).
    pub unsafe fn serialized_fmu_state_size(
        &mut self,
        state: FMUstate,
        size: *mut usize,
    ) -> Outcome {
        let p = self.own_snapshot(state)?;
        if size.is_null() {
            return Err("size pointer is NULL".into());
        }
        // SAFETY: a live snapshot of this instance; `size` as this function.
        unsafe { *size = (*p).to_bytes(self.guid_hash).len() };
        Ok(Status::Ok)
    }

    /// `fmi2SerializeFMUstate`.
    ///
    /// # Safety
    /// `bytes` holds `size` bytes.
    pub unsafe fn serialize_fmu_state(
        &mut self,
        state: FMUstate,
        bytes: *mut Byte,
        size: usize,
    ) -> Outcome {
        let p = self.own_snapshot(state)?;
        // SAFETY: a live snapshot of this instance.
        let data = unsafe { (*p).to_bytes(self.guid_hash) };
        if size < data.len() {
            return Err(format!(
                "buffer of {size} bytes is too small for {} bytes",
                data.len()
            ));
        }
        // SAFETY: as this function.
        let out = unsafe { slice_mut(bytes as *mut u8, data.len(), "serializedState")? };
        out.copy_from_slice(&data);
        Ok(Status::Ok)
    }

    /// `fmi2DeSerializeFMUstate`: refuses bytes that are truncated, from another FMU or corrupt.
    ///
    /// # Safety
    /// `bytes` holds `size` bytes; `state` points to an `fmi2FMUstate`.
    pub unsafe fn deserialize_fmu_state(
        &mut self,
        bytes: *const Byte,
        size: usize,
        state: *mut FMUstate,
    ) -> Outcome {
        if state.is_null() {
            return Err("FMUstate pointer is NULL".into());
        }
        // SAFETY: as this function.
        let data = unsafe { slice(bytes as *const u8, size, "serializedState")? };
        let snap = Snapshot::from_bytes(data, self.guid_hash, self.values.raw().len())?;
        // SAFETY: as this function.
        unsafe { self.store_snapshot(state, snap) }
    }
}
