//! The headless GPU context: pick an adapter by backend and name, open a device with only the
//! features that adapter has, and keep its description for reports.

use std::collections::BTreeMap;
use std::sync::Mutex;

use anyhow::{Context, Result, anyhow, bail};
use fragkit_report::AdapterDescription;

use crate::encoder_clock::EncoderClock;

/// Which adapter to open. `None` fields fall back to `WGPU_BACKEND` / `WGPU_ADAPTER_NAME`,
/// the variables wgpu's own utilities honour, then to wgpu's default choice.
#[derive(Clone, Debug, Default)]
pub struct AdapterSelector {
    /// A backend name: `vulkan`/`vk`, `gl`/`gles`/`opengl`, `metal`, `dx12`.
    pub backend: Option<String>,
    /// A case-insensitive substring of the adapter name.
    pub adapter_name: Option<String>,
    /// A case-insensitive glob the adapter's driver info must match (`OpenGL ES 3.0*`): a
    /// configuration holds its adapter to the context or driver it promises, so a run that got
    /// another (an override the driver ignored) fails instead of testing something else.
    pub driver_info: Option<String>,
    /// Load the Vulkan validation layer (`--validation`): its errors fail the case they come in.
    pub validation: bool,
}

/// What the report says about the adapter `info` describes.
pub fn describe(info: &wgpu::AdapterInfo) -> AdapterDescription {
    AdapterDescription {
        name: info.name.clone(),
        backend: info.backend.to_str().to_owned(),
        driver: info.driver.clone(),
        driver_info: info.driver_info.clone(),
        device_type: format!("{:?}", info.device_type),
    }
}

/// An open device on one adapter.
pub struct Gpu {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub description: AdapterDescription,
    /// Times every encoder from [`Gpu::encoder`] to [`Gpu::submit`]; None without timestamps
    /// outside passes.
    clock: Option<Mutex<EncoderClock>>,
    /// Why the device was lost, once it is (set by wgpu's device-lost callback).
    lost: std::sync::Arc<Mutex<Option<String>>>,
    /// What each device-wide probe found on this device, by the probe's name, once it has run:
    /// many plans ask, and one render answers for the device ([`Gpu::probed_once`]).
    device_probes: Mutex<BTreeMap<&'static str, Option<String>>>,
    /// The shader files (paths under `shaders/`) modules were built from since
    /// [`Gpu::take_shader_paths`] last asked.
    shader_paths: Mutex<Vec<&'static str>>,
}

/// A command encoder whose GPU time counts towards the running case.
pub struct Encoder {
    inner: wgpu::CommandEncoder,
    clock_pair: Option<u32>,
}

impl std::ops::Deref for Encoder {
    type Target = wgpu::CommandEncoder;
    fn deref(&self) -> &wgpu::CommandEncoder {
        &self.inner
    }
}

impl std::ops::DerefMut for Encoder {
    fn deref_mut(&mut self) -> &mut wgpu::CommandEncoder {
        &mut self.inner
    }
}

const NO_ADAPTER_HELP: &str = "no GPU adapter found. Install a Vulkan driver; on Debian/Ubuntu without a GPU, \
     `apt-get install mesa-vulkan-drivers libvulkan1` provides lavapipe, Mesa's software rasteriser";

/// Parses a backend name strictly (wgpu's own parser skips unknown names with a warning).
pub fn parse_backend(name: &str) -> Result<wgpu::Backends> {
    match name.trim().to_ascii_lowercase().as_str() {
        "vulkan" | "vk" => Ok(wgpu::Backends::VULKAN),
        "gl" | "gles" | "opengl" => Ok(wgpu::Backends::GL),
        "metal" | "mtl" => Ok(wgpu::Backends::METAL),
        "dx12" | "d3d12" => Ok(wgpu::Backends::DX12),
        other => bail!("unknown backend {other:?}; expected one of vulkan, gl, metal, dx12"),
    }
}

