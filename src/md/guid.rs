//! The GUID of a model description, computed from what the description states (the model's
//! information and its variable declarations) without writing the XML: the FMU binary checks
//! a host's GUID with [`guid`] and carries no XML writer (the description itself is written at
//! build time, by `bindery build` and `bindery describe`, with the same GUID).
//!
//! Every field of [`ModelInfo`] and [`Var`] that the description states is hashed, by exhaustive
//! destructuring: a field added to either does not compile until it is placed here. What the
//! writer adds of its own (units, log categories, authorship, version, [`FORMAT`]) is hashed too.

use super::{AUTHOR, COPYRIGHT, LICENSE, LOG_CATEGORIES, ModelInfo, UNITS};
use crate::model::{Experiment, Model, Var, VarType};

/// The writer's format: bumped when `md::xml` changes what it states for the same declarations.
pub const FORMAT: &str = "bindery-fmu FMI 2.0 modelDescription, format 1";

/// 128-bit FNV-1a: a small, dependency-free, stable content hash.
pub fn fnv1a_128(bytes: &[u8]) -> u128 {
    let mut h = Fnv::default();
    h.raw(bytes);
    h.0
}

/// Formats a 128-bit hash as a GUID `{xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx}`.
pub fn format_guid(h: u128) -> String {
    let s = format!("{h:032x}");
    format!(
        "{{{}-{}-{}-{}-{}}}",
        &s[0..8],
        &s[8..12],
        &s[12..16],
        &s[16..20],
        &s[20..32]
    )
}

struct Fnv(u128);

impl Default for Fnv {
    fn default() -> Self {
        Fnv(0x6c62272e07bb014262b821756295c58d)
    }
}

impl Fnv {
    fn raw(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= b as u128;
            self.0 = self.0.wrapping_mul(0x0000000001000000000000000000013B);
        }
    }
    /// A field, prefixed by its length: no two sequences of fields hash the same bytes.
    fn bytes(&mut self, b: &[u8]) {
        self.raw(&(b.len() as u64).to_le_bytes());
        self.raw(b);
    }
    fn str(&mut self, s: &str) {
        self.bytes(s.as_bytes());
    }
    fn u64(&mut self, x: u64) {
        self.bytes(&x.to_le_bytes());
    }
    fn f64(&mut self, x: f64) {
        self.u64(x.to_bits());
    }
    fn opt_f64(&mut self, x: Option<f64>) {
        match x {
            Some(x) => {
                self.u64(1);
                self.f64(x)
            }
            None => self.u64(0),
        }
    }
    fn opt_str(&mut self, s: Option<&str>) {
        match s {
            Some(s) => {
                self.u64(1);
                self.str(s)
            }
            None => self.u64(0),
        }
    }
}

/// The GUID of the description of `vars` (by value reference) with `info`.
pub fn guid(info: &ModelInfo, vars: &[(u32, &Var)]) -> String {
    let mut h = Fnv::default();
    for s in [
        FORMAT,
        AUTHOR,
        COPYRIGHT,
        LICENSE,
        env!("CARGO_PKG_VERSION"),
    ] {
        h.str(s);
    }
    for (n, d) in LOG_CATEGORIES {
        h.str(n);
        h.str(d);
    }
    for u in UNITS {
        h.str(u.name);
        h.bytes(&u.base.map(|x| x as u8));
        for (n, f) in u.display {
            h.str(n);
            h.f64(*f);
        }
    }
    let ModelInfo {
        identifier,
        model_name,
        description,
        experiment:
            Experiment {
                start,
                stop,
                step,
                tolerance,
            },
        event_indicators,
        can_interpolate_inputs,
        // not in the FMI 2.0 description: the FMI 3.0 terminals name variables it states
        terminals: _,
        variables: _,
        partials,
    } = info;
    for s in [identifier, model_name, description] {
        h.str(s);
    }
    for x in [start, stop, step] {
        h.f64(*x);
    }
    h.opt_f64(*tolerance);
    h.u64(*event_indicators as u64);
    h.u64(*can_interpolate_inputs as u64);
    // hashed where offered only: the GUIDs of the FMUs without stay as they were
    if *partials {
        h.str("providesDirectionalDerivative");
    }
    h.u64(vars.len() as u64);
    for &(vr, v) in vars {
        let Var {
            name,
            ty,
            causality,
            variability,
            initial,
            start,
            unit,
            display_unit,
            min,
            max,
            description,
            depends,
            derivative,
            // which computation stages produce or use a variable is not in the description
            needs: _,
            feeds: _,
            // nor which discrete outputs mark events (FMI 3.0's early return)
            event: _,
        } = v;
        h.u64(vr as u64);
        h.str(name);
        match ty {
            VarType::Real => h.u64(0),
            VarType::Integer => h.u64(1),
            VarType::Boolean => h.u64(2),
            VarType::Enumeration(t) => {
                h.u64(3);
                h.str(t.name);
                h.str(t.description);
                for (n, d) in t.items {
                    h.str(n);
                    h.str(d);
                }
            }
        }
        h.u64(*causality as u64);
        h.u64(*variability as u64);
        h.u64(initial.map_or(u64::MAX, |i| i as u64));
        h.opt_f64(*start);
        h.opt_str(*unit);
        h.opt_str(*display_unit);
        h.opt_f64(*min);
        h.opt_f64(*max);
        h.str(description);
        h.u64(depends.len() as u64);
        for d in *depends {
            h.u64(*d as u64);
        }
        h.u64(derivative.map_or(u64::MAX, |d| d as u64));
    }
    format_guid(h.0)
}

/// The GUID of the full description of a model type.
pub fn guid_of<M: Model>() -> String {
    guid(&ModelInfo::of::<M>(), &crate::model::variables_of::<M>())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guid_format_and_stability() {
        let g = format_guid(fnv1a_128(b"abc"));
        assert_eq!(g.len(), 38);
        assert_eq!(g, format_guid(fnv1a_128(b"abc")));
        assert_ne!(g, format_guid(fnv1a_128(b"abd")));
    }
}
