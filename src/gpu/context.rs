//! The wgpu device raystep traces on: a headless one of its own, or the app's.

use super::exact::{self, Arithmetic, Probe};
use super::tracer::GpuError;
use eframe::wgpu;
use std::borrow::Cow;
use std::sync::{Arc, OnceLock};

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

/// Why the GPU tracer does not run in a browser: it waits for the GPU's answers (a readback, an
/// error scope), and a page's only thread cannot wait.
pub const NOT_IN_BROWSER: &str = "raystep's GPU tracer waits for the GPU's results, which a web page cannot do; \
     the GPU tab, `render --gpu` and `compare` run in the desktop app and on the command line";

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
}

impl GpuContext {
    /// Creates an instance, picks the default adapter and opens a device on it, with no window.
    pub fn headless() -> Result<GpuContext, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter =
            crate::platform::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                ..Default::default()
            }))
            .ok_or_else(|| GpuError::NoAdapter(NOT_IN_BROWSER.into()))?
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let ray_query = adapter
            .features()
            .contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY);
        // Both only where the adapter offers them.
        let wanted = wgpu::Features::EXPERIMENTAL_RAY_QUERY | wgpu::Features::PASSTHROUGH_SHADERS;
        let (device, queue) =
            crate::platform::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
                label: Some("raystep gpu"),
                required_features: adapter.features() & wanted,
                required_limits: adapter.limits(),
                experimental_features: if ray_query {
                    experimental_features()
                } else {
                    wgpu::ExperimentalFeatures::disabled()
                },
                ..Default::default()
            }))
            .ok_or_else(|| GpuError::Device(NOT_IN_BROWSER.into()))?
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
        }
    }

    /// The arithmetic the compute path runs with on this device: whether it is loaded as SPIR-V
    /// with `NoContraction`, and the probe's answers (run once, on first use: a tiny compute
    /// kernel on [`exact::probe_inputs`], loaded the same way as the tracer).
    pub fn arithmetic(&self) -> Result<Arithmetic, GpuError> {
        self.arithmetic.get_or_init(|| self.run_probe()).clone()
    }

    fn run_probe(&self) -> Result<Arithmetic, GpuError> {
        let inputs = exact::probe_inputs();
        let bytes: Vec<u8> = inputs
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let form = if self.passthrough {
            KernelForm::SpirvNoContraction
        } else {
            KernelForm::Wgsl
        };
        let outputs = inputs.len() * exact::PROBE_OUTPUTS;
        let out = self.run_kernel(&exact::probe_wgsl(), &bytes, outputs, form)?;
        let probe = Probe::from_outputs(&inputs, &out);
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
        Ok(self
            .read_mapped(&readback)?
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .take(outputs)
            .collect())
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
        format!("{}, {:?}, {kind}", self.info.name, self.info.backend)
    }

    /// Runs `f` inside a validation and an out-of-memory error scope; a captured error becomes
    /// a [`GpuError`] instead of wgpu's default panic.
    pub(crate) fn checked<T>(&self, what: &str, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = f();
        // In the browser an error scope's answer comes later (`None` here): the error then
        // reaches the console as an uncaptured one.
        let v = crate::platform::block_on(validation.pop()).flatten();
        let o = crate::platform::block_on(oom.pop()).flatten();
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
        let bytes = self.read_mapped(&buffer)?;
        let used = (w * texel) as usize;
        Ok(bytes
            .chunks(row as usize)
            .take(h as usize)
            .flat_map(|r| &r[..used])
            .copied()
            .collect())
    }

    /// Maps a `MAP_READ` buffer whose copy has been submitted, waits for the GPU, and returns
    /// its bytes (the buffer is unmapped again).
    pub(crate) fn read_mapped(&self, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        if crate::platform::IN_BROWSER {
            return Err(GpuError::Device(NOT_IN_BROWSER.into()));
        }
        let slice = buffer.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv()
            .map_err(|e| GpuError::Device(e.to_string()))?
            .map_err(|e| GpuError::Device(format!("mapping the readback buffer: {e}")))?;
        let bytes = slice
            .get_mapped_range()
            .map_err(|e| GpuError::Device(format!("reading the readback buffer: {e:?}")))?
            .to_vec();
        buffer.unmap();
        Ok(bytes)
    }

    /// Waits until the GPU has done what was submitted. In the browser a page cannot wait: the
    /// work is done in order anyway (the 3D view draws, then egui shows it), so this returns.
    pub(crate) fn wait(&self) -> Result<(), GpuError> {
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
