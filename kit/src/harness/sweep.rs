//! Parameter sweeps: each case declares the ranges its parameters may take (`params::Sweep`), and a
//! seeded draw picks parameter sets inside them, so a case is checked across its declared space
//! rather than only at its defaults (`fragkit check --sweep N --seed S`, and the property test in
//! `cases/tests/sweep.rs`). Every drawn set prints as the `--set` line that reproduces it.

use std::collections::BTreeMap;

use super::case::Case;
use super::params::SweepRange;
use crate::scene::hash::{SeededRng, pcg_hash};

/// Log-uniform integer in `min..=max`.
fn log_uniform(rng: &mut SeededRng, min: u64, max: u64) -> u64 {
    if max <= min {
        return min;
    }
    let (lo, hi) = (((min.max(1)) as f64).ln(), ((max + 1) as f64).ln());
    let value = (lo + f64::from(rng.unit()) * (hi - lo)).exp().floor() as u64;
    value.clamp(min, max)
}

/// Stable across runs and platforms: FNV-1a of the case name.
fn name_hash(name: &str) -> u32 {
    name.bytes().fold(0x811c_9dc5u32, |h, b| (h ^ u32::from(b)).wrapping_mul(0x0100_0193))
}

/// Parameter set `index` of `case`'s sweep under `seed`, as `--set` overrides.
pub fn draw(case: &Case, seed: u64, index: u32) -> BTreeMap<String, String> {
    let key = pcg_hash(name_hash(case.name) ^ pcg_hash(seed as u32 ^ pcg_hash((seed >> 32) as u32 ^ index)));
    let mut rng = SeededRng::new(key);
    case.sweep
        .iter()
        .map(|sweep| {
            let text = match sweep.range {
                SweepRange::Count(min, max) => log_uniform(&mut rng, min, max).to_string(),
                SweepRange::Size { min, max } => {
                    let w = log_uniform(&mut rng, u64::from(min.0), u64::from(max.0));
                    let h = log_uniform(&mut rng, u64::from(min.1), u64::from(max.1));
                    format!("{w}x{h}")
                }
            };
            (sweep.param.to_owned(), text)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::{Outcome, ParamKind, ParamSpec, Sweep};

    const CASE: Case = Case {
        name: "kit.example",
        summary: "",
        requires: wgpu::Features::empty(),
        params: &[
            ParamSpec { name: "lights", kind: ParamKind::CountIn(1, 4096), default: "8", help: "" },
            ParamSpec { name: "size", kind: ParamKind::Sizes, default: "8x8", help: "" },
        ],
        sweep: &[
            Sweep { param: "lights", range: SweepRange::Count(1, 4096) },
            Sweep { param: "size", range: SweepRange::Size { min: (1, 1), max: (300, 200) } },
        ],
        budget_s: 1,
        timed_verdict: false,
        shaders: &[],
        run: |_| Ok(Outcome::Pass),
    };

    #[test]
    fn draws_are_seeded_inside_the_ranges_and_spread_over_decades() {
        let draws: Vec<_> = (0..200).map(|i| draw(&CASE, 1, i)).collect();
        assert_eq!(draws, (0..200).map(|i| draw(&CASE, 1, i)).collect::<Vec<_>>(), "same seed, same sets");
        assert_ne!(draws[0], draw(&CASE, 2, 0), "another seed, another set");
        let lights: Vec<u64> = draws.iter().map(|d| d["lights"].parse().unwrap()).collect();
        assert!(lights.iter().all(|l| (1..=4096).contains(l)));
        assert!(lights.iter().any(|&l| l < 10) && lights.iter().any(|&l| l > 1000), "{lights:?}");
        for d in &draws {
            let params = crate::harness::params::Params::resolve(CASE.name, CASE.params, d).unwrap();
            let (w, h) = params.sizes("size").unwrap()[0];
            assert!((1..=300).contains(&w) && (1..=200).contains(&h));
        }
    }

    #[test]
    fn the_name_hash_is_fnv_1a_and_draws_stay_what_earlier_runs_printed() {
        // FNV-1a's published 32-bit values.
        assert_eq!((name_hash(""), name_hash("a"), name_hash("foobar")), (0x811c_9dc5, 0xe40c_292c, 0xbf9c_f968));
        // A reproduce line printed by an earlier run must draw the same set again: these are
        // the draws of this kit's key (name, both halves of the seed, the index).
        let at = |seed: u64, index: u32| {
            let d = draw(&CASE, seed, index);
            format!("{} {}", d["lights"], d["size"])
        };
        let pinned = [at(1, 0), at(1, 1), at(1 << 32, 0), at(7, 3), at(1 << 32, 1)];
        assert_eq!(pinned, ["3259 41x108", "4 60x3", "13 12x1", "240 17x7", "566 29x60"]);
        let other = Case { name: "kit.other", ..CASE };
        assert_ne!(draw(&other, 1, 0), draw(&CASE, 1, 0));
    }

    #[test]
    fn counts_are_drawn_log_uniformly_over_the_whole_range() {
        let mut rng = SeededRng::new(5);
        let draws: Vec<u64> = (0..3000).map(|_| log_uniform(&mut rng, 1, 999)).collect();
        // Three decades, a third of the draws each (±5σ of a binomial of 3000 at 1/3: 129).
        for (lo, hi) in [(1, 9), (10, 99), (100, 999)] {
            let count = draws.iter().filter(|&&d| (lo..=hi).contains(&d)).count() as f64;
            assert!((count - 1000.0).abs() < 129.0, "{lo}..={hi}: {count}");
        }
        assert!(draws.contains(&1) && draws.contains(&999), "both ends are drawn");
        // From 10: two decades, half each.
        let upper: Vec<u64> = (0..2000).map(|_| log_uniform(&mut rng, 10, 999)).collect();
        let low = upper.iter().filter(|&&d| d < 100).count() as f64;
        assert!((low - 1000.0).abs() < 5.0 * 500f64.sqrt(), "{low} of 2000 below 100");
        assert_eq!(log_uniform(&mut rng, 7, 7), 7);
        assert_eq!(log_uniform(&mut rng, 9, 3), 9);
        let mut zero = SeededRng::new(6);
        assert!((0..200).map(|_| log_uniform(&mut zero, 0, 3)).all(|d| d <= 3));
    }
}
