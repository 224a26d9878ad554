//! Checkerboard rendering: quarter-resolution targets whose two samples per pixel land on the
//! centres of two diagonal full-resolution pixels, the view jittered one full-resolution pixel to
//! the right on alternate frames, so two frames together sample every pixel centre once; a
//! fragment pass reconstructs full resolution from frames N and N−1.

pub mod branch_scenes;
pub mod deferred_full_resolution;
pub mod frame;
pub mod layout_values;
pub mod measure;
pub mod model;
pub mod model_comparison;
pub mod pictures;
pub mod plan;
pub mod probe;
pub mod reconstruct;
pub mod renderer;
pub mod report;
pub mod sampling;
pub mod scene;
pub mod scene_pass;

pub use plan::{CheckerboardPlan, Shading};
pub use reconstruct::{Detection, PixelSource};
pub use renderer::{Checkerboard, CheckerboardConfig, FullResolutionScene, HalfResolutionUpscale};
pub use sampling::Orientation;
