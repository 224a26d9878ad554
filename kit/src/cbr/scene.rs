//! Checkerboard scenes: geometry in draws (opaque first, transparents back to front), each draw
//! optionally moving at a constant velocity, a camera that may pan (an image-space lens shift, so
//! every pixel moves by exactly the same amount) or travel, and the lights. Two kinds: flat-shaded
//! fronto-parallel rects whose edges lie on full-resolution pixel boundaries (so checkerboarding
//! can match full resolution exactly), and the lit, textured corridor with glass panes.

use std::ops::Range;

use glam::{Mat4, Vec2, Vec3};

use crate::scene::corridor::{Camera, Light, SceneVertex, corridor};
use crate::scene::hash::SeededRng;

/// One vertex as `shaders/cbr/scene.wgsl` reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct CheckerboardVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    /// Albedo and specular weight (opacity for transparent draws).
    pub albedo: [f32; 4],
    /// Negative: unlit, flat albedo.
    pub shininess: f32,
    /// Albedo-map repeats per metre; 0: untextured.
    pub texture_scale: f32,
}

/// A range of vertices drawn with one model matrix.
#[derive(Clone, Debug, PartialEq)]
pub struct Draw {
    pub vertices: Range<u32>,
    pub transparent: bool,
    /// World units a frame; zero for static geometry.
    pub velocity: Vec3,
}

/// How the camera moves each frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CameraMotion {
    /// Image-space pan in full-resolution pixels (x right, y down): a lens shift, so every
    /// pixel moves by exactly this much.
    pub pan_pixels: Vec2,
    /// World-space travel of eye and target (parallax, disocclusion).
    pub travel: Vec3,
}

#[derive(Clone, Debug)]
pub struct CheckerboardScene {
    pub name: String,
    pub vertices: Vec<CheckerboardVertex>,
    pub draws: Vec<Draw>,
    pub lights: Vec<Light>,
    pub camera: Camera,
    pub camera_motion: CameraMotion,
}

/// What one frame's passes need from the scene.
#[derive(Clone, Debug)]
pub struct FrameView {
    /// Unjittered full-resolution view-projection of this frame and of the one before.
    pub full_from_world: Mat4,
    pub previous_full_from_world: Mat4,
    pub eye: Vec3,
    /// Per draw: model matrix now and one frame earlier.
    pub models: Vec<(Mat4, Mat4)>,
}

impl CheckerboardScene {
    pub fn camera_moves(&self) -> bool {
        self.camera_motion != CameraMotion::default()
    }

    pub fn objects_move(&self) -> bool {
        self.draws.iter().any(|d| d.velocity != Vec3::ZERO)
    }

    pub fn has_transparents(&self) -> bool {
        self.draws.iter().any(|d| d.transparent)
    }

    fn view_projection(&self, frame: u32, (width, height): (u32, u32)) -> Mat4 {
        let travel = self.camera_motion.travel * frame as f32;
        let camera = Camera { eye: self.camera.eye + travel, target: self.camera.target + travel, ..self.camera };
        let pan = self.camera_motion.pan_pixels * frame as f32;
        let shift = Mat4::from_translation(Vec3::new(2.0 * pan.x / width as f32, -2.0 * pan.y / height as f32, 0.0));
        shift * camera.view_projection(width as f32 / height as f32)
    }

    /// Frame `frame` at full resolution `screen` (frame 0's previous frame is itself).
    pub fn frame_view(&self, frame: u32, screen: (u32, u32)) -> FrameView {
        let previous = frame.saturating_sub(1);
        let model = |f: u32, draw: &Draw| Mat4::from_translation(draw.velocity * f as f32);
        FrameView {
            full_from_world: self.view_projection(frame, screen),
            previous_full_from_world: self.view_projection(previous, screen),
            eye: self.camera.eye + self.camera_motion.travel * frame as f32,
            models: self.draws.iter().map(|d| (model(frame, d), model(previous, d))).collect(),
        }
    }
}

/// How a corridor sequence moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    Static,
    /// Image-space pan, full-resolution pixels a frame (1.0 horizontally cancels the jitter).
    Pan(Vec2),
    /// The camera travels sideways, metres a frame: parallax and disocclusion.
    Strafe(f32),
    /// A box crosses the corridor, metres a frame, in front of a static camera.
    Object(f32),
}

