//! The reconstruction pass (`shaders/cbr/reconstruct.wgsl`): full resolution rebuilt from
//! frames N and N−1 in the sample layout, with a second target saying where each pixel came from.

use anyhow::Result;
use serde::Serialize;

use super::frame::{CheckerboardFrame, TARGET_USAGE};
use super::plan::CheckerboardPlan;
use super::sampling::quarter_size;
use super::scene::FrameView;
use super::scene_pass::{DEPTH, HDR};
use crate::attachments;
use wgpu::util::DeviceExt;

use crate::fullscreen::{FullscreenPipeline, bind_group, bind_group_at};
use crate::gpu::Gpu;
use crate::probe::fragment_storage::fragment_storage_problem;
use crate::query::GpuTimer;
use crate::shaders;

/// Where a reconstructed pixel's colour came from (the pass's second output, R8Uint).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PixelSource {
    /// Frame N sampled it.
    Current,
    /// Frame N−1, through the motion.
    History,
    /// Filled: no frame N−1 yet.
    FirstFrame,
    /// Filled: the motion lands on one of frame N's own pixels (it cancels the jitter).
    JitterCancelled,
    /// Filled: the history is stale (CSO depth check failed, or an object left it).
    Disoccluded,
    /// Filled: moved at least a quarter-resolution pixel, and ASO assumes that is missing.
    Assumed,
    /// Filled: the history lies off screen or in the never-sampled gap column.
    OffScreen,
}

impl PixelSource {
    pub const ALL: [Self; 7] = [
        Self::Current,
        Self::History,
        Self::FirstFrame,
        Self::JitterCancelled,
        Self::Disoccluded,
        Self::Assumed,
        Self::OffScreen,
    ];

    pub fn from_byte(byte: u8) -> Option<Self> {
        Self::ALL.get(usize::from(byte)).copied()
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Current => "current",
            Self::History => "history",
            Self::FirstFrame => "first_frame",
            Self::JitterCancelled => "jitter_cancelled",
            Self::Disoccluded => "disoccluded",
            Self::Assumed => "assumed",
            Self::OffScreen => "off_screen",
        }
    }

    /// Whether the colour was filled from neighbours (missing shading).
    pub fn is_filled(self) -> bool {
        !matches!(self, Self::Current | Self::History)
    }
}

/// How a pixel that moved at least a quarter-resolution pixel is judged.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Detection {
    /// Checked: N−1's linear depth against the mean of frame N's four cardinal neighbours,
    /// within `tolerance` of it (relative).
    Cso { tolerance: f32 },
    /// Assumed missing.
    Aso,
}

impl Detection {
    pub const DEFAULT_CSO: Self = Self::Cso { tolerance: 0.05 };

    /// `aso`, `cso` (default tolerance) or `cso:<tolerance>` (relative, finite, at least 0).
    pub fn parse(name: &str) -> anyhow::Result<Self> {
        match name.split_once(':') {
            None if name == "aso" => Ok(Self::Aso),
            None if name == "cso" => Ok(Self::DEFAULT_CSO),
            Some(("cso", tolerance)) => match tolerance.parse::<f32>() {
                Ok(t) if t.is_finite() && t >= 0.0 => Ok(Self::Cso { tolerance: t }),
                _ => anyhow::bail!("CSO depth tolerance {tolerance:?} must be a finite number >= 0 (relative depth)"),
            },
            _ => anyhow::bail!("unknown detection {name:?}; expected aso, cso or cso:<tolerance>"),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Cso { .. } => "cso",
            Self::Aso => "aso",
        }
    }
}

pub const SOURCE: wgpu::TextureFormat = wgpu::TextureFormat::R8Uint;

/// Where the per-frame parameters (`rebuild` in the shader) live: a read-only storage buffer
/// where fragment shaders have storage buffers (the shader says why not a uniform), else a uniform
/// buffer. GL 3.3 (softpipe) has no storage buffers, and the pass only reads its parameters, so
/// it runs there too; the struct's layout is the same in both address spaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParameterBuffer {
    Storage,
    Uniform,
}

