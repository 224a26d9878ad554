//! A graphics debugger's capture of one case's GPU work (RenderDoc's in-application API, through
//! wgpu's `Device::start_graphics_debugger_capture`): with `FRAGKIT_DEBUGGER_CAPTURE` set (a bug
//! report's Vulkan run under `renderdoccmd capture` sets it), the runner brackets each case with
//! a capture. Without a debugger loaded in the process wgpu does nothing.

use std::sync::OnceLock;

use crate::gpu::Gpu;

/// Set in a process whose cases are to be captured.
pub const DEBUGGER_CAPTURE_ENV: &str = "FRAGKIT_DEBUGGER_CAPTURE";

fn wanted() -> bool {
    static WANTED: OnceLock<bool> = OnceLock::new();
    *WANTED.get_or_init(|| std::env::var_os(DEBUGGER_CAPTURE_ENV).is_some())
}

/// Runs `work` (a case) inside a capture where one is wanted.
pub fn bracket<T>(gpu: &Gpu, work: impl FnOnce() -> T) -> T {
    if !wanted() {
        return work();
    }
    // SAFETY: wgpu's contract is that no other capture is in progress and that the device is
    // not used from another thread meanwhile: a case runs alone on its device, and this is the
    // only place that starts or stops a capture.
    unsafe { gpu.device.start_graphics_debugger_capture() };
    let result = work();
    // Everything the case submitted finished: the capture ends after its last command.
    if let Err(e) = gpu.device.poll(wgpu::PollType::wait_indefinitely()) {
        log::warn!("waiting for the device before ending the capture: {e}");
    }
    // SAFETY: as above; the capture started just before.
    unsafe { gpu.device.stop_graphics_debugger_capture() };
    result
}
