// The stencil pyramid in its atlas: one draw a level, its viewport the level's rect, marks (op
// Replace) the texels whose LOD-present mask has the level's bit — some pixel of the texel's
// block uses that level — and discards the others. All levels in one pass, after the mask
// pyramid is built; this stands in for stencil export, which wgpu (and NVIDIA's GL) lack. The
// pyramid holds the even mips only: an even level reads its own mip, an odd one ORs its 2×2
// children in the even mip below (its own entry point: a branch on the level would run both
// sides on a CPU rasteriser).

struct AtlasLevel {
    level: u32,
    origin_x: u32,
    origin_y: u32,
}

@group(0) @binding(0) var mask: texture_2d<u32>;
@group(0) @binding(1) var<uniform> target_level: AtlasLevel;

fn texel_of_level(position: vec4f) -> vec2u {
    return vec2u(position.xy) - vec2u(target_level.origin_x, target_level.origin_y);
}

fn mark_if(bits: u32) {
    if ((bits >> target_level.level) & 1u) == 0u {
        discard;
    }
}

// The level is uniform across the draw: a direct fetch at it is exact on every adapter.
@fragment
fn fs_stencil_mark_even(@builtin(position) position: vec4f) {
    mark_if(textureLoad(mask, texel_of_level(position), i32(target_level.level)).x);
}

@fragment
fn fs_stencil_mark_odd(@builtin(position) position: vec4f) {
    let below = i32(target_level.level) - 1;
    let size = textureDimensions(mask, below);
    let q = texel_of_level(position);
    var bits = 0u;
    for (var dy = 0u; dy < 2u; dy++) {
        for (var dx = 0u; dx < 2u; dx++) {
            let child = 2u * q + vec2u(dx, dy);
            if child.x < size.x && child.y < size.y {
                bits |= textureLoad(mask, child, below).x;
            }
        }
    }
    mark_if(bits);
}
