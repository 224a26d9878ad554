// Content LOD policy, step 2: the coarsest level l whose aligned 2^l block around the pixel
// holds no edge, read from the OR-reduced edge pyramid (edge_pyramid mip l, texel pixel >> l).

struct ContentLod {
    max_level: u32,
}

@group(0) @binding(0) var<uniform> content: ContentLod;
@group(0) @binding(1) var edge_pyramid: texture_2d<u32>;

@fragment
fn fs_lod_content(@builtin(position) position: vec4f) -> @location(0) u32 {
    let pixel = vec2u(position.xy);
    var level = 0u;
    for (var l = 1u; l <= content.max_level; l++) {
        if textureLoad(edge_pyramid, pixel >> vec2u(l), i32(l)).x != 0u {
            break;
        }
        level = l;
    }
    return level;
}
