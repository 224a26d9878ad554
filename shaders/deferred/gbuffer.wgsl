// G-buffer pass: world position (w = 1 where a surface was drawn), normal + shininess, albedo +
// specular weight, for the deterministic corridor scene. The position's f32 bits travel in an
// Rgba32Uint target: exact, and renderable where Rgba32Float is not (wgpu's GL backend).

struct Camera {
    view_projection: mat4x4f,
}

@group(0) @binding(0) var<uniform> camera: Camera;

struct SceneVertex {
    @location(0) position: vec3f,
    @location(1) normal: vec3f,
    @location(2) albedo: vec4f,
    @location(3) shininess: f32,
}

struct GbufferVarying {
    @builtin(position) clip: vec4f,
    @location(0) world: vec3f,
    @location(1) normal: vec3f,
    @location(2) albedo: vec4f,
    @location(3) shininess: f32,
}

struct Gbuffer {
    @location(0) position: vec4u,
    @location(1) normal: vec4f,
    @location(2) albedo: vec4f,
}

@vertex
fn vs_scene(vertex: SceneVertex) -> GbufferVarying {
    return GbufferVarying(camera.view_projection * vec4f(vertex.position, 1.0), vertex.position, vertex.normal, vertex.albedo, vertex.shininess);
}

@fragment
fn fs_gbuffer(in: GbufferVarying) -> Gbuffer {
    return Gbuffer(bitcast<vec4u>(vec4f(in.world, 1.0)), vec4f(normalize(in.normal), in.shininess), in.albedo);
}
