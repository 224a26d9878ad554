// Deferred checkerboard shading, 2x path: the resolve pass that shades each sample of the 2x
// G-buffer into the shade resolve target (single-sampled, in the sample layout).

@group(0) @binding(0) var<uniform> shading: SampleShading;
@group(0) @binding(1) var gbuffer_normal: texture_multisampled_2d<f32>;
@group(0) @binding(2) var gbuffer_albedo: texture_multisampled_2d<f32>;
@group(0) @binding(3) var gbuffer_depth: texture_multisampled_2d<f32>;
@group(0) @binding(4) var lights: texture_2d<f32>;

@fragment
fn fs_shade_msaa_samples(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let texel = vec2i(position.xy);
    let at = layout_sample(texel, shading.quarter);
    let normal = textureLoad(gbuffer_normal, at.xy, at.z);
    let albedo = textureLoad(gbuffer_albedo, at.xy, at.z);
    return shade_layout_texel(shading, texel, normal, albedo, textureLoad(gbuffer_depth, at.xy, at.z).r, lights);
}
