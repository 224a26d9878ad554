//! Whether a GPU time changed beyond its noise. Two runs with repeats (`check --repeat N`,
//! `fragkit bench`'s rounds) are compared with the Mann–Whitney U test: it asks whether one run's
//! times tend to be larger than the other's without assuming a distribution (GPU times are
//! skewed: a frame is sometimes late, never early). Where one side has a single time, earlier
//! runs of the case on the adapter give the spread instead: the median absolute deviation, which
//! one outlying run does not inflate.

/// The median of timed repeats (the upper one of an even count): timings on busy machines have
/// outliers that a mean would carry.
pub fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Two-sided p-value of the Mann–Whitney U test that `a` and `b` come from one distribution.
/// Exact (counting every split of the ranks) when both samples are small and untied, the
/// normal approximation with tie and continuity corrections otherwise.
pub fn mann_whitney_p(a: &[f64], b: &[f64]) -> f64 {
    let (n1, n2) = (a.len(), b.len());
    if n1 == 0 || n2 == 0 {
        return 1.0;
    }
    let (u, tie_term) = rank_statistic(a, b);
    if tie_term == 0.0 && n1 * n2 <= MAX_EXACT {
        exact_p(n1, n2, u.round() as usize)
    } else {
        normal_p(n1, n2, u, tie_term)
    }
}

/// The Mann–Whitney U of `a` against `b` (pairs where `a`'s value is larger, ties counting one
/// half), from the midranks of the pooled sample, and the tie term: the sum of t³ − t over the
/// groups of t equal values.
fn rank_statistic(a: &[f64], b: &[f64]) -> (f64, f64) {
    let n1 = a.len();
    let mut pooled: Vec<(f64, bool)> = a.iter().map(|&x| (x, true)).chain(b.iter().map(|&x| (x, false))).collect();
    pooled.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut rank_sum_a = 0.0;
    let mut tie_term = 0.0;
    let mut i = 0;
    while i < pooled.len() {
        let mut j = i;
        while j + 1 < pooled.len() && pooled[j + 1].0 == pooled[i].0 {
            j += 1;
        }
        let midrank = (i + j) as f64 / 2.0 + 1.0;
        let tied = (j - i + 1) as f64;
        tie_term += tied * tied * tied - tied;
        rank_sum_a += pooled[i..=j].iter().filter(|(_, from_a)| *from_a).count() as f64 * midrank;
        i = j + 1;
    }
    (rank_sum_a - (n1 * (n1 + 1)) as f64 / 2.0, tie_term)
}

/// Largest n1·n2 counted exactly (50 repeats against 50): the normal approximation is off by up
/// to a factor of 2 in the far tail, where the verdicts are made.
const MAX_EXACT: usize = 2500;

/// Two-sided p-value of U = `u` from the normal approximation, with the variance corrected for
/// ties (`tie_term`: the sum of t³ − t over tied groups) and a continuity correction.
fn normal_p(n1: usize, n2: usize, u: f64, tie_term: f64) -> f64 {
    let variance = u_variance(n1, n2, tie_term);
    if variance <= 0.0 {
        return 1.0;
    }
    let (n1, n2) = (n1 as f64, n2 as f64);
    let z = ((u - n1 * n2 / 2.0).abs() - 0.5).max(0.0) / variance.sqrt();
    (2.0 * normal_upper_tail(z)).min(1.0)
}

/// The variance of U over every split of the pooled sample into sizes `n1` and `n2`, with the
/// tie correction (`tie_term`: the sum of t³ − t over tied groups).
fn u_variance(n1: usize, n2: usize, tie_term: f64) -> f64 {
    let (n1, n2) = (n1 as f64, n2 as f64);
    let n = n1 + n2;
    n1 * n2 / 12.0 * ((n + 1.0) - tie_term / (n * (n - 1.0)))
}

/// Exact two-sided p-value of U = `u` for untied samples of sizes `n1`, `n2`: the share of the
/// C(n1+n2, n1) orders whose U lies at least as far from the mean.
fn exact_p(n1: usize, n2: usize, u: usize) -> f64 {
    // counts[j][s], for the current i: orders of i values of the first sample and j of the
    // second with U = s (U counts pairs where the first sample's value is larger). The largest
    // value comes either from the first sample, adding j to U, or from the second, adding
    // nothing: f(i, j, s) = f(i − 1, j, s − j) + f(i, j − 1, s).
    let max_u = n1 * n2;
    let mut previous = vec![vec![0.0f64; max_u + 1]; n2 + 1];
    for row in &mut previous {
        row[0] = 1.0;
    }
    for _ in 1..=n1 {
        let mut current = vec![vec![0.0f64; max_u + 1]; n2 + 1];
        current[0][0] = 1.0;
        for j in 1..=n2 {
            for s in 0..=max_u {
                let top_from_first = if s >= j { previous[j][s - j] } else { 0.0 };
                current[j][s] = top_from_first + current[j - 1][s];
            }
        }
        previous = current;
    }
    let counts = &previous[n2];
    let total: f64 = counts.iter().sum();
    let mean = max_u as f64 / 2.0;
    let distance = (u as f64 - mean).abs();
    let extreme: f64 =
        counts.iter().enumerate().filter(|(s, _)| (*s as f64 - mean).abs() >= distance - 1e-9).map(|(_, c)| c).sum();
    (extreme / total).min(1.0)
}

