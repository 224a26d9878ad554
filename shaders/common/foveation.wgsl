// Foveated LOD, shared by the LOD pass (cps/lod.wgsl), the stencil marks that follow from it
// analytically (cps/stencil_mark.wgsl) and the composite (cps/composite.wgsl): a pixel's level is
// the whole octaves of 1 + distance / inner_radius from the focus, capped at the plan's top level.
// So its level is k or more exactly where its distance is at least R_k = inner_radius (2^k − 1):
// a pass counts the squared boundaries R_k² its squared distance reaches, comparisons instead of a
// log2 per pixel. The CPU computes R_k² in f64 and rounds it (`LodPolicy::foveation_words`; past
// the top level the largest f32, which no distance reaches). A squared distance of f32 inputs errs
// by a few 2^-24 of itself: a pixel's level may differ from the definition only within about
// 2^-22 octaves of a boundary, far inside the CPU model's ambiguity band (2^-17, cps/lod_model.rs).

struct Foveation {
    // The focus in pixels.
    focus: vec2f,
    // R_k² for k = 1..8 (MAX_LEVEL in cps/config.rs), in order.
    squared_boundaries: array<vec4f, 2>,
}

fn squared_distance_to_focus(pixel_centre: vec2f, foveation: Foveation) -> f32 {
    let offset = pixel_centre - foveation.focus;
    return dot(offset, offset);
}

// The level of a pixel at squared distance `squared` from the focus: the boundaries it reaches.
// Counted by converting the comparisons, not by a vector `select`: naga writes that as an integer
// `mix`, which GLSL before 4.50 lacks (kit.translate.integer_select reports it).
fn level_of_squared_distance(squared: f32, foveation: Foveation) -> u32 {
    let reached = vec4u(vec4f(squared) >= foveation.squared_boundaries[0])
        + vec4u(vec4f(squared) >= foveation.squared_boundaries[1]);
    return reached.x + reached.y + reached.z + reached.w;
}

fn foveated_level(pixel_centre: vec2f, foveation: Foveation) -> u32 {
    return level_of_squared_distance(squared_distance_to_focus(pixel_centre, foveation), foveation);
}

// The foveation with the screen and where each level starts in the CPS atlas: what the stencil
// marks (cps/stencil_mark.wgsl) and the lighting (cps/lighting.wgsl) decide a texel's levels by.
struct FoveatedBlocks {
    foveation: Foveation,
    screen: vec2u,
    // Per level (xy).
    origins: array<vec4u, 9>,
}

// How far a block's squared distances are widened (2^-20 of them), many times the GPU's error in
// a squared distance (a few 2^-24): no pixel the LOD pass or the composite gives a level lies
// outside the block's range.
const MARK_WIDENING: f32 = 9.5367431640625e-7;

// Whether some pixel of texel `texel`'s block (at `level`, in the level's own texels) has that
// level. A level's pixels lie in a ring around the focus, and a pixel's octaves grow with its
// distance: the levels of a block's pixels run from its pixel nearest the focus to its farthest,
// and each level in between is used too, as its ring is at least 2 inner radii wide (the plan
// takes this path for inner radii of one pixel or more), wider than the √2 between a pixel and
// the next.
fn foveated_block_has_level(texel: vec2u, level: u32, blocks: FoveatedBlocks) -> bool {
    let first = texel << vec2u(level);
    let last = min(first + vec2u((1u << level) - 1u), blocks.screen - 1u);
    let foveation = blocks.foveation;
    let focus = foveation.focus;
    let nearest = clamp(floor(focus), vec2f(first), vec2f(last));
    let farthest = select(vec2f(first), vec2f(last), vec2f(last) + 0.5 - focus > focus - (vec2f(first) + 0.5));
    let finest = level_of_squared_distance(squared_distance_to_focus(nearest + 0.5, foveation) * (1.0 - MARK_WIDENING), foveation);
    let coarsest = level_of_squared_distance(squared_distance_to_focus(farthest + 0.5, foveation) * (1.0 + MARK_WIDENING), foveation);
    return level >= finest && level <= coarsest;
}
