// A full-resolution image rasterised turned a quarter (QUARTER_TURN in kit/src/cbr/sampling.rs,
// as the offset passes draw their views), turned back upright: upright pixel (x, y) is texel
// (y, W − 1 − x) of the turned image, which is H wide and W tall.

@group(0) @binding(0) var turned: texture_2d<f32>;

@fragment
fn fs_turn_back(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let p = vec2i(position.xy);
    let width = i32(textureDimensions(turned).y);
    return textureLoad(turned, vec2i(p.y, width - 1 - p.x), 0);
}
