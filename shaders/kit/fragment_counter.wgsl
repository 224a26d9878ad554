// Counts the fragments that survive the depth/stencil test. A storage write would normally force
// late tests; `early_depth_test(force)` keeps them early, so the count equals the passing pixels.

@group(0) @binding(0) var<storage, read_write> fragment_count: atomic<u32>;

@fragment
@early_depth_test(force)
fn fs_count() {
    atomicAdd(&fragment_count, 1u);
}
