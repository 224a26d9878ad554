//! Where checkerboard samples land. A quarter-resolution pixel q has two samples at positions
//! p_s (pixel-relative; the standard 2x table: s0 (0.75, 0.75), s1 (0.25, 0.25)); with the view
//! jittered j full-resolution pixels right (j = 0 or 1, by frame parity) sample s of q sees the
//! full-resolution point 2 (q + p_s) + (j, 0), the centre of pixel floor of it. Sample indices come
//! from `sample_index` and the measured positions, never from `@builtin(position)`, whose meaning
//! differs between drivers.
//!
//! Two paths produce these samples: a real 2x MSAA target (where the kit measured one with the
//! standard positions), or, compute-free and everywhere, two single-sampled quarter-resolution
//! passes whose projections are offset by ±1/4 of a quarter-resolution pixel so that their pixel
//! centres fall where the 2x samples would.

use anyhow::{Result, ensure};
use serde::Serialize;

use crate::caps::matches_standard;
use crate::gpu::Gpu;
use crate::probe::sample_positions::{measure, standard_positions};

/// How a frame's two samples per quarter-resolution pixel are produced.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CheckerboardPath {
    /// One 2x multisampled pass, shaded per sample.
    Msaa2x,
    /// Two single-sampled passes, projections offset by ∓1/4 quarter-resolution pixel.
    OffsetPasses,
}

impl CheckerboardPath {
    /// How this path rasterises its views: the offset passes turned a quarter, the 2x target
    /// upright.
    pub fn orientation(self) -> Orientation {
        match self {
            Self::Msaa2x => Orientation::Upright,
            Self::OffsetPasses => Orientation::Turned,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Msaa2x => "msaa2x",
            Self::OffsetPasses => "offset_passes",
        }
    }

    /// `auto` (what [`Self::for_adapter`] picks), `msaa2x` (refused where the adapter offers no
    /// 2x target at all) or `offset_passes`.
    pub fn choose(gpu: &Gpu, name: &str) -> Result<Self> {
        match name {
            "auto" => Ok(Self::for_adapter(gpu)),
            "offset_passes" => Ok(Self::OffsetPasses),
            "msaa2x" => {
                let counts = crate::caps::common_sample_counts(gpu);
                ensure!(
                    counts.contains(&2),
                    "checkerboard path msaa2x needs 2x multisampling; this adapter offers {counts:?}"
                );
                Ok(Self::Msaa2x)
            }
            other => anyhow::bail!("unknown checkerboard path {other:?}; expected auto, msaa2x or offset_passes"),
        }
    }

    /// The real 2x path where this adapter renders a real 2x target at the standard positions,
    /// the offset passes otherwise (the flag alone is not trusted: llvmpipe's GL "2x" runs 4).
    pub fn for_adapter(gpu: &Gpu) -> Self {
        let real_2x = crate::caps::common_sample_counts(gpu).contains(&2)
            && measure(gpu, 2).is_ok_and(|m| m.agreed().is_some_and(|p| matches_standard(2, p)));
        if real_2x { Self::Msaa2x } else { Self::OffsetPasses }
    }
}

/// The standard 2x sample positions, pixel-relative.
pub fn sample_positions() -> [[f32; 2]; 2] {
    let table = standard_positions(2).expect("the 2x table exists");
    [table[0], table[1]]
}

/// Quarter-resolution size of a full-resolution screen.
pub fn quarter_size((width, height): (u32, u32)) -> (u32, u32) {
    (width.div_ceil(2), height.div_ceil(2))
}

/// The full-resolution pixel sample `sample` of quarter pixel `q` covers in jitter phase `phase`
/// (possibly outside the screen).
pub fn sample_pixel(q: (u32, u32), sample: usize, phase: u32, positions: &[[f32; 2]; 2]) -> (i64, i64) {
    let [px, py] = positions[sample];
    let x = 2.0 * (q.0 as f32 + px) + phase as f32;
    let y = 2.0 * (q.1 as f32 + py);
    (x.floor() as i64, y.floor() as i64)
}

