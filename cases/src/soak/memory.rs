//! What a soak samples at the end of each cycle, once the GPU is idle: the process's memory, split
//! as far as the platform tells (resident memory; with glibc, the live heap, the free memory its
//! allocator keeps, and what is resident outside the heap), and wgpu's live objects and memory
//! (its internal counters, every backend; and the bytes its allocator holds from the driver and
//! hands out of them, where the backend reports them: Vulkan).
//!
//! Which quantities can leak: resident memory less the free memory the allocator keeps (which
//! creeps up as the heap fragments: a cache of pages, not a leak), and wgpu's live objects and
//! bytes. Not the allocator's free memory, nor wgpu's allocator's blocks held from the driver:
//! those are caches by definition. The live heap (what Rust, wgpu and a driver allocated with
//! malloc and still hold) tells where growing memory lives: resident memory in use that grows
//! while the live heap does not is outside malloc — a driver's own mappings, a JIT's code pages.

use anyhow::{Context, Result};
use fragkit::gpu::Gpu;

/// One quantity of a cycle's sample.
#[derive(Clone, Copy, Debug)]
pub struct Quantity {
    pub name: &'static str,
    pub value: u64,
    /// Bytes (else a count of objects).
    pub bytes: bool,
    /// Whether growth in it can be a leak (see the module's notes), and if so the step it moves
    /// in without leaking: the growth over the judged cycles must reach it.
    pub leak_step: Option<u64>,
}

/// The step glibc's heap grows by when it takes memory from the kernel (M_TOP_PAD's default,
/// 128 KiB): process memory that rises by less over the judged cycles may be one such step, and a
/// step is not a leak. wgpu's counts move by one object or one allocation: any steady rise in them
/// is a leak.
pub const PROCESS_MEMORY_STEP: u64 = 128 << 10;

/// The process's resident set size in bytes (Linux: /proc/self/status).
pub fn resident_bytes() -> Result<u64> {
    let status = std::fs::read_to_string("/proc/self/status").context("reading /proc/self/status")?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:")).context("no VmRSS line in /proc/self/status")?;
    let kib: u64 = line.split_whitespace().nth(1).context("VmRSS without a value")?.parse().context("VmRSS value")?;
    Ok(kib * 1024)
}

/// Resident bytes of two kinds of mapping outside malloc (Linux: /proc/self/smaps): anonymous
/// or memfd mappings that are executable — code a JIT compiled (LLVM's for llvmpipe and lavapipe,
/// Reactor's through a memfd for SwiftShader) — and memfd mappings that are not — memory a driver
/// shares or exports (lavapipe's device memory when zink imports it).
struct Mappings {
    jit_code: u64,
    memfd_data: u64,
}

fn mappings() -> Option<Mappings> {
    let smaps = std::fs::read_to_string("/proc/self/smaps").ok()?;
    let mut found = Mappings { jit_code: 0, memfd_data: 0 };
    // Which total the current mapping's Rss goes to.
    let mut current: Option<&mut u64> = None;
    for line in smaps.lines() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        // A mapping's header: "start-end perms offset dev inode [path]".
        if fields.first().is_some_and(|f| f.contains('-') && f.chars().all(|c| c.is_ascii_hexdigit() || c == '-')) {
            let memfd = fields.get(5).is_some_and(|path| path.starts_with("/memfd:"));
            let anonymous = fields.len() == 5;
            let executable = fields.get(1).is_some_and(|perms| perms.contains('x'));
            current = if executable && (anonymous || memfd) {
                Some(&mut found.jit_code)
            } else if memfd {
                Some(&mut found.memfd_data)
            } else {
                None
            };
        } else if fields.first() == Some(&"Rss:")
            && let Some(total) = current.as_deref_mut()
        {
            *total += fields.get(1)?.parse::<u64>().ok()? * 1024;
        }
    }
    Some(found)
}

