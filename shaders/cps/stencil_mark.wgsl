// Stencil pyramid, step 2: level l's stencil gets the reference (op Replace) exactly where the
// mask pyramid says some pixel of the texel's block has LOD l; every other fragment is discarded.
// This stands in for stencil export, which wgpu (and NVIDIA's GL) lack.

struct Level {
    level: u32,
}

@group(0) @binding(0) var<uniform> target_level: Level;
@group(0) @binding(1) var mask: texture_2d<u32>;

@fragment
fn fs_stencil_mark(@builtin(position) position: vec4f) {
    if ((textureLoad(mask, vec2u(position.xy), 0).x >> target_level.level) & 1u) == 0u {
        discard;
    }
}
