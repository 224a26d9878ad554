//! CPU expectations for CPS: how many coarse texels each level must shade for a LOD buffer, and
//! the three composites computed from read-back lit levels by the same equations as
//! `shaders/cps/composite.wgsl`, `fill_pull.wgsl` and `fill_push.wgsl` (stored values rounded
//! to f16, as the GPU's `Rgba16Float` targets store them), each pixel with the bound a correct GPU
//! keeps to: one f16 ulp per store on the way (CPU and GPU may round a value a hair apart to
//! neighbouring f16s), f32 evaluation-order slack, both scaled by the magnitudes entering the
//! pixel, so bright scenes get proportionally wider bounds and dim pixels beside bright ones no
//! looser ones than they need.

use super::config::CompositeMode;

/// For level `level`, whether each texel (row-major over ceil(screen / 2^level)) holds some pixel
/// whose LOD, clamped to `top`, is `level`: exactly the texels its stencil must mark.
pub fn needed_texels(screen: (u32, u32), lod: &[u8], top: u32, level: u32) -> Vec<bool> {
    let at_level: Vec<bool> = lod.iter().map(|&l| u32::from(l).min(top) == level).collect();
    blocks_holding(screen, &at_level, level)
}

/// For level `level`, whether each texel's 2^level block holds a pixel marked in `pixels`.
pub fn blocks_holding(screen: (u32, u32), pixels: &[bool], level: u32) -> Vec<bool> {
    let (w, h) = (screen.0.div_ceil(1 << level), screen.1.div_ceil(1 << level));
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

    /// The (up to) four texels a bilinear read at `at` mixes.
    fn around(&self, at: [f32; 2]) -> [[f32; 4]; 4] {
        let (x, y) = (at[0].floor() as i64, at[1].floor() as i64);
        [self.at(x, y), self.at(x + 1, y), self.at(x, y + 1), self.at(x + 1, y + 1)]
    }

    /// Bilinear interpolation at texel coordinate `at` (centres at integers), clamped to the data.
    fn bilinear(&self, at: [f32; 2]) -> [f32; 4] {
        let base = [at[0].floor(), at[1].floor()];
        let f = [at[0] - base[0], at[1] - base[1]];
        let (x, y) = (base[0] as i64, base[1] as i64);
        let top = mix(self.at(x, y), self.at(x + 1, y), f[0]);
        let bottom = mix(self.at(x, y + 1), self.at(x + 1, y + 1), f[0]);
        mix(top, bottom, f[1])
    }
}

/// WGSL's `mix`: a · (1 − t) + b · t.
fn mix(a: [f32; 4], b: [f32; 4], t: f32) -> [f32; 4] {
    std::array::from_fn(|i| a[i] * (1.0 - t) + b[i] * t)
}

