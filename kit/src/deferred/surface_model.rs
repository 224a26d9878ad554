//! A CPU model of the G-buffer pass's definition (`shaders/deferred/gbuffer.wgsl`, back faces
//! culled, depth Less): at each pixel centre, the nearest front-facing triangle of the scene
//! between the near and far planes along the camera ray, ray-cast in f64 from the scene's own
//! vertices and camera. The independent expectation for `kit.deferred.gbuffer`.
//!
//! Rasterisation snaps vertices to a sub-pixel grid, so where a triangle edge (or the line where
//! two surfaces cross) passes within `band` pixels of a centre, the GPU may take either side: such
//! pixels are `Ambiguous` — found by casting the rays through the corners of a `band`-sized square
//! around the centre (a straight edge through the square puts a corner on its far side) — as are
//! pixels where two surfaces lie at depths a `Depth32Float` test cannot tell apart.

use glam::{DMat4, DVec3, DVec4};

use crate::scene::corridor::{Scene, SceneVertex};

/// What the G-buffer should hold at one pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ExpectedPixel {
    /// No surface: the cleared G-buffer.
    Background,
    /// The nearest front-facing surface: its triangle and the exact hit point.
    Surface { triangle: usize, position: DVec3 },
    /// Either side of an edge, or of a depth tie, within what the rasteriser may round.
    Ambiguous,
}

/// Depths (NDC, 0..1) closer than this may be ordered either way by a `Depth32Float` test of
/// interpolated f32 depths (a few ulps of values up to 1).
const DEPTH_TIE: f64 = 1.0 / (1 << 20) as f64;

/// A ray's hit: the triangle, the ray parameter, the NDC depth, and (for the nearest) whether
/// another face ties it.
struct Hit {
    triangle: usize,
    t: f64,
    depth: f64,
    tied: bool,
}

/// A scene's triangles in f64, seen through the G-buffer pass's camera at one size.
pub struct SurfaceModel<'a> {
    scene: &'a Scene,
    triangles: Vec<[DVec3; 3]>,
    clip_from_world: DMat4,
    world_from_clip: DMat4,
    size: (u32, u32),
}

impl<'a> SurfaceModel<'a> {
    /// The model for `scene` rendered at `size` (the G-buffer pass's own camera matrix).
    pub fn new(scene: &'a Scene, size: (u32, u32)) -> Self {
        let clip_from_world = scene.camera.view_projection(size.0 as f32 / size.1 as f32).as_dmat4();
        let triangles = scene
            .vertices
            .chunks_exact(3)
            .map(|t| [0, 1, 2].map(|i| DVec3::from(t[i].position.map(f64::from))))
            .collect();
        Self { scene, triangles, clip_from_world, world_from_clip: clip_from_world.inverse(), size }
    }

    /// The vertex whose material and normal triangle `triangle` carries (flat per face).
    pub fn vertex(&self, triangle: usize) -> &'a SceneVertex {
        &self.scene.vertices[3 * triangle]
    }

    /// Where a world point lands on the screen, in pixels (y down).
    pub fn project(&self, world: DVec3) -> (f64, f64) {
        let clip = self.clip_from_world * world.extend(1.0);
        let (w, h) = (f64::from(self.size.0), f64::from(self.size.1));
        ((clip.x / clip.w + 1.0) * 0.5 * w, (1.0 - clip.y / clip.w) * 0.5 * h)
    }

    /// The plane of triangle `triangle`: unit normal and one vertex.
    pub fn plane(&self, triangle: usize) -> (DVec3, DVec3) {
        let [a, b, c] = self.triangles[triangle];
        ((b - a).cross(c - a).normalize(), a)
    }

    /// Every pixel's expectation, row-major; `band` in pixels.
    pub fn expected(&self, band: f64) -> Vec<ExpectedPixel> {
        let (w, h) = self.size;
        let mut pixels = Vec::with_capacity((w * h) as usize);
        for y in 0..h {
            for x in 0..w {
                let (cx, cy) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
                let centre = self.cast(cx, cy);
                let face = |hit: &Option<Hit>| hit.as_ref().map(|h| h.triangle / 2);
                let corners = [(-band, -band), (band, -band), (-band, band), (band, band)];
                let edge_near = corners.iter().any(|(dx, dy)| face(&self.cast(cx + dx, cy + dy)) != face(&centre));
                pixels.push(match centre {
                    _ if edge_near => ExpectedPixel::Ambiguous,
                    Some(Hit { tied: true, .. }) => ExpectedPixel::Ambiguous,
                    Some(hit) => {
                        let (near, far) = self.ray(cx, cy);
                        ExpectedPixel::Surface { triangle: hit.triangle, position: near + (far - near) * hit.t }
                    }
                    None => ExpectedPixel::Background,
                });
            }
        }
        pixels
    }

    /// The ray through a screen point, as its points on the near (t = 0) and far (t = 1) planes.
    fn ray(&self, x: f64, y: f64) -> (DVec3, DVec3) {
        let (w, h) = (f64::from(self.size.0), f64::from(self.size.1));
        let ndc = (2.0 * x / w - 1.0, 1.0 - 2.0 * y / h);
        let unproject = |z: f64| {
            let p: DVec4 = self.world_from_clip * DVec4::new(ndc.0, ndc.1, z, 1.0);
            p.truncate() / p.w
        };
        (unproject(0.0), unproject(1.0))
    }

    /// The nearest front-facing triangle the ray through (x, y) meets between near and far.
    fn cast(&self, x: f64, y: f64) -> Option<Hit> {
        let (near, far) = self.ray(x, y);
        let direction = far - near;
        let mut best: Option<Hit> = None;
        let mut second_depth = f64::INFINITY;
        for (i, [a, b, c]) in self.triangles.iter().enumerate() {
            let (e1, e2) = (*b - *a, *c - *a);
            // Back faces (counter-clockwise on screen is front) are culled.
            if e1.cross(e2).dot(direction) >= 0.0 {
                continue;
            }
            // Möller–Trumbore.
            let p = direction.cross(e2);
            let det = e1.dot(p);
            let s = near - *a;
            let u = s.dot(p) / det;
            let q = s.cross(e1);
            let v = direction.dot(q) / det;
            let t = e2.dot(q) / det;
            if !(0.0..=1.0).contains(&u) || v < 0.0 || u + v > 1.0 || !(0.0..=1.0).contains(&t) {
                continue;
            }
            let hit = Hit { triangle: i, t, depth: self.ndc_depth(near + direction * t), tied: false };
            match &mut best {
                Some(nearest) if nearest.triangle / 2 == i / 2 => {}
                Some(nearest) if hit.depth < nearest.depth => {
                    second_depth = nearest.depth;
                    *nearest = hit;
                }
                Some(_) => second_depth = second_depth.min(hit.depth),
                None => best = Some(hit),
            }
        }
        best.map(|hit| Hit { tied: second_depth - hit.depth <= DEPTH_TIE, ..hit })
    }

    fn ndc_depth(&self, world: DVec3) -> f64 {
        let clip = self.clip_from_world * world.extend(1.0);
        clip.z / clip.w
    }
}
