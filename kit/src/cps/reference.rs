//! CPU expectations for CPS: how many coarse texels each level must shade for a LOD buffer, and
//! the three composites computed from read-back lit levels by the same equations as
//! `shaders/cps/composite.wgsl`, each pixel with the bound a correct GPU keeps to: one f16 ulp for
//! the store to the `Rgba16Float` image (CPU and GPU may round a value a hair apart to
//! neighbouring f16s) and f32 evaluation-order slack, scaled by the magnitudes entering the pixel,
//! so bright scenes get proportionally wider bounds and dim pixels beside bright ones no looser
//! ones than they need.

use super::config::CompositeMode;

/// For level `level`, whether each texel (row-major over ceil(screen / 2^level)) holds some pixel
/// whose LOD, clamped to `top`, is `level`: exactly the texels its stencil must mark.
pub fn needed_texels(screen: (u32, u32), lod: &[u8], top: u32, level: u32) -> Vec<bool> {
    let at_level: Vec<bool> = lod.iter().map(|&l| u32::from(l).min(top) == level).collect();
    blocks_holding(screen, &at_level, level)
}

/// Texels of level `level`: ceil(screen / 2^level).
fn level_extent(screen: (u32, u32), level: u32) -> (u32, u32) {
    (screen.0.div_ceil(1 << level), screen.1.div_ceil(1 << level))
}

/// For level `level`, whether each texel's 2^level block holds a pixel marked in `pixels`.
pub fn blocks_holding(screen: (u32, u32), pixels: &[bool], level: u32) -> Vec<bool> {
    let (w, h) = level_extent(screen, level);
    let mut held = vec![false; (w * h) as usize];
    for y in 0..screen.1 {
        for x in 0..screen.0 {
            if pixels[(y * screen.0 + x) as usize] {
                held[((y >> level) * w + (x >> level)) as usize] = true;
            }
        }
    }
    held
}

/// Texels each level 0..=top must shade.
pub fn expected_shaded_texels(screen: (u32, u32), lod: &[u8], top: u32) -> Vec<u64> {
    (0..=top).map(|level| needed_texels(screen, lod, top, level).iter().filter(|&&n| n).count() as u64).collect()
}

/// One level: its data extent and RGBA texels (alpha 1 = holds shading).
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    pub extent: (u32, u32),
    pub texels: Vec<[f32; 4]>,
}

impl Level {
    fn at(&self, x: i64, y: i64) -> [f32; 4] {
        let x = x.clamp(0, i64::from(self.extent.0) - 1);
        let y = y.clamp(0, i64::from(self.extent.1) - 1);
        self.texels[(y * i64::from(self.extent.0) + x) as usize]
    }
}

/// WGSL's `mix`: a · (1 − t) + b · t.
fn mix(a: [f32; 4], b: [f32; 4], t: f32) -> [f32; 4] {
    std::array::from_fn(|i| a[i] * (1.0 - t) + b[i] * t)
}

/// One f16 ulp relative to the value (10 fraction bits): what one store to an f16 target may move
/// a value, since Vulkan lets the conversion round to nearest or toward zero (lavapipe truncates)
/// while the CPU model rounds to nearest; and the subnormal spacing below the normal range.
const F16_ULP: f32 = 1.0 / 1024.0;
const F16_SUBNORMAL: f32 = 1.0 / 16_777_216.0;
/// The GPU may evaluate a few f32 operations in another order or fused (`mix` as a + t·(b − a)):
/// 16 f32 ulps of the largest value entering them.
const F32_SLACK: f32 = 16.0 / 8_388_608.0;

/// A composited pixel and how far a correct GPU may lie from it per channel: the differences the
/// f16 stores and f32 evaluation order allow, scaled by the magnitudes entering the pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Composited {
    pub colour: [f32; 4],
    pub bound: [f32; 3],
}

impl Composited {
    /// Channels of `gpu` outside the bound.
    pub fn within(&self, gpu: [f32; 4]) -> bool {
        (0..3).all(|c| (gpu[c] - self.colour[c]).abs() <= self.bound[c])
    }
}

/// The bound for `value` made from `inputs` and stored to f16 once: the f32 slack of the largest
/// input and the final rounding.
fn stored_bound(value: [f32; 4], inputs: &[[f32; 4]]) -> [f32; 4] {
    std::array::from_fn(|c| {
        let reach = inputs.iter().map(|t| t[c].abs()).fold(0.0f32, f32::max);
        F32_SLACK * reach + F16_ULP * value[c].abs() + F16_SUBNORMAL
    })
}

/// The pixel whose G-buffer sample texel `texel` of `level` is lit at: the centre pixel of its
/// 2^level block, clamped to the screen (`shaders/cps/lighting.wgsl`).
pub fn sample_pixel(screen: (u32, u32), level: u32, texel: [i64; 2]) -> [i64; 2] {
    let last = [i64::from(screen.0) - 1, i64::from(screen.1) - 1];
    [0, 1].map(|i| ((texel[i] << level) + ((1 << level) >> 1)).min(last[i]))
}

/// The sample pixel (row-major index) of every texel each level 0..=top must shade for `lod`,
/// level by level, each level's texels row by row: the G-buffer samples a CPS frame lights.
pub fn shaded_samples(screen: (u32, u32), lod: &[u8], top: u32) -> Vec<u32> {
    let mut samples = Vec::new();
    for level in 0..=top {
        let (width, _) = level_extent(screen, level);
        for (i, _) in needed_texels(screen, lod, top, level).into_iter().enumerate().filter(|&(_, needed)| needed) {
            let texel = [i64::from(i as u32 % width), i64::from(i as u32 / width)];
            let [x, y] = sample_pixel(screen, level, texel);
            samples.push((y * i64::from(screen.0) + x) as u32);
        }
    }
    samples
}

