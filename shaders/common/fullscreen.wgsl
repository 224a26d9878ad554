// One triangle that covers the whole target: vertices (-1,-1), (3,-1), (-1,3).
fn fullscreen_clip_position(vertex_index: u32) -> vec4f {
    let uv = vec2f(f32((vertex_index << 1u) & 2u), f32(vertex_index & 2u));
    return vec4f(uv * 2.0 - 1.0, 0.0, 1.0);
}
