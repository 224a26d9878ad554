//! GPU queries: occlusion counts and timestamps around whole render passes (timestamps inside a
//! pass are meaningless on tile/deferred rasterisers such as lavapipe, which runs at pass end).

use anyhow::{Context, Result};

use crate::gpu::Gpu;
use crate::query_set::ResolvedQueries;

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
        self.0.read(&gpu.device, self.0.count).context("reading occlusion query results")
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
        let stamps = queries.read(&gpu.device, timed * 2).context("reading pass timestamps")?;
        let times = recorded
            .into_iter()
            .take(timed as usize)
            .zip(stamps.chunks_exact(2))
            .map(|(label, pair)| PassTime { label, ms: pair[1].saturating_sub(pair[0]) as f64 * self.period_ns * 1e-6 })
            .collect();
        Ok(times)
    }
}
