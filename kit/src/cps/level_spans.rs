//! Under the foveated policy, what each level's stencil marks and lighting draw: rectangles over
//! the texels the marks can mark (common/foveation.wgsl's `foveated_block_has_level`), in bands of
//! atlas rows, instead of the box around the level's disk (`Plan::level_bounds`), whose hole and
//! corners hold a third of its texels. The stencil still decides which texels are lit: a span may
//! hold more than the marks mark, never less. (Where the adapter has no early stencil rejection,
//! the lighting shader also skips the lights of a texel the rule leaves out: cps/lighting.wgsl.)

use std::ops::Range;

use super::config::LodPolicy;
use super::plan::Plan;
use crate::gpu::Gpu;
use crate::rects::{Rect, RectBatch};

/// The spans' grain in atlas texels, rows and columns: coarser spans shade more rejected texels,
/// finer ones draw more rects. Measured with `fragkit bench cps --matrix lavapipe,swiftshader`
/// (r = 24, share of reachable on SwiftShader, two invocations each): 2 → 62 %, 16 → 82 / 82 %,
/// 64 → 77 / 75 %, the whole bounds → 74 / 76 %; lavapipe, which rejects early, 72–90 % at every
/// grain (docs/benchmarks.md).
const BAND: u32 = 16;

/// How far the spans widen a block's squared distances: 2^-16 of them, 16 times the marks' own
/// widening (2^-20, `MARK_WIDENING`), which already exceeds the GPU's f32 error many times over.
const SPAN_WIDENING: f64 = 1.0 / 65536.0;

/// Every level's spans, in atlas texels.
pub(super) struct LevelSpans {
    levels: Vec<Vec<Rect>>,
}

/// One batch of every level's spans (the level in each instance's red, as the marks read it)
/// and where each level's instances lie in it.
#[derive(Clone)]
pub(super) struct SpanBatch {
    batch: RectBatch,
    ranges: Vec<Range<u32>>,
}

impl LevelSpans {
    /// The spans of a plan whose levels come from the foveation.
    pub(super) fn foveated(plan: &Plan, policy: &LodPolicy) -> Self {
        let LodPolicy::Foveated { focus, inner_radius } = policy else {
            unreachable!("levels come from the foveation only under the foveated policy")
        };
        // The focus as the GPU has it (`LodPolicy::foveation_words`), the boundaries exact.
        let focus = (f64::from(focus.0 * plan.screen.0 as f32), f64::from(focus.1 * plan.screen.1 as f32));
        let radius = f64::from(inner_radius.max(1e-3));
        let squared_boundaries: Vec<f64> =
            (1..=plan.top_level).map(|k| (radius * (f64::from(1u32 << k) - 1.0)).powi(2)).collect();
        let rule = MarkRule { screen: plan.screen, focus, squared_boundaries };
        Self { levels: (0..plan.levels() as usize).map(|level| level_spans(plan, &rule, level)).collect() }
    }

    /// The spans of `level`.
    #[cfg(test)]
    fn level(&self, level: usize) -> &[Rect] {
        &self.levels[level]
    }

    /// Every level's spans in one batch on the atlas.
    pub(super) fn batch(&self, gpu: &Gpu, atlas_size: (u32, u32)) -> SpanBatch {
        let mut instances = Vec::new();
        let mut ranges = Vec::new();
        for (level, rects) in self.levels.iter().enumerate() {
            let start = instances.len() as u32;
            instances.extend(rects.iter().map(|&rect| (rect, [level as f32, 0.0, 0.0, 0.0])));
            ranges.push(start..instances.len() as u32);
        }
        SpanBatch { batch: RectBatch::new(gpu, atlas_size, &instances), ranges }
    }
}

impl SpanBatch {
    /// Every level's spans (the viewport: the whole atlas).
    pub(super) fn draw_all(&self, pass: &mut wgpu::RenderPass<'_>) {
        self.batch.draw(pass, ..);
    }

    /// Level `level`'s spans (the viewport: the whole atlas).
    pub(super) fn draw_level(&self, pass: &mut wgpu::RenderPass<'_>, level: usize) {
        self.batch.draw(pass, self.ranges[level].clone());
    }
}

