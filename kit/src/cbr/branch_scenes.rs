//! Pixel-rect scenes that drive every branch of the reconstruction, each small enough for the
//! CPU model (`model.rs`) to know every sample: which rect, at what depth, moving how, in which
//! colour. Placed in fractions of the screen; motions are in full-resolution pixels a frame.

use glam::Vec2;

use super::reconstruct::PixelSource;
use glam::Vec3;

use super::model::focal_pixels;
use super::scene::{CameraMotion, CheckerboardScene, PixelRect, pixel_rect_scene};

/// One scene and the sources it is built to produce (checked, for every screen a case declares,
/// by the unit test below and again by the case).
pub struct BranchScene {
    pub name: &'static str,
    pub rects: Vec<PixelRect>,
    pub camera: CameraMotion,
    pub exercises: &'static [PixelSource],
}

impl BranchScene {
    pub fn scene(&self, screen: (u32, u32)) -> CheckerboardScene {
        pixel_rect_scene(self.name, screen, &self.rects, self.camera)
    }
}

/// A rect over the fraction [fx0, fx1) × [fy0, fy1) of `screen`, rounded to whole pixels.
fn place(screen: (u32, u32), [fx0, fy0, fx1, fy1]: [f32; 4], distance: f32, rgb: [u32; 3]) -> PixelRect {
    let (w, h) = (screen.0 as f32, screen.1 as f32);
    let corners = [(fx0 * w).round(), (fy0 * h).round(), (fx1 * w).round(), (fy1 * h).round()].map(|c| c as i32);
    PixelRect::opaque(corners, distance, rgb.map(|c| c as f32 / 255.0))
}

fn backdrop(screen: (u32, u32)) -> PixelRect {
    place(screen, [0.0, 0.0, 1.0, 1.0], 40.0, [40, 60, 90])
}

/// Motion just inside the edge slack past half a pixel (`EDGE_SLACK` = 1/64 in reconstruct.wgsl),
/// and clearly beyond it; both exact in f16.
const JUST_PAST_HALF: f32 = 0.5 + 1.0 / 128.0;
const WELL_PAST_HALF: f32 = 0.5 + 1.0 / 32.0;

fn pan(pixels: Vec2) -> CameraMotion {
    CameraMotion { pan_pixels: pixels, travel: Vec3::ZERO }
}

