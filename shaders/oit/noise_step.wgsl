// Ping-pong noise: this frame's screen-size noise texture is the hash of last frame's, so every
// pixel of every frame gets a fresh, seeded number without a CPU upload.

struct NoiseStep {
    frame: u32,
}

@group(0) @binding(0) var<uniform> step: NoiseStep;
@group(0) @binding(1) var previous: texture_2d<u32>;

@fragment
fn fs_noise_step(@builtin(position) position: vec4f) -> @location(0) u32 {
    return pcg_hash(textureLoad(previous, vec2u(position.xy), 0).x ^ pcg_hash(step.frame));
}
