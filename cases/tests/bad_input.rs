//! The library refuses bad input with an error naming it, never a panic or a silent clamp.

mod support;

use fragkit::cbr::sampling::CheckerboardPath;
use fragkit::cbr::scene::{Motion, flat_rects};
use fragkit::cbr::{Checkerboard, CheckerboardConfig, Detection, Shading};
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy};
use fragkit::deferred::lights::LightTexture;
use fragkit::oit::scene::QuadScene;

fn message<T>(result: anyhow::Result<T>) -> String {
    match result {
        Ok(_) => panic!("bad input accepted"),
        Err(e) => format!("{e:#}"),
    }
}

#[test]
fn the_library_refuses_bad_sizes_levels_lights_and_names() {
    let gpu = support::gpu().lock().unwrap_or_else(|e| e.into_inner());
    let max = gpu.device.limits().max_texture_dimension_2d;
    let config = |max_level| CpsConfig::new(max_level, LodPolicy::foveated(), CompositeMode::Nearest);
    assert!(message(CpsRenderer::new(&gpu, (0, 4), config(4))).contains("empty"));
    assert!(message(CpsRenderer::new(&gpu, (max + 1, 4), config(4))).contains("texture limit"));
    assert!(message(CpsRenderer::new(&gpu, (64, 64), config(9))).contains("levels are 0..=8"));
    assert!(message(LightTexture::new(&gpu, &[])).contains("light count 0"));
    let checkerboard = |screen| {
        let scene = flat_rects((4, 4), 1, glam::Vec2::ZERO);
        Checkerboard::new(
            &gpu,
            &scene,
            CheckerboardConfig::new(screen, CheckerboardPath::OffsetPasses, Shading::Forward),
        )
    };
    assert!(message(checkerboard((1, 1))).contains("smaller than 2x2"));
    assert!(message(checkerboard((max + 1, 2))).contains("this adapter allows"));
    assert!(message(Motion::parse("pan_1xinf")).contains("not a finite number"));
    assert!(message(Detection::parse("cso:NaN")).contains("finite number"));
    assert!(message(Shading::parse("hybrid")).contains("forward or deferred"));
    for alpha in [f32::NAN, -0.1, 1.5] {
        let mut scene = QuadScene::paper();
        scene.quads[1].alpha = alpha;
        assert!(message(scene.validate()).contains("is outside 0..=1"), "opacity {alpha} accepted");
    }
}
