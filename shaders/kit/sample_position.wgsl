// Per-sample shading probe: using `sample_index` makes the fragment shader run once per sample.
// Each invocation appends what it saw (its sample_index and `fract(@builtin(position))`), so the
// kit counts the invocations and tells whether the driver reports sample locations or pixel
// centres, without relying on the pipeline sample mask (which wgpu's GL backend ignores).

struct Invocation {
    position: vec2f,
    sample_index: u32,
    pad: u32,
}

struct Invocations {
    count: atomic<u32>,
    pad: array<u32, 3>,
    records: array<Invocation, 64>,
}

@group(0) @binding(0) var<storage, read_write> invocations: Invocations;

@fragment
fn fs_sample_position(@builtin(position) position: vec4f, @builtin(sample_index) sample_index: u32) {
    let slot = atomicAdd(&invocations.count, 1u);
    if slot < 64u {
        invocations.records[slot] = Invocation(fract(position.xy), sample_index, 0u);
    }
}
