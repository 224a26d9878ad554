//! Bug reports a driver developer can act on without fragkit (`check --bug-report DIR`): per
//! case run that did not pass, a folder with a README in the form upstream trackers ask for, the
//! evidence, the shaders as WGSL and as the driver got them, a capture of the case's own process
//! and a `replay` script that shows its pixels with the capture tool alone.

pub mod gl_trace;
