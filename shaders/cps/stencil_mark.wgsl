// The stencil pyramid in its atlas: one draw a level, its viewport the level's rect, marks (op
// Replace) the texels whose LOD-present mask has the level's bit — some pixel of the texel's
// block uses that level — and discards the others. All levels in one pass, after the mask
// pyramid is built; this stands in for stencil export, which wgpu (and NVIDIA's GL) lack.

struct AtlasLevel {
    level: u32,
    origin_x: u32,
    origin_y: u32,
}

@group(0) @binding(0) var mask: texture_2d<u32>;
@group(0) @binding(1) var<uniform> target_level: AtlasLevel;

@fragment
fn fs_stencil_mark(@builtin(position) position: vec4f) {
    let q = vec2u(position.xy) - vec2u(target_level.origin_x, target_level.origin_y);
    // The level is uniform across the draw: a direct fetch is exact on every adapter.
    if ((textureLoad(mask, q, i32(target_level.level)).x >> target_level.level) & 1u) == 0u {
        discard;
    }
}
