//! The alternatives stochastic transparency is measured against, all compute-free: plain
//! alpha-to-coverage, sorted back-to-front blending, weighted blended OIT, and depth peeling
//! (exact; one layer per pass until an occlusion query finds nothing left).

use anyhow::{Result, ensure};

use super::scene::QuadScene;
use super::stochastic::{COLOUR, QuadBatch, QuadPipeline, ResolvedTarget};
use crate::attachments;
use crate::fullscreen::{FullscreenPipeline, bind_group};
use crate::gpu::Gpu;
use crate::query::{GpuTimer, OcclusionQueries};
use crate::shaders;

/// A blend state adding `src ×` source to `dst ×` destination, colour and alpha alike.
fn same_blend(src: wgpu::BlendFactor, dst: wgpu::BlendFactor) -> wgpu::BlendState {
    let component = wgpu::BlendComponent { src_factor: src, dst_factor: dst, operation: wgpu::BlendOperation::Add };
    wgpu::BlendState { color: component, alpha: component }
}

/// Opaque quads first (colour and depth), as every method needs them.
fn draw_opaque(gpu: &Gpu, pass: &mut wgpu::RenderPass<'_>, scene: &QuadScene, quads: &QuadBatch, samples: u32) {
    let pipeline = QuadPipeline {
        label: "opaque",
        fragment: shaders::OIT_PLAIN_COVERAGE,
        entry_point: "fs_plain_coverage",
        targets: &[Some(COLOUR.into())],
        depth_write: true,
        depth_compare: wgpu::CompareFunction::Less,
        samples,
        alpha_to_coverage: false,
    }
    .create(gpu);
    pass.set_pipeline(&pipeline);
    for (i, quad) in scene.quads.iter().enumerate() {
        if quad.is_opaque() {
            quads.draw(pass, i as u32..i as u32 + 1);
        }
    }
}

/// Plain alpha-to-coverage: alpha straight to the coverage unit, one pass.
pub fn render_plain_coverage(
    gpu: &Gpu,
    scene: &QuadScene,
    target: &ResolvedTarget,
    timer: &mut GpuTimer,
) -> Result<()> {
    let quads = QuadBatch::new(gpu, scene)?;
    let pipeline = QuadPipeline {
        label: "plain alpha-to-coverage",
        fragment: shaders::OIT_PLAIN_COVERAGE,
        entry_point: "fs_plain_coverage",
        targets: &[Some(target.format.into())],
        depth_write: true,
        depth_compare: wgpu::CompareFunction::LessEqual,
        samples: target.samples,
        alpha_to_coverage: true,
    }
    .create(gpu);
    let mut encoder = gpu.encoder("plain alpha-to-coverage");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("plain alpha-to-coverage"),
            color_attachments: &[target.colour_attachment()],
            depth_stencil_attachment: target.depth_attachment(),
            timestamp_writes: timer.pass("plain alpha-to-coverage"),
            ..Default::default()
        });
        pass.set_pipeline(&pipeline);
        quads.draw(&mut pass, 0..quads.count);
    }
    timer.resolve(&mut encoder);
    gpu.submit(encoder);
    Ok(())
}

/// Whether the transparent quads can be sorted: flat, and no two at the same depth overlap
/// ambiguity (equal depths).
pub fn sortable(scene: &QuadScene) -> bool {
    let transparent: Vec<f32> = scene.quads.iter().filter(|q| !q.is_opaque()).map(|q| q.depth.0).collect();
    scene.quads.iter().filter(|q| !q.is_opaque()).all(|q| q.depth.0 == q.depth.1)
        && transparent.iter().enumerate().all(|(i, a)| transparent[i + 1..].iter().all(|b| a != b))
}

/// Sorted blending: opaque first, then the transparent quads far to near with "over".
pub fn render_sorted_blend(gpu: &Gpu, scene: &QuadScene, target: &ResolvedTarget, timer: &mut GpuTimer) -> Result<()> {
    ensure!(sortable(scene), "scene {:?} cannot be sorted per object (equal depths or tilted quads)", scene.name);
    let quads = QuadBatch::new(gpu, scene)?;
    let over = wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING;
    let pipeline = QuadPipeline {
        label: "sorted blend",
        fragment: shaders::OIT_SORTED_BLEND,
        entry_point: "fs_sorted_blend",
        targets: &[Some(wgpu::ColorTargetState {
            format: COLOUR,
            blend: Some(over),
            write_mask: wgpu::ColorWrites::ALL,
        })],
        depth_write: false,
        depth_compare: wgpu::CompareFunction::Less,
        samples: target.samples,
        alpha_to_coverage: false,
    }
    .create(gpu);
    let mut order: Vec<usize> = (0..scene.quads.len()).filter(|&i| !scene.quads[i].is_opaque()).collect();
    order.sort_by(|&a, &b| scene.quads[b].depth.0.total_cmp(&scene.quads[a].depth.0));
    let mut encoder = gpu.encoder("sorted blend");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sorted blend"),
            color_attachments: &[target.colour_attachment()],
            depth_stencil_attachment: target.depth_attachment(),
            timestamp_writes: timer.pass("sorted blend"),
            ..Default::default()
        });
        draw_opaque(gpu, &mut pass, scene, &quads, target.samples);
        pass.set_pipeline(&pipeline);
        for i in order {
            quads.draw(&mut pass, i as u32..i as u32 + 1);
        }
    }
    timer.resolve(&mut encoder);
    gpu.submit(encoder);
    Ok(())
}