/// glibc's heap (mallinfo2, over every arena): bytes in live blocks (arena blocks in use and those
/// mapped on their own) and bytes free in the arenas.
struct Heap {
    live: u64,
    free: u64,
}

#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn heap() -> Option<Heap> {
    // SAFETY: mallinfo2 only reads the allocator's statistics (glibc 2.33 and later).
    let info = unsafe { libc::mallinfo2() };
    Some(Heap { live: (info.uordblks + info.hblkhd) as u64, free: info.fordblks as u64 })
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn heap() -> Option<Heap> {
    None
}

/// Samples everything at a cycle's end (the GPU idle).
pub fn sample(gpu: &Gpu) -> Result<Vec<Quantity>> {
    let resident = resident_bytes()?;
    let heap = heap();
    let process = |name, value, judged: bool| Quantity {
        name,
        value,
        bytes: true,
        leak_step: judged.then_some(PROCESS_MEMORY_STEP),
    };
    let mut quantities = vec![process("resident", resident, heap.is_none())];
    if let Some(heap) = heap {
        quantities.push(process("resident_in_use", resident.saturating_sub(heap.free), true));
        // Recorded, not judged: the live heap can only grow without bound by growing the
        // resident memory in use, and whether it grows tells a leak in malloc'd memory from one
        // in a driver's own mappings.
        quantities.push(process("heap_live", heap.live, false));
        quantities.push(process("heap_free", heap.free, false));
    }
    if let Some(mappings) = mappings() {
        // Recorded, not judged: where process memory outside malloc grows.
        quantities.push(process("resident_jit_code", mappings.jit_code, false));
        quantities.push(process("resident_memfd_data", mappings.memfd_data, false));
    }
    let counters = gpu.device.get_internal_counters().hal;
    // Each counter with whether it is bytes and whether it can leak. Not the command encoders:
    // wgpu-core keeps the encoders of retired submissions in a pool for the next ones and never
    // trims it (command/allocator.rs), so their count is the most ever in flight at once — a
    // high-water mark that creeps up whenever the GPU falls further behind (SwiftShader: 57 -> 59
    // over 64 resizes), a cache by definition.
    for (name, counter, is_bytes, judged) in [
        ("wgpu_buffers", &counters.buffers, false, true),
        ("wgpu_textures", &counters.textures, false, true),
        ("wgpu_texture_views", &counters.texture_views, false, true),
        ("wgpu_bind_groups", &counters.bind_groups, false, true),
        ("wgpu_bind_group_layouts", &counters.bind_group_layouts, false, true),
        ("wgpu_render_pipelines", &counters.render_pipelines, false, true),
        ("wgpu_pipeline_layouts", &counters.pipeline_layouts, false, true),
        ("wgpu_samplers", &counters.samplers, false, true),
        ("wgpu_shader_modules", &counters.shader_modules, false, true),
        ("wgpu_query_sets", &counters.query_sets, false, true),
        ("wgpu_command_encoders", &counters.command_encoders, false, false),
        ("wgpu_fences", &counters.fences, false, true),
        ("wgpu_buffer_bytes", &counters.buffer_memory, true, true),
        ("wgpu_texture_bytes", &counters.texture_memory, true, true),
        ("wgpu_memory_allocations", &counters.memory_allocations, false, true),
    ] {
        let leak_step = judged.then_some(0);
        quantities.push(Quantity { name, value: counter.read().max(0) as u64, bytes: is_bytes, leak_step });
    }
    if let Some(report) = gpu.device.generate_allocator_report() {
        let wgpu_bytes = |name, value, leak_step| Quantity { name, value, bytes: true, leak_step };
        quantities.push(wgpu_bytes("wgpu_allocator_reserved", report.total_reserved_bytes, None));
        quantities.push(wgpu_bytes("wgpu_allocator_allocated", report.total_allocated_bytes, Some(0)));
    }
    Ok(quantities)
}