const STORAGE_DECLARATION: &str = "var<storage, read> rebuild: Reconstruction;";
const UNIFORM_DECLARATION: &str = "var<uniform> rebuild: Reconstruction;";

impl ParameterBuffer {
    /// Storage where the fragment-storage probe's render wrote its buffer, else uniform.
    pub fn for_device(gpu: &Gpu) -> Result<Self> {
        Ok(match fragment_storage_problem(gpu)? {
            None => Self::Storage,
            Some(_) => Self::Uniform,
        })
    }

    /// The reconstruction shader as compiled, `rebuild` declared in this buffer.
    pub fn shader_source(self) -> Result<String> {
        let source = shaders::CBR_RECONSTRUCT.assembled();
        let declared = source.matches(STORAGE_DECLARATION).count();
        anyhow::ensure!(
            declared == 1,
            "{} declares `{STORAGE_DECLARATION}` {declared} times, not once: the uniform variant replaces it",
            shaders::CBR_RECONSTRUCT.path
        );
        Ok(match self {
            Self::Storage => source,
            Self::Uniform => source.replace(STORAGE_DECLARATION, UNIFORM_DECLARATION),
        })
    }

    fn usage(self) -> wgpu::BufferUsages {
        match self {
            Self::Storage => wgpu::BufferUsages::STORAGE,
            Self::Uniform => wgpu::BufferUsages::UNIFORM,
        }
    }
}

/// The reconstruction's pipelines, specialised on the renderer's plan and detection, its outputs,
/// and the 1×1 placeholders bound where a frame has no motion or forward buffer (WGSL bindings are
/// static; the specialisation keeps them unread).
pub struct Reconstruction {
    pipeline: wgpu::RenderPipeline,
    /// Where nothing moves: `fs_reconstruct_still`, for frames with history (all but column 0).
    still: Option<wgpu::RenderPipeline>,
    detection: Detection,
    parameters: ParameterBuffer,
    pub colour: wgpu::Texture,
    pub source: wgpu::Texture,
    /// The motion each pixel used, for pictures (`Reconstruction::showing_motion`).
    pub motion: Option<wgpu::Texture>,
    placeholder: wgpu::Texture,
    placeholder_depth: wgpu::Texture,
}

/// What one reconstruction reads.
pub struct ReconstructionInputs<'a> {
    pub current: &'a CheckerboardFrame,
    pub previous: Option<&'a CheckerboardFrame>,
    pub view: &'a FrameView,
    pub phase: u32,
    pub near_far: (f32, f32),
}

