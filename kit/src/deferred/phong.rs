//! A CPU model of the deferred Phong shading's definition (`shade_sample` in
//! `shaders/common/lighting.wgsl`), in f64, fed with read-back G-buffer samples and the scene's
//! own light list: the independent expectation for every path that lights a G-buffer sample.
//!
//! Each pixel gets an error bound derived from the GPU's arithmetic rather than tuned:
//! - every light's term, computed in f32 through ~20 operations, is off by at most 64 f32 ulps
//!   (2^-18 relative), plus `pow`'s error (exp2 of log2 with log2 absolute error ≤ 2^-21, scaled
//!   by the shininess) and the cancellation in `1 − (d/r)²` (absolute 2^-22, so 2^-21 / window
//!   relative once the window is squared);
//! - a decision the f32 arithmetic may take either way (a light at its range within 2^-20
//!   relative, a back-facing test within 2^-20 of zero) adds that whole term to the bound;
//! - summing N terms in f32 adds N · 2^-24 of their absolute sum;
//! - the `Rgba16Float` store loses up to one f16 ulp of the value (11 significant bits): Vulkan
//!   lets a conversion to a narrower float round to nearest or toward zero (lavapipe truncates).

use anyhow::Result;
use glam::DVec3;

use super::gbuffer::Gbuffer;
use crate::gpu::Gpu;
use crate::image_compare::{error_mask, side_by_side};
use crate::readback::read_texture;
use crate::scene::corridor::Light;
use crate::tonemap::to_display;

/// `BACKGROUND` in `lighting.wgsl`: where no surface was drawn.
pub const BACKGROUND: [f32; 3] = [0.02, 0.025, 0.035];

/// One G-buffer sample as the lighting shaders read it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// World position; `w` is 0 where no surface was drawn.
    pub position: [f32; 4],
    /// Normal (not normalised) and shininess.
    pub normal: [f32; 4],
    /// Albedo and specular weight.
    pub albedo: [f32; 4],
}

/// Reads every G-buffer sample back, row-major.
pub fn read_surfaces(gpu: &Gpu, gbuffer: &Gbuffer) -> Result<Vec<Surface>> {
    let all = wgpu::TextureAspect::All;
    let position = read_texture(gpu, &gbuffer.position, all, 0)?.as_f32();
    let normal = read_texture(gpu, &gbuffer.normal, all, 0)?.as_f16();
    let albedo = read_texture(gpu, &gbuffer.albedo, all, 0)?.bytes;
    let four = |values: &[f32]| -> [f32; 4] { [values[0], values[1], values[2], values[3]] };
    Ok(position
        .chunks_exact(4)
        .zip(normal.chunks_exact(4))
        .zip(albedo.chunks_exact(4))
        .map(|((p, n), a)| Surface {
            position: four(p),
            normal: four(n),
            albedo: a.iter().map(|&b| f32::from(b) / 255.0).collect::<Vec<_>>().try_into().expect("four bytes"),
        })
        .collect())
}

/// The expected colour of one sample and how far a correct GPU result may stray from it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadedSample {
    pub colour: [f64; 3],
    /// Absolute bound per channel, f16 storage included.
    pub bound: [f64; 3],
}

impl ShadedSample {
    /// Whether an `Rgba16Float` read-back colour is within the bound.
    pub fn admits(&self, gpu: &[f32]) -> bool {
        (0..3).all(|c| (f64::from(gpu[c]) - self.colour[c]).abs() <= self.bound[c])
    }

    /// The worst channel's error in units of its bound (≤ 1 passes).
    pub fn error_in_bounds(&self, gpu: &[f32]) -> f64 {
        (0..3).map(|c| (f64::from(gpu[c]) - self.colour[c]).abs() / self.bound[c]).fold(0.0, f64::max)
    }
}

/// A lit `Rgba16Float` image (read back as f32 RGBA) against one expectation per pixel.
pub struct PhongComparison {
    /// Per pixel: beyond its bound.
    pub wrong: Vec<bool>,
    pub wrong_count: usize,
    /// The worst channel error in units of its bound.
    pub worst: f64,
}

impl PhongComparison {
    pub fn new(expected: &[ShadedSample], gpu_rgba: &[f32]) -> Self {
        let pixels = || expected.iter().zip(gpu_rgba.chunks_exact(4));
        let wrong: Vec<bool> = pixels().map(|(e, g)| !e.admits(g)).collect();
        let worst = pixels().map(|(e, g)| e.error_in_bounds(g)).fold(0.0, f64::max);
        Self { wrong_count: wrong.iter().filter(|&&w| w).count(), wrong, worst }
    }

