//! The reconstruction's definition (`shaders/cbr/reconstruct.wgsl`) on the CPU, in f64, fed with
//! a pixel-rect scene's inputs: every sample's surface, depth, motion and colour follow from the
//! rects, the camera's pan and the sample placement's definition (`sampling::sampled_pixels`),
//! never from the GPU's frames. Where the formats or the rasteriser leave a decision open (an edge
//! within the sub-pixel precision of a sample centre, a motion within its rounding of a decision
//! boundary, a depth within its rounding of the tolerance) the model says the pixel cannot be
//! known rather than guess; the cases count such pixels and check the rest exactly.

use glam::Vec2;

use super::reconstruct::{Detection, PixelSource};
use super::sampling::sampled_pixels;
use super::scene::{CameraMotion, FLAT_CAMERA, PixelRect};

/// Vulkan, GL and WebGPU promise 4 sub-pixel bits. A quarter-resolution pixel is two full-resolution
/// pixels wide, so a vertex may snap by 1/16 of a full-resolution pixel; twice that, for the
/// vertex transform's own rounding, decides nothing within it.
const EDGE_PRECISION: f64 = 1.0 / 8.0;

/// Object motion is computed in f32 and stored in Rgba16Float (11 significant bits): within
/// 2^-10 of its length, plus 2^-10 pixel for the projections' rounding. Camera motion (f32
/// throughout) is held to the same bound.
fn motion_precision(length: f64) -> f64 {
    (1.0 + length) / 1024.0
}

/// Linear depth from a Depth32Float value through f32 arithmetic: within 2^-10 relative at the
/// flat scenes' distances (at 40 m, 1 ulp of depth is 2.4e-5 of the distance).
const DEPTH_PRECISION: f64 = 1.0 / 1024.0;

/// Mirrors of the shader's constants (reconstruct.wgsl): a quarter-resolution pixel in
/// full-resolution pixels, and the slack around the edge between two pixel centres.
const QUARTER_PIXEL: f64 = 2.0;
const EDGE_SLACK: f64 = 1.0 / 64.0;

/// The background colour of `shaders/common/lighting.wgsl`, where nothing was drawn.
const BACKGROUND: [f64; 3] = [0.02, 0.025, 0.035];

/// f16 keeps 11 significant bits: one rounding moves a value by at most 2^-11 of the largest
/// component involved. A sample's colour is rounded at most four times (the shaded sample, the
/// transparent blend or forward buffer, the composite, the reconstruction target): 2^-9.
fn stored_tolerance(peak: f64) -> f64 {
    peak.max(f64::from(f32::MIN_POSITIVE)) / 512.0
}

/// The fill averages its neighbours through compress_hdr / expand_hdr: an input error grows by
/// at most 2 through the compression and (1 + peak)^2 through the expansion.
fn fill_tolerance(peak: f64) -> f64 {
    stored_tolerance(peak) * (2.0 * (1.0 + peak) * (1.0 + peak) + 1.0)
}

/// Pixels per unit of tangent at the flat scenes' camera (`FLAT_CAMERA`): a point d metres away
/// and x metres aside lies `focal * x / d` pixels from the centre.
pub fn focal_pixels(screen: (u32, u32)) -> f64 {
    f64::from(screen.1) / 2.0 / (f64::from(FLAT_CAMERA.fov_y) / 2.0).tan()
}

/// What one sample of one frame shows, from the rects.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Shown {
    /// The opaque rect in front, by index.
    rect: usize,
    distance: f64,
    /// Whether that rect moves (its motion is written by the object-motion pass).
    moving: bool,
    /// Its screen motion since the previous frame (the rect's velocity plus the camera's pan).
    motion: [f64; 2],
    /// The opaque rect's albedo with the transparents in front composited over it.
    colour: [f64; 3],
    /// The largest colour component of any term, for the rounding bounds.
    peak: f64,
}

/// What the model expects of one reconstructed pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Expected {
    /// The source, and the colour within `tolerance` (absolute, per component).
    Known { source: PixelSource, colour: [f64; 3], tolerance: f64 },
    /// The formats leave it open; the reason says which input.
    Unknowable(&'static str),
}

/// Why a pixel cannot be known (metric keys): an input sample lies within the sub-pixel precision
/// of an edge; the motion lies within its rounding of a decision boundary; the depth difference
/// lies within its rounding of CSO's tolerance; two neighbours' surfaces lie within depth rounding
/// of each other.
pub const NEAR_AN_EDGE: &str = "open.edge_within_sub_pixel_precision";
pub const NEAR_A_DECISION: &str = "open.motion_within_rounding_of_a_decision";
pub const NEAR_THE_TOLERANCE: &str = "open.depth_within_rounding_of_the_tolerance";
pub const FRONT_TIE: &str = "open.front_neighbours_tied";

/// The reconstruction of a pixel-rect scene, frame by frame.
pub struct ReconstructionModel<'a> {
    rects: &'a [PixelRect],
    /// Per rect, its image's motion a frame: its own velocity, the camera's pan and the
    /// parallax of the camera's sideways travel at its distance.
    image_motion: Vec<[f64; 2]>,
    /// The transparent rects' indices, far to near (the order the scene draws them).
    transparents: Vec<usize>,
    screen: (u32, u32),
    detection: Detection,
    /// Whether the plan specialises for moving objects (any rect moves) and a moving camera.
    objects_move: bool,
    camera_moves: bool,
}

