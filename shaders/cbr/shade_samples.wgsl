// Deferred checkerboard shading, offset-pass path: the G-buffer already holds one texel per
// sample in the sample layout, so each texel of the shade resolve target shades its own texel.

struct SampleShading {
    world_from_clip: mat4x4f,
    screen: vec2f,
    quarter: vec2i,
    eye: vec3f,
    light_count: u32,
    phase: i32,
}

@group(0) @binding(0) var<uniform> shading: SampleShading;
@group(0) @binding(1) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(2) var gbuffer_albedo: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_depth: texture_2d<f32>;
@group(0) @binding(4) var lights: texture_2d<f32>;

@fragment
fn fs_shade_samples(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let texel = vec2i(position.xy);
    let centre = layout_pixel_centre(texel, shading.quarter, shading.phase);
    let world = unproject(centre, textureLoad(gbuffer_depth, texel, 0).r, shading.screen, shading.world_from_clip);
    let normal = textureLoad(gbuffer_normal, texel, 0);
    let albedo = textureLoad(gbuffer_albedo, texel, 0);
    return vec4f(shade_checkerboard_sample(normal, albedo, world, shading.eye, lights, shading.light_count), 1.0);
}
