//! `fragkit`: list adapters, measure capabilities, list and run the conformance cases.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use fragkit::caps::Caps;
use fragkit::gpu::{AdapterDescription, AdapterSelector, Gpu, all_adapters};
use fragkit::harness::expectations::{BUILT_IN, Expectations};
use fragkit::harness::params::parse_overrides;
use fragkit::harness::report::Report;
use fragkit::harness::runner::{check_overrides, check_sizes, is_opt_in, run_case, select};
use fragkit::harness::{Case, sweep};

#[derive(Parser)]
#[command(name = "fragkit", version, about = "Deterministic, compute-free GPU conformance kit")]
struct Cli {
    /// Backend: vulkan, gl, metal, dx12.
    #[arg(long, global = true, env = "WGPU_BACKEND")]
    backend: Option<String>,
    /// Substring of the adapter name.
    #[arg(long, global = true, env = "WGPU_ADAPTER_NAME")]
    adapter: Option<String>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Every adapter on every backend.
    Adapters,
    /// Measure the selected adapter's capabilities with tiny renders.
    Caps {
        /// Also write the report as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// List cases with their parameters and requirements.
    List { pattern: Option<String> },
    /// Render a technique's intermediates and results as PNGs for a person to look at.
    Render {
        #[command(subcommand)]
        technique: Technique,
    },
    /// Sweep a technique's settings and write error against GPU time (JSON, markdown, PNG plot).
    Report {
        #[command(subcommand)]
        technique: ReportTechnique,
    },
    /// Run cases (glob patterns; all when none) and exit 1 on any unexpected failure.
    Check {
        patterns: Vec<String>,
        /// Override a parameter: key=value.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Write the JSON report here.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Write evidence images into this folder.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Known-issues file (default: the one built in, cases/expectations.toml).
        #[arg(long)]
        expectations: Option<PathBuf>,
        /// Run each case with N parameter sets drawn from its declared ranges (cases without
        /// ranges run once at their defaults); `--set` pins a parameter. Failures print the
        /// command that reproduces them.
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=10_000))]
        sweep: Option<u32>,
        /// Seed of the sweep's draws.
        #[arg(long, default_value_t = 1, requires = "sweep")]
        seed: u64,
    },
}

#[derive(Subcommand)]
enum Technique {
    /// Order-independent transparency: every method's image and error map against the exact composite.
    Oit {
        #[arg(long)]
        out: PathBuf,
        #[arg(long, default_value = "160x160", value_parser = parse_size)]
        size: (u32, u32),
        /// paper, intersecting, or stiff_<layers>.
        #[arg(long, default_value = "paper")]
        scene: String,
        #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=64))]
        samples: u32,
        #[arg(long, default_value_t = 16, value_parser = frame_count())]
        frames: u32,
        #[arg(long, default_value_t = 1)]
        seed: u32,
    },
    /// Coarse pixel shading: LOD buffer, stencil masks, lit mips, the three composites.
    Cps {
        #[arg(long)]
        out: PathBuf,
        #[arg(long, default_value = "320x180", value_parser = parse_size)]
        size: (u32, u32),
        /// foveated or content.
        #[arg(long, default_value = "foveated")]
        policy: String,
        #[arg(long, default_value_t = 5, value_parser = lod_level())]
        max_level: u32,
        #[arg(long, default_value_t = 200, value_parser = light_count())]
        lights: u32,
        #[arg(long, default_value_t = 1)]
        seed: u32,
    },
    /// Checkerboard rendering: frames N−1 and N, motion, pixel sources, reconstruction, error map.
    Cbr {
        #[arg(long)]
        out: PathBuf,
        #[arg(long, default_value = "192x128", value_parser = parse_size)]
        size: (u32, u32),
        /// static, pan_<x>x<y> (pixels a frame), strafe_<metres>, object_<metres>.
        #[arg(long, default_value = "strafe_0.1")]
        motion: String,
        /// forward or deferred.
        #[arg(long, default_value = "forward")]
        shading: String,
        /// cso, cso:<tolerance> or aso.
        #[arg(long, default_value = "cso")]
        detection: String,
        /// auto (the kit's measured choice), msaa2x or offset_passes.
        #[arg(long, default_value = "auto")]
        path: String,
        #[arg(long, default_value_t = 4, value_parser = frame_count())]
        frames: u32,
        #[arg(long, default_value_t = 32, value_parser = light_count())]
        lights: u32,
        #[arg(long, default_value_t = 5)]
        seed: u32,
    },
}

