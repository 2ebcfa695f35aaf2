//! What a chain carries between steps besides its states, in the FMU state: [`Saved`], a fixed
//! count of numbers, written once per type ([`crate::chain_memory!`] for a struct of them), and
//! the dynamic factor's [`Peaks`].

use crate::model::saved::Rule;

/// A part of a chain's memory in the FMU state: [`Saved::LEN`] numbers.
pub trait Saved: Sized {
    /// How many numbers [`Saved::save`] writes.
    const LEN: usize;
    /// Appends the [`Saved::LEN`] numbers.
    fn save(&self, out: &mut Vec<f64>);
    /// From the [`Saved::LEN`] numbers [`Saved::save`] wrote, each checked: a host may hand
    /// back a state it altered, and nothing runs on a number the memory cannot hold.
    fn restore(s: &[f64]) -> Result<Self, String>;
}

/// A finite number ([`Rule::Finite`]).
impl Saved for f64 {
    const LEN: usize = 1;
    fn save(&self, out: &mut Vec<f64>) {
        out.push(*self);
    }
    fn restore(s: &[f64]) -> Result<f64, String> {
        Rule::Finite.check("value", s[0])
    }
}

/// 0 or 1.
impl Saved for bool {
    const LEN: usize = 1;
    fn save(&self, out: &mut Vec<f64>) {
        out.push(f64::from(u8::from(*self)));
    }
    fn restore(s: &[f64]) -> Result<bool, String> {
        match s[0] {
            0.0 => Ok(false),
            1.0 => Ok(true),
            x => Err(format!("flag = {x}, not 0 or 1")),
        }
    }
}

/// Declares a struct of a chain's memory whose fields are all [`Saved`], and its [`Saved`]
/// implementation: the fields' numbers in the order declared. An `f64` field may name its
/// [`Rule`] in brackets after its type (else [`Rule::Finite`]); a restored number that breaks
/// it refuses the FMU state, naming the field.
///
/// ```ignore
/// crate::chain_memory! {
///     /// What the ODE tracks between steps.
///     #[derive(Clone, Debug, PartialEq)]
///     struct TableMemory { peaks: Peaks, liftoffs: f64 [Count], landed: bool }
/// }
/// ```
#[macro_export]
macro_rules! chain_memory {
    (@restore $ty:ty, $s:expr, $name:expr) => {
        <$ty as $crate::solver::chain::Saved>::restore($s).map_err(|e| format!("{}: {e}", $name))
    };
    (@restore $ty:ty, $s:expr, $name:expr, $rule:ident) => {
        $crate::model::saved::Rule::$rule.check($name, $s[0])
    };
    (
        $( #[$meta:meta] )*
        $vis:vis struct $name:ident {
            $( $( #[$fmeta:meta] )* $fvis:vis $field:ident : $ty:ty $([$rule:ident])? ),+ $(,)?
        }
    ) => {
        $( #[$meta] )*
        $vis struct $name {
            $( $( #[$fmeta] )* $fvis $field: $ty ),+
        }

        impl $crate::solver::chain::Saved for $name {
            const LEN: usize = 0 $( + <$ty as $crate::solver::chain::Saved>::LEN )+;
            fn save(&self, out: &mut Vec<f64>) {
                $( $crate::solver::chain::Saved::save(&self.$field, out); )+
            }
            fn restore(s: &[f64]) -> Result<Self, String> {
                let mut at = 0;
                $(
                    let n = <$ty as $crate::solver::chain::Saved>::LEN;
                    let $field: $ty = $crate::chain_memory!(
                        @restore $ty, &s[at..at + n], stringify!($field) $(, $rule)?
                    )?;
                    at += n;
                )+
                let _ = at;
                Ok($name { $( $field ),+ })
            }
        }
    };
}

/// The dynamic-factor bookkeeping of a chain over shaft turns ([`Peaks::track`]), carried
/// between steps (the ODE holds it, with the rest of its memory, in a `Cell`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peaks {
    /// (turn, peak dynamic force, peak rigid force) of the running turn.
    pub turn: (f64, f64, f64),
    /// K_d of the last complete turn (NaN: none yet).
    pub k_d: f64,
}

impl Peaks {
    /// Nothing tracked yet, in turn `turn`, no K_d.
    pub fn new(turn: f64) -> Peaks {
        Peaks {
            turn: (turn, 0.0, 0.0),
            k_d: f64::NAN,
        }
    }

    /// An accepted step in turn `cycle` with chain force `f_dyn` and rigid (kinetostatic)
    /// force `f_rigid` (magnitudes): the running turn's peaks grow; at a new turn K_d becomes
    /// the ratio of the finished turn's peaks.
    pub fn track(&mut self, cycle: f64, f_dyn: f64, f_rigid: f64) {
        let p = self;
        let (c0, pd, pr) = p.turn;
        if cycle != c0 {
            if pr > 0.0 {
                p.k_d = pd / pr;
            }
            p.turn = (cycle, f_dyn, f_rigid);
        } else {
            p.turn = (c0, pd.max(f_dyn), pr.max(f_rigid));
        }
    }

    /// The dynamic factor K_d to report: that of the last complete turn, or before one is
    /// complete the running turn's peak ratio (1 without a rigid force yet).
    pub fn dyn_factor(&self) -> f64 {
        if self.k_d.is_nan() {
            if self.turn.2 > 0.0 {
                self.turn.1 / self.turn.2
            } else {
                1.0
            }
        } else {
            self.k_d
        }
    }
}

/// Turn, peak dynamic force, peak rigid force, K_d.
impl Saved for Peaks {
    const LEN: usize = 4;
    fn save(&self, out: &mut Vec<f64>) {
        let (c, pd, pr) = self.turn;
        out.extend([c, pd, pr, self.k_d]);
    }
    fn restore(s: &[f64]) -> Result<Peaks, String> {
        Ok(Peaks {
            turn: (
                Rule::Whole.check("turn", s[0])?,
                Rule::Finite.check("peak dynamic force", s[1])?,
                Rule::Finite.check("peak rigid force", s[2])?,
            ),
            k_d: Rule::OrNan.check("K_d", s[3])?,
        })
    }
}