/// One frame's inputs: which pixels it and its predecessor sampled, and what every pixel centre
/// shows in each.
struct Frames {
    frame: u32,
    now: Vec<bool>,
    before: Vec<bool>,
    shown_now: Vec<Option<Shown>>,
    shown_before: Vec<Option<Shown>>,
}

/// A missing pixel's decision, for one motion.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Decision {
    Fill(PixelSource),
    History((i64, i64)),
}

impl<'a> ReconstructionModel<'a> {
    /// The model of `rects` seen by the flat scenes' camera (`FLAT_CAMERA`) moving by `camera`;
    /// its travel must be sideways (x, y): travel along the view changes a rect's image size.
    pub fn new(
        rects: &'a [PixelRect],
        camera: CameraMotion,
        screen: (u32, u32),
        detection: Detection,
    ) -> anyhow::Result<Self> {
        anyhow::ensure!(camera.travel.z == 0.0, "the model takes sideways camera travel only, not {}", camera.travel);
        // A pinhole at the origin: a point d metres away moves focal/d pixels a metre of travel,
        // against the travel horizontally and (y down on screen) along it vertically.
        let focal = focal_pixels(screen);
        let (travel, pan) = (camera.travel.as_dvec3(), camera.pan_pixels.as_dvec2());
        let image_motion = rects
            .iter()
            .map(|r| {
                let parallax = focal / f64::from(r.distance);
                let velocity = r.velocity.as_dvec2();
                [velocity.x + pan.x - travel.x * parallax, velocity.y + pan.y + travel.y * parallax]
            })
            .collect();
        let mut transparents: Vec<usize> = (0..rects.len()).filter(|&i| rects[i].is_transparent()).collect();
        transparents.sort_by(|&a, &b| rects[b].distance.total_cmp(&rects[a].distance));
        Ok(Self {
            rects,
            image_motion,
            transparents,
            screen,
            detection,
            objects_move: rects.iter().any(|r| r.velocity != Vec2::ZERO),
            camera_moves: camera != CameraMotion::default(),
        })
    }

    fn on_screen(&self, x: i64, y: i64) -> bool {
        (0..i64::from(self.screen.0)).contains(&x) && (0..i64::from(self.screen.1)).contains(&y)
    }

    fn index(&self, x: i64, y: i64) -> usize {
        (y * i64::from(self.screen.0) + x) as usize
    }

    /// Where rect `index`'s edges lie in `frame`, in full-resolution pixels.
    fn edges(&self, index: usize, frame: u32) -> [f64; 4] {
        let (rect, [mx, my]) = (&self.rects[index], self.image_motion[index]);
        let (dx, dy) = (mx * f64::from(frame), my * f64::from(frame));
        [f64::from(rect.x0) + dx, f64::from(rect.y0) + dy, f64::from(rect.x1) + dx, f64::from(rect.y1) + dy]
    }

    /// Whether rect `index` covers the centre of pixel (x, y) in `frame`; None within the
    /// rasteriser's precision of an edge.
    fn covers(&self, index: usize, frame: u32, x: i64, y: i64) -> Option<bool> {
        let [x0, y0, x1, y1] = self.edges(index, frame);
        let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
        let near = [x0, x1].iter().any(|e| (cx - e).abs() <= EDGE_PRECISION) && (y0..y1).contains(&cy)
            || [y0, y1].iter().any(|e| (cy - e).abs() <= EDGE_PRECISION) && (x0..x1).contains(&cx);
        let near_corner = [x0, x1].iter().any(|e| (cx - e).abs() <= EDGE_PRECISION)
            && [y0, y1].iter().any(|e| (cy - e).abs() <= EDGE_PRECISION);
        if near || near_corner {
            return None;
        }
        Some((x0..x1).contains(&cx) && (y0..y1).contains(&cy))
    }

    /// What frame `frame`'s sample of pixel (x, y) shows: the front-most opaque rect, the
    /// transparents in front of it composited far to near; None where an edge leaves it open.
    fn sample(&self, frame: u32, x: i64, y: i64) -> Option<Shown> {
        let mut front: Option<usize> = None;
        let mut nearest_open = f32::INFINITY;
        for (i, rect) in self.rects.iter().enumerate().filter(|(_, r)| !r.is_transparent()) {
            match self.covers(i, frame, x, y) {
                Some(true) if front.is_none_or(|f| rect.distance < self.rects[f].distance) => front = Some(i),
                None => nearest_open = nearest_open.min(rect.distance),
                _ => {}
            }
        }
        let rect = front?;
        let distance = self.rects[rect].distance;
        // An edge in front of the surface may or may not hide it.
        if nearest_open <= distance {
            return None;
        }
        let opaque = &self.rects[rect];
        let mut colour = opaque.albedo.map(f64::from);
        let mut peak = colour.iter().copied().fold(0.0, f64::max);
        for &index in self.transparents.iter().filter(|&&i| self.rects[i].distance < distance) {
            let over = &self.rects[index];
            match self.covers(index, frame, x, y) {
                None => return None,
                Some(false) => {}
                Some(true) => {
                    let a = f64::from(over.opacity);
                    for (c, albedo) in colour.iter_mut().zip(over.albedo) {
                        *c = *c * (1.0 - a) + f64::from(albedo) * a;
                    }
                    peak = over.albedo.iter().map(|&v| f64::from(v)).fold(peak, f64::max);
                }
            }
        }

        Some(Shown {
            rect,
            distance: f64::from(distance),
            moving: opaque.velocity != Vec2::ZERO,
            // Frame 0's previous frame is itself: its motion is zero.
            motion: if frame == 0 { [0.0, 0.0] } else { self.image_motion[rect] },
            colour,
            peak,
        })
    }