impl Motion {
    /// Parses a [`Motion::name`]: `static`, `pan_<x>x<y>`, `strafe_<metres>`, `object_<metres>`.
    pub fn parse(name: &str) -> anyhow::Result<Self> {
        let number = |text: &str| {
            text.parse::<f32>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| anyhow::anyhow!("motion {name:?}: {text:?} is not a finite number"))
        };
        if name == "static" {
            return Ok(Self::Static);
        }
        if let Some(pan) = name.strip_prefix("pan_") {
            let (x, y) = pan.split_once('x').ok_or_else(|| anyhow::anyhow!("motion {name:?}: expected pan_<x>x<y>"))?;
            return Ok(Self::Pan(Vec2::new(number(x)?, number(y)?)));
        }
        if let Some(metres) = name.strip_prefix("strafe_") {
            return Ok(Self::Strafe(number(metres)?));
        }
        if let Some(metres) = name.strip_prefix("object_") {
            return Ok(Self::Object(number(metres)?));
        }
        anyhow::bail!("unknown motion {name:?}; expected static, pan_<x>x<y>, strafe_<metres> or object_<metres>")
    }

    pub fn name(self) -> String {
        match self {
            Self::Static => "static".into(),
            Self::Pan(p) => format!("pan_{}x{}", p.x, p.y),
            Self::Strafe(m) => format!("strafe_{m}"),
            Self::Object(m) => format!("object_{m}"),
        }
    }
}

fn quad(corners: [Vec3; 4], normal: Vec3, albedo: [f32; 4], shininess: f32) -> Vec<CheckerboardVertex> {
    let [a, b, c, d] = corners;
    [a, b, c, a, c, d]
        .iter()
        .map(|p| CheckerboardVertex {
            position: p.to_array(),
            normal: normal.to_array(),
            albedo,
            shininess,
            texture_scale: 0.0,
        })
        .collect()
}

fn push_draw(scene: &mut CheckerboardScene, vertices: Vec<CheckerboardVertex>, transparent: bool, velocity: Vec3) {
    let start = scene.vertices.len() as u32;
    scene.vertices.extend(vertices);
    scene.draws.push(Draw { vertices: start..scene.vertices.len() as u32, transparent, velocity });
}

/// A flat-shaded rect facing the camera, in full-resolution pixels of frame 0 (half-open
/// [x0, x1) × [y0, y1)), at `distance` metres, moving `velocity` pixels a frame (any real
/// amount; the camera's pan comes on top), opaque or (`opacity` < 1) transparent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelRect {
    pub x0: i32,
    pub y0: i32,
    pub x1: i32,
    pub y1: i32,
    pub distance: f32,
    pub velocity: Vec2,
    /// Multiples of 1/255: exact in every target format.
    pub albedo: [f32; 3],
    /// 1: opaque; below 1, drawn as a transparent (premultiplied over) after the opaque rects.
    pub opacity: f32,
}

impl PixelRect {
    /// An opaque, static rect.
    pub fn opaque(corners: [i32; 4], distance: f32, albedo: [f32; 3]) -> Self {
        let [x0, y0, x1, y1] = corners;
        Self { x0, y0, x1, y1, distance, velocity: Vec2::ZERO, albedo, opacity: 1.0 }
    }

    pub fn moving(self, velocity: Vec2) -> Self {
        Self { velocity, ..self }
    }

    pub fn transparent(self, opacity: f32) -> Self {
        Self { opacity, ..self }
    }

    pub fn is_transparent(&self) -> bool {
        self.opacity < 1.0
    }
}

/// The camera of the flat-rect scenes: at the origin looking down −z.
pub const FLAT_CAMERA: Camera = Camera { eye: Vec3::ZERO, target: Vec3::NEG_Z, fov_y: 1.0, near: 0.1, far: 60.0 };

