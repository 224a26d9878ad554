//! The plan: which levels, targets and passes a CPS frame needs for a screen and configuration.
//! Only what can contribute is created: no level coarser than one fragment covering the whole
//! screen, no edge pyramid unless the content policy reads it.

use anyhow::{Context, Result};
use serde::Serialize;

use super::atlas::LevelAtlas;
use super::config::{CpsConfig, LodPolicy};
use crate::gpu::Gpu;

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Plan {
    pub screen: (u32, u32),
    /// Coarsest level that can occur: min(max_level, ceil(log2(max(width, height)))). Beyond it a
    /// single fragment already covers the screen, so coarser levels would repeat it.
    pub top_level: u32,
    /// Texels of each level that hold data: ceil(screen / 2^l).
    pub level_extents: Vec<(u32, u32)>,
    /// Base size of the mip chains, rounded up to a multiple of 2^top_level so that mip l is at
    /// least ceil(screen / 2^l) (a mip is floor(base / 2^l)).
    pub padded: (u32, u32),
    /// Levels no pixel uses are drawn with zero instances, the counts written by a fragment pass
    /// (needs fragment storage writes and indirect draws that render); otherwise every level is
    /// drawn directly and the stencil rejects all.
    pub skip_absent_levels_on_gpu: bool,
    /// The stencil pyramid (absent for the naive, shade-everything comparison).
    pub stencil_pyramid: bool,
    /// The foveated policy with an inner radius of a pixel or more: every pass that needs a
    /// pixel's level computes it from the foveation (common/foveation.wgsl) instead of reading
    /// an LOD buffer, and the stencil marks a block's levels from its nearest and farthest pixels
    /// (the rings are too wide for a block to skip one). No LOD pass, no mask pyramid: the frame
    /// leaves out what only a data-dependent LOD needs.
    pub levels_from_foveation: bool,
    pub edge_pyramid: bool,
    /// Where each level lies in the stencil and lit atlases.
    pub atlas: LevelAtlas,
    /// Per level, the texels (x, y, width, height within the level) that can be needed: the whole
    /// level, or under the foveated policy with a stencil pyramid the box around the disk the
    /// level's pixels lie in. The marks (a quad over the bounds, or a scissor) and the lighting
    /// (a scissor) draw only there: the rest of a level's rect could only be discarded or
    /// stencil-rejected, texel by texel.
    pub level_bounds: Vec<(u32, u32, u32, u32)>,
}

/// The texels of `level` (below the top) that can hold a pixel of that level under the foveated
/// policy: level(d) = floor(log2(1 + d / r)) ≤ level only for d < r (2^(level+1) − 1), so its
/// pixels lie in that disk around the focus — widened by 2^-16 of it and a pixel for the GPU's
/// f32 squared distance and the marks' widening (together within 2^-19 of it) — and its texels in
/// the disk's box.
fn foveated_bounds(screen: (u32, u32), focus: (f32, f32), inner_radius: f32, level: u32) -> (u32, u32, u32, u32) {
    let radius = f64::from(inner_radius.max(1e-3)) * (f64::from(2u32 << level) - 1.0);
    let reach = radius * (1.0 + 1.0 / 65536.0) + 1.0;
    // Pixel centres x + 1/2 within `reach` of the focus, on screen, then their texels.
    let span = |centre: f64, extent: u32| {
        let first = (centre - reach - 0.5).ceil().clamp(0.0, f64::from(extent - 1)) as u32;
        let last = (centre + reach - 0.5).floor().clamp(0.0, f64::from(extent - 1)) as u32;
        (first >> level, (last.max(first) >> level) + 1)
    };
    let (x0, x1) = span(f64::from(focus.0) * f64::from(screen.0), screen.0);
    let (y0, y1) = span(f64::from(focus.1) * f64::from(screen.1), screen.1);
    (x0, y0, x1 - x0, y1 - y0)
}

/// Each level's `Plan::level_bounds`.
fn bounds_of_levels(
    screen: (u32, u32),
    level_extents: &[(u32, u32)],
    policy: &LodPolicy,
    stencil_pyramid: bool,
) -> Vec<(u32, u32, u32, u32)> {
    let top_level = level_extents.len() as u32 - 1;
    (0..=top_level)
        .map(|level| match policy {
            LodPolicy::Foveated { focus, inner_radius } if stencil_pyramid && level < top_level => {
                foveated_bounds(screen, *focus, *inner_radius, level)
            }
            _ => (0, 0, level_extents[level as usize].0, level_extents[level as usize].1),
        })
        .collect()
}

/// Levels needed until one fragment covers a screen side of `extent` pixels.
fn levels_to_cover(extent: u32) -> u32 {
    extent.max(1).next_power_of_two().trailing_zeros()
}

