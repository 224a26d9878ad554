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