/// A scene of `rects` (front-most opaque wins by distance, transparents composited over it far to
/// near) seen on `screen` by [`FLAT_CAMERA`] moving by `camera_motion` a frame; each rect's world
/// velocity moves it exactly its pixel velocity.
pub fn pixel_rect_scene(
    name: &str,
    screen: (u32, u32),
    rects: &[PixelRect],
    camera_motion: CameraMotion,
) -> CheckerboardScene {
    let camera = FLAT_CAMERA;
    let mut scene = CheckerboardScene {
        name: name.into(),
        vertices: Vec::new(),
        draws: Vec::new(),
        lights: Vec::new(),
        camera,
        camera_motion,
    };
    let world_from_clip = scene.view_projection(0, screen).inverse();
    let (width, height) = (screen.0 as f32, screen.1 as f32);
    let depth_of = |distance: f32| camera.far * (distance - camera.near) / (distance * (camera.far - camera.near));
    let corner = |x: f32, y: f32, distance: f32| {
        let ndc = Vec3::new(x / width * 2.0 - 1.0, 1.0 - y / height * 2.0, depth_of(distance));
        world_from_clip.project_point3(ndc)
    };
    // Opaque rects first, front to back (as a renderer orders them for early depth rejection: a
    // pass that ignores its depth test then shows the farther rect), then the transparents back
    // to front.
    let mut order: Vec<&PixelRect> = rects.iter().collect();
    order.sort_by(|a, b| {
        a.is_transparent().cmp(&b.is_transparent()).then(if a.is_transparent() {
            b.distance.total_cmp(&a.distance)
        } else {
            a.distance.total_cmp(&b.distance)
        })
    });
    for r in order {
        let (x0, y0, x1, y1) = (r.x0 as f32, r.y0 as f32, r.x1 as f32, r.y1 as f32);
        // Counter-clockwise seen from the camera: bottom-left, bottom-right, top-right, top-left.
        let corners = [
            corner(x0, y1, r.distance),
            corner(x1, y1, r.distance),
            corner(x1, y0, r.distance),
            corner(x0, y0, r.distance),
        ];
        // At a fixed distance the pixel-to-world map is affine, so this is exact up to rounding.
        let velocity = corner(r.velocity.x, r.velocity.y, r.distance) - corner(0.0, 0.0, r.distance);
        let albedo = [r.albedo[0], r.albedo[1], r.albedo[2], r.opacity];
        push_draw(&mut scene, quad(corners, Vec3::Z, albedo, -1.0), r.is_transparent(), velocity);
    }
    scene
}

/// Flat-shaded rects facing the camera, corners on full-resolution pixel corners of `screen`,
/// overlapping at seeded depths; colours are multiples of 1/255 (exact in every target format).
pub fn flat_rects(screen: (u32, u32), seed: u32, pan_pixels: Vec2) -> CheckerboardScene {
    let camera_motion = CameraMotion { pan_pixels, travel: Vec3::ZERO };
    pixel_rect_scene("flat_rects", screen, &seeded_rects(screen, seed), camera_motion)
}

/// The rects of [`flat_rects`]: a backdrop at 40 m, then twelve smaller ones from 2 to 32 m.
pub fn seeded_rects(screen: (u32, u32), seed: u32) -> Vec<PixelRect> {
    let mut rng = SeededRng::new(seed);
    // A backdrop over the whole screen, then smaller rects in front.
    let mut places = vec![(0, 0, screen.0, screen.1, 40.0)];
    for _ in 0..12 {
        let (x0, y0) = (rng.range(0, screen.0), rng.range(0, screen.1));
        let (x1, y1) = (rng.range(x0 + 1, screen.0 + 1), rng.range(y0 + 1, screen.1 + 1));
        places.push((x0, y0, x1, y1, 2.0 + 30.0 * rng.unit()));
    }
    places
        .into_iter()
        .map(|(x0, y0, x1, y1, distance)| {
            let albedo = [rng.range(0, 256), rng.range(0, 256), rng.range(0, 256)].map(|c| c as f32 / 255.0);
            PixelRect::opaque([x0, y0, x1, y1].map(|c| c as i32), distance, albedo)
        })
        .collect()
}

/// Albedo-map repeats per metre on the corridor's floor and walls.
const FLOOR_TEXTURE_SCALE: f32 = 1.0;
const WALL_TEXTURE_SCALE: f32 = 0.5;

