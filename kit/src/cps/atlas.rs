//! The levels side by side in one texture: level 0 at the origin, each coarser level stacked
//! in a column to its right (or, for a screen too wide for that, in a row below it). One texture lets one render pass light every level behind its
//! stencil (one draw a level, each with its viewport) and the composite read every level at a
//! per-pixel offset instead of a per-pixel mip level.

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
    /// The atlas of levels with these extents (level 0 first): the coarser levels in a column
    /// to the right of level 0.
    pub fn new(extents: &[(u32, u32)]) -> Self {
        let (w0, h0) = extents.first().copied().unwrap_or((1, 1));
        let mut origins = vec![(0, 0)];
        let mut y = 0;
        for &(_, h) in extents.iter().skip(1) {
            origins.push((w0, y));
            y += h;
        }
        let width = w0 + extents.get(1).map_or(0, |e| e.0);
        Self { size: (width.max(1), h0.max(y).max(1)), origins, extents: extents.to_vec() }
    }

    /// The same levels with the coarser ones in a row below level 0.
    fn below(extents: &[(u32, u32)]) -> Self {
        let transposed: Vec<(u32, u32)> = extents.iter().map(|&(w, h)| (h, w)).collect();
        let atlas = Self::new(&transposed);
        Self {
            size: (atlas.size.1, atlas.size.0),
            origins: atlas.origins.iter().map(|&(x, y)| (y, x)).collect(),
            extents: extents.to_vec(),
        }
    }

    /// The layout that fits a `max`×`max` texture (to the right where both do), or None.
    pub fn fitting(extents: &[(u32, u32)], max: u32) -> Option<Self> {
        [Self::new(extents), Self::below(extents)].into_iter().find(|a| a.size.0 <= max && a.size.1 <= max)
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
            for atlas in [LevelAtlas::new(&extents), LevelAtlas::below(&extents)] {
                let rects: Vec<_> = (0..levels).map(|l| atlas.rect(l)).collect();
                for (i, &(x, y, w, h)) in rects.iter().enumerate() {
                    assert!(x + w <= atlas.size.0 && y + h <= atlas.size.1, "{screen:?} level {i} outside");
                    for &(x2, y2, w2, h2) in &rects[i + 1..] {
                        assert!(
                            x + w <= x2 || x2 + w2 <= x || y + h <= y2 || y2 + h2 <= y,
                            "{screen:?}: levels overlap"
                        );
                    }
                }
            }
            // To the right: about half again as wide as the screen, no taller than it (plus one
            // texel a level).
            let right = LevelAtlas::new(&extents);
            assert!(right.size.0 <= screen.0 + screen.0.div_ceil(2));
            assert!(right.size.1 <= screen.1 + levels as u32);
            // A screen too wide for that goes below.
            let wide = [(12000u32, 64u32), (6000, 32)];
            assert_eq!(LevelAtlas::fitting(&wide, 16384).unwrap().origins[1], (0, 64));
            assert_eq!(LevelAtlas::fitting(&wide, 20000).unwrap().origins[1], (12000, 0));
        }
    }
}
