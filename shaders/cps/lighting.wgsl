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
// Under the foveated policy (fs_light_level_foveated).
@group(1) @binding(1) var<uniform> blocks: FoveatedBlocks;

@fragment
fn fs_light_level(@builtin(position) position: vec4f) -> @location(0) vec4f {
    return light_texel(vec2u(position.xy) - vec2u(target_level.origin_x, target_level.origin_y));
}

// Under the foveated policy the texel's levels are its block's geometry: the rule the stencil
// marks follow decides again before the shading, so an adapter that tests the stencil only after
// the fragment shader (SwiftShader: kit.early_rejection 1.01×) skips the lights of a texel the
// stencil will reject, as early stencil rejection does. The stencil still decides what is written.
@fragment
fn fs_light_level_foveated(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let q = vec2u(position.xy) - vec2u(target_level.origin_x, target_level.origin_y);
    if !foveated_block_has_level(q, target_level.level, blocks) {
        return vec4f(0.0);
    }
    return light_texel(q);
}

fn light_texel(q: vec2u) -> vec4f {
    let block = 1u << target_level.level;
    let pixel = min(q * block + vec2u(block / 2u), textureDimensions(gbuffer_position) - 1u);
    let colour = shade_gbuffer_pixel(gbuffer_position, gbuffer_normal, gbuffer_albedo, pixel, shading.eye, lights, shading.light_count);
    return vec4f(colour, 1.0);
}
