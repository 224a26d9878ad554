// Stochastic transparency by alpha-to-coverage: a fragment of opacity a outputs alpha f^g with
// g = 1/a - 1 and f uniform in (0, 1], so E[f^g] = a. With `correct` set, the adapter's
// quantised coverage is unbiased too: k = floor(N f^g + u) samples (E[k] = N a) through the
// alpha that this adapter maps to exactly k covered samples (measured, in `exact_alpha`).

struct Stochastic {
    correct: u32,
    samples: u32,
    exact_alpha: array<vec4f, 3>,
}

@group(0) @binding(0) var<uniform> params: Stochastic;
@group(0) @binding(1) var noise: texture_2d<u32>;

@fragment
fn fs_stochastic(in: QuadVarying) -> @location(0) vec4f {
    let alpha = sanitized_alpha(in.alpha);
    if alpha == 0.0 {
        discard;
    }
    var out_alpha = 1.0;
    if alpha < 1.0 {
        let n = textureLoad(noise, vec2u(in.position.xy), 0).x;
        let f = fragment_random(n, in.position.z, in.id, 0u);
        out_alpha = pow(f, 1.0 / alpha - 1.0);
        if params.correct == 1u {
            let u = fragment_random(n, in.position.z, in.id, 1u);
            let k = min(u32(floor(out_alpha * f32(params.samples) + u)), params.samples);
            out_alpha = params.exact_alpha[k / 4u][k % 4u];
        }
    }
    return vec4f(in.colour, out_alpha);
}
