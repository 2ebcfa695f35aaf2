//! The runs of a sweep: the grid of its grid and list axes, times the samples of its random
//! axes (Monte Carlo or Latin hypercube), each random value from a stream of its own seeded by
//! the sweep's seed and the sample's number, so a run's values do not depend on which process
//! or thread computes it, nor on the order the runs are done in.

/// How a swept parameter takes its values.
#[derive(Clone, Debug, PartialEq)]
pub enum Axis {
    /// Given values, in order (`values = [...]`, or `from`, `to`, `points`: evenly spaced).
    Values(Vec<f64>),
    /// Drawn from a distribution, once per sample.
    Random(Dist),
}

/// A distribution of a random axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Dist {
    /// Uniform on `[lo, hi]`.
    Uniform { lo: f64, hi: f64 },
    /// Normal with mean and standard deviation.
    Normal { mean: f64, sd: f64 },
}

impl Dist {
    /// The value at probability `u` in (0, 1) (the inverse of the distribution function).
    pub fn at(&self, u: f64) -> f64 {
        match *self {
            Dist::Uniform { lo, hi } => lo + (hi - lo) * u,
            Dist::Normal { mean, sd } => mean + sd * normal_quantile(u),
        }
    }
}

/// How the samples of the random axes are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Independent draws.
    MonteCarlo,
    /// One draw in each of `samples` equally probable strata of every axis, the strata paired
    /// at random (McKay, Beckman and Conover 1979).
    LatinHypercube,
}

/// The runs of a sweep: `axes` in the order written, `samples` draws of the random ones for each
/// point of the grid of the others.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    pub axes: Vec<Axis>,
    pub method: Method,
    /// Draws per grid point (1 when no axis is random).
    pub samples: usize,
    pub seed: u64,
}

impl Design {
    /// Number of runs: the product of the value axes' lengths, times the samples.
    pub fn runs(&self) -> usize {
        self.axes
            .iter()
            .map(|a| match a {
                Axis::Values(v) => v.len(),
                Axis::Random(_) => 1,
            })
            .product::<usize>()
            * self.samples
    }

    /// The values of the axes in run `run` (0-based, `< runs()`): the grid point is
    /// `run / samples` (the last value axis varies fastest), the sample `run % samples`. Every
    /// grid point sees the same samples (common random numbers: differences between grid
    /// points are not blurred by different draws).
    pub fn point(&self, run: usize) -> Vec<f64> {
        let sample = run % self.samples;
        let mut grid = run / self.samples;
        let mut out = vec![0.0; self.axes.len()];
        for (i, a) in self.axes.iter().enumerate().rev() {
            if let Axis::Values(v) = a {
                out[i] = v[grid % v.len()];
                grid /= v.len();
            }
        }
        let mut rng = SplitMix64::new(self.seed ^ sample as u64 ^ 0xA076_1D64_78BD_642F);
        for (dim, a) in self.axes.iter().enumerate() {
            if let Axis::Random(d) = a {
                let u = rng.open01();
                let u = match self.method {
                    Method::MonteCarlo => u,
                    Method::LatinHypercube => {
                        let stratum = self.strata(dim)[sample];
                        (stratum as f64 + u) / self.samples as f64
                    }
                };
                out[dim] = d.at(u);
            }
        }
        out
    }

    /// The stratum of each sample on random axis `dim` (a permutation of `0..samples`).
    fn strata(&self, dim: usize) -> Vec<usize> {
        let mut p: Vec<usize> = (0..self.samples).collect();
        let mut rng = SplitMix64::new(self.seed.rotate_left(17) ^ ((dim as u64 + 1) * 0x9E37_79B9));
        for i in (1..p.len()).rev() {
            p.swap(i, rng.below(i as u64 + 1) as usize);
        }
        p
    }
}

