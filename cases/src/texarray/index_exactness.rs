//! `texarray.index_exactness`: for each way of fetching element k of a 2D texture used as a 1D
//! array, every index of a sweep up to and past 2^24 (dense near powers of two and the end) is
//! fetched on the GPU and compared with k. Reports the first wrong index per variant on this
//! adapter; the integer variant — `array_texel` of shaders/common/lighting.wgsl, the very function
//! the lighting fetches lights with — must be exact everywhere.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange};
use fragkit::texarray::{FetchVariant, measure_index_exactness, sweep_indices};

pub const CASE: Case = Case {
    name: "texarray.index_exactness",
    summary: "element k of a texture used as a 1D array: which fetch variants stay exact past 2^24",
    requires: wgpu::Features::empty(),
    params: &[ParamSpec {
        name: "size",
        kind: ParamKind::Sizes,
        default: "4096x4097",
        help: "array texture size (4096x4097 holds 2^24 + 4096 elements)",
    }],
    sweep: &[Sweep { param: "size", range: SweepRange::Size { min: (1, 1), max: (4096, 4097) } }],
    budget_s: 2,
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.sizes("size")?[0];
    let elements = size.0 * size.1;
    let indices = sweep_indices(elements);
    ctx.metric("elements", elements);
    ctx.metric("indices_tried", indices.len());

    let results = measure_index_exactness(ctx.gpu, size, &indices)?;
    for result in &results {
        ctx.metric(&format!("{:?}", result.variant).to_lowercase(), result);
    }
    // Expected: the integer variant fetches every element exactly.
    let integer = results.iter().find(|r| r.variant == FetchVariant::Integer).expect("integer variant measured");
    Ok(match integer.first_wrong {
        None => Outcome::Pass,
        Some((k, got)) => {
            Outcome::Fail(format!("integer textureLoad fetched {got} for index {k} ({} indices wrong)", integer.wrong))
        }
    })
}
