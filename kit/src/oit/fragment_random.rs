//! The per-fragment uniform number of stochastic transparency by its definition
//! (`fragment_random` in `shaders/common/opacity.wgsl`): this frame's noise texel, the fragment's
//! depth bits and its primitive's stream, hashed together, then mapped to the 2^24 cell centres
//! of (0, 1]. Depth is in the key so that one primitive seen at two depths (a self-overlapping
//! mesh, one key drawn twice) draws independent numbers at each.

use crate::scene::hash::pcg_hash;

pub fn fragment_random(noise: u32, depth: f32, id: u32, stream: u32) -> f32 {
    let primitive = pcg_hash(id.wrapping_mul(2654435769).wrapping_add(stream));
    let h = pcg_hash(noise ^ pcg_hash(depth.to_bits() ^ primitive));
    ((h >> 8) as f32 + 0.5) * (1.0 / 16_777_216.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shader's expression (`fragment_random` of opacity.wgsl, `pcg_hash` of hash.wgsl)
    /// evaluated outside Rust (Python's integers, masked to 32 bits) at four keys: the hashes it
    /// gives, mapped as the shader maps them.
    #[test]
    fn the_number_is_the_shaders_at_keys_computed_elsewhere() {
        let cases: [((u32, f32, u32, u32), u32); 4] = [
            ((0, 0.0, 0, 0), 2_145_236_065),
            ((12_345, 0.5, 7, 1), 586_145_096),
            ((0xdead_beef, 0.999, 123_456, 3), 507_896_282),
            ((1, 0.25, u32::MAX, 2), 2_835_253_432),
        ];
        for ((noise, depth, id, stream), hash) in cases {
            let expected = ((hash >> 8) as f32 + 0.5) * (1.0 / 16_777_216.0);
            assert_eq!(fragment_random(noise, depth, id, stream), expected, "{noise} {depth} {id} {stream}");
        }
    }

    const N: u32 = 4096;

    /// Pearson's correlation of paired draws.
    fn correlation(pairs: &[(f32, f32)]) -> f64 {
        let n = pairs.len() as f64;
        let mean = |f: fn(&(f32, f32)) -> f32| pairs.iter().map(|p| f64::from(f(p))).sum::<f64>() / n;
        let (ma, mb) = (mean(|p| p.0), mean(|p| p.1));
        let (mut ab, mut aa, mut bb) = (0.0, 0.0, 0.0);
        for &(a, b) in pairs {
            let (da, db) = (f64::from(a) - ma, f64::from(b) - mb);
            (ab, aa, bb) = (ab + da * db, aa + da * da, bb + db * db);
        }
        ab / (aa * bb).sqrt()
    }

    /// Draws that should be independent: under independence the correlation of N pairs has a
    /// standard deviation of 1/√N and each quadrant of the unit square holds N/4 ± √(N·3/16); five
    /// deviations of either is a failure (p < 10⁻⁶ each).
    fn assert_independent(what: &str, pairs: &[(f32, f32)]) {
        let n = pairs.len() as f64;
        let r = correlation(pairs);
        assert!(r.abs() < 5.0 / n.sqrt(), "{what}: correlation {r}");
        for (low_a, low_b) in [(true, true), (true, false), (false, true), (false, false)] {
            let count = pairs.iter().filter(|(a, b)| (*a <= 0.5) == low_a && (*b <= 0.5) == low_b).count() as f64;
            assert!(
                (count - n / 4.0).abs() < 5.0 * (n * 3.0 / 16.0).sqrt(),
                "{what}: quadrant {low_a} {low_b} holds {count}"
            );
        }
    }

    #[test]
    fn streams_depths_and_frames_draw_independent_uniform_numbers() {
        let noise = |i: u32| pcg_hash(i ^ 0x5eed);
        let streams: Vec<(f32, f32)> =
            (0..N).map(|i| (fragment_random(noise(i), 0.5, 7, 0), fragment_random(noise(i), 0.5, 7, 1))).collect();
        assert_independent("streams 0 and 1 of one primitive", &streams);
        let depths: Vec<(f32, f32)> =
            (0..N).map(|i| (fragment_random(noise(i), 0.25, 7, 0), fragment_random(noise(i), 0.75, 7, 0))).collect();
        assert_independent("one primitive at two depths", &depths);
        let ids: Vec<(f32, f32)> =
            (0..N).map(|i| (fragment_random(noise(i), 0.5, 7, 0), fragment_random(noise(i), 0.5, 8, 0))).collect();
        assert_independent("two primitives", &ids);
        let frames: Vec<(f32, f32)> =
            (0..N).map(|i| (fragment_random(noise(i), 0.5, 7, 0), fragment_random(noise(i + N), 0.5, 7, 0))).collect();
        assert_independent("two frames' noise", &frames);
        // Each number lies in (0, 1] on the 2^-24 grid's cell centres, with mean 1/2 ± 5σ.
        let draws: Vec<f32> = streams.iter().map(|p| p.0).collect();
        assert!(draws.iter().all(|&u| u > 0.0 && u < 1.0 && (u * 16_777_216.0 - 0.5).fract() == 0.0));
        let mean = draws.iter().map(|&u| f64::from(u)).sum::<f64>() / f64::from(N);
        assert!((mean - 0.5).abs() < 5.0 * (1.0 / 12.0 / f64::from(N)).sqrt(), "mean {mean}");
    }
}
