// Records which samples of which pixels a draw covered: one per-sample invocation per covered
// sample writes a 1 at (pixel, sample_index). The storage route of the sample-position sweep,
// independent of the pipeline sample mask and of resolves. Each pixel has room for 32 sample
// indices, so a driver that runs more samples than the target claims shows it.

struct Strip {
    width: u32,
    slots_per_pixel: u32,
}

@group(0) @binding(0) var<uniform> strip: Strip;
@group(0) @binding(1) var<storage, read_write> covered: array<u32>;

@fragment
fn fs_record_sample(@builtin(position) position: vec4f, @builtin(sample_index) sample_index: u32) {
    let pixel = vec2u(position.xy);
    covered[(pixel.y * strip.width + pixel.x) * strip.slots_per_pixel + min(sample_index, strip.slots_per_pixel - 1u)] = 1u;
}
