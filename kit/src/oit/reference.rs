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

    fn quad(rect: [f32; 4], depth: (f32, f32), alpha: f32, colour: [f32; 3], key: u32) -> Quad {
        Quad { rect, depth, alpha, colour, key }
    }

    /// Which quads cover a point and at what depth, by the definition read plainly: a quad's
    /// clip rect (y up) is the pixel rect [(x0+1)w/2, (x1+1)w/2) × [(1−y0)h/2, (1−y1)h/2), half
    /// open, its depth linear from `depth.0` at its left edge to `depth.1` at its right; nearest
    /// first, ties by key.
    #[test]
    fn a_point_is_covered_by_the_quads_whose_pixel_rects_hold_it_nearest_first() {
        // On 8×4 pixels: the left half (x 0..4, y 0..4), its depth 0.2 → 0.6 across it; a quad
        // on x 2..6, y 1..3 at 0.4 flat, key 5; one at the same depth with key 3.
        let scene = QuadScene {
            name: "test".into(),
            quads: vec![
                quad([-1.0, 1.0, 0.0, -1.0], (0.2, 0.6), 0.5, [1.0, 0.0, 0.0], 9),
                quad([-0.5, 0.5, 0.5, -0.5], (0.4, 0.4), 0.5, [0.0, 1.0, 0.0], 5),
                quad([-0.5, 0.5, 0.5, -0.5], (0.4, 0.4), 0.5, [0.0, 0.0, 1.0], 3),
            ],
        };
        // Depths in thousandths.
        let at = |x: f32, y: f32| -> Vec<(i32, usize)> {
            covering(&scene, (8, 4), x, y).into_iter().map(|(d, i)| ((d * 1000.0).round() as i32, i)).collect()
        };
        assert_eq!(at(0.0, 0.0), [(200, 0)]);
        assert_eq!(at(1.0, 3.9), [(300, 0)]);
        // Left edge and top edge in, right and bottom out; equal depths by key.
        assert_eq!(at(2.0, 1.0), [(400, 2), (400, 1), (400, 0)]);
        assert_eq!(at(3.0, 2.0), [(400, 2), (400, 1), (500, 0)]);
        assert_eq!(at(1.5, 2.0), [(350, 0)]);
        assert_eq!(at(4.0, 2.0), [(400, 2), (400, 1)]);
        assert_eq!(at(5.9, 2.9), [(400, 2), (400, 1)]);
        assert_eq!(at(6.0, 2.0), []);
        assert_eq!(at(5.0, 3.0), []);
        assert_eq!(at(1.0, 4.0), []);
        // Above the small quads' top edge (pixel row 1).
        assert_eq!(at(3.0, 0.5), [(500, 0)]);
        assert_eq!(at(4.0, 0.5), []);
        // A pixel is the mean of its samples: one sample in the red quad alone, one in none.
        let image = exact_image(&scene, (8, 4), &[[0.5, 0.5], [7.0, 0.5]]);
        assert_eq!(image[0], [0.25, 0.0, 0.0]);
    }

    /// A quad's depth is linear across its own pixel rect, whichever column that rect starts at.
    #[test]
    fn depth_runs_from_the_left_edge_to_the_right_one() {
        // On 8×2 pixels, the right half (x 4..8) from depth 0.2 to 0.6.
        let scene =
            QuadScene { name: "test".into(), quads: vec![quad([0.0, 1.0, 1.0, -1.0], (0.2, 0.6), 0.5, [1.0; 3], 0)] };
        let depth = |x: f32| covering(&scene, (8, 2), x, 1.0)[0].0;
        for (x, expected) in [(4.0, 0.2), (6.0, 0.4), (7.0, 0.5)] {
            assert!((depth(x) - expected).abs() < 1e-6, "depth {} at x = {x}", depth(x));
        }
    }

    #[test]
    fn rmse_is_the_root_of_the_mean_square_over_every_channel() {
        let image = [[1.0, 0.0, 0.0], [0.0, 0.0, 0.5]];
        let reference = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]];
        assert!((rmse(&image, &reference) - (1.25f64 / 6.0).sqrt()).abs() < 1e-12);
        assert_eq!(rmse(&reference, &reference), 0.0);
        assert_eq!(rmse(&image, &image), 0.0);
        assert_eq!(rmse(&[], &[]), 0.0);
    }
}
