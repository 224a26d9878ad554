// Per-sample shading probe: using `sample_index` makes the fragment shader run once per sample.
// Writes which sample ran and what `@builtin(position)` said, so the kit can tell whether the
// driver reports sample locations or pixel centres.

@fragment
fn fs_sample_position(@builtin(position) position: vec4f, @builtin(sample_index) sample_index: u32) -> @location(0) vec4f {
    return vec4f(fract(position.xy), f32(sample_index + 1u) / 16.0, 1.0);
}