/// Levels 0..=top whose every texel holds `shading` at its sample pixel: lit levels as the
/// lighting pass would leave them for shading that is a known function of screen position.
pub fn sampled_levels(screen: (u32, u32), top: u32, shading: impl Fn([i64; 2]) -> [f32; 4]) -> Vec<Level> {
    (0..=top)
        .map(|level| {
            let extent = level_extent(screen, level);
            let texels = (0..i64::from(extent.1))
                .flat_map(|y| (0..i64::from(extent.0)).map(move |x| [x, y]))
                .map(|texel| shading(sample_pixel(screen, level, texel)))
                .collect();
            Level { extent, texels }
        })
        .collect()
}

/// A corner for the seam-free triangle: the pixel whose fragment's sample it is and the step from
/// A to that sample.
#[derive(Clone, Copy, Debug)]
struct Corner {
    pixel: [i64; 2],
    edge: [i64; 2],
}

/// The seam-free composite's triangle at a pixel P: the pixels whose fragments' samples are its
/// corners (P's own A, B across x, D across y) and P − A = β (B − A) + δ (D − A) as
/// β = `nb` / `det`, δ = `nd` / `det`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Triangle {
    pub corners: [[i64; 2]; 3],
    pub det: i64,
    pub nb: i64,
    pub nd: i64,
}

impl Triangle {
    /// (β, δ) as the GPU computes them (f32).
    pub fn weights(&self) -> (f32, f32) {
        (self.nb as f32 / self.det as f32, self.nd as f32 / self.det as f32)
    }

    /// Whether a corner is flat (P's own colour, beyond the outermost samples): there the
    /// composite is constant along that axis rather than linear.
    pub fn has_flat_corner(&self) -> bool {
        self.corners[1] == self.corners[0] || self.corners[2] == self.corners[0]
    }
}

/// The inputs of a composite: the screen, its LOD buffer and the lit levels 0..=top.
pub struct CompositeInputs<'a> {
    pub screen: (u32, u32),
    pub lod: &'a [u8],
    pub lit: &'a [Level],
}

