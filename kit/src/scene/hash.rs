//! The PCG hash of `shaders/common/hash.wgsl`, bit for bit, and a seeded generator built on it.

/// PCG hash (Jarzynski & Olano 2020), as in `shaders/common/hash.wgsl`.
pub fn pcg_hash(input: u32) -> u32 {
    let state = input.wrapping_mul(747796405).wrapping_add(2891336453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277803737);
    (word >> 22) ^ word
}

/// A uniform number in [0, 1) with 24 bits, as `hash_unit` in WGSL.
pub fn hash_unit(input: u32) -> f32 {
    (pcg_hash(input) >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// A seeded stream of numbers: the n-th draw is `pcg_hash(seed_hash + n)`.
#[derive(Clone, Debug)]
pub struct SeededRng {
    state: u32,
}

impl SeededRng {
    pub fn new(seed: u32) -> Self {
        Self { state: pcg_hash(seed) }
    }

    pub fn next_u32(&mut self) -> u32 {
        self.state = self.state.wrapping_add(1);
        pcg_hash(self.state)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Uniform integer in [lo, hi).
    pub fn range(&mut self, lo: u32, hi: u32) -> u32 {
        lo + ((u64::from(self.next_u32()) * u64::from(hi - lo)) >> 32) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pcg_matches_published_values() {
        // Computed independently from the formula (Python, arbitrary-precision integers masked to 32 bits).
        assert_eq!(pcg_hash(0), 129708002);
        assert_eq!(pcg_hash(1), 2831084092);
    }

    /// `hash_unit` is the hash's top 24 bits over 2^24 (the Python values above).
    #[test]
    fn a_unit_number_is_the_hashs_top_24_bits() {
        assert_eq!(hash_unit(0), (129_708_002u32 >> 8) as f32 / 16_777_216.0);
        assert_eq!(hash_unit(u32::MAX), (3_861_530_882u32 >> 8) as f32 / 16_777_216.0);
        assert!((0..1000).map(hash_unit).all(|u| (0.0..1.0).contains(&u)));
    }

    /// The n-th draw of seed 7 is pcg_hash(pcg_hash(7) + n) (Python's values); `unit` is its top
    /// 24 bits over 2^24.
    #[test]
    fn a_seeded_stream_draws_the_hash_of_its_seed_plus_n() {
        let mut rng = SeededRng::new(7);
        assert_eq!(rng.next_u32(), 2809854175);
        assert_eq!(rng.unit(), (3686869381u32 >> 8) as f32 / 16_777_216.0);
        assert_eq!(rng.next_u32(), 925619080);
    }

    /// `range(lo, hi)` draws every integer of [lo, hi) and nothing else, each about equally often:
    /// within 5σ of the binomial count (12 000 draws).
    #[test]
    fn range_draws_each_value_of_its_bounds_equally_often() {
        let mut rng = SeededRng::new(7);
        for (lo, hi) in [(3u32, 9u32), (0, 2), (1000, 1007)] {
            let span = f64::from(hi - lo);
            let draws = 12_000;
            let mut counts = vec![0u32; (hi - lo) as usize];
            for _ in 0..draws {
                let value = rng.range(lo, hi);
                assert!((lo..hi).contains(&value), "{value} outside {lo}..{hi}");
                counts[(value - lo) as usize] += 1;
            }
            let mean = f64::from(draws) / span;
            let sigma = (mean * (1.0 - 1.0 / span)).sqrt();
            for (offset, &count) in counts.iter().enumerate() {
                assert!(
                    (f64::from(count) - mean).abs() <= 5.0 * sigma,
                    "{lo}..{hi}: {} drawn {count} times",
                    lo + offset as u32
                );
            }
        }
        assert_eq!(rng.range(5, 6), 5);
    }
}
