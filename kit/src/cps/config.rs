//! What a CPS run is asked to do: the LOD policy, the top level, the composite mode.

use anyhow::{Result, bail, ensure};

/// Nine levels, 1×1 to 256×256 pixels a coarse fragment, as in the original method; the level
/// index also fits the 9-bit LOD-present mask.
pub const MAX_LEVEL: u32 = 8;

#[derive(Clone, Debug, PartialEq)]
pub enum LodPolicy {
    /// Finest within `inner_radius` pixels of `focus` (fractions of the screen), one level
    /// coarser each time the distance doubles.
    Foveated { focus: (f32, f32), inner_radius: f32 },
    /// Coarsest level whose aligned block holds no geometric edge (normal angle beyond
    /// acos(`normal_cos`), a position jump beyond `depth_ratio` times the distance from the eye,
    /// or a coverage change).
    Content { normal_cos: f32, depth_ratio: f32 },
    /// The caller's own LOD per pixel, row-major, `width * height` values in 0..=8.
    Explicit(Vec<u8>),
}

impl LodPolicy {
    pub fn foveated() -> Self {
        Self::Foveated { focus: (0.5, 0.5), inner_radius: 24.0 }
    }

    pub fn content() -> Self {
        Self::Content { normal_cos: 0.9, depth_ratio: 0.05 }
    }

    pub fn name(&self) -> &'static str {
        match self {
            Self::Foveated { .. } => "foveated",
            Self::Content { .. } => "content",
            Self::Explicit(_) => "explicit",
        }
    }

    /// The foveated policy as the shaders take it (`Foveation` in common/foveation.wgsl, f32
    /// bits): the focus in pixels of `screen`, two words of padding, then the squared level
    /// boundaries (inner_radius (2^k − 1))² for k = 1..=8, computed in f64 and rounded, the
    /// largest f32 past `top` (no pixel is coarser than the plan's top level); zeros for the
    /// other policies.
    pub fn foveation_words(&self, screen: (u32, u32), top: u32) -> [u32; 4 + MAX_LEVEL as usize] {
        let mut words = [0.0f32.to_bits(); 4 + MAX_LEVEL as usize];
        if let Self::Foveated { focus, inner_radius } = self {
            words[0] = (focus.0 * screen.0 as f32).to_bits();
            words[1] = (focus.1 * screen.1 as f32).to_bits();
            let radius = f64::from(inner_radius.max(1e-3));
            for k in 1..=MAX_LEVEL {
                let boundary = radius * (f64::from(1u32 << k) - 1.0);
                let squared = if k <= top { (boundary * boundary) as f32 } else { f32::MAX };
                words[3 + k as usize] = squared.to_bits();
            }
        }
        words
    }

    /// Parses `foveated` or `content` (explicit policies come through the API).
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "foveated" => Ok(Self::foveated()),
            "content" => Ok(Self::content()),
            other => bail!("unknown LOD policy {other:?}; expected foveated or content"),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompositeMode {
    Nearest,
    FourNeighbour,
    SeamFree,
}

impl CompositeMode {
    pub const ALL: [Self; 3] = [Self::Nearest, Self::FourNeighbour, Self::SeamFree];

    pub fn name(self) -> &'static str {
        match self {
            Self::Nearest => "nearest",
            Self::FourNeighbour => "four_neighbour",
            Self::SeamFree => "seam_free",
        }
    }

    pub fn entry_point(self) -> &'static str {
        match self {
            Self::Nearest => "fs_composite_nearest",
            Self::FourNeighbour => "fs_composite_four_neighbour",
            Self::SeamFree => "fs_composite_seam_free",
        }
    }

    pub fn parse(name: &str) -> Result<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name).ok_or_else(|| {
            anyhow::anyhow!("unknown composite mode {name:?}; expected nearest, four_neighbour or seam_free")
        })
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct CpsConfig {
    /// Coarsest level any pixel may use (0..=8); clamped further on small screens.
    pub max_level: u32,
    pub policy: LodPolicy,
    pub composite: CompositeMode,
    /// The naive alternative the original method argues against: every texel of every level
    /// lit (no stencil pyramid), then composited. For comparison only.
    pub shade_every_texel: bool,
}

impl CpsConfig {
    pub fn new(max_level: u32, policy: LodPolicy, composite: CompositeMode) -> Self {
        Self { max_level, policy, composite, shade_every_texel: false }
    }

    /// The same configuration, lit the naive way (every level in full).
    pub fn naive(self) -> Self {
        Self { shade_every_texel: true, ..self }
    }

