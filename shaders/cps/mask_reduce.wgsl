// One level up a bitmask pyramid: texel q ORs the children 2q + {0,1}^2 of the finer level that
// lie inside it (odd sizes have a missing last row or column). In the LOD-present pyramid the
// same pass also builds level l's stencil: a second draw, which cannot read the mask it is
// writing, ORs the same children and marks (op Replace) where bit l is set, discarding
// elsewhere. This stands in for stencil export, which wgpu (and NVIDIA's GL) lack.

struct Level {
    level: u32,
}

@group(0) @binding(0) var finer: texture_2d<u32>;
@group(0) @binding(1) var<uniform> target_level: Level;

fn or_children(q: vec2u) -> u32 {
    let size = textureDimensions(finer);
    var bits = 0u;
    for (var dy = 0u; dy < 2u; dy++) {
        for (var dx = 0u; dx < 2u; dx++) {
            let child = 2u * q + vec2u(dx, dy);
            if child.x < size.x && child.y < size.y {
                bits |= textureLoad(finer, child, 0).x;
            }
        }
    }
    return bits;
}

@fragment
fn fs_mask_reduce(@builtin(position) position: vec4f) -> @location(0) u32 {
    return or_children(vec2u(position.xy));
}

@fragment
fn fs_stencil_mark(@builtin(position) position: vec4f) {
    if ((or_children(vec2u(position.xy)) >> target_level.level) & 1u) == 0u {
        discard;
    }
}
