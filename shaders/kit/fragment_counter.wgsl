// Counts the fragments that survive the depth/stencil test. A storage write would normally force
// late tests; `early_depth_test(force)` keeps them early, so the count equals the passing pixels.

@group(0) @binding(0) var<storage, read_write> fragment_count: atomic<u32>;

@vertex
fn vs_fullscreen(@builtin(vertex_index) vertex_index: u32) -> @builtin(position) vec4f {
    return fullscreen_clip_position(vertex_index);
}

@fragment
@early_depth_test(force)
fn fs_count() {
    atomicAdd(&fragment_count, 1u);
}
