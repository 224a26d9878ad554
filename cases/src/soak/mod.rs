//! `soak.*`: long runs, only when named (`fragkit check 'soak.*'`). Each technique renders
//! `frames` frames in `cycles` cycles, recreating every resource at each cycle's start, as a
//! resize does (cycling through three sizes). At each cycle's end, once the GPU is idle, the
//! process's memory and wgpu's live objects and memory are sampled (`memory.rs`); memory that
//! keeps growing through the second half of the cycles is a leak, reported in bytes a frame, and
//! one that stops (a cache) is not (`fragkit::memory_growth`). Growth is checked by running on:
//! the run doubles, up to four times its length, until the growth stops — a cache that fills
//! slowly (SwiftShader's, over about 1500 frames of OIT) then passes at any requested length, and
//! a leak fails with its rate. And the last frame must equal, bit for bit, a fresh render of it:
//! new objects replaying the last cycle's frames.

fragkit::cases! {
    cps: CASE;
    oit: CASE;
    cbr: CASE;
}

use anyhow::{Context, Result, bail, ensure};
use fragkit::gpu::Gpu;
use fragkit::harness::{Ctx, Outcome, ParamKind, ParamSpec, Verdict};
use fragkit::memory_growth::{Growth, MIN_JUDGED, growth, judged_cycles};

mod memory;
use memory::Quantity;

pub const PARAMS: &[ParamSpec] = &[
    ParamSpec { name: "frames", kind: ParamKind::CountIn(64, 1_000_000), default: "1000", help: "frames rendered" },
    ParamSpec {
        name: "cycles",
        kind: ParamKind::CountIn(2 * MIN_JUDGED as u64, 32),
        default: "20",
        help: "resize cycles (every resource recreated at each start); the second half is judged for growth",
    },
];

/// The sizes a soak cycles through, one per cycle.
const SIZES: [(u32, u32); 3] = [(64, 48), (48, 64), (80, 40)];

/// A technique under soak: made for one size, renders frame after frame, shows its output.
pub trait Soaked: Sized {
    /// What a run decides once, before its first cycle: what the adapter can do (a probe's
    /// answer), which a resize does not change. A technique that probed again at every resize
    /// would build the probes' pipelines and targets as often — on GLES 3.1 a pipeline that fails
    /// to compile, whose GL program wgpu-hal 30 never deletes (docs/adapters.md).
    type Setup;
    fn setup(gpu: &Gpu) -> Result<Self::Setup>;
    fn new(gpu: &Gpu, setup: &Self::Setup, size: (u32, u32)) -> Result<Self>;
    fn render(&mut self, gpu: &Gpu, frame: u32) -> Result<()>;
    /// The output's raw texels.
    fn output(&self, gpu: &Gpu) -> Result<Vec<u8>>;
}

/// The first frame of cycle `cycle` when `cycles` cycles share `frames` frames evenly (a cycle
/// past `cycles` goes on at the same pace: an extended run).
fn cycle_start(cycle: u32, cycles: u32, frames: u32) -> u32 {
    (u64::from(cycle) * u64::from(frames) / u64::from(cycles)) as u32
}

/// How many times its requested length a soak may run on: growth in the judged half of a run is
/// checked by running on, doubling the cycles, until it stops (a cache, however slowly it fills,
/// within twice the requested length) or the run is this many times as long (a leak).
const MAX_EXTENSION: u32 = 4;

/// Every cycle's sample of every quantity, kept in memory taken (and written) once, before the
/// first cycle, for the longest run the soak may make: a log that grew with the run would be the
/// very growth it measures (it was: about 1 KB of stored samples a cycle, which heaptrack put in
/// the soak itself, enough for process memory on lavapipe to cross a heap step in 64 cycles).
struct SampleLog {
    /// The quantities sampled, as the first sample had them (their names and kinds).
    quantities: Vec<Quantity>,
    /// Quantity-major: quantity `q`'s value at cycle `c` is at `q * capacity + c`.
    values: Vec<u64>,
    capacity: usize,
    cycles: usize,
}

