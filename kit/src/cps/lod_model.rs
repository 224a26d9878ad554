//! CPU models of the LOD policies' definitions (see [`LodPolicy`]), fed with the scene's inputs
//! (screen, focus, radius; for the content policy the read-back G-buffer and the eye): the
//! independent expectation of `shaders/cps/lod.wgsl` (its foveated and content levels) and
//! `edge_mask.wgsl`.
//!
//! A pixel whose level hangs on a comparison closer than the GPU's f32 arithmetic can decide is
//! *ambiguous*: the models say so rather than guess, and the cases skip and count those pixels.

use glam::DVec3;

use super::config::LodPolicy;
use crate::deferred::phong::Surface;
use crate::scene::hash::SeededRng;

/// The GPU compares a pixel's f32 squared distance with the f32-rounded squared boundaries
/// (shaders/common/foveation.wgsl), each within a few 2^-24 of itself: a level boundary closer
/// than about 2^-22 in log2 may fall either way. The stencil marks widen a block's squared
/// distances by 2^-20 more (shaders/cps/stencil_mark.wgsl), under 2^-20 in log2: within 2^-17,
/// a block may be marked for the level across the boundary too.
const LOG2_AMBIGUITY: f64 = 1.0 / (1u64 << 17) as f64;

/// A comparison of two f32 results whose difference is within 2^-20 of their magnitude may fall
/// either way (a dot product or a distance of f32 inputs errs by a few 2^-24).
const COMPARISON_AMBIGUITY: f64 = 1.0 / (1u64 << 20) as f64;

/// The level of every pixel and whether it is ambiguous, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelledLod {
    pub levels: Vec<u8>,
    pub ambiguous: Vec<bool>,
}

/// A seeded LOD made of whole blocks, as the content policy's is: every pixel of level l has its
/// aligned 2^l block all at level l. From `top` down, each such block splits into its four
/// children with probability one half.
pub fn nested_random(screen: (u32, u32), top: u32, seed: u32) -> Vec<u8> {
    let (w, h) = screen;
    let mut rng = SeededRng::new(seed);
    let mut lod = vec![top as u8; (w * h) as usize];
    for level in (1..=top).rev() {
        for by in 0..h.div_ceil(1 << level) {
            for bx in 0..w.div_ceil(1 << level) {
                let rows = (by << level)..((by + 1) << level).min(h);
                let pixels: Vec<usize> = rows
                    .flat_map(|y| ((bx << level)..((bx + 1) << level).min(w)).map(move |x| (y * w + x) as usize))
                    .collect();
                if pixels.iter().all(|&i| u32::from(lod[i]) == level) && rng.range(0, 2) == 1 {
                    for i in pixels {
                        lod[i] = level as u8 - 1;
                    }
                }
            }
        }
    }
    lod
}

/// Foveated: level = floor(log2(1 + distance / inner_radius)) at the pixel centre, capped at `top`;
/// the focus is a fraction of the screen.
pub fn foveated(screen: (u32, u32), focus: (f32, f32), inner_radius: f32, top: u32) -> ModelledLod {
    let focus = (f64::from(focus.0 * screen.0 as f32), f64::from(focus.1 * screen.1 as f32));
    let radius = f64::from(inner_radius).max(1e-3);
    let (mut levels, mut ambiguous) = (Vec::new(), Vec::new());
    for y in 0..screen.1 {
        for x in 0..screen.0 {
            let distance = (f64::from(x) + 0.5 - focus.0).hypot(f64::from(y) + 0.5 - focus.1);
            let octaves = (1.0 + distance / radius).log2();
            let boundary = octaves.round();
            levels.push(octaves.floor().min(f64::from(top)) as u8);
            ambiguous
                .push(boundary >= 1.0 && boundary <= f64::from(top) && (octaves - boundary).abs() <= LOG2_AMBIGUITY);
        }
    }
    ModelledLod { levels, ambiguous }
}

