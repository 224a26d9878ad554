// A 2D texture used as a 1D array, fetched four ways; pixel i of the result looks up element
// `indices[i]` and writes the element's value (its index, stored in the texel's four bytes).
//   0 integer:     array_texel (shaders/common/lighting.wgsl, the renderer's own fetch):
//                  textureLoad at (k mod w, k div w)
//   1 divide:      y = floor(k / w), x = k - y w, sampled at the texel centre
//   2 reciprocal:  t = k (1/w); x from fract(t), y from floor(t)
//   3 one multiply: uv = (1/w, 1/(w h)) (k + 0.5), relying on repeat addressing and nearest filtering
// The float variants take k as f32, so they are only as exact as f32 and the sampler allow.

struct Fetch {
    variant: u32,
    count: u32,
    list_width: u32,
}

@group(0) @binding(0) var<uniform> fetch: Fetch;
@group(0) @binding(1) var elements: texture_2d<f32>;
@group(0) @binding(2) var nearest_repeat: sampler;
@group(0) @binding(3) var indices: texture_2d<u32>;

fn decode(texel: vec4f) -> u32 {
    let bytes = vec4u(round(texel * 255.0));
    return bytes.x | (bytes.y << 8u) | (bytes.z << 16u) | (bytes.w << 24u);
}

@fragment
fn fs_fetch(@builtin(position) position: vec4f) -> @location(0) u32 {
    let slot = vec2u(position.xy);
    if slot.y * fetch.list_width + slot.x >= fetch.count {
        return 0u;
    }
    let k = textureLoad(indices, slot, 0).x;
    let size = textureDimensions(elements);
    let w = f32(size.x);
    let h = f32(size.y);
    let kf = f32(k);
    var texel: vec4f;
    switch fetch.variant {
        case 0u: {
            texel = array_texel(elements, k);
        }
        case 1u: {
            let y = floor(kf / w);
            let x = kf - y * w;
            texel = textureSampleLevel(elements, nearest_repeat, (vec2f(x, y) + 0.5) / vec2f(w, h), 0.0);
        }
        case 2u: {
            let t = kf * (1.0 / w);
            let x = floor(fract(t) * w + 0.5);
            texel = textureSampleLevel(elements, nearest_repeat, (vec2f(x, floor(t)) + 0.5) / vec2f(w, h), 0.0);
        }
        default: {
            texel = textureSampleLevel(elements, nearest_repeat, vec2f(1.0 / w, 1.0 / (w * h)) * (kf + 0.5), 0.0);
        }
    }
    return decode(texel);
}
