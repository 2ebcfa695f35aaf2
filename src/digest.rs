//! Warnings gathered over a shaft turn: at most one warning per kind per turn, with the count
//! of that turn's occurrences and the worst of them. A mechanism keeps one [`TurnDigest`] per
//! kind of warning; the numbers it holds are part of the FMU state, so a replayed run logs the
//! same lines.

use crate::model::saved::Rule;
use crate::model::{Log, Severity};

/// One kind of warning over the turns of the shaft: the occurrences in the turn being gathered,
/// their count, and the numbers of the worst (`worst[0]` its badness, larger is worse; the rest
/// what the report names), reported once when the turn is over ([`TurnDigest::at_turn`]) or
/// the run ends ([`TurnDigest::flush`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurnDigest<const N: usize> {
    /// The turn gathered (NaN: none yet).
    pub turn: f64,
    /// Occurrences in it.
    pub count: f64,
    /// The worst occurrence's numbers (NaN: none).
    pub worst: [f64; N],
}

impl<const N: usize> Default for TurnDigest<N> {
    fn default() -> Self {
        TurnDigest {
            turn: f64::NAN,
            count: 0.0,
            worst: [f64::NAN; N],
        }
    }
}

impl<const N: usize> TurnDigest<N> {
    /// Numbers of [`TurnDigest::save`].
    pub const LEN: usize = N + 2;

    /// The shaft is in turn `turn`: a gathered turn that is over is reported with `report`.
    pub fn at_turn(&mut self, turn: f64, log: &mut dyn Log, report: &dyn Fn(&Self) -> String) {
        if turn != self.turn {
            self.flush(log, report);
            self.turn = turn;
        }
    }

    /// One occurrence in turn `turn` with its numbers `data`.
    pub fn note(
        &mut self,
        turn: f64,
        data: [f64; N],
        log: &mut dyn Log,
        report: &dyn Fn(&Self) -> String,
    ) {
        self.at_turn(turn, log, report);
        self.count += 1.0;
        self.worsen(data);
    }

    /// The numbers of an occurrence already counted, kept if worse (its badness larger).
    pub fn worsen(&mut self, data: [f64; N]) {
        if self.worst[0].is_nan() || data[0] > self.worst[0] {
            self.worst = data;
        }
    }

    /// Reports the gathered turn, if anything happened in it, and starts afresh.
    pub fn flush(&mut self, log: &mut dyn Log, report: &dyn Fn(&Self) -> String) {
        if self.count > 0.0 {
            log.log(Severity::Warning, &report(self));
        }
        *self = TurnDigest {
            turn: self.turn,
            ..TurnDigest::default()
        };
    }

    /// The numbers of the FMU state.
    pub fn save(&self, out: &mut Vec<f64>) {
        out.push(self.turn);
        out.push(self.count);
        out.extend_from_slice(&self.worst);
    }

    /// From [`TurnDigest::save`]'s numbers.
    pub fn restore(s: &[f64]) -> Result<Self, String> {
        crate::model::saved::expect_len("a warning digest", s, &[Self::LEN])?;
        let what = |e| format!("a warning digest: {e}");
        let count = Rule::Count.check("count", s[1]).map_err(what)?;
        let turn = Rule::WholeOrNan.check("turn", s[0]).map_err(what)?;
        let mut worst = [0.0; N];
        for (w, &x) in worst.iter_mut().zip(&s[2..]) {
            *w = Rule::OrNan.check("worst", x).map_err(what)?;
        }
        Ok(TurnDigest { turn, count, worst })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Lines(Vec<String>);
    impl Log for Lines {
        fn log(&mut self, s: Severity, m: &str) {
            assert_eq!(s, Severity::Warning);
            self.0.push(m.to_string());
        }
    }

    fn report(d: &TurnDigest<2>) -> String {
        format!(
            "turn {} x{} worst {} at {}",
            d.turn, d.count, d.worst[0], d.worst[1]
        )
    }

    #[test]
    fn one_line_per_turn_with_the_count_and_the_worst() {
        let (mut d, mut log) = (TurnDigest::<2>::default(), Lines(vec![]));
        for (turn, bad, at) in [(0.0, 4.9, 1.0), (0.0, 39.6, 2.0), (0.0, 7.0, 3.0)] {
            d.note(turn, [bad, at], &mut log, &report);
        }
        d.worsen([12.0, 2.5]); // a later sample of an occurrence, not worse
        assert!(log.0.is_empty(), "nothing before the turn is over");
        d.at_turn(1.0, &mut log, &report); // a quiet turn starts: the last one is reported
        d.at_turn(2.0, &mut log, &report); // nothing in turn 1: no line
        d.note(2.0, [1.0, 9.0], &mut log, &report);
        let saved = {
            let mut v = vec![];
            d.save(&mut v);
            v
        };
        assert_eq!(TurnDigest::<2>::restore(&saved).unwrap(), d);
        d.flush(&mut log, &report);
        d.flush(&mut log, &report);
        assert_eq!(
            log.0,
            ["turn 0 x3 worst 39.6 at 2", "turn 2 x1 worst 1 at 9"],
            "one line per turn that had any"
        );
        assert!(TurnDigest::<2>::restore(&[0.0, -1.0, 0.0, 0.0]).is_err());
        // a fresh digest (NaN: no turn, no worst) restores; a tampered one names the number
        let mut fresh = vec![];
        TurnDigest::<2>::default().save(&mut fresh);
        assert_eq!(TurnDigest::<2>::restore(&fresh).map(|d| d.count), Ok(0.0));
        for (i, x, why) in [
            (0, 0.5, "turn = 0.5, not a whole number or NaN (none yet)"),
            (
                0,
                f64::INFINITY,
                "turn = inf, not a whole number or NaN (none yet)",
            ),
            (
                1,
                1e300,
                "count = 1e300, not a count (a whole number from 0)",
            ),
            (
                3,
                f64::NEG_INFINITY,
                "worst = -inf, not a finite number or NaN (none yet)",
            ),
        ] {
            let mut bad = saved.clone();
            bad[i] = x;
            assert_eq!(
                TurnDigest::<2>::restore(&bad),
                Err(format!("a warning digest: {why}"))
            );
        }
        assert!(TurnDigest::<2>::restore(&[0.0]).is_err());
    }
}
