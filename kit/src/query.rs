//! GPU queries: occlusion counts and timestamps around whole render passes (timestamps inside a
//! pass are meaningless on tile/deferred rasterisers such as lavapipe, which runs at pass end).

use anyhow::{Context, Result};

use crate::gpu::Gpu;
use crate::readback::map_buffer;

/// A query set plus the buffers its results travel through to the CPU.
struct ResolvedQueries {
    set: wgpu::QuerySet,
    count: u32,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
}

impl ResolvedQueries {
    fn new(device: &wgpu::Device, ty: wgpu::QueryType, count: u32, label: &str) -> Self {
        let size = u64::from(count.max(1)) * 8;
        Self {
            set: device.create_query_set(&wgpu::QuerySetDescriptor { label: Some(label), ty, count: count.max(1) }),
            count,
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            }),
        }
    }

    fn resolve(&self, encoder: &mut wgpu::CommandEncoder, used: u32) {
        if used > 0 {
            encoder.resolve_query_set(&self.set, 0..used, &self.resolve, 0);
            encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, u64::from(used) * 8);
        }
    }

    fn read(&self, gpu: &Gpu, used: u32) -> Result<Vec<u64>> {
        if used == 0 {
            return Ok(Vec::new());
        }
        let bytes = map_buffer(gpu, &self.readback)?;
        Ok(bytes.chunks_exact(8).take(used as usize).map(|c| u64::from_le_bytes(c.try_into().unwrap())).collect())
    }
}

/// Occlusion queries: `begin_occlusion_query(i)` inside a pass that names [`Self::set`].
pub struct OcclusionQueries(ResolvedQueries);

impl OcclusionQueries {
    pub fn new(gpu: &Gpu, count: u32) -> Self {
        Self(ResolvedQueries::new(&gpu.device, wgpu::QueryType::Occlusion, count, "occlusion queries"))
    }

    pub fn set(&self) -> &wgpu::QuerySet {
        &self.0.set
    }

    /// Records the copy of all results; call after the last pass that uses them.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        self.0.resolve(encoder, self.0.count);
    }

    /// Reads the results after the encoder holding [`Self::resolve`] was submitted.
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<u64>> {
        self.0.read(gpu, self.0.count).context("reading occlusion query results")
    }
}

/// GPU time of whole render passes, from a begin/end timestamp pair per pass; and, with or
/// without timestamps, which passes were recorded.
pub struct GpuTimer {
    queries: Option<ResolvedQueries>,
    /// Every pass recorded since the last read, timed or not (an adapter without timestamps —
    /// GLES, WebGL2 — still says which passes a frame recorded); the first ones, up to the
    /// timer's capacity, are timed.
    recorded: Vec<String>,
    period_ns: f64,
    /// Passes that found the timer full (warned about once).
    untimed: u32,
}

/// One timed pass.
#[derive(Clone, Debug)]
pub struct PassTime {
    pub label: String,
    pub ms: f64,
}

impl GpuTimer {
    /// A timer for up to `passes` passes; inert (every pass untimed) without `TIMESTAMP_QUERY`.
    pub fn new(gpu: &Gpu, passes: u32) -> Self {
        let queries = gpu
            .has(wgpu::Features::TIMESTAMP_QUERY)
            .then(|| ResolvedQueries::new(&gpu.device, wgpu::QueryType::Timestamp, passes * 2, "pass timestamps"));
        Self { queries, recorded: Vec::new(), period_ns: f64::from(gpu.queue.get_timestamp_period()), untimed: 0 }
    }

    /// Timestamp writes for the next pass, or `None` when the adapter has no timestamps or
    /// the timer is full (that pass then goes untimed rather than failing).
    pub fn pass(&mut self, label: &str) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let index = self.recorded.len() as u32 * 2;
        self.recorded.push(label.to_owned());
        let queries = self.queries.as_ref()?;
        if index + 2 > queries.count {
            if self.untimed == 0 {
                log::warn!("GpuTimer full: pass {label:?} and later ones are not timed");
            }
            self.untimed += 1;
            return None;
        }
        Some(wgpu::RenderPassTimestampWrites {
            query_set: &queries.set,
            beginning_of_pass_write_index: Some(index),
            end_of_pass_write_index: Some(index + 1),
        })
    }

    /// How many of the recorded passes have timestamps.
    fn timed(&self) -> u32 {
        self.queries.as_ref().map_or(0, |queries| (self.recorded.len() as u32).min(queries.count / 2))
    }

    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(queries) = &self.queries {
            queries.resolve(encoder, self.timed() * 2);
        }
    }

    /// The passes recorded since the last read, in order, timed or not.
    pub fn recorded(&self) -> &[String] {
        &self.recorded
    }

    /// The passes' times once the encoder holding [`Self::resolve`] was submitted; empty
    /// without timestamps. Clears the timer for reuse.
    pub fn read(&mut self, gpu: &Gpu) -> Result<Vec<PassTime>> {
        let timed = self.timed();
        let recorded = std::mem::take(&mut self.recorded);
        let Some(queries) = &self.queries else {
            return Ok(Vec::new());
        };
        let stamps = queries.read(gpu, timed * 2).context("reading pass timestamps")?;
        let times = recorded
            .into_iter()
            .take(timed as usize)
            .zip(stamps.chunks_exact(2))
            .map(|(label, pair)| PassTime { label, ms: pair[1].saturating_sub(pair[0]) as f64 * self.period_ns * 1e-6 })
            .collect();
        Ok(times)
    }
}

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
    pub(crate) fn start(&mut self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder) -> Option<u32> {
        if self.used_pairs == CLOCK_PAIRS {
            if self.open > 0 {
                log::warn!("encoder clock full with {} encoders open: this encoder is not timed", self.open);
                return None;
            }
            match self.read_used(gpu) {
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
    pub(crate) fn take_ms(&mut self, gpu: &Gpu) -> Result<f64> {
        self.open = 0;
        let ms = self.read_used(gpu)?;
        Ok(std::mem::take(&mut self.carried_ms) + ms)
    }

    /// Sums the started pairs' spans and frees them.
    fn read_used(&mut self, gpu: &Gpu) -> Result<f64> {
        let used = std::mem::take(&mut self.used_pairs) * 2;
        if used == 0 {
            return Ok(0.0);
        }
        let mut encoder =
            gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("encoder clock") });
        self.queries.resolve(&mut encoder, used);
        gpu.queue.submit([encoder.finish()]);
        let stamps = self.queries.read(gpu, used).context("reading the encoder clock")?;
        let ns: u64 = stamps.chunks_exact(2).map(|pair| pair[1].saturating_sub(pair[0])).sum();
        Ok(ns as f64 * self.period_ns * 1e-6)
    }
}