impl SampleLog {
    /// A log for `capacity` cycles of the quantities `first` has.
    fn new(first: &[Quantity], capacity: usize) -> Self {
        // Filled, not zeroed: calloc may hand out untouched zero pages, which would become
        // resident one by one as the run writes them.
        let values = vec![u64::MAX; first.len() * capacity];
        Self { quantities: first.to_vec(), values, capacity, cycles: 0 }
    }

    /// Logs the next cycle's sample.
    fn push(&mut self, sample: &[Quantity]) -> Result<()> {
        ensure!(self.cycles < self.capacity, "more than the {} cycles a soak may run", self.capacity);
        ensure!(
            sample.iter().map(|q| q.name).eq(self.quantities.iter().map(|q| q.name)),
            "cycle {} sampled other quantities than the first cycle",
            self.cycles
        );
        for (index, quantity) in sample.iter().enumerate() {
            self.values[index * self.capacity + self.cycles] = quantity.value;
        }
        self.cycles += 1;
        Ok(())
    }

    /// Quantity `index`'s value at each cycle's end, in order.
    fn series(&self, index: usize) -> &[u64] {
        &self.values[index * self.capacity..][..self.cycles]
    }
}

/// One sampled quantity over a run, and how it grew.
struct Judged {
    quantity: Quantity,
    /// Its place in the [`SampleLog`].
    index: usize,
    growth: Growth,
}

impl Judged {
    /// Growth in it that is a leak (see `memory.rs` for which quantities can leak).
    fn leaks(&self) -> bool {
        self.quantity.leak_step.is_some_and(|step| self.growth.is_leak(step))
    }
}

/// Every quantity of the run logged so far, with its growth.
fn judge(log: &SampleLog) -> Result<Vec<Judged>> {
    (0..log.quantities.len())
        .map(|index| {
            let growth = growth(log.series(index)).context("too few cycles to judge growth")?;
            Ok(Judged { quantity: log.quantities[index], index, growth })
        })
        .collect()
}

