//! One reconstructed frame held to the CPU model (`model.rs`) pixel by pixel: the GPU's source
//! and colour against the model's, the pixels the model cannot know counted by reason, and the
//! evidence strip where they differ.

use std::collections::BTreeMap;

use anyhow::Result;

use super::model::Expected;
use super::reconstruct::PixelSource;
use crate::image_compare::{error_mask, side_by_side};
use crate::tonemap::ldr_to_display;

/// One frame held to the model, pixel by pixel.
pub struct Comparison {
    /// Pixels per source the model knows, and per reason it cannot.
    pub tally: BTreeMap<&'static str, u64>,
    /// Where the GPU's source or colour is not the model's.
    pub wrong: Vec<bool>,
    pub differences: Vec<String>,
}

impl Comparison {
    pub fn of(expected: &[Expected], colours: &[f32], sources: &[PixelSource], width: u32) -> Self {
        let mut comparison =
            Self { tally: BTreeMap::new(), wrong: vec![false; expected.len()], differences: Vec::new() };
        for (i, expectation) in expected.iter().enumerate() {
            let (x, y) = (i as u32 % width, i as u32 / width);
            let (source, colour, bound) = match *expectation {
                Expected::Known { source, colour, tolerance } => (source, colour, tolerance),
                Expected::Unknowable(reason) => {
                    *comparison.tally.entry(reason).or_default() += 1;
                    continue;
                }
            };
            *comparison.tally.entry(source.name()).or_default() += 1;
            let got = [0, 1, 2].map(|c| f64::from(colours[i * 4 + c]));
            // Non-finite colours fail the comparison.
            let within = got.iter().zip(colour).all(|(g, e)| (g - e).abs() <= bound);
            let difference = if sources[i] != source {
                format!("({x}, {y}) {} where the model says {}", sources[i].name(), source.name())
            } else if !within {
                format!("({x}, {y}) from {} shows {got:.4?}, the model {colour:.4?} (±{bound:.2e})", source.name())
            } else {
                continue;
            };
            comparison.differences.push(difference);
            comparison.wrong[i] = true;
        }
        comparison
    }

    pub fn known_sources(&self) -> impl Iterator<Item = &'static str> + '_ {
        let sources = PixelSource::ALL.map(PixelSource::name);
        self.tally.keys().copied().filter(move |name| sources.contains(name))
    }

    /// Result, the model's colours (black where it cannot know) and the error mask.
    pub fn evidence(&self, screen: (u32, u32), expected: &[Expected], colours: &[f32]) -> Result<image::RgbaImage> {
        let modelled: Vec<[f32; 3]> = expected
            .iter()
            .map(|e| match e {
                Expected::Known { colour, .. } => colour.map(|c| c as f32),
                Expected::Unknowable(_) => [0.0; 3],
            })
            .collect();
        let result: Vec<[f32; 3]> = colours.chunks(4).map(|c| [c[0], c[1], c[2]]).collect();
        let reference = ldr_to_display(screen.0, screen.1, &modelled)?;
        let result = ldr_to_display(screen.0, screen.1, &result)?;
        Ok(side_by_side(&result, &reference, &error_mask(&reference, &self.wrong)))
    }
}