#[derive(Subcommand)]
enum ReportTechnique {
    /// OIT: method × sample count × frames × post-filter, against the exact composite.
    Oit {
        #[arg(long)]
        out: PathBuf,
        #[arg(long, default_value = "128x128", value_parser = parse_size)]
        size: (u32, u32),
        /// paper, intersecting, or stiff_<layers>.
        #[arg(long, default_value = "paper")]
        scene: String,
        #[arg(long, value_delimiter = ',', default_value = "1,4,16,64", value_parser = frame_count())]
        frames: Vec<u32>,
        #[arg(long, default_value_t = 1)]
        seed: u32,
    },
    /// CPS: policy × top level × light count × composite, against full resolution and the naive way.
    Cps {
        #[arg(long)]
        out: PathBuf,
        #[arg(long, default_value = "320x180", value_parser = parse_size)]
        size: (u32, u32),
        #[arg(long, value_delimiter = ',', default_value = "1,16,64,200", value_parser = light_count())]
        lights: Vec<u32>,
        #[arg(long, value_delimiter = ',', default_value = "2,4,6", value_parser = lod_level())]
        max_levels: Vec<u32>,
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=1000))]
        repeats: u32,
    },
    /// CBR: full resolution, checkerboarding (forward/deferred × ASO/CSO × path) and a half-resolution
    /// upscale, on static and moving sequences.
    Cbr {
        #[arg(long)]
        out: PathBuf,
        #[arg(long, default_value = "320x180", value_parser = parse_size)]
        size: (u32, u32),
        #[arg(long, default_value_t = 64, value_parser = light_count())]
        lights: u32,
        /// Frames a sequence runs (the first is warm-up, the last is measured).
        #[arg(long, default_value_t = 6, value_parser = frame_count())]
        frames: u32,
        /// Sequences: static, pan_<x>x<y>, strafe_<metres>, object_<metres> (default: one of each).
        #[arg(long, value_delimiter = ',')]
        motions: Vec<String>,
    },
}

/// Light counts: at least one; 65536 lights are 2048 rows of the 64-wide light texture, within
/// WebGPU's guaranteed 8192.
fn light_count() -> clap::builder::RangedI64ValueParser<u32> {
    clap::value_parser!(u32).range(1..=65_536)
}

fn frame_count() -> clap::builder::RangedI64ValueParser<u32> {
    clap::value_parser!(u32).range(1..=100_000)
}

/// CPS levels: 0..=8 (2^8-pixel coarse fragments, the stencil pyramid's top).
fn lod_level() -> clap::builder::RangedI64ValueParser<u32> {
    clap::value_parser!(u32).range(0..=fragkit::cps::MAX_LEVEL as i64)
}

