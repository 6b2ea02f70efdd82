//! The GPU's own step trace of one pixel: the trace shader (the tracer's shader with `TRACE` on,
//! compiled the same way: SPIR-V with `NoContraction` where the device takes it) run by one
//! invocation, its log read back and decoded ([`crate::trace_log`]).

use super::*;
use crate::context::Readback;
use crate::trace_log::{self, GpuTrace, LOG_HEADER};

/// A pixel's GPU trace on its way back ([`GpuTracer::start_trace_pixel`]): poll
/// [`PendingTrace::readback`], then [`GpuTracer::finish_trace`].
#[derive(Debug)]
pub struct PendingTrace {
    /// The log's bytes, on their way.
    pub readback: Readback,
    pixel: [u32; 2],
    sample: u32,
}

impl GpuTracer {
    /// Traces sample `sample` of pixel (x, y) on the GPU with the trace shader (the compute path:
    /// the CPU's primary ray) and returns its steps in raystep's trace format. `log_words`: the
    /// size of the log buffer in 32-bit words (see [`trace_log::DEFAULT_LOG_WORDS`]); a trace
    /// that outgrows it ends in a `truncated` step.
    pub fn trace_pixel(
        &mut self,
        x: u32,
        y: u32,
        sample: u32,
        log_words: usize,
    ) -> Result<GpuTrace, GpuError> {
        self.trace_pixel_on(GpuPath::Compute, x, y, sample, log_words)
    }

    /// [`GpuTracer::trace_pixel`] on either path. The fragment path draws the same full-screen
    /// triangle as its render, scissored to the pixel, so the rasterizer interpolates the same
    /// primary-ray direction (its screen position is not computed: NaN in the camera step); the
    /// fragment shader is compiled from WGSL, as the fragment path's is.
    pub fn trace_pixel_on(
        &mut self,
        path: GpuPath,
        x: u32,
        y: u32,
        sample: u32,
        log_words: usize,
    ) -> Result<GpuTrace, GpuError> {
        let pending = self.start_trace_pixel(path, x, y, sample, log_words)?;
        let bytes = self.ctx.finish_read(pending.readback)?;
        self.finish_trace([x, y], sample, &bytes)
    }