    /// What every pixel centre of `frame` shows (row-major), sampled or not.
    fn shown(&self, frame: u32) -> Vec<Option<Shown>> {
        let (w, h) = (i64::from(self.screen.0), i64::from(self.screen.1));
        (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).map(|(x, y)| self.sample(frame, x, y)).collect()
    }

    /// Every pixel of frame `frame` (row-major), the frame before it as its history.
    pub fn frame(&self, frame: u32) -> Vec<Expected> {
        let (w, h) = (i64::from(self.screen.0), i64::from(self.screen.1));
        let frames = Frames {
            frame,
            now: sampled_pixels(self.screen, frame % 2),
            before: sampled_pixels(self.screen, 1 - frame % 2),
            shown_now: self.shown(frame),
            shown_before: if frame == 0 { Vec::new() } else { self.shown(frame - 1) },
        };
        (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).map(|(x, y)| self.pixel(&frames, x, y)).collect()
    }

    fn pixel(&self, frames: &Frames, x: i64, y: i64) -> Expected {
        let (frame, now) = (frames.frame, &frames.now);
        if now[self.index(x, y)] {
            return match frames.shown_now[self.index(x, y)] {
                Some(s) => Expected::Known {
                    source: PixelSource::Current,
                    colour: s.colour,
                    tolerance: stored_tolerance(s.peak),
                },
                None => Expected::Unknowable(NEAR_AN_EDGE),
            };
        }
        // The cardinal neighbours frame N sampled, in the shader's order.
        let mut neighbours = Vec::new();
        for (nx, ny) in [(x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)] {
            if !self.on_screen(nx, ny) || !now[self.index(nx, ny)] {
                continue;
            }
            match frames.shown_now[self.index(nx, ny)] {
                Some(s) => neighbours.push(s),
                None => return Expected::Unknowable(NEAR_AN_EDGE),
            }
        }
        if neighbours.is_empty() {
            return Expected::Known {
                source: PixelSource::OffScreen,
                colour: BACKGROUND,
                tolerance: stored_tolerance(0.035),
            };
        }
        let peak = neighbours.iter().map(|s| s.peak).fold(0.0, f64::max);
        let compress = |c: [f64; 3]| c.map(|v| v / (1.0 + c[0].max(c[1]).max(c[2])));
        let mut sum = [0.0; 3];
        for s in &neighbours {
            for (total, v) in sum.iter_mut().zip(compress(s.colour)) {
                *total += v;
            }
        }
        let mean = sum.map(|v| v / neighbours.len() as f64);
        let fill = mean.map(|v| v / (1.0 - mean[0].max(mean[1]).max(mean[2])).max(1e-4));
        let filled = |source| Expected::Known { source, colour: fill, tolerance: fill_tolerance(peak) };
        if frame == 0 {
            return filled(PixelSource::FirstFrame);
        }

        // The front-most neighbour's motion stands in for this pixel's; the mean of the
        // neighbours' linear depths is what CSO compares with.
        let front = neighbours.iter().min_by(|a, b| a.distance.total_cmp(&b.distance)).expect("one at least");
        let tie = neighbours
            .iter()
            .any(|s| s.rect != front.rect && (s.distance - front.distance).abs() <= DEPTH_PRECISION * front.distance);
        if tie {
            return Expected::Unknowable(FRONT_TIE);
        }
        let mean_depth = neighbours.iter().map(|s| s.distance).sum::<f64>() / neighbours.len() as f64;
        let moving_object = self.objects_move && front.moving;
        let motion = if moving_object || self.camera_moves { front.motion } else { [0.0, 0.0] };

        // The decision must not change anywhere within the motion's rounding.
        let precision = motion_precision(motion[0].hypot(motion[1]));
        let mut decisions = Vec::new();
        // The motion and its eight neighbours one precision away on each axis (a 3×3 grid).
        let axis = |m: f64| [m, m - precision, m + precision];
        for perturbed in axis(motion[0]).into_iter().flat_map(|mx| axis(motion[1]).map(|my| [mx, my])) {
            match self.decide(frames, (x, y), perturbed, mean_depth, moving_object) {
                Ok(decision) => decisions.push(decision),
                Err(reason) => return Expected::Unknowable(reason),
            }
        }
        if decisions.iter().any(|d| *d != decisions[0]) {
            return Expected::Unknowable(NEAR_A_DECISION);
        }
        match decisions[0] {
            Decision::Fill(source) => filled(source),
            Decision::History((hx, hy)) => match frames.shown_before[self.index(hx, hy)] {
                Some(s) => Expected::Known {
                    source: PixelSource::History,
                    colour: s.colour,
                    tolerance: stored_tolerance(s.peak),
                },
                None => Expected::Unknowable(NEAR_AN_EDGE),
            },
        }
    }

