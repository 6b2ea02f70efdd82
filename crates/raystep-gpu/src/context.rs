//! The wgpu device raystep traces on: a headless one of its own, or the app's.

use super::error::GpuError;
use super::exact::{self, Arithmetic, Probe};
use std::borrow::Cow;
use std::sync::{Arc, Mutex, OnceLock};

/// How [`GpuContext::run_kernel`] loads a kernel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KernelForm {
    /// WGSL, compiled by wgpu and the driver as they see fit.
    Wgsl,
    /// SPIR-V with every float result decorated `NoContraction` (passthrough).
    SpirvNoContraction,
    /// The same, also asking for subnormals to be kept (`DenormPreserve`, passthrough).
    SpirvNoContractionDenormPreserve,
    /// The same SPIR-V without the decorations (passthrough): what contraction does.
    SpirvPlain,
}

/// What a call that waits for the GPU says in a web page, whose only thread cannot wait: there the
/// app asks for the GPU's answers ([`GpuContext::start_read`]) and takes them on a later frame
/// ([`Readback::poll`]).
pub const NOT_IN_BROWSER: &str = "a web page cannot wait for the GPU's answer: the app's GPU tab takes it on a \
     later frame, and `render --gpu` and `compare` run on the command line";

/// A buffer's bytes on their way back from the GPU: asked for by [`GpuContext::start_read`],
/// taken by [`Readback::poll`] once the GPU has written them. Natively
/// [`GpuContext::finish_read`] waits for them; a web page, whose only thread cannot wait, polls
/// on each frame until they have come (the browser maps the buffer between frames).
#[derive(Debug)]
pub struct Readback {
    buffer: wgpu::Buffer,
    /// Set by the map callback.
    mapped: Arc<Mutex<Option<Result<(), wgpu::BufferAsyncError>>>>,
    /// The answer was taken (the buffer is unmapped again).
    taken: bool,
}

impl Drop for Readback {
    /// A readback dropped before its answer was taken unmaps its buffer (cancelling the map if
    /// it is still on its way), so that the buffer can be mapped again.
    fn drop(&mut self) {
        if !self.taken {
            self.buffer.unmap();
        }
    }
}

impl Readback {
    /// The bytes, once the GPU has written them (the buffer is unmapped again); `None` while they
    /// are still on their way. Returns the answer once: a later call gives `None`.
    pub fn poll(&mut self) -> Option<Result<Vec<u8>, GpuError>> {
        if self.taken {
            return None;
        }
        let answer = self.mapped.lock().ok()?.take()?;
        self.taken = true;
        Some(match answer {
            Err(e) => Err(GpuError::Device(format!(
                "mapping the readback buffer: {e}"
            ))),
            Ok(()) => {
                let bytes = self
                    .buffer
                    .slice(..)
                    .get_mapped_range()
                    .map_err(|e| GpuError::Device(format!("reading the readback buffer: {e:?}")))
                    .map(|range| range.to_vec());
                self.buffer.unmap();
                bytes
            }
        })
    }
}

/// A texture's rows on their way back ([`GpuContext::start_read_texture`]).
#[derive(Debug)]
pub struct TextureReadback {
    /// The buffer's bytes, rows padded to wgpu's copy alignment.
    pub readback: Readback,
    size: [u32; 2],
    texel: u32,
    row: u32,
}

impl TextureReadback {
    /// The texture's size in pixels.
    pub fn size(&self) -> [u32; 2] {
        self.size
    }

    /// The rows tightly packed, row-major from the top-left, once they have come.
    pub fn poll(&mut self) -> Option<Result<Vec<u8>, GpuError>> {
        let bytes = self.readback.poll()?;
        let used = (self.size[0] * self.texel) as usize;
        Some(bytes.map(|b| {
            b.chunks(self.row as usize)
                .take(self.size[1] as usize)
                .flat_map(|r| &r[..used])
                .copied()
                .collect()
        }))
    }
}

/// A device to trace on: raystep's own (headless) or the app's (eframe's).
#[derive(Debug, Clone)]
pub struct GpuContext {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter's name, backend and type.
    pub info: wgpu::AdapterInfo,
    /// Whether the adapter offers hardware ray queries (`EXPERIMENTAL_RAY_QUERY`). They are used
    /// when the device was also created with the feature ([`GpuContext::headless`] asks for it
    /// where the adapter has it); otherwise the WGSL traversal runs.
    pub ray_query: bool,
    /// Whether the device accepts SPIR-V passthrough modules (`PASSTHROUGH_SHADERS`): then the
    /// compute path is loaded as SPIR-V with every float result decorated `NoContraction`.
    pub passthrough: bool,
    /// The probe's answers, computed on first use ([`GpuContext::arithmetic`]).
    arithmetic: Arc<OnceLock<Result<Arithmetic, GpuError>>>,
    /// The probe on its way back in a web page ([`GpuContext::arithmetic_nowait`]).
    probe: Arc<Mutex<Option<Readback>>>,
    /// Errors the browser reported after the call that caused them had returned (a web page
    /// cannot wait for an error scope: [`GpuContext::checked`] hears of them later).
    late_errors: Arc<Mutex<Vec<String>>>,
}