/// The kit's instance for `backends`, with flags it sets itself — never the build profile's or
/// the environment's, so that a debug and a release build run alike whatever is installed:
/// - GL: the driver's debug output (VALIDATION, DEBUG): the kit's GL verdicts read the API errors
///   the driver raises (`diagnostics::gl_api_errors`), and nothing outside the driver loads;
/// - Vulkan (and the others): nothing, or with `validation` the Khronos validation layer and the
///   debug messenger that relays it (VALIDATION, DEBUG).
///
/// wgpu's indirect-call validation is off: it builds a compute pipeline, which a compute-free
/// adapter (softpipe's GL 3.3) does not have, so with it no device opens. The kit's only indirect
/// draws are the CPS levels' full-screen triangles, which bind no vertex buffer, and whose
/// arguments `cps.level_lighting` reads back and holds to their definition.
fn instance(backends: wgpu::Backends, validation: bool) -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = backends;
    let debug = backends == wgpu::Backends::GL || validation;
    desc.flags =
        if debug { wgpu::InstanceFlags::VALIDATION | wgpu::InstanceFlags::DEBUG } else { wgpu::InstanceFlags::empty() };
    wgpu::Instance::new(desc)
}

/// The adapters of `backends`, GL's from an instance of its own (its flags differ), Vulkan's and
/// the others' first.
fn enumerate(backends: wgpu::Backends, validation: bool) -> Vec<wgpu::Adapter> {
    let others = backends - wgpu::Backends::GL;
    let mut adapters = Vec::new();
    if !others.is_empty() {
        adapters.extend(pollster::block_on(instance(others, validation).enumerate_adapters(others)));
    }
    if backends.contains(wgpu::Backends::GL) {
        let gl = wgpu::Backends::GL;
        adapters.extend(pollster::block_on(instance(gl, validation).enumerate_adapters(gl)));
    }
    adapters
}

impl AdapterSelector {
    fn backends(&self) -> Result<wgpu::Backends> {
        match self.backend.clone().or_else(|| std::env::var("WGPU_BACKEND").ok()) {
            Some(name) => parse_backend(&name).context("choosing the backend (--backend / WGPU_BACKEND)"),
            None => Ok(wgpu::Backends::VULKAN | wgpu::Backends::GL | wgpu::Backends::METAL | wgpu::Backends::DX12),
        }
    }

    fn name_filter(&self) -> Option<String> {
        self.adapter_name.clone().or_else(|| std::env::var("WGPU_ADAPTER_NAME").ok()).filter(|name| !name.is_empty())
    }
}

/// Every adapter on every backend this build supports.
pub fn all_adapters() -> Vec<wgpu::Adapter> {
    let backends = wgpu::Backends::VULKAN | wgpu::Backends::GL | wgpu::Backends::METAL | wgpu::Backends::DX12;
    enumerate(backends, false)
}

/// Picks the adapter a selector names: by name among all adapters of its backends, or wgpu's
/// preferred one, where Vulkan wins over GL.
pub fn select_adapter(selector: &AdapterSelector) -> Result<wgpu::Adapter> {
    let backends = selector.backends()?;
    let candidates = enumerate(backends, selector.validation);
    if candidates.is_empty() {
        bail!("{NO_ADAPTER_HELP} (backends searched: {backends:?})");
    }
    let mut matching: Vec<wgpu::Adapter> = match selector.name_filter() {
        Some(filter) => {
            let needle = filter.to_lowercase();
            let names: Vec<String> = candidates.iter().map(|a| a.get_info().name).collect();
            let found: Vec<wgpu::Adapter> =
                candidates.into_iter().filter(|a| a.get_info().name.to_lowercase().contains(&needle)).collect();
            if found.is_empty() {
                bail!("no adapter name contains {filter:?} (--adapter / WGPU_ADAPTER_NAME); adapters found: {names:?}");
            }
            found
        }
        None => candidates,
    };
    if let Some(pattern) = &selector.driver_info {
        let glob = glob::Pattern::new(pattern).with_context(|| format!("--driver-info {pattern:?} is not a glob"))?;
        let options = glob::MatchOptions { case_sensitive: false, ..Default::default() };
        let found: Vec<String> =
            matching.iter().map(|a| format!("{} ({})", a.get_info().name, a.get_info().driver_info)).collect();
        matching.retain(|a| glob.matches_with(&a.get_info().driver_info, options));
        if matching.is_empty() {
            bail!("no adapter's driver info matches {pattern:?} (--driver-info); adapters found: {found:?}");
        }
    }
    if selector.validation && backends.contains(wgpu::Backends::VULKAN) && validation_layer_manifest().is_none() {
        // wgpu goes on without the layer, saying so only at debug level.
        bail!(
            "--validation: no manifest of the Vulkan validation layer ({VALIDATION_LAYER}) in the loader's layer folders; on Debian: apt-get install vulkan-validationlayers"
        );
    }
    // Prefer real hardware, then Vulkan over GL: the order wgpu's own default follows.
    matching.sort_by_key(|a| {
        let info = a.get_info();
        let hardware = !matches!(info.device_type, wgpu::DeviceType::Cpu | wgpu::DeviceType::Other);
        let vulkan = info.backend == wgpu::Backend::Vulkan;
        (!hardware, !vulkan)
    });
    Ok(matching.remove(0))
}