fn to_f16(texel: [f32; 4]) -> [f32; 4] {
    texel.map(|v| half::f16::from_f32(v).to_f32())
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

/// The bound for `value` made from `inputs` (each carrying its own error `carried`), stored to f16
/// once: the carried errors (convex combinations do not amplify them), the f32 slack of the
/// largest input and the final rounding.
fn stored_bound(value: [f32; 4], inputs: &[[f32; 4]], carried: [f32; 4], store_ulps: f32) -> [f32; 4] {
    std::array::from_fn(|c| {
        let reach = inputs.iter().map(|t| t[c].abs()).fold(0.0f32, f32::max);
        carried[c] + F32_SLACK * reach + store_ulps * value[c].abs() + F16_SUBNORMAL
    })
}

fn channel_max(a: [f32; 4], b: [f32; 4]) -> [f32; 4] {
    std::array::from_fn(|c| a[c].max(b[c]))
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

    /// The pull-push filled pyramid, as `fill_pull.wgsl` then `fill_push.wgsl` make it, each
    /// level with its texels' error bounds (a level of bounds per channel; lit texels carry none).
    pub fn filled(&self) -> Vec<(Level, Level)> {
        let exact = |level: &Level| Level { extent: level.extent, texels: vec![[0.0; 4]; level.texels.len()] };
        let mut pulled: Vec<(Level, Level)> = vec![(self.lit[0].clone(), exact(&self.lit[0]))];
        for level in 1..self.lit.len() {
            let lit = &self.lit[level];
            let (finer, finer_error) = &pulled[level - 1];
            let (w, h) = lit.extent;
            let (texels, errors): (Vec<[f32; 4]>, Vec<[f32; 4]>) = (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .map(|(x, y)| {
                    let own = lit.texels[(y * w + x) as usize];
                    if own[3] == 1.0 {
                        return (own, [0.0; 4]);
                    }
                    let children: Vec<usize> = [(0, 0), (1, 0), (0, 1), (1, 1)]
                        .into_iter()
                        .map(|(dx, dy)| (2 * x + dx, 2 * y + dy))
                        .filter(|&(cx, cy)| cx < finer.extent.0 && cy < finer.extent.1)
                        .map(|(cx, cy)| (cy * finer.extent.0 + cx) as usize)
                        .filter(|&i| finer.texels[i][3] == 1.0)
                        .collect();
                    if children.is_empty() {
                        return ([0.0; 4], [0.0; 4]);
                    }
                    let n = children.len() as f32;
                    let values: Vec<[f32; 4]> = children.iter().map(|&i| finer.texels[i]).collect();
                    let sum = values.iter().fold([0.0f32; 3], |s, t| [s[0] + t[0], s[1] + t[1], s[2] + t[2]]);
                    let texel = to_f16([sum[0] / n, sum[1] / n, sum[2] / n, 1.0]);
                    let carried = children.iter().fold([0.0; 4], |e, &i| channel_max(e, finer_error.texels[i]));
                    (texel, stored_bound(texel, &values, carried, F16_ULP))
                })
                .unzip();
            pulled.push((Level { extent: lit.extent, texels }, Level { extent: lit.extent, texels: errors }));
        }
        let mut filled = vec![pulled.last().expect("at least one level").clone()];
        for level in (0..pulled.len() - 1).rev() {
            let (coarser, coarser_error) = filled.last().expect("pushed from the top").clone();
            let (own, own_error) = &pulled[level];
            let (w, h) = own.extent;
            let (texels, errors): (Vec<[f32; 4]>, Vec<[f32; 4]>) = (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .map(|(x, y)| {
                    let i = (y * w + x) as usize;
                    if own.texels[i][3] == 1.0 {
                        return (own.texels[i], own_error.texels[i]);
                    }
                    let at = [(x as f32 + 0.5) * 0.5 - 0.5, (y as f32 + 0.5) * 0.5 - 0.5];
                    let c = coarser.bilinear(at);
                    let texel = to_f16([c[0], c[1], c[2], 1.0]);
                    let carried = coarser_error.around(at).into_iter().fold([0.0; 4], channel_max);
                    (texel, stored_bound(texel, &coarser.around(at), carried, F16_ULP))
                })
                .unzip();
            filled.push((Level { extent: own.extent, texels }, Level { extent: own.extent, texels: errors }));
        }
        filled.reverse();
        filled
    }

    /// Finest level present in each texel of level `k` (the lowest bit of the LOD-present mask).
    fn finest_present(&self, k: u32) -> Level {
        let (w, h) = (self.screen.0.div_ceil(1 << k), self.screen.1.div_ceil(1 << k));
        let mut finest = vec![u32::MAX; (w * h) as usize];
        for y in 0..self.screen.1 {
            for x in 0..self.screen.0 {
                let cell = &mut finest[((y >> k) * w + (x >> k)) as usize];
                *cell = (*cell).min(self.level_of([i64::from(x), i64::from(y)]));
            }
        }
        Level { extent: (w, h), texels: finest.into_iter().map(|l| [l as f32; 4]).collect() }
    }

    fn seam_free(&self, p: [i64; 2], filled: &[(Level, Level)]) -> Composited {
        let top = self.top();
        let k = super::renderer::SEAM_FREE_TRANSITION_LEVEL.min(top);
        let cell = (1i64 << k) as f32;
        let field =
            self.finest_present(k).bilinear([(p[0] as f32 + 0.5) / cell - 0.5, (p[1] as f32 + 0.5) / cell - 0.5])[0];
        let fine = (field.floor() as u32).min(top);
        let coarse = (fine + 1).min(top);
        let at = |level: u32| {
            let size = (1i64 << level) as f32;
            [(p[0] as f32 + 0.5) / size - 0.5, (p[1] as f32 + 0.5) / size - 0.5]
        };
        let [(fine_colour, fine_error), (coarse_colour, coarse_error)] = [fine, coarse].map(|level| {
            let (colours, errors) = &filled[level as usize];
            (colours.bilinear(at(level)), errors.around(at(level)).into_iter().fold([0.0; 4], channel_max))
        });
        let colour = mix(fine_colour, coarse_colour, field - field.floor());
        let inputs: Vec<[f32; 4]> =
            [fine, coarse].iter().flat_map(|&level| filled[level as usize].0.around(at(level))).collect();
        let bound = stored_bound(colour, &inputs, channel_max(fine_error, coarse_error), F16_ULP);
        Composited { colour, bound: [bound[0], bound[1], bound[2]] }
    }

    /// The composite in `mode`, RGBA per pixel (alpha 1), before the f16 store.
    pub fn composite(&self, mode: CompositeMode) -> Vec<[f32; 4]> {
        self.composite_with_bounds(mode).into_iter().map(|pixel| pixel.colour).collect()
    }

    /// The composite in `mode` with each pixel's bound (its f16 store included).
    pub fn composite_with_bounds(&self, mode: CompositeMode) -> Vec<Composited> {
        let filled = (mode == CompositeMode::SeamFree).then(|| self.filled());
        let (w, h) = self.screen;
        let direct = |colour: [f32; 4], inputs: &[[f32; 4]]| {
            let bound = stored_bound(colour, inputs, [0.0; 4], F16_ULP);
            Composited { colour, bound: [bound[0], bound[1], bound[2]] }
        };
        (0..h)
            .flat_map(|y| (0..w).map(move |x| [i64::from(x), i64::from(y)]))
            .map(|p| {
                let pixel = match (mode, &filled) {
                    (CompositeMode::Nearest, _) => {
                        let colour = self.coarse_colour(p);
                        direct(colour, &[colour])
                    }
                    (CompositeMode::FourNeighbour, _) => {
                        let (colour, inputs) = self.four_neighbour(p);
                        direct(colour, &inputs)
                    }
                    (CompositeMode::SeamFree, Some(filled)) => self.seam_free(p, filled),
                    (CompositeMode::SeamFree, None) => unreachable!("filled is computed for the seam-free mode"),
                };
                Composited { colour: [pixel.colour[0], pixel.colour[1], pixel.colour[2], 1.0], ..pixel }
            })
            .collect()
    }
}

/// Whether the kit claims, for a screen and a plan's top level, that the seam-free composite has
/// a lower seam error than the 4-neighbour one (Err: why not). The claim needs at least two level
/// steps (with one, both blend over the same two pixels and tie within rounding) and a short side
/// of at least four transition cells of 2^k pixels, so the blend band is not clipped by the
/// screen's edges; measured on lavapipe over sizes 1x8..200x150, top levels 1..8 and 1..1000
/// lights, it held wherever these do. Outside them `fragkit report cps` shows both errors.
pub fn seam_claim_applies(screen: (u32, u32), top_level: u32) -> Result<(), String> {
    let k = super::renderer::SEAM_FREE_TRANSITION_LEVEL.min(top_level);
    if top_level < 2 {
        return Err(format!("top level {top_level} has fewer than two level steps"));
    }
    let needed = 4 << k;
    if screen.0.min(screen.1) < needed {
        return Err(format!(
            "the short side {} spans fewer than four {}-pixel transition cells",
            screen.0.min(screen.1),
            1 << k
        ));
    }
    Ok(())
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
}
