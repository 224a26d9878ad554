// The stencil pyramid in its atlas: each level's marks (one draw a level, its viewport the
// level's rect, or under the foveated policy one draw of every level's spans) mark (op Replace)
// the texels some pixel of whose block uses that level, and discard the others; the draws open the lighting
// pass (cps/lighting.wgsl), whose stencil-Equal draws follow them. This stands in for stencil
// export, which wgpu (and NVIDIA's GL) lack.
//
// In general the levels a block uses come from the LOD-present mask pyramid, built before the
// pass. It holds the even mips only: an even level reads its own mip, an odd one ORs its 2×2
// children in the even mip below (its own entry point: a branch on the level would run both sides
// on a CPU rasteriser). Under the foveated policy they follow from the block's geometry instead
// (fs_stencil_mark_foveated), and no pyramid is built; one pipeline serves every level, so all
// the levels' marks are one draw over every level's spans: lavapipe pays about as much for a draw
// as for a few hundred marked texels.

struct AtlasLevel {
    level: u32,
    origin_x: u32,
    origin_y: u32,
}

@group(0) @binding(0) var mask: texture_2d<u32>;
@group(0) @binding(1) var<uniform> target_level: AtlasLevel;

@group(0) @binding(2) var<uniform> marks: FoveatedBlocks;

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

// Under the foveated policy a block's levels follow from its geometry
// (common/foveation.wgsl's foveated_block_has_level). Drawn as rects (kit/src/rects.rs,
// shaders/kit/rect.wgsl) over every level's spans in the atlas (cps/level_spans.rs), the level in
// the rect's colour (red; constant across the rect, rounded).
@fragment
fn fs_stencil_mark_foveated(@builtin(position) position: vec4f, @location(0) level_in_red: vec4f) {
    let level = u32(round(level_in_red.r));
    let texel = vec2u(position.xy) - marks.origins[level].xy;
    if !foveated_block_has_level(texel, level, marks) {
        discard;
    }
}
