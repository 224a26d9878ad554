// The sub-pixel precision probe (kit/src/probe/subpixel_precision.rs). Instance k draws a quad over
// pixel columns 2k and 2k + 1 of a 512×256 target whose left edge runs from (2k + f, 0) down to
// (2k + f + 1, 256), f = (k + 1/4) / 256: off the half steps, which a round-half-even snap would
// send only to even grid points. Both left vertices have the fractional x f, which the rasteriser
// snaps to its sub-pixel grid; every other coordinate is an integer that no snapping moves. Row
// r's pixel centres then see the edge at 2k + snapped(f) + (r + 1/2) / 256, so the two columns'
// covered pixels count 256 (3/2 − snapped(f)).

const WIDTH: f32 = 512.0;
const HEIGHT: f32 = 256.0;
const OFFSETS: f32 = 256.0;

@vertex
fn vs_sloped_edge(@builtin(vertex_index) vertex: u32, @builtin(instance_index) k: u32) -> @builtin(position) vec4f {
    let left = 2.0 * f32(k) + (f32(k) + 0.25) / OFFSETS;
    let right = 2.0 * f32(k) + 2.0;
    // Top-left, top-right, bottom-right; top-left, bottom-right, bottom-left.
    var corners = array<vec2f, 6>(
        vec2f(left, 0.0),
        vec2f(right, 0.0),
        vec2f(right, HEIGHT),
        vec2f(left, 0.0),
        vec2f(right, HEIGHT),
        vec2f(left + 1.0, HEIGHT),
    );
    let p = corners[vertex];
    // Power-of-two target: the viewport transform gives these pixel coordinates back exactly.
    return vec4f(p.x / WIDTH * 2.0 - 1.0, 1.0 - p.y / HEIGHT * 2.0, 0.0, 1.0);
}

@fragment
fn fs_sloped_edge() -> @location(0) vec4f {
    return vec4f(1.0);
}
