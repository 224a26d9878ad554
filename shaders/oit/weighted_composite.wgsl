// Weighted blended OIT, composite over the opaque background: colour = accumulated / weight,
// coverage = 1 - revealage.

@group(0) @binding(0) var accumulation: texture_2d<f32>;
@group(0) @binding(1) var revealage: texture_2d<f32>;

@fragment
fn fs_weighted_composite(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let pixel = vec2u(position.xy);
    let sum = textureLoad(accumulation, pixel, 0);
    let revealed = textureLoad(revealage, pixel, 0).r;
    let average = sum.rgb / max(sum.a, 1e-5);
    return vec4f(average * (1.0 - revealed), 1.0 - revealed);
}