/// Runs the soak for technique `T`.
pub fn soak<T: Soaked>(ctx: &mut Ctx) -> Result<Outcome> {
    if memory::resident_bytes().is_err() {
        return Ok(Outcome::NotSupported("resident memory: /proc/self/status has no VmRSS here".into()));
    }
    let frames = ctx.params.count_u32("frames")?;
    let cycles = ctx.params.count_u32("cycles")?;
    let setup = T::setup(ctx.gpu)?;
    let mut log = SampleLog::new(&memory::sample(ctx.gpu)?, (MAX_EXTENSION * cycles) as usize);
    let mut judged = Vec::new();
    let mut last = Vec::new();
    let mut planned = cycles;
    let mut cycle = 0;
    while cycle < planned {
        // A new technique per cycle, the old one dropped first, as a resizing app would.
        let mut technique = T::new(ctx.gpu, &setup, SIZES[cycle as usize % SIZES.len()])?;
        for frame in cycle_start(cycle, cycles, frames)..cycle_start(cycle + 1, cycles, frames) {
            technique.render(ctx.gpu, frame).with_context(|| format!("frame {frame}"))?;
        }
        ctx.gpu.wait()?;
        log.push(&memory::sample(ctx.gpu)?)?;
        cycle += 1;
        if cycle == planned {
            judged = judge(&log)?;
            if planned < MAX_EXTENSION * cycles && judged.iter().any(Judged::leaks) {
                planned *= 2;
            } else {
                last = technique.output(ctx.gpu)?;
            }
        }
    }
    if last.is_empty() {
        bail!("the soak read back an empty output");
    }
    let run_frames = cycle_start(planned, cycles, frames);

    let mut fresh = T::new(ctx.gpu, &setup, SIZES[(planned - 1) as usize % SIZES.len()])?;
    for frame in cycle_start(planned - 1, cycles, frames)..run_frames {
        fresh.render(ctx.gpu, frame)?;
    }
    let differing = last.iter().zip(fresh.output(ctx.gpu)?).filter(|(a, b)| **a != *b).count();

    let frames_per_cycle = f64::from(frames) / f64::from(cycles);
    ctx.metric("frames", run_frames);
    ctx.metric("cycles", planned);
    ctx.metric("judged_cycles", judged_cycles(planned as usize).len());
    let mut verdict = Verdict::new();
    // Where growing process memory lives: in malloc's live blocks, or outside them.
    let heap_note = match judged.iter().find(|j| j.quantity.name == "heap_live") {
        Some(heap) => format!(" (the live heap: {:.1} bytes a frame)", heap.growth.per_cycle / frames_per_cycle),
        None => String::new(),
    };
    for judged in &judged {
        let Judged { quantity, index, growth } = judged;
        let series = log.series(*index);
        let unit = if quantity.bytes { " bytes" } else { "" };
        if quantity.bytes {
            ctx.metric(
                &format!("{}_mib_per_cycle", quantity.name),
                series.iter().map(|&b| b as f64 / 1048576.0).collect::<Vec<_>>(),
            );
        } else {
            ctx.metric(&format!("{}_per_cycle", quantity.name), series.to_vec());
        }
        if growth.per_cycle != 0.0 {
            ctx.metric(&format!("{}_growth_per_frame", quantity.name), growth.per_cycle / frames_per_cycle);
            ctx.metric(&format!("{}_noise_per_cycle", quantity.name), growth.noise);
            ctx.metric(&format!("{}_growth_p", quantity.name), growth.p);
        }
        if judged.leaks() {
            let last_cycles = &series[judged_cycles(series.len())];
            verdict.fail(format!(
                "{}{} keeps growing through {run_frames} frames: {:.1}{unit} a frame ({:.1} a resize cycle of {frames_per_cycle:.0} frames), {} → {} over the last {} cycles (identical cycles vary by {:.1}, p = {:.1e})",
                quantity.name,
                if quantity.name.starts_with("resident") { &heap_note } else { "" },
                growth.per_cycle / frames_per_cycle,
                growth.per_cycle,
                last_cycles[0],
                last_cycles[last_cycles.len() - 1],
                growth.judged,
                growth.noise,
                growth.p
            ));
        }
    }
    ctx.metric("last_frame_bytes_differing_from_fresh", differing);
    if differing > 0 {
        verdict.fail(format!("the last frame differs from a fresh render of it in {differing} bytes"));
    }
    Ok(verdict.outcome())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quantity(name: &'static str, value: u64) -> Quantity {
        Quantity { name, value, bytes: true, leak_step: None }
    }

    /// The log keeps each quantity's values in cycle order, within the memory it took at the
    /// start, and refuses a cycle past its capacity or a sample of other quantities.
    #[test]
    fn the_sample_log_keeps_each_series_in_the_memory_it_took_first() {
        let mut log = SampleLog::new(&[quantity("a", 0), quantity("b", 0)], 3);
        let taken = log.values.as_ptr();
        for cycle in 0..3 {
            log.push(&[quantity("a", cycle), quantity("b", 10 + cycle)]).unwrap();
        }
        assert_eq!((log.series(0), log.series(1)), (&[0, 1, 2][..], &[10, 11, 12][..]));
        assert_eq!((log.values.as_ptr(), log.values.capacity()), (taken, 6));
        assert!(log.push(&[quantity("a", 3), quantity("b", 13)]).is_err());
        let mut other = SampleLog::new(&[quantity("a", 0)], 2);
        assert!(other.push(&[quantity("c", 0)]).is_err());
        assert_eq!(other.series(0), &[] as &[u64]);
    }
}