impl GpuContext {
    /// Creates an instance, picks the default adapter and opens a device on it, with no window.
    /// (In a web page, which cannot wait, an error: there [`GpuContext::open`] is awaited.)
    pub fn headless() -> Result<GpuContext, GpuError> {
        crate::platform::block_on(Self::open())
            .ok_or_else(|| GpuError::NoAdapter(NOT_IN_BROWSER.into()))?
    }

    /// [`GpuContext::headless`] as a future: natively any backend wgpu finds (the environment
    /// may choose, `WGPU_BACKEND`); in a web page WebGPU only (the page itself draws with
    /// WebGL2, and a WebGL context needs a canvas of its own).
    pub async fn open() -> Result<GpuContext, GpuError> {
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        if crate::platform::IN_BROWSER {
            descriptor.backends = wgpu::Backends::BROWSER_WEBGPU;
        }
        let instance = wgpu::Instance::new(descriptor);
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let ray_query = adapter
            .features()
            .contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY);
        // Both only where the adapter offers them.
        let wanted = wgpu::Features::EXPERIMENTAL_RAY_QUERY | wgpu::Features::PASSTHROUGH_SHADERS;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("raystep gpu"),
                required_features: adapter.features() & wanted,
                required_limits: adapter.limits(),
                experimental_features: if ray_query {
                    experimental_features()
                } else {
                    wgpu::ExperimentalFeatures::disabled()
                },
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::Device(e.to_string()))?;
        Ok(GpuContext::from_device(
            device,
            queue,
            adapter.get_info(),
            adapter.features(),
        ))
    }

    /// Wraps a device someone else created — the app's: with eframe's
    /// `egui_wgpu::RenderState` `rs`, `GpuContext::from_device(rs.device.clone(),
    /// rs.queue.clone(), rs.adapter.get_info(), rs.adapter.features())`.
    pub fn from_device(
        device: wgpu::Device,
        queue: wgpu::Queue,
        info: wgpu::AdapterInfo,
        adapter_features: wgpu::Features,
    ) -> GpuContext {
        let passthrough = device
            .features()
            .contains(wgpu::Features::PASSTHROUGH_SHADERS)
            && info.backend == wgpu::Backend::Vulkan;
        GpuContext {
            device,
            queue,
            info,
            ray_query: adapter_features.contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY),
            passthrough,
            arithmetic: Arc::default(),
            probe: Arc::default(),
            late_errors: Arc::default(),
        }
    }

    /// The arithmetic the compute path runs with on this device: whether it is loaded as SPIR-V
    /// with `NoContraction`, and the probe's answers (run once, on first use: a tiny compute
    /// kernel on [`exact::probe_inputs`], loaded the same way as the tracer).
    pub fn arithmetic(&self) -> Result<Arithmetic, GpuError> {
        self.arithmetic.get_or_init(|| self.run_probe()).clone()
    }

    /// The arithmetic without waiting (for a web page): `None` while the probe is on its way
    /// (it is started by the first call; ask again on a later frame). Natively the same as
    /// [`GpuContext::arithmetic`].
    pub fn arithmetic_nowait(&self) -> Option<Result<Arithmetic, GpuError>> {
        if !crate::platform::IN_BROWSER {
            return Some(self.arithmetic());
        }
        if let Some(known) = self.arithmetic.get() {
            return Some(known.clone());
        }
        let Ok(mut pending) = self.probe.lock() else {
            return Some(Err(GpuError::Device(
                "the probe's lock was poisoned".into(),
            )));
        };
        let answer = match pending.as_mut() {
            None => match self.start_probe() {
                Ok(r) => {
                    *pending = Some(r);
                    return None;
                }
                Err(e) => Err(e),
            },
            Some(r) => match r.poll()? {
                Ok(bytes) => Ok(self.probe_answers(&words(&bytes, probe_outputs()))),
                Err(e) => Err(e),
            },
        };
        *pending = None;
        Some(self.arithmetic.get_or_init(|| answer).clone())
    }

    /// The probe kernel on its way, loaded as the tracer will be.
    fn start_probe(&self) -> Result<Readback, GpuError> {
        let form = if self.passthrough {
            KernelForm::SpirvNoContraction
        } else {
            KernelForm::Wgsl
        };
        self.start_kernel(&exact::probe_wgsl(), &probe_bytes(), probe_outputs(), form)
    }

    /// The probe's answers from its output words (loaded as [`Self::start_probe`] loads it).
    fn probe_answers(&self, out: &[u32]) -> Arithmetic {
        Arithmetic {
            spirv: self.passthrough,
            float_controls: false,
            probe: Probe::from_outputs(&exact::probe_inputs(), out),
        }
    }

    fn run_probe(&self) -> Result<Arithmetic, GpuError> {
        let inputs = exact::probe_inputs();
        let bytes = probe_bytes();
        let outputs = probe_outputs();
        let first = self.start_probe()?;
        let probe = self
            .probe_answers(&words(&self.finish_read(first)?, outputs))
            .probe;
        // A driver that flushes subnormals may keep them when asked (SPIR-V float controls).
        // Asked only then, and kept only if nothing else came out worse.
        if self.passthrough && !probe.subnormals_kept() {
            let asked = KernelForm::SpirvNoContractionDenormPreserve;
            if let Ok(out) = self.run_kernel(&exact::probe_wgsl(), &bytes, outputs, asked) {
                let with = Probe::from_outputs(&inputs, &out);
                if with.subnormals_kept() && with.exact() >= probe.exact() {
                    return Ok(Arithmetic {
                        spirv: true,
                        float_controls: true,
                        probe: with,
                    });
                }
            }
        }
        Ok(Arithmetic {
            spirv: self.passthrough,
            float_controls: false,
            probe,
        })
    }

    /// Errors the browser reported after the calls that caused them had returned (taken: each is
    /// given once). Natively always empty: [`Self::checked`] waits for its error scopes.
    pub fn late_errors(&self) -> Vec<String> {
        self.late_errors
            .lock()
            .map(|mut e| std::mem::take(&mut *e))
            .unwrap_or_default()
    }

    /// Runs a small compute kernel once and returns its output words: the WGSL's entry point
    /// `main` (`@workgroup_size(64)`, one invocation per 16 input bytes) reads `inputs` at
    /// `@group(0) @binding(0)` (a read-only storage array) and writes `outputs` 32-bit words at
    /// `@binding(1)` (a read-write storage array). `form`: how the kernel is loaded — the probe
    /// and the `NoContraction` test use it.
    pub fn run_kernel(
        &self,
        wgsl: &str,
        inputs: &[u8],
        outputs: usize,
        form: KernelForm,
    ) -> Result<Vec<u32>, GpuError> {
        let readback = self.start_kernel(wgsl, inputs, outputs, form)?;
        Ok(words(&self.finish_read(readback)?, outputs))
    }

    /// [`Self::run_kernel`] without waiting: the output words' bytes on their way back.
    fn start_kernel(
        &self,
        wgsl: &str,
        inputs: &[u8],
        outputs: usize,
        form: KernelForm,
    ) -> Result<Readback, GpuError> {
        use wgpu::util::DeviceExt;
        let device = &self.device;
        let out_size = (outputs.max(1) * 4) as u64;
        let storage = |binding: u32, read_only: bool| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let module = match form {
            KernelForm::Wgsl => None,
            KernelForm::SpirvNoContraction
            | KernelForm::SpirvNoContractionDenormPreserve
            | KernelForm::SpirvPlain
                if !self.passthrough =>
            {
                return Err(GpuError::Device(
                    "this device does not take SPIR-V passthrough shaders".into(),
                ));
            }
            KernelForm::SpirvNoContraction => Some(
                exact::spirv_no_contraction(wgsl)
                    .map_err(GpuError::Shader)?
                    .0,
            ),
            KernelForm::SpirvNoContractionDenormPreserve => {
                let mut words = exact::spirv_no_contraction(wgsl)
                    .map_err(GpuError::Shader)?
                    .0;
                exact::preserve_denormals(&mut words).map_err(GpuError::Shader)?;
                Some(words)
            }
            KernelForm::SpirvPlain => Some(exact::spirv(wgsl).map_err(GpuError::Shader)?),
        };
        let readback = self.checked("running a compute kernel", || {
            let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("raystep kernel inputs"),
                contents: inputs,
                usage: wgpu::BufferUsages::STORAGE,
            });
            let output = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("raystep kernel outputs"),
                size: out_size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let readback = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("raystep kernel readback"),
                size: out_size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("raystep kernel"),
                entries: &[storage(0, true), storage(1, false)],
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("raystep kernel"),
                layout: &bgl,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: input.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: output.as_entire_binding(),
                    },
                ],
            });
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("raystep kernel"),
                bind_group_layouts: &[Some(&bgl)],
                immediate_size: 0,
            });
            let module = match module {
                Some(words) => {
                    passthrough_module(device, "raystep kernel", words, &[("main", (64, 1, 1))])
                }
                None => device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some("raystep kernel"),
                    source: wgpu::ShaderSource::Wgsl(wgsl.into()),
                }),
            };
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("raystep kernel"),
                layout: Some(&layout),
                module: &module,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            });
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.dispatch_workgroups((inputs.len() as u32).div_ceil(16 * 64).max(1), 1, 1);
            }
            encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, out_size);
            self.queue.submit([encoder.finish()]);
            readback
        })?;
        Ok(self.start_read(&readback))
    }

    /// A compute shader module from WGSL: compiled to SPIR-V with `NoContraction` on every
    /// float result and loaded through passthrough where the device accepts it (then `true`),
    /// otherwise handed to wgpu as WGSL. `entry_points`: the compute entry points and their
    /// workgroup sizes.
    pub(crate) fn compute_module(
        &self,
        label: &str,
        wgsl: &str,
        entry_points: &[(&str, (u32, u32, u32))],
    ) -> Result<(wgpu::ShaderModule, bool), GpuError> {
        if self.passthrough {
            let (mut words, _) = exact::spirv_no_contraction(wgsl).map_err(GpuError::Shader)?;
            // Subnormals kept where the probe found that asking for it works.
            if let Some(Ok(a)) = self.arithmetic.get()
                && a.float_controls
            {
                exact::preserve_denormals(&mut words).map_err(GpuError::Shader)?;
            }
            return Ok((
                passthrough_module(&self.device, label, words, entry_points),
                true,
            ));
        }
        let module = self
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(wgsl.into()),
            });
        Ok((module, false))
    }

    /// "llvmpipe (LLVM 15.0.6, 256 bits), Vulkan, CPU": the adapter, its backend and type.
    pub fn adapter_name(&self) -> String {
        let kind = match self.info.device_type {
            wgpu::DeviceType::Cpu => "CPU (software rasterizer)",
            wgpu::DeviceType::IntegratedGpu => "integrated GPU",
            wgpu::DeviceType::DiscreteGpu => "discrete GPU",
            wgpu::DeviceType::VirtualGpu => "virtual GPU",
            wgpu::DeviceType::Other => "other",
        };
        // A browser may withhold the adapter's name (WebGPU's `description`).
        let name = if self.info.name.is_empty() {
            "an adapter whose name the browser withholds"
        } else {
            &self.info.name
        };
        format!("{name}, {:?}, {kind}", self.info.backend)
    }

    /// Runs `f` inside a validation and an out-of-memory error scope; a captured error becomes
    /// a [`GpuError`] instead of wgpu's default panic.
    pub(crate) fn checked<T>(&self, what: &str, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = f();
        // Popped here, innermost first (a pop takes effect at once; its answer comes later).
        let (v, o) = (validation.pop(), oom.pop());
        if crate::platform::IN_BROWSER {
            // A page cannot wait for the scopes' answers: they come on the event loop, and an
            // error is kept for the GPU view to show ([`Self::late_errors`]).
            let (late, what) = (Arc::clone(&self.late_errors), what.to_string());
            crate::platform::browser::spawn_local(async move {
                let (v, o) = (v.await, o.await);
                if let (Some(e), Ok(mut late)) = (v.or(o), late.lock()) {
                    late.push(format!("{what}: {e}"));
                }
            });
            return Ok(value);
        }
        let v = crate::platform::block_on(v).flatten();
        let o = crate::platform::block_on(o).flatten();
        match v.or(o) {
            Some(e) => Err(GpuError::Device(format!("{what}: {e}"))),
            None => Ok(value),
        }
    }

    /// Copies `texture` (`size` pixels, `texel` bytes each) into a mappable buffer, waits, and
    /// returns its rows tightly packed, row-major from the top-left.
    pub(crate) fn read_texture(
        &self,
        texture: &wgpu::Texture,
        size: [u32; 2],
        texel: u32,
    ) -> Result<Vec<u8>, GpuError> {
        let mut r = self.start_read_texture(texture, size, texel)?;
        self.wait()?;
        r.poll().unwrap_or_else(|| Err(not_yet()))
    }

    /// [`Self::read_texture`] without waiting: the texture's rows on their way back.
    pub(crate) fn start_read_texture(
        &self,
        texture: &wgpu::Texture,
        size: [u32; 2],
        texel: u32,
    ) -> Result<TextureReadback, GpuError> {
        let [w, h] = size;
        let row = (w * texel).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let device = &self.device;
        let buffer = self.checked("reading the image back", || {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("raystep readback"),
                size: u64::from(row) * u64::from(h),
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut encoder = device.create_command_encoder(&Default::default());
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row),
                        rows_per_image: Some(h),
                    },
                },
                wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
            );
            self.queue.submit([encoder.finish()]);
            buffer
        })?;
        Ok(TextureReadback {
            readback: self.start_read(&buffer),
            size,
            texel,
            row,
        })
    }

    /// Asks for a `MAP_READ` buffer's bytes (its copy submitted): [`Readback::poll`] takes them
    /// once the GPU has written them.
    pub fn start_read(&self, buffer: &wgpu::Buffer) -> Readback {
        let mapped = Arc::new(Mutex::new(None));
        let answer = Arc::clone(&mapped);
        buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            if let Ok(mut a) = answer.lock() {
                *a = Some(r);
            }
        });
        Readback {
            buffer: buffer.clone(),
            mapped,
            taken: false,
        }
    }

    /// Waits for a readback's bytes (natively; in a web page an error unless they have come).
    pub fn finish_read(&self, mut readback: Readback) -> Result<Vec<u8>, GpuError> {
        self.wait()?;
        readback.poll().unwrap_or_else(|| Err(not_yet()))
    }

    /// Waits until the GPU has done what was submitted. In the browser a page cannot wait: the
    /// work is done in order anyway (the 3D view draws, then egui shows it), so this returns.
    pub fn wait(&self) -> Result<(), GpuError> {
        if crate::platform::IN_BROWSER {
            return Ok(());
        }
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .map(|_| ())
            .map_err(|e| GpuError::Device(e.to_string()))
    }
}