/// Weighted blended OIT: opaque, then accumulation and revealage, then a composite over.
pub fn render_weighted(gpu: &Gpu, scene: &QuadScene, target: &ResolvedTarget, timer: &mut GpuTimer) -> Result<()> {
    ensure!(target.samples == 1, "weighted blended OIT runs single-sampled here");
    let quads = QuadBatch::new(gpu, scene)?;
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
    let accumulation = gpu.texture("wboit accumulation", target.size, COLOUR, 1, usage);
    let revealage = gpu.texture("wboit revealage", target.size, COLOUR, 1, usage);
    let (accumulation_view, revealage_view) =
        (accumulation.create_view(&Default::default()), revealage.create_view(&Default::default()));
    let add = same_blend(wgpu::BlendFactor::One, wgpu::BlendFactor::One);
    let reveal = same_blend(wgpu::BlendFactor::Zero, wgpu::BlendFactor::OneMinusSrc);
    let accumulate = QuadPipeline {
        label: "weighted accumulate",
        fragment: shaders::OIT_WEIGHTED_ACCUMULATE,
        entry_point: "fs_weighted_accumulate",
        targets: &[
            Some(wgpu::ColorTargetState { format: COLOUR, blend: Some(add), write_mask: wgpu::ColorWrites::ALL }),
            Some(wgpu::ColorTargetState { format: COLOUR, blend: Some(reveal), write_mask: wgpu::ColorWrites::ALL }),
        ],
        depth_write: false,
        depth_compare: wgpu::CompareFunction::Less,
        samples: 1,
        alpha_to_coverage: false,
    }
    .create(gpu);
    let over = wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING;
    let composite = FullscreenPipeline {
        label: "weighted composite",
        fragment: shaders::OIT_WEIGHTED_COMPOSITE,
        entry_point: "fs_weighted_composite",
        targets: &[Some(wgpu::ColorTargetState {
            format: COLOUR,
            blend: Some(over),
            write_mask: wgpu::ColorWrites::ALL,
        })],
        depth_stencil: None,
        samples: 1,
    }
    .create(gpu);
    let group = bind_group(
        gpu,
        "weighted composite",
        &composite,
        0,
        &[wgpu::BindingResource::TextureView(&accumulation_view), wgpu::BindingResource::TextureView(&revealage_view)],
    );
    let depth =
        gpu.texture("wboit depth", target.size, super::stochastic::DEPTH, 1, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let depth_view = depth.create_view(&Default::default());
    let mut encoder = gpu.encoder("weighted blended");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("opaque"),
            color_attachments: &[attachments::colour(&target.resolved_view, None, wgpu::Color::TRANSPARENT)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: timer.pass("weighted: opaque"),
            ..Default::default()
        });
        draw_opaque(gpu, &mut pass, scene, &quads, 1);
    }
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("weighted accumulate"),
            color_attachments: &[
                attachments::colour(&accumulation_view, None, wgpu::Color::TRANSPARENT),
                attachments::colour(&revealage_view, None, wgpu::Color::WHITE),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Discard }),
                stencil_ops: None,
            }),
            timestamp_writes: timer.pass("weighted: accumulate"),
            ..Default::default()
        });
        pass.set_pipeline(&accumulate);
        for (i, quad) in scene.quads.iter().enumerate() {
            if !quad.is_opaque() {
                quads.draw(&mut pass, i as u32..i as u32 + 1);
            }
        }
    }
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("weighted composite"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target.resolved_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
            })],
            timestamp_writes: timer.pass("weighted: composite"),
            ..Default::default()
        });
        pass.set_pipeline(&composite);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
    timer.resolve(&mut encoder);
    gpu.submit(encoder);
    Ok(())
}

