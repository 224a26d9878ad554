//! Transparent scenes as quads: the original paper's validation quads, a stiff pile of seeded
//! layers, and an opaque object cutting through transparent layers. Quads are drawn in the
//! order given, and every scene starts with an opaque background. Keys number the quads in the
//! order a scene is built; permuting the draw order keeps them.

use anyhow::{Result, bail};

use crate::scene::hash::SeededRng;

/// A quad in clip space, flat or tilted along x (depth at its left and right edges).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quad {
    /// x0, y0 (top), x1, y1 (bottom) in clip space: y up, so y0 > y1.
    pub rect: [f32; 4],
    pub depth: (f32, f32),
    pub alpha: f32,
    pub colour: [f32; 3],
    /// Identity whatever the draw order: breaks depth ties, seeds the quad's random numbers.
    pub key: u32,
}

impl Quad {
    fn flat(rect: [f32; 4], depth: f32, alpha: f32, colour: [f32; 3]) -> Self {
        Self { rect, depth: (depth, depth), alpha, colour, key: 0 }
    }

    pub fn is_opaque(&self) -> bool {
        self.alpha >= 1.0
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct QuadScene {
    pub name: String,
    pub quads: Vec<Quad>,
}

/// Background: opaque mid grey at the far end.
fn background() -> Quad {
    Quad::flat([-1.0, 1.0, 1.0, -1.0], 0.999, 1.0, [0.5, 0.5, 0.5])
}

impl QuadScene {
    /// Red, green, blue and white quads of opacity 0.6, 0.6, 0.6, 0.2, each offset by half a
    /// quad towards upper-left, upper-right, lower-left, lower-right, near to far, drawn near to far.
    pub fn paper() -> Self {
        let half = 0.3;
        let quad = |dx: f32, dy: f32, depth, alpha, colour| {
            Quad::flat([dx * half - 0.45, dy * half + 0.45, dx * half + 0.45, dy * half - 0.45], depth, alpha, colour)
        };
        Self::keyed(
            "paper",
            vec![
                background(),
                quad(-1.0, 1.0, 0.2, 0.6, [1.0, 0.0, 0.0]),
                quad(1.0, 1.0, 0.4, 0.6, [0.0, 1.0, 0.0]),
                quad(-1.0, -1.0, 0.6, 0.6, [0.0, 0.0, 1.0]),
                quad(1.0, -1.0, 0.8, 0.2, [1.0, 1.0, 1.0]),
            ],
        )
    }

    /// A scene whose keys number its quads in order.
    pub fn keyed(name: &str, quads: Vec<Quad>) -> Self {
        let quads = quads.into_iter().enumerate().map(|(i, q)| Quad { key: i as u32, ..q }).collect();
        Self { name: name.into(), quads }
    }

    /// `layers` seeded quads: random colour and opacity (some nearly opaque, some nearly
    /// transparent), every fourth at the same depth as the one before.
    pub fn stiff(layers: u32, seed: u32) -> Self {
        let mut rng = SeededRng::new(seed);
        let mut quads = vec![background()];
        let mut depth = 0.1;
        for i in 0..layers {
            if i % 4 != 3 {
                depth = 0.05 + 0.9 * rng.unit();
            }
            let alpha = match i % 5 {
                0 => 0.97 + 0.029 * rng.unit(),
                1 => 0.001 + 0.02 * rng.unit(),
                _ => 0.1 + 0.8 * rng.unit(),
            };
            let (x, y) = (rng.unit() * 1.2 - 0.9, rng.unit() * 1.2 - 0.3);
            let (w, h) = (0.5 + 0.6 * rng.unit(), 0.5 + 0.6 * rng.unit());
            quads.push(Quad::flat([x, y, x + w, y - h], depth, alpha, [rng.unit(), rng.unit(), rng.unit()]));
        }
        Self::keyed(&format!("stiff_{layers}"), quads)
    }

    /// The paper's quads with an opaque slab tilted in depth cutting through all of them.
    pub fn intersecting() -> Self {
        let mut quads = Self::paper().quads;
        quads.insert(
            1,
            Quad { rect: [-0.8, 0.15, 0.8, -0.15], depth: (0.05, 0.95), alpha: 1.0, colour: [0.9, 0.6, 0.1], key: 0 },
        );
        Self::keyed("intersecting", quads)
    }

    /// Checks every quad; errors name the quad and the allowed range.
    pub fn validate(&self) -> Result<()> {
        for (i, quad) in self.quads.iter().enumerate() {
            if !(0.0..=1.0).contains(&quad.alpha) {
                bail!("quad {i} of scene {:?}: opacity {} is outside 0..=1 (NaN included)", self.name, quad.alpha);
            }
            if ![quad.depth.0, quad.depth.1].iter().all(|d| (0.0..=1.0).contains(d)) {
                bail!("quad {i} of scene {:?}: depth {:?} is outside 0..=1", self.name, quad.depth);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's scene: an opaque grey background at 0.999, then red, green, blue and white
    /// quads 0.9 wide, offset by 0.3 towards the upper-left, upper-right, lower-left and
    /// lower-right corners, at depths 0.2 to 0.8, opacity 0.6 but the white 0.2; keys in order.
    #[test]
    fn the_papers_quads_are_where_its_figure_puts_them() {
        let scene = QuadScene::paper();
        assert_eq!(scene.name, "paper");
        let expected = [
            ([-1.0, 1.0, 1.0, -1.0], 0.999, 1.0, [0.5, 0.5, 0.5]),
            ([-0.75, 0.75, 0.15, -0.15], 0.2, 0.6, [1.0, 0.0, 0.0]),
            ([-0.15, 0.75, 0.75, -0.15], 0.4, 0.6, [0.0, 1.0, 0.0]),
            ([-0.75, 0.15, 0.15, -0.75], 0.6, 0.6, [0.0, 0.0, 1.0]),
            ([-0.15, 0.15, 0.75, -0.75], 0.8, 0.2, [1.0, 1.0, 1.0]),
        ];
        assert_eq!(scene.quads.len(), 5);
        for (i, (quad, (rect, depth, alpha, colour))) in scene.quads.iter().zip(expected).enumerate() {
            assert!(quad.rect.iter().zip(rect).all(|(a, b)| (a - b).abs() < 1e-6), "quad {i}: {:?}", quad.rect);
            assert_eq!((quad.depth, quad.alpha, quad.colour, quad.key), ((depth, depth), alpha, colour, i as u32));
            assert_eq!(quad.is_opaque(), i == 0);
        }
        scene.validate().unwrap();
    }

    /// The stiff pile: the background and `layers` quads; every fourth layer at the depth of the
    /// one before, the others drawn in (0.05, 0.95); by layer index mod 5 nearly opaque (≥ 0.97),
    /// nearly clear (≤ 0.021) or in between; sizes 0.5–1.1; the seed decides them.
    #[test]
    fn a_stiff_pile_has_its_ties_and_its_extreme_opacities() {
        let scene = QuadScene::stiff(40, 9);
        assert_eq!((scene.name.as_str(), scene.quads.len()), ("stiff_40", 41));
        assert_eq!(scene.quads[0].depth, (0.999, 0.999));
        assert!(scene.quads.iter().enumerate().all(|(i, q)| q.key == i as u32));
        let layers = &scene.quads[1..];
        for (i, quad) in layers.iter().enumerate() {
            let depth = quad.depth.0;
            assert_eq!(quad.depth.1, depth);
            if i % 4 == 3 {
                assert_eq!(depth, layers[i - 1].depth.0, "layer {i} ties with the one before");
            } else {
                assert!((0.05..0.95).contains(&depth), "layer {i} at {depth}");
                assert!(i == 0 || depth != layers[i - 1].depth.0, "layer {i} ties by chance");
            }
            let alpha = quad.alpha;
            match i % 5 {
                0 => assert!((0.97..0.999).contains(&alpha), "layer {i}: {alpha}"),
                1 => assert!((0.001..0.021).contains(&alpha), "layer {i}: {alpha}"),
                _ => assert!((0.1..0.9).contains(&alpha), "layer {i}: {alpha}"),
            }
            let [x0, y0, x1, y1] = quad.rect;
            assert!((-0.9..0.3).contains(&x0) && (-0.3..0.9).contains(&y0), "layer {i}: {:?}", quad.rect);
            assert!((0.5..1.1).contains(&(x1 - x0)) && (0.5..1.1).contains(&(y0 - y1)), "layer {i}: {:?}", quad.rect);
            assert!(quad.colour.iter().all(|c| (0.0..1.0).contains(c)));
        }
        // The corners fill their ranges, not a part of them: within a tenth of each end.
        for (axis, (low, high)) in [(0, (-0.9, 0.3)), (1, (-0.3, 0.9))] {
            let corner = |q: &Quad| q.rect[axis];
            let (min, max) = layers.iter().map(corner).fold((f32::MAX, f32::MIN), |(a, b), v| (a.min(v), b.max(v)));
            assert!(min < low + 0.1 && max > high - 0.1, "axis {axis}: corners span {min}..{max}");
        }
        assert_eq!(QuadScene::stiff(40, 9), scene);
        assert_ne!(QuadScene::stiff(40, 10), scene);
        scene.validate().unwrap();
    }

    /// The intersecting scene: the paper's quads with an opaque slab from depth 0.05 at its left
    /// edge to 0.95 at its right inserted after the background; keys renumbered in order.
    #[test]
    fn the_intersecting_slab_cuts_through_the_papers_quads() {
        let scene = QuadScene::intersecting();
        let paper = QuadScene::paper();
        assert_eq!((scene.name.as_str(), scene.quads.len()), ("intersecting", 6));
        let slab = scene.quads[1];
        assert_eq!((slab.rect, slab.depth, slab.alpha, slab.key), ([-0.8, 0.15, 0.8, -0.15], (0.05, 0.95), 1.0, 1));
        assert!(slab.is_opaque());
        for (i, quad) in scene.quads.iter().enumerate().filter(|(i, _)| *i != 1) {
            let from_paper = paper.quads[if i == 0 { 0 } else { i - 1 }];
            assert_eq!(*quad, Quad { key: i as u32, ..from_paper });
        }
    }

    /// Opacities and depths outside 0..=1 (NaN included) are refused, naming the quad and scene.
    #[test]
    fn validation_refuses_opacities_and_depths_outside_0_to_1() {
        let with = |alpha: f32, depth: (f32, f32)| {
            let mut scene = QuadScene::paper();
            scene.quads[2].alpha = alpha;
            scene.quads[2].depth = depth;
            scene.validate().map_err(|e| e.to_string())
        };
        assert!(with(0.0, (0.0, 1.0)).is_ok() && with(1.0, (1.0, 0.0)).is_ok());
        for alpha in [-0.01, 1.01, f32::NAN] {
            let error = with(alpha, (0.5, 0.5)).unwrap_err();
            assert!(error.contains("quad 2 of scene \"paper\": opacity") && error.contains("outside 0..=1"), "{error}");
        }
        for depth in [(-0.1, 0.5), (0.5, 1.1), (0.5, f32::NAN), (f32::NAN, 0.5)] {
            let error = with(0.5, depth).unwrap_err();
            assert!(error.contains("quad 2 of scene \"paper\": depth"), "{error}");
        }
    }
}
