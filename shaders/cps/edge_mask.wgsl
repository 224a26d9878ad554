// Content LOD policy, step 1: marks pixels on a geometric discontinuity. A pixel is an edge
// where its surface coverage, its normal (angle beyond `normal_cos`) or its position (a jump
// beyond `depth_ratio` times its distance from the eye) differs from any of its four
// neighbours': both sides of a discontinuity are marked, so no coarse fragment borders one and
// the composites never interpolate across it. Positions rather than the depth buffer: GLSL cannot load from depth textures.

struct EdgeThresholds {
    eye: vec3f,
    normal_cos: f32,
    depth_ratio: f32,
}

@group(0) @binding(0) var<uniform> thresholds: EdgeThresholds;
@group(0) @binding(1) var gbuffer_position: texture_2d<u32>;
@group(0) @binding(2) var gbuffer_normal: texture_2d<f32>;

fn differs(a: vec2u, b: vec2u) -> bool {
    let pa = bitcast<vec4f>(textureLoad(gbuffer_position, a, 0));
    let pb = bitcast<vec4f>(textureLoad(gbuffer_position, b, 0));
    if pa.w != pb.w {
        return true;
    }
    if pa.w == 0.0 {
        return false;
    }
    let na = textureLoad(gbuffer_normal, a, 0).xyz;
    let nb = textureLoad(gbuffer_normal, b, 0).xyz;
    let depth_jump = distance(pa.xyz, pb.xyz) > thresholds.depth_ratio * distance(pa.xyz, thresholds.eye);
    return dot(na, nb) < thresholds.normal_cos || depth_jump;
}

@fragment
fn fs_edge_mask(@builtin(position) position: vec4f) -> @location(0) u32 {
    let pixel = vec2u(position.xy);
    let last = textureDimensions(gbuffer_position) - 1u;
    let right = vec2u(min(pixel.x + 1u, last.x), pixel.y);
    let below = vec2u(pixel.x, min(pixel.y + 1u, last.y));
    let left = vec2u(max(pixel.x, 1u) - 1u, pixel.y);
    let above = vec2u(pixel.x, max(pixel.y, 1u) - 1u);
    let edge = differs(pixel, right) || differs(pixel, below) || differs(pixel, left) || differs(pixel, above);
    return select(0u, 1u, edge);
}