/// Whether two samples lie across a geometric edge: `Some(answer)`, or `None` when a threshold
/// comparison is too close to call.
fn across_edge(a: &Surface, b: &Surface, eye: DVec3, normal_cos: f64, depth_ratio: f64) -> Option<bool> {
    if a.position[3] != b.position[3] {
        return Some(true);
    }
    if a.position[3] == 0.0 {
        return Some(false);
    }
    let vec = |v: &[f32; 4]| DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
    let (pa, pb) = (vec(&a.position), vec(&b.position));
    let cosine = vec(&a.normal).dot(vec(&b.normal));
    let jump = pa.distance(pb);
    let allowed = depth_ratio * pa.distance(eye);
    let normal_close = (cosine - normal_cos).abs() <= COMPARISON_AMBIGUITY * (1.0 + cosine.abs());
    let depth_close = (jump - allowed).abs() <= COMPARISON_AMBIGUITY * (jump + allowed);
    let normal_edge = cosine < normal_cos;
    let depth_edge = jump > allowed;
    // A decided edge on either test settles it; otherwise any close call leaves it open.
    if (normal_edge && !normal_close) || (depth_edge && !depth_close) {
        Some(true)
    } else if normal_close || depth_close {
        None
    } else {
        Some(false)
    }
}

/// Content: a pixel is an edge where it differs from any of its four neighbours (clamped at the
/// screen's border); its level is the coarsest l ≤ `top` whose aligned 2^l block, and every finer
/// block around it, holds no edge pixel (level 0 if its 2×2 block holds one).
pub fn content(screen: (u32, u32), surfaces: &[Surface], eye: glam::Vec3, policy: (f32, f32), top: u32) -> ModelledLod {
    let (w, h) = screen;
    let (normal_cos, depth_ratio) = (f64::from(policy.0), f64::from(policy.1));
    let eye = eye.as_dvec3();
    let at = |x: u32, y: u32| &surfaces[(y * w + x) as usize];
    // Edge per pixel: Some(true/false), None where undecidable.
    let edges: Vec<Option<bool>> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let here = at(x, y);
            let neighbours = [
                at((x + 1).min(w - 1), y),
                at(x, (y + 1).min(h - 1)),
                at(x.saturating_sub(1), y),
                at(x, y.saturating_sub(1)),
            ];
            let answers = neighbours.map(|there| across_edge(here, there, eye, normal_cos, depth_ratio));
            if answers.contains(&Some(true)) {
                Some(true)
            } else if answers.iter().all(|a| *a == Some(false)) {
                Some(false)
            } else {
                None
            }
        })
        .collect();
    // Per level l ≥ 1 and block: (holds a certain edge, holds an undecidable pixel).
    let block_state = |level: u32| -> Vec<(bool, bool)> {
        let (bw, bh) = (w.div_ceil(1 << level), h.div_ceil(1 << level));
        let mut state = vec![(false, false); (bw * bh) as usize];
        for y in 0..h {
            for x in 0..w {
                let cell = &mut state[((y >> level) * bw + (x >> level)) as usize];
                match edges[(y * w + x) as usize] {
                    Some(true) => cell.0 = true,
                    None => cell.1 = true,
                    Some(false) => {}
                }
            }
        }
        state
    };
    let states: Vec<Vec<(bool, bool)>> = (1..=top).map(block_state).collect();
    let (mut levels, mut ambiguous) = (Vec::new(), Vec::new());
    for y in 0..h {
        for x in 0..w {
            // The level if every undecidable pixel were an edge (low) or were not (high).
            let (mut low, mut high) = (0u32, 0u32);
            let mut low_open = true;
            for level in 1..=top {
                let bw = w.div_ceil(1 << level);
                let (edge, open) = states[level as usize - 1][((y >> level) * bw + (x >> level)) as usize];
                if edge {
                    break;
                }
                if low_open && !open {
                    low = level;
                } else {
                    low_open = false;
                }
                high = level;
            }
            levels.push(low as u8);
            ambiguous.push(low != high);
        }
    }
    ModelledLod { levels, ambiguous }
}

