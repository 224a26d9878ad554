//! fragkit: a deterministic, compute-free GPU conformance kit on wgpu.
//!
//! The GPU produces results (read-back, occlusion counts, timestamps); CPU code only computes
//! the exact expectations they are compared with.

pub mod attachments;
pub mod bench;
pub mod caps;
pub mod cbr;
pub mod cps;
pub mod deferred;
pub mod depth_readback;
pub mod diagnostics;
mod encoder_clock;
pub mod fullscreen;
pub mod gpu;
pub mod graphics_debugger;
pub mod harness;
pub mod image_compare;
pub mod mapping;
pub mod memory_growth;
pub mod oit;
pub mod probe;
pub mod query;
mod query_set;
pub mod readback;
pub mod readback_log;
pub mod rects;
pub mod scene;
pub mod shaders;
pub mod texarray;
pub mod tonemap;

pub use gpu::{AdapterSelector, Gpu};
