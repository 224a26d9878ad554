//! What a case read back, kept for a bug report: with `FRAGKIT_READBACK_DIR` set (the bug
//! report's captured run sets it), every texture read-back is also written there, in the order
//! the case made them: `readback-NNN.json` (format, mip level, size), `readback-NNN.bin` (the
//! rows as the kit holds them, top row first, unpadded) and `readback-NNN.png` where the format
//! has four 8-bit channels. A replayed capture is held to these: the pixels the case judged.

use std::path::PathBuf;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU32, Ordering};

use anyhow::{Context, Result};
use serde::Serialize;

use crate::readback::Texels;

/// The folder a bug report's captured run keeps its read-backs in.
pub const READBACK_DIR_ENV: &str = "FRAGKIT_READBACK_DIR";

fn folder() -> Option<&'static PathBuf> {
    static FOLDER: OnceLock<Option<PathBuf>> = OnceLock::new();
    FOLDER.get_or_init(|| std::env::var_os(READBACK_DIR_ENV).map(PathBuf::from)).as_ref()
}

/// One read-back's description, beside its pixels.
#[derive(Serialize)]
struct ReadbackEntry<'a> {
    index: u32,
    format: String,
    mip_level: u32,
    width: u32,
    height: u32,
    bytes_per_texel: u32,
    /// The PNG beside it, where the format has one.
    image: Option<&'a str>,
}

/// Keeps `texels` of a texture of `format` (mip `mip_level`) where a bug report asked for it.
pub fn keep(format: wgpu::TextureFormat, mip_level: u32, texels: &Texels) -> Result<()> {
    let Some(dir) = folder() else {
        return Ok(());
    };
    static NEXT: AtomicU32 = AtomicU32::new(0);
    let index = NEXT.fetch_add(1, Ordering::Relaxed);
    let stem = format!("readback-{index:03}");
    let four_bytes = matches!(
        format,
        wgpu::TextureFormat::Rgba8Unorm | wgpu::TextureFormat::Rgba8UnormSrgb | wgpu::TextureFormat::Rgba8Uint
    );
    let image_name = format!("{stem}.png");
    if four_bytes {
        let image = image::RgbaImage::from_raw(texels.width, texels.height, texels.bytes.clone())
            .context("read-back size and bytes disagree")?;
        image.save(dir.join(&image_name)).with_context(|| format!("writing {}", dir.join(&image_name).display()))?;
    }
    let entry = ReadbackEntry {
        index,
        format: format!("{format:?}"),
        mip_level,
        width: texels.width,
        height: texels.height,
        bytes_per_texel: texels.bytes_per_texel,
        image: four_bytes.then_some(image_name.as_str()),
    };
    let path = dir.join(format!("{stem}.json"));
    std::fs::write(&path, serde_json::to_string_pretty(&entry)?)
        .with_context(|| format!("writing {}", path.display()))?;
    std::fs::write(dir.join(format!("{stem}.bin")), &texels.bytes)
        .with_context(|| format!("writing {}", dir.join(format!("{stem}.bin")).display()))?;
    Ok(())
}
