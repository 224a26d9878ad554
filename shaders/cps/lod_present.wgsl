// Stencil pyramid, level 0: the "LOD-present" bitmask of each pixel, 1 << lod (lod clamped to the
// plan's top level), written to mip 0 of the mask pyramid. Where the plan skips absent levels on
// the GPU, each pixel also sets its level's indirect instance count to 1, so a level no pixel
// uses is drawn with zero instances, without a read-back.

struct LodRange {
    max_level: u32,
}

struct DrawIndirect {
    vertex_count: u32,
    instance_count: u32,
    first_vertex: u32,
    first_instance: u32,
}

@group(0) @binding(0) var<uniform> range: LodRange;
@group(0) @binding(1) var lod: texture_2d<u32>;
@group(1) @binding(0) var<storage, read_write> level_draws: array<DrawIndirect, 9>;

fn present_level(position: vec4f) -> u32 {
    return min(textureLoad(lod, vec2u(position.xy), 0).x, range.max_level);
}

@fragment
fn fs_lod_present(@builtin(position) position: vec4f) -> @location(0) u32 {
    return 1u << present_level(position);
}

@fragment
fn fs_lod_present_and_count(@builtin(position) position: vec4f) -> @location(0) u32 {
    let level = present_level(position);
    level_draws[level].instance_count = 1u;
    return 1u << level;
}

