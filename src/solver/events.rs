//! Locating an event inside an accepted attempt: the interpolant's root, then real steps that
//! bracket the crossing, the step ending just after it.

use super::*;

impl Integrator {
    /// Locates the earliest event of the accepted attempt over `hs` from `at` (its end state and
    /// derivative in `end`), seen at `s_seen` (the step's end, or its middle on the interpolant)
    /// with the event functions `g_seen` there (`g0` at the start): the earliest root on the
    /// interpolant, then real steps that bracket it to `1e-10` of the step, the step ending just
    /// after it. `end` becomes that step's state and derivative; its length is returned. `None`:
    /// a change seen only on the interpolant that real steps do not show (no event).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn locate_event(
        &mut self,
        stepper: Stepper,
        at: Start,
        att: &Attempt,
        hs: f64,
        s_seen: f64,
        g_seen: &[f64],
        end: (&mut [f64], &mut [f64]),
        g0: &[f64],
        st: &mut Stats,
    ) -> Option<f64> {
        let Start { sys, t, y, f0 } = at;
        let (y1, f1) = end;
        let (n, ne) = (y.len(), g0.len());
        let (mut yt, mut ft, mut gt) = (vec![0.0; n], vec![0.0; n], vec![0.0; ne]);
        let crossed =
            |ga: &[f64], gb: &[f64]| ga.iter().zip(gb).any(|(a, b)| event_between(*a, *b));
        // earliest root on the interpolant
        let mut s_star = s_seen;
        for i in 0..ne {
            if !event_between(g0[i], g_seen[i]) {
                continue;
            }
            let (mut lo, mut hi) = (0.0, s_seen);
            let (mut glo, mut ghi) = (g0[i], g_seen[i]);
            for _ in 0..60 {
                let mid = if ghi != glo {
                    (lo - glo * (hi - lo) / (ghi - glo))
                        .clamp(lo + 0.01 * (hi - lo), hi - 0.01 * (hi - lo))
                } else {
                    0.5 * (lo + hi)
                };
                att.interpolate(
                    &Ends {
                        y,
                        f0,
                        y1,
                        f1,
                        h: hs,
                    },
                    mid,
                    &mut yt,
                );
                sys.events_held(t + mid, &yt, g0, &mut gt);
                if !event_between(g0[i], gt[i]) {
                    lo = mid;
                    glo = gt[i];
                } else {
                    hi = mid;
                    ghi = gt[i];
                }
                if hi - lo < 1e-12 * hs {
                    break;
                }
            }
            s_star = s_star.min(hi);
        }
        // the bracket's upper end: the step's end, or a real step to where the interpolant saw
        // the pair
        let (mut yhi, mut fhi) = (y1.to_vec(), f1.to_vec());
        if s_seen < hs {
            if self
                .attempt(stepper, at, s_seen, &mut yhi, &mut fhi, st)
                .is_err()
            {
                return None;
            }
            sys.events_held(t + s_seen, &yhi, g0, &mut gt);
            if !crossed(g0, &gt) {
                return None;
            }
        }
        // confirm with real steps: bracket [lo, hi] with the crossing inside, first just after
        // and just before the interpolant's root, then by bisection: its points depend on the
        // bracket alone, so two hosts whose communication points differ by rounding locate the
        // same event with the same steps (regula falsi on the function's values, tried, saved
        // 5-10 % of the right-hand sides on event-heavy runs but followed the rounding)
        let tol = (1e-10 * hs).max(4.0 * f64::EPSILON * t.abs().max(1.0));
        let (mut lo, mut hi) = (0.0f64, s_seen);
        let mut guess = Some((s_star + tol).min(s_seen));
        let mut second = Some((s_star - tol).max(0.0));
        let mut iter = 0;
        while hi - lo > 2.0 * tol && iter < 80 {
            iter += 1;
            let s = if let Some(g) = guess.take() {
                g
            } else if let Some(g) = second.take() {
                g
            } else {
                0.5 * (lo + hi)
            };
            if s <= lo || s >= hi {
                continue;
            }
            if self.attempt(stepper, at, s, &mut yt, &mut ft, st).is_err() {
                lo = s; // treat as not yet crossed; bisection continues
                continue;
            }
            sys.events_held(t + s, &yt, g0, &mut gt);
            if crossed(g0, &gt) {
                hi = s;
                yhi.copy_from_slice(&yt);
                fhi.copy_from_slice(&ft);
            } else {
                lo = s;
            }
        }
        y1.copy_from_slice(&yhi);
        f1.copy_from_slice(&fhi);
        Some(hi)
    }
}
