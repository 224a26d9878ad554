// Depth peeling, one layer: the nearest fragment behind the previous layer, ordered by
// (depth, primitive) so layers at equal depth are peeled one by one. The previous layer's key
// (depth bits, primitive) arrives in an Rg32Uint texture (depth textures cannot be read on every
// backend); the depth test then keeps the nearest remaining fragment.

@group(0) @binding(0) var previous_key: texture_2d<u32>;

struct PeeledLayer {
    @location(0) colour: vec4f,
    @location(1) key: vec2u,
}

@fragment
fn fs_peel(in: QuadVarying) -> PeeledLayer {
    let previous = textureLoad(previous_key, vec2u(in.position.xy), 0).xy;
    let depth = bitcast<u32>(in.position.z);
    // Positive floats order like their bits.
    if depth < previous.x || (depth == previous.x && in.id + 1u <= previous.y) {
        discard;
    }
    let alpha = sanitized_alpha(in.alpha);
    return PeeledLayer(vec4f(in.colour * alpha, alpha), vec2u(depth, in.id + 1u));
}
