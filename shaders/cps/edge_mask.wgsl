// Content LOD policy, step 1: marks pixels on a geometric discontinuity. A pixel is an edge
// where its surface coverage, its normal (angle beyond `normal_cos`) or its depth (relative jump
// beyond `depth_ratio`) differs from its right or lower neighbour's.

struct EdgeThresholds {
    normal_cos: f32,
    depth_ratio: f32,
}

@group(0) @binding(0) var<uniform> thresholds: EdgeThresholds;
@group(0) @binding(1) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(2) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_depth: texture_depth_2d;

fn differs(a: vec2u, b: vec2u) -> bool {
    let pa = textureLoad(gbuffer_position, a, 0);
    let pb = textureLoad(gbuffer_position, b, 0);
    if pa.w != pb.w {
        return true;
    }
    if pa.w == 0.0 {
        return false;
    }
    let na = textureLoad(gbuffer_normal, a, 0).xyz;
    let nb = textureLoad(gbuffer_normal, b, 0).xyz;
    let da = textureLoad(gbuffer_depth, a, 0);
    let db = textureLoad(gbuffer_depth, b, 0);
    let depth_jump = abs(da - db) > thresholds.depth_ratio * max(1.0 - max(da, db), 1e-6);
    return dot(na, nb) < thresholds.normal_cos || depth_jump;
}

@fragment
fn fs_edge_mask(@builtin(position) position: vec4f) -> @location(0) u32 {
    let pixel = vec2u(position.xy);
    let last = textureDimensions(gbuffer_position) - 1u;
    let right = vec2u(min(pixel.x + 1u, last.x), pixel.y);
    let below = vec2u(pixel.x, min(pixel.y + 1u, last.y));
    return select(0u, 1u, differs(pixel, right) || differs(pixel, below));
}