/// P(Z > z) for a standard normal Z (Abramowitz–Stegun 7.1.26 through erfc; error < 1.5e-7).
fn normal_upper_tail(z: f64) -> f64 {
    let x = z / std::f64::consts::SQRT_2;
    let t = 1.0 / (1.0 + 0.327_591_1 * x);
    let poly =
        t * (0.254_829_592 + t * (-0.284_496_736 + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    0.5 * poly * (-x * x).exp()
}

/// Median and median absolute deviation, scaled by 1.4826 to estimate a normal's σ.
pub fn median_and_spread(values: &[f64]) -> (f64, f64) {
    let centre = median(values.to_vec());
    let deviations = values.iter().map(|v| (v - centre).abs()).collect();
    (centre, 1.4826 * median(deviations))
}

/// A confidence interval of a median, and the probability that it holds it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MedianInterval {
    pub low: f64,
    pub high: f64,
    /// Probability that the interval holds the median.
    pub coverage: f64,
}

/// The distribution-free interval of the median of `values` (None for none): the order
/// statistics x(k) ≤ median ≤ x(n+1−k) of `n` independent values hold the true median with
/// probability 1 − 2·P(B ≤ k − 1), B ~ Binomial(n, ½), whatever the distribution. `k` is the
/// largest rank that reaches `confidence`; with too few values for that, the whole range and the
/// coverage it has (5 values: 93.75 %).
pub fn median_interval(values: &[f64], confidence: f64) -> Option<MedianInterval> {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    if n == 0 {
        return None;
    }
    // Start at the range (k = 1) and move inward while the next pair of ranks still reaches
    // `confidence`; P(B = j) = C(n, j) / 2^n, each term the one before times (n − j + 1) / j.
    let mut k = 1;
    let mut term = 0.5f64.powi(n as i32); // P(B = k − 1)
    let mut below = term; // P(B ≤ k − 1)
    while 2 * k < n {
        let next = term * (n - k + 1) as f64 / k as f64;
        if confidence > 1.0 - 2.0 * (below + next) {
            break;
        }
        (term, below, k) = (next, below + next, k + 1);
    }
    Some(MedianInterval { low: sorted[k - 1], high: sorted[n - k], coverage: 1.0 - 2.0 * below })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_intervals_take_the_published_ranks() {
        // Ranks from the binomial table for 95 %: n = 9 → 2nd and 8th (coverage 1 − 2·10/512),
        // n = 15 → 4th and 12th (1 − 2·576/32768), n = 5 → the range (1 − 2/32), n = 1 → 0.
        let values = |n: usize| (1..=n).rev().map(|i| i as f64).collect::<Vec<_>>();
        let nine = median_interval(&values(9), 0.95).unwrap();
        assert_eq!((nine.low, nine.high), (2.0, 8.0));
        assert!((nine.coverage - (1.0 - 20.0 / 512.0)).abs() < 1e-12);
        let fifteen = median_interval(&values(15), 0.95).unwrap();
        assert_eq!((fifteen.low, fifteen.high), (4.0, 12.0));
        assert!((fifteen.coverage - (1.0 - 1152.0 / 32768.0)).abs() < 1e-12);
        let five = median_interval(&values(5), 0.95).unwrap();
        assert_eq!((five.low, five.high, five.coverage), (1.0, 5.0, 1.0 - 2.0 / 32.0));
        // A confidence the next ranks reach exactly is reached: n = 5 at 62.5 % takes the 2nd and
        // 4th (coverage 1 − 2·6/32).
        let exact = median_interval(&values(5), 0.625).unwrap();
        assert_eq!((exact.low, exact.high, exact.coverage), (2.0, 4.0, 0.625));
        let one = median_interval(&[3.0], 0.95).unwrap();
        assert_eq!((one.low, one.high, one.coverage), (3.0, 3.0, 0.0));
        assert_eq!(median_interval(&[], 0.95), None);
    }

    #[test]
    fn exact_p_values_match_the_published_table() {
        // n1 = n2 = 4: P(U <= 0) = 1/70, two-sided 2/70; P(U <= 1) = 2/70.
        let (low, high) = ([1.0, 2.0, 3.0, 4.0], [5.0, 6.0, 7.0, 8.0]);
        assert!((mann_whitney_p(&low, &high) - 2.0 / 70.0).abs() < 1e-12);
        let (low, high) = ([1.0, 2.0, 3.0, 5.0], [4.0, 6.0, 7.0, 8.0]);
        assert!((mann_whitney_p(&low, &high) - 4.0 / 70.0).abs() < 1e-12);
        // Interleaved samples: no evidence of a shift.
        assert_eq!(mann_whitney_p(&[1.0, 4.0, 5.0, 8.0], &[2.0, 3.0, 6.0, 7.0]), 1.0);
    }

    #[test]
    fn exact_counts_match_an_independent_count_and_the_approximation_where_it_holds() {
        // 21 against 21 untied values, shifted by 7.25: U = 91. The exact p-value, 2·P(U <= 91),
        // counted independently as Gaussian binomial coefficients [42 choose 21]_q.
        let a: Vec<f64> = (0..21).map(f64::from).collect();
        let b: Vec<f64> = (0..21).map(|i| f64::from(i) + 7.25).collect();
        assert!((mann_whitney_p(&a, &b) / 0.000_811_699_411_651_992_4 - 1.0).abs() < 1e-9);
        // In the far tail the approximation is off by nearly half; near p = 0.2 by under 10 %.
        let tail = normal_p(21, 21, 91.0, 0.0);
        assert!((tail / exact_p(21, 21, 91) - 1.0).abs() < 0.5, "{tail}");
        let moderate = normal_p(21, 21, 171.0, 0.0);
        assert!((moderate / exact_p(21, 21, 171) - 1.0).abs() < 0.1, "{moderate}");
        // Ties take the approximation: identical samples show nothing.
        assert!(mann_whitney_p(&[1.0; 9], &[1.0; 9]) >= 0.99);
    }

    #[test]
    fn the_normal_tail_matches_the_published_table() {
        // P(Z > z) for z = 0, 1, 1.96, 3 (to the approximation's 1.5e-7).
        for (z, tail) in [(0.0, 0.5), (1.0, 0.158_655_25), (1.96, 0.024_997_9), (3.0, 0.001_349_9)] {
            assert!((normal_upper_tail(z) - tail).abs() < 2e-7, "P(Z > {z}) = {}", normal_upper_tail(z));
        }
    }

    #[test]
    fn spread_ignores_one_outlying_run() {
        let (median, spread) = median_and_spread(&[10.0, 10.2, 9.8, 10.1, 9.9, 30.0]);
        assert!((median - 10.1).abs() < 1e-12);
        assert!(spread < 0.5, "{spread}");
    }

    // Property tests: each statistic against a brute-force reading of its definition.

    /// Every split of `pooled` into a first sample of `n1` values and the rest.
    fn splits(pooled: &[f64], n1: usize) -> Vec<(Vec<f64>, Vec<f64>)> {
        let n = pooled.len();
        (0u32..1 << n)
            .filter(|mask| mask.count_ones() as usize == n1)
            .map(|mask| {
                let (mut a, mut b) = (Vec::new(), Vec::new());
                for (i, &x) in pooled.iter().enumerate() {
                    if mask & (1 << i) != 0 { a.push(x) } else { b.push(x) }
                }
                (a, b)
            })
            .collect()
    }

    /// The drawn values as one pooled sample, and the size of a first sample of `first` of them
    /// that leaves the second at least one.
    fn pooled_with_first<V: Into<f64>>(values: impl IntoIterator<Item = V>, first: usize) -> (Vec<f64>, usize) {
        let pooled: Vec<f64> = values.into_iter().map(Into::into).collect();
        let n1 = first.min(pooled.len() - 1);
        (pooled, n1)
    }

    /// U by its definition: the pairs where `a`'s value is larger, ties counting one half.
    fn u_by_pairs(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .flat_map(|x| {
                b.iter().map(move |y| {
                    if x > y {
                        1.0
                    } else if x == y {
                        0.5
                    } else {
                        0.0
                    }
                })
            })
            .sum()
    }

    /// The sum of t³ − t over the groups of equal values, counted directly.
    fn tie_term_by_groups(values: &[f64]) -> f64 {
        let mut distinct: Vec<f64> = values.to_vec();
        distinct.sort_by(f64::total_cmp);
        distinct.dedup();
        distinct
            .iter()
            .map(|v| {
                let t = values.iter().filter(|x| *x == v).count() as f64;
                t * t * t - t
            })
            .sum()
    }

    use proptest::prelude::*;

    proptest! {
        #[test]
        fn untied_p_values_are_the_share_of_splits_at_least_as_extreme(
            values in proptest::collection::btree_set(0u16..1000, 2..=11),
            first in 1usize..=6,
        ) {
            let (pooled, n1) = pooled_with_first(values, first);
            let (a, b) = (&pooled[..n1], &pooled[n1..]);
            let u = u_by_pairs(a, b);
            let mean = (n1 * (pooled.len() - n1)) as f64 / 2.0;
            let all = splits(&pooled, n1);
            let extreme = all.iter().filter(|(x, y)| (u_by_pairs(x, y) - mean).abs() >= (u - mean).abs()).count();
            let p = mann_whitney_p(a, b);
            prop_assert!((p - extreme as f64 / all.len() as f64).abs() < 1e-12, "{p} against {extreme}/{}", all.len());
            prop_assert_eq!(p, mann_whitney_p(b, a));
        }

        #[test]
        fn with_ties_u_the_tie_term_and_the_variance_are_their_definitions(
            values in proptest::collection::vec(0u8..4, 2..=12),
            first in 1usize..=6,
        ) {
            let (pooled, n1) = pooled_with_first(values, first);
            let (a, b) = (&pooled[..n1], &pooled[n1..]);
            let (u, tie_term) = rank_statistic(a, b);
            prop_assert_eq!(u, u_by_pairs(a, b));
            prop_assert_eq!(tie_term, tie_term_by_groups(&pooled));
            // The variance of U over every split of the pooled values, by enumeration.
            let all: Vec<f64> = splits(&pooled, n1).iter().map(|(x, y)| u_by_pairs(x, y)).collect();
            let mean = all.iter().sum::<f64>() / all.len() as f64;
            let variance = all.iter().map(|u| (u - mean) * (u - mean)).sum::<f64>() / all.len() as f64;
            prop_assert!((u_variance(n1, pooled.len() - n1, tie_term) - variance).abs() < 1e-9 * (1.0 + variance));
            let p = mann_whitney_p(a, b);
            prop_assert_eq!(p, mann_whitney_p(b, a));
            if tie_term > 0.0 {
                // Ties take the normal approximation with the continuity correction, on the
                // variance the enumeration gave.
                let shift = ((u - mean).abs() - 0.5).max(0.0);
                let expected = if variance > 0.0 { (2.0 * normal_upper_tail(shift / variance.sqrt())).min(1.0) } else { 1.0 };
                prop_assert!((p - expected).abs() < 1e-9, "{p} against {expected}");
            }
        }

        #[test]
        fn the_median_is_the_upper_middle_value_and_the_spread_its_scaled_deviation(
            values in proptest::collection::vec(-1000i32..1000, 1..40),
        ) {
            let values: Vec<f64> = values.into_iter().map(f64::from).collect();
            let m = median(values.clone());
            // The upper median: exactly n/2 values (rounded down) strictly precede it in order.
            let mut sorted = values.clone();
            sorted.sort_by(f64::total_cmp);
            prop_assert_eq!(m, sorted[values.len() / 2]);
            let (centre, spread) = median_and_spread(&values);
            prop_assert_eq!(centre, m);
            let deviations: Vec<f64> = values.iter().map(|v| (v - m).abs()).collect();
            prop_assert_eq!(spread, 1.4826 * median(deviations));
        }

        #[test]
        fn the_median_interval_takes_the_innermost_ranks_that_reach_the_confidence(
            values in proptest::collection::vec(0u16..1000, 1..40),
            confidence in 0.5f64..0.999,
        ) {
            let values: Vec<f64> = values.into_iter().map(f64::from).collect();
            let mut sorted = values.clone();
            sorted.sort_by(f64::total_cmp);
            let n = sorted.len();
            // P(B ≤ j) for B ~ Binomial(n, ½), from binomial coefficients summed directly.
            let choose = |n: usize, k: usize| (0..k).fold(1.0f64, |c, i| c * (n - i) as f64 / (i + 1) as f64);
            let at_most = |j: usize| (0..=j).map(|i| choose(n, i)).sum::<f64>() / 2f64.powi(n as i32);
            let coverage = |k: usize| 1.0 - 2.0 * at_most(k - 1);
            let k = (1..=n.div_ceil(2)).filter(|&k| k == 1 || (2 * (k - 1) < n && coverage(k) >= confidence)).max().unwrap();
            let interval = median_interval(&values, confidence).unwrap();
            prop_assert_eq!((interval.low, interval.high), (sorted[k - 1], sorted[n - k]));
            prop_assert!((interval.coverage - coverage(k)).abs() < 1e-12);
        }
    }
}
