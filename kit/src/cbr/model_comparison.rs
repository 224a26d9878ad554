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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cbr::model::NEAR_AN_EDGE;

    /// A frame of four pixels (2×2): each known pixel passes only with the model's source and
    /// every channel within the tolerance; one channel out, or the wrong source, fails it and
    /// names it; what the model cannot know is counted by reason and never judged.
    #[test]
    fn a_pixel_passes_with_the_models_source_and_every_channel_within_its_tolerance() {
        let known = |source, colour| Expected::Known { source, colour, tolerance: 0.01 };
        let expected = [
            known(PixelSource::Current, [0.5, 0.5, 0.5]),
            known(PixelSource::History, [0.2, 0.4, 0.6]),
            Expected::Unknowable(NEAR_AN_EDGE),
            known(PixelSource::History, [1.0, 0.0, 0.0]),
        ];
        let colours = [
            [0.509, 0.491, 0.5, 1.0], // within in every channel
            [0.2, 0.4, 0.62, 1.0],    // blue out by 0.02
            [9.0, 9.0, 9.0, 1.0],     // unknowable: anything goes
            [1.0, 0.0, 0.0, 1.0],     // right colour, wrong source
        ]
        .concat();
        let sources = [PixelSource::Current, PixelSource::History, PixelSource::Current, PixelSource::Disoccluded];
        let comparison = Comparison::of(&expected, &colours, &sources, 2);
        assert_eq!(comparison.wrong, [false, true, false, true]);
        assert_eq!(comparison.differences.len(), 2);
        assert!(comparison.differences[0].starts_with("(1, 0) from history shows"), "{:?}", comparison.differences);
        assert_eq!(comparison.differences[1], "(1, 1) disoccluded where the model says history");
        let tally: Vec<(&str, u64)> = comparison.tally.iter().map(|(k, v)| (*k, *v)).collect();
        assert_eq!(tally, [("current", 1), ("history", 2), (NEAR_AN_EDGE, 1)]);
        assert_eq!(comparison.known_sources().collect::<Vec<_>>(), ["current", "history"]);
        // Each channel alone out of bounds fails; a NaN fails.
        for c in 0..3 {
            let mut colours = [0.5f32, 0.5, 0.5, 1.0];
            colours[c] += 0.011;
            let one = Comparison::of(&expected[..1], &colours, &sources[..1], 1);
            assert_eq!(one.wrong, [true], "channel {c}");
        }
        let nan = Comparison::of(&expected[..1], &[0.5, f32::NAN, 0.5, 1.0], &sources[..1], 1);
        assert_eq!(nan.wrong, [true]);
        // Each pixel is read at its own four floats.
        let two = [known(PixelSource::Current, [0.5, 0.5, 0.5]), known(PixelSource::Current, [0.9, 0.1, 0.2])];
        let right = Comparison::of(&two, &[0.5, 0.5, 0.5, 1.0, 0.9, 0.1, 0.2, 1.0], &[PixelSource::Current; 2], 2);
        assert_eq!(right.wrong, [false, false]);
        // The evidence: result, model (black where unknowable), the mask red where wrong.
        let image = comparison.evidence((2, 2), &expected, &colours).unwrap();
        assert_eq!(image.dimensions(), (6, 2));
        assert_eq!(image.get_pixel(2, 1).0, [0, 0, 0, 255]);
        assert_eq!(image.get_pixel(5, 0).0, [255, 0, 0, 255]);
        assert_ne!(image.get_pixel(4, 0).0, [255, 0, 0, 255]);
    }
}
