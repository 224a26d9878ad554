// The checkerboard layout functions of shaders/common/checkerboard.wgsl — the ones the
// reconstruction and the deferred shade passes call — evaluated everywhere, for
// kit/src/cbr/layout_values.rs to compare with the sample placement's definition:
// fs_texel_of_pixel over the full-resolution screen writes checkerboard_texel (-1 where the phase
// has no sample), fs_centre_of_texel over the sample layout writes layout_pixel_centre's bits.

struct Layout {
    quarter: vec2i,
    phase: i32,
}

@group(0) @binding(0) var<uniform> mapping: Layout;

@fragment
fn fs_texel_of_pixel(@builtin(position) position: vec4f) -> @location(0) vec4i {
    return vec4i(checkerboard_texel(vec2i(position.xy), mapping.phase, mapping.quarter), 0, 0);
}

// The centre's f32 bits, as integers: 32-bit float targets are not renderable everywhere (GL).
@fragment
fn fs_centre_of_texel(@builtin(position) position: vec4f) -> @location(0) vec4i {
    return vec4i(bitcast<vec2i>(layout_pixel_centre(vec2i(position.xy), mapping.quarter, mapping.phase)), 0, 0);
}
