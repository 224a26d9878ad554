// The fragment-storage probe (kit/src/probe/fragment_storage.rs): each pixel of a 4×1 target
// writes its column + 1 into the storage buffer, so the buffer reads [1, 2, 3, 4] where fragment
// shaders can write storage.

@group(0) @binding(0) var<storage, read_write> written: array<u32, 4>;

@fragment
fn fs_fragment_storage(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let column = u32(position.x);
    written[column] = column + 1u;
    return vec4f(1.0);
}
