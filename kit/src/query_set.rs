//! A query set with the buffers its results travel through to the CPU: what occlusion queries,
//! pass timers and the encoder clock share.

use anyhow::Result;

use crate::mapping::map_read;

/// A query set plus the buffers its results travel through to the CPU.
pub(crate) struct ResolvedQueries {
    pub(crate) set: wgpu::QuerySet,
    pub(crate) count: u32,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
}

impl ResolvedQueries {
    pub(crate) fn new(device: &wgpu::Device, ty: wgpu::QueryType, count: u32, label: &str) -> Self {
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

    pub(crate) fn resolve(&self, encoder: &mut wgpu::CommandEncoder, used: u32) {
        if used > 0 {
            encoder.resolve_query_set(&self.set, 0..used, &self.resolve, 0);
            encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, u64::from(used) * 8);
        }
    }

    pub(crate) fn read(&self, device: &wgpu::Device, used: u32) -> Result<Vec<u64>> {
        if used == 0 {
            return Ok(Vec::new());
        }
        let bytes = map_read(device, &self.readback)?;
        Ok(bytes.chunks_exact(8).take(used as usize).map(|c| u64::from_le_bytes(c.try_into().unwrap())).collect())
    }
}
