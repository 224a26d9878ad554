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

    /// Off the screen's corner, on a screen taller than wide: the focus is the fraction of each
    /// side, the level floor(log2(1 + distance / radius)) from the pixel centre.
    #[test]
    fn foveated_levels_follow_the_distance_from_a_focus_anywhere() {
        // 16×8, focus (0.25, 0.5) → (4, 4), radius 2.
        let lod = foveated((16, 8), (0.25, 0.5), 2.0, 8);
        let level = |x: u32, y: u32| lod.levels[(y * 16 + x) as usize];
        for (x, y) in [(0u32, 0u32), (4, 4), (12, 4), (4, 0), (0, 7), (15, 7), (9, 1)] {
            let distance = (f64::from(x) + 0.5 - 4.0).hypot(f64::from(y) + 0.5 - 4.0);
            let expected = (1.0 + distance / 2.0).log2().floor() as u8;
            assert_eq!(level(x, y), expected, "({x}, {y}) at {distance}");
        }
        assert_eq!([level(4, 4), level(4, 0), level(12, 4)], [0, 1, 2]);
        // The ambiguity: on 1×16 with the focus at the top, radius 1: pixel y's centre lies at
        // y + 0.5, so 1 + 0.5 = 1.5 … never a power of two; radius 0.5: y = 0 gives 2, y = 1 gives 4.
        let column = foveated((1, 16), (0.5, 0.0), 0.5, 8);
        assert_eq!(&column.ambiguous[..4], &[true, true, false, true]);
        assert!(!foveated((1, 16), (0.5, 0.0), 1.0, 8).ambiguous.iter().any(|&a| a));
    }

    /// Each block the nesting reaches splits with probability one half, at every level: over
    /// aligned 64×64 screens, the share of reached blocks that split lies within 4 standard
    /// deviations of 1/2 (a block is reached when every pixel is at its level or finer, split
    /// when every pixel is finer).
    #[test]
    fn nested_blocks_split_with_probability_one_half() {
        let top = 3;
        for level in 1..=top {
            let (mut reached, mut split) = (0u32, 0u32);
            for seed in 0..20 {
                let lod = nested_random((64, 64), top, seed);
                let side = 1u32 << level;
                for by in 0..64 / side {
                    for bx in 0..64 / side {
                        let pixels: Vec<u32> = (0..side * side)
                            .map(|i| u32::from(lod[((by * side + i / side) * 64 + bx * side + i % side) as usize]))
                            .collect();
                        reached += u32::from(pixels.iter().all(|&l| l <= level));
                        split += u32::from(pixels.iter().all(|&l| l < level));
                    }
                }
            }
            let share = f64::from(split) / f64::from(reached);
            let sigma = 0.5 / f64::from(reached).sqrt();
            assert!((share - 0.5).abs() <= 4.0 * sigma, "level {level}: {split} of {reached} split");
        }
        assert_eq!(nested_random((64, 64), top, 1), nested_random((64, 64), top, 1));
    }

    fn facing(position: [f32; 3], normal: [f32; 3]) -> Surface {
        Surface {
            position: [position[0], position[1], position[2], 1.0],
            normal: [normal[0], normal[1], normal[2], 8.0],
            albedo: [0.5; 4],
        }
    }

    /// The edge tests: coverage; normals whose cosine is under the threshold; a position jump over
    /// `depth_ratio` of the distance to the eye. Within 2^-20 (relative) of either threshold the
    /// answer is open unless the other test decides an edge.
    #[test]
    fn an_edge_is_decided_by_coverage_normals_or_depth_and_open_near_a_threshold() {
        let eye = DVec3::ZERO;
        let a = facing([0.0, 0.0, -1.0], [0.0, 0.0, 1.0]);
        let empty = Surface { position: [0.0; 4], normal: [0.0; 4], albedo: [0.0; 4] };
        assert_eq!(across_edge(&a, &empty, eye, 0.9, 0.5), Some(true));
        assert_eq!(across_edge(&empty, &empty, eye, 0.9, 0.5), Some(false));
        // Normals: the cosine is the tilted normal's z. f32 steps at 0.9 are 2^-24; the open band
        // is 2^-20 (1 + 0.9) ≈ 30 of them.
        let threshold = f64::from(0.9f32);
        let tilted = |steps: i32| {
            let z = 0.9f32 + steps as f32 * 2f32.powi(-24);
            facing([0.0, 0.0, -1.0], [(1.0 - z * z).sqrt(), 0.0, z])
        };
        assert_eq!(across_edge(&a, &tilted(-1000), eye, threshold, 0.5), Some(true));
        assert_eq!(across_edge(&a, &tilted(1000), eye, threshold, 0.5), Some(false));
        assert_eq!(across_edge(&a, &tilted(0), eye, threshold, 0.5), None);
        assert_eq!(across_edge(&a, &tilted(25), eye, threshold, 0.5), None);
        assert_eq!(across_edge(&a, &tilted(-25), eye, threshold, 0.5), None);
        assert_eq!(across_edge(&a, &tilted(40), eye, threshold, 0.5), Some(false));
        assert_eq!(across_edge(&a, &tilted(-40), eye, threshold, 0.5), Some(true));
        // Depth: a at 1 m, the allowed jump 0.5 m; f32 steps at 1.5 are 2^-23, the open band
        // 2^-20 (0.5 + 0.5) = 8 of them.
        let behind = |steps: i32| facing([0.0, 0.0, -1.5 - steps as f32 * 2f32.powi(-23)], [0.0, 0.0, 1.0]);
        assert_eq!(across_edge(&a, &behind(-1000), eye, 0.5, 0.5), Some(false));
        assert_eq!(across_edge(&a, &behind(1000), eye, 0.5, 0.5), Some(true));
        assert_eq!(across_edge(&a, &behind(0), eye, 0.5, 0.5), None);
        assert_eq!(across_edge(&a, &behind(5), eye, 0.5, 0.5), None);
        assert_eq!(across_edge(&a, &behind(-5), eye, 0.5, 0.5), None);
        assert_eq!(across_edge(&a, &behind(12), eye, 0.5, 0.5), Some(true));
        assert_eq!(across_edge(&a, &behind(-12), eye, 0.5, 0.5), Some(false));
        // The allowed jump scales with the distance to the eye: from 1 m away the same 0.5 m
        // jump is within 0.5 · 2.
        let eye_back = DVec3::new(0.0, 0.0, 1.0);
        assert_eq!(across_edge(&a, &behind(1000), eye_back, 0.5, 0.5), Some(false));
        // The open band is relative to jump + allowed: from 2 m the allowed jump is 1 m, and f32
        // steps at 2 are 2^-22, so the band 2^-20 (1 + 1) is 8 of them.
        let far_behind = |steps: i32| facing([0.0, 0.0, -2.0 - steps as f32 * 2f32.powi(-22)], [0.0, 0.0, 1.0]);
        assert_eq!(across_edge(&a, &far_behind(5), eye_back, 0.5, 0.5), None);
        assert_eq!(across_edge(&a, &far_behind(12), eye_back, 0.5, 0.5), Some(true));
        // A decided edge on one test settles an open call on the other; a decided non-edge does not.
        let both = |normal_steps: i32, depth_steps: i32| {
            let mut b = tilted(normal_steps);
            b.position = behind(depth_steps).position;
            across_edge(&a, &b, eye, threshold, 0.5)
        };
        assert_eq!(both(-1000, 0), Some(true));
        assert_eq!(both(0, 1000), Some(true));
        assert_eq!(both(1000, 0), None);
        assert_eq!(both(0, -1000), None);
        assert_eq!(both(1000, -1000), Some(false));
    }

    /// On 8×12 (taller than wide), empty below row 10: rows 9 and 10 are edges. Rows 0–7 lie in an
    /// edge-free 8×8 block (level 3); rows 8–11 share 2×2 blocks with an edge (level 0).
    #[test]
    fn content_levels_follow_blocks_in_both_directions() {
        let full = facing([0.0, 0.0, -1.0], [0.0, 0.0, 1.0]);
        let empty = Surface { position: [0.0; 4], normal: [0.0; 4], albedo: [0.0; 4] };
        let surfaces: Vec<Surface> = (0..12).flat_map(|y| [if y < 10 { full } else { empty }; 8]).collect();
        let lod = content((8, 12), &surfaces, glam::Vec3::ZERO, (0.9, 0.05), 3);
        let rows: Vec<u8> = (0..12).map(|y| lod.levels[y * 8]).collect();
        assert_eq!(rows, [3, 3, 3, 3, 3, 3, 3, 3, 0, 0, 0, 0]);
        assert!((0..12).all(|y| lod.levels[y * 8..y * 8 + 8].iter().all(|&l| l == rows[y])));
        assert!(!lod.ambiguous.iter().any(|&a| a));
        // Empty right of column 6 on rows 0–3 too: columns 5 and 6 are edges there.
        let surfaces: Vec<Surface> = (0..12)
            .flat_map(|y| (0..8).map(move |x| if y >= 10 || (y < 4 && x >= 6) { empty } else { full }))
            .collect();
        let lod = content((8, 12), &surfaces, glam::Vec3::ZERO, (0.9, 0.05), 3);
        let level = |x: usize, y: usize| lod.levels[y * 8 + x];
        assert_eq!((0..8).map(|x| level(x, 0)).collect::<Vec<_>>(), [2, 2, 2, 2, 0, 0, 0, 0]);
        // Row 4: its level-2 block (rows 4–7, columns 4–7) holds column 6's edge at row 4 (its
        // neighbour above is empty).
        assert_eq!((0..8).map(|x| level(x, 4)).collect::<Vec<_>>(), [2, 2, 2, 2, 1, 1, 0, 0]);
    }

    /// An undecidable pixel (a normal exactly at the threshold) and its neighbours are open: the
    /// level is what it would be were they edges, and marked ambiguous where it would differ.
    #[test]
    fn content_levels_over_an_undecidable_pixel_are_ambiguous() {
        let flat = facing([0.0, 0.0, -1.0], [0.0, 0.0, 1.0]);
        let z = 0.9f32;
        let tilted = facing([0.0, 0.0, -1.0], [(1.0 - z * z).sqrt(), 0.0, z]);
        let mut surfaces = [flat; 8];
        surfaces[5] = tilted;
        let lod = content((8, 1), &surfaces, glam::Vec3::ZERO, (z, 0.05), 2);
        assert_eq!(lod.levels, [2, 2, 2, 2, 0, 0, 0, 0]);
        assert_eq!(lod.ambiguous, [false, false, false, false, true, true, true, true]);
    }
}
