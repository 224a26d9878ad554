// One level up a bitmask pyramid: texel q ORs the children 2q + {0,1}^2 of the finer level that
// lie inside it (odd sizes have a missing last row or column). The stencil marks read the
// finished pyramid (stencil_mark.wgsl).

@group(0) @binding(0) var finer: texture_2d<u32>;

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

