// A deliberately expensive full-screen fragment shader: the early-rejection probe compares its cost
// behind a stencil test that passes few pixels with its cost when every pixel passes.

struct Workload {
    iterations: u32,
}

@group(0) @binding(0) var<uniform> workload: Workload;

@fragment
fn fs_heavy(@builtin(position) position: vec4f) -> @location(0) vec4f {
    var value = vec3f(position.xy * 0.001, 0.5);
    for (var i = 0u; i < workload.iterations; i++) {
        value = fract(sin(value.yzx * 12.9898 + vec3f(f32(i) * 0.37)) * 43758.547);
    }
    return vec4f(value, 1.0);
}
