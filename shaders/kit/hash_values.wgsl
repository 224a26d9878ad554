// The shared hash functions (shaders/common/hash.wgsl, shaders/common/opacity.wgsl) evaluated on
// inputs made from the pixel index k alone, so the CPU can rebuild every input exactly
// (kit/src/probe/hash_values.rs): x = pcg_hash(k), y = bits of hash_unit(k), z = bits of
// fragment_random(noise, depth, id, stream) for the inputs below.

struct Grid {
    width: u32,
}

@group(0) @binding(0) var<uniform> grid: Grid;

@fragment
fn fs_hash_values(@builtin(position) position: vec4f) -> @location(0) vec4u {
    let k = u32(position.y) * grid.width + u32(position.x);
    // Neighbouring k share noise, id and stream in runs of four and differ only in depth, so a
    // function that drops the depth term repeats itself.
    let run = k >> 2u;
    let noise = run * 2654435761u;
    let depth = bitcast<f32>(0x3f800000u - (k * 40503u) % 0x3f800000u);
    let id = run / 3u;
    let stream = run % 4u;
    return vec4u(pcg_hash(k), bitcast<u32>(hash_unit(k)), bitcast<u32>(fragment_random(noise, depth, id, stream)), 0u);
}
