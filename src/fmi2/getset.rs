//! `fmi2Get*` and `fmi2Set*` of Real, Integer, Boolean and String variables, and the calls a
//! model does not support.

use super::*;

/// The FMI type a get/set call handles: its name (for messages), its [`access`] bit and the
/// declared types it covers (Integer calls also read and write Enumerations).
#[derive(Clone, Copy)]
pub(super) struct Kind {
    pub(super) name: &'static str,
    pub(super) bit: access::Bits,
    pub(super) ok: fn(VarType) -> bool,
}

pub(super) const REAL: Kind = Kind {
    name: "Real",
    bit: access::REAL,
    ok: |t| t == VarType::Real,
};
pub(super) const INTEGER: Kind = Kind {
    name: "Integer",
    bit: access::INTEGER,
    ok: VarType::is_integer_like,
};
pub(super) const BOOLEAN: Kind = Kind {
    name: "Boolean",
    bit: access::BOOLEAN,
    ok: |t| t == VarType::Boolean,
};
/// The models have no String variables: every String call is refused by the slow path.
pub(super) const STRING: Kind = Kind {
    name: "String",
    bit: 0,
    ok: |_| false,
};

/// `fmi2GetReal`.
///
/// # Safety
/// As [`entry`]; arrays hold `n` elements.
pub unsafe fn get_real<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *mut Real,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M>(c, Call::GetReal, |inst| {
            let vrs = slice(vr, n, "vr")?;
            let out = slice_mut(value, n, "value")?;
            inst.read_values(vrs, out, REAL, |x| x)
        })
    }
}

/// `fmi2GetInteger` (Integer and Enumeration variables).
///
/// # Safety
/// As [`entry`]; arrays hold `n` elements.
pub unsafe fn get_integer<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *mut Integer,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M>(c, Call::GetInteger, |inst| {
            let vrs = slice(vr, n, "vr")?;
            let out = slice_mut(value, n, "value")?;
            inst.read_values(vrs, out, INTEGER, |x| x as Integer)
        })
    }
}

/// `fmi2GetBoolean`.
///
/// # Safety
/// As [`entry`]; arrays hold `n` elements.
pub unsafe fn get_boolean<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *mut Boolean,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M>(c, Call::GetBoolean, |inst| {
            let vrs = slice(vr, n, "vr")?;
            let out = slice_mut(value, n, "value")?;
            inst.read_values(vrs, out, BOOLEAN, |x| if x != 0.0 { TRUE } else { FALSE })
        })
    }
}

/// `fmi2GetString`: the models have no String variables.
///
/// # Safety
/// As [`entry`]; arrays hold `n` elements.
pub unsafe fn get_string<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *mut FmiString,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M>(c, Call::GetString, |inst| {
            let vrs = slice(vr, n, "vr")?;
            let out = slice_mut(value, n, "value")?;
            inst.read_values(vrs, out, STRING, |_| std::ptr::null())
        })
    }
}

/// `fmi2SetReal`: non-finite values are refused and the previous values kept.
///
/// # Safety
/// As [`entry`]; arrays hold `n` elements.
pub unsafe fn set_real<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *const Real,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M>(c, Call::SetReal, |inst| {
            let vrs = slice(vr, n, "vr")?;
            let vals = slice(value, n, "value")?;
            inst.set_values(vrs, vals, REAL)
        })
    }
}

/// `fmi2SetInteger` (Integer and Enumeration variables).
///
/// # Safety
/// As [`entry`]; arrays hold `n` elements.
pub unsafe fn set_integer<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *const Integer,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M>(c, Call::SetInteger, |inst| {
            let vrs = slice(vr, n, "vr")?;
            let vals: Vec<f64> = slice(value, n, "value")?
                .iter()
                .map(|&x| x as f64)
                .collect();
            inst.set_values(vrs, &vals, INTEGER)
        })
    }
}

/// `fmi2SetBoolean`.
///
/// # Safety
/// As [`entry`]; arrays hold `n` elements.
pub unsafe fn set_boolean<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *const Boolean,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M>(c, Call::SetBoolean, |inst| {
            let vrs = slice(vr, n, "vr")?;
            let vals: Vec<f64> = slice(value, n, "value")?
                .iter()
                .map(|&x| if x != FALSE { 1.0 } else { 0.0 })
                .collect();
            inst.set_values(vrs, &vals, BOOLEAN)
        })
    }
}

/// `fmi2SetString`: the models have no String variables.
///
/// # Safety
/// As [`entry`]; arrays hold `n` elements.
pub unsafe fn set_string<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *const FmiString,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M>(c, Call::SetString, |inst| {
            let vrs = slice(vr, n, "vr")?;
            let _ = slice(value, n, "value")?;
            let vals = vec![0.0; n];
            inst.set_values(vrs, &vals, STRING)
        })
    }
}

/// A call whose capability flag is false: logged and refused.
///
/// # Safety
/// As [`entry`].
pub unsafe fn unsupported<M: Model>(c: Component, call: Call, why: &str) -> Status {
    // SAFETY: as entry.
    unsafe { entry::<M>(c, call, |_| Err(format!("not supported: {why}"))) }
}