    /// The image, the expectation and the pixels beyond their bound, side by side.
    pub fn evidence(&self, size: (u32, u32), expected: &[ShadedSample], gpu_rgba: &[f32]) -> Result<image::RgbaImage> {
        let reference: Vec<f32> =
            expected.iter().flat_map(|e| [e.colour[0] as f32, e.colour[1] as f32, e.colour[2] as f32, 1.0]).collect();
        let reference = to_display(size.0, size.1, &reference)?;
        let result = to_display(size.0, size.1, gpu_rgba)?;
        Ok(side_by_side(&result, &reference, &error_mask(&reference, &self.wrong)))
    }
}

const F32_TERM_RELATIVE: f64 = 1.0 / (1u64 << 18) as f64;
const LOG2_ABSOLUTE: f64 = 1.0 / (1u64 << 21) as f64;
const WINDOW_ABSOLUTE: f64 = 1.0 / (1u64 << 22) as f64;
const AMBIGUOUS_RELATIVE: f64 = 1.0 / (1u64 << 20) as f64;
const F32_EPSILON_HALF: f64 = 1.0 / (1u64 << 24) as f64;

/// One f16 ulp of `value` (11 significant bits; subnormals below 2^-14 step by 2^-24).
fn f16_ulp(value: f64) -> f64 {
    let magnitude = value.abs().max(2f64.powi(-14));
    2f64.powi(magnitude.log2().floor() as i32 - 10)
}

fn vec3(v: &[f32]) -> DVec3 {
    DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))
}

/// `v` normalised, or `fallback` where `v` is too short to have a direction (the shader's
/// `select(n, v / length, length > 1e-6)`: an eye or a light at the surface point).
fn direction(v: DVec3, fallback: DVec3) -> DVec3 {
    let length = v.length();
    if length > 1e-6 { v / length } else { fallback }
}