    /// [`Self::trace_pixel_on`] without waiting: the log on its way back (for a caller that
    /// cannot wait: the app in a web page).
    pub fn start_trace_pixel(
        &mut self,
        path: GpuPath,
        x: u32,
        y: u32,
        sample: u32,
        log_words: usize,
    ) -> Result<PendingTrace, GpuError> {
        if x >= self.camera.width || y >= self.camera.height {
            return Err(GpuError::Scene(format!(
                "pixel ({x}, {y}) is outside the {}×{} image",
                self.camera.width, self.camera.height
            )));
        }
        let spp = self.scene.settings.spp.max(1);
        if sample >= spp {
            return Err(GpuError::Scene(format!(
                "sample {sample} does not exist: the scene takes {spp} per pixel (0 to {})",
                spp - 1
            )));
        }
        let max_words = (self.ctx.device.limits().max_storage_buffer_binding_size / 4) as usize;
        let words = log_words.clamp(LOG_HEADER + 64, max_words.max(LOG_HEADER + 64));
        let (pipeline, log_layout) = match &self.trace_kernel {
            Some(k) => k.clone(),
            None => {
                let k = self.trace_kernel()?;
                self.trace_kernel = Some(k.clone());
                k
            }
        };
        let fragment = match path {
            GpuPath::Compute => None,
            GpuPath::Fragment => Some(match &self.trace_fragment {
                Some(f) => f.clone(),
                None => {
                    let f = self.trace_fragment_pipeline(&log_layout)?;
                    self.trace_fragment = Some(f.clone());
                    f
                }
            }),
        };
        let (width, height) = (self.camera.width, self.camera.height);
        let device = self.ctx.device.clone();
        let size = (words * 4) as u64;
        let (log, readback, group) = self.ctx.checked("creating the GPU trace's log", || {
            // Created zeroed (wgpu clears new buffers): no words used, not run out.
            let log = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("raystep trace log"),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let readback = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("raystep trace log readback"),
                size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("raystep trace log"),
                layout: &log_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: log.as_entire_binding(),
                }],
            });
            (log, readback, group)
        })?;
        let keep = self.debug_pixel;
        self.debug_pixel = [x, y];
        self.trace_sample = sample;
        self.write_params();
        let run = self
            .ctx
            .checked("tracing a pixel with the trace shader", || {
                let mut encoder = device.create_command_encoder(&Default::default());
                if let Some(fragment) = &fragment {
                    // A target of the image's size, so the viewport and the interpolation are
                    // the render's; only the pixel's fragment runs.
                    let target = device.create_texture(&wgpu::TextureDescriptor {
                        label: Some("raystep trace target"),
                        size: wgpu::Extent3d {
                            width,
                            height,
                            depth_or_array_layers: 1,
                        },
                        mip_level_count: 1,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format: LINEAR_FORMAT,
                        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                        view_formats: &[],
                    });
                    let view = target.create_view(&Default::default());
                    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some("raystep trace (fragment)"),
                        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                            view: &view,
                            depth_slice: None,
                            resolve_target: None,
                            ops: wgpu::Operations {
                                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                                store: wgpu::StoreOp::Store,
                            },
                        })],
                        ..Default::default()
                    });
                    pass.set_pipeline(fragment);
                    pass.set_bind_group(0, &self.scene_group, &[]);
                    pass.set_bind_group(1, &group, &[]);
                    pass.set_scissor_rect(x, y, 1, 1);
                    pass.draw(0..3, 0..1);
                } else {
                    let mut pass = encoder.begin_compute_pass(&Default::default());
                    pass.set_pipeline(&pipeline);
                    pass.set_bind_group(0, &self.scene_group, &[]);
                    pass.set_bind_group(1, &group, &[]);
                    pass.dispatch_workgroups(1, 1, 1);
                }
                encoder.copy_buffer_to_buffer(&log, 0, &readback, 0, size);
                self.ctx.queue.submit([encoder.finish()]);
            });
        self.debug_pixel = keep;
        self.trace_sample = 0;
        self.write_params();
        run?;
        Ok(PendingTrace {
            readback: self.ctx.start_read(&readback),
            pixel: [x, y],
            sample,
        })
    }

    /// The trace from a [`PendingTrace`]'s log bytes.
    pub fn finish_trace_of(
        &self,
        pending: &PendingTrace,
        bytes: &[u8],
    ) -> Result<GpuTrace, GpuError> {
        self.finish_trace(pending.pixel, pending.sample, bytes)
    }

    fn finish_trace(
        &self,
        [x, y]: [u32; 2],
        sample: u32,
        bytes: &[u8],
    ) -> Result<GpuTrace, GpuError> {
        let log: Vec<u32> = bytes
            .chunks_exact(4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
            .collect();
        trace_log::decode(&log, &self.scene, [x, y], sample, self.outline.clone())
            .map_err(|e| GpuError::Scene(format!("the GPU trace could not be read: {e}")))
    }

    /// Makes the trace shader's pipeline: the tracer's shader with `TRACE` on, compiled the same
    /// way (SPIR-V with `NoContraction` where the device takes it), and its log's layout.
    fn trace_kernel(&self) -> Result<(wgpu::ComputePipeline, wgpu::BindGroupLayout), GpuError> {
        let mut config = self.config;
        config.trace = true;
        let wgsl = shader::wgsl(&config);
        shader::validate(&wgsl).map_err(GpuError::Shader)?;
        let ctx = &self.ctx;
        let device = ctx.device.clone();
        let (module, _) = ctx.checked("compiling the GPU trace shader", || {
            ctx.compute_module("raystep trace shader", &wgsl, &[("trace_main", (1, 1, 1))])
        })??;
        ctx.checked("creating the GPU trace shader's pipeline", || {
            let log_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("raystep trace log"),
                entries: &[wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: false },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                }],
            });
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("raystep trace"),
                bind_group_layouts: &[Some(&self.scene_layout), Some(&log_layout)],
                immediate_size: 0,
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("trace_main"),
                layout: Some(&layout),
                module: &module,
                entry_point: Some("trace_main"),
                compilation_options: Default::default(),
                cache: None,
            });
            (pipeline, log_layout)
        })
    }

    /// The fragment path's trace pipeline: the trace shader's `vs_main` and `fs_trace`, compiled
    /// from WGSL as the fragment path's render is.
    fn trace_fragment_pipeline(
        &self,
        log_layout: &wgpu::BindGroupLayout,
    ) -> Result<wgpu::RenderPipeline, GpuError> {
        let mut config = self.config;
        config.trace = true;
        let wgsl = shader::wgsl(&config);
        let device = self.ctx.device.clone();
        self.ctx
            .checked("creating the GPU trace shader's fragment pipeline", || {
                let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some("raystep trace shader (fragment)"),
                    source: wgpu::ShaderSource::Wgsl(wgsl.into()),
                });
                let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some("raystep trace (fragment)"),
                    bind_group_layouts: &[Some(&self.scene_layout), Some(log_layout)],
                    immediate_size: 0,
                });
                full_screen_pipeline(
                    &device,
                    "raystep trace (fragment)",
                    &layout,
                    &module,
                    "fs_trace",
                    LINEAR_FORMAT,
                )
            })
    }

    /// Plants a divergence for tests: from now on the trace shader computes dot products as a
    /// chain of fused multiply-adds (what NVIDIA's driver makes of WGSL's `dot`), so its trace
    /// parts from the CPU's at the first dot product that rounds differently. The render
    /// shaders are not changed.
    pub fn plant_fused_dot(&mut self) {
        self.config.arith.fused_dot = true;
        self.trace_kernel = None;
        self.trace_fragment = None;
    }
}
