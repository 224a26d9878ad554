//! The deterministic corridor: walls, floor and ceiling, two rows of columns, seeded boxes
//! (some turned about the vertical axis), seeded point lights, and a camera looking down it.
//! Many objects, depth complexity, and normals and materials that make shading vary.

use glam::{Mat4, Vec3};

use super::hash::SeededRng;

/// One vertex as `shaders/deferred/gbuffer.wgsl` reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SceneVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    /// Albedo and specular weight.
    pub albedo: [f32; 4],
    pub shininess: f32,
}

/// A point light: position and range, colour and intensity (the two texels it occupies).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub position: Vec3,
    pub range: f32,
    pub colour: Vec3,
    pub intensity: f32,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub fov_y: f32,
    pub near: f32,
    pub far: f32,
}

impl Camera {
    /// Right-handed view and a projection onto wgpu's 0..1 depth range.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        Mat4::perspective_rh(self.fov_y, aspect, self.near, self.far) * Mat4::look_at_rh(self.eye, self.target, Vec3::Y)
    }
}

#[derive(Clone, Debug)]
pub struct Scene {
    pub vertices: Vec<SceneVertex>,
    pub lights: Vec<Light>,
    pub camera: Camera,
}

/// Corridor half-width, height and length (metres).
const HALF_WIDTH: f32 = 3.0;
const HEIGHT: f32 = 3.0;
const LENGTH: f32 = 30.0;

struct Material {
    albedo: [f32; 4],
    shininess: f32,
}

/// Appends a box of half-extents `half` centred at `centre`, turned by `yaw` about +y.
fn push_box(vertices: &mut Vec<SceneVertex>, centre: Vec3, half: Vec3, yaw: f32, material: &Material) {
    let rotation = Mat4::from_rotation_y(yaw);
    let corner = |sx: f32, sy: f32, sz: f32| centre + rotation.transform_vector3(half * Vec3::new(sx, sy, sz));
    // Each face: outward normal (before rotation) and its four corners counter-clockwise seen from outside.
    type Face = (Vec3, [(f32, f32, f32); 4]);
    let faces: [Face; 6] = [
        (Vec3::X, [(1., -1., 1.), (1., -1., -1.), (1., 1., -1.), (1., 1., 1.)]),
        (Vec3::NEG_X, [(-1., -1., -1.), (-1., -1., 1.), (-1., 1., 1.), (-1., 1., -1.)]),
        (Vec3::Y, [(-1., 1., 1.), (1., 1., 1.), (1., 1., -1.), (-1., 1., -1.)]),
        (Vec3::NEG_Y, [(-1., -1., -1.), (1., -1., -1.), (1., -1., 1.), (-1., -1., 1.)]),
        (Vec3::Z, [(-1., -1., 1.), (1., -1., 1.), (1., 1., 1.), (-1., 1., 1.)]),
        (Vec3::NEG_Z, [(1., -1., -1.), (-1., -1., -1.), (-1., 1., -1.), (1., 1., -1.)]),
    ];
    for (normal, quad) in faces {
        let normal = rotation.transform_vector3(normal).to_array();
        let [a, b, c, d] = quad.map(|(x, y, z)| corner(x, y, z).to_array());
        for position in [a, b, c, a, c, d] {
            vertices.push(SceneVertex { position, normal, albedo: material.albedo, shininess: material.shininess });
        }
    }
}

fn random_material(rng: &mut SeededRng) -> Material {
    let albedo = [0.2 + 0.7 * rng.unit(), 0.2 + 0.7 * rng.unit(), 0.2 + 0.7 * rng.unit(), 0.1 + 0.8 * rng.unit()];
    Material { albedo, shininess: 4.0 + 60.0 * rng.unit() }
}

