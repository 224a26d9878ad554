// Fetches from a mipmapped texture at a level chosen per pixel (read from a level map): mip l
// texel t holds (1 << 31) | (l << 24) | (t.y << 12) | t.x, so the value says which level and
// texel a fetch really read (0: none). Two ways: the level straight from the map (it varies
// across a SIMD vector, as in the CPS composite), and the level as a loop counter (uniform in
// every lane).

// A bound on any texture's mip count (2^15 texels a side at most): the loop needs no
// textureNumLevels, which GLSL ES has no counterpart of (GLES 3.x, WebGL2).
const MAX_LEVELS = 16u;

@group(0) @binding(0) var level_map: texture_2d<u32>;
@group(0) @binding(1) var source: texture_2d<u32>;

@fragment
fn fs_fetch_varying_level(@builtin(position) position: vec4f) -> @location(0) u32 {
    let p = vec2u(position.xy);
    let level = textureLoad(level_map, p, 0).x;
    return textureLoad(source, p >> vec2u(level), i32(level)).x;
}

@fragment
fn fs_fetch_uniform_level(@builtin(position) position: vec4f) -> @location(0) u32 {
    let p = vec2u(position.xy);
    let level = textureLoad(level_map, p, 0).x;
    var value = 0u;
    for (var l = 0u; l < MAX_LEVELS; l++) {
        if l == level {
            value = textureLoad(source, p >> vec2u(l), i32(l)).x;
        }
    }
    return value;
}