/// The on-screen full-resolution pixels jitter phase `phase` samples, one item per sample.
fn phase_samples(screen: (u32, u32), phase: u32, positions: [[f32; 2]; 2]) -> impl Iterator<Item = (u32, u32)> {
    let (qw, qh) = quarter_size(screen);
    (0..qh)
        .flat_map(move |qy| (0..qw).flat_map(move |qx| (0..2).map(move |sample| ((qx, qy), sample))))
        .map(move |(q, sample)| sample_pixel(q, sample, phase, &positions))
        .filter(move |(x, y)| (0..i64::from(screen.0)).contains(x) && (0..i64::from(screen.1)).contains(y))
        .map(|(x, y)| (x as u32, y as u32))
}

/// For each full-resolution pixel, how many samples of the two phases land on it.
pub fn coverage_counts(screen: (u32, u32), positions: &[[f32; 2]; 2]) -> Vec<u32> {
    let mut counts = vec![0u32; (screen.0 * screen.1) as usize];
    for (x, y) in (0..2).flat_map(|phase| phase_samples(screen, phase, *positions)) {
        counts[(y * screen.0 + x) as usize] += 1;
    }
    counts
}

/// Per full-resolution pixel (row-major), whether jitter phase `phase` samples it.
pub fn sampled_pixels(screen: (u32, u32), phase: u32) -> Vec<bool> {
    let mut sampled = vec![false; (screen.0 * screen.1) as usize];
    for (x, y) in phase_samples(screen, phase, sample_positions()) {
        sampled[(y * screen.0 + x) as usize] = true;
    }
    sampled
}

/// The pixels the two phases leave unsampled by construction: the first column's odd rows
/// (phase 1 shifts the odd rows' samples right; nothing lands on x = 0 there).
pub fn documented_gaps(screen: (u32, u32)) -> Vec<(u32, u32)> {
    (0..screen.1).filter(|y| y % 2 == 1).map(|y| (0, y)).collect()
}

/// The jittered frames' projection offset in quarter-resolution pixels for the offset-pass path:
/// a pass whose pixel centre q + 1/2 must sample where sample s would, q + p_s.
pub fn offset_for_sample(sample: usize, positions: &[[f32; 2]; 2]) -> [f32; 2] {
    let [px, py] = positions[sample];
    [0.5 - px, 0.5 - py]
}

/// The clip-space transform that turns a full-resolution projection of `screen` into the
/// quarter-resolution one of jitter phase `phase`, shifted by `offset` quarter-resolution pixels:
/// full-resolution pixel coordinate x lands on quarter-resolution (x − phase) / 2 + offset (y
/// likewise, unjittered), odd sizes included (the quarter target covers one extra column/row).
pub fn quarter_projection(screen: (u32, u32), phase: u32, offset: [f32; 2]) -> glam::Mat4 {
    let (qw, qh) = quarter_size(screen);
    let (width, height, qw, qh) = (screen.0 as f32, screen.1 as f32, qw as f32, qh as f32);
    // ndc' = scale · ndc + shift, per axis, derived from the pixel mappings above (y points down
    // in pixels, up in NDC).
    let scale_x = width / (2.0 * qw);
    let shift_x = scale_x - 1.0 + (2.0 * offset[0] - phase as f32) / qw;
    let scale_y = height / (2.0 * qh);
    let shift_y = 1.0 - scale_y - 2.0 * offset[1] / qh;
    glam::Mat4::from_cols(
        glam::Vec4::new(scale_x, 0.0, 0.0, 0.0),
        glam::Vec4::new(0.0, scale_y, 0.0, 0.0),
        glam::Vec4::new(0.0, 0.0, 1.0, 0.0),
        glam::Vec4::new(shift_x, shift_y, 0.0, 1.0),
    )
}