/// The Khronos validation layer, as its manifest names it.
const VALIDATION_LAYER: &str = "VK_LAYER_KHRONOS_validation";

/// The validation layer's manifest among the folders the Vulkan loader reads explicit layers from
/// on Linux (`VK_LAYER_PATH` alone where set, else `VK_ADD_LAYER_PATH`, the XDG config and data
/// folders and /etc), if one is there.
pub fn validation_layer_manifest() -> Option<std::path::PathBuf> {
    let folders_of = |variable: &str, default: &str| -> Vec<std::path::PathBuf> {
        let value = std::env::var(variable).unwrap_or_else(|_| default.to_owned());
        value.split(':').filter(|f| !f.is_empty()).map(std::path::PathBuf::from).collect()
    };
    let explicit = |base: std::path::PathBuf| base.join("vulkan/explicit_layer.d");
    let folders: Vec<std::path::PathBuf> = match std::env::var("VK_LAYER_PATH") {
        Ok(paths) => paths.split(':').map(std::path::PathBuf::from).collect(),
        Err(_) => {
            let home_data = std::env::var("XDG_DATA_HOME")
                .map(std::path::PathBuf::from)
                .or_else(|_| std::env::var("HOME").map(|home| std::path::Path::new(&home).join(".local/share")));
            folders_of("VK_ADD_LAYER_PATH", "")
                .into_iter()
                .chain(folders_of("XDG_CONFIG_DIRS", "/etc/xdg").into_iter().map(explicit))
                .chain(std::iter::once(explicit("/etc".into())))
                .chain(home_data.into_iter().map(explicit))
                .chain(folders_of("XDG_DATA_DIRS", "/usr/local/share:/usr/share").into_iter().map(explicit))
                .collect()
        }
    };
    folders
        .into_iter()
        .flat_map(|folder| std::fs::read_dir(folder).into_iter().flatten().flatten())
        .map(|entry| entry.path())
        .find(|path| {
            path.extension().is_some_and(|e| e == "json")
                && std::fs::read_to_string(path).is_ok_and(|text| text.contains(VALIDATION_LAYER))
        })
}

/// The optional features the kit uses when an adapter offers them; a case that needs a missing
/// one reports NotSupported.
pub const WANTED_FEATURES: wgpu::Features = wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES
    .union(wgpu::Features::TIMESTAMP_QUERY)
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    .union(wgpu::Features::SHADER_EARLY_DEPTH_TEST);

impl Gpu {
    /// Opens the adapter a selector names.
    pub fn open(selector: &AdapterSelector) -> Result<Self> {
        Self::from_adapter(select_adapter(selector)?)
    }

