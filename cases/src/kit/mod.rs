//! `kit.*`: conformance of the adapter features the techniques rely on.

pub mod deferred_gbuffer;
pub mod deferred_lighting;
pub mod determinism;
pub mod early_rejection;
pub mod hash_values;
pub mod indirect_draw;
pub mod mip_fetch;
pub mod msaa_sample_positions;
pub mod occlusion_exact;
pub mod sample_mask;
pub mod scissor_msaa;
pub mod subpixel_precision;