/// The lit corridor (`scene::corridor`) with a textured floor and walls, two glass panes and,
/// for [`Motion::Object`], a box crossing it.
pub fn textured_corridor(seed: u32, light_count: u32, motion: Motion) -> CheckerboardScene {
    let base = corridor(seed, light_count);
    let mut scene = CheckerboardScene {
        name: format!("corridor_{}", motion.name()),
        vertices: Vec::new(),
        draws: Vec::new(),
        lights: base.lights,
        camera: base.camera,
        camera_motion: match motion {
            Motion::Pan(pixels) => CameraMotion { pan_pixels: pixels, travel: Vec3::ZERO },
            Motion::Strafe(metres) => CameraMotion { pan_pixels: Vec2::ZERO, travel: Vec3::X * metres },
            Motion::Static | Motion::Object(_) => CameraMotion::default(),
        },
    };
    // The corridor's first four boxes (36 vertices each) are floor, ceiling and the two walls.
    let to_vertex = |(i, v): (usize, &SceneVertex)| CheckerboardVertex {
        position: v.position,
        normal: v.normal,
        albedo: v.albedo,
        shininess: v.shininess,
        texture_scale: match i / 36 {
            0 => FLOOR_TEXTURE_SCALE,
            2 | 3 => WALL_TEXTURE_SCALE,
            _ => 0.0,
        },
    };
    push_draw(&mut scene, base.vertices.iter().enumerate().map(to_vertex).collect(), false, Vec3::ZERO);
    if let Motion::Object(metres) = motion {
        let mut cube = Vec::new();
        let half = 0.45;
        let centre = Vec3::new(-1.8, 1.3, -2.0);
        for (normal, u, v) in
            [(Vec3::Z, Vec3::X, Vec3::Y), (Vec3::X, Vec3::NEG_Z, Vec3::Y), (Vec3::NEG_X, Vec3::Z, Vec3::Y)]
        {
            let c = centre + normal * half;
            let corners = [c - (u + v) * half, c + (u - v) * half, c + (u + v) * half, c - (u - v) * half];
            cube.extend(quad(corners, normal, [0.85, 0.3, 0.2, 0.5], 24.0));
        }
        push_draw(&mut scene, cube, false, Vec3::X * metres);
    }
    // Glass panes across the corridor, the farther first (drawn back to front).
    for (z, tint) in [(-9.0, [0.3, 0.6, 0.9, 0.35]), (-3.0, [0.9, 0.7, 0.3, 0.3])] {
        let corners =
            [Vec3::new(-1.2, 0.2, z), Vec3::new(1.0, 0.2, z), Vec3::new(1.0, 2.2, z), Vec3::new(-1.2, 2.2, z)];
        push_draw(&mut scene, quad(corners, Vec3::Z, tint, 16.0), true, Vec3::ZERO);
    }
    scene
}

/// Side of the albedo map's top level.
pub const ALBEDO_MAP_SIZE: u32 = 128;