    pub fn from_adapter(adapter: wgpu::Adapter) -> Result<Self> {
        let info = adapter.get_info();
        let required_features = adapter.features() & WANTED_FEATURES;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("fragkit device"),
            required_features,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| anyhow!("{e}"))
        .with_context(|| format!("opening a device on {} ({})", info.name, info.backend))?;
        // Errors outside a case's error scope must not abort the process: log them, the
        // harness captures the ones that matter per case.
        device.on_uncaptured_error(std::sync::Arc::new(|error| log::error!("uncaptured wgpu error: {error}")));
        let lost = std::sync::Arc::new(Mutex::new(None));
        let lost_in_callback = lost.clone();
        device.set_device_lost_callback(move |reason, message| {
            *lost_in_callback.lock().unwrap_or_else(|e| e.into_inner()) =
                Some(if message.is_empty() { format!("{reason:?}") } else { format!("{reason:?}: {message}") });
        });
        let clock = device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
            .then(|| Mutex::new(EncoderClock::new(&device, &queue)));
        Ok(Self {
            description: describe(&info),
            adapter,
            device,
            queue,
            clock,
            lost,
            device_probes: Mutex::new(BTreeMap::new()),
            shader_paths: Mutex::new(Vec::new()),
        })
    }

    /// Notes that a module is being built from the shader file at `path` (the shader table's
    /// modules call it).
    pub(crate) fn built_from(&self, path: &'static str) {
        let mut paths = self.shader_paths.lock().unwrap_or_else(|e| e.into_inner());
        if !paths.contains(&path) {
            paths.push(path);
        }
    }

    /// The shader files modules were built from since the last call, in the order first built:
    /// what a case's pipelines came from.
    pub fn take_shader_paths(&self) -> Vec<&'static str> {
        std::mem::take(&mut *self.shader_paths.lock().unwrap_or_else(|e| e.into_inner()))
    }

    /// Why the device was lost, or None while it works. Polls first, so that a loss the driver
    /// has reported is seen.
    pub fn lost(&self) -> Option<String> {
        let _ = self.device.poll(wgpu::PollType::Poll);
        self.lost.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// A fresh device on the same adapter (after a loss).
    pub fn reopen(&self) -> Result<Self> {
        Self::from_adapter(self.adapter.clone())
    }

    pub fn has(&self, features: wgpu::Features) -> bool {
        self.device.features().contains(features)
    }

    /// The finding of the device-wide probe `name` (None: no problem), measured on first use
    /// and kept for the device, with the GL errors the probe met appended as its evidence.
    pub fn probed_once(
        &self,
        name: &'static str,
        measure: impl FnOnce(&Self) -> Result<Option<String>>,
    ) -> Result<Option<String>> {
        let probes = || self.device_probes.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(known) = probes().get(name) {
            return Ok(known.clone());
        }
        // Measured without the lock: a probe may ask another.
        let (problem, raised) = crate::diagnostics::probing(|| measure(self));
        let problem = problem?.map(|problem| crate::diagnostics::with_raised(problem, &raised));
        Ok(probes().entry(name).or_insert(problem).clone())
    }

    /// Waits for all submitted work.
    pub fn wait(&self) -> Result<()> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| anyhow!("waiting for the GPU: {e}"))
    }
}

impl Gpu {
    /// Runs `body` inside validation, out-of-memory and internal error scopes and turns any
    /// error they caught into an `Err` naming `what`.
    pub fn scoped<T>(&self, what: &str, body: impl FnOnce() -> Result<T>) -> Result<T> {
        let internal = self.device.push_error_scope(wgpu::ErrorFilter::Internal);
        let memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let result = body();
        let errors = [validation.pop(), memory.pop(), internal.pop()].map(pollster::block_on);
        let mut errors = errors.into_iter().flatten();
        if let Some(error) = errors.next() {
            // A pipeline the driver's compiler refused is an internal error, and each later use
            // of it a validation error: the cause follows the first symptom.
            let causes: Vec<String> = errors.map(|e| format!("\n(also: {e})")).collect();
            bail!("wgpu error during {what}: {error}{}", causes.concat());
        }
        result
    }

    /// A 2D texture with one mip level.
    pub fn texture(
        &self,
        label: &str,
        (width, height): (u32, u32),
        format: wgpu::TextureFormat,
        samples: u32,
        usage: wgpu::TextureUsages,
    ) -> wgpu::Texture {
        self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    }

    /// A command encoder whose GPU time counts towards the running case (submit it with
    /// [`Gpu::submit`]).
    pub fn encoder(&self, label: &str) -> Encoder {
        let mut inner = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
        let clock_pair = self
            .clock
            .as_ref()
            .and_then(|clock| clock.lock().expect("clock lock").start(&self.device, &self.queue, &mut inner));
        Encoder { inner, clock_pair }
    }

    /// Submits an encoder made by [`Gpu::encoder`], closing its clock span.
    pub fn submit(&self, mut encoder: Encoder) -> wgpu::SubmissionIndex {
        if let (Some(clock), Some(pair)) = (&self.clock, encoder.clock_pair) {
            clock.lock().expect("clock lock").stop(&mut encoder.inner, pair);
        }
        self.queue.submit([encoder.inner.finish()])
    }

    /// GPU time (ms) of the encoders submitted since the last call; None without timestamps.
    pub fn take_gpu_ms(&self) -> Result<Option<f64>> {
        match &self.clock {
            Some(clock) => Ok(Some(clock.lock().expect("clock lock").take_ms(&self.device, &self.queue)?)),
            None => Ok(None),
        }
    }
}
