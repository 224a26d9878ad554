// Lighting of one level behind its stencil (Equal: early stencil rejection skips every texel no
// pixel needs); every level is one draw of one pass, its viewport the level's rect of the atlas.
// Coarse texel q of level l shades the G-buffer sample at the centre pixel of its 2^l block
// (clamped to the screen); at level 0 that is the pixel itself, as at full resolution. Alpha 1
// marks a shaded texel.

struct Shading {
    eye: vec3f,
    light_count: u32,
}

// The level and where its texels start in the lit and stencil atlases.
struct AtlasLevel {
    level: u32,
    origin_x: u32,
    origin_y: u32,
}

@group(0) @binding(0) var<uniform> shading: Shading;
@group(0) @binding(1) var gbuffer_position: texture_2d<u32>;
@group(0) @binding(2) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_albedo: texture_2d<f32>;
@group(0) @binding(4) var lights: texture_2d<f32>;
@group(1) @binding(0) var<uniform> target_level: AtlasLevel;

@fragment
fn fs_light_level(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let q = vec2u(position.xy) - vec2u(target_level.origin_x, target_level.origin_y);
    let block = 1u << target_level.level;
    let pixel = min(q * block + vec2u(block / 2u), textureDimensions(gbuffer_position) - 1u);
    let colour = shade_gbuffer_pixel(gbuffer_position, gbuffer_normal, gbuffer_albedo, pixel, shading.eye, lights, shading.light_count);
    return vec4f(colour, 1.0);
}
