// The 2x path's sample placement probe: each per-sample invocation records which full-resolution
// pixel's rect covered it (the rect's colour encodes its pixel: x in red/green, y in blue/alpha
// bytes) at (quarter pixel, sample_index), so the kit reads where every sample of a real 2x
// target landed without resolves or @builtin(position).

struct Grid {
    quarter_width: u32,
}

@group(0) @binding(0) var<uniform> grid: Grid;
@group(0) @binding(1) var<storage, read_write> landed: array<u32>;

@fragment
fn fs_record_sample_pixel(@builtin(position) position: vec4f, @builtin(sample_index) sample_index: u32, @location(0) colour: vec4f) {
    let q = vec2u(position.xy);
    let bytes = vec4u(round(colour * 255.0));
    landed[(q.y * grid.quarter_width + q.x) * 2u + min(sample_index, 1u)] = bytes.x | (bytes.y << 8u) | (bytes.z << 16u) | (bytes.w << 24u);
}
