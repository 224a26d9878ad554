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
    fn new(gpu: &Gpu, ty: wgpu::QueryType, count: u32, label: &str) -> Self {
        let size = u64::from(count.max(1)) * 8;
        Self {
            set: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some(label),
                ty,
                count: count.max(1),
            }),
            count,
            resolve: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: gpu.device.create_buffer(&wgpu::BufferDescriptor {
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
        Ok(bytes
            .chunks_exact(8)
            .take(used as usize)
            .map(|c| u64::from_le_bytes(c.try_into().unwrap()))
            .collect())
    }
}

/// Occlusion queries: `begin_occlusion_query(i)` inside a pass that names [`Self::set`].
pub struct OcclusionQueries(ResolvedQueries);

impl OcclusionQueries {
    pub fn new(gpu: &Gpu, count: u32) -> Self {
        Self(ResolvedQueries::new(
            gpu,
            wgpu::QueryType::Occlusion,
            count,
            "occlusion queries",
        ))
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
        self.0
            .read(gpu, self.0.count)
            .context("reading occlusion query results")
    }
}

/// GPU time of whole render passes, from a begin/end timestamp pair per pass.
pub struct GpuTimer {
    queries: Option<ResolvedQueries>,
    labels: Vec<String>,
    period_ns: f64,
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
        let queries = gpu.has(wgpu::Features::TIMESTAMP_QUERY).then(|| {
            ResolvedQueries::new(
                gpu,
                wgpu::QueryType::Timestamp,
                passes * 2,
                "pass timestamps",
            )
        });
        Self {
            queries,
            labels: Vec::new(),
            period_ns: f64::from(gpu.queue.get_timestamp_period()),
        }
    }

    pub fn is_active(&self) -> bool {
        self.queries.is_some()
    }

    /// Timestamp writes for the next pass, or `None` when the adapter has no timestamps or
    /// the timer is full (that pass then goes untimed rather than failing).
    pub fn pass(&mut self, label: &str) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let queries = self.queries.as_ref()?;
        let index = self.labels.len() as u32 * 2;
        if index + 2 > queries.count {
            log::warn!("GpuTimer full: pass {label:?} is not timed");
            return None;
        }
        self.labels.push(label.to_owned());
        Some(wgpu::RenderPassTimestampWrites {
            query_set: &queries.set,
            beginning_of_pass_write_index: Some(index),
            end_of_pass_write_index: Some(index + 1),
        })
    }

    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(queries) = &self.queries {
            queries.resolve(encoder, self.labels.len() as u32 * 2);
        }
    }

    /// The passes' times once the encoder holding [`Self::resolve`] was submitted; empty
    /// without timestamps. Clears the timer for reuse.
    pub fn read(&mut self, gpu: &Gpu) -> Result<Vec<PassTime>> {
        let Some(queries) = &self.queries else {
            return Ok(Vec::new());
        };
        let stamps = queries
            .read(gpu, self.labels.len() as u32 * 2)
            .context("reading pass timestamps")?;
        let times = self
            .labels
            .drain(..)
            .zip(stamps.chunks_exact(2))
            .map(|(label, pair)| PassTime {
                label,
                ms: pair[1].saturating_sub(pair[0]) as f64 * self.period_ns * 1e-6,
            })
            .collect();
        Ok(times)
    }
}
