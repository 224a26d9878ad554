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
