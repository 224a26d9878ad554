// Deferred checkerboard shading, offset-pass path: the G-buffer already holds one texel per
// sample in the sample layout, so each texel of the shade resolve target shades its own texel.

@group(0) @binding(0) var<uniform> shading: SampleShading;
@group(0) @binding(1) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(2) var gbuffer_albedo: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_depth: texture_2d<f32>;
@group(0) @binding(4) var lights: texture_2d<f32>;

@fragment
fn fs_shade_samples(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let texel = vec2i(position.xy);
    let normal = textureLoad(gbuffer_normal, texel, 0);
    let albedo = textureLoad(gbuffer_albedo, texel, 0);
    return shade_layout_texel(shading, texel, normal, albedo, textureLoad(gbuffer_depth, texel, 0).r, lights);
}
