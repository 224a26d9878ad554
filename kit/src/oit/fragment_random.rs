//! The per-fragment uniform number of stochastic transparency by its definition
//! (`fragment_random` in `shaders/common/opacity.wgsl`): this frame's noise texel, the fragment's
//! depth bits and its primitive's stream, hashed together, then mapped to the 2^24 cell centres
//! of (0, 1]. Depth is in the key so that one primitive seen at two depths (a self-overlapping
//! mesh, one key drawn twice) draws independent numbers at each.

use crate::scene::hash::pcg_hash;

pub fn fragment_random(noise: u32, depth: f32, id: u32, stream: u32) -> f32 {
    let primitive = pcg_hash(id.wrapping_mul(2654435769).wrapping_add(stream));
    let h = pcg_hash(noise ^ pcg_hash(depth.to_bits() ^ primitive));
    ((h >> 8) as f32 + 0.5) * (1.0 / 16_777_216.0)
}
