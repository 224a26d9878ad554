//! The clock every encoder of a case runs under: timestamps at each encoder's start and end,
//! summed into the case's GPU time. It needs the device and queue alone, so the GPU context can
//! hold it without anything above it.

use anyhow::{Context, Result};

use crate::query_set::ResolvedQueries;

/// GPU time of every command encoder made with [`Gpu::encoder`] and submitted with
/// [`Gpu::submit`]: a timestamp at each encoder's start and end, outside any pass.
pub(crate) struct EncoderClock {
    queries: ResolvedQueries,
    used_pairs: u32,
    /// Encoders started and not yet submitted.
    open: u32,
    /// Time of pairs already read back to make room.
    carried_ms: f64,
    period_ns: f64,
}

/// Encoders one clock can time between two reads; later ones go untimed (and are logged).
const CLOCK_PAIRS: u32 = 1024;

impl EncoderClock {
    pub(crate) fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        Self {
            queries: ResolvedQueries::new(device, wgpu::QueryType::Timestamp, CLOCK_PAIRS * 2, "encoder clock"),
            used_pairs: 0,
            open: 0,
            carried_ms: 0.0,
            period_ns: f64::from(queue.get_timestamp_period()),
        }
    }

    /// Writes the start stamp; returns the pair's index, or None when the clock is full with
    /// encoders still open (a full clock with none open is read back to make room first).
    pub(crate) fn start(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Option<u32> {
        if self.used_pairs == CLOCK_PAIRS {
            if self.open > 0 {
                log::warn!("encoder clock full with {} encoders open: this encoder is not timed", self.open);
                return None;
            }
            match self.read_used(device, queue) {
                Ok(ms) => self.carried_ms += ms,
                Err(e) => log::warn!("reading the encoder clock to make room: {e:#}"),
            }
        }
        self.open += 1;
        self.used_pairs += 1;
        let pair = self.used_pairs - 1;
        encoder.write_timestamp(&self.queries.set, pair * 2);
        Some(pair)
    }

    pub(crate) fn stop(&mut self, encoder: &mut wgpu::CommandEncoder, pair: u32) {
        self.open = self.open.saturating_sub(1);
        encoder.write_timestamp(&self.queries.set, pair * 2 + 1);
    }

    /// Sums every started pair's span in ms and resets the clock. Pairs whose encoder was
    /// never submitted read as zero and add nothing.
    pub(crate) fn take_ms(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<f64> {
        self.open = 0;
        let ms = self.read_used(device, queue)?;
        Ok(std::mem::take(&mut self.carried_ms) + ms)
    }

    /// Sums the started pairs' spans and frees them.
    fn read_used(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<f64> {
        let used = std::mem::take(&mut self.used_pairs) * 2;
        if used == 0 {
            return Ok(0.0);
        }
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("encoder clock") });
        self.queries.resolve(&mut encoder, used);
        queue.submit([encoder.finish()]);
        let stamps = self.queries.read(device, used).context("reading the encoder clock")?;
        let ns: u64 = stamps.chunks_exact(2).map(|pair| pair[1].saturating_sub(pair[0])).sum();
        Ok(ns as f64 * self.period_ns * 1e-6)
    }
}
