// Seam-free composite, step 1 (pull, fine to coarse): a texel keeps its own shading where it was
// lit (alpha 1); otherwise it takes the mean of its lit or pulled children; alpha 0 where none
// of them holds anything.

@group(0) @binding(0) var lit_level: texture_2d<f32>;
@group(0) @binding(1) var pulled_finer: texture_2d<f32>;

@fragment
fn fs_fill_pull(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let q = vec2u(position.xy);
    let own = textureLoad(lit_level, q, 0);
    if own.a == 1.0 {
        return own;
    }
    let size = textureDimensions(pulled_finer);
    var sum = vec3f(0.0);
    var count = 0.0;
    for (var dy = 0u; dy < 2u; dy++) {
        for (var dx = 0u; dx < 2u; dx++) {
            let child = 2u * q + vec2u(dx, dy);
            if child.x < size.x && child.y < size.y {
                let texel = textureLoad(pulled_finer, child, 0);
                if texel.a == 1.0 {
                    sum += texel.rgb;
                    count += 1.0;
                }
            }
        }
    }
    return select(vec4f(0.0), vec4f(sum / max(count, 1.0), 1.0), count > 0.0);
}