    /// `missing` and `history_texel` of reconstruct.wgsl for pixel `p`, whose content moved by
    /// `motion` since frame N−1.
    fn decide(
        &self,
        frames: &Frames,
        p: (i64, i64),
        motion: [f64; 2],
        mean_depth: f64,
        moving_object: bool,
    ) -> Result<Decision, &'static str> {
        let (w, h) = (f64::from(self.screen.0), f64::from(self.screen.1));
        let (now, before) = (&frames.now, &frames.before);
        let then = [p.0 as f64 + 0.5 - motion[0], p.1 as f64 + 0.5 - motion[1]];
        if !(then[0] >= 0.0 && then[0] < w && then[1] >= 0.0 && then[1] < h) {
            return Ok(Decision::Fill(PixelSource::OffScreen));
        }
        let was = (then[0].floor() as i64, then[1].floor() as i64);
        let candidates = [was, (was.0 - 1, was.1), (was.0 + 1, was.1), (was.0, was.1 - 1), (was.0, was.1 + 1)];
        let history = candidates.into_iter().find(|&(cx, cy)| {
            let direct = (cx, cy) == was;
            let within = (cx as f64 + 0.5 - then[0]).abs() <= 0.5 + EDGE_SLACK
                && (cy as f64 + 0.5 - then[1]).abs() <= 0.5 + EDGE_SLACK;
            self.on_screen(cx, cy) && (direct || within) && before[self.index(cx, cy)]
        });
        let Some(history) = history else {
            // One of frame N's own pixels (the motion cancelled the jitter), or the gap column.
            let cancelled = now[self.index(was.0, was.1)];
            return Ok(Decision::Fill(if cancelled { PixelSource::JitterCancelled } else { PixelSource::OffScreen }));
        };
        let shown = frames.shown_before[self.index(history.0, history.1)].ok_or(NEAR_AN_EDGE)?;
        // History that moved with an object where this pixel does not (or the reverse) is stale.
        if self.objects_move && shown.moving != moving_object {
            return Ok(Decision::Fill(PixelSource::Disoccluded));
        }
        if motion[0].hypot(motion[1]) >= QUARTER_PIXEL - EDGE_SLACK {
            let Detection::Cso { tolerance } = self.detection else {
                return Ok(Decision::Fill(PixelSource::Assumed));
            };
            let margin = (shown.distance - mean_depth).abs() - f64::from(tolerance) * mean_depth;
            if margin.abs() <= DEPTH_PRECISION * mean_depth {
                return Err(NEAR_THE_TOLERANCE);
            }
            if margin > 0.0 {
                return Ok(Decision::Fill(PixelSource::Disoccluded));
            }
        }
        Ok(Decision::History(history))
    }
}

