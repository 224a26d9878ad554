// The determinism scene: seeded triangles with depth, each fragment's colour a hash of its
// pixel, its primitive and the seed, so any nondeterminism in rasterisation or ordering shows.

struct Seed {
    value: u32,
}

@group(0) @binding(0) var<uniform> seed: Seed;

struct TriangleVarying {
    @builtin(position) position: vec4f,
    @location(0) @interpolate(flat) primitive: u32,
    @location(1) shade: vec3f,
}

@vertex
fn vs_triangle(@builtin(vertex_index) vertex_index: u32, @location(0) position: vec3f, @location(1) shade: vec3f) -> TriangleVarying {
    return TriangleVarying(vec4f(position, 1.0), vertex_index / 3u, shade);
}

@fragment
fn fs_noise(in: TriangleVarying) -> @location(0) vec4f {
    let pixel = vec2u(in.position.xy);
    let noise = hash_unit(seed.value ^ pcg_hash(in.primitive * 65536u + pixel.y * 4096u + pixel.x));
    return vec4f(in.shade * (0.75 + 0.25 * noise), 1.0);
}
