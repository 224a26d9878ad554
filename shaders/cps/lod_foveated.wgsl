// Foveated LOD policy: level 0 within `inner_radius` pixels of the focus point, one level coarser
// each time the distance doubles (level = floor(log2(1 + distance / inner_radius))).

struct Foveation {
    focus: vec2f,
    inner_radius: f32,
    max_level: u32,
}

@group(0) @binding(0) var<uniform> foveation: Foveation;

@fragment
fn fs_lod_foveated(@builtin(position) position: vec4f) -> @location(0) u32 {
    let distance = length(position.xy - foveation.focus);
    let level = floor(log2(1.0 + distance / max(foveation.inner_radius, 1e-3)));
    return min(u32(level), foveation.max_level);
}