/// Depth peeling into `target` (single-sampled): returns the number of layers peeled. Each pass
/// peels the nearest remaining fragment per pixel (by depth, then draw order) and blends it under
/// the accumulation; an occlusion query around the peel stops the loop when nothing is left. A
/// pixel's key (the last fragment peeled there) carries over to the next pass where nothing is
/// peeled, so a pixel with fewer layers stays finished rather than starting again from the front.
pub fn render_depth_peeling(
    gpu: &Gpu,
    scene: &QuadScene,
    target: &ResolvedTarget,
    timer: &mut GpuTimer,
    max_layers: u32,
) -> Result<u32> {
    ensure!(target.samples == 1, "depth peeling runs single-sampled here");
    let quads = QuadBatch::new(gpu, scene)?;
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
    let layer = gpu.texture("peeled layer", target.size, COLOUR, 1, usage);
    let key_usage = usage | wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST;
    let keys = [0, 1].map(|_| gpu.texture("peel key", target.size, wgpu::TextureFormat::Rg32Uint, 1, key_usage));
    let key_views = [&keys[0], &keys[1]].map(|k| k.create_view(&Default::default()));
    let layer_view = layer.create_view(&Default::default());
    let depth =
        gpu.texture("peel depth", target.size, super::stochastic::DEPTH, 1, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let depth_view = depth.create_view(&Default::default());
    let peel = QuadPipeline {
        label: "peel",
        fragment: shaders::OIT_PEEL,
        entry_point: "fs_peel",
        targets: &[Some(COLOUR.into()), Some(wgpu::TextureFormat::Rg32Uint.into())],
        depth_write: true,
        depth_compare: wgpu::CompareFunction::Less,
        samples: 1,
        alpha_to_coverage: false,
    }
    .create(gpu);
    let under = same_blend(wgpu::BlendFactor::OneMinusDstAlpha, wgpu::BlendFactor::One);
    let accumulate = FullscreenPipeline {
        label: "under",
        fragment: shaders::OIT_UNDER,
        entry_point: "fs_under",
        targets: &[Some(wgpu::ColorTargetState {
            format: COLOUR,
            blend: Some(under),
            write_mask: wgpu::ColorWrites::ALL,
        })],
        depth_stencil: None,
        samples: 1,
    }
    .create(gpu);
    let layer_group = bind_group(gpu, "under", &accumulate, 0, &[wgpu::BindingResource::TextureView(&layer_view)]);
    // Clear the accumulation and the first key (nothing peeled yet).
    let mut encoder = gpu.encoder("peel start");
    for view in [&target.resolved_view, &key_views[0]] {
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("clear"),
            color_attachments: &[attachments::colour(view, None, wgpu::Color::TRANSPARENT)],
            ..Default::default()
        });
    }
    gpu.submit(encoder);
    let mut layers = 0;
    while layers < max_layers {
        let (previous, next) = ((layers % 2) as usize, ((layers + 1) % 2) as usize);
        let group = bind_group(gpu, "peel", &peel, 0, &[wgpu::BindingResource::TextureView(&key_views[previous])]);
        let queries = OcclusionQueries::new(gpu, 1);
        let mut encoder = gpu.encoder("peel");
        encoder.copy_texture_to_texture(
            keys[previous].as_image_copy(),
            keys[next].as_image_copy(),
            keys[previous].size(),
        );
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("peel"),
                color_attachments: &[
                    attachments::colour(&layer_view, None, wgpu::Color::TRANSPARENT),
                    Some(wgpu::RenderPassColorAttachment {
                        view: &key_views[next],
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                    }),
                ],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                    stencil_ops: None,
                }),
                occlusion_query_set: Some(queries.set()),
                timestamp_writes: timer.pass("peel"),
                ..Default::default()
            });
            pass.set_pipeline(&peel);
            pass.set_bind_group(0, &group, &[]);
            pass.begin_occlusion_query(0);
            quads.draw(&mut pass, 0..quads.count);
            pass.end_occlusion_query();
        }
        queries.resolve(&mut encoder);
        gpu.submit(encoder);
        if queries.read(gpu)?[0] == 0 {
            break;
        }
        let mut encoder = gpu.encoder("under");
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("under"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target.resolved_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                })],
                timestamp_writes: timer.pass("under"),
                ..Default::default()
            });
            pass.set_pipeline(&accumulate);
            pass.set_bind_group(0, &layer_group, &[]);
            pass.draw(0..3, 0..1);
        }
        gpu.submit(encoder);
        layers += 1;
    }
    let mut encoder = gpu.encoder("peel timestamps");
    timer.resolve(&mut encoder);
    gpu.submit(encoder);
    Ok(layers)
}