/// The albedo map's mip chain (Rgba8Unorm texels, top level first): stone tiles with mortar
/// lines and seeded grain, each level the 2×2 box filter of the one above.
pub fn albedo_map_levels() -> Vec<Vec<[u8; 4]>> {
    let size = ALBEDO_MAP_SIZE;
    let mut top = Vec::with_capacity((size * size) as usize);
    for y in 0..size {
        for x in 0..size {
            let mortar = x % 32 < 2 || (y + if (x / 32) % 2 == 0 { 0 } else { 16 }) % 32 < 2;
            let grain = crate::scene::hash::hash_unit(y * size + x);
            let tile = crate::scene::hash::hash_unit(0x9e37 + (y / 32) * 8 + x / 32);
            let value = if mortar { 0.35 } else { 0.65 + 0.25 * tile + 0.1 * grain };
            let byte = |scale: f32| (value * scale * 255.0).round().clamp(0.0, 255.0) as u8;
            top.push([byte(1.0), byte(0.95), byte(0.85), 255]);
        }
    }
    let mut levels = vec![top];
    let mut side = size;
    while side > 1 {
        let above = levels.last().expect("a level");
        let half = side / 2;
        let mut level = Vec::with_capacity((half * half) as usize);
        for y in 0..half {
            for x in 0..half {
                let texel = |dx: u32, dy: u32| above[((2 * y + dy) * side + 2 * x + dx) as usize];
                let mut mean = [0u8; 4];
                for (c, m) in mean.iter_mut().enumerate() {
                    let sum: u32 =
                        [texel(0, 0), texel(1, 0), texel(0, 1), texel(1, 1)].iter().map(|t| u32::from(t[c])).sum();
                    *m = ((sum + 2) / 4) as u8;
                }
                level.push(mean);
            }
        }
        levels.push(level);
        side = half;
    }
    levels
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_rect_corners_land_on_pixel_corners() {
        let screen = (37, 23);
        let scene = flat_rects(screen, 7, Vec2::ZERO);
        let view = scene.frame_view(0, screen);
        for v in &scene.vertices {
            let ndc = view.full_from_world.project_point3(Vec3::from_array(v.position));
            let (x, y) = ((ndc.x + 1.0) * 0.5 * screen.0 as f32, (1.0 - ndc.y) * 0.5 * screen.1 as f32);
            assert!((x - x.round()).abs() < 1e-3 && (y - y.round()).abs() < 1e-3, "corner at ({x}, {y})");
        }
    }

    #[test]
    fn a_pan_moves_every_point_by_the_same_pixels() {
        let screen = (64, 48);
        let scene = flat_rects(screen, 1, Vec2::new(1.0, 0.5));
        let (before, after) = (scene.frame_view(2, screen), scene.frame_view(3, screen));
        for v in &scene.vertices {
            let p = Vec3::from_array(v.position);
            let shift = (after.full_from_world.project_point3(p) - before.full_from_world.project_point3(p)).truncate()
                * Vec2::new(screen.0 as f32 / 2.0, -(screen.1 as f32) / 2.0);
            assert!((shift - Vec2::new(1.0, 0.5)).length() < 1e-3, "moved {shift}");
        }
    }

    #[test]
    fn motions_parse_back_from_their_names() {
        for motion in [Motion::Static, Motion::Pan(Vec2::new(0.5, -1.0)), Motion::Strafe(0.1), Motion::Object(0.25)] {
            assert_eq!(Motion::parse(&motion.name()).unwrap(), motion);
        }
        for bad in ["", "pan_1", "pan_ax1", "strafe_inf", "object_NaN", "spin_1"] {
            assert!(Motion::parse(bad).is_err(), "{bad:?} parsed");
        }
    }

    #[test]
    fn the_albedo_map_has_a_full_mip_chain() {
        let levels = albedo_map_levels();
        assert_eq!(levels.len(), ALBEDO_MAP_SIZE.trailing_zeros() as usize + 1);
        assert_eq!(levels.last().unwrap().len(), 1);
        // Each level is the rounded mean of the 2×2 texels above it.
        for (level, above) in levels.iter().skip(1).zip(&levels) {
            let side = (level.len() as f64).sqrt() as usize;
            assert_eq!(side * side * 4, above.len());
            for (i, texel) in level.iter().enumerate() {
                let (x, y) = (i % side, i / side);
                for c in 0..4 {
                    let sum: f64 = [(0, 0), (1, 0), (0, 1), (1, 1)]
                        .iter()
                        .map(|(dx, dy)| f64::from(above[(2 * y + dy) * 2 * side + 2 * x + dx][c]))
                        .sum();
                    assert_eq!(f64::from(texel[c]), (sum / 4.0 + 0.5).floor(), "level of side {side}, texel {i}");
                }
            }
        }
    }

    /// The top level: mortar lines two texels wide every 32, offset by half a tile in every other
    /// column of tiles, at 0.35; a tile's texel at 0.65 + 0.25 tile + 0.1 grain; the channels
    /// scaled by (1, 0.95, 0.85), opaque.
    #[test]
    fn the_albedo_map_is_tiles_with_mortar_and_grain() {
        let top = &albedo_map_levels()[0];
        let texel = |x: u32, y: u32| top[(y * ALBEDO_MAP_SIZE + x) as usize];
        let byte = |value: f32, scale: f32| (value * scale * 255.0).round() as u8;
        let mortar = [byte(0.35, 1.0), byte(0.35, 0.95), byte(0.35, 0.85), 255];
        for (x, y) in [(0, 5), (1, 5), (32, 5), (5, 0), (5, 1), (5, 33), (40, 16), (40, 17), (100, 48)] {
            assert_eq!(texel(x, y), mortar, "({x}, {y}) is mortar");
        }
        for (x, y) in [(2, 5), (5, 2), (40, 0), (40, 14), (8, 16), (31, 31), (40, 40), (100, 40), (70, 100)] {
            let grain = crate::scene::hash::hash_unit(y * ALBEDO_MAP_SIZE + x);
            let tile = crate::scene::hash::hash_unit(0x9e37 + (y / 32) * 8 + x / 32);
            let value = 0.65 + 0.25 * tile + 0.1 * grain;
            assert_eq!(texel(x, y), [byte(value, 1.0), byte(value, 0.95), byte(value, 0.85), 255], "({x}, {y})");
        }
    }

    /// Projects a point to full-resolution pixels (y down) and its distance from the camera.
    fn to_pixels(view: &FrameView, screen: (u32, u32), p: Vec3) -> (f32, f32) {
        let ndc = view.full_from_world.project_point3(p);
        ((ndc.x + 1.0) * 0.5 * screen.0 as f32, (1.0 - ndc.y) * 0.5 * screen.1 as f32)
    }

    /// Each rect is one draw of two counter-clockwise triangles over exactly its pixel rect at
    /// its distance, facing the camera, unlit (shininess −1), its opacity in albedo's w; opaque
    /// draws front to back, then transparents back to front; a rect's velocity moves it that
    /// many pixels a frame.
    #[test]
    fn a_pixel_rect_scene_draws_each_rect_where_and_as_it_is_given() {
        let screen = (40, 30);
        let rects = [
            PixelRect::opaque([0, 0, 40, 30], 30.0, [0.1, 0.2, 0.3]),
            PixelRect::opaque([2, 3, 12, 9], 5.0, [0.4, 0.5, 0.6]).moving(Vec2::new(1.5, -2.0)),
            PixelRect::opaque([20, 4, 30, 20], 8.0, [0.7, 0.8, 0.9]).transparent(0.25),
            PixelRect::opaque([22, 6, 24, 8], 12.0, [0.3, 0.3, 0.3]).transparent(0.5),
            PixelRect::opaque([5, 5, 6, 6], 20.0, [1.0, 0.0, 0.0]),
        ];
        let scene = pixel_rect_scene("test", screen, &rects, CameraMotion::default());
        assert_eq!(scene.name, "test");
        // Drawn: opaque 5 m, 20 m, 30 m; transparent 12 m, 8 m.
        let order = [1, 4, 0, 3, 2];
        assert_eq!(scene.draws.len(), 5);
        let view = scene.frame_view(0, screen);
        for (draw, &r) in scene.draws.iter().zip(&order) {
            let rect = &rects[r];
            assert_eq!(draw.vertices.len(), 6);
            assert_eq!(draw.transparent, rect.is_transparent());
            let vertices = &scene.vertices[draw.vertices.start as usize..draw.vertices.end as usize];
            let (x0, y0, x1, y1) = (rect.x0 as f32, rect.y0 as f32, rect.x1 as f32, rect.y1 as f32);
            // Bottom-left, bottom-right, top-right twice as two triangles (a, b, c), (a, c, d).
            let expected = [(x0, y1), (x1, y1), (x1, y0), (x0, y1), (x1, y0), (x0, y0)];
            for (v, (ex, ey)) in vertices.iter().zip(expected) {
                let p = Vec3::from_array(v.position);
                let (x, y) = to_pixels(&view, screen, p);
                assert!((x - ex).abs() < 1e-3 && (y - ey).abs() < 1e-3, "rect {r}: ({x}, {y}) against ({ex}, {ey})");
                assert!((-p.z - rect.distance).abs() < 1e-4 * rect.distance, "rect {r} at {}", -p.z);
                assert_eq!(v.normal, [0.0, 0.0, 1.0]);
                assert_eq!(v.albedo, [rect.albedo[0], rect.albedo[1], rect.albedo[2], rect.opacity]);
                assert_eq!((v.shininess, v.texture_scale), (-1.0, 0.0));
            }
            // The velocity in world units moves the rect's image by its pixel velocity.
            let p = Vec3::from_array(vertices[0].position);
            let (ax, ay) = to_pixels(&view, screen, p);
            let (bx, by) = to_pixels(&view, screen, p + draw.velocity * 2.0);
            let moved = Vec2::new(bx - ax, by - ay);
            assert!((moved - rect.velocity * 2.0).length() < 1e-3, "rect {r} moved {moved}");
        }
        assert!(scene.objects_move() && scene.has_transparents() && !scene.camera_moves());
        let still = pixel_rect_scene("still", screen, &rects[..1], CameraMotion::default());
        assert!(!still.objects_move() && !still.has_transparents());
    }

    /// Frame N's view: the camera travelled N times its travel and panned N times its pan; each
    /// draw moved N times its velocity, and the previous view is frame N − 1's (frame 0's own).
    #[test]
    fn a_frame_view_moves_camera_and_draws_by_the_frame_number() {
        let screen = (64, 32);
        let rects = [PixelRect::opaque([8, 8, 16, 16], 10.0, [0.5; 3]).moving(Vec2::new(2.0, 1.0))];
        let camera_motion = CameraMotion { pan_pixels: Vec2::new(1.0, -0.5), travel: Vec3::new(0.2, -0.1, 0.0) };
        let scene = pixel_rect_scene("test", screen, &rects, camera_motion);
        assert!(scene.camera_moves());
        let (zero, three) = (scene.frame_view(0, screen), scene.frame_view(3, screen));
        assert_eq!(zero.previous_full_from_world, zero.full_from_world);
        assert_eq!(three.previous_full_from_world, scene.frame_view(2, screen).full_from_world);
        assert_eq!(three.eye, Vec3::new(0.6, -0.3, 0.0) * 1.0);
        let velocity = scene.draws[0].velocity;
        assert_eq!(three.models[0].0, Mat4::from_translation(velocity * 3.0));
        assert_eq!(three.models[0].1, Mat4::from_translation(velocity * 2.0));
        assert_eq!(zero.models[0], (Mat4::IDENTITY, Mat4::IDENTITY));
        // A point straight ahead at 10 m: the travel moves its image by focal/10 pixels a metre
        // against the travel in x, along it in y (y down); the pan adds its pixels.
        let focal = screen.1 as f32 / 2.0 / (FLAT_CAMERA.fov_y / 2.0).tan();
        let p = Vec3::new(0.0, 0.0, -10.0);
        let (x0, y0) = to_pixels(&zero, screen, p);
        let (x3, y3) = to_pixels(&three, screen, p);
        let expected = Vec2::new(3.0 * (1.0 - 0.2 * focal / 10.0), 3.0 * (-0.5 - 0.1 * focal / 10.0));
        assert!((Vec2::new(x3 - x0, y3 - y0) - expected).length() < 1e-3, "moved ({}, {})", x3 - x0, y3 - y0);
    }

    /// Twelve rects in front of a backdrop over the whole screen at 40 m: each inside the screen
    /// and at least a pixel wide, 2 to 32 m away, colours in 1/255 steps; the seed decides them.
    #[test]
    fn seeded_rects_lie_on_screen_in_front_of_the_backdrop() {
        let screen = (37, 23);
        let mut extremes = (f32::MAX, f32::MIN);
        // Whether some rect reaches the right and the bottom edge from short of the last column or
        // row (x1, y1 range up to the screen's; a rect starting in the last one can only end there).
        let mut reach = (false, false);
        for seed in 0..40 {
            let rects = seeded_rects(screen, seed);
            assert_eq!(rects.len(), 13);
            assert_eq!((rects[0].x0, rects[0].y0, rects[0].x1, rects[0].y1, rects[0].distance), (0, 0, 37, 23, 40.0));
            for r in &rects[1..] {
                assert!(0 <= r.x0 && r.x0 < r.x1 && r.x1 <= 37 && 0 <= r.y0 && r.y0 < r.y1 && r.y1 <= 23, "{r:?}");
                assert!((2.0..32.0).contains(&r.distance), "{r:?}");
                extremes = (extremes.0.min(r.distance), extremes.1.max(r.distance));
                reach = (reach.0 || (r.x1 == 37 && r.x0 < 36), reach.1 || (r.y1 == 23 && r.y0 < 22));
            }
            for r in &rects {
                assert!(r.albedo.iter().all(|&c| (c * 255.0).fract() == 0.0 && (0.0..=1.0).contains(&c)), "{r:?}");
                assert_eq!((r.velocity, r.opacity), (Vec2::ZERO, 1.0));
            }
            assert_eq!(seeded_rects(screen, seed), rects);
            assert_ne!(seeded_rects(screen, seed + 1000), rects);
        }
        assert!(extremes.0 < 3.0 && extremes.1 > 31.0, "distances span {extremes:?}");
        assert_eq!(reach, (true, true), "rects reaching the right and bottom edges");
        let scene = flat_rects(screen, 3, Vec2::new(1.0, 0.0));
        assert_eq!((scene.name.as_str(), scene.draws.len()), ("flat_rects", 13));
        assert_eq!(scene.camera_motion, CameraMotion { pan_pixels: Vec2::new(1.0, 0.0), travel: Vec3::ZERO });
    }

    /// The corridor: its geometry textured on the floor (scale 1) and walls (0.5) only, the
    /// object box for `object_*` moving along x, two glass panes last, the farther first; the
    /// camera moving as the motion says.
    #[test]
    fn the_textured_corridor_moves_and_textures_as_its_motion_says() {
        let base = corridor(5, 4);
        for motion in [Motion::Static, Motion::Pan(Vec2::new(1.0, 0.5)), Motion::Strafe(0.1), Motion::Object(0.25)] {
            let scene = textured_corridor(5, 4, motion);
            assert_eq!(scene.name, format!("corridor_{}", motion.name()));
            assert_eq!((scene.lights.as_slice(), scene.camera), (base.lights.as_slice(), base.camera));
            let expected_camera = match motion {
                Motion::Pan(p) => CameraMotion { pan_pixels: p, travel: Vec3::ZERO },
                Motion::Strafe(m) => CameraMotion { pan_pixels: Vec2::ZERO, travel: Vec3::new(m, 0.0, 0.0) },
                _ => CameraMotion::default(),
            };
            assert_eq!(scene.camera_motion, expected_camera);
            let geometry = &scene.draws[0];
            assert_eq!((geometry.vertices.clone(), geometry.transparent), (0..base.vertices.len() as u32, false));
            for (i, (v, b)) in scene.vertices.iter().zip(&base.vertices).enumerate() {
                assert_eq!(
                    (v.position, v.normal, v.albedo, v.shininess),
                    (b.position, b.normal, b.albedo, b.shininess)
                );
                let scale = match i / 36 {
                    0 => 1.0,
                    2 | 3 => 0.5,
                    _ => 0.0,
                };
                assert_eq!(v.texture_scale, scale, "vertex {i}");
            }
            let object = matches!(motion, Motion::Object(_));
            assert_eq!(scene.draws.len(), if object { 4 } else { 3 });
            assert_eq!(scene.objects_move(), object);
            if let Motion::Object(metres) = motion {
                let cube = &scene.draws[1];
                assert_eq!((cube.velocity, cube.transparent, cube.vertices.len()), (Vec3::X * metres, false, 18));
                // Three faces of a 0.9 m cube about (−1.8, 1.3, −2), each facing out.
                for v in &scene.vertices[cube.vertices.start as usize..cube.vertices.end as usize] {
                    let offset = Vec3::from_array(v.position) - Vec3::new(-1.8, 1.3, -2.0);
                    let normal = Vec3::from_array(v.normal);
                    assert!((offset.dot(normal) - 0.45).abs() < 1e-5, "{offset} along {normal}");
                    assert!(offset.abs().max_element() <= 0.45 + 1e-5);
                }
                // Each face (two triangles) spans its square: four distinct corners of the cube.
                for face in scene.vertices[cube.vertices.start as usize..cube.vertices.end as usize].chunks(6) {
                    let mut corners: Vec<[i32; 3]> = face
                        .iter()
                        .map(|v| (Vec3::from_array(v.position) - Vec3::new(-1.8, 1.3, -2.0)).to_array())
                        .map(|o| o.map(|c| (c / 0.45).round() as i32))
                        .collect();
                    corners.sort();
                    corners.dedup();
                    assert_eq!(corners.len(), 4, "{corners:?}");
                    assert!(corners.iter().flatten().all(|c| c.abs() == 1), "{corners:?}");
                }
            }
            let panes = &scene.draws[scene.draws.len() - 2..];
            assert!(panes.iter().all(|d| d.transparent && d.velocity == Vec3::ZERO && d.vertices.len() == 6));
            let z = |d: &Draw| scene.vertices[d.vertices.start as usize].position[2];
            assert_eq!((z(&panes[0]), z(&panes[1])), (-9.0, -3.0));
            // Each pane spans the corridor: x from −1.2 to 1.0, y from 0.2 to 2.2.
            for pane in panes {
                let positions = &scene.vertices[pane.vertices.start as usize..pane.vertices.end as usize];
                let extent = |axis: usize| {
                    positions
                        .iter()
                        .map(|v| v.position[axis])
                        .fold((f32::MAX, f32::MIN), |(lo, hi), p| (lo.min(p), hi.max(p)))
                };
                assert_eq!((extent(0), extent(1)), ((-1.2, 1.0), (0.2, 2.2)));
            }
            assert!(scene.has_transparents());
        }
    }
}
