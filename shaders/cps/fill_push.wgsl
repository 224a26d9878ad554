// Seam-free composite, step 2 (push, coarse to fine): a texel with nothing after the pull takes
// the bilinear interpolation of the filled coarser level at its centre, so every level is
// complete and bilinear reconstruction never reads an unshaded texel.

struct Extent {
    // Last texel of the coarser level that holds data.
    coarser_last: vec2u,
}

@group(0) @binding(0) var pulled_level: texture_2d<f32>;
@group(0) @binding(1) var filled_coarser: texture_2d<f32>;
@group(0) @binding(2) var<uniform> extent: Extent;

@fragment
fn fs_fill_push(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let q = vec2u(position.xy);
    let own = textureLoad(pulled_level, q, 0);
    if own.a == 1.0 {
        return own;
    }
    // Texel q's centre in the coarser level's texel coordinates: (q + 0.5) / 2 - 0.5.
    return vec4f(bilinear_load(filled_coarser, 0u, (vec2f(q) + 0.5) * 0.5 - 0.5, vec2i(extent.coarser_last)).rgb, 1.0);
}
