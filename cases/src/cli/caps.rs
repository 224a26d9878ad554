//! `fragkit caps`: the selected adapter's capabilities, measured with tiny renders.

use std::path::PathBuf;

use anyhow::{Context, Result};
use fragkit::caps::Caps;
use fragkit::gpu::{AdapterSelector, Gpu};

use super::matrix::{MatrixArgs, run_each_showing_output};

#[derive(clap::Args)]
pub struct CapsArgs {
    /// Also write the report as JSON (with --matrix: `<reports>/<name>.caps.json` each).
    #[arg(long)]
    json: Option<PathBuf>,
    #[command(flatten)]
    matrix: MatrixArgs,
}

pub fn caps(selector: &AdapterSelector, args: CapsArgs) -> Result<()> {
    if let Some(names) = &args.matrix.matrix {
        return run_each_showing_output(selector, &args.matrix, names, "caps");
    }
    let json = args.json;
    let gpu = Gpu::open(selector)?;
    let caps = Caps::measure(&gpu)?;
    print_caps(&caps);
    if let Some(path) = json {
        let text = serde_json::to_string_pretty(&caps)?;
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

fn print_caps(caps: &Caps) {
    let d = &caps.adapter;
    println!("adapter: {} ({}, {} {})", d.name, d.backend, d.driver, d.driver_info);
    println!("max 2D texture: {}", caps.max_texture_dimension_2d);
    match &caps.subpixel_precision {
        Ok(p) => {
            println!("sub-pixel precision (measured): {} bits, vertices moved up to {} px", p.bits, p.largest_move)
        }
        Err(e) => println!("sub-pixel precision: measurement failed: {e}"),
    }
    for f in &caps.format_samples {
        println!("sample counts advertised for {:<22} {:?}", f.format, f.advertised);
    }
    for m in &caps.multisample {
        println!("{}x: standard positions: {}", m.samples, m.standard_positions);
        match &m.positions {
            Ok(p) => {
                println!("    sample mask honoured: {}", p.sample_mask_honoured);
                for (route, result) in &p.routes {
                    match result {
                        Ok(positions) => {
                            let mids: Vec<_> = positions.iter().map(|s| s.mid()).collect();
                            println!("    positions by {route:?}: {mids:?}")
                        }
                        Err(e) => println!("    positions by {route:?}: failed: {e}"),
                    }
                }
                for (route, why) in &p.skipped {
                    println!("    positions by {route:?}: skipped, {why}");
                }
            }
            Err(e) => println!("    positions: measurement failed: {e}"),
        }
        match &m.per_sample_shading {
            Ok(s) => println!(
                "    per-sample shading: {} invocations, sample_index {:?}, fract(position) {:?}",
                s.invocations, s.sample_index, s.position
            ),
            Err(e) => println!("    per-sample shading: failed: {e}"),
        }
        match &m.alpha_to_coverage {
            Ok(a) => println!(
                "    alpha-to-coverage: levels {:?}, monotonic {}, dithered {}, masks {:?}, first alpha step (of 256) per count {:?}",
                a.levels, a.monotonic, a.dithered, a.masks, a.thresholds
            ),
            Err(e) => println!("    alpha-to-coverage: {e}"),
        }
    }
    println!("real sample counts (measured): {:?}", caps.real_sample_counts());
    println!("occlusion queries: {:?}", caps.occlusion);
    println!("timestamps: {} (period {} ns)", caps.timestamps, caps.timestamp_period_ns);
    println!("early depth test feature: {}", caps.early_depth_test_feature);
    println!("fragment storage writes: {}", caps.fragment_storage_writes);
}