/// The corridor for `seed` with `light_count` lights.
pub fn corridor(seed: u32, light_count: u32) -> Scene {
    let mut rng = SeededRng::new(seed);
    let mut vertices = Vec::new();
    let stone = Material { albedo: [0.55, 0.5, 0.45, 0.2], shininess: 8.0 };
    let plaster = Material { albedo: [0.7, 0.68, 0.62, 0.05], shininess: 4.0 };
    let mid_z = -LENGTH / 2.0 + 2.0;
    push_box(&mut vertices, Vec3::new(0.0, -0.1, mid_z), Vec3::new(HALF_WIDTH, 0.1, LENGTH / 2.0), 0.0, &stone);
    push_box(
        &mut vertices,
        Vec3::new(0.0, HEIGHT + 0.1, mid_z),
        Vec3::new(HALF_WIDTH, 0.1, LENGTH / 2.0),
        0.0,
        &plaster,
    );
    for side in [-1.0, 1.0] {
        push_box(
            &mut vertices,
            Vec3::new(side * (HALF_WIDTH + 0.1), HEIGHT / 2.0, mid_z),
            Vec3::new(0.1, HEIGHT / 2.0, LENGTH / 2.0),
            0.0,
            &plaster,
        );
    }
    // Columns every 3 m along both walls.
    let column = Material { albedo: [0.8, 0.78, 0.7, 0.6], shininess: 32.0 };
    for i in 0..9 {
        let z = -1.0 - 3.0 * i as f32;
        for side in [-1.0, 1.0] {
            push_box(
                &mut vertices,
                Vec3::new(side * (HALF_WIDTH - 0.4), HEIGHT / 2.0, z),
                Vec3::new(0.25, HEIGHT / 2.0, 0.25),
                0.0,
                &column,
            );
        }
    }
    // Seeded boxes on the floor, some stacked.
    for _ in 0..24 {
        let half = Vec3::new(0.15 + 0.35 * rng.unit(), 0.15 + 0.4 * rng.unit(), 0.15 + 0.35 * rng.unit());
        let centre = Vec3::new(
            (rng.unit() * 2.0 - 1.0) * (HALF_WIDTH - 1.0),
            half.y + if rng.unit() < 0.2 { 0.6 } else { 0.0 },
            -2.0 - rng.unit() * (LENGTH - 6.0),
        );
        let yaw = if rng.unit() < 0.5 { rng.unit() * std::f32::consts::FRAC_PI_2 } else { 0.0 };
        let material = random_material(&mut rng);
        push_box(&mut vertices, centre, half, yaw, &material);
    }
    let lights = (0..light_count)
        .map(|_| Light {
            position: Vec3::new(
                (rng.unit() * 2.0 - 1.0) * (HALF_WIDTH - 0.2),
                0.2 + rng.unit() * (HEIGHT - 0.4),
                1.0 - rng.unit() * (LENGTH - 2.0),
            ),
            range: 2.0 + 3.0 * rng.unit(),
            colour: Vec3::new(0.4 + 0.6 * rng.unit(), 0.4 + 0.6 * rng.unit(), 0.4 + 0.6 * rng.unit()),
            intensity: 0.15 + 0.35 * rng.unit(),
        })
        .collect();
    let camera =
        Camera { eye: Vec3::new(0.4, 1.6, 1.5), target: Vec3::new(-0.3, 1.2, -12.0), fov_y: 1.0, near: 0.1, far: 60.0 };
    Scene { vertices, lights, camera }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The boxes of a corridor, 36 vertices each.
    fn boxes(scene: &Scene) -> Vec<&[SceneVertex]> {
        scene.vertices.chunks_exact(36).collect()
    }

    fn min_max(vertices: &[SceneVertex]) -> (Vec3, Vec3) {
        vertices
            .iter()
            .map(|v| Vec3::from_array(v.position))
            .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), p| (lo.min(p), hi.max(p)))
    }

    /// Every face of every box is two triangles wound counter-clockwise seen from outside: the
    /// cross product of each triangle's edges is its stored normal, of unit length, pointing away
    /// from the box's centre; every box is closed (six faces, opposite normals in pairs).
    #[test]
    fn every_box_is_closed_and_faces_outward_counter_clockwise() {
        let scene = corridor(11, 3);
        assert_eq!(scene.vertices.len(), 36 * (4 + 18 + 24));
        for (b, vertices) in boxes(&scene).into_iter().enumerate() {
            let (lo, hi) = min_max(vertices);
            let centre = (lo + hi) / 2.0;
            let mut normals = Vec::new();
            for triangle in vertices.chunks_exact(3) {
                let [a, p, q] = [0, 1, 2].map(|i| Vec3::from_array(triangle[i].position));
                let normal = Vec3::from_array(triangle[0].normal);
                assert!(triangle.iter().all(|v| v.normal == triangle[0].normal));
                let winding = (p - a).cross(q - a);
                assert!((normal.length() - 1.0).abs() < 1e-5, "box {b}: normal {normal}");
                assert!(winding.normalize().dot(normal) > 0.9999, "box {b}: wound {winding} against {normal}");
                assert!(((a + p + q) / 3.0 - centre).dot(normal) > 0.0, "box {b}: normal {normal} points inward");
                normals.push(normal);
            }
            for n in &normals {
                assert!(normals.iter().any(|m| (*m + *n).length() < 1e-5), "box {b}: no face opposite {n}");
            }
            // The two triangles of a face share its diagonal: (a, b, c), (a, c, d).
            for face in vertices.chunks_exact(6) {
                assert_eq!((face[0].position, face[2].position), (face[3].position, face[4].position));
            }
        }
    }

    /// The fixed geometry: a floor whose top is y = 0 and a ceiling whose underside is y = 3,
    /// 6 m wide and 30 m long (z from 2 to −28), walls 0.2 m thick outside x = ±3, and columns
    /// 0.5 m square and 3 m tall at x = ±2.6 every 3 m from z = −1.
    #[test]
    fn floor_ceiling_walls_and_columns_stand_where_the_corridor_says() {
        let scene = corridor(1, 0);
        let boxes = boxes(&scene);
        let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 1e-5;
        let extent = |i: usize| min_max(boxes[i]);
        assert!(close(extent(0).0, Vec3::new(-3.0, -0.2, -28.0)) && close(extent(0).1, Vec3::new(3.0, 0.0, 2.0)));
        assert!(close(extent(1).0, Vec3::new(-3.0, 3.0, -28.0)) && close(extent(1).1, Vec3::new(3.0, 3.2, 2.0)));
        assert!(close(extent(2).0, Vec3::new(-3.2, 0.0, -28.0)) && close(extent(2).1, Vec3::new(-3.0, 3.0, 2.0)));
        assert!(close(extent(3).0, Vec3::new(3.0, 0.0, -28.0)) && close(extent(3).1, Vec3::new(3.2, 3.0, 2.0)));
        assert_eq!((boxes[0][0].albedo, boxes[0][0].shininess), ([0.55, 0.5, 0.45, 0.2], 8.0));
        assert_eq!((boxes[1][0].albedo, boxes[1][0].shininess), ([0.7, 0.68, 0.62, 0.05], 4.0));
        assert_eq!(boxes[2][0].albedo, boxes[3][0].albedo);
        for i in 0..9 {
            for (j, side) in [-1.0, 1.0].into_iter().enumerate() {
                let (lo, hi) = extent(4 + 2 * i + j);
                let centre = Vec3::new(side * 2.6, 1.5, -1.0 - 3.0 * i as f32);
                assert!(
                    close(lo, centre - Vec3::new(0.25, 1.5, 0.25)) && close(hi, centre + Vec3::new(0.25, 1.5, 0.25))
                );
                assert_eq!(boxes[4 + 2 * i + j][0].albedo, [0.8, 0.78, 0.7, 0.6]);
            }
        }
        assert_eq!(
            scene.camera,
            Camera {
                eye: Vec3::new(0.4, 1.6, 1.5),
                target: Vec3::new(-0.3, 1.2, -12.0),
                fov_y: 1.0,
                near: 0.1,
                far: 60.0
            }
        );
    }

    /// The seeded boxes over many seeds: half-extents 0.15–0.5 (0.15–0.55 tall), standing on the
    /// floor or 0.6 m up, centres within 2 m of the axis and 2 to 26 m down it, turned by 0 or up
    /// to a quarter turn about y; materials within their ranges. Each range is reached at both ends.
    #[test]
    fn seeded_boxes_stay_within_their_ranges_and_reach_them() {
        let (mut halves, mut centres, mut yaws, mut bases) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let (mut albedos, mut shininess) = (Vec::new(), Vec::new());
        for seed in 0..30 {
            let scene = corridor(seed, 0);
            for vertices in &boxes(&scene)[22..] {
                // The +x face's normal (the first face) gives the yaw; the box's own axes its size.
                let normal = Vec3::from_array(vertices[0].normal);
                let yaw = (-normal.z).atan2(normal.x);
                let rotation = Mat4::from_rotation_y(-yaw);
                let local: Vec<Vec3> =
                    vertices.iter().map(|v| rotation.transform_vector3(Vec3::from_array(v.position))).collect();
                let lo = local.iter().fold(Vec3::splat(f32::MAX), |a, p| a.min(*p));
                let hi = local.iter().fold(Vec3::splat(f32::MIN), |a, p| a.max(*p));
                let (_, world_hi) = min_max(vertices);
                let (world_lo, _) = min_max(vertices);
                halves.push((hi - lo) / 2.0);
                centres.push(Mat4::from_rotation_y(yaw).transform_vector3((hi + lo) / 2.0));
                yaws.push(yaw);
                bases.push(world_lo.y);
                assert!(world_hi.y > world_lo.y);
                albedos.push(vertices[0].albedo);
                shininess.push(vertices[0].shininess);
            }
        }
        let span = |values: &mut dyn Iterator<Item = f32>| {
            values.fold((f32::MAX, f32::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)))
        };
        let within = |(lo, hi): (f32, f32), (a, b): (f32, f32), slack: f32| {
            lo >= a - 1e-4 && hi <= b + 1e-4 && lo <= a + slack && hi >= b - slack
        };
        assert!(within(span(&mut halves.iter().map(|h| h.x)), (0.15, 0.5), 0.02));
        assert!(within(span(&mut halves.iter().map(|h| h.y)), (0.15, 0.55), 0.02));
        assert!(within(span(&mut halves.iter().map(|h| h.z)), (0.15, 0.5), 0.02));
        assert!(within(span(&mut centres.iter().map(|c| c.x)), (-2.0, 2.0), 0.1));
        assert!(within(span(&mut centres.iter().map(|c| c.z)), (-26.0, -2.0), 0.3));
        assert!(within(span(&mut yaws.iter().copied()), (0.0, std::f32::consts::FRAC_PI_2), 0.05));
        let turned = yaws.iter().filter(|&&y| y.abs() > 1e-6).count();
        assert!(turned > 200 && turned < 520, "{turned} of {} turned", yaws.len());
        // Standing on the floor, or one in five lifted 0.6 m.
        assert!(bases.iter().all(|&b| b.abs() < 1e-5 || (b - 0.6).abs() < 1e-5), "{bases:?}");
        let lifted = bases.iter().filter(|&&b| b > 0.3).count();
        assert!(lifted > 80 && lifted < 220, "{lifted} of {} lifted", bases.len());
        for c in 0..3 {
            assert!(within(span(&mut albedos.iter().map(|a| a[c])), (0.2, 0.9), 0.02));
        }
        assert!(within(span(&mut albedos.iter().map(|a| a[3])), (0.1, 0.9), 0.02));
        assert!(within(span(&mut shininess.iter().copied()), (4.0, 64.0), 1.0));
    }

    /// Lights: as many as asked, inside the corridor (0.2 m from its walls, floor and ceiling,
    /// from z = 1 to −27), range 2–5, colour channels 0.4–1, intensity 0.15–0.5; each range
    /// reached; the seed decides them.
    #[test]
    fn seeded_lights_lie_inside_the_corridor_within_their_ranges() {
        let lights: Vec<Light> = (0..40).flat_map(|seed| corridor(seed, 8).lights).collect();
        assert_eq!(corridor(3, 8).lights.len(), 8);
        assert_eq!(corridor(3, 8).lights, corridor(3, 8).lights);
        assert_ne!(corridor(3, 8).lights, corridor(4, 8).lights);
        assert_ne!(corridor(3, 0).vertices, corridor(4, 0).vertices);
        let span = |f: &dyn Fn(&Light) -> f32| {
            lights.iter().map(f).fold((f32::MAX, f32::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)))
        };
        let within = |(lo, hi): (f32, f32), (a, b): (f32, f32), slack: f32| {
            lo >= a - 1e-4 && hi <= b + 1e-4 && lo <= a + slack && hi >= b - slack
        };
        assert!(within(span(&|l| l.position.x), (-2.8, 2.8), 0.1));
        assert!(within(span(&|l| l.position.y), (0.2, 2.8), 0.1));
        assert!(within(span(&|l| l.position.z), (-27.0, 1.0), 0.5));
        assert!(within(span(&|l| l.range), (2.0, 5.0), 0.1));
        for c in 0..3 {
            assert!(within(span(&|l| l.colour[c]), (0.4, 1.0), 0.02));
        }
        assert!(within(span(&|l| l.intensity), (0.15, 0.5), 0.01));
    }

    /// The camera's view-projection puts its target at the screen's centre, a point at the near
    /// plane at depth 0 and one at the far plane at 1 (wgpu's depth range), and keeps y up.
    #[test]
    fn the_camera_projects_its_target_to_the_centre_and_depth_onto_0_to_1() {
        let camera = Camera {
            eye: Vec3::new(1.0, 2.0, 3.0),
            target: Vec3::new(1.0, 2.0, -7.0),
            fov_y: 1.0,
            near: 0.5,
            far: 20.0,
        };
        let m = camera.view_projection(2.0);
        let at = |p: Vec3| m.project_point3(p);
        assert!((at(camera.target).truncate()).length() < 1e-5);
        assert!(at(Vec3::new(1.0, 2.0, 2.5)).z.abs() < 1e-5);
        assert!((at(Vec3::new(1.0, 2.0, -17.0)).z - 1.0).abs() < 1e-5);
        // Half the vertical field of view up at 10 m is the top edge; the aspect widens x.
        let up = 10.0 * (0.5f32).tan();
        assert!((at(Vec3::new(1.0, 2.0 + up, -7.0)).y - 1.0).abs() < 1e-4);
        assert!((at(Vec3::new(1.0 + 2.0 * up, 2.0, -7.0)).x - 1.0).abs() < 1e-4);
    }
}
