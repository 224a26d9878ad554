// Stochastic transparency with an exact coverage pattern (Enderton et al.): k = floor(N a + u)
// samples (E[k] = N a, stratified), a run of k samples starting at a random one, written through
// @builtin(sample_mask) instead of alpha-to-coverage, so no adapter quantisation is involved.

struct MaskParams {
    samples: u32,
}

@group(0) @binding(0) var<uniform> params: MaskParams;
@group(0) @binding(1) var noise: texture_2d<u32>;

struct MaskedFragment {
    @location(0) colour: vec4f,
    @builtin(sample_mask) mask: u32,
}

@fragment
fn fs_sample_mask(in: QuadVarying) -> MaskedFragment {
    let alpha = sanitized_alpha(in.alpha);
    let n = textureLoad(noise, vec2u(in.position.xy), 0).x;
    let count = params.samples;
    let k = min(u32(floor(alpha * f32(count) + fragment_random(n, in.position.z, in.id, 1u))), count);
    let start = min(u32(fragment_random(n, in.position.z, in.id, 2u) * f32(count)), count - 1u);
    let run = select((1u << k) - 1u, 0xffffffffu, k >= 32u);
    let full = (1u << count) - 1u;
    let mask = ((run << start) | (run >> (count - start))) & full;
    return MaskedFragment(vec4f(in.colour, 1.0), mask);
}
