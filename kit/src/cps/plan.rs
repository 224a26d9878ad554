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
    /// (needs fragment storage writes); otherwise every level is drawn and the stencil rejects all.
    pub skip_absent_levels_on_gpu: bool,
    /// The stencil pyramid (absent for the naive, shade-everything comparison).
    pub stencil_pyramid: bool,
    pub edge_pyramid: bool,
    /// Where each level lies in the stencil and lit atlases.
    pub atlas: LevelAtlas,
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
        Ok(Self {
            screen,
            top_level,
            level_extents,
            padded,
            skip_absent_levels_on_gpu: !config.shade_every_texel
                && gpu.adapter.get_downlevel_capabilities().flags.contains(
                    wgpu::DownlevelFlags::FRAGMENT_WRITABLE_STORAGE | wgpu::DownlevelFlags::INDIRECT_EXECUTION,
                ),
            stencil_pyramid: !config.shade_every_texel,
            edge_pyramid: matches!(config.policy, LodPolicy::Content { .. }),
            atlas,
        })
    }

    pub fn levels(&self) -> u32 {
        self.top_level + 1
    }
}

#[cfg(test)]
mod tests {
    use super::levels_to_cover;

    #[test]
    fn levels_stop_where_one_fragment_covers_the_screen() {
        assert_eq!(levels_to_cover(1), 0);
        assert_eq!(levels_to_cover(2), 1);
        assert_eq!(levels_to_cover(3), 2);
        assert_eq!(levels_to_cover(256), 8);
        assert_eq!(levels_to_cover(300), 9);
    }
}