impl CompositeInputs<'_> {
    fn top(&self) -> u32 {
        self.lit.len() as u32 - 1
    }

    fn clamp(&self, p: [i64; 2]) -> [i64; 2] {
        [p[0].clamp(0, i64::from(self.screen.0) - 1), p[1].clamp(0, i64::from(self.screen.1) - 1)]
    }

    fn level_of(&self, p: [i64; 2]) -> u32 {
        let [x, y] = self.clamp(p);
        u32::from(self.lod[(y * i64::from(self.screen.0) + x) as usize]).min(self.top())
    }

    fn coarse_colour(&self, p: [i64; 2]) -> [f32; 4] {
        let [x, y] = self.clamp(p);
        let level = self.level_of(p);
        self.lit[level as usize].at(x >> level, y >> level)
    }

    fn beyond_fragment(&self, p: [i64; 2], axis: usize, direction: i64) -> [i64; 2] {
        let level = self.level_of(p);
        let size = 1i64 << level;
        let origin = (p[axis] >> level) << level;
        let mut neighbour = p;
        neighbour[axis] = if direction < 0 { origin - 1 } else { origin + size };
        neighbour
    }

    /// The 4-neighbour colour and the four coarse colours it mixed.
    fn four_neighbour(&self, p: [i64; 2]) -> ([f32; 4], [[f32; 4]; 4]) {
        let level = self.level_of(p);
        let size = (1i64 << level) as f32;
        let origin = [((p[0] >> level) << level) as f32, ((p[1] >> level) << level) as f32];
        let q = [0, 1].map(|i| (p[i] as f32 + 0.5 - (origin[i] + 0.5 * size)) / size);
        let dx = if q[0] < 0.0 { -1 } else { 1 };
        let dy = if q[1] < 0.0 { -1 } else { 1 };
        let px = self.beyond_fragment(p, 0, dx);
        let py = self.beyond_fragment(p, 1, dy);
        let p2 =
            if q[0].abs() >= q[1].abs() { self.beyond_fragment(px, 1, dy) } else { self.beyond_fragment(py, 0, dx) };
        let inputs = [p, px, py, p2].map(|at| self.coarse_colour(at));
        let top = mix(inputs[0], inputs[1], q[0].abs());
        let bottom = mix(inputs[2], inputs[3], q[0].abs());
        (mix(top, bottom, q[1].abs()), inputs)
    }

    /// Where the fragment holding `p` was lit: its block's centre pixel, clamped to the screen
    /// (`shaders/cps/lighting.wgsl`).
    fn sample_of(&self, p: [i64; 2]) -> [i64; 2] {
        let level = self.level_of(p);
        let [x, y] = self.clamp(p);
        sample_pixel(self.screen, level, [x >> level, y >> level])
    }

    fn on_screen(&self, p: [i64; 2]) -> bool {
        (0..i64::from(self.screen.0)).contains(&p[0]) && (0..i64::from(self.screen.1)).contains(&p[1])
    }

    /// The sample of the fragment just across `p`'s along `axis` on the side of `direction`: the
    /// pixel whose fragment it is and the step from `a` to it; unusable (zero step) past the
    /// screen's edge.
    fn corner_across(&self, p: [i64; 2], a: [i64; 2], axis: usize, direction: i64) -> Corner {
        let across = self.beyond_fragment(p, axis, direction);
        if !self.on_screen(across) {
            return Corner { pixel: p, edge: [0, 0] };
        }
        let b = self.sample_of(across);
        Corner { pixel: across, edge: [b[0] - a[0], b[1] - a[1]] }
    }

    /// The two corners along `axis`, the side `p` lies towards first (either where level with
    /// `a`); the first flat (`p`'s own colour, level with `p`) where `p` lies beyond the outermost
    /// sample or no sample lies apart from `a`.
    fn corners_along(&self, p: [i64; 2], a: [i64; 2], axis: usize, toward: i64) -> [Corner; 2] {
        let mut corners = [self.corner_across(p, a, axis, toward), self.corner_across(p, a, axis, -toward)];
        if corners[0].edge == [0, 0] && p[axis] == a[axis] {
            corners.swap(0, 1);
        }
        if corners[0].edge == [0, 0] {
            let mut edge = [0, 0];
            edge[axis] = toward * (p[axis] - a[axis]).abs().max(1);
            corners[0] = Corner { pixel: p, edge };
        }
        corners
    }

    /// The seam-free composite's triangle at `p`, as `fs_composite_seam_free` picks it: the
    /// first of the four (either side along each axis, the sides `p` lies towards first) that
    /// holds P with three samples, else with a flat corner, else the first that is not
    /// degenerate, else none.
    pub fn seam_free_triangle(&self, p: [i64; 2]) -> Option<Triangle> {
        let a = self.sample_of(p);
        let d = [p[0] - a[0], p[1] - a[1]];
        let toward = [0, 1].map(|i| if p[i] < a[i] { -1 } else { 1 });
        let along_x = self.corners_along(p, a, 0, toward[0]);
        let along_y = self.corners_along(p, a, 1, toward[1]);
        let candidates = (0..4).filter_map(|i| {
            let (b, e) = (along_x[i & 1], along_y[i >> 1]);
            let (u, v) = (b.edge, e.edge);
            let det = u[0] * v[1] - u[1] * v[0];
            let nb = d[0] * v[1] - d[1] * v[0];
            let nd = u[0] * d[1] - u[1] * d[0];
            let sign = det.signum();
            let holds = nb * sign >= 0 && nd * sign >= 0 && (nb + nd) * sign <= det * sign;
            let triangle = Triangle { corners: [p, b.pixel, e.pixel], det, nb, nd };
            let rank = match (holds, triangle.has_flat_corner()) {
                (true, false) => 3,
                (true, true) => 2,
                (false, _) => 1,
            };
            (det != 0).then_some((rank, triangle))
        });
        // The first of the highest rank.
        candidates.rev().max_by_key(|&(rank, _)| rank).map(|(_, triangle)| triangle)
    }

    /// Ours, as `fs_composite_seam_free`: C(A) + β (C(B) − C(A)) + δ (C(D) − C(A)).
    fn seam_free(&self, p: [i64; 2]) -> Composited {
        let own = self.coarse_colour(p);
        let Some(triangle) = self.seam_free_triangle(p) else {
            let bound = stored_bound(own, &[own]);
            return Composited { colour: own, bound: [bound[0], bound[1], bound[2]] };
        };
        let (beta, delta) = triangle.weights();
        let [_, across_x, across_y] = triangle.corners.map(|at| self.coarse_colour(at));
        let colour: [f32; 4] =
            std::array::from_fn(|c| own[c] + beta * (across_x[c] - own[c]) + delta * (across_y[c] - own[c]));
        // f32 slack grows with the weights where the triangle extrapolates.
        let amplification = 1.0 + 2.0 * (beta.abs() + delta.abs());
        let inputs = [own, across_x, across_y].map(|t| t.map(|v| v * amplification));
        let bound = stored_bound(colour, &inputs);
        Composited { colour, bound: [bound[0], bound[1], bound[2]] }
    }

    /// The composite in `mode`, RGBA per pixel (alpha 1), before the f16 store.
    pub fn composite(&self, mode: CompositeMode) -> Vec<[f32; 4]> {
        self.composite_with_bounds(mode).into_iter().map(|pixel| pixel.colour).collect()
    }

    /// The composite in `mode` with each pixel's bound (its f16 store included).
    pub fn composite_with_bounds(&self, mode: CompositeMode) -> Vec<Composited> {
        let (w, h) = self.screen;
        let direct = |colour: [f32; 4], inputs: &[[f32; 4]]| {
            let bound = stored_bound(colour, inputs);
            Composited { colour, bound: [bound[0], bound[1], bound[2]] }
        };
        (0..h)
            .flat_map(|y| (0..w).map(move |x| [i64::from(x), i64::from(y)]))
            .map(|p| {
                let pixel = match mode {
                    CompositeMode::Nearest => {
                        let colour = self.coarse_colour(p);
                        direct(colour, &[colour])
                    }
                    CompositeMode::FourNeighbour => {
                        let (colour, inputs) = self.four_neighbour(p);
                        direct(colour, &inputs)
                    }
                    CompositeMode::SeamFree => self.seam_free(p),
                };
                Composited { colour: [pixel.colour[0], pixel.colour[1], pixel.colour[2], 1.0], ..pixel }
            })
            .collect()
    }
}

