// One triangle that covers the whole target: vertices (-1,-1), (3,-1), (-1,3).
fn fullscreen_clip_position(vertex_index: u32) -> vec4f {
    let uv = vec2f(f32((vertex_index << 1u) & 2u), f32(vertex_index & 2u));
    return vec4f(uv * 2.0 - 1.0, 0.0, 1.0);
}

// Set by a pipeline whose adapter reads a wrong level when a fetch's level differs between the
// lanes of one SIMD vector (GL llvmpipe; probed by fragkit::probe::mip_fetch): every fetch at a
// per-pixel level then loops over the levels, so that each fetch's level is uniform across lanes.
override LOOP_COUNTER_FETCH: bool = false;

// Texel `texel` of mip `level` of `image`, `level` possibly chosen per pixel. Levels are passed to
// textureLoad as i32: naga's GLSL output bounds-checks loads with textureSize(image, level),
// which GLSL only has for int levels.
fn load_at_level(image: texture_2d<f32>, texel: vec2i, level: u32) -> vec4f {
    if !LOOP_COUNTER_FETCH {
        return textureLoad(image, texel, i32(level));
    }
    var value = vec4f(0.0);
    for (var l = 0u; l < textureNumLevels(image); l++) {
        if l == level {
            value = textureLoad(image, texel, i32(l));
        }
    }
    return value;
}

// Bilinear interpolation of mip `level` at continuous texel coordinate `at` (texel centres at
// integers), clamped to the texels 0..=last that hold data (mip chains are padded); by loads,
// so it is exact and filter-free.
fn bilinear_load(image: texture_2d<f32>, level: u32, at: vec2f, last: vec2i) -> vec4f {
    let base = floor(at);
    let f = at - base;
    let t0 = clamp(vec2i(base), vec2i(0), last);
    let t1 = clamp(vec2i(base) + 1, vec2i(0), last);
    let a = load_at_level(image, vec2i(t0.x, t0.y), level);
    let b = load_at_level(image, vec2i(t1.x, t0.y), level);
    let c = load_at_level(image, vec2i(t0.x, t1.y), level);
    let d = load_at_level(image, vec2i(t1.x, t1.y), level);
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}
