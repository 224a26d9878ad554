//! The levels side by side in one texture: the coarser levels in a row along the top (finest
//! first), level 0 under them (or, for a screen too tall for that, the coarser levels in a column
//! to the left of level 0). One texture lets one render pass light every level behind its stencil
//! (one draw a level, each with its viewport) and the composite read every level at a per-pixel
//! offset instead of a per-pixel mip level.
//!
//! Why the coarse levels come first in raster order: llvmpipe's threads take a pass's 64×64 tiles
//! one at a time in raster order (Mesa's `lp_scene_bin_iter_next`), so the pass ends on whatever
//! its last tiles hold. Around a fovea a coarse level's lit texels crowd into a few tiles, level
//! 0's spread over more; ending on level 0's smaller jobs leaves less of one thread waiting for
//! the other (`fragkit bench cps`, r = 24, interleaved: lighting 17.4–17.8 ms against 17.9–18.0 ms
//! with the coarse levels in a column to the right of level 0; 20.8 ms with level 1 at that
//! column's foot; docs/benchmarks.md).

use serde::Serialize;

#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct LevelAtlas {
    /// Texels of the whole atlas.
    pub size: (u32, u32),
    /// Where level l's texels start.
    pub origins: Vec<(u32, u32)>,
    /// Texels of level l that hold data.
    pub extents: Vec<(u32, u32)>,
}

impl LevelAtlas {
    /// The atlas of levels with these extents (level 0 first): the coarser levels in a row along
    /// the top, level 0 under them.
    pub fn new(extents: &[(u32, u32)]) -> Self {
        let (w0, h0) = extents.first().copied().unwrap_or((1, 1));
        let row_height = extents.get(1).map_or(0, |e| e.1);
        let mut origins = vec![(0, row_height)];
        let mut x = 0;
        for &(w, _) in extents.iter().skip(1) {
            origins.push((x, 0));
            x += w;
        }
        Self { size: (w0.max(x).max(1), (h0 + row_height).max(1)), origins, extents: extents.to_vec() }
    }

    /// The same levels with the coarser ones in a column to the left of level 0.
    fn left(extents: &[(u32, u32)]) -> Self {
        let transposed: Vec<(u32, u32)> = extents.iter().map(|&(w, h)| (h, w)).collect();
        let atlas = Self::new(&transposed);
        Self {
            size: (atlas.size.1, atlas.size.0),
            origins: atlas.origins.iter().map(|&(x, y)| (y, x)).collect(),
            extents: extents.to_vec(),
        }
    }

    /// The layout that fits a `max`×`max` texture (the row on top where both do), or None.
    pub fn fitting(extents: &[(u32, u32)], max: u32) -> Option<Self> {
        [Self::new(extents), Self::left(extents)].into_iter().find(|a| a.size.0 <= max && a.size.1 <= max)
    }

    /// Level `level`'s rect: x, y, width, height.
    pub fn rect(&self, level: usize) -> (u32, u32, u32, u32) {
        let ((x, y), (w, h)) = (self.origins[level], self.extents[level]);
        (x, y, w, h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_lie_apart_and_inside_the_atlas() {
        for screen in [(1u32, 1u32), (2, 1), (640, 360), (257, 131), (3, 1000)] {
            let levels = 9;
            let extents: Vec<(u32, u32)> =
                (0..levels).map(|l| (screen.0.div_ceil(1 << l), screen.1.div_ceil(1 << l))).collect();
            for atlas in [LevelAtlas::new(&extents), LevelAtlas::left(&extents)] {
                let rects: Vec<_> = (0..levels).map(|l| atlas.rect(l)).collect();
                for (i, &(x, y, w, h)) in rects.iter().enumerate() {
                    assert_eq!(((x, y), (w, h)), (atlas.origins[i], extents[i]), "{screen:?} level {i}");
                    assert!(x + w <= atlas.size.0 && y + h <= atlas.size.1, "{screen:?} level {i} outside");
                    for &(x2, y2, w2, h2) in &rects[i + 1..] {
                        assert!(
                            x + w <= x2 || x2 + w2 <= x || y + h <= y2 || y2 + h2 <= y,
                            "{screen:?}: levels overlap"
                        );
                    }
                }
            }
            // The row on top: no wider than the screen (plus one texel a level), half as tall
            // again.
            let top = LevelAtlas::new(&extents);
            assert!(top.size.0 <= screen.0 + levels as u32);
            assert!(top.size.1 <= screen.1 + screen.1.div_ceil(2));
            // A screen too tall for that puts them in a column to the left.
            let tall = [(64u32, 12000u32), (32, 6000)];
            assert_eq!(LevelAtlas::fitting(&tall, 16384).unwrap().origins, [(32, 0), (0, 0)]);
            assert_eq!(LevelAtlas::fitting(&tall, 20000).unwrap().origins, [(0, 6000), (0, 0)]);
        }
    }
}
