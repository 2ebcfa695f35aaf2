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
        let total: f64 = times.iter().sum();
        let enough = times.len() >= MIN_RUNS && (total >= MIN_TOTAL || times.len() >= MAX_RUNS);
        if r.is_err() {
            return (times[times.len() - 1], r);
        }
        if enough {
            times.sort_by(f64::total_cmp);
            return (times[times.len() / 2], r);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeats_short_runs_and_stops_at_an_error() {
        let mut n = 0;
        let (secs, r) = timed(|| {
            n += 1;
            Ok::<_, String>(n)
        });
        // a run of nothing: the cap
        assert_eq!((r, n), (Ok(MAX_RUNS), MAX_RUNS));
        assert!(secs < 1e-3);
        let mut m = 0;
        let (_, r) = timed(|| {
            m += 1;
            if m == 2 { Err("no".to_string()) } else { Ok(m) }
        });
        assert_eq!((r, m), (Err("no".to_string()), 2));
        // a run of 40 ms: three runs
        let mut k = 0;
        let (secs, _) = timed(|| {
            k += 1;
            std::thread::sleep(std::time::Duration::from_millis(40));
            Ok::<_, String>(())
        });
        assert_eq!(k, MIN_RUNS);
        assert!(secs >= 0.04);
    }
}
