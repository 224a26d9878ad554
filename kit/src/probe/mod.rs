//! Tiny renders that measure what an adapter really does; [`crate::caps::Caps`] collects them and
//! the `kit.*` cases compare them with what the standards say.

pub mod alpha_to_coverage;
pub mod fragment_storage;
pub mod hash_values;
pub mod indirect_draw;
pub mod mip_fetch;
pub mod multisample_render;
pub mod occlusion;
pub mod sample_mask;
pub mod sample_positions;
pub mod sample_projections;
pub mod stencil_gated_draw;
pub mod subpixel_precision;

use anyhow::Result;

use crate::gpu::Gpu;

/// A probe's GPU work: wgpu's errors fail it (`Gpu::scoped`), and the GL errors it meets — a
/// target GL refuses shows in what the probe measures — are its own evidence
/// (`diagnostics::probing`), not charged to the case that asked.
pub(crate) fn scoped<T>(gpu: &Gpu, what: &str, body: impl FnOnce() -> Result<T>) -> Result<T> {
    crate::diagnostics::probing(|| gpu.scoped(what, body)).0
}
