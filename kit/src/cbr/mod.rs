//! Checkerboard rendering: quarter-resolution targets whose two samples per pixel land on the
//! centres of two diagonal full-resolution pixels, the view jittered one full-resolution pixel to
//! the right on alternate frames, so two frames together sample every pixel centre once.

pub mod probe;
pub mod sampling;
