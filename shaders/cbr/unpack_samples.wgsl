// 2x path: copies each sample of a 2x target into the sample layout (single-sampled, each
// sample's view turned a quarter into its half), so that the reconstruction reads both paths'
// frames alike. Colour-like targets through `fs_unpack_colour`, depth through `fs_unpack_depth`
// into a depth attachment.

struct Layout {
    quarter: vec2i,
}

@group(0) @binding(0) var<uniform> sample_layout: Layout;
@group(0) @binding(1) var samples: texture_multisampled_2d<f32>;
@group(0) @binding(2) var depth_samples: texture_multisampled_2d<f32>;

@fragment
fn fs_unpack_colour(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let at = layout_sample(vec2i(position.xy), sample_layout.quarter);
    return textureLoad(samples, at.xy, at.z);
}

@fragment
fn fs_unpack_depth(@builtin(position) position: vec4f) -> @builtin(frag_depth) f32 {
    let at = layout_sample(vec2i(position.xy), sample_layout.quarter);
    return textureLoad(depth_samples, at.xy, at.z).r;
}
