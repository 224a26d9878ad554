//! Coarse pixel shading through a stencil pyramid: an LOD buffer beside the G-buffer, a stencil
//! per level built from an OR-reduced "LOD-present" bitmask pyramid (under the foveated policy,
//! whose levels are a function of the pixel's position, from the geometry: no LOD buffer, no
//! pyramid), every level lit into one atlas behind a stencil-Equal test, and a composite (nearest, the original 4-neighbour
//! interpolation, or our seam-free one, linear over the shading samples where they were lit).

pub mod atlas;
pub mod config;
mod level_spans;
pub mod lod_model;
pub mod pictures;
pub mod plan;
pub mod reference;
pub mod renderer;
pub mod report;
mod stencil_marks;
pub mod targets;

pub use config::{CompositeMode, CpsConfig, LodPolicy, MAX_LEVEL};
pub use plan::Plan;
pub use renderer::{CpsOutput, CpsRenderer};
