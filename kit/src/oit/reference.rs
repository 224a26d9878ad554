//! The exact composite on the CPU: at each sample position, the quads covering it sorted by
//! (depth, draw index) and blended front to back; a pixel is the mean of its samples, as a
//! multisample resolve makes it.

use super::scene::{Quad, QuadScene};

/// The quads covering a point (pixels, y down) with their depth there, nearest first; ties go
/// by key, as in the GPU passes.
fn covering(scene: &QuadScene, size: (u32, u32), x: f32, y: f32) -> Vec<(f32, usize)> {
    let (w, h) = (size.0 as f32, size.1 as f32);
    let mut hits: Vec<(f32, usize)> = scene
        .quads
        .iter()
        .enumerate()
        .filter_map(|(i, quad): (usize, &Quad)| {
            let [x0, y0, x1, y1] = quad.rect;
            let (px0, px1) = ((x0 + 1.0) * 0.5 * w, (x1 + 1.0) * 0.5 * w);
            let (py0, py1) = ((1.0 - y0) * 0.5 * h, (1.0 - y1) * 0.5 * h);
            let inside = x >= px0 && x < px1 && y >= py0 && y < py1;
            inside.then(|| (quad.depth.0 + (quad.depth.1 - quad.depth.0) * (x - px0) / (px1 - px0), i))
        })
        .collect();
    hits.sort_by(|a, b| a.0.total_cmp(&b.0).then(scene.quads[a.1].key.cmp(&scene.quads[b.1].key)));
    hits
}

/// Front-to-back "under" compositing of the quads at one point.
fn composite_at(scene: &QuadScene, hits: &[(f32, usize)]) -> [f32; 3] {
    let mut colour = [0.0f32; 3];
    let mut transmittance = 1.0f32;
    for &(_, i) in hits {
        let quad = &scene.quads[i];
        let alpha = quad.alpha.clamp(0.0, 1.0);
        for (sum, channel) in colour.iter_mut().zip(quad.colour) {
            *sum += transmittance * alpha * channel;
        }
        transmittance *= 1.0 - alpha;
        if transmittance == 0.0 {
            break;
        }
    }
    colour
}

/// The exact image (RGB per pixel) for samples at `positions` (pixel-relative).
pub fn exact_image(scene: &QuadScene, size: (u32, u32), positions: &[[f32; 2]]) -> Vec<[f32; 3]> {
    let mut image = Vec::with_capacity((size.0 * size.1) as usize);
    for y in 0..size.1 {
        for x in 0..size.0 {
            let mut sum = [0.0f32; 3];
            for [sx, sy] in positions {
                let sample = composite_at(scene, &covering(scene, size, x as f32 + sx, y as f32 + sy));
                for (total, value) in sum.iter_mut().zip(sample) {
                    *total += value;
                }
            }
            image.push(sum.map(|v| v / positions.len() as f32));
        }
    }
    image
}

/// Root-mean-square error over RGB.
pub fn rmse(image: &[[f32; 3]], reference: &[[f32; 3]]) -> f64 {
    let sum: f64 =
        image.iter().zip(reference).flat_map(|(a, b)| (0..3).map(move |c| f64::from(a[c] - b[c]).powi(2))).sum();
    (sum / (3.0 * image.len().max(1) as f64)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_quads_composite_front_to_back() {
        // At the centre all four quads and the background overlap: red (0.6) in front, then
        // green, blue, white (0.2), grey background.
        let scene = QuadScene::paper();
        // Pixel (0, 0) sampled at its far corner, the screen centre.
        let image = exact_image(&scene, (2, 2), &[[1.0, 1.0]]);
        let centre = image[0];
        let red = 0.6;
        let green = 0.4 * 0.6;
        let blue = 0.4 * 0.4 * 0.6;
        let white = 0.4 * 0.4 * 0.4 * 0.2;
        let grey = 0.4 * 0.4 * 0.4 * 0.8 * 0.5;
        let expected = [red + white + grey, green + white + grey, blue + white + grey];
        for c in 0..3 {
            assert!((centre[c] - expected[c]).abs() < 1e-6, "{centre:?} vs {expected:?}");
        }
    }
}