/// The model of `policy` where it has one (explicit policies are their own input).
pub fn model(policy: &LodPolicy, screen: (u32, u32), surfaces: &[Surface], eye: glam::Vec3, top: u32) -> ModelledLod {
    match policy {
        LodPolicy::Foveated { focus, inner_radius } => foveated(screen, *focus, *inner_radius, top),
        LodPolicy::Content { normal_cos, depth_ratio } => {
            content(screen, surfaces, eye, (*normal_cos, *depth_ratio), top)
        }
        LodPolicy::Explicit(levels) => ModelledLod {
            levels: levels.iter().map(|&l| l.min(top as u8)).collect(),
            ambiguous: vec![false; levels.len()],
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn foveated_levels_double_with_distance() {
        // 1 × 64 row, focus at x = 0, radius 4: level = floor(log2(1 + (x + 0.5) / 4)).
        let lod = foveated((64, 1), (0.0, 0.5), 4.0, 8);
        assert_eq!(lod.levels[0], 0);
        assert_eq!(lod.levels[3], 0); // 1 + 3.5/4 < 2
        assert_eq!(lod.levels[4], 1); // 1 + 4.5/4 ≥ 2
        assert_eq!(lod.levels[12], 2); // 1 + 12.5/4 ≥ 4
        assert!(lod.ambiguous.iter().all(|a| !a));
    }

    #[test]
    fn foveated_boundaries_exactly_on_a_power_of_two_are_ambiguous() {
        // Pixel centre x + 0.5 = 4 → 1 + 4/4 = 2 exactly.
        let lod = foveated((8, 1), (0.0, 0.5), 3.5, 8);
        assert!(lod.ambiguous[3]);
    }

    #[test]
    fn foveated_levels_stop_at_the_top_where_no_boundary_is_left_to_be_ambiguous() {
        // Focus at x = 0, radius 1: pixel x's level is floor(log2(1.5 + x)), capped at 2.
        let lod = foveated((64, 1), (0.0, 0.5), 1.0, 2);
        assert_eq!(&lod.levels[..4], &[0, 1, 1, 2]);
        assert!(lod.levels[4..].iter().all(|&l| l == 2), "capped at the top");
        // On a power of two the level is a boundary the GPU may round either way, except past
        // the top (level 2 either way).
        let at = foveated((16, 1), (0.0, 0.5), 0.5, 2);
        // Pixel 0: 1 + 0.5/0.5 = 2, the boundary between levels 0 and 1.
        assert!(at.ambiguous[0]);
        // Pixel 1: 1 + 1.5/0.5 = 4, between levels 1 and 2.
        assert!(at.ambiguous[1]);
        // Pixel 3: 1 + 3.5/0.5 = 8, past the top: not ambiguous.
        assert!(!at.ambiguous[3] && at.levels[3] == 2);
    }

    #[test]
    fn nested_random_levels_are_whole_aligned_blocks() {
        for (screen, top, seed) in [((37, 23), 3, 1), ((64, 64), 4, 2), ((5, 40), 5, 3)] {
            let lod = nested_random(screen, top, seed);
            assert!(lod.iter().any(|&l| u32::from(l) < top), "some block split");
            for y in 0..screen.1 {
                for x in 0..screen.0 {
                    let level = u32::from(lod[(y * screen.0 + x) as usize]);
                    assert!(level <= top);
                    let (bx, by) = (x >> level << level, y >> level << level);
                    for yy in by..(by + (1 << level)).min(screen.1) {
                        for xx in bx..(bx + (1 << level)).min(screen.0) {
                            assert_eq!(u32::from(lod[(yy * screen.0 + xx) as usize]), level, "({x},{y}) in {screen:?}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn content_level_is_the_coarsest_edge_free_block() {
        // 8×1 screen: a coverage change between x = 3 and x = 4 makes pixels 3 and 4 edges.
        let empty = Surface { position: [0.0; 4], normal: [0.0; 4], albedo: [0.0; 4] };
        let full = Surface { position: [0.0, 0.0, -1.0, 1.0], normal: [0.0, 0.0, 1.0, 1.0], albedo: [0.0; 4] };
        let surfaces = [full, full, full, full, empty, empty, empty, empty];
        let lod = content((8, 1), &surfaces, glam::Vec3::ZERO, (0.9, 0.05), 2);
        // Level-1 blocks {2,3} and {4,5} hold an edge; {0,1} and {6,7} do not, but their level-2
        // blocks {0..3} and {4..7} do.
        assert_eq!(lod.levels, vec![1, 1, 0, 0, 0, 0, 1, 1]);
    }
}