/// The Phong shading of `surface` seen from `eye` under `lights`, as defined in `lighting.wgsl`.
pub fn shade(surface: &Surface, eye: glam::Vec3, lights: &[Light]) -> ShadedSample {
    if surface.position[3] == 0.0 {
        let colour = BACKGROUND.map(f64::from);
        return ShadedSample { colour, bound: colour.map(f16_ulp) };
    }
    let n = vec3(&surface.normal).normalize();
    let shininess = f64::from(surface.normal[3]);
    let albedo = vec3(&surface.albedo);
    let specular_weight = f64::from(surface.albedo[3]);
    let position = vec3(&surface.position);
    let v = direction(eye.as_dvec3() - position, n);

    let mut colour = albedo * 0.03;
    let mut magnitude = colour;
    let mut bound = DVec3::ZERO;
    for light in lights {
        let to_light = light.position.as_dvec3() - position;
        let distance = to_light.length();
        let range = f64::from(light.range).max(1e-6);
        let range_ambiguous = (distance - range).abs() <= AMBIGUOUS_RELATIVE * range;
        if distance >= range && !range_ambiguous {
            continue;
        }
        let l = direction(to_light, n);
        let window = (1.0 - (distance / range).powi(2)).max(0.0);
        let attenuation = window * window / (1.0 + distance * distance);
        let cosine = n.dot(l);
        let diffuse = cosine.max(0.0);
        let h = (l + v).normalize_or_zero();
        let highlight = n.dot(h).max(0.0).powf(shininess);
        let radiance = light.colour.as_dvec3() * f64::from(light.intensity) * attenuation;
        let diffuse_term = radiance * albedo * diffuse;
        let specular_term = radiance * specular_weight * highlight;
        let term = diffuse_term + if diffuse > 0.0 { specular_term } else { DVec3::ZERO };

        let relative = F32_TERM_RELATIVE
            + shininess * LOG2_ABSOLUTE * std::f64::consts::LN_2
            + if window > 0.0 { 2.0 * WINDOW_ABSOLUTE / window } else { 0.0 };
        bound += term.abs() * relative;
        if cosine.abs() <= AMBIGUOUS_RELATIVE {
            bound += specular_term.abs();
        }
        if range_ambiguous {
            bound += (diffuse_term + specular_term).abs();
        } else {
            colour += term;
        }
        magnitude += term.abs();
    }
    bound += magnitude * (lights.len() as f64 + 1.0) * F32_EPSILON_HALF;
    let colour = colour.to_array();
    let bound = std::array::from_fn(|c| bound[c] + f16_ulp(colour[c].abs() + bound[c]));
    ShadedSample { colour, bound }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    fn surface_facing_up() -> Surface {
        Surface { position: [0.0, 0.0, 0.0, 1.0], normal: [0.0, 1.0, 0.0, 8.0], albedo: [0.5, 0.5, 0.5, 0.0] }
    }

    #[test]
    fn a_light_overhead_lights_by_its_window_and_distance() {
        let light = Light { position: Vec3::new(0.0, 1.0, 0.0), range: 2.0, colour: Vec3::ONE, intensity: 1.0 };
        let shaded = shade(&surface_facing_up(), Vec3::new(0.0, 5.0, 0.0), &[light]);
        // window = 1 − 1/4; attenuation = window² / 2; diffuse 1, no specular weight.
        let expected = 0.5 * 0.03 + 0.5 * 0.75f64.powi(2) / 2.0;
        assert!((shaded.colour[0] - expected).abs() < 1e-12, "{:?}", shaded.colour);
        assert!(shaded.bound[0] < 1e-3 && shaded.bound[0] > 0.0);
    }

    #[test]
    fn a_light_beyond_its_range_adds_nothing() {
        let light = Light { position: Vec3::new(0.0, 3.0, 0.0), range: 2.0, colour: Vec3::ONE, intensity: 9.0 };
        let shaded = shade(&surface_facing_up(), Vec3::new(0.0, 5.0, 0.0), &[light]);
        assert!((shaded.colour[0] - 0.015).abs() < 1e-12);
    }

    #[test]
    fn a_light_at_its_range_is_a_decision_the_bound_leaves_open_and_inside_it_lights() {
        let ambient = 0.5 * 0.03;
        let at = |distance: f32| {
            let light =
                Light { position: Vec3::new(0.0, distance, 0.0), range: 2.0, colour: Vec3::ONE, intensity: 1e6 };
            shade(&surface_facing_up(), Vec3::new(0.0, 5.0, 0.0), &[light])
        };
        // Exactly at its range the window is 0: nothing added either way, and no window error
        // (a relative error of 1/window) left in the bound.
        assert_eq!(at(2.0).colour[0], ambient);
        assert!(at(2.0).bound[0] < 1e-4, "{:?}", at(2.0).bound);
        // Within 2^-20 of the range the f32 comparison may go either way: the term is left out
        // of the colour and its whole size put in the bound.
        let edge = 2.0 * (1.0 - 2f32.powi(-21));
        let window = 1.0 - (f64::from(edge) / 2.0).powi(2);
        let term = 1e6 * 0.5 * window * window / (1.0 + f64::from(edge).powi(2));
        assert_eq!(at(edge).colour[0], ambient);
        assert!(at(edge).bound[0] >= term && term > 0.0, "{:?} against {term}", at(edge).bound);
        // Past that it is lit, and the term is in the colour, not the bound.
        let inside = at(2.0 * (1.0 - 1e-3));
        assert!(inside.colour[0] > ambient + 0.1 && inside.bound[0] < 1e-3, "{inside:?}");
        // Just beyond the ambiguity nothing is added and nothing left open.
        let beyond = at(2.0 * (1.0 + 2f32.powi(-18)));
        assert_eq!(beyond.colour[0], ambient);
        assert!(beyond.bound[0] < 1e-4, "{beyond:?}");
    }

    /// A light within the ambiguity of its range leaves its whole term — diffuse and specular —
    /// open in the bound.
    #[test]
    fn a_light_at_its_range_leaves_its_diffuse_and_specular_open() {
        let surface = Surface { albedo: [0.5, 0.5, 0.5, 1.0], normal: [0.0, 1.0, 0.0, 1.0], ..surface_facing_up() };
        // The light overhead at its range, the eye along the surface: h at 45°, n·h = 1/√2.
        let edge = 2.0 * (1.0 - 2f32.powi(-21));
        // Bright enough that the term (window² ≈ 2^-40) outweighs the stored value's f16 ulp.
        let light = Light { position: Vec3::new(0.0, edge, 0.0), range: 2.0, colour: Vec3::ONE, intensity: 1e12 };
        let shaded = shade(&surface, Vec3::new(5.0, 0.0, 0.0), &[light]);
        let d = f64::from(edge);
        let radiance = f64::from(1e12f32) * (1.0 - (d / 2.0).powi(2)).powi(2) / (1.0 + d * d);
        let open = radiance * 0.5 + radiance * std::f64::consts::FRAC_1_SQRT_2;
        // The term's own error beside it: f32's, pow's, and the window's 2^-21 / window (1/2 here).
        let window = 1.0 - (d / 2.0).powi(2);
        let relative = 2f64.powi(-18) + 2f64.powi(-21) * std::f64::consts::LN_2 + 2f64.powi(-21) / window;
        let inner = open * (1.0 + relative);
        let expected = inner + f16_ulp(0.015 + inner);
        assert_eq!(shaded.colour[0], 0.015);
        assert!(
            (shaded.bound[0] - expected).abs() <= 1e-6 * expected,
            "{:?} against the term {open} and its error {relative}",
            shaded.bound
        );
    }

    /// A light exactly in the surface's plane (n·l = 0, a decision the f32 dot product may take
    /// either way) adds no diffuse and leaves its specular open in the bound; the stored value's
    /// f16 ulp is that of the colour plus its bound.
    #[test]
    fn a_grazing_light_leaves_its_specular_open() {
        let surface = Surface { albedo: [0.5, 0.5, 0.5, 1.0], normal: [0.0, 1.0, 0.0, 2.0], ..surface_facing_up() };
        // Light at distance 1 along x, range 2: window 3/4, attenuation (3/4)² / 2. The eye
        // straight above: h at 45°, highlight (1/√2)² = 1/2.
        let specular = |intensity: f64| intensity * 0.75f64.powi(2) / 2.0 * 0.5;
        let intensity = 0.99 / specular(1.0);
        let light = Light { position: Vec3::X, range: 2.0, colour: Vec3::ONE, intensity: intensity as f32 };
        let shaded = shade(&surface, Vec3::new(0.0, 100.0, 0.0), &[light]);
        let open = specular(f64::from(intensity as f32));
        assert_eq!(shaded.colour[0], 0.015);
        // 0.015 + 0.99 lies in [1, 2): one f16 ulp there is 2^-10 (below 1 it would be 2^-11).
        let stored = 2f64.powi(-10);
        assert!(
            shaded.bound[0] >= open + stored && shaded.bound[0] <= open + stored + 1e-6,
            "{:?} against the specular {open} and the f16 ulp {stored}",
            shaded.bound
        );
    }

    #[test]
    fn empty_pixels_are_the_background() {
        let mut surface = surface_facing_up();
        surface.position[3] = 0.0;
        assert_eq!(shade(&surface, Vec3::ZERO, &[]).colour, BACKGROUND.map(f64::from));
    }

    #[test]
    fn f16_ulp_is_2_to_the_minus_10_relative() {
        assert_eq!(f16_ulp(1.0), 2f64.powi(-10));
        assert_eq!(f16_ulp(1.5), 2f64.powi(-10));
        assert_eq!(f16_ulp(1000.0), 2f64.powi(9 - 10));
    }

    /// A seeded stream of numbers in [0, 1).
    fn uniform(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn vector(next: &mut impl FnMut() -> f64, scale: f64) -> DVec3 {
        DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * scale
    }

    /// `shade_sample` of lighting.wgsl read plainly, in f64, and the documented bound beside it:
    /// per light term its relative f32 error, pow's and the window's; the f32 sum's; one f16 ulp
    /// of the stored value.
    fn plain_shading(surface: &Surface, eye: DVec3, lights: &[Light]) -> (DVec3, [f64; 3]) {
        let n = vec3(&surface.normal).normalize();
        let position = vec3(&surface.position);
        let v = (eye - position).normalize();
        let shininess = f64::from(surface.normal[3]);
        let mut colour = vec3(&surface.albedo) * 0.03;
        let (mut sum, mut magnitude) = (DVec3::ZERO, colour);
        for light in lights {
            let to_light = light.position.as_dvec3() - position;
            let distance = to_light.length();
            let range = f64::from(light.range);
            if distance >= range {
                continue;
            }
            let l = to_light / distance;
            let window = 1.0 - (distance / range) * (distance / range);
            let attenuation = window * window / (1.0 + distance * distance);
            let diffuse = n.dot(l).max(0.0);
            let h = (l + v).normalize();
            let specular = if diffuse > 0.0 { n.dot(h).max(0.0).powf(shininess) } else { 0.0 };
            let tint = light.colour.as_dvec3() * f64::from(light.intensity);
            let term = tint
                * attenuation
                * (vec3(&surface.albedo) * diffuse + DVec3::splat(f64::from(surface.albedo[3]) * specular));
            colour += term;
            let relative =
                2f64.powi(-18) + shininess * 2f64.powi(-21) * std::f64::consts::LN_2 + 2.0 * 2f64.powi(-22) / window;
            sum += term.abs() * relative;
            magnitude += term.abs();
        }
        sum += magnitude * (lights.len() as f64 + 1.0) * 2f64.powi(-24);
        (colour, std::array::from_fn(|c| sum[c] + f16_ulp(colour[c].abs() + sum[c])))
    }

    /// On seeded surfaces and lights where no decision is close (no light within 1 % of its
    /// range, no surface within 0.01 of grazing), the model's colour is the plain reading's and
    /// its bound the documented one's.
    #[test]
    fn shading_and_its_bound_are_the_definitions_on_seeded_scenes() {
        let mut next = uniform(7);
        let mut lit = 0;
        for _ in 0..300 {
            let position = vector(&mut next, 4.0);
            let normal = vector(&mut next, 2.0) + DVec3::new(0.0, 0.3, 0.0);
            let eye = position + vector(&mut next, 6.0) + normal.normalize() * 2.0;
            let lights: Vec<Light> = (0..3)
                .map(|_| Light {
                    position: (position + vector(&mut next, 5.0)).as_vec3(),
                    range: (1.0 + 4.0 * next()) as f32,
                    colour: Vec3::new(next() as f32, next() as f32, next() as f32),
                    intensity: (0.5 + 3.0 * next()) as f32,
                })
                .collect();
            let f = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32];
            let [px, py, pz] = f(position);
            let [nx, ny, nz] = f(normal);
            let surface = Surface {
                position: [px, py, pz, 1.0],
                normal: [nx, ny, nz, (1.0 + 60.0 * next()) as f32],
                albedo: [next() as f32, next() as f32, next() as f32, next() as f32],
            };
            let (p, n) = (vec3(&surface.position), vec3(&surface.normal).normalize());
            let close = lights.iter().any(|light| {
                let to_light = light.position.as_dvec3() - p;
                ((to_light.length() / f64::from(light.range)) - 1.0).abs() < 0.01
                    || n.dot(to_light.normalize()).abs() < 0.01
            });
            if close {
                continue;
            }
            let eye = eye.as_vec3();
            let shaded = shade(&surface, eye, &lights);
            let (colour, bound) = plain_shading(&surface, eye.as_dvec3(), &lights);
            for c in 0..3 {
                assert!(
                    (shaded.colour[c] - colour[c]).abs() <= 1e-12 * colour[c].abs().max(1e-3),
                    "{shaded:?} vs {colour}"
                );
            }
            for c in 0..3 {
                assert!((shaded.bound[c] - bound[c]).abs() <= 1e-9 * bound[c], "{:?} vs {bound:?}", shaded.bound);
            }
            lit += usize::from(colour.x > 0.03 * f64::from(surface.albedo[0]) + 1e-6);
        }
        assert!(lit > 50, "{lit} lit samples");
    }

    /// A sample within its bound in every channel is admitted; one channel past it is not, and
    /// its error is that channel's, in units of its own bound.
    #[test]
    fn a_sample_is_admitted_within_its_bound_in_every_channel() {
        let sample = ShadedSample { colour: [0.5, 1.0, 2.0], bound: [0.01, 0.02, 0.04] };
        let at = |offsets: [f64; 3]| {
            std::array::from_fn::<f32, 4, _>(|c| if c < 3 { (sample.colour[c] + offsets[c]) as f32 } else { 1.0 })
        };
        assert!(sample.admits(&at([0.009, -0.019, 0.039])));
        for channel in 0..3 {
            let mut offsets = [0.0; 3];
            offsets[channel] = -1.5 * sample.bound[channel];
            assert!(!sample.admits(&at(offsets)), "channel {channel}");
            assert!((sample.error_in_bounds(&at(offsets)) - 1.5).abs() < 1e-4, "channel {channel}");
        }
        assert!((sample.error_in_bounds(&at([0.005, 0.0, -0.02])) - 0.5).abs() < 1e-4);
        let comparison = PhongComparison::new(&[sample, sample], &[at([0.0; 3]), at([0.0, 0.03, 0.0])].concat());
        assert_eq!((comparison.wrong.as_slice(), comparison.wrong_count), (&[false, true][..], 1));
        assert!((comparison.worst - 1.5).abs() < 1e-4);
        let image =
            comparison.evidence((2, 1), &[sample, sample], &[at([0.0; 3]), at([0.0, 0.03, 0.0])].concat()).unwrap();
        assert_eq!(image.dimensions(), (6, 1));
        // Result, expectation, and the mask: red where wrong.
        assert_eq!(image.get_pixel(5, 0).0, [255, 0, 0, 255]);
        assert_ne!(image.get_pixel(4, 0).0, [255, 0, 0, 255]);
        assert_eq!(image.get_pixel(0, 0), image.get_pixel(2, 0), "the result's first pixel is its expectation");
    }
}
