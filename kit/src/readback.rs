//! Texture and buffer read-back without compute passes: copies of copyable formats and aspects
//! (colour, `Depth32Float`, the stencil aspect of `Depth24PlusStencil8`) into a mappable buffer.
//! Depth an adapter cannot copy is read through a fragment pass (`depth_readback`).

use anyhow::{Context, Result, bail};

use crate::gpu::Gpu;
pub use crate::mapping::READBACK_TIMEOUT;
use crate::mapping::map_read;

/// Maps a `MAP_READ` buffer after the work that fills it has been submitted, waiting at most
/// [`READBACK_TIMEOUT`].
pub fn map_buffer(gpu: &Gpu, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
    map_read(&gpu.device, buffer)
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
    let texels = Texels { width, height, bytes_per_texel, bytes };
    crate::readback_log::keep(format, mip_level, &texels)?;
    Ok(texels)
}

/// Reads an `Rgba8Unorm` texture as an image.
pub fn read_rgba8(gpu: &Gpu, texture: &wgpu::Texture) -> Result<image::RgbaImage> {
    if texture.format() != wgpu::TextureFormat::Rgba8Unorm {
        bail!("read_rgba8 needs Rgba8Unorm, got {:?}", texture.format());
    }
    let texels = read_texture(gpu, texture, wgpu::TextureAspect::All, 0)?;
    image::RgbaImage::from_raw(texels.width, texels.height, texels.bytes).context("texel count does not match size")
}

/// Reads the stencil aspect of a single-sampled depth-stencil texture.
pub fn read_stencil(gpu: &Gpu, texture: &wgpu::Texture, mip_level: u32) -> Result<Texels> {
    read_texture(gpu, texture, wgpu::TextureAspect::StencilOnly, mip_level)
}
