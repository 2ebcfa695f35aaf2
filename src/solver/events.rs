//! Locating an event inside an accepted attempt: the interpolant's root, then real steps that
//! bracket the crossing (regula falsi on their values), the step ending just after it.

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
        let mut g_hi = g_seen.to_vec();
        if s_seen < hs {
            if self
                .attempt(stepper, at, s_seen, &mut yhi, &mut fhi, st)
                .is_err()
            {
                return None;
            }
            sys.events_held(t + s_seen, &yhi, g0, &mut g_hi);
            if !crossed(g0, &g_hi) {
                return None;
            }
        }
        // confirm with real steps: bracket [lo, hi] with the crossing inside, first just after
        // and just before the interpolant's root; then regula falsi (Illinois) on the real steps'
        // values, the earliest root of the functions that cross by `hi`, aimed a tolerance past
        // it on the side of the bracket that did not move last (so that both ends close in), and
        // bisection where that stalls. The probes stay near the root: within `LU_SLACK` of one
        // another, Radau IIA's attempts share one factorization (bisection from the step's
        // start took ~40 attempts, ~10 of them with a factorization of their own)
        let tol = (1e-10 * hs).max(4.0 * f64::EPSILON * t.abs().max(1.0));
        let (mut lo, mut hi) = (0.0f64, s_seen);
        // the functions at both ends, and the Illinois weight of each end's values
        let (mut g_lo, mut w) = (g0.to_vec(), [1.0f64; 2]);
        let mut guess = Some((s_star + tol).min(s_seen));
        let mut second = Some((s_star - tol).max(0.0));
        // which end the last probe moved, and how many probes in a row moved it; regula falsi's
        // probes since the bracket last halved, and its width then
        let (mut moved_hi, mut same) = (true, 0);
        let (mut n_fp, mut w_ref) = (0, f64::INFINITY);
        let mut iter = 0;
        while hi - lo > 2.0 * tol && iter < 80 {
            iter += 1;
            let s = if let Some(g) = guess.take() {
                g
            } else if let Some(g) = second.take() {
                g
            } else {
                // regula falsi while it halves the bracket every three probes, on values that
                // say where the root is (a function coming to rest is held at zero)
                if hi - lo <= 0.5 * w_ref {
                    (n_fp, w_ref) = (0, hi - lo);
                }
                let fp = (0..ne)
                    .filter(|&i| n_fp < 3 && event_between(g0[i], g_hi[i]))
                    .filter(|&i| g_lo[i].abs() != HELD && g_hi[i].abs() != HELD)
                    .map(|i| {
                        let (a, b) = (w[0] * g_lo[i], w[1] * g_hi[i]);
                        lo - a * (hi - lo) / (b - a)
                    })
                    .filter(|s| s.is_finite())
                    .reduce(f64::min);
                match fp {
                    Some(fp) => {
                        n_fp += 1;
                        (if moved_hi { fp - tol } else { fp + tol })
                            .clamp(lo + 0.5 * tol, hi - 0.5 * tol)
                    }
                    None => 0.5 * (lo + hi),
                }
            };
            if s <= lo || s >= hi {
                continue;
            }
            let crossed_at_s = match self.attempt(stepper, at, s, &mut yt, &mut ft, st) {
                Ok(_) => {
                    sys.events_held(t + s, &yt, g0, &mut gt);
                    crossed(g0, &gt)
                }
                // treat as not yet crossed, its values unknown: bisection continues
                Err(_) => {
                    gt.fill(f64::NAN);
                    false
                }
            };
            let was_hi = std::mem::replace(&mut moved_hi, crossed_at_s);
            same = if moved_hi == was_hi { same + 1 } else { 1 };
            // (Illinois: an end kept twice in a row counts half its values)
            let (moved, kept) = if moved_hi { (1, 0) } else { (0, 1) };
            w[moved] = 1.0;
            if same >= 2 {
                w[kept] *= 0.5;
            }
            if moved_hi {
                hi = s;
                g_hi.copy_from_slice(&gt);
                yhi.copy_from_slice(&yt);
                fhi.copy_from_slice(&ft);
            } else {
                lo = s;
                g_lo.copy_from_slice(&gt);
            }
        }
        y1.copy_from_slice(&yhi);
        f1.copy_from_slice(&fhi);
        Some(hi)
    }
}
