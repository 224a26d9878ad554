// The stencil pyramid in its atlas: each level's marks (one draw a level, its viewport the
// level's rect, or under the foveated policy one instance a level) mark (op Replace) the texels
// some pixel of whose block uses that level, and discard the others; the draws open the lighting
// pass (cps/lighting.wgsl), whose stencil-Equal draws follow them. This stands in for stencil
// export, which wgpu (and NVIDIA's GL) lack.
//
// In general the levels a block uses come from the LOD-present mask pyramid, built before the
// pass. It holds the even mips only: an even level reads its own mip, an odd one ORs its 2×2
// children in the even mip below (its own entry point: a branch on the level would run both sides
// on a CPU rasteriser). Under the foveated policy they follow from the block's geometry instead
// (fs_stencil_mark_foveated), and no pyramid is built; one pipeline serves every level, so all
// the levels' marks are one draw, an instance a level (vs_level_bounds): lavapipe pays about as
// much for a draw as for a few hundred marked texels.

struct AtlasLevel {
    level: u32,
    origin_x: u32,
    origin_y: u32,
}

@group(0) @binding(0) var mask: texture_2d<u32>;
@group(0) @binding(1) var<uniform> target_level: AtlasLevel;

// The foveated policy, as the LOD pass has it, the screen, and per level the quad its marks
// are drawn over.
struct FoveatedMarks {
    foveation: Foveation,
    screen: vec2u,
    // The atlas's size in texels.
    atlas: vec2u,
    // Per level: the texels that can be needed (the plan's level_bounds) in the atlas, first and
    // one past the last (x0, y0, x1, y1).
    bounds: array<vec4u, 9>,
    // Per level: where its rect starts in the atlas (xy).
    origins: array<vec4u, 9>,
}

@group(0) @binding(2) var<uniform> marks: FoveatedMarks;

// How far the marks widen a block's squared distances (2^-20 of them), many times the GPU's error
// in a squared distance (a few 2^-24): no pixel the LOD pass or the composite gives a level lies
// outside the block's marked range.
const MARK_WIDENING: f32 = 9.5367431640625e-7;

fn texel_of_level(position: vec4f) -> vec2u {
    return vec2u(position.xy) - vec2u(target_level.origin_x, target_level.origin_y);
}

fn mark_if(bits: u32) {
    if ((bits >> target_level.level) & 1u) == 0u {
        discard;
    }
}

// The level is uniform across the draw: a direct fetch at it is exact on every adapter.
@fragment
fn fs_stencil_mark_even(@builtin(position) position: vec4f) {
    mark_if(textureLoad(mask, texel_of_level(position), i32(target_level.level)).x);
}

@fragment
fn fs_stencil_mark_odd(@builtin(position) position: vec4f) {
    let below = i32(target_level.level) - 1;
    let size = textureDimensions(mask, below);
    let q = texel_of_level(position);
    var bits = 0u;
    for (var dy = 0u; dy < 2u; dy++) {
        for (var dx = 0u; dx < 2u; dx++) {
            let child = 2u * q + vec2u(dx, dy);
            if child.x < size.x && child.y < size.y {
                bits |= textureLoad(mask, child, below).x;
            }
        }
    }
    mark_if(bits);
}

// One instance a level: two triangles over the level's bounds in the atlas (their edges on texel
// edges, so exactly the bounds' texel centres are covered), carrying the level.
struct LevelTexel {
    @builtin(position) position: vec4f,
    @location(0) @interpolate(flat) level: u32,
}

@vertex
fn vs_level_bounds(@builtin(vertex_index) vertex: u32, @builtin(instance_index) level: u32) -> LevelTexel {
    var corners = array<vec2u, 6>(vec2u(0u, 0u), vec2u(1u, 0u), vec2u(0u, 1u), vec2u(0u, 1u), vec2u(1u, 0u), vec2u(1u, 1u));
    let bounds = marks.bounds[level];
    let texel = select(bounds.xy, bounds.zw, corners[vertex] == vec2u(1u));
    let clip = vec2f(texel) / vec2f(marks.atlas) * vec2f(2.0, -2.0) + vec2f(-1.0, 1.0);
    return LevelTexel(vec4f(clip, 0.0, 1.0), level);
}

// A level's pixels lie in a ring around the focus, and a pixel's octaves grow with its distance:
// the levels of a block's pixels run from its pixel nearest the focus to its farthest, and each
// level in between is used too, as its ring is at least 2 inner radii wide (the plan takes this
// path for inner radii of one pixel or more), wider than the √2 between a pixel and the next.
@fragment
fn fs_stencil_mark_foveated(texel: LevelTexel) {
    let level = texel.level;
    let first = (vec2u(texel.position.xy) - marks.origins[level].xy) << vec2u(level);
    let last = min(first + vec2u((1u << level) - 1u), marks.screen - 1u);
    let foveation = marks.foveation;
    let focus = foveation.focus;
    let nearest = clamp(floor(focus), vec2f(first), vec2f(last));
    let farthest = select(vec2f(first), vec2f(last), vec2f(last) + 0.5 - focus > focus - (vec2f(first) + 0.5));
    let finest = level_of_squared_distance(squared_distance_to_focus(nearest + 0.5, foveation) * (1.0 - MARK_WIDENING), foveation);
    let coarsest = level_of_squared_distance(squared_distance_to_focus(farthest + 0.5, foveation) * (1.0 + MARK_WIDENING), foveation);
    if level < finest || level > coarsest {
        discard;
    }
}
