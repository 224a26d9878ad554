//! `fragkit adapters`: every adapter on every backend, as a table. What probing the backends
//! logs (EGL looking for a DRI driver on a machine without one) is kept out of it; `-v` prints it.

use anyhow::Result;
use fragkit::gpu::{AdapterDescription, all_adapters};

pub fn adapters(verbose: bool) -> Result<()> {
    let adapters: Vec<AdapterDescription> =
        all_adapters().iter().map(|a| AdapterDescription::of(&a.get_info())).collect();
    let logged = fragkit::harness::diagnostics::take();
    if adapters.is_empty() {
        anyhow::bail!(
            "no GPU adapter found. Install a Vulkan driver; on Debian `apt-get install mesa-vulkan-drivers` gives lavapipe"
        );
    }
    let width = |column: fn(&AdapterDescription) -> &str, title: &str| {
        adapters.iter().map(|d| column(d).chars().count()).max().unwrap_or(0).max(title.len())
    };
    let widths = [
        width(|d| &d.backend, "backend"),
        width(|d| &d.name, "adapter"),
        width(|d| &d.device_type, "type"),
        width(|d| &d.driver, "driver"),
    ];
    let row = |cells: [&str; 5]| {
        println!(
            "{:<w0$}  {:<w1$}  {:<w2$}  {:<w3$}  {}",
            cells[0],
            cells[1],
            cells[2],
            cells[3],
            cells[4],
            w0 = widths[0],
            w1 = widths[1],
            w2 = widths[2],
            w3 = widths[3]
        )
    };
    row(["backend", "adapter", "type", "driver", "driver info"]);
    for d in &adapters {
        row([&d.backend, &d.name, &d.device_type, &d.driver, d.driver_info.trim()]);
    }
    if !logged.is_empty() && !verbose {
        let plural = if logged.len() == 1 { "" } else { "s" };
        println!("({} log record{plural} from probing the backends hidden; -v prints them)", logged.len());
    }
    Ok(())
}
