// Up a bitmask pyramid: texel q ORs its children in a finer mip that lie inside it (odd sizes
// have a missing last row or column) — the 2×2 children one mip down (the edge pyramid, whose
// every mip the content policy reads), or the 4×4 two mips down (the LOD-present pyramid, whose
// odd mips the stencil marks OR from the even mip below: half the passes). The stencil marks
// read the finished pyramid (stencil_mark.wgsl).

@group(0) @binding(0) var finer: texture_2d<u32>;

fn or_children(q: vec2u, side: u32) -> u32 {
    let size = textureDimensions(finer);
    var bits = 0u;
    for (var dy = 0u; dy < side; dy++) {
        for (var dx = 0u; dx < side; dx++) {
            let child = side * q + vec2u(dx, dy);
            if child.x < size.x && child.y < size.y {
                bits |= textureLoad(finer, child, 0).x;
            }
        }
    }
    return bits;
}

@fragment
fn fs_mask_reduce(@builtin(position) position: vec4f) -> @location(0) u32 {
    return or_children(vec2u(position.xy), 2u);
}

@fragment
fn fs_mask_reduce_two_levels(@builtin(position) position: vec4f) -> @location(0) u32 {
    return or_children(vec2u(position.xy), 4u);
}