impl Plan {
    pub fn new(gpu: &Gpu, screen: (u32, u32), config: &CpsConfig) -> Result<Self> {
        crate::deferred::gbuffer::check_size(gpu, screen)?;
        config.validate(screen)?;
        let top_level = config.max_level.min(levels_to_cover(screen.0.max(screen.1)));
        let level_extents: Vec<(u32, u32)> =
            (0..=top_level).map(|l| (screen.0.div_ceil(1 << l), screen.1.div_ceil(1 << l))).collect();
        let unit = 1u32 << top_level;
        let padded = (screen.0.div_ceil(unit) * unit, screen.1.div_ceil(unit) * unit);
        let max = gpu.device.limits().max_texture_dimension_2d;
        anyhow::ensure!(
            padded.0 <= max && padded.1 <= max,
            "the {}x{} screen pads to {}x{} for level {top_level}, beyond this adapter's {max}x{max} limit",
            screen.0,
            screen.1,
            padded.0,
            padded.1
        );
        // Every level side by side in one texture (cps/atlas.rs): half as wide or as tall again as
        // the screen.
        let atlas = LevelAtlas::fitting(&level_extents, max).with_context(|| {
            format!(
                "the {}x{} screen's levels side by side take half as much again as the screen, beyond this adapter's {max}x{max} limit",
                screen.0, screen.1
            )
        })?;
        let stencil_pyramid = !config.shade_every_texel;
        let levels_from_foveation =
            matches!(config.policy, LodPolicy::Foveated { inner_radius, .. } if inner_radius >= 1.0);
        let level_bounds = bounds_of_levels(screen, &level_extents, &config.policy, stencil_pyramid);
        Ok(Self {
            screen,
            top_level,
            level_extents,
            level_bounds,
            padded,
            // Fragment storage and indirect draws as renders showed them, not as the flags claim
            // (softpipe's GL 3.3 claims storage; GLES 3.1 refuses indirect draws under wgpu-hal).
            skip_absent_levels_on_gpu: stencil_pyramid
                && !levels_from_foveation
                && crate::probe::indirect_draw::indirect_draw_problem(gpu)?.is_none()
                && crate::probe::fragment_storage::fragment_storage_problem(gpu)?.is_none(),
            stencil_pyramid,
            levels_from_foveation,
            edge_pyramid: matches!(config.policy, LodPolicy::Content { .. }),
            atlas,
        })
    }

    /// A stencil-pyramid plan without a device: the CPU side of a foveated frame, for tests.
    #[cfg(test)]
    pub(crate) fn for_test(screen: (u32, u32), top_level: u32, atlas: LevelAtlas, policy: &LodPolicy) -> Self {
        let level_extents = atlas.extents.clone();
        Self {
            screen,
            top_level,
            level_bounds: bounds_of_levels(screen, &level_extents, policy, true),
            level_extents,
            padded: screen,
            skip_absent_levels_on_gpu: false,
            stencil_pyramid: true,
            levels_from_foveation: matches!(policy, LodPolicy::Foveated { .. }),
            edge_pyramid: false,
            atlas,
        }
    }

    pub fn levels(&self) -> u32 {
        self.top_level + 1
    }

    /// A level's draw in atlas coordinates (its spans): the whole atlas as viewport, scissored as
    /// `set_level_viewport`.
    pub(crate) fn set_atlas_viewport(&self, pass: &mut wgpu::RenderPass<'_>, level: usize) {
        let (x, y, _, _) = self.atlas.rect(level);
        let (bx, by, bw, bh) = self.level_bounds[level];
        pass.set_viewport(0.0, 0.0, self.atlas.size.0 as f32, self.atlas.size.1 as f32, 0.0, 1.0);
        pass.set_scissor_rect(x + bx, y + by, bw, bh);
    }

    /// A level's draw: its rect of the atlas as viewport, scissored to the texels that can be
    /// needed (`level_bounds`, within the level).
    pub(crate) fn set_level_viewport(&self, pass: &mut wgpu::RenderPass<'_>, level: usize) {
        let (x, y, width, height) = self.atlas.rect(level);
        let (bx, by, bw, bh) = self.level_bounds[level];
        pass.set_viewport(x as f32, y as f32, width as f32, height as f32, 0.0, 1.0);
        pass.set_scissor_rect(x + bx, y + by, bw, bh);
    }
}

#[cfg(test)]
mod tests {
    use super::{bounds_of_levels, foveated_bounds, levels_to_cover};
    use crate::cps::config::LodPolicy;
    use crate::cps::lod_model::foveated;

