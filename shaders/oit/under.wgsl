// Depth peeling, accumulation: the peeled layer goes under what is already accumulated
// (front to back): C += (1 - A) c, A += (1 - A) a, by the blend state. This pass just forwards
// the layer's premultiplied texel.

@group(0) @binding(0) var layer: texture_2d<f32>;

@fragment
fn fs_under(@builtin(position) position: vec4f) -> @location(0) vec4f {
    return textureLoad(layer, vec2u(position.xy), 0);
}
