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
                let corners =
                    [(cx - band, cy - band), (cx + band, cy - band), (cx - band, cy + band), (cx + band, cy + band)];
                let edge_near = corners.iter().any(|&(x, y)| face(&self.cast(x, y)) != face(&centre));
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

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::*;
    use crate::scene::corridor::corridor;

    /// A plain reading of the G-buffer pass's definition, by other means than the model's: the
    /// ray from the eye through a pixel point built from the camera's basis and field of view, met
    /// with each triangle's plane, kept where it lies inside all three edges, faces the camera and
    /// lies between the near and far planes; NDC depth from the projection's formula. Per face
    /// (two triangles), its first triangle hit; the nearest face, and the next face's depth.
    struct Reference<'a> {
        scene: &'a Scene,
        size: (u32, u32),
    }

    struct ReferenceHit {
        triangle: usize,
        position: DVec3,
        depth: f64,
        next_depth: f64,
    }

    impl Reference<'_> {
        fn cast(&self, x: f64, y: f64) -> Option<ReferenceHit> {
            let camera = &self.scene.camera;
            let (eye, target) = (camera.eye.as_dvec3(), camera.target.as_dvec3());
            let forward = (target - eye).normalize();
            let right = forward.cross(DVec3::Y).normalize();
            let up = right.cross(forward);
            let (w, h) = (f64::from(self.size.0), f64::from(self.size.1));
            let half_height = (f64::from(camera.fov_y) / 2.0).tan();
            let screen = DVec2::new(2.0 * x / w - 1.0, 1.0 - 2.0 * y / h);
            // One unit along `forward` per unit of view depth.
            let direction = forward + right * screen.x * half_height * (w / h) + up * screen.y * half_height;
            let (near, far) = (f64::from(camera.near), f64::from(camera.far));
            let mut faces: Vec<(usize, DVec3, f64)> = Vec::new();
            for (i, t) in self.scene.vertices.chunks_exact(3).enumerate() {
                let [a, b, c] = [0, 1, 2].map(|k| DVec3::from(t[k].position.map(f64::from)));
                let normal = (b - a).cross(c - a);
                if normal.dot(direction) >= 0.0 || faces.iter().any(|(j, ..)| j / 2 == i / 2) {
                    continue;
                }
                let depth = normal.dot(a - eye) / normal.dot(direction);
                let point = eye + direction * depth;
                let inside =
                    [(a, b), (b, c), (c, a)].iter().all(|(p, q)| (*q - *p).cross(point - *p).dot(normal) >= 0.0);
                if inside && (near..=far).contains(&depth) {
                    let ndc = far * (depth - near) / (depth * (far - near));
                    faces.push((i, point, ndc));
                }
            }
            let nearest = faces.iter().enumerate().min_by(|(_, a), (_, b)| a.2.total_cmp(&b.2))?.0;
            let (triangle, position, depth) = faces[nearest];
            let next_depth =
                faces.iter().enumerate().filter(|(k, _)| *k != nearest).map(|(_, f)| f.2).fold(f64::INFINITY, f64::min);
            Some(ReferenceHit { triangle, position, depth, next_depth })
        }

        fn expected(&self, band: f64) -> Vec<ExpectedPixel> {
            let mut pixels = Vec::new();
            for y in 0..self.size.1 {
                for x in 0..self.size.0 {
                    let (cx, cy) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
                    let centre = self.cast(cx, cy);
                    let face = |hit: &Option<ReferenceHit>| hit.as_ref().map(|h| h.triangle / 2);
                    let straddles = [(-band, -band), (band, -band), (-band, band), (band, band)]
                        .iter()
                        .any(|(dx, dy)| face(&self.cast(cx + dx, cy + dy)) != face(&centre));
                    pixels.push(match centre {
                        _ if straddles => ExpectedPixel::Ambiguous,
                        Some(hit) if hit.next_depth - hit.depth <= DEPTH_TIE => ExpectedPixel::Ambiguous,
                        Some(hit) => ExpectedPixel::Surface { triangle: hit.triangle, position: hit.position },
                        None => ExpectedPixel::Background,
                    });
                }
            }
            pixels
        }
    }

    /// The model's expectation is the definition's, pixel by pixel, on corridors from several
    /// seeds, at a band of a quarter pixel and of none; positions to within the f32 camera.
    #[test]
    fn the_model_is_the_definition_pixel_by_pixel() {
        let size = (32, 24);
        let (mut surfaces, mut ambiguous, mut background) = (0, 0, 0);
        for seed in 1..=2 {
            let scene = corridor(seed, 1);
            let model = SurfaceModel::new(&scene, size);
            let reference = Reference { scene: &scene, size };
            for band in [0.25, 0.0] {
                let (got, want) = (model.expected(band), reference.expected(band));
                for (index, (got, want)) in got.iter().zip(&want).enumerate() {
                    let at = (index as u32 % size.0, index as u32 / size.0);
                    match (got, want) {
                        (
                            ExpectedPixel::Surface { triangle, position },
                            ExpectedPixel::Surface { triangle: t, position: p },
                        ) => {
                            assert_eq!(triangle, t, "seed {seed} band {band} pixel {at:?}");
                            // The model casts through the pass's own f32 camera matrix: its rays
                            // are the exact ones' to within a few f32 ulps.
                            let error = (*position - *p).length();
                            assert!(
                                error <= 2f64.powi(-16) * p.length().max(1.0),
                                "seed {seed} pixel {at:?}: {position} vs {p}"
                            );
                            surfaces += 1;
                        }
                        _ => {
                            assert_eq!(got, want, "seed {seed} band {band} pixel {at:?}");
                            ambiguous += usize::from(*got == ExpectedPixel::Ambiguous);
                            background += usize::from(*got == ExpectedPixel::Background);
                        }
                    }
                }
            }
        }
        // The scenes exercise every kind of pixel.
        assert!(surfaces > 2500 && ambiguous > 200 && background > 0, "{surfaces} {ambiguous} {background}");
    }

    /// A hit projects back onto its pixel's centre, lies in its triangle's plane, and carries its
    /// triangle's first vertex.
    #[test]
    fn a_hit_projects_to_its_pixel_and_lies_in_its_triangles_plane() {
        let scene = corridor(2, 1);
        let size = (32, 24);
        let model = SurfaceModel::new(&scene, size);
        let mut checked = 0;
        for (index, pixel) in model.expected(0.25).iter().enumerate() {
            let ExpectedPixel::Surface { triangle, position } = *pixel else { continue };
            let centre = (f64::from(index as u32 % size.0) + 0.5, f64::from(index as u32 / size.0) + 0.5);
            let (x, y) = model.project(position);
            assert!((x - centre.0).abs() < 1e-6 && (y - centre.1).abs() < 1e-6, "{:?} vs {centre:?}", (x, y));
            let (normal, vertex) = model.plane(triangle);
            assert!((normal.length() - 1.0).abs() < 1e-12);
            assert!(normal.dot(position - vertex).abs() < 1e-9, "off the plane of {triangle}");
            let [a, b, c] = [0, 1, 2].map(|k| DVec3::from(scene.vertices[3 * triangle + k].position.map(f64::from)));
            assert!(
                (b - a).cross(c - a).normalize().dot(normal) > 1.0 - 1e-12,
                "the plane's normal faces the other way"
            );
            assert_eq!(vertex, a);
            assert!(std::ptr::eq(model.vertex(triangle), &scene.vertices[3 * triangle]));
            checked += 1;
        }
        assert!(checked > 400, "{checked}");
    }

    /// A quad facing the camera (two triangles, counter-clockwise seen from it) over x0..x1,
    /// y0..y1 at depth z.
    fn quad(x: (f32, f32), y: (f32, f32), z: f32) -> Vec<SceneVertex> {
        let corner = |x: f32, y: f32| SceneVertex {
            position: [x, y, z],
            normal: [0.0, 0.0, 1.0],
            albedo: [0.5; 4],
            shininess: 8.0,
        };
        let [a, b, c, d] = [corner(x.0, y.0), corner(x.1, y.0), corner(x.1, y.1), corner(x.0, y.1)];
        vec![a, b, c, a, c, d]
    }

    /// Far from the camera a few millimetres are within a Depth32Float test's reach: at 50 m
    /// (near 0.1, far 60), faces 2 mm apart lie 8e-8 apart in NDC depth (about an f32 ulp
    /// there), so where they overlap the pixel is a tie, as the definition has it; where only
    /// one lies, it.
    #[test]
    fn far_faces_millimetres_apart_are_a_depth_tie() {
        use crate::scene::corridor::Camera;
        let camera = Camera { eye: DVec3::ZERO.as_vec3(), target: glam::Vec3::NEG_Z, fov_y: 1.0, near: 0.1, far: 60.0 };
        let mut vertices = quad((-20.0, 20.0), (-20.0, 20.0), -50.0);
        vertices.extend(quad((0.0, 30.0), (-30.0, 30.0), -50.002));
        let scene = Scene { vertices, lights: Vec::new(), camera };
        let size = (8, 8);
        let (got, want) =
            (SurfaceModel::new(&scene, size).expected(0.0), Reference { scene: &scene, size }.expected(0.0));
        for y in 1..7 {
            let row = &got[y * 8..y * 8 + 8];
            assert!(matches!(row[2], ExpectedPixel::Surface { triangle: 0 | 1, .. }), "(2, {y}): {:?}", row[2]);
            assert_eq!(row[5], ExpectedPixel::Ambiguous, "(5, {y})");
            assert_eq!(want[y * 8 + 5], ExpectedPixel::Ambiguous, "the reference at (5, {y})");
        }
    }

    /// Where the corridors hardly go: a face's own diagonal through pixel centres (its two
    /// triangles are one face, not a tie), two faces at depths a Depth32Float test cannot order
    /// (ambiguous), a nearer face over a farther one (the nearer wins) — the model against the
    /// definition read plainly, with and without a band.
    #[test]
    fn diagonals_ties_and_overlaps_follow_the_definition() {
        use crate::scene::corridor::Camera;
        let camera = Camera { eye: DVec3::ZERO.as_vec3(), target: glam::Vec3::NEG_Z, fov_y: 1.0, near: 0.1, far: 60.0 };
        // At 5 m the half-height of the view is 5 tan(1/2) ≈ 2.73 m.
        let mut vertices = quad((-2.0, 2.0), (-2.0, 2.0), -5.0);
        // A face 1e-7 m behind the first over its right half: NDC depths 4e-9 apart.
        vertices.extend(quad((0.5, 2.5), (-2.5, 0.5), -5.0000001));
        // A nearer face over the lower left.
        vertices.extend(quad((-2.5, -0.5), (-2.5, -0.5), -3.0));
        let scene = Scene { vertices, lights: Vec::new(), camera };
        let size = (16, 16);
        let model = SurfaceModel::new(&scene, size);
        let reference = Reference { scene: &scene, size };
        let mut kinds = [0; 3];
        for band in [0.0, 0.25] {
            let (got, want) = (model.expected(band), reference.expected(band));
            for (index, (got, want)) in got.iter().zip(&want).enumerate() {
                let at = (index as u32 % size.0, index as u32 / size.0);
                match (got, want) {
                    (
                        ExpectedPixel::Surface { triangle, position },
                        ExpectedPixel::Surface { triangle: t, position: p },
                    ) => {
                        assert_eq!(triangle / 2, t / 2, "band {band} pixel {at:?}: another face");
                        assert!((*position - *p).length() <= 1e-5, "band {band} pixel {at:?}: {position} vs {p}");
                        kinds[0] += 1;
                    }
                    _ => {
                        assert_eq!(got, want, "band {band} pixel {at:?}");
                        kinds[usize::from(*got == ExpectedPixel::Background) + 1] += 1;
                    }
                }
            }
        }
        // The first face's diagonal (bottom left to top right) runs through the centres of
        // pixels (i, 15 − i): with no band they are that face's, not a tie of its triangles.
        let exact = model.expected(0.0);
        for i in 6..=9 {
            let pixel = exact[((15 - i) * 16 + i) as usize];
            assert!(matches!(pixel, ExpectedPixel::Surface { triangle: 0 | 1, .. }), "({i}, {}): {pixel:?}", 15 - i);
        }
        // Where the face behind it by 1e-7 m overlaps, ambiguous; where the nearer one does, it.
        assert_eq!(exact[10 * 16 + 12], ExpectedPixel::Ambiguous);
        assert!(matches!(exact[13 * 16 + 3], ExpectedPixel::Surface { triangle: 4 | 5, .. }));
        assert!(kinds.iter().all(|&k| k > 0), "surface, ambiguous, background: {kinds:?}");
    }
}