    #[test]
    fn every_foveated_pixel_lies_within_its_levels_bounds() {
        for screen in [(640u32, 360u32), (37, 23), (1, 1), (300, 6), (5, 200)] {
            let top = levels_to_cover(screen.0.max(screen.1));
            for inner_radius in [0.0, 0.5, 1.0, 6.0, 24.0, 100.0] {
                for focus in [(0.5, 0.5), (0.0, 0.0), (1.0, 1.0), (0.3, 0.9)] {
                    let model = foveated(screen, focus, inner_radius, top);
                    for (i, (&level, &ambiguous)) in model.levels.iter().zip(&model.ambiguous).enumerate() {
                        let (x, y) = (i as u32 % screen.0, i as u32 / screen.0);
                        // An ambiguous pixel lies at a level boundary: the GPU may take either side.
                        let candidates = if ambiguous {
                            let f = (f64::from(focus.0 * screen.0 as f32), f64::from(focus.1 * screen.1 as f32));
                            let d = (f64::from(x) + 0.5 - f.0).hypot(f64::from(y) + 0.5 - f.1);
                            let boundary = (1.0 + d / f64::from(inner_radius).max(1e-3)).log2().round() as u8;
                            vec![boundary - 1, boundary]
                        } else {
                            vec![level]
                        };
                        for level in candidates.into_iter().map(u32::from).filter(|&l| l < top) {
                            let (bx, by, bw, bh) = foveated_bounds(screen, focus, inner_radius, level);
                            let (tx, ty) = (x >> level, y >> level);
                            assert!(
                                (bx..bx + bw).contains(&tx) && (by..by + bh).contains(&ty),
                                "{screen:?} r {inner_radius} focus {focus:?}: pixel ({x}, {y}) of level {level} outside {:?}",
                                (bx, by, bw, bh)
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn levels_stop_where_one_fragment_covers_the_screen() {
        assert_eq!(levels_to_cover(1), 0);
        assert_eq!(levels_to_cover(2), 1);
        assert_eq!(levels_to_cover(3), 2);
        assert_eq!(levels_to_cover(256), 8);
        assert_eq!(levels_to_cover(300), 9);
    }

    /// The bounds read plainly: the texels holding a pixel centre within R = r (2^(level+1) − 1)
    /// (1 + 2^-16) + 1 of the focus along each axis, on screen — checked pixel by pixel.
    #[test]
    fn foveated_bounds_are_the_box_of_the_widened_disk() {
        let mut rng = crate::scene::hash::SeededRng::new(52);
        for _ in 0..300 {
            let screen = (rng.range(1, 400), rng.range(1, 300));
            let focus = (rng.unit() * 1.4 - 0.2, rng.unit() * 1.4 - 0.2);
            let inner_radius: f32 = [0.0, 0.3, 1.0, 2.5, 7.0, 40.0][rng.range(0, 6) as usize];
            let level = rng.range(0, 6);
            let reach =
                f64::from(inner_radius.max(1e-3)) * (f64::from(1u32 << (level + 1)) - 1.0) * (1.0 + 2f64.powi(-16))
                    + 1.0;
            let texels = |centre: f64, extent: u32| {
                let inside: Vec<u32> =
                    (0..extent).filter(|&p| (f64::from(p) + 0.5 - centre).abs() <= reach).map(|p| p >> level).collect();
                match (inside.first(), inside.last()) {
                    (Some(&a), Some(&b)) => (a, b + 1 - a),
                    // No centre within reach: the nearest edge texel, one wide.
                    _ => {
                        let nearest = if centre < 0.0 { 0 } else { (extent - 1) >> level };
                        (nearest, 1)
                    }
                }
            };
            let (x0, w) = texels(f64::from(focus.0) * f64::from(screen.0), screen.0);
            let (y0, h) = texels(f64::from(focus.1) * f64::from(screen.1), screen.1);
            assert_eq!(
                foveated_bounds(screen, focus, inner_radius, level),
                (x0, y0, w, h),
                "{screen:?} focus {focus:?} r {inner_radius} level {level}"
            );
        }
        // A centre exactly a pixel past the disk's edge lies within the widening, along either
        // axis: r = 999.5 at level 0 (R = r), the focus on the screen's first pixel edge, pixel
        // 1000's centre at 1000.5 = R + 1.
        assert_eq!(foveated_bounds((2048, 1), (0.0, 0.5), 999.5, 0), (0, 0, 1001, 1));
        assert_eq!(foveated_bounds((1, 2048), (0.5, 0.0), 999.5, 0), (0, 0, 1, 1001));
    }

    /// Under the foveated policy with a stencil pyramid, each level below the top is drawn
    /// within its disk's box and the top whole; without the pyramid, or under another policy,
    /// every level whole.
    #[test]
    fn only_foveated_levels_below_the_top_are_bounded() {
        let screen = (200u32, 120u32);
        let extents: Vec<(u32, u32)> =
            (0..=5).map(|l| (screen.0.div_ceil(1 << l), screen.1.div_ceil(1 << l))).collect();
        let foveated = LodPolicy::Foveated { focus: (0.5, 0.5), inner_radius: 4.0 };
        let bounded = bounds_of_levels(screen, &extents, &foveated, true);
        for level in 0..5 {
            assert_eq!(bounded[level], foveated_bounds(screen, (0.5, 0.5), 4.0, level as u32), "level {level}");
            // Level 4's disk (radius 4 · 31 px) covers the screen.
            if level < 4 {
                assert_ne!(bounded[level], (0, 0, extents[level].0, extents[level].1), "level {level} is bounded");
            }
        }
        assert_eq!(bounded[5], (0, 0, extents[5].0, extents[5].1));
        let whole: Vec<(u32, u32, u32, u32)> = extents.iter().map(|&(w, h)| (0, 0, w, h)).collect();
        assert_eq!(bounds_of_levels(screen, &extents, &foveated, false), whole);
        let content = LodPolicy::Content { normal_cos: 0.9, depth_ratio: 0.05 };
        assert_eq!(bounds_of_levels(screen, &extents, &content, true), whole);
    }
}