/// The marks' rule, in f64 and widened: which levels a block of pixels can be marked for.
struct MarkRule {
    screen: (u32, u32),
    /// In pixels.
    focus: (f64, f64),
    /// R_k² for k = 1..=top.
    squared_boundaries: Vec<f64>,
}

impl MarkRule {
    fn level_of_squared_distance(&self, squared: f64) -> u32 {
        self.squared_boundaries.iter().filter(|&&boundary| squared >= boundary).count() as u32
    }

    /// Whether the marks can mark texel (x, y) of `level`: as the shader, from the block's
    /// nearest pixel centre and its farther corner's, but both corners taken (the shader's f32
    /// choice between them may go either way at a tie) and the distances widened.
    fn may_mark(&self, level: u32, x: u32, y: u32) -> bool {
        let span = |texel: u32, extent: u32, focus: f64| {
            let first = texel << level;
            let last = (first + (1 << level) - 1).min(extent - 1);
            let nearest = focus.floor().clamp(f64::from(first), f64::from(last)) + 0.5 - focus;
            let farthest = (f64::from(first) + 0.5 - focus).abs().max((f64::from(last) + 0.5 - focus).abs());
            (nearest * nearest, farthest * farthest)
        };
        let (near_x, far_x) = span(x, self.screen.0, self.focus.0);
        let (near_y, far_y) = span(y, self.screen.1, self.focus.1);
        let finest = self.level_of_squared_distance((near_x + near_y) * (1.0 - SPAN_WIDENING));
        let coarsest = self.level_of_squared_distance((far_x + far_y) * (1.0 + SPAN_WIDENING));
        (finest..=coarsest).contains(&level)
    }
}

