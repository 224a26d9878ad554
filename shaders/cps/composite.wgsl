// Composite: every pixel takes its colour from the lit levels. Three modes: nearest (plain CPS:
// the pixel's own coarse texel), the original method's 4-neighbour interpolation, and our
// seam-free one, linear over the shading samples where they were taken. The lit levels are one
// atlas, read at a per-pixel offset (no fetch at a per-pixel mip level, which GL llvmpipe gets
// wrong: kit.fetch.per_pixel_level). A pixel's level is read from the LOD buffer, or where the
// frame has none (the foveated policy: plan.levels_from_foveation) computed as the LOD pass would.

struct Composite {
    max_level: u32,
    screen: vec2u,
    // Where each level's texels start in the lit atlas (xy).
    origins: array<vec4u, 9>,
    // The foveated policy (read where `foveated`).
    foveation: Foveation,
}

// The plan's levels_from_foveation.
override foveated: bool;

@group(0) @binding(0) var<uniform> composite: Composite;
@group(0) @binding(1) var lod: texture_2d<u32>;
// Every lit level side by side (cps/atlas.rs): a per-pixel level is a per-pixel offset.
@group(0) @binding(2) var lit: texture_2d<f32>;


fn level_of(pixel: vec2i) -> u32 {
    let clamped = vec2u(clamp(pixel, vec2i(0), vec2i(composite.screen) - 1));
    if foveated {
        return foveated_level(vec2f(clamped) + 0.5, composite.foveation);
    }
    return min(textureLoad(lod, clamped, 0).x, composite.max_level);
}

// The texel of `level` holding `pixel`.
fn colour_at(pixel: vec2i, level: u32) -> vec4f {
    let clamped = vec2u(clamp(pixel, vec2i(0), vec2i(composite.screen) - 1));
    return textureLoad(lit, vec2i(composite.origins[level].xy + (clamped >> vec2u(level))), 0);
}

// The shading a pixel gets under nearest composition (its own coarse texel).
fn coarse_colour(pixel: vec2i) -> vec4f {
    return colour_at(pixel, level_of(pixel));
}

// The pixel just outside the coarse fragment holding `pixel`, along `axis` (0 = x, 1 = y), on the
// side of `direction` (-1 or +1).
fn beyond_fragment(pixel: vec2i, axis: u32, direction: i32) -> vec2i {
    return beyond_fragment_at(pixel, level_of(pixel), axis, direction);
}