/// A quarter turn of clip space, x' = −y, y' = x: a rotation, so faces keep their winding. The
/// offset passes draw each view through it into its Hq×Wq half of the sample layout (quarter pixel
/// (x, y) of the Wq×Hq view lands on texel (y, Wq − 1 − x)). llvmpipe shades groups of 4×2 pixels
/// and shades a partly covered group whole; turned, the vertical edges that dominate a scene of
/// walls, columns and boxes run along the groups' long side and cut half as many of them.
pub const QUARTER_TURN: glam::Mat4 = glam::Mat4::from_cols(
    glam::Vec4::new(0.0, 1.0, 0.0, 0.0),
    glam::Vec4::new(-1.0, 0.0, 0.0, 0.0),
    glam::Vec4::new(0.0, 0.0, 1.0, 0.0),
    glam::Vec4::new(0.0, 0.0, 0.0, 1.0),
);

/// How a frame is rasterised: upright, or turned a quarter (`QUARTER_TURN`) as the offset passes
/// draw their views — the full-resolution baselines of checkerboarding draw both ways.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Orientation {
    Upright,
    Turned,
}

impl Orientation {
    pub fn name(self) -> &'static str {
        match self {
            Self::Upright => "upright",
            Self::Turned => "turned",
        }
    }

    /// Applied after a view's projection.
    pub fn clip_transform(self) -> glam::Mat4 {
        match self {
            Self::Upright => glam::Mat4::IDENTITY,
            Self::Turned => QUARTER_TURN,
        }
    }

    /// The target a `(width, height)` image is rasterised into.
    pub fn target_size(self, size: (u32, u32)) -> (u32, u32) {
        match self {
            Self::Upright => size,
            Self::Turned => (size.1, size.0),
        }
    }
}

