//! Whether memory keeps growing over a long run. A leak grows with every cycle of the same work;
//! a cache (an allocator's pool, a driver's shader or descriptor cache) grows until it holds what
//! the work needs and then stops. So a long run is sampled once per cycle, the first half of its
//! cycles is warm-up (whatever fills there and stops is a cache), and the second half is judged:
//! the least-squares slope of the samples against the cycle number, and whether that slope is
//! larger than the samples' own noise allows — a permutation test, which assumes nothing about
//! the noise's distribution (resident memory moves in pages and allocator chunks, not normally)
//! and, seeded, gives the same answer every time.

use crate::scene::hash::SeededRng;

/// Fewest judged samples: below this no ordering is rare enough to call a trend at [`ALPHA`]
/// (the smallest one-sided p of `n` distinct samples is 1/n!: 1/40 320 at 8).
pub const MIN_JUDGED: usize = 8;

/// A slope whose one-sided p is below this is growth. Small, because a fleet runs many soaks:
/// at 0.001, 21 soaks (three techniques on seven configurations) call a plateau a leak about
/// once in fifty matrix runs.
pub const ALPHA: f64 = 0.001;

/// Up to this many judged samples every ordering is counted (8! = 40 320).
pub const EXACT_UP_TO: usize = 8;

/// Orderings drawn (seeded) above [`EXACT_UP_TO`] samples: the p-value's resolution.
pub const PERMUTATIONS: usize = 20_000;

/// The trend of the judged samples.
#[derive(Clone, Debug, PartialEq)]
pub struct Growth {
    /// Least-squares slope: units (bytes, objects) per cycle.
    pub per_cycle: f64,
    /// Standard deviation of the samples around the fitted line: the noise of identical cycles.
    pub noise: f64,
    /// One-sided p-value of the slope: the share of the samples' orderings whose slope is at
    /// least as large (exact up to [`EXACT_UP_TO`] samples).
    pub p: f64,
    /// How many samples were judged (the second half of the cycles).
    pub judged: usize,
}

impl Growth {
    /// Growth that keeps going: a positive slope that the noise does not explain, rising over the
    /// judged cycles by at least `step`, the step the quantity moves in without leaking (an
    /// allocator takes memory from the system in steps: one of them is not a leak).
    pub fn is_leak(&self, step: u64) -> bool {
        self.per_cycle > 0.0 && self.p < ALPHA && self.rise() >= step as f64
    }

    /// The fitted line's rise from the first judged cycle to the last.
    pub fn rise(&self) -> f64 {
        self.per_cycle * (self.judged - 1) as f64
    }
}

/// The cycles judged among `cycles` sampled ones: the second half (the first is warm-up).
pub fn judged_cycles(cycles: usize) -> std::ops::Range<usize> {
    cycles / 2..cycles
}

/// The growth of `samples`, one per cycle in order, judged over their second half; `None` when
/// that half has fewer than [`MIN_JUDGED`] samples.
pub fn growth(samples: &[u64]) -> Option<Growth> {
    let judged = &samples[judged_cycles(samples.len())];
    if judged.len() < MIN_JUDGED {
        return None;
    }
    let observed = slope_numerator(judged.iter().copied());
    let (per_cycle, noise) = fit(judged, observed);
    Some(Growth { per_cycle, noise, p: slope_p(judged, observed), judged: judged.len() })
}

/// The least-squares slope of `samples` against their index, from their slope numerator
/// `observed`, and the standard deviation of the samples around that line.
fn fit(samples: &[u64], observed: i128) -> (f64, f64) {
    let n = samples.len();
    // At doubled centred positions xᵢ = 2i − (n − 1), Σ xᵢ² = n(n² − 1)/3, and the slope per
    // cycle is 2 Σ xᵢyᵢ / Σ xᵢ².
    let per_cycle = 2.0 * observed as f64 / ((n * (n * n - 1)) as f64 / 3.0);
    let mean = samples.iter().map(|&y| y as f64).sum::<f64>() / n as f64;
    let centre = (n - 1) as f64 / 2.0;
    let residual_squares: f64 =
        samples.iter().enumerate().map(|(i, &y)| (y as f64 - mean - per_cycle * (i as f64 - centre)).powi(2)).sum();
    (per_cycle, (residual_squares / (n - 2) as f64).sqrt())
}

/// Σ (2i − (n − 1)) yᵢ: twice the slope's numerator, exact in integers (so ties compare equal).
fn slope_numerator(samples: impl ExactSizeIterator<Item = u64>) -> i128 {
    let n = samples.len() as i128;
    samples.enumerate().map(|(i, y)| (2 * i as i128 - (n - 1)) * i128::from(y)).sum()
}

