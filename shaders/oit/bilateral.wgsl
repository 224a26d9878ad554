// Bilateral filter, 5×5: neighbours weighted by distance (Gaussian, sigma 1.5 px) and by colour
// difference (Gaussian, sigma `range_sigma`), so noise is smoothed and edges are kept.

struct Bilateral {
    range_sigma: f32,
}

@group(0) @binding(0) var<uniform> bilateral: Bilateral;
@group(0) @binding(1) var image: texture_2d<f32>;

@fragment
fn fs_bilateral(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let centre = vec2i(position.xy);
    let last = vec2i(textureDimensions(image)) - 1;
    let own = textureLoad(image, centre, 0);
    var sum = vec4f(0.0);
    var weights = 0.0;
    for (var dy = -2; dy <= 2; dy++) {
        for (var dx = -2; dx <= 2; dx++) {
            let texel = textureLoad(image, clamp(centre + vec2i(dx, dy), vec2i(0), last), 0);
            let difference = texel.rgb - own.rgb;
            let spatial = f32(dx * dx + dy * dy) / (2.0 * 1.5 * 1.5);
            let range = dot(difference, difference) / (2.0 * bilateral.range_sigma * bilateral.range_sigma);
            let weight = exp(-spatial - range);
            sum += texel * weight;
            weights += weight;
        }
    }
    return sum / weights;
}
