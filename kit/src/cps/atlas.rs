//! The levels side by side in one texture: level 0 at the origin, each coarser level stacked
//! in a column to its right. One texture lets one render pass light every level behind its
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
    /// The atlas of levels with these extents (level 0 first).
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
            let atlas = LevelAtlas::new(&extents);
            let rects: Vec<_> = (0..levels).map(|l| atlas.rect(l)).collect();
            for (i, &(x, y, w, h)) in rects.iter().enumerate() {
                assert!(x + w <= atlas.size.0 && y + h <= atlas.size.1, "{screen:?} level {i} outside");
                for &(x2, y2, w2, h2) in &rects[i + 1..] {
                    assert!(x + w <= x2 || x2 + w2 <= x || y + h <= y2 || y2 + h2 <= y, "{screen:?}: levels overlap");
                }
            }
            // About half again as wide as the screen, no taller than it (plus one texel a level).
            assert!(atlas.size.0 <= screen.0 + screen.0.div_ceil(2));
            assert!(atlas.size.1 <= screen.1 + levels as u32);
        }
    }
}
