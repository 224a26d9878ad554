//! `soak.*`: long runs, only when named (`fragkit check 'soak.*'`). Each technique renders
//! `frames` frames, recreating every resource on a resize every `resize_every` frames (cycling
//! through three sizes). After warm-up (the first cycle, so every size has been allocated once)
//! the process's resident memory may grow by less than 5 %; and the last frame must equal, bit for
//! bit, a fresh render of it — new objects replaying the frames since the last resize.

fragkit::cases! {
    cps: CASE;
    oit: CASE;
    cbr: CASE;
}

use anyhow::{Context, Result, bail};
use fragkit::gpu::Gpu;
use fragkit::harness::{Ctx, Outcome, ParamKind, ParamSpec, Verdict};

pub const PARAMS: &[ParamSpec] = &[
    ParamSpec { name: "frames", kind: ParamKind::CountIn(4, 1_000_000), default: "1000", help: "frames rendered" },
    ParamSpec {
        name: "resize_every",
        kind: ParamKind::CountIn(2, 1_000_000),
        default: "100",
        help: "frames between resizes (every resource recreated)",
    },
];

/// The sizes a soak cycles through, one per segment.
const SIZES: [(u32, u32); 3] = [(64, 48), (48, 64), (80, 40)];

/// Resident memory may grow by less than this after warm-up.
const MAX_GROWTH: f64 = 0.05;

/// A technique under soak: made for one size, renders frame after frame, shows its output.
pub trait Soaked: Sized {
    fn new(gpu: &Gpu, size: (u32, u32)) -> Result<Self>;
    fn render(&mut self, gpu: &Gpu, frame: u32) -> Result<()>;
    /// The output's raw texels.
    fn output(&self, gpu: &Gpu) -> Result<Vec<u8>>;
}

/// The process's resident set size in bytes (Linux: /proc/self/status).
fn resident_bytes() -> Result<u64> {
    let status = std::fs::read_to_string("/proc/self/status").context("reading /proc/self/status")?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:")).context("no VmRSS line in /proc/self/status")?;
    let kib: u64 = line.split_whitespace().nth(1).context("VmRSS without a value")?.parse().context("VmRSS value")?;
    Ok(kib * 1024)
}

/// Runs the soak for technique `T`.
pub fn soak<T: Soaked>(ctx: &mut Ctx) -> Result<Outcome> {
    if resident_bytes().is_err() {
        return Ok(Outcome::NotSupported("resident memory: /proc/self/status has no VmRSS here".into()));
    }
    let frames = ctx.params.count_u32("frames")?;
    let every = ctx.params.count_u32("resize_every")?;
    let warm_up = (every * SIZES.len() as u32).min(frames - 1);
    let (mut technique, mut segment_start) = (T::new(ctx.gpu, SIZES[0])?, 0);
    let mut resident_after_warm_up = 0;
    let mut resident_peak = 0;
    for frame in 0..frames {
        if frame > 0 && frame % every == 0 {
            // Drop the old resources before making the new ones, as a resizing app would.
            drop(technique);
            technique = T::new(ctx.gpu, SIZES[((frame / every) as usize) % SIZES.len()])?;
            segment_start = frame;
        }
        technique.render(ctx.gpu, frame).with_context(|| format!("frame {frame}"))?;
        if frame == warm_up {
            ctx.gpu.wait()?;
            resident_after_warm_up = resident_bytes()?;
        }
        if frame > warm_up && frame % 10 == 0 {
            resident_peak = resident_peak.max(resident_bytes()?);
        }
    }
    ctx.gpu.wait()?;
    let resident_end = resident_bytes()?;
    resident_peak = resident_peak.max(resident_end);
    let last = technique.output(ctx.gpu)?;
    drop(technique);

    let size = SIZES[(((frames - 1) / every) as usize) % SIZES.len()];
    let mut fresh = T::new(ctx.gpu, size)?;
    for frame in segment_start..frames {
        fresh.render(ctx.gpu, frame)?;
    }
    let differing = last.iter().zip(fresh.output(ctx.gpu)?).filter(|(a, b)| **a != *b).count();

    let growth = resident_peak as f64 / resident_after_warm_up as f64 - 1.0;
    ctx.metric("frames", frames);
    ctx.metric("resizes", (frames - 1) / every);
    ctx.metric("resident_mib_after_warm_up", resident_after_warm_up as f64 / 1048576.0);
    ctx.metric("resident_mib_peak_after_warm_up", resident_peak as f64 / 1048576.0);
    ctx.metric("resident_growth", growth);
    ctx.metric("last_frame_bytes_differing_from_fresh", differing);
    let mut verdict = Verdict::new();
    if growth >= MAX_GROWTH {
        verdict.fail(format!(
            "resident memory grew {:.1} % after warm-up ({:.1} → {:.1} MiB peak), at most {:.0} % allowed",
            100.0 * growth,
            resident_after_warm_up as f64 / 1048576.0,
            resident_peak as f64 / 1048576.0,
            100.0 * MAX_GROWTH
        ));
    }
    if differing > 0 {
        verdict.fail(format!("the last frame differs from a fresh render of it in {differing} bytes"));
    }
    if last.is_empty() {
        bail!("the soak read back an empty output");
    }
    Ok(verdict.outcome())
}
