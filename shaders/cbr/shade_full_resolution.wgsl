// Deferred shading at full resolution: the baseline deferred checkerboarding is measured against.
// The same G-buffer and lighting as the checkerboard's shade pass, at every pixel's centre, so
// that the two differ only in the pixels shaded.

@group(0) @binding(0) var<uniform> shading: SampleShading;
@group(0) @binding(1) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(2) var gbuffer_albedo: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_depth: texture_2d<f32>;
@group(0) @binding(4) var lights: texture_2d<f32>;

@fragment
fn fs_shade_full_resolution(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let texel = vec2i(position.xy);
    let normal = textureLoad(gbuffer_normal, texel, 0);
    let albedo = textureLoad(gbuffer_albedo, texel, 0);
    return shade_at(shading, position.xy, normal, albedo, textureLoad(gbuffer_depth, texel, 0).r, lights);
}
