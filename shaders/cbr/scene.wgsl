// Checkerboard scene pass: the scene's geometry through one frame's projection (quarter
// resolution, jittered or offset, or full resolution for the reference), shaded per sample.
// Entry points: opaque forward shading, transparent forward shading (premultiplied), the
// G-buffer of the deferred path, and per-object motion vectors for moving objects.

struct View {
    // What rasterises: the frame's quarter-resolution (jittered, offset) or full projection.
    clip_from_world: mat4x4f,
    // The unjittered full-resolution view-projection now and one frame earlier (motion).
    full_from_world: mat4x4f,
    previous_full_from_world: mat4x4f,
    screen: vec2f,
    // 0: textureSampleBias by `lod_value`; 1: textureSampleGrad with gradients × `lod_value`.
    lod_mode: u32,
    lod_value: f32,
    eye: vec3f,
    light_count: u32,
}

struct Object {
    model: mat4x4f,
    previous_model: mat4x4f,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> object: Object;
@group(0) @binding(2) var lights: texture_2d<f32>;
@group(0) @binding(3) var albedo_map: texture_2d<f32>;
@group(0) @binding(4) var albedo_sampler: sampler;

struct SceneVertex {
    @location(0) position: vec3f,
    @location(1) normal: vec3f,
    @location(2) albedo: vec4f,
    @location(3) shininess: f32,
    @location(4) texture_scale: f32,
}

// Sample interpolation: every sample of a 2x target is its own shading point (and forces
// per-sample shading); on single-sampled targets it is the pixel centre, and the kit compiles
// it there as `center` (`ShaderFile::single_sampled`), which GL 3.3 accepts. Materials are flat:
// constant per triangle, bit-exact whatever the interpolation weights.
struct SceneVarying {
    @builtin(position) @invariant clip: vec4f,
    @location(0) @interpolate(perspective, sample) world: vec3f,
    @location(1) @interpolate(perspective, sample) normal: vec3f,
    @location(2) @interpolate(flat) albedo: vec4f,
    @location(3) @interpolate(flat) shininess: f32,
    @location(4) @interpolate(flat) texture_scale: f32,
    @location(5) @interpolate(perspective, sample) full_now: vec4f,
    @location(6) @interpolate(perspective, sample) full_before: vec4f,
}

@vertex
fn vs_scene(vertex: SceneVertex) -> SceneVarying {
    let world = object.model * vec4f(vertex.position, 1.0);
    let before = object.previous_model * vec4f(vertex.position, 1.0);
    let normal = (object.model * vec4f(vertex.normal, 0.0)).xyz;
    return SceneVarying(
        view.clip_from_world * world,
        world.xyz,
        normal,
        vertex.albedo,
        vertex.shininess,
        vertex.texture_scale,
        view.full_from_world * world,
        view.previous_full_from_world * before,
    );
}

// Texture coordinates projected along the normal's dominant axis.
fn surface_uv(world: vec3f, normal: vec3f, scale: f32) -> vec2f {
    let n = abs(normal);
    if n.y >= n.x && n.y >= n.z {
        return world.xz * scale;
    }
    if n.x >= n.z {
        return world.zy * scale;
    }
    return world.xy * scale;
}

// The material's albedo and specular weight, the albedo map applied where the material has a
// texture scale. Sampled unconditionally: derivatives need uniform control flow.
fn material_albedo(in: SceneVarying) -> vec4f {
    let uv = surface_uv(in.world, in.normal, in.texture_scale);
    let biased = textureSampleBias(albedo_map, albedo_sampler, uv, view.lod_value);
    let graded = textureSampleGrad(albedo_map, albedo_sampler, uv, dpdx(uv) * view.lod_value, dpdy(uv) * view.lod_value);
    let texel = select(biased, graded, view.lod_mode == 1u);
    let textured = in.texture_scale > 0.0;
    return vec4f(select(in.albedo.rgb, in.albedo.rgb * texel.rgb, textured), in.albedo.a);
}

fn shade(in: SceneVarying, albedo: vec4f) -> vec3f {
    return shade_checkerboard_sample(vec4f(normalize(in.normal), in.shininess), albedo, in.world, view.eye, lights, view.light_count);
}

// The forward path's depth pass: depth only (the colour target's write mask is empty).
@fragment
fn fs_depth_only() -> @location(0) vec4f {
    return vec4f(0.0);
}

@fragment
fn fs_forward(in: SceneVarying) -> @location(0) vec4f {
    return vec4f(shade(in, material_albedo(in)), 1.0);
}

// Premultiplied colour over what is behind (blend One, OneMinusSrcAlpha): onto the opaque
// colour on the forward path, into the forward buffer (colour + accumulated alpha) on the
// deferred one. The vertex albedo's alpha is the opacity; the surface has no specular term.
@fragment
fn fs_transparent(in: SceneVarying) -> @location(0) vec4f {
    let albedo = material_albedo(in);
    let colour = shade(in, vec4f(albedo.rgb, 0.0));
    return vec4f(colour * in.albedo.a, in.albedo.a);
}

struct GbufferSample {
    @location(0) normal: vec4f,
    @location(1) albedo: vec4f,
}

@fragment
fn fs_gbuffer(in: SceneVarying) -> GbufferSample {
    return GbufferSample(vec4f(normalize(in.normal), in.shininess), material_albedo(in));
}

// Screen motion of the surface since the previous frame, in full-resolution pixels; alpha 1
// marks an object that moves (cleared texels: static).
@fragment
fn fs_object_motion(in: SceneVarying) -> @location(0) vec4f {
    let now = in.full_now.xy / in.full_now.w;
    let before = in.full_before.xy / in.full_before.w;
    return vec4f((now - before) * vec2f(0.5, -0.5) * view.screen, 0.0, 1.0);
}