/// Steele, Lea and Flood's SplitMix64: a small generator with good statistical quality, used
/// here for its exact reproducibility on every platform.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        let mut s = SplitMix64(seed);
        s.next_u64(); // the seed's bits mixed before the first draw
        s
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in the open interval (0, 1): the midpoints of 2^53 equal cells.
    pub fn open01(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform integer in `0..n` (`n > 0`), without modulo bias (Lemire's method).
    pub fn below(&mut self, n: u64) -> u64 {
        loop {
            let m = u128::from(self.next_u64()) * u128::from(n);
            let low = m as u64;
            if low >= n.wrapping_neg() % n {
                return (m >> 64) as u64;
            }
        }
    }
}

/// The standard normal distribution's quantile Φ⁻¹(p), p in (0, 1): Wichura's algorithm AS 241
/// (PPND16, Applied Statistics 37, 1988), relative error about 1e-16. The coefficients as
/// published.
#[allow(clippy::excessive_precision)]
pub fn normal_quantile(p: f64) -> f64 {
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        let r = 0.180625 - q * q;
        return q
            * (((((((2509.0809287301227 * r + 33430.575583588128) * r + 67265.7709270087) * r
                + 45921.95393154987)
                * r
                + 13731.693765509461)
                * r
                + 1971.5909503065513)
                * r
                + 133.14166789178438)
                * r
                + 3.3871328727963665)
            / (((((((5226.495278852545 * r + 28729.085735721943) * r + 39307.89580009271) * r
                + 21213.794301586597)
                * r
                + 5394.196021424751)
                * r
                + 687.1870074920579)
                * r
                + 42.31333070160091)
                * r
                + 1.0);
    }
    let r = if q < 0.0 { p } else { 1.0 - p };
    let r = (-r.ln()).sqrt();
    let x = if r <= 5.0 {
        let r = r - 1.6;
        (((((((7.745450142783414e-4 * r + 0.022723844989269184) * r + 0.2417807251774506) * r
            + 1.2704582524523684)
            * r
            + 3.6478483247632045)
            * r
            + 5.769497221460691)
            * r
            + 4.630337846156546)
            * r
            + 1.4234371107496835)
            / (((((((1.0507500716444169e-9 * r + 5.475938084995345e-4) * r
                + 0.015198666563616457)
                * r
                + 0.14810397642748008)
                * r
                + 0.6897673349851)
                * r
                + 1.6763848301838038)
                * r
                + 2.053191626637759)
                * r
                + 1.0)
    } else {
        let r = r - 5.0;
        (((((((2.0103343992922881e-7 * r + 2.7115555687434876e-5) * r + 0.0012426609473880784)
            * r
            + 0.026532189526576124)
            * r
            + 0.2965605718285049)
            * r
            + 1.7848265399172913)
            * r
            + 5.463784911164114)
            * r
            + 6.657904643501103)
            / (((((((2.0442631033899397e-15 * r + 1.421511758316446e-7) * r
                + 1.8463183175100548e-5)
                * r
                + 7.868691311456133e-4)
                * r
                + 0.014875361290850615)
                * r
                + 0.1369298809227358)
                * r
                + 0.599832206555888)
                * r
                + 1.0)
    };
    if q < 0.0 { -x } else { x }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Φ(x) by the complementary error function's continued fraction is not in std; the test
    /// checks Φ⁻¹ against printed quantiles (Abramowitz and Stegun, table 26.5) and its symmetry.
    #[test]
    fn normal_quantile_matches_the_tables() {
        for (p, x) in [
            (0.975, 1.959_963_984_540_054),
            (0.95, 1.644_853_626_951_472_2),
            (0.999, 3.090_232_306_167_813_5),
            (1e-10, -6.361_340_902_404_056),
            (0.5, 0.0),
            (0.841_344_746_068_542_9, 1.0),
        ] {
            assert!(
                (normal_quantile(p) - x).abs() <= 1e-14 * x.abs().max(1.0),
                "p = {p}: {} vs {x}",
                normal_quantile(p)
            );
            // 1 - p is rounded to a double (relative error 1e-7 at p = 1e-10), Φ⁻¹ with it
            let mirrored = normal_quantile(1.0 - p) + normal_quantile(p);
            assert!(mirrored.abs() <= 1e-7, "p = {p}: {mirrored}");
        }
    }

    fn design(method: Method, samples: usize) -> Design {
        Design {
            axes: vec![
                Axis::Values(vec![1.0, 2.0, 3.0]),
                Axis::Random(Dist::Uniform { lo: 0.0, hi: 1.0 }),
                Axis::Values(vec![10.0, 20.0]),
                Axis::Random(Dist::Normal { mean: 5.0, sd: 0.1 }),
            ],
            method,
            samples,
            seed: 7,
        }
    }

    #[test]
    fn the_grid_varies_the_last_axis_fastest_and_every_grid_point_sees_the_same_samples() {
        let d = design(Method::MonteCarlo, 4);
        assert_eq!(d.runs(), 3 * 2 * 4);
        let p: Vec<Vec<f64>> = (0..d.runs()).map(|r| d.point(r)).collect();
        assert_eq!((p[0][0], p[0][2]), (1.0, 10.0));
        assert_eq!((p[4][0], p[4][2]), (1.0, 20.0));
        assert_eq!((p[8][0], p[8][2]), (2.0, 10.0));
        assert_eq!((p[23][0], p[23][2]), (3.0, 20.0));
        for r in 0..d.runs() {
            assert_eq!(p[r][1], p[r % 4][1]);
            assert_eq!(p[r][3], p[r % 4][3]);
        }
        // another seed draws other values
        let other = Design {
            seed: 8,
            ..d.clone()
        };
        assert_ne!(other.point(0)[1], p[0][1]);
        // the same run twice: the same values
        assert_eq!(d.point(17), p[17]);
    }

    #[test]
    fn a_latin_hypercube_puts_one_sample_in_each_stratum_of_every_axis() {
        let n = 50;
        let d = design(Method::LatinHypercube, n);
        let mut hit = vec![0; n];
        for s in 0..n {
            let u = d.point(s)[1]; // uniform on [0, 1]
            hit[(u * n as f64) as usize] += 1;
        }
        assert!(hit.iter().all(|&h| h == 1), "{hit:?}");
        // the normal axis: one sample between consecutive quantiles
        let mut hit = vec![0; n];
        for s in 0..n {
            let x = d.point(s)[3];
            let k = (0..n)
                .filter(|&k| k > 0 && 5.0 + 0.1 * normal_quantile(k as f64 / n as f64) <= x)
                .count();
            hit[k] += 1;
        }
        assert!(hit.iter().all(|&h| h == 1), "{hit:?}");
    }

    #[test]
    fn monte_carlo_draws_have_the_distributions_moments() {
        let n = 20_000;
        let d = design(Method::MonteCarlo, n);
        let (mut s1, mut s2, mut u1) = (0.0, 0.0, 0.0);
        for s in 0..n {
            let p = d.point(s);
            u1 += p[1];
            s1 += p[3];
            s2 += (p[3] - 5.0).powi(2);
        }
        let nf = n as f64;
        // standard errors: uniform mean 0.29/sqrt(n) = 0.002, normal mean 0.1/sqrt(n) = 7e-4,
        // sd of the sample variance about sd^2 sqrt(2/n) = 1e-4; five of them
        assert!((u1 / nf - 0.5).abs() < 0.01, "{}", u1 / nf);
        assert!((s1 / nf - 5.0).abs() < 0.0035, "{}", s1 / nf);
        assert!((s2 / nf - 0.01).abs() < 0.0005, "{}", s2 / nf);
    }

    #[test]
    fn below_is_in_range_and_reaches_every_value() {
        let mut r = SplitMix64::new(1);
        let mut seen = [false; 7];
        for _ in 0..1000 {
            let k = r.below(7) as usize;
            seen[k] = true;
        }
        assert!(seen.iter().all(|&s| s));
    }
}
