// The LOD buffer and level 0 of the LOD-present mask pyramid, in one pass: each pixel's level
// under the frame's policy, written to the LOD buffer (`R8Uint`) and as the bit 1 << level to mip
// 0 of the mask pyramid. Foveated: level 0 within `inner_radius` pixels of the focus point, one
// level coarser each time the distance doubles (level = floor(log2(1 + distance /
// inner_radius)), common/foveation.wgsl). Content: the coarsest level l whose aligned 2^l block
// around the pixel holds no edge, read from the OR-reduced edge pyramid (edge_pyramid mip l,
// texel pixel >> l). The caller's own LOD, uploaded, is only read (fs_lod_present*). Levels are
// capped at the plan's top level. Where the plan skips absent levels on the GPU (the *_counted
// entry points), each pixel also sets its level's indirect instance count to 1, so a level no
// pixel uses is drawn with zero instances, without a read-back.

struct LodParameters {
    // Foveated only.
    foveation: Foveation,
    // The plan's top level.
    max_level: u32,
}

struct DrawIndirect {
    vertex_count: u32,
    instance_count: u32,
    first_vertex: u32,
    first_instance: u32,
}

@group(0) @binding(0) var<uniform> parameters: LodParameters;
// Content only.
@group(0) @binding(1) var edge_pyramid: texture_2d<u32>;
// The caller's own LOD only.
@group(0) @binding(2) var lod: texture_2d<u32>;
@group(1) @binding(0) var<storage, read_write> level_draws: array<DrawIndirect, 9>;

fn pixel_foveated_level(position: vec4f) -> u32 {
    return foveated_level(position.xy, parameters.foveation);
}

fn content_level(position: vec4f) -> u32 {
    let pixel = vec2u(position.xy);
    var level = 0u;
    for (var l = 1u; l <= parameters.max_level; l++) {
        if textureLoad(edge_pyramid, pixel >> vec2u(l), i32(l)).x != 0u {
            break;
        }
        level = l;
    }
    return level;
}

fn uploaded_level(position: vec4f) -> u32 {
    return min(textureLoad(lod, vec2u(position.xy), 0).x, parameters.max_level);
}

fn counted(level: u32) -> u32 {
    level_draws[level].instance_count = 1u;
    return level;
}

struct LodAndPresent {
    @location(0) lod: u32,
    @location(1) present: u32,
}

fn lod_and_present(level: u32) -> LodAndPresent {
    return LodAndPresent(level, 1u << level);
}

@fragment
fn fs_lod_foveated(@builtin(position) position: vec4f) -> LodAndPresent {
    return lod_and_present(pixel_foveated_level(position));
}

// The LOD alone, for a frame whose passes compute the foveated level where they need it: the
// LOD picture, rendered on request (CpsRenderer::read_lod).
@fragment
fn fs_lod_foveated_alone(@builtin(position) position: vec4f) -> @location(0) u32 {
    return pixel_foveated_level(position);
}

@fragment
fn fs_lod_foveated_counted(@builtin(position) position: vec4f) -> LodAndPresent {
    return lod_and_present(counted(pixel_foveated_level(position)));
}

@fragment
fn fs_lod_content(@builtin(position) position: vec4f) -> LodAndPresent {
    return lod_and_present(content_level(position));
}

@fragment
fn fs_lod_content_counted(@builtin(position) position: vec4f) -> LodAndPresent {
    return lod_and_present(counted(content_level(position)));
}

@fragment
fn fs_lod_present(@builtin(position) position: vec4f) -> @location(0) u32 {
    return 1u << uploaded_level(position);
}

@fragment
fn fs_lod_present_counted(@builtin(position) position: vec4f) -> @location(0) u32 {
    return 1u << counted(uploaded_level(position));
}
