//! Mapping a read-back buffer on the CPU, with a bound on the wait: the step under every
//! read-back, query and clock, which needs a device and nothing of the kit above it.

use std::time::Duration;

use anyhow::{Result, anyhow};

/// How long a read-back may wait for the GPU before it is reported as hung.
pub const READBACK_TIMEOUT: Duration = Duration::from_secs(120);

/// Maps a `MAP_READ` buffer after the work that fills it has been submitted, waiting at most
/// [`READBACK_TIMEOUT`].
pub fn map_read(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |result| {
        // The receiver only disappears when the wait below has already given up.
        let _ = sender.send(result);
    });
    device
        .poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(READBACK_TIMEOUT) })
        .map_err(|e| anyhow!("GPU did not finish within {READBACK_TIMEOUT:?} while reading back {buffer:?}: {e}"))?;
    receiver
        .recv_timeout(READBACK_TIMEOUT)
        .map_err(|_| anyhow!("buffer map callback never ran within {READBACK_TIMEOUT:?}"))?
        .map_err(|e| anyhow!("mapping a read-back buffer failed: {e}"))?;
    let bytes = buffer.get_mapped_range(..).map_err(|e| anyhow!("reading a mapped buffer: {e}"))?.to_vec();
    buffer.unmap();
    Ok(bytes)
}
