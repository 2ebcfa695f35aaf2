//! Checks of the numbers a model keeps in an FMU state ([`super::Dynamics::save_state`]): a
//! host may hand back a state it altered, so a model reads none of them before they pass.

/// `s` holds one of the lengths `lens` (the first is the usual one); else the error names
/// `what` and every length it could have.
pub fn expect_len(what: &str, s: &[f64], lens: &[usize]) -> Result<(), String> {
    if lens.contains(&s.len()) {
        return Ok(());
    }
    let expected: Vec<String> = lens.iter().map(|n| n.to_string()).collect();
    Err(format!(
        "{what} has {} numbers, expected {}",
        s.len(),
        expected.join(" or ")
    ))
}

/// What a saved number may be (`crate::chain_memory!`: a field's rule in brackets after its
/// type; an `f64` without one is [`Rule::Finite`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rule {
    /// A finite number.
    Finite,
    /// A finite whole number (the index of a shaft turn).
    Whole,
    /// A whole number, or NaN while none is known (the turn before the first step).
    WholeOrNan,
    /// A whole number from 0 below 2^53 (a count).
    Count,
    /// Finite, or NaN while none is known (a ratio of a turn not yet complete).
    OrNan,
    /// Finite, or +∞ while none is known (a running minimum).
    OrInf,
}

impl Rule {
    /// `x` if it keeps the rule, else the error naming `what`.
    pub fn check(self, what: &str, x: f64) -> Result<f64, String> {
        let (ok, expected) = match self {
            Rule::Finite => (x.is_finite(), "a finite number"),
            Rule::Whole => (x.is_finite() && x.fract() == 0.0, "a whole number"),
            Rule::WholeOrNan => (
                x.is_nan() || x.is_finite() && x.fract() == 0.0,
                "a whole number or NaN (none yet)",
            ),
            Rule::Count => (
                (0.0..9.007_199_254_740_992e15).contains(&x) && x.fract() == 0.0,
                "a count (a whole number from 0)",
            ),
            Rule::OrNan => (!x.is_infinite(), "a finite number or NaN (none yet)"),
            Rule::OrInf => (
                x.is_finite() || x == f64::INFINITY,
                "a finite number or +inf (none yet)",
            ),
        };
        if ok {
            Ok(x)
        } else {
            Err(format!("{what} = {x:?}, not {expected}"))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_are_named_when_refused() {
        assert_eq!(expect_len("x", &[0.0; 3], &[3]), Ok(()));
        assert_eq!(expect_len("x", &[0.0; 4], &[3, 4]), Ok(()));
        assert_eq!(
            expect_len("x", &[0.0; 2], &[3, 4]),
            Err("x has 2 numbers, expected 3 or 4".to_string())
        );
        assert_eq!(
            expect_len("y", &[], &[5]),
            Err("y has 0 numbers, expected 5".to_string())
        );
    }

    #[test]
    fn rules_take_what_they_name_and_refuse_the_rest() {
        let (inf, nan) = (f64::INFINITY, f64::NAN);
        let cases: [(Rule, &[f64], &[f64]); 6] = [
            (Rule::Finite, &[0.0, -1.5, 1e300], &[nan, inf, -inf]),
            (Rule::Whole, &[0.0, -3.0, 1e20], &[0.5, nan, inf]),
            (Rule::WholeOrNan, &[0.0, -3.0, nan], &[0.5, inf, -inf]),
            (
                Rule::Count,
                &[0.0, 7.0, 9e15],
                &[-1.0, 0.5, 1e16, 1e300, nan, inf],
            ),
            (Rule::OrNan, &[nan, 2.5], &[inf, -inf]),
            (Rule::OrInf, &[inf, -2.0], &[nan, -inf]),
        ];
        for (rule, good, bad) in cases {
            for &x in good {
                assert!(rule.check("x", x).is_ok(), "{rule:?} {x}");
            }
            for &x in bad {
                let e = rule.check("x", x).unwrap_err();
                assert!(e.starts_with(&format!("x = {x:?}, not ")), "{e}");
            }
        }
    }
}