/// Level `level`'s spans: for each band of `BAND` atlas rows, the runs of texels any of its rows
/// may mark, widened to whole `BAND`-texel columns and clipped to the level's bounds; a band with
/// the same runs as the one above extends its rects.
fn level_spans(plan: &Plan, rule: &MarkRule, level: usize) -> Vec<Rect> {
    let (ox, oy, _, _) = plan.atlas.rect(level);
    let (bx, by, bw, bh) = plan.level_bounds[level];
    let mut rects: Vec<Rect> = Vec::new();
    let mut above: Vec<(u32, u32)> = Vec::new();
    let mut above_first = 0;
    let band = BAND;
    // Bands of `band` atlas rows on the atlas's grid, from the one holding the bounds' top.
    for pair in ((oy + by) / band * band..oy + by + bh).step_by(band as usize) {
        let rows = pair.max(oy + by) - oy..(pair + band).min(oy + by + bh) - oy;
        let marked: Vec<bool> =
            (bx..bx + bw).map(|x| rows.clone().any(|y| rule.may_mark(level as u32, x, y))).collect();
        let mut runs: Vec<(u32, u32)> = Vec::new();
        let mut x = 0;
        while x < marked.len() {
            if !marked[x] {
                x += 1;
                continue;
            }
            let start = x;
            while x < marked.len() && marked[x] {
                x += 1;
            }
            let left = ((ox + bx + start as u32) / band * band).max(ox + bx);
            let right = ((ox + bx + x as u32).next_multiple_of(band)).min(ox + bx + bw);
            match runs.last_mut() {
                Some(last) if last.1 >= left => last.1 = right,
                _ => runs.push((left, right)),
            }
        }
        let (top, bottom) = (pair.max(oy + by), (pair + band).min(oy + by + bh));
        if runs == above && !runs.is_empty() {
            for rect in &mut rects[above_first..] {
                rect.y1 = bottom as f32;
            }
        } else {
            above_first = rects.len();
            rects.extend(runs.iter().map(|&(x0, x1)| Rect::new(x0 as f32, top as f32, x1 as f32, bottom as f32)));
            above = runs;
        }
    }
    rects
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cps::atlas::LevelAtlas;

    /// The marks shader's decision in f32, with the GPU's rounding errors allowed for by a
    /// widening `error` times the shader's own (2^-20).
    fn shader_marks(
        screen: (u32, u32),
        focus: (f32, f32),
        words: &[u32],
        level: u32,
        texel: (u32, u32),
        error: f32,
    ) -> bool {
        let boundaries: Vec<f32> = words[4..].iter().map(|&w| f32::from_bits(w)).collect();
        let level_of = |squared: f32| boundaries.iter().filter(|&&b| squared >= b).count() as u32;
        let focus = (focus.0 * screen.0 as f32, focus.1 * screen.1 as f32);
        let first = (texel.0 << level, texel.1 << level);
        let last = ((first.0 + (1 << level) - 1).min(screen.0 - 1), (first.1 + (1 << level) - 1).min(screen.1 - 1));
        let nearest = (
            focus.0.floor().clamp(first.0 as f32, last.0 as f32),
            focus.1.floor().clamp(first.1 as f32, last.1 as f32),
        );
        let far = |first: u32, last: u32, focus: f32| {
            if last as f32 + 0.5 - focus > focus - (first as f32 + 0.5) { last as f32 } else { first as f32 }
        };
        let farthest = (far(first.0, last.0, focus.0), far(first.1, last.1, focus.1));
        let squared = |p: (f32, f32)| (p.0 + 0.5 - focus.0).powi(2) + (p.1 + 0.5 - focus.1).powi(2);
        let widening = 9.536_743e-7 * error;
        let finest = level_of(squared(nearest) * (1.0 - widening));
        let coarsest = level_of(squared(farthest) * (1.0 + widening));
        (finest..=coarsest).contains(&level)
    }

    #[test]
    fn every_texel_the_marks_can_mark_lies_in_a_span_of_its_level() {
        for screen in [(640u32, 360u32), (37, 23), (1, 1), (300, 6), (5, 200), (257, 131)] {
            let top = screen.0.max(screen.1).next_power_of_two().trailing_zeros().min(8);
            for inner_radius in [1.0, 6.0, 24.0, 100.0] {
                for focus in [(0.5, 0.5), (0.0, 0.0), (1.0, 1.0), (0.3, 0.9), (0.501, 0.499)] {
                    let policy = LodPolicy::Foveated { focus, inner_radius };
                    let extents: Vec<(u32, u32)> =
                        (0..=top).map(|l| (screen.0.div_ceil(1 << l), screen.1.div_ceil(1 << l))).collect();
                    let plan = Plan::for_test(screen, top, LevelAtlas::new(&extents), &policy);
                    let spans = LevelSpans::foveated(&plan, &policy);
                    let words = policy.foveation_words(screen, top);
                    let mut spanned = 0u64;
                    let mut boxed = 0u64;
                    for level in 0..=top {
                        let (ox, oy, w, h) = plan.atlas.rect(level as usize);
                        for rect in spans.level(level as usize) {
                            assert!(
                                rect.x0 >= ox as f32 && rect.y0 >= oy as f32,
                                "{screen:?} level {level}: {rect:?} outside its rect"
                            );
                            assert!(
                                rect.x1 <= (ox + w) as f32 && rect.y1 <= (oy + h) as f32,
                                "{screen:?} level {level}: {rect:?} outside its rect"
                            );
                            spanned += ((rect.x1 - rect.x0) * (rect.y1 - rect.y0)) as u64;
                        }
                        let (_, _, bw, bh) = plan.level_bounds[level as usize];
                        boxed += u64::from(bw * bh);
                        for y in 0..h {
                            for x in 0..w {
                                let centre = ((ox + x) as f32 + 0.5, (oy + y) as f32 + 0.5);
                                let covered = spans.level(level as usize).iter().any(|r| r.covers(centre.0, centre.1));
                                // Four times the shader's widening stands for the GPU's errors.
                                assert!(
                                    covered || !shader_marks(screen, focus, &words, level, (x, y), 4.0),
                                    "{screen:?} r {inner_radius} focus {focus:?}: level {level} texel ({x}, {y}) may be marked outside every span"
                                );
                            }
                        }
                    }
                    // Around a ring wide enough to hold bands, the spans leave out its hole.
                    if inner_radius >= 24.0 && screen == (640, 360) {
                        assert!(spanned < boxed, "{spanned} texels spanned, {boxed} in the levels' bounds");
                    }
                }
            }
        }
    }

    /// The rule read plainly: a texel of `level` may be marked exactly when some pixel centre of
    /// its block (clipped to the screen) lies at that level's distance from the focus, level k
    /// from R_k = r (2^k − 1) on. Checked on every texel of seeded screens and foci, away from
    /// blocks with a centre within 2^-14 (relative, squared) of a boundary, where the rule's
    /// widening may add the level across it.
    #[test]
    fn a_texel_may_be_marked_for_the_levels_of_its_blocks_pixel_centres() {
        let mut rng = crate::scene::hash::SeededRng::new(16);
        let mut checked = 0;
        for _ in 0..40 {
            let screen = (rng.range(1, 90), rng.range(1, 90));
            let focus = (f64::from(rng.range(0, 1000)) / 10.0 - 5.0, f64::from(rng.range(0, 1000)) / 10.0 - 5.0);
            let radius = 0.5 + 12.0 * f64::from(rng.unit());
            let top = 4;
            let squared_boundaries: Vec<f64> =
                (1..=top).map(|k| (radius * f64::from((1u32 << k) - 1)).powi(2)).collect();
            let rule = MarkRule { screen, focus, squared_boundaries: squared_boundaries.clone() };
            for level in 0..=top {
                let side = 1u32 << level;
                for ty in 0..screen.1.div_ceil(side) {
                    for tx in 0..screen.0.div_ceil(side) {
                        let centres: Vec<f64> = (ty * side..((ty + 1) * side).min(screen.1))
                            .flat_map(|y| {
                                (tx * side..((tx + 1) * side).min(screen.0)).map(move |x| {
                                    (f64::from(x) + 0.5 - focus.0).powi(2) + (f64::from(y) + 0.5 - focus.1).powi(2)
                                })
                            })
                            .collect();
                        let near_a_boundary = centres
                            .iter()
                            .any(|&d| squared_boundaries.iter().any(|&b| (d - b).abs() <= b * 2f64.powi(-14)));
                        if near_a_boundary {
                            continue;
                        }
                        let level_at = |d: f64| squared_boundaries.iter().filter(|&&b| d >= b).count() as u32;
                        let levels: Vec<u32> = centres.iter().map(|&d| level_at(d)).collect();
                        let (lo, hi) = (*levels.iter().min().unwrap(), *levels.iter().max().unwrap());
                        assert_eq!(
                            rule.may_mark(level, tx, ty),
                            (lo..=hi).contains(&level),
                            "{screen:?} focus {focus:?} r {radius}: level {level} texel ({tx}, {ty}) spans levels {lo}..={hi}"
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 20_000, "{checked} texels checked");
    }

    /// A block whose farthest pixel centre lies just inside a boundary, within the marks' own
    /// widening (2^-20), may be marked for the coarser level, so it is spanned for it; and one
    /// whose nearest lies just past a boundary, for the finer level. On an 8×1 screen with the
    /// focus at (0, 0.5), level 1's texel 1 covers pixels 2 and 3, whose centres lie at squared
    /// distances 6.25 and 12.25.
    #[test]
    fn a_block_the_marks_widen_across_a_boundary_is_spanned_for_that_level() {
        let marks_widening = f64::from(2f32.powi(-20));
        let boundary = 12.25 * (1.0 + 2f64.powi(-21));
        assert!(12.25 * (1.0 + marks_widening) >= boundary, "the marks' widening reaches R_1");
        let rule = MarkRule { screen: (8, 1), focus: (0.0, 0.5), squared_boundaries: vec![boundary, 1e6] };
        assert!(rule.may_mark(1, 1, 0), "level 1's texel 1, its far centre 2^-21 inside R_1");
        assert!(!rule.may_mark(2, 0, 0), "level 2's texel 0: pixels 0–3 lie within R_2");
        let boundary = 6.25 * (1.0 - 2f64.powi(-21));
        assert!(6.25 * (1.0 - marks_widening) < boundary, "the marks' widening reaches back past R_1");
        let rule = MarkRule { screen: (8, 1), focus: (0.0, 0.5), squared_boundaries: vec![boundary] };
        assert!(rule.may_mark(0, 2, 0), "level 0's texel 2, 2^-21 past R_1");
    }

    /// The spans are as tight as their grain allows: their edges on the `BAND` grid or the
    /// level's bounds; none overlapping, none that could have extended another (same columns,
    /// one ending where the other starts); every `BAND`-square block of the grid inside one holds
    /// a texel the marks may mark.
    #[test]
    fn spans_hold_no_band_block_the_marks_cannot_mark() {
        for screen in [(640u32, 360u32), (257, 131), (300, 70)] {
            let top = screen.0.max(screen.1).next_power_of_two().trailing_zeros().min(8);
            for (inner_radius, focus) in
                [(24.0, (0.5, 0.5)), (6.0, (0.3, 0.9)), (100.0, (0.0, 0.0)), (40.0, (0.7, 0.4))]
            {
                let policy = LodPolicy::Foveated { focus, inner_radius };
                let extents: Vec<(u32, u32)> =
                    (0..=top).map(|l| (screen.0.div_ceil(1 << l), screen.1.div_ceil(1 << l))).collect();
                let plan = Plan::for_test(screen, top, LevelAtlas::new(&extents), &policy);
                let spans = LevelSpans::foveated(&plan, &policy);
                let focus_px = (f64::from(focus.0 * screen.0 as f32), f64::from(focus.1 * screen.1 as f32));
                let radius = f64::from(inner_radius);
                let squared_boundaries = (1..=top).map(|k| (radius * f64::from((1u32 << k) - 1)).powi(2)).collect();
                let rule = MarkRule { screen, focus: focus_px, squared_boundaries };
                for level in 0..=top as usize {
                    let (ox, oy, _, _) = plan.atlas.rect(level);
                    let (bx, by, bw, bh) = plan.level_bounds[level];
                    let on_grid =
                        |v: f32, lo: u32, hi: u32| (v as u32).is_multiple_of(BAND) || v as u32 == lo || v as u32 == hi;
                    let rects = spans.level(level);
                    for (i, r) in rects.iter().enumerate() {
                        let what = format!("{screen:?} r {inner_radius} focus {focus:?} level {level}: {r:?}");
                        assert!(on_grid(r.x0, ox + bx, ox + bx + bw) && on_grid(r.x1, ox + bx, ox + bx + bw), "{what}");
                        assert!(on_grid(r.y0, oy + by, oy + by + bh) && on_grid(r.y1, oy + by, oy + by + bh), "{what}");
                        for other in &rects[i + 1..] {
                            let overlap = r.x0 < other.x1 && other.x0 < r.x1 && r.y0 < other.y1 && other.y0 < r.y1;
                            assert!(!overlap, "{what} overlaps {other:?}");
                            let stacked =
                                (r.x0, r.x1) == (other.x0, other.x1) && (r.y1 == other.y0 || other.y1 == r.y0);
                            assert!(!stacked, "{what} could have extended {other:?}");
                        }
                        let (x0, y0, x1, y1) = (r.x0 as u32, r.y0 as u32, r.x1 as u32, r.y1 as u32);
                        let mut block_y = y0 / BAND * BAND;
                        while block_y < y1 {
                            let rows = block_y.max(y0)..(block_y + BAND).min(y1);
                            let mut block_x = x0 / BAND * BAND;
                            while block_x < x1 {
                                let columns = block_x.max(x0)..(block_x + BAND).min(x1);
                                let markable = rows
                                    .clone()
                                    .any(|y| columns.clone().any(|x| rule.may_mark(level as u32, x - ox, y - oy)));
                                assert!(markable, "{what}: block at ({block_x}, {block_y}) holds no markable texel");
                                block_x += BAND;
                            }
                            block_y += BAND;
                        }
                    }
                }
            }
        }
    }
}