/// The shader's `override` constants: what the plan says the scene can need.
fn specialisation(plan: &CheckerboardPlan, detection: Detection) -> [(&'static str, f64); 4] {
    let on = |b: bool| f64::from(u8::from(b));
    [
        ("camera_moves", on(plan.camera_reprojection)),
        ("objects_move", on(plan.object_motion)),
        ("forward_buffer", on(plan.forward_buffer)),
        ("depth_check", on(matches!(detection, Detection::Cso { .. }))),
    ]
}

impl Reconstruction {
    pub fn new(gpu: &Gpu, screen: (u32, u32), plan: &CheckerboardPlan, detection: Detection) -> Result<Self> {
        Self::create(gpu, screen, plan, detection, false)
    }

    /// A reconstruction that also writes the motion each pixel used (pictures).
    pub fn showing_motion(
        gpu: &Gpu,
        screen: (u32, u32),
        plan: &CheckerboardPlan,
        detection: Detection,
    ) -> Result<Self> {
        Self::create(gpu, screen, plan, detection, true)
    }

    fn create(
        gpu: &Gpu,
        screen: (u32, u32),
        plan: &CheckerboardPlan,
        detection: Detection,
        with_motion: bool,
    ) -> Result<Self> {
        let mut targets = vec![Some(HDR.into()), Some(SOURCE.into())];
        if with_motion {
            targets.push(Some(HDR.into()));
        }
        let constants = specialisation(plan, detection);
        let parameters = ParameterBuffer::for_device(gpu)?;
        let module = shaders::CBR_RECONSTRUCT.module_from(gpu, parameters.shader_source()?);
        let pipeline = |label, entry_point| {
            FullscreenPipeline {
                label,
                fragment: shaders::CBR_RECONSTRUCT,
                entry_point,
                targets: &targets,
                depth_stencil: None,
                samples: 1,
            }
            .create_from_module(gpu, &module, &constants)
        };
        let entry_point = if with_motion { "fs_reconstruct_showing_motion" } else { "fs_reconstruct" };
        let nothing_moves = !plan.camera_reprojection && !plan.object_motion;
        let still = (nothing_moves && !with_motion)
            .then(|| pipeline("reconstruction of a still frame", "fs_reconstruct_still"));
        let pipeline = pipeline("reconstruction", entry_point);
        Ok(Self {
            pipeline,
            still,
            detection,
            parameters,
            colour: gpu.texture("reconstruction", screen, HDR, 1, TARGET_USAGE),
            source: gpu.texture("pixel sources", screen, SOURCE, 1, TARGET_USAGE),
            motion: with_motion.then(|| gpu.texture("reconstruction motion", screen, HDR, 1, TARGET_USAGE)),
            placeholder: gpu.texture("no texture", (1, 1), HDR, 1, wgpu::TextureUsages::TEXTURE_BINDING),
            placeholder_depth: gpu.texture("no depth", (1, 1), DEPTH, 1, wgpu::TextureUsages::TEXTURE_BINDING),
        })
    }

    pub fn record(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        inputs: &ReconstructionInputs,
    ) {
        let screen = (self.colour.width(), self.colour.height());
        let (qw, qh) = quarter_size(screen);
        let tolerance = match self.detection {
            Detection::Cso { tolerance } => tolerance,
            Detection::Aso => 0.0,
        };
        let mut words: Vec<u32> = inputs.view.full_from_world.inverse().to_cols_array().map(f32::to_bits).to_vec();
        words.extend(inputs.view.previous_full_from_world.to_cols_array().map(f32::to_bits));
        words.extend([
            screen.0,
            screen.1,
            qw,
            qh,
            inputs.phase,
            u32::from(inputs.previous.is_some()),
            tolerance.to_bits(),
            inputs.near_far.0.to_bits(),
        ]);
        words.extend([inputs.near_far.1.to_bits(), 0, 0, 0]);
        let parameters = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("reconstruction parameters"),
            contents: bytemuck::cast_slice(&words),
            usage: self.parameters.usage(),
        });

        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let frame_views = |frame: Option<&CheckerboardFrame>| {
            let or_placeholder = |t: Option<&wgpu::Texture>| view(t.unwrap_or(&self.placeholder));
            [
                view(frame.map_or(&self.placeholder, |f| &f.colour)),
                view(frame.map_or(&self.placeholder_depth, |f| &f.depth)),
                or_placeholder(frame.and_then(|f| f.motion.as_ref())),
                or_placeholder(frame.and_then(|f| f.forward.as_ref())),
            ]
        };
        let current = frame_views(Some(inputs.current));
        let previous = frame_views(inputs.previous);
        let mut resources = vec![parameters.as_entire_binding()];
        resources.extend(current.iter().chain(&previous).map(wgpu::BindingResource::TextureView));
        let group = bind_group(gpu, "reconstruction", &self.pipeline, 0, &resources);

        let (colour, source) = (view(&self.colour), view(&self.source));
        let motion = self.motion.as_ref().map(view);
        let mut targets = vec![
            attachments::colour(&colour, None, wgpu::Color::TRANSPARENT),
            attachments::colour(&source, None, wgpu::Color::TRANSPARENT),
        ];
        if let Some(motion) = &motion {
            targets.push(attachments::colour(motion, None, wgpu::Color::TRANSPARENT));
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("reconstruction"),
            color_attachments: &targets,
            timestamp_writes: timer.pass("reconstruction"),
            ..Default::default()
        });
        match (&self.still, inputs.previous) {
            // Column 0's odd rows need the fill: the full pipeline draws that column.
            (Some(still), Some(_)) if screen.0 > 1 => {
                let [current_colour, _, _, current_forward] = &current;
                let [previous_colour, _, _, previous_forward] = &previous;
                let still_group = bind_group_at(
                    gpu,
                    "reconstruction of a still frame",
                    still,
                    0,
                    &[
                        (0, parameters.as_entire_binding()),
                        (1, wgpu::BindingResource::TextureView(current_colour)),
                        (4, wgpu::BindingResource::TextureView(current_forward)),
                        (5, wgpu::BindingResource::TextureView(previous_colour)),
                        (8, wgpu::BindingResource::TextureView(previous_forward)),
                    ],
                );
                pass.set_scissor_rect(1, 0, screen.0 - 1, screen.1);
                pass.set_pipeline(still);
                pass.set_bind_group(0, &still_group, &[]);
                pass.draw(0..3, 0..1);
                pass.set_scissor_rect(0, 0, 1, screen.1);
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.draw(0..3, 0..1);
            }
            _ => {
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.draw(0..3, 0..1);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cbr::plan::Shading;
    use crate::cbr::sampling::CheckerboardPath;

    /// The source map stores each pixel's source as its index in `ALL`: every byte 0..7 reads
    /// back as the source written, anything else as none; two of them shaded, five filled.
    #[test]
    fn sources_read_back_from_their_bytes_and_say_whether_they_were_filled() {
        for (byte, source) in PixelSource::ALL.iter().enumerate() {
            assert_eq!(PixelSource::from_byte(byte as u8), Some(*source));
        }
        assert_eq!(PixelSource::from_byte(7), None);
        assert_eq!(PixelSource::from_byte(255), None);
        let names = PixelSource::ALL.map(PixelSource::name);
        assert_eq!(
            names,
            ["current", "history", "first_frame", "jitter_cancelled", "disoccluded", "assumed", "off_screen"]
        );
        let filled: Vec<bool> = PixelSource::ALL.iter().map(|s| s.is_filled()).collect();
        assert_eq!(filled, [false, false, true, true, true, true, true]);
    }

    #[test]
    fn detections_parse_from_their_names_and_refuse_bad_tolerances() {
        assert_eq!(Detection::parse("aso").unwrap(), Detection::Aso);
        assert_eq!(Detection::parse("cso").unwrap(), Detection::Cso { tolerance: 0.05 });
        assert_eq!(Detection::parse("cso:0.2").unwrap(), Detection::Cso { tolerance: 0.2 });
        assert_eq!(Detection::parse("cso:0").unwrap(), Detection::Cso { tolerance: 0.0 });
        assert_eq!((Detection::Aso.name(), Detection::DEFAULT_CSO.name()), ("aso", "cso"));
        for bad in ["cso:-0.1", "cso:inf", "cso:NaN", "cso:x", "aso:1", "", "CSO", "cso:"] {
            let error = Detection::parse(bad).unwrap_err().to_string();
            assert!(error.contains("tolerance") || error.contains("unknown detection"), "{bad:?}: {error}");
        }
        assert!(Detection::parse("cso:-0.1").unwrap_err().to_string().contains("finite number >= 0"));
    }

    /// The shader's specialisation constants say exactly what the plan needs.
    #[test]
    fn specialisation_follows_the_plan_and_the_detection() {
        let plan = |object_motion, camera_reprojection, forward_buffer| CheckerboardPlan {
            path: CheckerboardPath::OffsetPasses,
            shading: Shading::Deferred,
            object_motion,
            camera_reprojection,
            transparents: forward_buffer,
            forward_buffer,
        };
        let constants = |p: &CheckerboardPlan, d| specialisation(p, d).map(|(name, value)| format!("{name}={value}"));
        assert_eq!(
            constants(&plan(true, false, true), Detection::Aso),
            ["camera_moves=0", "objects_move=1", "forward_buffer=1", "depth_check=0"]
        );
        assert_eq!(
            constants(&plan(false, true, false), Detection::DEFAULT_CSO),
            ["camera_moves=1", "objects_move=0", "forward_buffer=0", "depth_check=1"]
        );
    }
}
