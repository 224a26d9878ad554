// Composite: every pixel takes its colour from the lit mip its LOD names. Three modes:
// nearest (plain CPS), the original method's 4-neighbour interpolation, and our seam-free
// bilinear reconstruction over the pull-push filled pyramid.

struct Composite {
    max_level: u32,
    screen: vec2u,
}

@group(0) @binding(0) var<uniform> composite: Composite;
@group(0) @binding(1) var lod: texture_2d<u32>;
@group(0) @binding(2) var lit: texture_2d<f32>;

fn level_of(pixel: vec2i) -> u32 {
    let clamped = vec2u(clamp(pixel, vec2i(0), vec2i(composite.screen) - 1));
    return min(textureLoad(lod, clamped, 0).x, composite.max_level);
}

// The shading a pixel gets under nearest composition (its own coarse texel).
fn coarse_colour(pixel: vec2i) -> vec4f {
    let clamped = vec2u(clamp(pixel, vec2i(0), vec2i(composite.screen) - 1));
    let level = level_of(pixel);
    return textureLoad(lit, clamped >> vec2u(level), level);
}

// The pixel just outside the coarse fragment holding `pixel`, along `axis` (0 = x, 1 = y), on the
// side of `direction` (-1 or +1).
fn beyond_fragment(pixel: vec2i, axis: u32, direction: i32) -> vec2i {
    let size = 1 << level_of(pixel);
    let origin = (pixel >> vec2u(level_of(pixel))) << vec2u(level_of(pixel));
    var neighbour = pixel;
    neighbour[axis] = select(origin[axis] + size, origin[axis] - 1, direction < 0);
    return neighbour;
}

@fragment
fn fs_composite_nearest(@builtin(position) position: vec4f) -> @location(0) vec4f {
    return vec4f(coarse_colour(vec2i(position.xy)).rgb, 1.0);
}

// The original method: q = (P - O(P)) / S(P) relative to the fragment centre O(P); P^x, P^y are
// the pixels just outside the fragment on P's side (same row, same column); the diagonal P^2
// steps on from whichever of them is nearer to P, through that neighbour's own fragment; then
// C = lerp(lerp(C(P), C(P^x), |q.x|), lerp(C(P^y), C(P^2), |q.x|), |q.y|).
@fragment
fn fs_composite_four_neighbour(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let p = vec2i(position.xy);
    let level = level_of(p);
    let size = f32(1 << level);
    let origin = vec2f((p >> vec2u(level)) << vec2u(level));
    let q = (vec2f(p) + 0.5 - (origin + 0.5 * size)) / size;
    let dx = select(1, -1, q.x < 0.0);
    let dy = select(1, -1, q.y < 0.0);
    let px = beyond_fragment(p, 0u, dx);
    let py = beyond_fragment(p, 1u, dy);
    let p2 = select(beyond_fragment(py, 0u, dx), beyond_fragment(px, 1u, dy), abs(q.x) >= abs(q.y));
    let w = abs(q);
    let top = mix(coarse_colour(p), coarse_colour(px), w.x);
    let bottom = mix(coarse_colour(py), coarse_colour(p2), w.x);
    return vec4f(mix(top, bottom, w.y).rgb, 1.0);
}

@group(0) @binding(3) var filled: texture_2d<f32>;

// Ours: bilinear interpolation of the filled pyramid at the pixel's own level. Every texel it
// reads holds shading (own, pulled from finer or pushed from coarser), so there is no jump where
// the level changes: across a boundary both sides blend the same neighbouring shading.
@fragment
fn fs_composite_seam_free(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let p = vec2i(position.xy);
    let level = level_of(p);
    let size = 1u << level;
    let last = vec2i((composite.screen + size - 1u) / size) - 1;
    let at = (vec2f(p) + 0.5) / f32(size) - 0.5;
    return vec4f(bilinear_load(filled, level, at, last).rgb, 1.0);
}
