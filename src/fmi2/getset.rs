//! `fmi2Get*` and `fmi2Set*` of Real, Integer, Boolean and String variables, and the calls a
//! model does not support.

use super::*;
use std::borrow::Cow;

/// The FMI type a get/set call handles: its name (for messages), its [`access`] bit and the
/// declared types it covers (Integer calls also read and write Enumerations).
#[derive(Clone, Copy)]
pub struct Kind {
    pub(super) name: &'static str,
    pub(super) bit: access::Bits,
    pub(super) ok: fn(VarType) -> bool,
}

impl Kind {
    /// A kind of value: its name, the [`access`] bit that marks its variables and the test of
    /// a declared type (for the messages).
    pub const fn new(name: &'static str, bit: access::Bits, ok: fn(VarType) -> bool) -> Kind {
        Kind { name, bit, ok }
    }
}

pub const REAL: Kind = Kind::new("Real", access::REAL, |t| t == VarType::Real);
pub const INTEGER: Kind = Kind::new("Integer", access::INTEGER, VarType::is_integer_like);
pub const BOOLEAN: Kind = Kind::new("Boolean", access::BOOLEAN, |t| t == VarType::Boolean);
/// The models have no String variables: every String call is refused by the slow path (no
/// variable has the bit).
pub const STRING: Kind = Kind::new("String", access::STRING, |_| false);

/// One `fmi2Get*` (or `fmi3Get*`) call: the host's arrays, then [`Instance::read_values`]
/// with `conv`.
///
/// # Safety
/// As [`entry`]; arrays hold `n` elements.
pub unsafe fn get<M: Model, T>(
    c: Component,
    call: impl Api,
    vr: *const ValueReference,
    n: usize,
    value: *mut T,
    kind: Kind,
    conv: impl Fn(f64) -> T,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            let vrs = slice(vr, n, "vr")?;
            let out = slice_mut(value, n, "value")?;
            inst.read_values(vrs, out, kind, conv)
        })
    }
}

/// One `fmi2Set*` (or `fmi3Set*`) call: the host's arrays, the values as `f64` (`conv`), then
/// [`Instance::set_values`].
///
/// # Safety
/// As [`entry`]; arrays hold `n` elements.
pub unsafe fn set<M: Model, T>(
    c: Component,
    call: impl Api,
    vr: *const ValueReference,
    n: usize,
    value: *const T,
    kind: Kind,
    conv: impl FnOnce(&[T]) -> Cow<'_, [f64]>,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            let vrs = slice(vr, n, "vr")?;
            let vals = conv(slice(value, n, "value")?);
            inst.set_values(vrs, &vals, kind)
        })
    }
}

/// The public get and set calls of either version, one entry each: the name, the host's
/// value array (FMI 3.0: and its length `nValues`, which must equal the number of value
/// references: every variable is a scalar), and [`get`] or [`set`] with the version's call,
/// its [`Kind`] and the conversion. The invoking module imports its version's `Call` and its
/// C types.
#[doc(hidden)]
#[macro_export]
macro_rules! __get_set_calls {
    ($(
        $(#[$doc:meta])*
        $name:ident($value:ty $(, $n_values:ident)?) = $how:ident($call:ident, $kind:expr, $conv:expr);
    )*) => {$(
        $(#[$doc])*
        ///
        /// # Safety
        /// As [`entry`]; arrays hold `n` elements.
        pub unsafe fn $name<M: Model>(
            c: $crate::fmi2::types::Component,
            vr: *const ValueReference,
            n: usize,
            value: $value,
            $($n_values: usize,)?
        ) -> Status {
            $(
                if let Err(why) = $crate::fmi2::runtime::scalars(n, $n_values) {
                    // SAFETY: as this function.
                    return unsafe { entry::<M, _>(c, Call::$call, |_| Err(why)) };
                }
            )?
            // SAFETY: as this function.
            unsafe { $how::<M, _>(c, Call::$call, vr, n, value, $kind, $conv) }
        }
    )*};
}

crate::__get_set_calls! {
    /// `fmi2GetReal`.
    get_real(*mut Real) = get(GetReal, REAL, |x| x);
    /// `fmi2GetInteger` (Integer and Enumeration variables).
    get_integer(*mut Integer) = get(GetInteger, INTEGER, |x| x as Integer);
    /// `fmi2GetBoolean`.
    get_boolean(*mut Boolean) = get(GetBoolean, BOOLEAN, |x| {
        if x != 0.0 { TRUE } else { FALSE }
    });
    /// `fmi2GetString`: the models have no String variables.
    get_string(*mut FmiString) = get(GetString, STRING, |_| std::ptr::null());
    /// `fmi2SetReal`: non-finite values are refused and the previous values kept.
    set_real(*const Real) = set(SetReal, REAL, |v| v.into());
    /// `fmi2SetInteger` (Integer and Enumeration variables).
    set_integer(*const Integer) = set(SetInteger, INTEGER, |v| {
        v.iter().map(|&x| x as f64).collect()
    });
    /// `fmi2SetBoolean`.
    set_boolean(*const Boolean) = set(SetBoolean, BOOLEAN, |v| {
        v.iter().map(|&x| if x != FALSE { 1.0 } else { 0.0 }).collect()
    });
    /// `fmi2SetString`: the models have no String variables.
    set_string(*const FmiString) = set(SetString, STRING, |v| vec![0.0; v.len()].into());
}

/// Refuses an FMI 3.0 array of `n_values` values for `nvr` value references unless they are
/// equal: every variable is a scalar.
pub fn scalars(nvr: usize, n_values: usize) -> Result<(), String> {
    if n_values == nvr {
        Ok(())
    } else {
        Err(format!(
            "nValues = {n_values} but nValueReferences = {nvr}: every variable of this FMU is a scalar"
        ))
    }
}

/// A call whose capability flag is false: logged and refused.
///
/// # Safety
/// As [`entry`].
pub unsafe fn unsupported<M: Model>(c: Component, call: impl Api, why: &str) -> Status {
    // SAFETY: as entry.
    unsafe { entry::<M, _>(c, call, |_| Err(format!("not supported: {why}"))) }
}

impl<M: Model> Instance<M> {
    /// The values of Real variables (`fmi2GetReal`'s checks and lazy outputs).
    pub fn read_reals(&mut self, vrs: &[ValueReference], out: &mut [f64]) -> Outcome {
        self.read_values(vrs, out, REAL, |x| x)
    }

    /// Refuses the value references of a call on a type no variable has, naming the first
    /// one's type (no value reference: nothing to refuse).
    pub fn refuse_type(&self, vrs: &[ValueReference], kind: Kind) -> Outcome {
        self.check_get(vrs, kind)?;
        Ok(Status::Ok)
    }
}