/// What a wait that a web page cannot make says.
fn not_yet() -> GpuError {
    GpuError::Device(NOT_IN_BROWSER.into())
}

/// Little-endian 32-bit words from bytes, the first `n`.
fn words(bytes: &[u8], n: usize) -> Vec<u32> {
    bytes
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .take(n)
        .collect()
}

/// The probe's inputs as the kernel reads them.
fn probe_bytes() -> Vec<u8> {
    exact::probe_inputs()
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect()
}

/// How many words the probe writes.
fn probe_outputs() -> usize {
    exact::probe_inputs().len() * exact::PROBE_OUTPUTS
}

/// Loads SPIR-V words as a shader module without wgpu's translation.
#[allow(unsafe_code)]
fn passthrough_module(
    device: &wgpu::Device,
    label: &str,
    words: Vec<u32>,
    entry_points: &[(&str, (u32, u32, u32))],
) -> wgpu::ShaderModule {
    let entry_points: Vec<wgpu::PassthroughShaderEntryPoint> = entry_points
        .iter()
        .map(
            |&(name, workgroup_size)| wgpu::PassthroughShaderEntryPoint {
                name: name.into(),
                workgroup_size,
            },
        )
        .collect();
    // SAFETY: wgpu's passthrough skips its own shader validation, so the words must be a valid
    // SPIR-V module for the pipelines built from it. They are: naga's SPIR-V writer emitted them
    // from WGSL that naga validated (`exact::spirv_no_contraction`), and the only change made
    // afterwards is `OpDecorate <result id> NoContraction` for arithmetic results, a decoration
    // that changes how results round, never what the module accesses. The pipelines that use it
    // get explicit layouts matching the WGSL's bindings.
    unsafe {
        device.create_shader_module_passthrough(wgpu::ShaderModuleDescriptorPassthrough {
            label: Some(label),
            entry_points: Cow::Owned(entry_points),
            spirv: Some(Cow::Owned(words)),
            ..Default::default()
        })
    }
}

/// wgpu's token for experimental features, needed to request `EXPERIMENTAL_RAY_QUERY`.
#[allow(unsafe_code)]
fn experimental_features() -> wgpu::ExperimentalFeatures {
    // SAFETY: `enabled()` is unsafe only because experimental features may have bugs in wgpu
    // (wgpu's words: "may be unsound"). It is called only when the adapter reports ray queries,
    // and the feature is used only through wgpu's own safe API (BLAS/TLAS builds and WGSL ray
    // queries); no raw pointers or driver handles are involved.
    unsafe { wgpu::ExperimentalFeatures::enabled() }
}