/// The seam metric: across every pair of neighbouring pixels with different LODs, how far the
/// step between them in `image` departs from the step in `reference` (mean over pairs and RGB).
/// A composite that is continuous where the reference is scores near 0 however coarse it is.
pub fn seam_error(screen: (u32, u32), lod: &[u8], image: &[[f32; 4]], reference: &[[f32; 4]]) -> f64 {
    let (w, h) = (screen.0 as usize, screen.1 as usize);
    let mut total = 0.0;
    let mut pairs = 0u64;
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let neighbours = [(x + 1 < w).then_some(i + 1), (y + 1 < h).then_some(i + w)];
            for j in neighbours.into_iter().flatten().filter(|&j| lod[j] != lod[i]) {
                let step = |img: &[[f32; 4]], c: usize| f64::from(img[i][c] - img[j][c]);
                total += (0..3).map(|c| (step(image, c) - step(reference, c)).abs()).sum::<f64>() / 3.0;
                pairs += 1;
            }
        }
    }
    if pairs == 0 { 0.0 } else { total / pairs as f64 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shaded_texels_count_blocks_holding_their_level() {
        // 3×2 screen: LODs [0 1 1 / 0 1 2]; level 1 blocks are (0,0) covering x 0..2 and (1,0) x 2..3.
        let lod = [0, 1, 1, 0, 1, 2];
        assert_eq!(expected_shaded_texels((3, 2), &lod, 2), vec![2, 2, 1]);
        // Clamped: LOD 2 counts at top level 1.
        assert_eq!(expected_shaded_texels((3, 2), &lod, 1), vec![2, 2]);
        // Their samples: level 0 pixels (0,0), (0,1); level 1 texels (0,0), (1,0) at pixels (1,1)
        // and (2,1) (the centre clamped to the screen); level 2 texel (0,0) at (2,1).
        assert_eq!(shaded_samples((3, 2), &lod, 2), vec![0, 3, 4, 5, 5]);
        // Full detail on three rows: every pixel once, row by row (a texel's row is its index over
        // the level's width).
        assert_eq!(shaded_samples((2, 3), &[0; 6], 0), vec![0, 1, 2, 3, 4, 5]);
    }

    #[test]
    fn a_composited_pixel_is_within_only_when_every_colour_channel_is() {
        let expected = Composited { colour: [0.5, 1.0, 2.0, 1.0], bound: [0.01, 0.02, 0.04] };
        assert!(expected.within([0.51, 0.98, 2.04, 0.0]), "at the bound, alpha free");
        for channel in 0..3 {
            for sign in [1.0, -1.0] {
                let mut gpu = expected.colour;
                gpu[channel] += sign * expected.bound[channel] * 1.01;
                assert!(!expected.within(gpu), "channel {channel} off by {sign} · 1.01 bound");
            }
        }
    }

    #[test]
    fn needed_texels_are_those_whose_block_holds_a_pixel_of_their_level_by_the_definition() {
        use crate::scene::hash::SeededRng;
        let mut rng = SeededRng::new(37);
        for _ in 0..60 {
            let screen = (rng.range(1, 40), rng.range(1, 40));
            let top = rng.range(0, 6);
            // LODs past the top too: they count at the top.
            let lod: Vec<u8> = (0..screen.0 * screen.1).map(|_| rng.range(0, 8) as u8).collect();
            let mut counts = Vec::new();
            for level in 0..=top {
                // Texel by texel: any pixel of its 2^level block, inside the screen, whose LOD
                // (clamped to the top) is this level.
                let side = 1u32 << level;
                let (w, h) = (screen.0.div_ceil(side), screen.1.div_ceil(side));
                let definition: Vec<bool> = (0..w * h)
                    .map(|t| {
                        let (tx, ty) = (t % w, t / w);
                        (ty * side..((ty + 1) * side).min(screen.1)).any(|y| {
                            (tx * side..((tx + 1) * side).min(screen.0))
                                .any(|x| u32::from(lod[(y * screen.0 + x) as usize]).min(top) == level)
                        })
                    })
                    .collect();
                assert_eq!(needed_texels(screen, &lod, top, level), definition, "{screen:?} top {top} level {level}");
                counts.push(definition.iter().filter(|&&n| n).count() as u64);
            }
            assert_eq!(expected_shaded_texels(screen, &lod, top), counts);
            // One G-buffer sample is lit for each needed texel.
            assert_eq!(shaded_samples(screen, &lod, top).len() as u64, counts.iter().sum::<u64>());
        }
    }

    /// Shading linear in screen position, in [1, 2) over the tests' screens.
    fn linear(p: [i64; 2]) -> [f32; 4] {
        let (x, y) = (p[0] as f32, p[1] as f32);
        [1.0 + 0.004 * x, 1.0 + 0.006 * y, 1.0 + 0.003 * x + 0.002 * y, 1.0]
    }

    #[test]
    fn seam_free_reproduces_linear_shading_between_the_outermost_samples() {
        let mut checked = 0;
        for (seed, screen, top) in
            [(1, (37, 23), 3), (2, (64, 48), 4), (3, (13, 50), 2), (4, (100, 7), 5), (5, (1, 9), 2)]
        {
            let lod = crate::cps::lod_model::nested_random(screen, top, seed);
            let lit = sampled_levels(screen, top, linear);
            let inputs = CompositeInputs { screen, lod: &lod, lit: &lit };
            for (i, pixel) in inputs.composite(CompositeMode::SeamFree).iter().enumerate() {
                let p = [i as i64 % i64::from(screen.0), i as i64 / i64::from(screen.0)];
                let triangle = inputs.seam_free_triangle(p).expect("nested levels always give a triangle");
                // Flat corners only beyond the outermost samples, towards the screen's edges, or
                // where the fragment spans the screen along an axis.
                let beyond = (0..2).any(|axis| {
                    let a = inputs.sample_of(p);
                    let off = |direction| !inputs.on_screen(inputs.beyond_fragment(p, axis, direction));
                    let toward = if p[axis] < a[axis] { -1 } else { 1 };
                    (p[axis] != a[axis] && off(toward)) || (off(1) && off(-1))
                });
                assert!(!triangle.has_flat_corner() || beyond, "{screen:?} seed {seed} pixel {p:?}: {triangle:?}");
                if triangle.has_flat_corner() {
                    continue;
                }
                let want = linear(p);
                for c in 0..3 {
                    assert!(
                        (pixel[c] - want[c]).abs() <= 1e-5,
                        "{screen:?} seed {seed} pixel {p:?}: {pixel:?} vs {want:?}"
                    );
                }
                checked += 1;
            }
        }
        assert!(checked > 2500, "only {checked} of 5282 pixels lie between samples");
    }

    #[test]
    fn four_neighbour_does_not_reproduce_linear_shading_across_levels() {
        let screen = (64, 48);
        let lod = crate::cps::lod_model::nested_random(screen, 4, 2);
        let lit = sampled_levels(screen, 4, linear);
        let inputs = CompositeInputs { screen, lod: &lod, lit: &lit };
        let worst = inputs
            .composite(CompositeMode::FourNeighbour)
            .iter()
            .enumerate()
            .map(|(i, pixel)| (pixel[0] - linear([i as i64 % 64, i as i64 / 64])[0]).abs())
            .fold(0.0f32, f32::max);
        assert!(worst > 0.01, "worst departure {worst}");
    }

    #[test]
    fn nearest_reads_each_pixels_own_coarse_texel() {
        let lit = [
            Level { extent: (2, 1), texels: vec![[1.0, 0.0, 0.0, 1.0], [2.0, 0.0, 0.0, 1.0]] },
            Level { extent: (1, 1), texels: vec![[5.0, 0.0, 0.0, 1.0]] },
        ];
        let inputs = CompositeInputs { screen: (2, 1), lod: &[0, 1], lit: &lit };
        let image = inputs.composite(CompositeMode::Nearest);
        assert_eq!(image.iter().map(|t| t[0]).collect::<Vec<_>>(), vec![1.0, 5.0]);
    }

    /// A level's texel at a position off its extent is the nearest edge texel's (clamp to edge).
    #[test]
    fn a_level_clamps_reads_to_its_edge() {
        let texel = |i: u32| [i as f32, 0.0, 0.0, 1.0];
        let level = Level { extent: (3, 2), texels: (0..6).map(texel).collect() };
        assert_eq!(level.at(1, 1), texel(4));
        assert_eq!(level.at(5, 0), texel(2));
        assert_eq!(level.at(-3, 1), texel(3));
        assert_eq!(level.at(2, 7), texel(5));
        assert_eq!(level.at(-1, -1), texel(0));
    }

    /// A texel is lit at the centre pixel of its 2^level block (the block's origin plus half its
    /// side, rounded down), clamped to the screen.
    #[test]
    fn a_texel_is_lit_at_its_blocks_centre_pixel() {
        assert_eq!(sample_pixel((16, 16), 0, [3, 5]), [3, 5]);
        assert_eq!(sample_pixel((16, 16), 1, [3, 5]), [7, 11]);
        assert_eq!(sample_pixel((16, 16), 2, [1, 2]), [6, 10]);
        assert_eq!(sample_pixel((16, 16), 3, [1, 0]), [12, 4]);
        // Clamped to the last column and row.
        assert_eq!(sample_pixel((7, 3), 2, [1, 0]), [6, 2]);
        assert_eq!(sample_pixel((5, 9), 3, [0, 1]), [4, 8]);
    }

    /// One composited pixel's bound: 16 f32 ulps (2^-19) of the largest input, one f16 ulp
    /// (2^-10) of the value and the f16 subnormal step (2^-24).
    #[test]
    fn a_nearest_pixels_bound_is_the_f32_slack_and_one_f16_ulp() {
        let lit = [Level { extent: (1, 1), texels: vec![[2.0, -0.5, 0.0, 1.0]] }];
        let inputs = CompositeInputs { screen: (1, 1), lod: &[0], lit: &lit };
        let pixel = inputs.composite_with_bounds(CompositeMode::Nearest)[0];
        assert_eq!(pixel.colour, [2.0, -0.5, 0.0, 1.0]);
        let bound = |v: f32| 2f32.powi(-19) * v + 2f32.powi(-10) * v + 2f32.powi(-24);
        assert_eq!(pixel.bound, [bound(2.0), bound(0.5), bound(0.0)]);
    }

    /// LODs past the last lit level read that level.
    #[test]
    fn lods_past_the_top_read_the_top_level() {
        let lit = [
            Level { extent: (2, 2), texels: vec![[1.0, 0.0, 0.0, 1.0]; 4] },
            Level { extent: (1, 1), texels: vec![[7.0, 0.0, 0.0, 1.0]] },
        ];
        let inputs = CompositeInputs { screen: (2, 2), lod: &[5, 1, 0, 9], lit: &lit };
        let image = inputs.composite(CompositeMode::Nearest);
        assert_eq!(image.iter().map(|t| t[0]).collect::<Vec<_>>(), [7.0, 7.0, 1.0, 7.0]);
    }

    /// The paper's 4-neighbour composite, read plainly: a pixel at offset q from its fragment's
    /// centre (in fragment sizes) blends its own coarse colour with the fragments just across x
    /// and y on its side, and the diagonal one reached across the larger offset first, bilinearly
    /// by |q|. The colours of a 2×2-fragment level: 1, 2 (top), 4, 8 (bottom).
    #[test]
    fn four_neighbour_blends_the_fragments_on_a_pixels_side_bilinearly() {
        let colour = |v: f32| [v, 10.0 * v, 0.0, 1.0];
        let lit = [
            Level { extent: (4, 4), texels: vec![colour(0.0); 16] },
            Level { extent: (2, 2), texels: [1.0, 2.0, 4.0, 8.0].map(colour).to_vec() },
        ];
        let inputs = CompositeInputs { screen: (4, 4), lod: &[1; 16], lit: &lit };
        let image = inputs.composite(CompositeMode::FourNeighbour);
        let bilinear = |own: f32, across_x: f32, across_y: f32, diagonal: f32, a: f32, b: f32| {
            own * (1.0 - a) * (1.0 - b) + across_x * a * (1.0 - b) + across_y * (1.0 - a) * b + diagonal * a * b
        };
        let expected = [
            // (0, 0): q = (−1/4, −1/4); across the screen's edge the clamped reads are its own.
            ((0, 0), 1.0),
            ((1, 1), bilinear(1.0, 2.0, 4.0, 8.0, 0.25, 0.25)),
            ((2, 1), bilinear(2.0, 1.0, 8.0, 4.0, 0.25, 0.25)),
            ((1, 2), bilinear(4.0, 8.0, 1.0, 2.0, 0.25, 0.25)),
            ((2, 2), bilinear(8.0, 4.0, 2.0, 1.0, 0.25, 0.25)),
            ((1, 0), bilinear(1.0, 2.0, 1.0, 2.0, 0.25, 0.25)),
            ((3, 3), 8.0),
        ];
        for ((x, y), want) in expected {
            let got = image[y * 4 + x];
            assert!(
                (got[0] - want).abs() < 1e-5 && (got[1] - 10.0 * want).abs() < 1e-4,
                "({x}, {y}): {got:?} against {want}"
            );
        }
        // Across levels, with |q_y| > |q_x|: a 4×4 fragment (level 2) beside 2×2 ones (level 1)
        // and single pixels (level 0). Pixel (1, 0) of the level-2 fragment lies at
        // q = (−1/8, −3/8): across y first (above the screen: its own), then across x.
        let mut lod = vec![2u8; 64];
        for y in 0..8 {
            for x in 4..8 {
                lod[y * 8 + x] = if y < 4 { 1 } else { 0 };
            }
        }
        let lit = [
            Level { extent: (8, 8), texels: (0..64).map(|i| colour(100.0 + i as f32)).collect() },
            Level { extent: (4, 4), texels: (0..16).map(|i| colour(10.0 + i as f32)).collect() },
            Level { extent: (2, 2), texels: (0..4).map(|i| colour(1.0 + i as f32)).collect() },
        ];
        let inputs = CompositeInputs { screen: (8, 8), lod: &lod, lit: &lit };
        let image = inputs.composite(CompositeMode::FourNeighbour);
        // (3, 1): q = (3/8, −1/8); across x is level-1 texel (2, 0) = 12, across y (above) its
        // own 1; the diagonal across x then y: pixel (4, −1), clamped to (4, 0) = 12.
        let want = bilinear(1.0, 12.0, 1.0, 12.0, 0.375, 0.125);
        assert!((image[8 + 3][0] - want).abs() < 1e-4, "(3, 1): {:?} against {want}", image[8 + 3]);
        // (3, 2): q = (3/8, 1/8); across x (4, 2) is level-1 texel (2, 1) = 16; across y (3, 4)
        // is level 2's texel (0, 1) = 3; the diagonal from (4, 2) across y: its fragment (2×2 at
        // rows 2–3) ends at row 4, pixel (4, 4): level 0, 100 + 36.
        let want = bilinear(1.0, 16.0, 3.0, 136.0, 0.375, 0.125);
        assert!((image[16 + 3][0] - want).abs() < 1e-3, "(3, 2): {:?} against {want}", image[16 + 3]);
        // (2, 3): q = (1/8, 3/8): |q_y| larger, so the diagonal goes across y first: (2, 4) at
        // level 2 = 3, then across x from there: (4, 4) = 136; across x directly: (4, 3) = 16.
        let want = bilinear(1.0, 16.0, 3.0, 136.0, 0.125, 0.375);
        assert!((image[24 + 2][0] - want).abs() < 1e-3, "(2, 3): {:?} against {want}", image[24 + 2]);
    }

    /// Which fragments the 4-neighbour composite reads, as `fs_composite_four_neighbour` picks
    /// them: a single-pixel fragment lies at q = 0, where `select(1, -1, q < 0.0)` steps right and
    /// down (its weights are 0, but the colours it reads enter the bound); and the diagonal is
    /// reached across the larger |q| first, which lands on another fragment where a small one
    /// stands beside a large one.
    #[test]
    fn four_neighbour_reads_right_and_below_at_q_zero_and_the_diagonal_across_the_larger_offset() {
        let colour = |v: f32| [v, 0.0, 0.0, 1.0];
        let single = [Level { extent: (3, 3), texels: (0..9).map(|i| colour(1.0 + i as f32)).collect() }];
        let inputs = CompositeInputs { screen: (3, 3), lod: &[0; 9], lit: &single };
        let (own, read) = inputs.four_neighbour([1, 1]);
        assert_eq!(own, colour(5.0));
        assert_eq!(read, [5.0, 6.0, 8.0, 9.0].map(colour), "(1, 1) reads (1, 1), (2, 1), (1, 2), (2, 2)");
        // Left half: 4×4 fragments (level 2), right half single pixels. Pixel (3, 2) lies at
        // q = (3/8, 1/8): across x first, to (4, 2), then down past that single pixel: (4, 3).
        // Across y first would have gone to (3, 4), then past its 4×4 fragment: (4, 4).
        let lod: Vec<u8> = (0..64).map(|i| if i % 8 < 4 { 2 } else { 0 }).collect();
        let lit = [
            Level { extent: (8, 8), texels: (0..64).map(|i| colour(100.0 + i as f32)).collect() },
            Level { extent: (4, 4), texels: vec![colour(0.0); 16] },
            Level { extent: (2, 2), texels: (0..4).map(|i| colour(1.0 + i as f32)).collect() },
        ];
        let inputs = CompositeInputs { screen: (8, 8), lod: &lod, lit: &lit };
        let (_, read) = inputs.four_neighbour([3, 2]);
        assert_eq!(read, [1.0, 120.0, 3.0, 128.0].map(colour), "(3, 2): own, (4, 2), (3, 4)'s fragment, (4, 3)");
    }

    /// The seam-free triangle's choice read plainly, on every pixel of seeded LOD maps, nested
    /// and not (a content LOD may change from pixel to pixel within a block): of the four
    /// candidates (the corners each side along x and y, in `corners_along`'s order), each solved
    /// in f64, the first of the best kind — holding P with three samples, holding it with a flat
    /// corner, not holding it — leaving out degenerate ones.
    #[test]
    fn seam_free_takes_the_first_candidate_of_the_best_kind() {
        use crate::scene::hash::SeededRng;
        let mut rng = SeededRng::new(275);
        let mut kinds = [0u32; 4];
        for round in 0..120 {
            let screen = (rng.range(1, 24), rng.range(1, 24));
            let top = rng.range(0, 4);
            let lod: Vec<u8> = if round % 2 == 0 {
                crate::cps::lod_model::nested_random(screen, top, round)
            } else {
                (0..screen.0 * screen.1).map(|_| rng.range(0, top + 1) as u8).collect()
            };
            let lit = sampled_levels(screen, top, |p| [p[0] as f32, p[1] as f32, 0.0, 1.0]);
            let inputs = CompositeInputs { screen, lod: &lod, lit: &lit };
            for p in (0..i64::from(screen.1)).flat_map(|y| (0..i64::from(screen.0)).map(move |x| [x, y])) {
                let a = inputs.sample_of(p);
                let toward = [0, 1].map(|i| if p[i] < a[i] { -1 } else { 1 });
                let along_x = inputs.corners_along(p, a, 0, toward[0]);
                let along_y = inputs.corners_along(p, a, 1, toward[1]);
                let d = [(p[0] - a[0]) as f64, (p[1] - a[1]) as f64];
                let candidates = (0..4).filter_map(|i| {
                    let (b, e) = (along_x[i & 1], along_y[i >> 1]);
                    let (u, v) = (b.edge.map(|c| c as f64), e.edge.map(|c| c as f64));
                    let det = u[0] * v[1] - u[1] * v[0];
                    if det == 0.0 {
                        return None;
                    }
                    let (beta, delta) = ((d[0] * v[1] - d[1] * v[0]) / det, (u[0] * d[1] - u[1] * d[0]) / det);
                    let holds = beta >= 0.0 && delta >= 0.0 && beta + delta <= 1.0 + 1e-12;
                    let flat = b.pixel == p || e.pixel == p;
                    let kind = if holds && !flat {
                        3
                    } else if holds {
                        2
                    } else {
                        1
                    };
                    Some((kind, [p, b.pixel, e.pixel]))
                });
                let mut best: Option<(u32, [[i64; 2]; 3])> = None;
                for (kind, corners) in candidates {
                    if best.is_none_or(|(best_kind, _)| kind > best_kind) {
                        best = Some((kind, corners));
                    }
                }
                let chosen = inputs.seam_free_triangle(p).map(|t| t.corners);
                assert_eq!(chosen, best.map(|(_, corners)| corners), "{screen:?} round {round} {p:?} (A {a:?})");
                kinds[best.map_or(0, |(kind, _)| kind as usize)] += 1;
            }
        }
        // Each kind is chosen somewhere, the last resort (no candidate holds P) included.
        assert!(kinds[1..].iter().all(|&n| n > 100), "choices by kind (none, other, flat, three samples): {kinds:?}");
    }

    /// The seam metric by its definition on 2×2: pairs (0,0)–(1,0) and (0,0)–(0,1) cross a LOD
    /// change, (1,0)–(1,1) and (0,1)–(1,1) do not. Red steps: image −2 and −4 against the
    /// reference's −1 and −1: departures 1 and 3, a third of each over RGB, their mean 2/3.
    #[test]
    fn the_seam_error_is_the_mean_departure_of_steps_across_lod_changes() {
        let red = |values: [f32; 4]| values.map(|v| [v, 0.0, 0.0, 1.0]).to_vec();
        let lod = [0, 1, 1, 1];
        let image = red([1.0, 3.0, 5.0, 100.0]);
        let reference = red([1.0, 2.0, 2.0, -50.0]);
        assert!((seam_error((2, 2), &lod, &image, &reference) - 2.0 / 3.0).abs() < 1e-12);
        // Green and blue count too, each a third.
        let mut green = image.clone();
        green[1][1] = 0.6;
        assert!((seam_error((2, 2), &lod, &green, &reference) - (2.0 / 3.0 + 0.6 / 3.0 / 2.0)).abs() < 1e-6);
        // On 3×1 with LODs 0, 0, 1: only the pair (1, 2), whatever happens elsewhere.
        let row = |values: &[f32]| values.iter().map(|&v| [v, v, v, 1.0]).collect::<Vec<_>>();
        let error = seam_error((3, 1), &[0, 0, 1], &row(&[9.0, 2.0, 1.0]), &row(&[-9.0, 2.0, 1.5]));
        assert!((error - 0.5).abs() < 1e-12, "{error}");
        // No LOD change, no seam.
        assert_eq!(seam_error((2, 2), &[1; 4], &image, &reference), 0.0);
        // An image offset from the reference by a constant steps as it does: no seam.
        assert_eq!(seam_error((2, 1), &[0, 1], &row(&[2.0, 3.0]), &row(&[1.0, 2.0])), 0.0);
    }

    /// A composite's alpha is 1 whatever the lit level's alpha.
    #[test]
    fn a_composited_pixel_is_opaque() {
        let lit = [Level { extent: (1, 1), texels: vec![[0.5, 0.5, 0.5, 0.25]] }];
        let inputs = CompositeInputs { screen: (1, 1), lod: &[0], lit: &lit };
        for mode in [CompositeMode::Nearest, CompositeMode::FourNeighbour, CompositeMode::SeamFree] {
            assert_eq!(inputs.composite(mode)[0][3], 1.0, "{mode:?}");
        }
    }

    /// On single-pixel fragments every sample is its pixel: the seam-free triangle at a pixel is
    /// its own sample with the next ones along +x and +y (where P lies on its sample, the
    /// positive side first), the other side where the screen ends; the bound covers the
    /// largest of its three corners.
    #[test]
    fn seam_free_triangles_on_single_pixel_fragments_take_the_positive_side_first() {
        let magnitude = |p: [i64; 2]| [1.0 + 10.0 * (p[0] + 3 * p[1]) as f32, 0.0, 0.0, 1.0];
        let lit = sampled_levels((3, 3), 0, magnitude);
        let inputs = CompositeInputs { screen: (3, 3), lod: &[0; 9], lit: &lit };
        let triangle = |p: [i64; 2]| inputs.seam_free_triangle(p).unwrap().corners;
        assert_eq!(triangle([1, 1]), [[1, 1], [2, 1], [1, 2]]);
        assert_eq!(triangle([0, 0]), [[0, 0], [1, 0], [0, 1]]);
        assert_eq!(triangle([2, 1]), [[2, 1], [1, 1], [2, 2]]);
        assert_eq!(triangle([2, 2]), [[2, 2], [1, 2], [2, 1]]);
        let pixels = inputs.composite_with_bounds(CompositeMode::SeamFree);
        // (1, 1): its own colour 41; the corners 41, 51 and 71 (weights 0, no amplification).
        let centre = pixels[4];
        assert_eq!(centre.colour[0], 41.0);
        let expected = 2f32.powi(-19) * 71.0 + 2f32.powi(-10) * 41.0 + 2f32.powi(-24);
        assert!((centre.bound[0] - expected).abs() <= 1e-6 * expected, "{:?} against {expected}", centre.bound);
    }

    /// Beyond the outermost sample the triangle is flat: at (1, 0) of a 4×4 fragment sampled at
    /// (2, 2), with single pixels right and below, no candidate holds P; the first, flat along
    /// both axes by P's own distance from A (−1 in x, −2 in y), is kept: det 2, β = δ = 1. Its
    /// colour is P's own, its bound amplified by 1 + 2 (|β| + |δ|) = 5.
    #[test]
    fn beyond_the_outermost_sample_the_triangle_is_flat_by_the_pixels_own_distance() {
        let lod: Vec<u8> = (0..64).map(|i| if i % 8 < 4 && i / 8 < 4 { 2 } else { 0 }).collect();
        let lit = sampled_levels((8, 8), 2, |p| [2.0 + p[0] as f32, 0.0, 0.0, 1.0]);
        let inputs = CompositeInputs { screen: (8, 8), lod: &lod, lit: &lit };
        let triangle = inputs.seam_free_triangle([1, 0]).unwrap();
        assert_eq!(triangle, Triangle { corners: [[1, 0]; 3], det: 2, nb: 2, nd: 2 });
        assert!(triangle.has_flat_corner());
        let pixel = inputs.composite_with_bounds(CompositeMode::SeamFree)[1];
        // The fragment was lit at (2, 2): 4.
        assert_eq!(pixel.colour[0], 4.0);
        let expected = 2f32.powi(-19) * 4.0 * 5.0 + 2f32.powi(-10) * 4.0 + 2f32.powi(-24);
        assert!((pixel.bound[0] - expected).abs() <= 1e-6 * expected, "{:?} against {expected}", pixel.bound);
    }

    /// On nested LODs, wherever a triangle of A and the samples of the fragments just across x
    /// and y (either side, read plainly: the pixel past the block's edge) holds P, the chosen one
    /// holds it, with real corners: P − A = β (B − A) + δ (D − A), β, δ ≥ 0, β + δ ≤ 1, solved
    /// here in f64 and equal to the triangle's weights. Shading that is not linear then stays
    /// within its corners' colours there (an interpolation, never an extrapolation).
    #[test]
    fn seam_free_triangles_hold_their_pixel_wherever_one_can() {
        let mut held = 0;
        for (seed, screen, top) in [(1, (37, 23), 3), (2, (64, 48), 4), (3, (13, 50), 2), (6, (40, 40), 3)] {
            let lod = crate::cps::lod_model::nested_random(screen, top, seed);
            let wavy = |p: [i64; 2]| [(p[0] as f32 * 0.7).sin() + (p[1] as f32 * 0.3).cos() + 3.0, 1.0, 1.0, 1.0];
            let lit = sampled_levels(screen, top, wavy);
            let inputs = CompositeInputs { screen, lod: &lod, lit: &lit };
            let image = inputs.composite(CompositeMode::SeamFree);
            let solve = |a: [f64; 2], b: [f64; 2], d: [f64; 2], p: [f64; 2]| {
                let (u, v, w) = ([b[0] - a[0], b[1] - a[1]], [d[0] - a[0], d[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
                let det = u[0] * v[1] - u[1] * v[0];
                (det != 0.0).then(|| ((w[0] * v[1] - w[1] * v[0]) / det, (u[0] * w[1] - u[1] * w[0]) / det))
            };
            let holds = |(beta, delta): (f64, f64)| beta >= 0.0 && delta >= 0.0 && beta + delta <= 1.0 + 1e-12;
            let sample = |at: [i64; 2]| inputs.sample_of(at).map(|v| v as f64);
            for (i, pixel) in image.iter().enumerate() {
                let p = [i as i64 % i64::from(screen.0), i as i64 / i64::from(screen.0)];
                let level = u32::from(lod[i]).min(top);
                let across = |axis: usize, side: i64| {
                    let origin = (p[axis] >> level) << level;
                    let mut q = p;
                    q[axis] = if side < 0 { origin - 1 } else { origin + (1 << level) };
                    inputs.on_screen(q).then(|| sample(q))
                };
                let pf = p.map(|v| v as f64);
                let any = [-1, 1].iter().any(|&sx| {
                    [-1, 1].iter().any(|&sy| match (across(0, sx), across(1, sy)) {
                        (Some(b), Some(d)) => solve(sample(p), b, d, pf).is_some_and(holds),
                        _ => false,
                    })
                });
                if !any {
                    continue;
                }
                let triangle = inputs.seam_free_triangle(p).unwrap();
                assert!(!triangle.has_flat_corner(), "{screen:?} seed {seed} {p:?}: flat {triangle:?}");
                let [a, b, d] = triangle.corners.map(sample);
                let (beta, delta) = solve(a, b, d, pf).expect("not degenerate");
                assert!(holds((beta, delta)), "{screen:?} seed {seed} {p:?}: β {beta}, δ {delta} in {triangle:?}");
                let (gb, gd) = triangle.weights();
                assert!((f64::from(gb) - beta).abs() < 1e-6 && (f64::from(gd) - delta).abs() < 1e-6);
                let corners = triangle.corners.map(|at| inputs.coarse_colour(at)[0]);
                let lo = corners.iter().copied().fold(f32::MAX, f32::min);
                let hi = corners.iter().copied().fold(f32::MIN, f32::max);
                assert!(pixel[0] >= lo - 1e-5 && pixel[0] <= hi + 1e-5, "{p:?}: {} outside {lo}..{hi}", pixel[0]);
                held += 1;
            }
        }
        assert!(held > 2000, "only {held} pixels between samples");
    }
}
