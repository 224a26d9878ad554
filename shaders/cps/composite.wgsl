// Composite: every pixel takes its colour from the lit levels. Three modes: nearest (plain CPS:
// the pixel's own coarse texel), the original method's 4-neighbour interpolation, and our
// seam-free trilinear reconstruction over the pull-push filled pyramid. The lit levels are one
// atlas, read at a per-pixel offset; the filled pyramid's fetches at a per-pixel mip level go
// through load_at_level (common/fullscreen.wgsl), which the renderer sets to loop over the levels
// where the kit's probe found the direct fetch wrong.

struct Composite {
    max_level: u32,
    // Seam-free mode: the level whose blocks carry the smooth level field.
    transition_level: u32,
    screen: vec2u,
    // Where each level's texels start in the lit atlas (xy).
    origins: array<vec4u, 9>,
}

@group(0) @binding(0) var<uniform> composite: Composite;
@group(0) @binding(1) var lod: texture_2d<u32>;
// Every lit level side by side (cps/atlas.rs): a per-pixel level is a per-pixel offset.
@group(0) @binding(2) var lit: texture_2d<f32>;


fn level_of(pixel: vec2i) -> u32 {
    let clamped = vec2u(clamp(pixel, vec2i(0), vec2i(composite.screen) - 1));
    return min(textureLoad(lod, clamped, 0).x, composite.max_level);
}

// The shading a pixel gets under nearest composition (its own coarse texel).
fn coarse_colour(pixel: vec2i) -> vec4f {
    let clamped = vec2u(clamp(pixel, vec2i(0), vec2i(composite.screen) - 1));
    let level = level_of(pixel);
    return textureLoad(lit, vec2i(composite.origins[level].xy + (clamped >> vec2u(level))), 0);
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
@group(0) @binding(4) var mask: texture_2d<u32>;

// Texels of `level` that hold data: ceil(screen / 2^level).
fn level_last(level: u32) -> vec2i {
    let size = 1u << level;
    return vec2i((composite.screen + size - 1u) / size) - 1;
}

fn filled_at(p: vec2i, level: u32) -> vec4f {
    let at = (vec2f(p) + 0.5) / f32(1u << level) - 0.5;
    return bilinear_load(filled, level, at, level_last(level));
}

// The finest level present in texel t of the mask pyramid's transition level.
fn finest_present(t: vec2i) -> f32 {
    let last = level_last(composite.transition_level);
    let clamped = clamp(t, vec2i(0), last);
    return f32(firstTrailingBit(textureLoad(mask, clamped, i32(composite.transition_level)).x));
}

// Ours: a smooth level field, the finest level present per 2^k block (k = the transition level)
// interpolated bilinearly between blocks, selects a trilinear blend of the filled pyramid. Every
// texel read holds shading (own, pulled from finer or pushed from coarser) and the field changes
// gradually, so no step appears where the LOD changes.
@fragment
fn fs_composite_seam_free(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let p = vec2i(position.xy);
    let at = (vec2f(p) + 0.5) / f32(1u << composite.transition_level) - 0.5;
    let base = floor(at);
    let f = at - base;
    let t = vec2i(base);
    let field = mix(
        mix(finest_present(t), finest_present(t + vec2i(1, 0)), f.x),
        mix(finest_present(t + vec2i(0, 1)), finest_present(t + vec2i(1, 1)), f.x),
        f.y,
    );
    let fine = min(u32(floor(field)), composite.max_level);
    let coarse = min(fine + 1u, composite.max_level);
    return vec4f(mix(filled_at(p, fine), filled_at(p, coarse), field - floor(field)).rgb, 1.0);
}