/// One-sided p of the slope numerator `observed` among the orderings of `samples`: every ordering
/// up to [`EXACT_UP_TO`] samples, else [`PERMUTATIONS`] seeded ones (counting the observed
/// ordering itself, so the p is never 0).
fn slope_p(samples: &[u64], observed: i128) -> f64 {
    match samples.len() {
        n if n <= EXACT_UP_TO => {
            let count: u64 = (1..=n as u64).product();
            let at_least = every_ordering(samples).filter(|&s| s >= observed).count();
            at_least as f64 / count as f64
        }
        _ => {
            let mut rng = SeededRng::new(samples.len() as u32);
            let mut shuffled = samples.to_vec();
            let at_least = (0..PERMUTATIONS)
                .filter(|_| {
                    shuffle(&mut shuffled, &mut rng);
                    slope_numerator(shuffled.iter().copied()) >= observed
                })
                .count();
            (1 + at_least) as f64 / (1 + PERMUTATIONS) as f64
        }
    }
}

/// Puts `values` in a uniformly drawn order (Fisher–Yates).
fn shuffle(values: &mut [u64], rng: &mut SeededRng) {
    for i in (1..values.len()).rev() {
        values.swap(i, rng.range(0, i as u32 + 1) as usize);
    }
}

/// The slope numerators of every ordering of `samples` (Heap's algorithm).
fn every_ordering(samples: &[u64]) -> impl Iterator<Item = i128> {
    let mut order = samples.to_vec();
    let mut counters = vec![0usize; order.len()];
    let mut first = true;
    let mut i = 0;
    std::iter::from_fn(move || {
        if first {
            first = false;
            return Some(slope_numerator(order.iter().copied()));
        }
        while i < order.len() {
            if counters[i] < i {
                order.swap(if i % 2 == 0 { 0 } else { counters[i] }, i);
                counters[i] += 1;
                i = 0;
                return Some(slope_numerator(order.iter().copied()));
            }
            counters[i] = 0;
            i += 1;
        }
        None
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Samples around a level with seeded noise of ±`spread`, plus `slope` per cycle.
    fn noisy(cycles: usize, level: u64, spread: u32, slope: u64, seed: u32) -> Vec<u64> {
        let mut rng = SeededRng::new(seed);
        (0..cycles).map(|i| level + slope * i as u64 + u64::from(rng.range(0, 2 * spread + 1))).collect()
    }

    #[test]
    fn too_few_judged_samples_give_no_verdict() {
        assert_eq!(growth(&[1; 14]), None);
        assert_eq!(growth(&[1; 15]).map(|g| g.judged), Some(MIN_JUDGED));
    }

    #[test]
    fn the_first_half_is_warm_up() {
        assert_eq!(judged_cycles(20), 10..20);
        assert_eq!(judged_cycles(21), 10..21);
        // A cache that fills during warm-up and then holds: a plateau, no leak.
        let mut samples = vec![100, 150, 200, 250, 300, 350, 400, 450, 500, 500];
        samples.extend([500; 10]);
        let plateau = growth(&samples).unwrap();
        assert_eq!((plateau.per_cycle, plateau.noise, plateau.p), (0.0, 0.0, 1.0));
        assert!(!plateau.is_leak(0));
    }

    #[test]
    fn a_steady_leak_is_measured_and_called_one() {
        // 1 MiB a cycle under ±256 KiB of noise.
        let samples = noisy(20, 200 << 20, 256 << 10, 1 << 20, 7);
        let leak = growth(&samples).unwrap();
        assert!((leak.per_cycle / f64::from(1 << 20) - 1.0).abs() < 0.1, "{leak:?}");
        assert!(leak.noise > 0.0 && leak.noise < f64::from(512 << 10), "{leak:?}");
        assert!(leak.is_leak(0) && leak.is_leak(8 << 20), "{leak:?}");
        // Nine cycles of 1 MiB: not a rise of 10 MiB.
        assert!(!leak.is_leak(10 << 20), "{leak:?}");
        assert_eq!(leak.judged, 10);
    }

    #[test]
    fn a_shrinking_series_is_no_leak() {
        let samples: Vec<u64> = (0..20).map(|i| 1000 - i).collect();
        let shrink = growth(&samples).unwrap();
        assert!(shrink.per_cycle < 0.0 && !shrink.is_leak(0));
    }

    #[test]
    fn one_step_up_is_not_a_trend() {
        // A pool that takes one more block once in the judged half: rare, but not rare enough.
        let mut samples = vec![7; 15];
        samples.extend([8; 5]);
        let step = growth(&samples).unwrap();
        assert!(step.per_cycle > 0.0 && step.p > ALPHA && !step.is_leak(0), "{step:?}");
    }

    #[test]
    fn exact_orderings_are_counted_plainly() {
        // Eight distinct increasing samples: only the observed ordering has the largest slope.
        let rising: Vec<u64> = (0..16).collect();
        let exact = growth(&rising).unwrap();
        assert_eq!(exact.p, 1.0 / 40_320.0);
        assert!(exact.is_leak(7) && !exact.is_leak(8));
    }

    #[test]
    fn the_shuffle_draws_every_ordering_alike() {
        // 60 000 shuffles of four values: each of the 24 orderings 2 500 times expected, within
        // 4.5 binomial standard deviations (4.5 · √(60 000 · 1/24 · 23/24) ≈ 220).
        let mut rng = SeededRng::new(4);
        let mut counts = std::collections::BTreeMap::new();
        for _ in 0..60_000 {
            let mut values = [0, 1, 2, 3];
            shuffle(&mut values, &mut rng);
            *counts.entry(values).or_insert(0) += 1;
        }
        assert_eq!(counts.len(), 24);
        assert!(counts.values().all(|&n| (2_280..=2_720).contains(&n)), "{counts:?}");
    }

    #[test]
    fn drawn_orderings_estimate_the_exact_p() {
        // Nine samples: drawn orderings (above EXACT_UP_TO), against all 9! counted. The estimate
        // of a p in (0.1, 0.4) from 20 000 uniform draws lies within 4.5 binomial standard
        // deviations of it.
        let samples = [3, 1, 4, 1, 5, 9, 2, 6, 5];
        let observed = slope_numerator(samples.iter().copied());
        let at_least = every_ordering(&samples).filter(|&s| s >= observed).count();
        let exact = at_least as f64 / 362_880.0;
        let drawn = slope_p(&samples, observed);
        let sigma = (exact * (1.0 - exact) / PERMUTATIONS as f64).sqrt();
        assert!((0.1..0.4).contains(&exact), "exact p {exact}");
        assert!((drawn - exact).abs() < 4.5 * sigma, "drawn {drawn}, exact {exact}");
    }

    /// Every ordering by plain recursion, for comparison with Heap's algorithm.
    fn orderings_by_recursion(rest: &mut Vec<u64>, prefix: &mut Vec<u64>, out: &mut Vec<i128>) {
        if rest.is_empty() {
            out.push(slope_numerator(prefix.iter().copied()));
        }
        for i in 0..rest.len() {
            let y = rest.remove(i);
            prefix.push(y);
            orderings_by_recursion(rest, prefix, out);
            prefix.pop();
            rest.insert(i, y);
        }
    }

    proptest! {
        #[test]
        fn every_ordering_visits_each_permutation_once(samples in proptest::collection::vec(0u64..6, 1..7)) {
            let mut heap: Vec<i128> = every_ordering(&samples).collect();
            let mut plain = Vec::new();
            orderings_by_recursion(&mut samples.clone(), &mut Vec::new(), &mut plain);
            heap.sort();
            plain.sort();
            prop_assert_eq!(heap, plain);
        }

        #[test]
        fn the_fit_is_the_least_squares_line(judged in proptest::collection::vec(0u64..1_000_000, 3..40)) {
            let y: Vec<f64> = judged.iter().map(|&v| v as f64).collect();
            let n = y.len() as f64;
            let (mx, my) = ((n - 1.0) / 2.0, y.iter().sum::<f64>() / n);
            let sxy: f64 = y.iter().enumerate().map(|(i, v)| (i as f64 - mx) * (v - my)).sum();
            let sxx: f64 = (0..y.len()).map(|i| (i as f64 - mx).powi(2)).sum();
            let slope = sxy / sxx;
            let residuals: f64 = y.iter().enumerate().map(|(i, v)| (v - my - slope * (i as f64 - mx)).powi(2)).sum();
            let (per_cycle, noise) = fit(&judged, slope_numerator(judged.iter().copied()));
            prop_assert!((per_cycle - slope).abs() <= 1e-6 * (1.0 + slope.abs()));
            let plain_noise = (residuals / (n - 2.0)).sqrt();
            prop_assert!((noise - plain_noise).abs() <= 1e-6 * (1.0 + plain_noise));
        }

    }

    proptest! {
        // Few cases: each draws 20 000 orderings twice.
        #![proptest_config(ProptestConfig::with_cases(16))]
        #[test]
        fn the_verdict_does_not_depend_on_the_level(samples in proptest::collection::vec(0u64..1000, 16..24), level in 0u64..1 << 40) {
            let shifted: Vec<u64> = samples.iter().map(|y| y + level).collect();
            let (a, b) = (growth(&samples).unwrap(), growth(&shifted).unwrap());
            prop_assert_eq!(a.p, b.p);
            prop_assert_eq!(a.is_leak(1), b.is_leak(1));
        }
    }
}