/// Each rule of reconstruct.wgsl on an 8×8 screen, the expected pixels worked out by hand from the
/// sample placement: phase 0 (even frames) samples the pixels with x + y even, phase 1 those with
/// x + y odd except the first column (the gap).
#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    const SCREEN: (u32, u32) = (8, 8);
    const B: [f32; 3] = [0.2, 0.4, 0.6];
    const R: [f32; 3] = [0.8, 0.1, 0.3];
    const CSO: Detection = Detection::Cso { tolerance: 0.05 };

    fn backdrop() -> PixelRect {
        PixelRect::opaque([-16, -16, 24, 24], 40.0, B)
    }

    fn pan(x: f32) -> CameraMotion {
        CameraMotion { pan_pixels: Vec2::new(x, 0.0), travel: Vec3::ZERO }
    }

    fn frame(rects: &[PixelRect], camera: CameraMotion, detection: Detection, frame: u32) -> Vec<Expected> {
        ReconstructionModel::new(rects, camera, SCREEN, detection).unwrap().frame(frame)
    }

    fn at(pixels: &[Expected], x: usize, y: usize) -> Expected {
        pixels[y * 8 + x]
    }

    fn source(pixels: &[Expected], x: usize, y: usize) -> Result<PixelSource, &'static str> {
        match at(pixels, x, y) {
            Expected::Known { source, .. } => Ok(source),
            Expected::Unknowable(reason) => Err(reason),
        }
    }

    fn f64s(colour: [f32; 3]) -> [f64; 3] {
        colour.map(f64::from)
    }

    /// The fill's definition: each neighbour compressed by 1 / (1 + its largest component), the
    /// mean expanded by 1 / (1 − its largest).
    fn fill(neighbours: &[[f32; 3]]) -> [f64; 3] {
        let compressed = neighbours.iter().map(|c| {
            let c = f64s(*c);
            c.map(|v| v / (1.0 + c[0].max(c[1]).max(c[2])))
        });
        let mut mean = [0.0; 3];
        for c in compressed {
            (0..3).for_each(|i| mean[i] += c[i] / neighbours.len() as f64);
        }
        mean.map(|v| v / (1.0 - mean[0].max(mean[1]).max(mean[2])))
    }

    fn assert_known(pixel: Expected, source: PixelSource, colour: [f64; 3], tolerance: f64) {
        let Expected::Known { source: s, colour: c, tolerance: t } = pixel else {
            panic!("{pixel:?}: expected {source:?}")
        };
        assert_eq!(s, source, "{pixel:?}");
        assert!((0..3).all(|i| (c[i] - colour[i]).abs() < 1e-12), "{c:?} against {colour:?}");
        // Relative: the albedos are f32.
        assert!((t - tolerance).abs() < 1e-6 * tolerance, "tolerance {t} against {tolerance}");
    }

    #[test]
    fn a_still_scene_shows_its_samples_fills_frame_zero_and_keeps_its_history() {
        let rects = [backdrop(), PixelRect::opaque([2, 2, 6, 6], 10.0, R)];
        let zero = frame(&rects, CameraMotion::default(), CSO, 0);
        // Sampled: the colour, within 4 f16 roundings of its largest component.
        assert_known(at(&zero, 2, 2), PixelSource::Current, f64s(R), 0.8 / 512.0);
        assert_known(at(&zero, 0, 0), PixelSource::Current, f64s(B), 0.6 / 512.0);
        // Missing in frame 0: its four neighbours (2,2), (4,2) and (3,3) red, (3,1) the backdrop,
        // filled; the fill's tolerance grows through the compression (2) and expansion (1.8²).
        let tolerance = 0.8 / 512.0 * (2.0 * 1.8 * 1.8 + 1.0);
        assert_known(at(&zero, 3, 2), PixelSource::FirstFrame, fill(&[R, R, B, R]), tolerance);
        assert_known(at(&zero, 1, 0), PixelSource::FirstFrame, f64s(B), 0.6 / 512.0 * (2.0 * 1.6 * 1.6 + 1.0));

        let one = frame(&rects, CameraMotion::default(), CSO, 1);
        assert_known(at(&one, 3, 2), PixelSource::Current, f64s(R), 0.8 / 512.0);
        // Missing in frame 1, sampled in frame 0 where nothing moved: the history.
        assert_known(at(&one, 2, 2), PixelSource::History, f64s(R), 0.8 / 512.0);
        assert_known(at(&one, 0, 2), PixelSource::History, f64s(B), 0.6 / 512.0);
        // The gap: no neighbour of frame 1 sampled, nothing in frame 0 either — the background.
        assert_known(at(&one, 0, 1), PixelSource::OffScreen, BACKGROUND, 0.035 / 512.0);
        assert_known(at(&one, 0, 5), PixelSource::OffScreen, BACKGROUND, 0.035 / 512.0);
    }

    /// A pan of one quarter-resolution pixel: the history is where the content was, judged by
    /// depth under CSO, assumed missing under ASO; history off the screen is filled.
    #[test]
    fn a_pan_takes_history_from_where_the_content_was() {
        let rects = [backdrop(), PixelRect::opaque([2, 2, 6, 6], 10.0, R)];
        let cso = frame(&rects, pan(2.0), CSO, 1);
        // (6, 4) and (7, 3) show the red rect now (at [4, 8)) among red neighbours; frame 0
        // showed it two pixels left.
        assert_known(at(&cso, 6, 4), PixelSource::History, f64s(R), 0.8 / 512.0);
        assert_known(at(&cso, 7, 3), PixelSource::History, f64s(R), 0.8 / 512.0);
        // At its left edge the neighbours' mean depth (40 + 3 · 10) / 4 is far from the history's.
        assert_eq!(source(&cso, 4, 4), Ok(PixelSource::Disoccluded));
        assert_eq!(source(&cso, 0, 2), Ok(PixelSource::OffScreen));
        assert_eq!(source(&cso, 1, 1), Ok(PixelSource::OffScreen));
        let aso = frame(&rects, pan(2.0), Detection::Aso, 1);
        assert_eq!(source(&aso, 6, 4), Ok(PixelSource::Assumed));
        assert_eq!(source(&aso, 0, 2), Ok(PixelSource::OffScreen));
        // Frame 0 is its own predecessor: no motion, the first frame's fill.
        assert_eq!(source(&frame(&rects, pan(2.0), CSO, 0), 3, 2), Ok(PixelSource::FirstFrame));
        // Frame 2 (phase 0 again, the rect at [6, 10)) takes its history from frame 1's samples.
        let two = frame(&rects, pan(2.0), CSO, 2);
        assert_known(at(&two, 6, 2), PixelSource::Current, f64s(R), 0.8 / 512.0);
        assert_known(at(&two, 7, 4), PixelSource::History, f64s(R), 0.8 / 512.0);
        assert_known(at(&two, 3, 2), PixelSource::History, f64s(B), 0.6 / 512.0);
    }

    /// A pan of one full-resolution pixel lands each missing pixel on one that frame N sampled:
    /// no pixel of frame N−1 lies within half a pixel (and the slack).
    #[test]
    fn a_one_pixel_pan_cancels_the_jitter() {
        let one = frame(&[backdrop()], pan(1.0), CSO, 1);
        for (x, y) in [(2, 2), (4, 4), (3, 5), (7, 1)] {
            assert_eq!(source(&one, x, y), Ok(PixelSource::JitterCancelled), "({x}, {y})");
        }
        // Half a pixel and a little: the neighbour within the slack; short of half: the texel.
        assert_eq!(source(&frame(&[backdrop()], pan(0.5 + 1.0 / 128.0), CSO, 1), 4, 4), Ok(PixelSource::History));
        assert_eq!(source(&frame(&[backdrop()], pan(0.25), CSO, 1), 4, 4), Ok(PixelSource::History));
    }

    /// Where the motion lies within its rounding of ASO's quarter-pixel threshold (2 − 1/64) the
    /// decision is open; clearly short of it, the history.
    #[test]
    fn a_motion_at_a_decision_boundary_leaves_the_pixel_open() {
        let rects = [backdrop()];
        assert_eq!(source(&frame(&rects, pan(2.0 - 1.0 / 64.0), Detection::Aso, 1), 4, 4), Err(NEAR_A_DECISION));
        assert_eq!(source(&frame(&rects, pan(2.0 - 1.0 / 16.0), Detection::Aso, 1), 4, 4), Ok(PixelSource::History));
        assert_eq!(source(&frame(&rects, pan(2.0 + 1.0 / 16.0), Detection::Aso, 1), 4, 4), Ok(PixelSource::Assumed));
    }

    /// An object moving two pixels right over a still backdrop: behind it the history moved with
    /// the object and this pixel does not (stale); on it, CSO compares the history's depth with
    /// the neighbours' mean (10 against (40 + 10 + 40 + 10) / 4 = 25).
    #[test]
    fn a_moving_object_leaves_stale_history_behind_and_is_judged_by_depth_on_it() {
        let rects = [backdrop(), PixelRect::opaque([2, 2, 4, 6], 10.0, R).moving(Vec2::new(2.0, 0.0))];
        let one = frame(&rects, CameraMotion::default(), CSO, 1);
        assert_known(
            at(&one, 2, 2),
            PixelSource::Disoccluded,
            fill(&[B, B, B, B]),
            0.6 / 512.0 * (2.0 * 1.6 * 1.6 + 1.0),
        );
        // |10 − 25| = 15 against 0.05 · 25: stale; against 0.9 · 25: kept.
        assert_eq!(source(&one, 4, 2), Ok(PixelSource::Disoccluded));
        let lenient = frame(&rects, CameraMotion::default(), Detection::Cso { tolerance: 0.9 }, 1);
        assert_known(at(&lenient, 4, 2), PixelSource::History, f64s(R), 0.8 / 512.0);
        // Still pixels far from it keep theirs.
        assert_known(at(&one, 6, 6), PixelSource::History, f64s(B), 0.6 / 512.0);
    }

    /// Pixel (6, 2) in frame 1 of a two-pixel pan: neighbours A (10 m) at (5, 2), (6, 1), (6, 3)
    /// and B (20 m) at (7, 2), mean 12.5; the history shows A: |10 − 12.5| = 2.5 = 0.2 · 12.5.
    #[test]
    fn a_depth_difference_at_the_tolerance_leaves_the_pixel_open() {
        let rects = [PixelRect::opaque([-16, -16, 5, 24], 10.0, R), PixelRect::opaque([5, -16, 24, 24], 20.0, B)];
        let with = |tolerance| source(&frame(&rects, pan(2.0), Detection::Cso { tolerance }, 1), 6, 2);
        assert_eq!(with(0.2), Err(NEAR_THE_TOLERANCE));
        // A margin of 0.005 m: within the depth's precision at 12.5 m (0.012).
        assert_eq!(with(0.1996), Err(NEAR_THE_TOLERANCE));
        assert_eq!(with(0.1), Ok(PixelSource::Disoccluded));
        assert_eq!(with(0.3), Ok(PixelSource::History));
    }

    /// Two surfaces at one depth meet at (4, 2): which one's motion stands in is open.
    #[test]
    fn neighbours_tied_in_depth_leave_the_pixel_open() {
        let rects = [PixelRect::opaque([-16, -16, 4, 24], 20.0, R), PixelRect::opaque([4, -16, 24, 24], 20.0, B)];
        assert_eq!(source(&frame(&rects, CameraMotion::default(), CSO, 1), 4, 2), Err(FRONT_TIE));
        // Frame 0 fills without motion, so no tie matters there.
        assert_eq!(source(&frame(&rects, CameraMotion::default(), CSO, 0), 4, 1), Ok(PixelSource::FirstFrame));
        let apart = [PixelRect::opaque([-16, -16, 4, 24], 20.0, R), PixelRect::opaque([4, -16, 24, 24], 21.0, B)];
        assert_eq!(source(&frame(&apart, CameraMotion::default(), CSO, 1), 4, 2), Ok(PixelSource::History));
    }

    /// An edge within 1/8 pixel of a sample centre (the 4 sub-pixel bits at quarter resolution)
    /// leaves what the sample shows open — unless a nearer surface hides it.
    #[test]
    fn an_edge_near_a_sample_centre_leaves_it_open_unless_hidden() {
        // Moving 0.45 a frame: in frame 1 the left edge lies at 2.45, 0.05 from column 2's centres.
        let rect = PixelRect::opaque([2, 2, 6, 6], 20.0, R).moving(Vec2::new(0.45, 0.0));
        let one = frame(&[backdrop(), rect], CameraMotion::default(), CSO, 1);
        assert_eq!(source(&one, 2, 3), Err(NEAR_AN_EDGE));
        // Missing, with that pixel among its neighbours.
        assert_eq!(source(&one, 2, 4), Err(NEAR_AN_EDGE));
        assert_eq!(source(&one, 3, 4), Ok(PixelSource::Current));
        // Under a nearer surface the open edge behind changes nothing.
        let cover = PixelRect::opaque([0, 0, 8, 8], 5.0, B);
        assert_eq!(
            source(&frame(&[backdrop(), rect, cover], CameraMotion::default(), CSO, 1), 2, 3),
            Ok(PixelSource::Current)
        );
        // Far (0.55) from the edge the sample is known; exactly on a corner, open.
        let alone = [rect];
        let model = ReconstructionModel::new(&alone, CameraMotion::default(), SCREEN, CSO).unwrap();
        assert_eq!(model.covers(0, 1, 3, 3), Some(true));
        assert_eq!(model.covers(0, 1, 1, 3), Some(false));
        assert_eq!(model.covers(0, 1, 2, 3), None);
        assert_eq!(model.covers(0, 1, 5, 3), Some(true));
        assert_eq!(model.covers(0, 1, 6, 3), None, "the right edge at 6.45");
        assert_eq!(model.covers(0, 1, 7, 3), Some(false));
        // The bottom edge: a rect moving down 0.4 a frame has it at 6.4 in frame 1.
        let down = PixelRect::opaque([2, 2, 6, 6], 20.0, R).moving(Vec2::new(0.0, 0.4));
        let down = [down];
        let model = ReconstructionModel::new(&down, CameraMotion::default(), SCREEN, CSO).unwrap();
        assert_eq!(model.covers(0, 1, 3, 6), None);
        assert_eq!(model.covers(0, 1, 3, 5), Some(true));
        assert_eq!(model.covers(0, 1, 3, 2), None, "the top edge at 2.4");
        assert_eq!(model.covers(0, 1, 3, 7), Some(false));
    }

    /// Transparents in front of the opaque surface composite over it far to near; one behind it
    /// adds nothing, and the rounding bound follows the largest albedo composited.
    #[test]
    fn transparents_in_front_composite_far_to_near() {
        let far = PixelRect::opaque([0, 0, 8, 8], 20.0, [0.0, 0.0, 1.0]).transparent(0.5);
        let near = PixelRect::opaque([0, 0, 8, 8], 10.0, [1.0, 0.0, 0.0]).transparent(0.25);
        let behind = PixelRect::opaque([0, 0, 8, 8], 50.0, [0.0, 1.0, 0.0]).transparent(0.5);
        let zero = frame(&[near, backdrop(), behind, far], CameraMotion::default(), CSO, 0);
        let b = f64s(B);
        let under = [b[0] * 0.5, b[1] * 0.5, b[2] * 0.5 + 0.5];
        let over = [under[0] * 0.75 + 0.25, under[1] * 0.75, under[2] * 0.75];
        assert_known(at(&zero, 2, 2), PixelSource::Current, over, 1.0 / 512.0);
        // A transparent whose edge is open in front of the surface leaves the sample open.
        let edge = PixelRect::opaque([2, 0, 8, 8], 10.0, R).transparent(0.5).moving(Vec2::new(0.45, 0.0));
        let one = frame(&[backdrop(), edge], CameraMotion::default(), CSO, 1);
        assert_eq!(source(&one, 2, 3), Err(NEAR_AN_EDGE));
        assert_eq!(source(&one, 4, 3), Ok(PixelSource::Current));
    }

    /// Each rect's image moves by its velocity, the pan, and the parallax of sideways travel
    /// (focal / distance pixels a metre: against the travel in x, along it in y, y down).
    #[test]
    fn images_move_by_velocity_pan_and_parallax() {
        let focal = focal_pixels(SCREEN);
        assert!((focal - 4.0 / 0.5f64.tan()).abs() < 1e-12);
        let rects = [PixelRect::opaque([1, 2, 3, 4], 8.0, R).moving(Vec2::new(0.5, -1.0))];
        let camera = CameraMotion { pan_pixels: Vec2::new(2.0, 3.0), travel: Vec3::new(0.25, 0.5, 0.0) };
        let model = ReconstructionModel::new(&rects, camera, SCREEN, CSO).unwrap();
        let [dx, dy] = [0.5 + 2.0 - 0.25 * focal / 8.0, -1.0 + 3.0 + 0.5 * focal / 8.0];
        let edges = model.edges(0, 3);
        let expected = [1.0 + 3.0 * dx, 2.0 + 3.0 * dy, 3.0 + 3.0 * dx, 4.0 + 3.0 * dy];
        assert!((0..4).all(|i| (edges[i] - expected[i]).abs() < 1e-9), "{edges:?} against {expected:?}");
        assert!(model.objects_move && model.camera_moves);
        let backdrop = [backdrop()];
        let still = ReconstructionModel::new(&backdrop, CameraMotion::default(), SCREEN, CSO).unwrap();
        assert!(!still.objects_move && !still.camera_moves);
        let forward = CameraMotion { pan_pixels: Vec2::ZERO, travel: Vec3::new(0.0, 0.0, 1.0) };
        assert!(ReconstructionModel::new(&rects, forward, SCREEN, CSO).is_err());
    }

    fn pan_xy(x: f32, y: f32) -> CameraMotion {
        CameraMotion { pan_pixels: Vec2::new(x, y), travel: Vec3::ZERO }
    }

    /// A sample centre just outside a rect's corner, within the edge precision of both edges, is
    /// open; one within the precision of one edge's line but beside the rect is not.
    #[test]
    fn a_sample_centre_beside_a_corner_is_open_only_near_both_edges() {
        // Moving 0.55 a frame both ways: in frame 1 the top-left corner lies at (2.55, 2.55).
        let rect = [PixelRect::opaque([2, 2, 6, 6], 20.0, R).moving(Vec2::new(0.55, 0.55))];
        let model = ReconstructionModel::new(&rect, CameraMotion::default(), SCREEN, CSO).unwrap();
        assert_eq!(model.covers(0, 1, 2, 2), None, "(2.5, 2.5): 0.05 outside both edges");
        assert_eq!(model.covers(0, 1, 2, 0), Some(false), "near the left edge's line only, far above");
        assert_eq!(model.covers(0, 1, 0, 2), Some(false), "near the top edge's line only, far left");
    }

    /// The front-most opaque rect shows, wherever it stands in the list; of two at one distance,
    /// the first drawn (the depth test passes on less).
    #[test]
    fn the_nearest_opaque_rect_shows_whatever_its_place_in_the_list() {
        let near_first = [PixelRect::opaque([0, 0, 8, 8], 10.0, R), backdrop()];
        let tied = [PixelRect::opaque([0, 0, 8, 8], 40.0, R), backdrop()];
        // A transparent at the opaque surface's own distance is not in front of it.
        let level = [backdrop(), PixelRect::opaque([0, 0, 8, 8], 40.0, R).transparent(0.5)];
        for (rects, shown, peak) in [(&near_first, R, 0.8), (&tied, R, 0.8), (&level, B, 0.6)] {
            let zero = frame(rects, CameraMotion::default(), CSO, 0);
            assert_known(at(&zero, 2, 2), PixelSource::Current, f64s(shown), peak / 512.0);
        }
    }

    /// Neighbours less than the depth's precision apart (2^-10 of the front one's distance) tie.
    #[test]
    fn neighbours_within_the_depth_precision_tie() {
        let rects = [PixelRect::opaque([-16, -16, 4, 24], 20.0, R), PixelRect::opaque([4, -16, 24, 24], 20.01, B)];
        assert_eq!(source(&frame(&rects, CameraMotion::default(), CSO, 1), 4, 2), Err(FRONT_TIE));
    }

    /// Vertical motion: history from where the content was above, off the screen at the top, and
    /// from the pixel above within the slack.
    #[test]
    fn a_vertical_pan_takes_history_from_above() {
        let one = |y_pan: f32, detection| frame(&[backdrop()], pan_xy(0.0, y_pan), detection, 1);
        // (3, 1) was at (3.5, -0.5): above the screen.
        assert_eq!(source(&one(2.0, CSO), 3, 1), Ok(PixelSource::OffScreen));
        assert_eq!(source(&one(2.0, CSO), 3, 5), Ok(PixelSource::History));
        // Up half a pixel and a little: (4, 4) was at (4.5, 5.008), in the unsampled row 5 of
        // column 4, within the slack of (4, 4) above it; the same to the left.
        assert_eq!(source(&one(-(0.5 + 1.0 / 128.0), CSO), 4, 4), Ok(PixelSource::History));
        let left = frame(&[backdrop()], pan(-(0.5 + 1.0 / 128.0)), CSO, 1);
        assert_eq!(source(&left, 4, 4), Ok(PixelSource::History));
        // Down half a pixel and a little: (4, 4) was at (4.5, 3.992), within the slack of (4, 4).
        assert_eq!(source(&one(0.5 + 1.0 / 128.0, CSO), 4, 4), Ok(PixelSource::History));
    }

    /// A diagonal motion one precision past ASO's threshold: the grid's inward diagonal point
    /// (√2 precisions in) crosses it, its inward axis points (1/√2 in) do not — open.
    #[test]
    fn a_diagonal_motion_near_the_threshold_is_open_through_the_diagonal_perturbation() {
        let threshold = QUARTER_PIXEL - EDGE_SLACK;
        let length = threshold + motion_precision(threshold);
        let a = (length / 2f64.sqrt()) as f32;
        assert_eq!(source(&frame(&[backdrop()], pan_xy(a, a), Detection::Aso, 1), 4, 4), Err(NEAR_A_DECISION));
        // Half a precision short of it along x: the outward point crosses.
        let short = (threshold - motion_precision(threshold) / 2.0) as f32;
        assert_eq!(source(&frame(&[backdrop()], pan(short), Detection::Aso, 1), 4, 4), Err(NEAR_A_DECISION));
        let clear = (threshold + 3.0 * motion_precision(threshold)) / 2f64.sqrt();
        assert_eq!(
            source(&frame(&[backdrop()], pan_xy(clear as f32, clear as f32), Detection::Aso, 1), 4, 4),
            Ok(PixelSource::Assumed)
        );
    }

    /// The rounding bounds: motion 2^-10 of (1 + length); a stored colour 2^-9 of its peak (never
    /// 0); the fill's growth through compression and expansion.
    #[test]
    fn rounding_bounds_follow_their_definitions() {
        assert_eq!(motion_precision(3.0), 4.0 / 1024.0);
        assert_eq!(stored_tolerance(2.0), 2.0 / 512.0);
        assert_eq!(stored_tolerance(0.0), f64::from(f32::MIN_POSITIVE) / 512.0);
        assert_eq!(fill_tolerance(1.0), 1.0 / 512.0 * 9.0);
    }
}
