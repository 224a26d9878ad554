//! `fragkit adapters`: every adapter on every backend.

use anyhow::Result;
use fragkit::gpu::{AdapterDescription, all_adapters};

pub fn adapters() -> Result<()> {
    let adapters = all_adapters();
    if adapters.is_empty() {
        anyhow::bail!(
            "no GPU adapter found. Install a Vulkan driver; on Debian `apt-get install mesa-vulkan-drivers` gives lavapipe"
        );
    }
    for adapter in adapters {
        let d = AdapterDescription::of(&adapter.get_info());
        println!("{:<8} {:<40} {} ({}) [{}]", d.backend, d.name, d.driver, d.driver_info, d.device_type);
    }
    Ok(())
}
