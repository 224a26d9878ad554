// Foveated LOD, shared by the LOD pass (cps/lod.wgsl) and the stencil marks that follow from it
// analytically (cps/stencil_mark.wgsl): a pixel is log2(1 + distance / inner_radius) octaves from
// the focus, and its level is the whole octaves, capped at the plan's top level.

fn foveated_octaves(pixel_centre: vec2f, focus: vec2f, inner_radius: f32) -> f32 {
    return log2(1.0 + length(pixel_centre - focus) / max(inner_radius, 1e-3));
}

fn level_of_octaves(octaves: f32, max_level: u32) -> u32 {
    return min(u32(max(floor(octaves), 0.0)), max_level);
}
