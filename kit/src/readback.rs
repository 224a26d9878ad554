//! Texture and buffer read-back without compute passes: copies of copyable formats and aspects
//! (colour, `Depth32Float`, the stencil aspect of `Depth24PlusStencil8`) into a mappable buffer,
//! and depth through a fragment pass where the adapter cannot copy it.

use std::time::Duration;

use anyhow::{Context, Result, anyhow, bail};

use crate::gpu::Gpu;

/// How long a read-back may wait for the GPU before it is reported as hung.
pub const READBACK_TIMEOUT: Duration = Duration::from_secs(120);

/// Maps a `MAP_READ` buffer after the work that fills it has been submitted, waiting at most
/// [`READBACK_TIMEOUT`].
pub fn map_buffer(gpu: &Gpu, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |result| {
        // The receiver only disappears when the wait below has already given up.
        let _ = sender.send(result);
    });
    gpu.device
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

/// Copies a `COPY_SRC` buffer into a fresh mappable one after the work submitted so far and
/// reads it as little-endian `u32` words (indirect arguments, counters).
pub fn read_buffer_words(gpu: &Gpu, buffer: &wgpu::Buffer) -> Result<Vec<u32>> {
    let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("buffer read-back"),
        size: buffer.size(),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.encoder("buffer read-back");
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, buffer.size());
    gpu.submit(encoder);
    let bytes = map_buffer(gpu, &staging).with_context(|| format!("reading back {buffer:?}"))?;
    Ok(bytes.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])).collect())
}

/// Tightly packed texels of one mip level and aspect.
#[derive(Clone, Debug, PartialEq)]
pub struct Texels {
    pub width: u32,
    pub height: u32,
    pub bytes_per_texel: u32,
    pub bytes: Vec<u8>,
}

impl Texels {
    pub fn texel(&self, x: u32, y: u32) -> &[u8] {
        let start = ((y * self.width + x) * self.bytes_per_texel) as usize;
        &self.bytes[start..start + self.bytes_per_texel as usize]
    }

    /// Interprets the texels as little-endian `f32` components (`R32Float`, `Depth32Float`, ...).
    pub fn as_f32(&self) -> Vec<f32> {
        self.bytes.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect()
    }

    /// The `width`×`height` texels whose top left is (`x`, `y`).
    pub fn region(&self, x: u32, y: u32, width: u32, height: u32) -> Texels {
        let (texel, stride) = (self.bytes_per_texel as usize, (self.width * self.bytes_per_texel) as usize);
        let bytes = (y as usize..(y + height) as usize)
            .flat_map(|row| {
                let start = row * stride + x as usize * texel;
                self.bytes[start..start + width as usize * texel].iter().copied()
            })
            .collect();
        Texels { width, height, bytes_per_texel: self.bytes_per_texel, bytes }
    }

    /// Interprets the texels as `f16` components (`Rgba16Float`, ...).
    pub fn as_f16(&self) -> Vec<f32> {
        self.bytes.chunks_exact(2).map(|c| half::f16::from_le_bytes([c[0], c[1]]).to_f32()).collect()
    }
}

/// Copies one mip level and aspect of a single-sampled texture to the CPU.
pub fn read_texture(gpu: &Gpu, texture: &wgpu::Texture, aspect: wgpu::TextureAspect, mip_level: u32) -> Result<Texels> {
    if texture.sample_count() != 1 {
        bail!("{texture:?} is multisampled; resolve it or read it through a fragment pass");
    }
    let format = texture.format();
    let bytes_per_texel = format
        .block_copy_size(Some(aspect))
        .with_context(|| format!("{format:?} aspect {aspect:?} cannot be copied to a buffer"))?;
    let width = (texture.width() >> mip_level).max(1);
    let height = (texture.height() >> mip_level).max(1);
    let unpadded_row = width * bytes_per_texel;
    let padded_row = unpadded_row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read-back buffer"),
        size: u64::from(padded_row) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.encoder("read-back");
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo { texture, mip_level, origin: wgpu::Origin3d::ZERO, aspect },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(padded_row), rows_per_image: None },
        },
        wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
    );
    gpu.submit(encoder);
    let padded = map_buffer(gpu, &buffer).with_context(|| format!("reading back {texture:?} mip {mip_level}"))?;
    let mut bytes = Vec::with_capacity((unpadded_row * height) as usize);
    for row in padded.chunks_exact(padded_row as usize) {
        bytes.extend_from_slice(&row[..unpadded_row as usize]);
    }
    Ok(Texels { width, height, bytes_per_texel, bytes })
}

/// Reads an `Rgba8Unorm` texture as an image.
pub fn read_rgba8(gpu: &Gpu, texture: &wgpu::Texture) -> Result<image::RgbaImage> {
    if texture.format() != wgpu::TextureFormat::Rgba8Unorm {
        bail!("read_rgba8 needs Rgba8Unorm, got {:?}", texture.format());
    }
    let texels = read_texture(gpu, texture, wgpu::TextureAspect::All, 0)?;
    image::RgbaImage::from_raw(texels.width, texels.height, texels.bytes).context("texel count does not match size")
}

/// Reads a single-sampled `Depth32Float` texture's values: by copy where the adapter can copy
/// depth to a buffer, else through a fragment pass writing each value's bits
/// (`shaders/kit/depth_bits.wgsl`). The texture needs `TEXTURE_BINDING` for the second.
pub fn read_depth(gpu: &Gpu, texture: &wgpu::Texture) -> Result<Vec<f32>> {
    if texture.format() != wgpu::TextureFormat::Depth32Float {
        bail!("read_depth needs Depth32Float, got {:?}", texture.format());
    }
    let copies = gpu.adapter.get_downlevel_capabilities().flags;
    if copies.contains(wgpu::DownlevelFlags::DEPTH_TEXTURE_AND_BUFFER_COPIES) {
        return Ok(read_texture(gpu, texture, wgpu::TextureAspect::All, 0)?.as_f32());
    }
    let format = wgpu::TextureFormat::R32Uint;
    let pipeline = crate::fullscreen::FullscreenPipeline {
        label: "depth bits",
        fragment: crate::shaders::DEPTH_BITS,
        entry_point: "fs_depth_bits",
        targets: &[Some(format.into())],
        depth_stencil: None,
        samples: 1,
    }
    .create(gpu);
    let depth_view = texture
        .create_view(&wgpu::TextureViewDescriptor { aspect: wgpu::TextureAspect::DepthOnly, ..Default::default() });
    let group = crate::fullscreen::bind_group(
        gpu,
        "depth bits",
        &pipeline,
        0,
        &[wgpu::BindingResource::TextureView(&depth_view)],
    );
    let size = (texture.width(), texture.height());
    Ok(crate::fullscreen::render_to_readback(gpu, "depth bits", &pipeline, &group, format, size)?.as_f32())
}

/// Reads the stencil aspect of a single-sampled depth-stencil texture.
pub fn read_stencil(gpu: &Gpu, texture: &wgpu::Texture, mip_level: u32) -> Result<Texels> {
    read_texture(gpu, texture, wgpu::TextureAspect::StencilOnly, mip_level)
}