/// The scenes, for CSO at relative depth tolerance `tolerance`.
pub fn branch_scenes(screen: (u32, u32), tolerance: f32) -> Vec<BranchScene> {
    use PixelSource::*;
    // Sideways travel that moves a rect 12 m away by 2.5 full-resolution pixels a frame (more
    // than a quarter-resolution pixel, so even the farthest surface is judged by depth).
    let parallax_travel = (2.5 * 12.0 / focal_pixels(screen)) as f32;
    let at = |f: [f32; 4], distance, rgb| place(screen, f, distance, rgb);
    vec![
        // Two rects crossing over a static rect: the back one reappears behind the front one's
        // trailing edge where frame N−1 showed the front rect, moving too, so only CSO's depth
        // test can refuse that history. (4, 0) and (−2, −2) keep a pixel's checkerboard parity.
        BranchScene {
            name: "crossing",
            rects: vec![
                backdrop(screen),
                at([0.05, 0.6, 0.3, 0.95], 20.0, [200, 180, 40]),
                at([0.15, 0.3, 0.8, 0.8], 10.0, [30, 170, 60]).moving(Vec2::new(-2.0, -2.0)),
                at([0.3, 0.15, 0.55, 0.6], 5.0, [220, 50, 70]).moving(Vec2::new(4.0, 0.0)),
            ],
            camera: CameraMotion::default(),
            exercises: &[Current, History, FirstFrame, Disoccluded, Assumed, OffScreen],
        },
        // Moving rects partly behind a still one: the still rect's pixels must keep no motion
        // (the object-motion pass tests depth). (3, 0) lands on frame N's own pixels; (1, 1)
        // moves less than a quarter-resolution pixel, so its history needs no depth test.
        BranchScene {
            name: "under_still_occluder",
            rects: vec![
                backdrop(screen),
                at([0.1, 0.1, 0.55, 0.6], 20.0, [90, 200, 120]).moving(Vec2::new(3.0, 0.0)),
                at([0.5, 0.45, 0.9, 0.9], 15.0, [200, 90, 160]).moving(Vec2::new(1.0, 1.0)),
                at([0.3, 0.3, 0.7, 0.7], 8.0, [230, 220, 60]),
            ],
            camera: CameraMotion::default(),
            exercises: &[History, JitterCancelled, Disoccluded],
        },
        // A rect moving right passes two moving left; behind their trailing edges frame N−1
        // showed them where the back rect shows now. One is nearer by 0.8 of the tolerance (CSO
        // keeps that history), the other by 1.2 of it (CSO fills).
        BranchScene {
            name: "depth_tolerance",
            rects: vec![
                backdrop(screen),
                at([0.05, 0.05, 0.7, 0.95], 20.0, [70, 130, 210]).moving(Vec2::new(2.0, 0.0)),
                at([0.35, 0.1, 0.6, 0.45], 20.0 * (1.0 - 0.8 * tolerance), [240, 160, 40]).moving(Vec2::new(-2.0, 0.0)),
                at([0.35, 0.55, 0.6, 0.9], 20.0 * (1.0 - 1.2 * tolerance), [250, 80, 40]).moving(Vec2::new(-2.0, 0.0)),
            ],
            camera: CameraMotion::default(),
            exercises: &[History, Disoccluded, Assumed],
        },
        // Transparent rects over still and moving opaque ones, one partly behind a still rect:
        // the deferred path composites its forward buffer over the shading.
        BranchScene {
            name: "transparent",
            rects: vec![
                backdrop(screen),
                at([0.1, 0.2, 0.5, 0.8], 20.0, [200, 200, 200]).moving(Vec2::new(1.0, -1.0)),
                at([0.6, 0.1, 0.9, 0.5], 6.0, [60, 200, 90]),
                at([0.2, 0.1, 0.75, 0.6], 10.0, [255, 40, 40]).transparent(0.5),
                at([0.4, 0.4, 0.95, 0.95], 12.0, [40, 80, 255]).transparent(0.25),
            ],
            camera: CameraMotion::default(),
            exercises: &[Current, History, Disoccluded],
        },
        // Rects moving just past half a pixel (history from the neighbour within the slack),
        // well past it (lands on frame N's own pixels) and just short of it (the direct texel).
        BranchScene {
            name: "half_pixel_objects",
            rects: vec![
                backdrop(screen),
                at([0.1, 0.1, 0.45, 0.45], 20.0, [220, 120, 50]).moving(Vec2::new(JUST_PAST_HALF, 0.0)),
                at([0.55, 0.1, 0.9, 0.45], 20.0, [120, 220, 50]).moving(Vec2::new(WELL_PAST_HALF, 0.0)),
                at([0.1, 0.55, 0.45, 0.9], 20.0, [50, 120, 220]).moving(Vec2::new(0.0, 1.0 - WELL_PAST_HALF)),
            ],
            camera: CameraMotion::default(),
            exercises: &[History, JitterCancelled],
        },
        // The camera pans left just past half a pixel: every pixel's history is the neighbour
        // within the slack.
        BranchScene {
            name: "half_pixel_pan",
            rects: vec![
                backdrop(screen),
                at([0.2, 0.2, 0.6, 0.7], 15.0, [200, 60, 200]),
                at([0.5, 0.4, 0.85, 0.85], 7.0, [60, 200, 200]),
            ],
            camera: pan(Vec2::new(-JUST_PAST_HALF, 0.0)),
            exercises: &[History, OffScreen],
        },
        // The camera pans a quarter-resolution pixel while rects move: static content is judged
        // by depth, moving content by its own motion plus the pan.
        BranchScene {
            name: "camera_and_objects",
            rects: vec![
                backdrop(screen),
                at([0.1, 0.5, 0.4, 0.9], 18.0, [180, 180, 60]),
                at([0.3, 0.1, 0.7, 0.6], 9.0, [60, 90, 230]).moving(Vec2::new(-3.0, 1.0)),
                at([0.6, 0.4, 0.9, 0.8], 12.0, [230, 90, 60]).moving(Vec2::new(1.0, 0.0)),
            ],
            camera: pan(Vec2::new(2.0, 0.0)),
            exercises: &[History, JitterCancelled, Disoccluded, Assumed, OffScreen],
        },
        // The camera travels sideways: each rect's image moves by its own parallax (6 pixels a
        // frame at 5 m, 2.5 at the 12 m backdrop, wider than the screen), which the reconstruction
        // finds only through depth; behind the near rects' trailing edges the backdrop reappears
        // where frame N−1 showed them (CSO's depth test, every surface still).
        BranchScene {
            name: "parallax",
            rects: vec![
                at([-1.0, -0.2, 2.0, 1.2], 12.0, [40, 60, 90]),
                at([0.3, 0.2, 0.6, 0.8], 5.0, [230, 170, 60]),
                at([0.65, 0.3, 0.95, 0.7], 9.0, [90, 220, 140]),
            ],
            camera: CameraMotion { pan_pixels: Vec2::ZERO, travel: Vec3::new(parallax_travel, 0.0, 0.0) },
            exercises: &[History, Disoccluded, Assumed],
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cbr::Detection;
    use crate::cbr::model::{Expected, ReconstructionModel};

    /// Every scene produces each source it lists, known to the model, over frames 0..4 (CSO,
    /// and ASO for `Assumed`), at the sizes and tolerances `cbr.reconstruct.exact_sources`
    /// declares.
    #[test]
    fn every_scene_exercises_its_branches() {
        for screen in [(16, 16), (17, 23), (64, 48), (16, 150), (200, 16)] {
            for tolerance in [0.01, 0.05, 0.5] {
                for scene in branch_scenes(screen, tolerance) {
                    let mut seen = Vec::new();
                    for detection in [Detection::Cso { tolerance }, Detection::Aso] {
                        let model = ReconstructionModel::new(&scene.rects, scene.camera, screen, detection).unwrap();
                        for frame in 0..4 {
                            for expected in model.frame(frame) {
                                if let Expected::Known { source, .. } = expected {
                                    seen.push(source);
                                }
                            }
                        }
                    }
                    for source in scene.exercises {
                        assert!(
                            seen.contains(source),
                            "{} at {screen:?}, tolerance {tolerance}: no known {} pixel",
                            scene.name,
                            source.name()
                        );
                    }
                }
            }
        }
    }
}
