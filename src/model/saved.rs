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
}
