// Temporal accumulation: the running mean of the frames so far, where the new frame's colour is
// within `tolerance` of the history (a static scene keeps accumulating); elsewhere the history
// restarts from the new frame (motion).

struct Temporal {
    frames_so_far: u32,
    tolerance: f32,
}

@group(0) @binding(0) var<uniform> temporal: Temporal;
@group(0) @binding(1) var current: texture_2d<f32>;
@group(0) @binding(2) var history: texture_2d<f32>;

@fragment
fn fs_temporal(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let pixel = vec2u(position.xy);
    let now = textureLoad(current, pixel, 0);
    if temporal.frames_so_far == 0u {
        return now;
    }
    let before = textureLoad(history, pixel, 0);
    if any(abs(now.rgb - before.rgb) > vec3f(temporal.tolerance)) {
        return now;
    }
    return before + (now - before) / f32(temporal.frames_so_far + 1u);
}
