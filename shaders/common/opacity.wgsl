// What the OIT quad vertex stage (shaders/oit/quad.wgsl) hands every OIT fragment stage.
struct QuadVarying {
    @builtin(position) position: vec4f,
    @location(0) colour: vec3f,
    @location(1) @interpolate(flat) alpha: f32,
    @location(2) @interpolate(flat) id: u32,
}

// Opacity as the OIT passes read it: NaN counts as 0 (transparent) and values are clamped to
// 0..1, so no pass ever evaluates 1 / 0 or pow(0, 0).
fn sanitized_alpha(alpha: f32) -> f32 {
    if !(alpha > 0.0) {
        return 0.0;
    }
    return min(alpha, 1.0);
}

// The per-fragment uniform numbers of stochastic transparency, in (0, 1]: this frame's noise
// texel, the fragment's depth bits and the primitive, hashed together.
fn fragment_random(noise: u32, depth: f32, id: u32, stream: u32) -> f32 {
    let h = pcg_hash(noise ^ pcg_hash(bitcast<u32>(depth) ^ pcg_hash(id * 2654435769u + stream)));
    return (f32(h >> 8u) + 0.5) * (1.0 / 16777216.0);
}