// The same for a pixel whose level is known.
fn beyond_fragment_at(pixel: vec2i, level: u32, axis: u32, direction: i32) -> vec2i {
    let size = 1 << level;
    let origin = (pixel >> vec2u(level)) << vec2u(level);
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

// Where a fragment of `level` holding `pixel` was lit: the centre pixel of its 2^level block,
// clamped to the screen (cps/lighting.wgsl); a level-0 fragment is its own pixel.
fn sample_at(pixel: vec2i, level: u32) -> vec2i {
    let origin = (pixel >> vec2u(level)) << vec2u(level);
    return min(origin + ((1 << level) >> 1), vec2i(composite.screen) - 1);
}

fn on_screen(pixel: vec2i) -> bool {
    return all(pixel >= vec2i(0)) && all(pixel < vec2i(composite.screen));
}

// A corner for the seam-free triangle: the pixel whose fragment's sample it is (P itself for a
// flat corner of P's own colour), that fragment's level and the step from A to the sample (zero
// where unusable).
struct Corner {
    pixel: vec2i,
    level: u32,
    edge: vec2i,
}

// The sample of the fragment just across P's fragment (of level `own`) along `axis` on the side
// of `direction`; unusable (zero step) past the screen's edge.
fn corner_across(p: vec2i, own: u32, a: vec2i, axis: u32, direction: i32) -> Corner {
    let across = beyond_fragment_at(p, own, axis, direction);
    if !on_screen(across) {
        return Corner(p, own, vec2i(0));
    }
    let level = level_of(across);
    return Corner(across, level, sample_at(across, level) - a);
}

struct CornerPair {
    first: Corner,
    second: Corner,
}

// The two corners along `axis`, the side P lies towards first (either, where P is level with A).
// Where P lies beyond the outermost sample towards the screen's edge, or no sample lies apart
// from A (a level that does not nest in the others' blocks can hold another's sample), the first
// is flat: P's own colour, level with P, so the composite is constant along `axis` there, as
// clamp-to-edge addressing is, rather than extrapolated.
fn corners_along(p: vec2i, own: u32, a: vec2i, axis: u32, toward: i32) -> CornerPair {
    var pair = CornerPair(corner_across(p, own, a, axis, toward), corner_across(p, own, a, axis, -toward));
    if all(pair.first.edge == vec2i(0)) && p[axis] == a[axis] {
        pair = CornerPair(pair.second, pair.first);
    }
    if all(pair.first.edge == vec2i(0)) {
        var edge = vec2i(0);
        edge[axis] = toward * max(abs(p[axis] - a[axis]), 1);
        pair.first = Corner(p, own, edge);
    }
    return pair;
}

// How well the triangle A, B, D serves P (P - A = `d`): rank 3 holds P with three samples, 2
// holds P with a flat corner, 1 extrapolates, 0 degenerate; and beta = nb / det, delta = nd / det.
struct Candidate {
    rank: i32,
    nb: i32,
    nd: i32,
    det: i32,
}

fn candidate(p: vec2i, d: vec2i, b: Corner, e: Corner) -> Candidate {
    let u = b.edge;
    let v = e.edge;
    let det = u.x * v.y - u.y * v.x;
    let nb = d.x * v.y - d.y * v.x;
    let nd = u.x * d.y - u.y * d.x;
    let sign = select(1, -1, det < 0);
    let holds = nb * sign >= 0 && nd * sign >= 0 && (nb + nd) * sign <= det * sign;
    let flat = all(b.pixel == p) || all(e.pixel == p);
    let rank = select(0, select(1, select(3, 2, flat), holds), det != 0);
    return Candidate(rank, nb, nd, det);
}

// Ours: linear interpolation over a triangle of three shading samples, each where its fragment
// was lit: A, the pixel's own fragment's, and one across its fragment along x (B) and along y (D):
// C = C(A) + beta (C(B) - C(A)) + delta (C(D) - C(A)) with P - A = beta (B - A) + delta (D - A).
// Shading linear in screen position is reproduced exactly whatever the levels, so a level boundary
// adds no step the shading does not have, except beyond the outermost samples towards the
// screen's edges, where it is constant (no extrapolation). Of the four triangles (either side
// along each axis, the sides P lies towards first) it takes the first that holds P (weights in
// [0, 1]: no overshoot) with three samples, else with a flat corner, else the first that is not
// degenerate (it extrapolates); with none, P's own colour. Integer tests, so every adapter picks
// the same triangle. Five LOD texels and three lit texels a pixel.
@fragment
fn fs_composite_seam_free(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let p = vec2i(position.xy);
    let own = level_of(p);
    let a = sample_at(p, own);
    let d = p - a;
    // 1 or −1 per axis, without a vector `select` (an integer `mix` before GLSL 4.50).
    let toward = vec2i(1) - 2 * vec2i(p < a);
    let along_x = corners_along(p, own, a, 0u, toward.x);
    let along_y = corners_along(p, own, a, 1u, toward.y);
    // The first of the highest rank, in the order (x, y) nearer sides first.
    var best = candidate(p, d, along_x.first, along_y.first);
    var b = along_x.first;
    var e = along_y.first;
    let x_away = candidate(p, d, along_x.second, along_y.first);
    if x_away.rank > best.rank {
        best = x_away;
        b = along_x.second;
    }
    let y_away = candidate(p, d, along_x.first, along_y.second);
    if y_away.rank > best.rank {
        best = y_away;
        b = along_x.first;
        e = along_y.second;
    }
    let both_away = candidate(p, d, along_x.second, along_y.second);
    if both_away.rank > best.rank {
        best = both_away;
        b = along_x.second;
        e = along_y.second;
    }
    let colour_a = colour_at(p, own);
    if best.rank == 0 {
        return vec4f(colour_a.rgb, 1.0);
    }
    let beta = f32(best.nb) / f32(best.det);
    let delta = f32(best.nd) / f32(best.det);
    let colour = colour_a + beta * (colour_at(b.pixel, b.level) - colour_a) + delta * (colour_at(e.pixel, e.level) - colour_a);
    return vec4f(colour.rgb, 1.0);
}
