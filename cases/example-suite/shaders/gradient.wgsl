// A full-screen triangle whose colour is the pixel's place on the target: red the x of its
// centre over the width, green the y over the height, blue a constant quarter.

struct Target {
    size: vec2f,
}

@group(0) @binding(0) var<uniform> target_size: Target;

@vertex
fn vs(@builtin(vertex_index) index: u32) -> @builtin(position) vec4f {
    // (-1, -1), (3, -1), (-1, 3): one triangle covering the target.
    let corner = vec2f(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4f(corner * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs(@builtin(position) centre: vec4f) -> @location(0) vec4f {
    return vec4f(centre.xy / target_size.size, 0.25, 1.0);
}
