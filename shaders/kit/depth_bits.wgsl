// A depth texture's values as their f32 bits, for adapters that cannot copy depth to a buffer
// (GL: no DEPTH_TEXTURE_AND_BUFFER_COPIES); read by `readback::read_depth`. Depth is bound as
// unfilterable float (`.r`): naga's GLSL output has no textureLoad on depth textures.

@group(0) @binding(0) var depth: texture_2d<f32>;

@fragment
fn fs_depth_bits(@builtin(position) position: vec4f) -> @location(0) u32 {
    return bitcast<u32>(textureLoad(depth, vec2u(position.xy), 0).r);
}
