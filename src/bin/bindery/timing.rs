//! The report's wall times: runs repeated until their median is steady, timed in rounds so
//! that the runs compared with each other share the machine's load.

use std::time::Instant;

/// At least this many runs of one measurement.
const MIN_RUNS: usize = 3;
/// Runs go on until they took this long together, s (a run of 2 ms alone moves by ±30 % with
/// the machine's other work; the median of some fifty does not).
const MIN_TOTAL: f64 = 0.1;
/// At most this many runs (odd: the median is one of them).
const MAX_RUNS: usize = 51;

/// Times `n` measurements, `once(i)` being one run of measurement `i`: each at least
/// [`MIN_RUNS`] times and until its runs took [`MIN_TOTAL`] together (at most [`MAX_RUNS`]).
/// The runs go in rounds, every measurement not yet done once a round, in turn and the other
/// way round every second round: a change of the machine's load during the measurements (an
/// editor, a build, a browser) then falls on all of them alike, not on whichever was being
/// timed while it lasted, and the ratios between them keep. `done(i, secs, result)` is told of
/// each measurement as it completes. Per measurement: the median time of a run and the last
/// result; at its first error a measurement stops with that run's time.
pub fn timed_in_rounds<T>(
    n: usize,
    mut once: impl FnMut(usize) -> Result<T, String>,
    mut done: impl FnMut(usize, f64, &Result<T, String>),
) -> Vec<(f64, Result<T, String>)> {
    let mut times: Vec<Vec<f64>> = vec![vec![]; n];
    let mut out: Vec<Option<(f64, Result<T, String>)>> = (0..n).map(|_| None).collect();
    let mut round = 0;
    while out.iter().any(Option::is_none) {
        let order: Vec<usize> = if round % 2 == 0 {
            (0..n).collect()
        } else {
            (0..n).rev().collect()
        };
        for i in order {
            if out[i].is_some() {
                continue;
            }
            let t0 = Instant::now();
            let r = once(i);
            let t = &mut times[i];
            t.push(t0.elapsed().as_secs_f64());
            let secs = if r.is_err() {
                t[t.len() - 1]
            } else if enough(t) {
                t.sort_by(f64::total_cmp);
                t[t.len() / 2]
            } else {
                continue;
            };
            done(i, secs, &r);
            out[i] = Some((secs, r));
        }
        round += 1;
    }
    out.into_iter().flatten().collect()
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
    fn an_error_ends_its_measurement_and_no_other() {
        let mut calls = [0; 2];
        let r = timed_in_rounds(
            2,
            |i| {
                calls[i] += 1;
                if i == 0 && calls[0] == 2 {
                    Err("no".to_string())
                } else {
                    Ok(calls[i])
                }
            },
            |_, _, _| {},
        );
        assert_eq!(r[0].1, Err("no".to_string()));
        assert_eq!(calls[0], 2);
        // the other goes on to its own end (runs of ~0 s: the cap), its last result kept
        assert_eq!(calls[1], MAX_RUNS);
        assert_eq!(r[1].1, Ok(MAX_RUNS));
    }

    #[test]
    fn the_runs_alternate_in_rounds_forth_and_back() {
        let mut seen = vec![];
        let mut told = vec![];
        let r = timed_in_rounds(
            3,
            |i| {
                seen.push(i);
                // measurement 1 is slow (three runs are enough), the others run to the cap
                if i == 1 {
                    std::thread::sleep(std::time::Duration::from_millis(40));
                }
                Ok(i)
            },
            |i, secs, _| told.push((i, secs)),
        );
        assert_eq!(&seen[..9], &[0, 1, 2, 2, 1, 0, 0, 1, 2]);
        // after its third run measurement 1 is done; the rounds go on without it
        assert_eq!(&seen[9..13], &[2, 0, 0, 2]);
        assert_eq!(seen.iter().filter(|&&i| i == 1).count(), 3);
        assert_eq!(seen.len(), 3 + 2 * MAX_RUNS);
        // each measurement is told once, the slow one first, with its median (≥ 40 ms)
        assert_eq!(told.iter().map(|t| t.0).collect::<Vec<_>>(), [1, 0, 2]);
        assert!(told[0].1 >= 0.04 && r[1].0 == told[0].1);
        assert_eq!(
            r.iter().map(|x| x.1.clone().unwrap()).collect::<Vec<_>>(),
            [0, 1, 2]
        );
    }
}
