// Alpha-to-coverage probe: column x of a (steps + 1)-wide target outputs alpha x / steps, so one
// draw sweeps the whole alpha range.

struct AlphaRamp {
    steps: f32,
}

@group(0) @binding(0) var<uniform> ramp: AlphaRamp;

@fragment
fn fs_alpha_ramp(@builtin(position) position: vec4f) -> @location(0) vec4f {
    return vec4f(1.0, 1.0, 1.0, floor(position.x) / ramp.steps);
}