fn parse_size(text: &str) -> Result<(u32, u32), String> {
    match fragkit::harness::ParamKind::Sizes.parse(text) {
        Ok(fragkit::harness::params::ParamValue::Sizes(sizes)) if sizes.len() == 1 => Ok(sizes[0]),
        Ok(_) => Err(format!("{text:?}: expected one size like 320x180")),
        Err(e) => Err(format!("{e:#}")),
    }
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => code,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> Result<ExitCode> {
    fragkit::shaders::check_shader_dir()?;
    let selector = AdapterSelector { backend: cli.backend, adapter_name: cli.adapter };
    match cli.command {
        Command::Adapters => {
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
        }
        Command::Caps { json } => {
            let gpu = Gpu::open(&selector)?;
            let caps = Caps::measure(&gpu)?;
            print_caps(&caps);
            if let Some(path) = json {
                let text = serde_json::to_string_pretty(&caps)?;
                std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
            }
        }
        Command::List { pattern } => {
            let patterns: Vec<String> = pattern.into_iter().collect();
            let cases = if patterns.is_empty() {
                fragkit_cases::ALL.iter().collect()
            } else {
                select(fragkit_cases::ALL, &patterns)?
            };
            for case in cases {
                let requires =
                    if case.requires.is_empty() { String::new() } else { format!(" [requires {:?}]", case.requires) };
                let opt_in = if is_opt_in(case.name) { " [opt-in: runs only when a pattern names it]" } else { "" };
                println!("{}{requires}{opt_in}\n    {}", case.name, case.summary);
                for p in case.params {
                    println!("    --set {}={}   ({})", p.name, p.default, p.help);
                }
            }
        }
        Command::Render { technique } => render(&selector, technique)?,
        Command::Report { technique } => report(&selector, technique)?,
        Command::Check { patterns, sets, json, out, expectations, sweep, seed } => {
            let sweep = sweep.map(|runs| (runs, seed));
            return check(&selector, &patterns, &sets, json, out, expectations, sweep);
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn render(selector: &AdapterSelector, technique: Technique) -> Result<()> {
    match technique {
        Technique::Oit { out, size, scene, samples, frames, seed } => {
            let scene = oit_scene(&scene, seed)?;
            std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
            let gpu = Gpu::open(selector)?;
            let offered = fragkit::caps::common_sample_counts(&gpu);
            anyhow::ensure!(
                offered.contains(&samples),
                "--samples {samples}: this adapter offers sample counts {offered:?}"
            );
            fragkit::deferred::gbuffer::check_size(&gpu, size).context("--size")?;
            let pictures = gpu.scoped("render oit", || {
                fragkit::oit::pictures::render_all(&gpu, &scene, size, samples, frames, seed)
            })?;
            for (name, image) in pictures {
                let path = out.join(format!("oit_{}_{name}.png", scene.name));
                image.save(&path).with_context(|| format!("writing {}", path.display()))?;
                println!("{}", path.display());
            }
        }
        Technique::Cps { out, size, policy, max_level, lights, seed } => {
            let policy = fragkit::cps::LodPolicy::parse(&policy)?;
            std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
            let gpu = Gpu::open(selector)?;
            fragkit::deferred::gbuffer::check_size(&gpu, size).context("--size")?;
            let pictures = gpu.scoped("render cps", || {
                fragkit::cps::pictures::render_all(&gpu, size, policy, max_level, lights, seed)
            })?;
            for (name, image) in pictures {
                let path = out.join(format!("cps_{name}.png"));
                image.save(&path).with_context(|| format!("writing {}", path.display()))?;
                println!("{}", path.display());
            }
        }
        Technique::Cbr { out, size, motion, shading, detection, path, frames, lights, seed } => {
            let motion = fragkit::cbr::scene::Motion::parse(&motion)?;
            let shading = fragkit::cbr::Shading::parse(&shading)?;
            let detection = fragkit::cbr::Detection::parse(&detection)?;
            std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
            let gpu = Gpu::open(selector)?;
            fragkit::cbr::renderer::check_checkerboard_screen(&gpu, size).context("--size")?;
            let scene = fragkit::cbr::scene::textured_corridor(seed, lights, motion);
            let path = fragkit::cbr::sampling::CheckerboardPath::choose(&gpu, &path)?;
            let config = fragkit::cbr::CheckerboardConfig {
                detection,
                ..fragkit::cbr::CheckerboardConfig::new(size, path, shading)
            };
            println!("path: {}", path.name());
            let pictures =
                gpu.scoped("render cbr", || fragkit::cbr::pictures::render_all(&gpu, &scene, config, frames))?;
            for (name, image) in pictures {
                let path = out.join(format!("cbr_{name}.png"));
                image.save(&path).with_context(|| format!("writing {}", path.display()))?;
                println!("{}", path.display());
            }
        }
    }
    Ok(())
}

/// A named OIT scene: `paper`, `intersecting` or `stiff_<layers>`.
fn oit_scene(name: &str, seed: u32) -> Result<fragkit::oit::scene::QuadScene> {
    use fragkit::oit::scene::QuadScene;
    match name {
        "paper" => Ok(QuadScene::paper()),
        "intersecting" => Ok(QuadScene::intersecting()),
        other => match other.strip_prefix("stiff_").map(str::parse::<u32>) {
            Some(Ok(layers)) if (1..=256).contains(&layers) => Ok(QuadScene::stiff(layers, seed)),
            _ => anyhow::bail!("unknown OIT scene {other:?}; expected paper, intersecting or stiff_<1..=256>"),
        },
    }
}

fn report(selector: &AdapterSelector, technique: ReportTechnique) -> Result<()> {
    match technique {
        ReportTechnique::Oit { out, size, scene, frames, seed } => {
            let scene = oit_scene(&scene, seed)?;
            let sweep = fragkit::oit::report::OitSweep { size, frame_counts: frames, seed };
            let gpu = Gpu::open(selector)?;
            fragkit::deferred::gbuffer::check_size(&gpu, size).context("--size")?;
            let progress = indicatif::ProgressBar::new_spinner();
            let rows = gpu.scoped("oit report", || {
                fragkit::oit::report::run_sweep(&gpu, &scene, &sweep, |row| {
                    progress.set_message(format!("{} {}x {} frames", row.method, row.samples, row.frames));
                    progress.tick();
                })
            })?;
            progress.finish_and_clear();
            fragkit::oit::report::write_report(&out, &gpu.description, &rows)?;
            println!("{}", out.join("oit_report.md").display());
        }
        ReportTechnique::Cps { out, size, lights, max_levels, repeats } => {
            let sweep = fragkit::cps::report::CpsSweep {
                size,
                light_counts: lights,
                max_levels,
                repeats,
                ..Default::default()
            };
            let gpu = Gpu::open(selector)?;
            fragkit::deferred::gbuffer::check_size(&gpu, size).context("--size")?;
            let progress = indicatif::ProgressBar::new_spinner();
            let rows = gpu.scoped("cps report", || {
                fragkit::cps::report::run_sweep(&gpu, &sweep, |row| {
                    progress.set_message(format!(
                        "{} lights, {} {} level {}",
                        row.lights, row.method, row.composite, row.max_level
                    ));
                    progress.tick();
                })
            })?;
            progress.finish_and_clear();
            fragkit::cps::report::write_report(&out, &gpu.description, &rows)?;
            println!("{}", out.join("cps_report.md").display());
        }
        ReportTechnique::Cbr { out, size, lights, frames, motions } => {
            let motions = motions.iter().map(|m| fragkit::cbr::scene::Motion::parse(m)).collect::<Result<Vec<_>>>()?;
            anyhow::ensure!(
                frames >= 2,
                "--frames {frames}: a sequence needs at least 2 frames (warm-up and one timed)"
            );
            let gpu = Gpu::open(selector)?;
            fragkit::cbr::renderer::check_checkerboard_screen(&gpu, size).context("--size")?;
            let defaults = fragkit::cbr::report::CbrSweep::for_adapter(&gpu);
            let sweep = fragkit::cbr::report::CbrSweep {
                size,
                lights,
                frames,
                motions: if motions.is_empty() { defaults.motions.clone() } else { motions },
                ..defaults
            };
            let progress = indicatif::ProgressBar::new_spinner();
            let rows = gpu.scoped("cbr report", || {
                fragkit::cbr::report::run_sweep(&gpu, &sweep, |sequence| {
                    progress.set_message(sequence.to_owned());
                    progress.tick();
                })
            })?;
            progress.finish_and_clear();
            fragkit::cbr::report::write_report(&out, &gpu.description, &sweep, &rows)?;
            println!("{}", out.join("cbr_report.md").display());
        }
    }
    Ok(())
}

fn check(
    selector: &AdapterSelector,
    patterns: &[String],
    sets: &[String],
    json: Option<PathBuf>,
    out: Option<PathBuf>,
    expectations: Option<PathBuf>,
    sweep: Option<(u32, u64)>,
) -> Result<ExitCode> {
    // Check every input before touching the GPU.
    let cases = select(fragkit_cases::ALL, patterns)?;
    let overrides = parse_overrides(sets)?;
    check_overrides(&cases, &overrides)?;
    let expectations = match expectations {
        Some(path) => Expectations::load(&path)?,
        None => Expectations::parse(BUILT_IN, "cases/expectations.toml (built in)")?,
    };
    if let Some(dir) = &out {
        std::fs::create_dir_all(dir).with_context(|| format!("creating the evidence folder {}", dir.display()))?;
    }
    if let Some(path) = &json {
        // Fail now, not after the run, when the report cannot be written.
        let probe = path.with_extension("json.tmp");
        std::fs::write(&probe, b"").with_context(|| format!("the report path {} is not writable", path.display()))?;
        std::fs::remove_file(&probe).ok();
    }
    let gpu = Gpu::open(selector)?;
    let d = &gpu.description;
    println!("adapter: {} ({}, {} {})", d.name, d.backend, d.driver, d.driver_info);

    // Each run: a case and its overrides (drawn from its ranges under --sweep, --set pinned).
    let runs: Vec<(&Case, BTreeMap<String, String>)> = match sweep {
        None => cases.iter().map(|&case| (case, overrides.clone())).collect(),
        Some((count, seed)) => cases
            .iter()
            .flat_map(|&case| {
                let draws = if case.sweep.is_empty() { 1 } else { count };
                let overrides = &overrides;
                (0..draws).map(move |index| {
                    let mut drawn = sweep::draw(case, seed, index);
                    drawn.extend(overrides.iter().map(|(k, v)| (k.clone(), v.clone())));
                    drawn.retain(|key, _| case.params.iter().any(|p| p.name == key));
                    (case, drawn)
                })
            })
            .collect(),
    };
    for (case, drawn) in &runs {
        check_sizes(&gpu, &[case], drawn)?;
    }

    let progress = indicatif::ProgressBar::new(runs.len() as u64);
    progress.set_style(indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}").expect("static template"));
    let mut report = Report { adapter: gpu.description.clone(), cases: Vec::new() };
    let mut gpu = gpu;
    for (case, drawn) in runs {
        progress.set_message(case.name);
        let mut record = run_case(&gpu, case, &drawn, &expectations, out.as_deref());
        if sweep.is_some() && record.outcome.is_failure() {
            record.reason = format!("{} [reproduce: {}]", record.reason, sweep::reproduce_line(case, &drawn));
        }
        report.cases.push(record);
        progress.inc(1);
        if gpu.lost().is_some() {
            // The lost case is recorded as failed; the rest run on a fresh device.
            match gpu.reopen() {
                Ok(fresh) => gpu = fresh,
                Err(e) => {
                    progress.finish_and_clear();
                    if let Some(path) = &json {
                        report.write_atomically(path)?;
                    }
                    return Err(
                        e.context("reopening the device after it was lost; the report holds the cases that ran")
                    );
                }
            }
        }
    }
    progress.finish_and_clear();
    print_table(&report);
    if let Some(path) = &json {
        report.write_atomically(path)?;
    }
    let failures = report.failures();
    println!("{} cases: {} unexpected failures", report.cases.len(), failures);
    Ok(if failures == 0 { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

/// The most telling metric of a case, shown in the table.
fn key_metric(metrics: &std::collections::BTreeMap<String, serde_json::Value>) -> String {
    const KEYS: &[&str] = &["positions", "time_ratio", "differing_pixels", "4x.pixels_differing", "precision"];
    KEYS.iter().find_map(|k| metrics.get(*k).map(|v| format!("{k}={}", compact(v)))).unwrap_or_default()
}

fn compact(value: &serde_json::Value) -> String {
    match value {
        serde_json::Value::Number(n) => n.as_f64().map_or(n.to_string(), |f| format!("{f:.3}")),
        other => {
            let text = other.to_string();
            if text.len() > 60 { format!("{}…", &text[..60]) } else { text }
        }
    }
}

fn print_table(report: &Report) {
    println!("{:<34} {:<15} {:>9} {:>9}  {:<40} reason", "case", "outcome", "gpu ms", "wall ms", "key metric");
    for c in &report.cases {
        let gpu_ms = c.gpu_ms.map_or("-".into(), |ms| format!("{ms:.2}"));
        println!(
            "{:<34} {:<15} {:>9} {:>9.1}  {:<40} {}",
            c.name,
            c.outcome.label(),
            gpu_ms,
            c.wall_ms,
            key_metric(&c.metrics),
            // One line a case: wgpu's multi-line messages are joined.
            c.reason.lines().map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" / ")
        );
    }
}

fn print_caps(caps: &Caps) {
    let d = &caps.adapter;
    println!("adapter: {} ({}, {} {})", d.name, d.backend, d.driver, d.driver_info);
    println!("max 2D texture: {}", caps.max_texture_dimension_2d);
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