/// Checks a screen size for checkerboarding (at least 2×2: a quarter pixel needs its diagonal).
pub fn check_screen(screen: (u32, u32)) -> Result<()> {
    ensure!(screen.0 >= 2 && screen.1 >= 2, "checkerboard screen {screen:?} is smaller than 2x2");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_2x_table_puts_samples_on_diagonal_pixel_centres() {
        let positions = sample_positions();
        // Phase 0: s1 on the top-left pixel of the 2×2 block, s0 on the bottom-right.
        assert_eq!(sample_pixel((3, 5), 1, 0, &positions), (6, 10));
        assert_eq!(sample_pixel((3, 5), 0, 0, &positions), (7, 11));
        // Phase 1: one pixel to the right, the anti-diagonal (s0 in the next block's row).
        assert_eq!(sample_pixel((3, 5), 1, 1, &positions), (7, 10));
        assert_eq!(sample_pixel((3, 5), 0, 1, &positions), (8, 11));
    }

    #[test]
    fn two_phases_hit_every_pixel_once_but_the_documented_column() {
        let positions = sample_positions();
        for screen in [(2, 2), (7, 5), (64, 48), (33, 17)] {
            let counts = coverage_counts(screen, &positions);
            let gaps = documented_gaps(screen);
            for y in 0..screen.1 {
                for x in 0..screen.0 {
                    let expected = u32::from(!gaps.contains(&(x, y)));
                    assert_eq!(counts[(y * screen.0 + x) as usize], expected, "{screen:?} pixel ({x}, {y})");
                }
            }
        }
    }

    #[test]
    fn the_quarter_projection_maps_pixels_as_documented() {
        for (screen, phase, offset) in
            [((64, 48), 0, [0.0, 0.0]), ((33, 17), 1, [-0.25, -0.25]), ((7, 5), 1, [0.25, 0.25])]
        {
            let m = quarter_projection(screen, phase, offset);
            let (qw, qh) = quarter_size(screen);
            for (x, y) in [(0.0f32, 0.0f32), (3.5, 2.5), (screen.0 as f32, screen.1 as f32)] {
                let ndc = glam::Vec4::new(x / screen.0 as f32 * 2.0 - 1.0, 1.0 - y / screen.1 as f32 * 2.0, 0.5, 1.0);
                let q = m * ndc;
                let (qx, qy) = ((q.x + 1.0) * 0.5 * qw as f32, (1.0 - q.y) * 0.5 * qh as f32);
                let expected = ((x - phase as f32) / 2.0 + offset[0], y / 2.0 + offset[1]);
                assert!(
                    (qx - expected.0).abs() < 1e-4 && (qy - expected.1).abs() < 1e-4,
                    "{screen:?} ({x}, {y}): ({qx}, {qy}) not {expected:?}"
                );
            }
        }
    }

    #[test]
    fn the_quarter_turn_puts_view_pixels_on_turned_texels() {
        let (w, h) = (7.0f32, 5.0f32);
        for (x, y) in [(0.5f32, 0.5f32), (6.5, 0.5), (2.5, 4.5), (0.0, 5.0)] {
            let ndc = glam::Vec3::new(x / w * 2.0 - 1.0, 1.0 - y / h * 2.0, 0.5);
            let turned = QUARTER_TURN.project_point3(ndc);
            // The turned target is h wide and w tall.
            let (tx, ty) = ((turned.x + 1.0) * 0.5 * h, (1.0 - turned.y) * 0.5 * w);
            assert!((tx - y).abs() < 1e-5 && (ty - (w - x)).abs() < 1e-5, "({x}, {y}) -> ({tx}, {ty})");
        }
        assert!(QUARTER_TURN.determinant() > 0.0, "a turn keeps the winding");
    }

    #[test]
    fn offset_passes_centre_on_the_2x_positions() {
        let positions = sample_positions();
        assert_eq!(offset_for_sample(0, &positions), [-0.25, -0.25]);
        assert_eq!(offset_for_sample(1, &positions), [0.25, 0.25]);
    }

    /// A phase samples the checkerboard's pixels of its parity: (x + y + phase) even — the
    /// definition, read plainly — on screens odd and even.
    #[test]
    fn a_phase_samples_the_pixels_of_its_parity() {
        for screen in [(2, 2), (5, 4), (7, 3)] {
            for phase in 0..2 {
                let sampled = sampled_pixels(screen, phase);
                assert_eq!(sampled.len(), (screen.0 * screen.1) as usize);
                for (index, &hit) in sampled.iter().enumerate() {
                    let (x, y) = (index as u32 % screen.0, index as u32 / screen.0);
                    // Phase 1 samples one pixel to the right of phase 0: nothing lands on the
                    // first column's odd rows (the documented gap).
                    let parity = (x + y + phase) % 2 == 0;
                    let past = phase == 1 && x == 0 && y % 2 == 1;
                    assert_eq!(hit, parity && !past, "{screen:?} phase {phase} pixel ({x}, {y})");
                }
            }
        }
    }

    #[test]
    fn orientations_turn_the_target_and_the_clip_space_a_quarter() {
        assert_eq!([Orientation::Upright.name(), Orientation::Turned.name()], ["upright", "turned"]);
        assert_eq!(Orientation::Upright.target_size((64, 48)), (64, 48));
        assert_eq!(Orientation::Turned.target_size((64, 48)), (48, 64));
        assert_eq!(Orientation::Upright.clip_transform(), glam::Mat4::IDENTITY);
        // A quarter turn: clip x goes to y, y to −x.
        let turned = Orientation::Turned.clip_transform() * glam::Vec4::new(0.5, 0.25, 0.3, 1.0);
        assert_eq!(turned, glam::Vec4::new(-0.25, 0.5, 0.3, 1.0));
        assert_eq!(CheckerboardPath::Msaa2x.orientation(), Orientation::Upright);
        assert_eq!(CheckerboardPath::OffsetPasses.orientation(), Orientation::Turned);
        assert_eq!(
            [CheckerboardPath::Msaa2x.name(), CheckerboardPath::OffsetPasses.name()],
            ["msaa2x", "offset_passes"]
        );
        assert!(check_screen((2, 2)).is_ok());
        for small in [(1, 2), (2, 1), (0, 0)] {
            assert!(check_screen(small).is_err(), "{small:?}");
        }
    }
}
