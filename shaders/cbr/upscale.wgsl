// The baseline checkerboarding is measured against: a quarter-resolution image (one sample per
// 2×2 pixels, rendered with the phase-0 quarter projection) upscaled bilinearly to full size.

struct Upscale {
    screen: vec2f,
    quarter: vec2f,
}

@group(0) @binding(0) var<uniform> upscale: Upscale;
@group(0) @binding(1) var half_resolution: texture_2d<f32>;
@group(0) @binding(2) var bilinear: sampler;

@fragment
fn fs_upscale(@builtin(position) position: vec4f) -> @location(0) vec4f {
    // Full-resolution x maps to quarter-resolution x / 2 (odd sizes included).
    let uv = position.xy * 0.5 / upscale.quarter;
    return textureSampleLevel(half_resolution, bilinear, uv, 0.0);
}