    /// Checks the configuration for a screen; errors name the bad value and the allowed range.
    pub fn validate(&self, (width, height): (u32, u32)) -> Result<()> {
        ensure!(
            self.max_level <= MAX_LEVEL,
            "max LOD level {} is out of range: levels are 0..={MAX_LEVEL} (2^8 = 256-pixel fragments, a 9-bit LOD mask)",
            self.max_level
        );
        match &self.policy {
            LodPolicy::Foveated { focus, inner_radius } => {
                ensure!(
                    inner_radius.is_finite() && *inner_radius > 0.0,
                    "foveation radius {inner_radius} must be a positive number of pixels"
                );
                ensure!(focus.0.is_finite() && focus.1.is_finite(), "foveation focus {focus:?} must be finite");
            }
            LodPolicy::Content { normal_cos, depth_ratio } => {
                ensure!((-1.0..=1.0).contains(normal_cos), "content policy normal_cos {normal_cos} must lie in -1..=1");
                ensure!(
                    depth_ratio.is_finite() && *depth_ratio >= 0.0,
                    "content policy depth_ratio {depth_ratio} must be >= 0"
                );
            }
            LodPolicy::Explicit(levels) => {
                let expected = width as usize * height as usize;
                ensure!(
                    levels.len() == expected,
                    "explicit LOD buffer has {} values; a {width}x{height} screen needs {expected}",
                    levels.len()
                );
                if let Some((i, &level)) = levels.iter().enumerate().find(|(_, l)| u32::from(**l) > MAX_LEVEL) {
                    bail!(
                        "explicit LOD {level} at pixel ({}, {}) is out of range 0..={MAX_LEVEL}",
                        i % width as usize,
                        i / width as usize
                    );
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_entry_points_are_the_composite_shaders() {
        for policy in [LodPolicy::foveated(), LodPolicy::content()] {
            assert_eq!(LodPolicy::parse(policy.name()).unwrap(), policy);
        }
        assert_eq!(LodPolicy::Explicit(vec![0]).name(), "explicit");
        assert!(LodPolicy::parse("explicit").is_err() && LodPolicy::parse("Foveated").is_err());
        let names = CompositeMode::ALL.map(CompositeMode::name);
        assert_eq!(names, ["nearest", "four_neighbour", "seam_free"]);
        for mode in CompositeMode::ALL {
            assert_eq!(CompositeMode::parse(mode.name()).unwrap(), mode);
            assert_eq!(mode.entry_point(), format!("fs_composite_{}", mode.name()));
        }
        assert!(CompositeMode::parse("bilinear").is_err());
        let config = CpsConfig::new(3, LodPolicy::content(), CompositeMode::SeamFree);
        assert!(!config.shade_every_texel && config.clone().naive().shade_every_texel);
        assert_eq!(CpsConfig { shade_every_texel: false, ..config.clone().naive() }, config);
    }

    /// The words the shaders read: the focus in pixels, then (r (2^k − 1))² for k ≤ top, rounded
    /// from f64, and f32::MAX past it; zeros for the other policies.
    #[test]
    fn foveation_words_are_the_focus_and_the_squared_boundaries() {
        let policy = LodPolicy::Foveated { focus: (0.25, 0.75), inner_radius: 3.0 };
        let words = policy.foveation_words((200, 100), 5);
        assert_eq!([f32::from_bits(words[0]), f32::from_bits(words[1])], [50.0, 75.0]);
        assert_eq!([words[2], words[3]], [0, 0]);
        for k in 1..=MAX_LEVEL {
            let boundary = 3.0 * (2f64.powi(k as i32) - 1.0);
            let expected = if k <= 5 { (boundary * boundary) as f32 } else { f32::MAX };
            assert_eq!(f32::from_bits(words[3 + k as usize]), expected, "level {k}");
        }
        // A radius that does not round exactly in f32: the square is taken in f64 first.
        let odd = LodPolicy::Foveated { focus: (0.5, 0.5), inner_radius: 24.1 }.foveation_words((64, 64), 8);
        assert_eq!(f32::from_bits(odd[4]), (f64::from(24.1f32) * f64::from(24.1f32)) as f32);
        assert_eq!(LodPolicy::content().foveation_words((64, 64), 8), [0; 4 + MAX_LEVEL as usize]);
    }

    #[test]
    fn a_configuration_outside_its_ranges_is_refused_naming_the_value() {
        let with = |policy: LodPolicy, max_level| CpsConfig::new(max_level, policy, CompositeMode::Nearest);
        let refused = |config: CpsConfig, size, said: &str| {
            let error = format!("{:#}", config.validate(size).unwrap_err());
            assert!(error.contains(said), "{error}");
        };
        assert!(with(LodPolicy::foveated(), MAX_LEVEL).validate((8, 8)).is_ok());
        refused(with(LodPolicy::foveated(), MAX_LEVEL + 1), (8, 8), "max LOD level 9 is out of range");
        for radius in [0.0, -1.0, f32::NAN] {
            refused(
                with(LodPolicy::Foveated { focus: (0.5, 0.5), inner_radius: radius }, 2),
                (8, 8),
                "foveation radius",
            );
        }
        refused(with(LodPolicy::Foveated { focus: (f32::INFINITY, 0.5), inner_radius: 4.0 }, 2), (8, 8), "focus");
        refused(with(LodPolicy::Content { normal_cos: 1.5, depth_ratio: 0.1 }, 2), (8, 8), "normal_cos 1.5");
        refused(with(LodPolicy::Content { normal_cos: 0.5, depth_ratio: -0.1 }, 2), (8, 8), "depth_ratio -0.1");
        assert!(with(LodPolicy::Content { normal_cos: -1.0, depth_ratio: 0.0 }, 2).validate((8, 8)).is_ok());
        refused(with(LodPolicy::Explicit(vec![0; 15]), 2), (4, 4), "has 15 values; a 4x4 screen needs 16");
        let mut levels = vec![MAX_LEVEL as u8; 16];
        assert!(with(LodPolicy::Explicit(levels.clone()), 2).validate((4, 4)).is_ok());
        levels[6] = MAX_LEVEL as u8 + 1;
        refused(with(LodPolicy::Explicit(levels), 2), (4, 4), "explicit LOD 9 at pixel (2, 1)");
    }
}
