//! What a communication step's chain ODE keeps of its last evaluations: the rigid motion at the
//! last few instants ([`LastAt`]) and the chain's point at the last `(t, y)` ([`LastPoint`]).
//! Pure memoization: a kept value is the one the function gives again, bit for bit, so nothing
//! of it is saved with an FMU state (a new ODE starts with nothing kept).

use super::ShaftPath;
use std::cell::Cell;

/// The last values computed of a function of time alone on one communication step's ODE (the
/// rigid motion on the step's shaft path), kept for the next calls at those times (keyed on the
/// time's bits: the same value, not a near one). A step meets few instants many times: Radau
/// IIA's Newton iterations evaluate its three stage times again and again, DOPRI5's last two
/// stages share the step's end, and the event indicators and the checks after a step are at
/// that end too; [`LAST_AT`] instants are kept, the oldest replaced first.
#[derive(Debug)]
pub struct LastAt<K: Copy> {
    /// The instants' bits; `EMPTY` where nothing is kept.
    keys: [Cell<u64>; LAST_AT],
    values: [Cell<Option<K>>; LAST_AT],
    /// The slot the next new instant takes.
    next: Cell<usize>,
}

/// How many instants a [`LastAt`] keeps: Radau IIA's three stage times and one more.
pub const LAST_AT: usize = 4;

/// The key of an empty [`LastAt`] slot: a NaN's bits, which no time has.
const EMPTY: u64 = u64::MAX;

impl<K: Copy> Default for LastAt<K> {
    /// Nothing kept yet.
    fn default() -> Self {
        LastAt {
            keys: std::array::from_fn(|_| Cell::new(EMPTY)),
            values: std::array::from_fn(|_| Cell::new(None)),
            next: Cell::new(0),
        }
    }
}

impl<K: Copy> LastAt<K> {
    /// The value at `t` of `at(φ, ω, ε)`, a function of the shaft's state on `path`
    /// ([`LastAt::get_or`]).
    pub fn on_path(&self, path: &ShaftPath, t: f64, at: impl FnOnce(f64, f64, f64) -> K) -> K {
        self.get_or(t, || {
            let (phi, w, a) = path.at(t);
            at(phi, w, a)
        })
    }

    /// The value at `t`: a kept one if it is `t`'s, else `at()`, then kept.
    pub fn get_or(&self, t: f64, at: impl FnOnce() -> K) -> K {
        let bits = t.to_bits();
        if let Some(i) = self.keys.iter().position(|k| k.get() == bits)
            && let Some(k) = self.values[i].get()
        {
            return k;
        }
        let k = at();
        let i = self.next.get();
        self.keys[i].set(bits);
        self.values[i].set(Some(k));
        self.next.set((i + 1) % LAST_AT);
        k
    }
}

/// The last value computed of a function of the time and the chain's states `y = [x, ẋ, W]`
/// (the chain's point, an evaluation of its balance) on one communication step's ODE, kept for
/// the next call at the same bits: the right-hand side that ends a step (DOPRI5's last stage,
/// Radau IIA's derivative at the new state) and the checks after the step (`on_step`) are at
/// one `(t, y)`.
#[derive(Debug)]
pub struct LastPoint<P: Copy> {
    /// The bits of `t` and `y`; a NaN's where nothing is kept.
    key: Cell<[u64; 4]>,
    value: Cell<Option<P>>,
}

impl<P: Copy> Default for LastPoint<P> {
    /// Nothing kept yet.
    fn default() -> Self {
        LastPoint {
            key: Cell::new([EMPTY; 4]),
            value: Cell::new(None),
        }
    }
}

impl<P: Copy> LastPoint<P> {
    /// The value at `(t, y)`: the kept one if it is of these values, else `at()`, then kept.
    pub fn get_or(&self, t: f64, y: &[f64], at: impl FnOnce() -> P) -> P {
        let key = [t.to_bits(), y[0].to_bits(), y[1].to_bits(), y[2].to_bits()];
        if self.key.get() == key
            && let Some(p) = self.value.get()
        {
            return p;
        }
        let p = at();
        self.key.set(key);
        self.value.set(Some(p));
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn last_at_computes_once_per_instant() {
        let calls = Cell::new(0);
        let kept = LastAt::default();
        let f = |t: f64| {
            kept.get_or(t, || {
                calls.set(calls.get() + 1);
                2.0 * t
            })
        };
        assert_eq!((f(0.5), f(0.5), calls.get()), (1.0, 1.0, 1));
        // another instant, however near, is computed
        let near = f64::from_bits(0.5f64.to_bits() + 1);
        assert_eq!((f(near), calls.get()), (2.0 * near, 2));
        // both are kept, and more instants up to LAST_AT
        assert_eq!((f(0.5), f(near), calls.get()), (1.0, 2.0 * near, 2));
        for i in 1..LAST_AT {
            f(i as f64);
        }
        assert_eq!(calls.get(), 1 + LAST_AT);
        // the oldest (0.5) made way for the last of them
        assert_eq!((f(near), calls.get()), (2.0 * near, 1 + LAST_AT));
        assert_eq!((f(0.5), calls.get()), (1.0, 2 + LAST_AT));
    }

    #[test]
    fn last_point_computes_once_per_time_and_state() {
        let calls = Cell::new(0);
        let kept = LastPoint::default();
        let f = |t: f64, y: [f64; 3]| {
            kept.get_or(t, &y, || {
                calls.set(calls.get() + 1);
                t + y[0] + 2.0 * y[1] + 3.0 * y[2]
            })
        };
        assert_eq!((f(0.5, [1.0, 2.0, 3.0]), calls.get()), (14.5, 1));
        assert_eq!((f(0.5, [1.0, 2.0, 3.0]), calls.get()), (14.5, 1));
        // another time or any other state is computed
        assert_eq!((f(0.25, [1.0, 2.0, 3.0]), calls.get()), (14.25, 2));
        assert_eq!((f(0.25, [1.0, 2.0, 4.0]), calls.get()), (17.25, 3));
        assert_eq!((f(0.25, [1.0, 2.5, 4.0]), calls.get()), (18.25, 4));
        assert_eq!((f(0.25, [0.0, 2.5, 4.0]), calls.get()), (17.25, 5));
    }
}
