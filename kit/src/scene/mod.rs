//! Deterministic scene inputs: everything random is drawn from a seeded hash shared with WGSL.

pub mod corridor;
pub mod hash;
