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
