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
