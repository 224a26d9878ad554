// Deferred checkerboard shading, 2x path: the resolve pass that shades each sample of the 2x
// G-buffer into the shade resolve target (single-sampled, twice the width: the sample layout).

struct SampleShading {
    world_from_clip: mat4x4f,
    screen: vec2f,
    quarter: vec2i,
    eye: vec3f,
    light_count: u32,
    phase: i32,
}

@group(0) @binding(0) var<uniform> shading: SampleShading;
@group(0) @binding(1) var gbuffer_normal: texture_multisampled_2d<f32>;
@group(0) @binding(2) var gbuffer_albedo: texture_multisampled_2d<f32>;
@group(0) @binding(3) var gbuffer_depth: texture_multisampled_2d<f32>;
@group(0) @binding(4) var lights: texture_2d<f32>;

@fragment
fn fs_shade_msaa_samples(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let texel = vec2i(position.xy);
    let at = layout_sample(texel, shading.quarter);
    let centre = layout_pixel_centre(texel, shading.quarter, shading.phase);
    let world = unproject(centre, textureLoad(gbuffer_depth, at.xy, at.z).r, shading.screen, shading.world_from_clip);
    let normal = textureLoad(gbuffer_normal, at.xy, at.z);
    let albedo = textureLoad(gbuffer_albedo, at.xy, at.z);
    return vec4f(shade_checkerboard_sample(normal, albedo, world, shading.eye, lights, shading.light_count), 1.0);
}
