// Deferred shading of a single-sampled G-buffer. On the offset-pass path the G-buffer already
// holds one texel per sample in the sample layout, so each texel of the shade resolve target
// shades its own texel (fs_shade_samples). The full-resolution baseline deferred checkerboarding
// is measured against shades every pixel's centre with the same G-buffer and lighting
// (fs_shade_full_resolution; fs_shade_full_resolution_turned where that G-buffer is turned a
// quarter, upright pixel (x, y) at texel (y, W − 1 − x)), so that the two differ only in the
// pixels shaded.

@group(0) @binding(0) var<uniform> shading: SampleShading;
@group(0) @binding(1) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(2) var gbuffer_albedo: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_depth: texture_2d<f32>;
@group(0) @binding(4) var lights: texture_2d<f32>;

struct GbufferTexel {
    normal: vec4f,
    albedo: vec4f,
    depth: f32,
}

fn gbuffer_at(texel: vec2i) -> GbufferTexel {
    return GbufferTexel(
        textureLoad(gbuffer_normal, texel, 0),
        textureLoad(gbuffer_albedo, texel, 0),
        textureLoad(gbuffer_depth, texel, 0).r,
    );
}

@fragment
fn fs_shade_samples(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let texel = vec2i(position.xy);
    let g = gbuffer_at(texel);
    return shade_layout_texel(shading, texel, g.normal, g.albedo, g.depth, lights);
}

@fragment
fn fs_shade_full_resolution(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let g = gbuffer_at(vec2i(position.xy));
    return shade_at(shading, position.xy, g.normal, g.albedo, g.depth, lights);
}

@fragment
fn fs_shade_full_resolution_turned(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let g = gbuffer_at(vec2i(position.xy));
    let upright = vec2f(shading.screen.x - position.y, position.x);
    return shade_at(shading, upright, g.normal, g.albedo, g.depth, lights);
}
