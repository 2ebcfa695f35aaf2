//! The report's wall times: one run repeated until its median is steady.

use std::time::Instant;

/// At least this many runs of one measurement.
const MIN_RUNS: usize = 3;
/// Runs go on until they took this long together, s (a run of 2 ms alone moves by ±30 % with
/// the machine's other work; the median of some fifty does not).
const MIN_TOTAL: f64 = 0.1;
/// At most this many runs (odd: the median is one of them).
const MAX_RUNS: usize = 51;

/// Runs `once` at least [`MIN_RUNS`] times and until they took [`MIN_TOTAL`] together (at most
/// [`MAX_RUNS`]): the median time of a run and the last result. At the first error it stops,
/// with that run's time.
pub fn timed<T>(mut once: impl FnMut() -> Result<T, String>) -> (f64, Result<T, String>) {
    let mut times = vec![];
    loop {
        let t0 = Instant::now();
        let r = once();
        times.push(t0.elapsed().as_secs_f64());
        if r.is_err() {
            return (times[times.len() - 1], r);
        }
        if enough(&times) {
            times.sort_by(f64::total_cmp);
            return (times[times.len() / 2], r);
        }
    }
}

/// Whether the runs that took `times` (s) are enough: at least [`MIN_RUNS`], and together
/// [`MIN_TOTAL`] or [`MAX_RUNS`] of them.
fn enough(times: &[f64]) -> bool {
    let total: f64 = times.iter().sum();
    times.len() >= MIN_RUNS && (total >= MIN_TOTAL || times.len() >= MAX_RUNS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_runs_are_repeated_to_the_total_long_ones_three_times() {
        // runs of 40 ms: three (120 ms); of 1/64 s: seven (109 ms); of 1 µs: the cap
        assert!(!enough(&[0.04; 2]) && enough(&[0.04; 3]));
        assert!(!enough(&[0.015625; 6]) && enough(&[0.015625; 7]));
        assert!(!enough(&[1e-6; MAX_RUNS - 1]) && enough(&[1e-6; MAX_RUNS]));
        // a slow first run does not end it before three
        assert!(!enough(&[1.0, 1.0]));
    }

    #[test]
    fn an_error_ends_the_runs_with_it() {
        let mut m = 0;
        let (_, r) = timed(|| {
            m += 1;
            if m == 2 { Err("no".to_string()) } else { Ok(m) }
        });
        assert_eq!((r, m), (Err("no".to_string()), 2));
    }
}
