//! The wgpu side: the tracer and its two render paths (its GPU objects are made in
//! `tracer/setup.rs`, the device is in `context.rs`, reading
//! the images and the debug pixel back in `tracer/readback.rs`).

use super::buffers::{self, DEBUG_SIZE, PARAMS_SIZE, RqBlas, SceneData};
use super::error::GpuError;
use super::exact::Arithmetic;
use super::shader::{self, MAX_BVH_STACK, ShaderConfig, ShaderVariant};
use crate::platform::{Duration, Instant};
use crate::scene::camera::CameraRays;
use crate::scene::{Camera, Scene, Shape};
use crate::trace::PreparedScene;
use glam::Vec3;

pub use super::context::GpuContext;

mod gpu_trace;
mod readback;
mod setup;

pub use gpu_trace::PendingTrace;
pub use readback::linear_from;

use setup::{full_screen_pass, full_screen_pipeline};

/// How primary rays are made on the GPU.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum GpuPath {
    /// A full-screen triangle: the rasterizer interpolates the ray direction per pixel and the
    /// fragment shader traces it (the lecture notes' approach, docs/SOURCES.md).
    #[default]
    Fragment,
    /// A compute shader, one invocation per pixel, the ray computed as on the CPU.
    Compute,
}

impl GpuPath {
    /// The name, as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            GpuPath::Fragment => "fragment",
            GpuPath::Compute => "compute",
        }
    }
}

/// One GPU frame read back: linear RGB, like [`crate::render::RenderOutput::pixels`].
#[derive(Debug, Clone)]
pub struct GpuFrame {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Linear RGB, row-major from the top-left.
    pub pixels: Vec<Vec3>,
    /// The trace pass alone, from submit to completion.
    pub time: Duration,
    /// Which path made it.
    pub path: GpuPath,
}

/// The selected pixel traced on the GPU (the debug-pixel storage buffer, read back): what its
/// primary ray (first sample) hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelDebug {
    /// The pixel.
    pub pixel: [u32; 2],
    /// The object the primary ray hit (its id in the scene), if any.
    pub object: Option<u32>,
    /// The instance the hit lies on (its index in the scene's instances; `object` is then
    /// the prototype's primitive), if any.
    pub instance: Option<u32>,
    /// Distance along the primary ray (0 on a miss).
    pub t: f32,
    /// Triangle barycentric u (weight of P1); 0 for other shapes.
    pub u: f32,
    /// Triangle barycentric v (weight of P2); 0 for other shapes.
    pub v: f32,
    /// The sphere test's discriminant (b² − 4ac, or 4a·Δ′ for the stable method) when the hit
    /// object is a sphere.
    pub discriminant: Option<f32>,
    /// The hit test's key quantity whatever the shape: the sphere's discriminant, the triangle's
    /// determinant, the plane's denominator Q·n.
    pub aux: f32,
    /// BVH nodes whose boxes the primary ray tested (0 for brute force, and under hardware ray
    /// queries, where [`Self::hardware_traversal`] says so).
    pub nodes_visited: u32,
    /// The hardware walked its own BLAS/TLAS (ray queries): its node visits are not observable,
    /// so [`Self::nodes_visited`] is 0 and means nothing.
    pub hardware_traversal: bool,
    /// The pixel's linear colour (all samples).
    pub color: Vec3,
}

impl PixelDebug {
    /// The BVH node count in words: the number, or that the hardware walked its own BLAS/TLAS.
    pub fn nodes_text(&self) -> String {
        if self.hardware_traversal {
            "walked by the hardware (BLAS/TLAS): not observable".into()
        } else {
            self.nodes_visited.to_string()
        }
    }
}

/// Everything [`GpuTracer::build`] creates.
struct Built {
    params: wgpu::Buffer,
    scene_layout: wgpu::BindGroupLayout,
    scene_group: wgpu::BindGroup,
    output_layout: wgpu::BindGroupLayout,
    accum_layout: wgpu::BindGroupLayout,
    display_layout: wgpu::BindGroupLayout,
    /// The tracer's SPIR-V (or WGSL) module for the compute path's pipelines.
    compute_module: wgpu::ShaderModule,
    fragment_layout: wgpu::PipelineLayout,
    compute_layout: wgpu::PipelineLayout,
    display_pipeline: wgpu::RenderPipeline,
    debug: wgpu::Buffer,
    debug_readback: wgpu::Buffer,
    target: Target,
    acceleration: Option<(Vec<wgpu::Blas>, wgpu::Tlas)>,
    /// The compute pipelines run SPIR-V with `NoContraction` (passthrough).
    spirv: bool,
}

/// The per-size resources: the linear image, the display texture, their bind groups.
struct Target {
    width: u32,
    height: u32,
    linear: wgpu::Texture,
    linear_view: wgpu::TextureView,
    display: wgpu::Texture,
    display_view: wgpu::TextureView,
    output_group: wgpu::BindGroup,
    /// The running sums bound for the fragment path.
    accum_group: wgpu::BindGroup,
    display_group: wgpu::BindGroup,
    /// Each pixel's running sum, one `vec4f` a pixel (a progressive render's, on either path).
    _accum: wgpu::Buffer,
}

/// The tracer's own pipelines (the full-screen fragment path, the compute path, and the compute
/// shader that reads back one pixel's hit), made when first used.
struct Pipelines {
    compute_module: wgpu::ShaderModule,
    fragment_layout: wgpu::PipelineLayout,
    compute_layout: wgpu::PipelineLayout,
    fragment: Option<wgpu::RenderPipeline>,
    compute: Option<wgpu::ComputePipeline>,
    debug: Option<wgpu::ComputePipeline>,
}

/// One of [`Pipelines`].
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Kernel {
    /// The fragment path's `fs_main`.
    Fragment,
    /// The compute path's `cs_main`.
    Compute,
    /// `debug_main`: one pixel's hit into the debug buffer.
    Debug,
}

impl From<GpuPath> for Kernel {
    fn from(path: GpuPath) -> Kernel {
        match path {
            GpuPath::Fragment => Kernel::Fragment,
            GpuPath::Compute => Kernel::Compute,
        }
    }
}

/// The GPU tracer of one scene. See the [module documentation](super) for how the app uses it.
pub struct GpuTracer {
    ctx: GpuContext,
    scene: Scene,
    data: SceneData,
    use_bvh: bool,
    variant: ShaderVariant,
    wgsl: String,
    camera: Camera,
    debug_pixel: [u32; 2],
    /// The sample the trace shader traces (0 while rendering).
    /// The compute path's pass: its first sample and its count ([`GpuTracer::render_progressive`]).
    pass: [u32; 2],
    trace_sample: u32,
    /// The shader's configuration (the trace shader is this with `trace` on).
    config: ShaderConfig,
    /// The scene's bind group layout (group 0 of every pipeline).
    scene_layout: wgpu::BindGroupLayout,
    /// The top of the BVH the GPU walks, for GPU traces (none under ray queries or brute force).
    outline: Option<Vec<crate::record::OutlineNode>>,
    /// The trace shader's pipeline and its log's bind group layout, made on first use.
    trace_kernel: Option<(wgpu::ComputePipeline, wgpu::BindGroupLayout)>,
    /// The fragment path's trace pipeline, made on first use.
    trace_fragment: Option<wgpu::RenderPipeline>,
    params: wgpu::Buffer,
    scene_group: wgpu::BindGroup,
    output_layout: wgpu::BindGroupLayout,
    /// The fragment path's group 1: the running sums.
    accum_layout: wgpu::BindGroupLayout,
    display_layout: wgpu::BindGroupLayout,
    debug: wgpu::Buffer,
    debug_readback: wgpu::Buffer,
    /// The tracer's pipelines, each made on first use ([`Self::pipelines`]): a driver compiles
    /// the whole tracer for each (on lavapipe, seconds to tens of seconds each), and most uses
    /// need one of the three.
    pipelines: Pipelines,
    display_pipeline: wgpu::RenderPipeline,
    target: Target,
    /// The BLAS and TLAS when tracing with hardware ray queries (kept alive while bound).
    acceleration: Option<(Vec<wgpu::Blas>, wgpu::Tlas)>,
    /// The device's arithmetic (the probe's answers) the shader was generated for.
    arithmetic: Arithmetic,
    /// The compute path runs SPIR-V with `NoContraction` (passthrough).
    spirv: bool,
}

const LINEAR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// The format of [`GpuTracer::display_view`].
pub const DISPLAY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

impl GpuTracer {
    /// Uploads a prepared scene (flattening the BVH it was prepared with, when it uses one;
    /// hardware ray queries build their own structures), generates and compiles its shader
    /// (`variant`), and prepares both paths at the scene camera's size.
    pub fn new(
        ctx: GpuContext,
        prepared: &PreparedScene,
        variant: ShaderVariant,
    ) -> Result<Self, GpuError> {
        let scene = prepared.scene();
        // With instances: the TLAS and each prototype's BLAS the CPU built (the compute path
        // walks them as the CPU does; ray queries build the hardware's own).
        let two = match prepared.accel() {
            crate::accel::SceneAccel::TwoLevel(t) => Some(t.as_ref()),
            _ => None,
        };
        let finite = scene.objects.iter().any(|o| !o.shape.is_infinite());
        let ray_query = finite
            && ctx
                .device
                .features()
                .contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY);
        let bvh = if ray_query { None } else { prepared.bvh() };
        if let Some(b) = bvh
            && b.max_depth + 2 > MAX_BVH_STACK as usize
        {
            return Err(GpuError::Scene(format!(
                "the scene's BVH is {} levels deep; the GPU traversal's stack holds {MAX_BVH_STACK}",
                b.max_depth
            )));
        }
        if let Some(t) = two.filter(|_| !ray_query) {
            let deepest = t.blas.iter().map(|b| b.max_depth).max().unwrap_or(0);
            if deepest + 2 > MAX_BVH_STACK as usize {
                return Err(GpuError::Scene(format!(
                    "a prototype's BLAS is {deepest} levels deep; the GPU traversal's stack holds {MAX_BVH_STACK}"
                )));
            }
        }
        let (data, blas) = if ray_query {
            let (d, b) = buffers::ray_query_data(scene);
            (d, Some(b))
        } else {
            (buffers::scene_data(scene, bvh, two), None)
        };
        let mut config = ShaderConfig::variant(scene, bvh, variant);
        if let Some(t) = two {
            config = config.two_level(t);
            if config.instances && !ray_query && config.tlas_stack > MAX_BVH_STACK {
                return Err(GpuError::Scene(format!(
                    "the scene's TLAS is {} levels deep; the GPU traversal's stack holds {MAX_BVH_STACK}",
                    config.tlas_stack - 2
                )));
            }
        }
        if ray_query {
            config = config.with_ray_query();
        }
        let arithmetic = ctx.arithmetic()?;
        config.arith = arithmetic.config();
        let wgsl = shader::wgsl(&config);
        shader::validate(&wgsl).map_err(GpuError::Shader)?;
        let device = ctx.device.clone();
        let queue = ctx.queue.clone();
        let compute_module = ctx.checked("compiling the GPU tracer", || {
            ctx.compute_module(
                "raystep tracer (compute)",
                &wgsl,
                &[("cs_main", (8, 8, 1)), ("debug_main", (1, 1, 1))],
            )
        })??;
        let b = ctx.checked("creating the GPU tracer", || {
            Self::build(
                compute_module,
                &device,
                &queue,
                &data,
                blas.as_deref(),
                scene,
                scene.camera.width,
                scene.camera.height,
            )
        })?;
        let mut tracer = GpuTracer {
            ctx,
            scene: scene.clone(),
            data,
            use_bvh: bvh.is_some(),
            variant,
            wgsl,
            camera: scene.camera.clone(),
            debug_pixel: [0, 0],
            trace_sample: 0,
            pass: [0, scene.settings.spp.max(1)],
            config,
            scene_layout: b.scene_layout,
            outline: bvh.and_then(|t| {
                crate::accel::Accelerator::outline(t, crate::trace::tracer::BVH_OUTLINE_DEPTH)
            }),
            trace_kernel: None,
            trace_fragment: None,
            params: b.params,
            scene_group: b.scene_group,
            output_layout: b.output_layout,
            accum_layout: b.accum_layout,
            display_layout: b.display_layout,
            debug: b.debug,
            debug_readback: b.debug_readback,
            pipelines: Pipelines {
                compute_module: b.compute_module,
                fragment_layout: b.fragment_layout,
                compute_layout: b.compute_layout,
                fragment: None,
                compute: None,
                debug: None,
            },
            display_pipeline: b.display_pipeline,
            target: b.target,
            acceleration: b.acceleration,
            arithmetic,
            spirv: b.spirv,
        };
        tracer.write_params();
        Ok(tracer)
    }

    fn write_params(&mut self) {
        let cam = CameraRays::new(&self.camera);
        let bytes = buffers::params(
            &self.scene,
            &cam,
            &self.data,
            self.use_bvh,
            self.debug_pixel,
            self.trace_sample,
            self.pass,
        );
        self.ctx.queue.write_buffer(&self.params, 0, &bytes);
    }

    /// The generated (or full) WGSL this tracer runs, for the app to show.
    pub fn wgsl(&self) -> &str {
        &self.wgsl
    }

    /// Which shader variant this tracer runs.
    pub fn variant(&self) -> ShaderVariant {
        self.variant
    }

    /// The device this tracer runs on.
    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// The samples per pixel a frame traces (the scene's spp, at least 1).
    pub fn spp(&self) -> u32 {
        self.scene.settings.spp.max(1)
    }

    /// The camera frames are traced with.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Traces later frames with `camera` (its width and height set the image size; the textures
    /// are re-created when the size changes, so re-register [`Self::display_view`] then).
    /// The camera must be valid (as the scene loader checks: `from` ≠ `at`, `up` not along the
    /// view direction, size at least 1×1).
    pub fn set_camera(&mut self, camera: &Camera) -> Result<(), GpuError> {
        if camera.width == 0 || camera.height == 0 {
            return Err(GpuError::Scene(
                "the image size must be at least 1×1".into(),
            ));
        }
        self.camera = camera.clone();
        if (camera.width, camera.height) != (self.target.width, self.target.height) {
            let device = self.ctx.device.clone();
            let target = self.ctx.checked("resizing the GPU image", || {
                Self::make_target(
                    &device,
                    &self.output_layout,
                    &self.accum_layout,
                    &self.display_layout,
                    &self.debug,
                    camera.width,
                    camera.height,
                )
            })?;
            self.target = target;
        }
        self.write_params();
        Ok(())
    }

    /// The scene it traces.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The device's arithmetic: the probe's answers the shader was generated for.
    pub fn arithmetic(&self) -> &Arithmetic {
        &self.arithmetic
    }

    /// Whether `path` computes the CPU's f32 bits here: the compute path loaded as SPIR-V with
    /// `NoContraction`, on a device whose probe found every operation exact (or made exact).
    /// Never the fragment path: the rasterizer interpolates its ray directions.
    pub fn exact(&self, path: GpuPath) -> bool {
        path == GpuPath::Compute && self.spirv && self.arithmetic.probe.exact()
    }

    /// Whether the hardware walks its own BLAS/TLAS (ray queries). Its arithmetic may still be
    /// exact, but where two candidates lie at the same t it may report the other one than the
    /// CPU's traversal order picks (the leaky-edge scene's shared edges show it).
    pub fn hardware_ray_queries(&self) -> bool {
        self.acceleration.is_some()
    }

    /// What the adapter line says about the arithmetic of `path`.
    pub fn arithmetic_line(&self, path: GpuPath) -> String {
        let probe = self.arithmetic.probe.summary();
        match path {
            GpuPath::Fragment => format!(
                "arithmetic: inexact by design on the fragment path (the rasterizer interpolates \
                 the ray directions){} — probe: {probe}",
                if self.spirv {
                    "; the compute path is exact SPIR-V"
                } else {
                    ""
                }
            ),
            GpuPath::Compute if self.exact(path) => {
                format!("arithmetic: exact (SPIR-V, NoContraction) — probe: {probe}")
            }
            GpuPath::Compute if self.spirv => format!(
                "arithmetic: SPIR-V with NoContraction, but last bits may differ — probe: {probe}"
            ),
            GpuPath::Compute => format!(
                "arithmetic: as the driver compiles WGSL: last bits may differ — probe: {probe}"
            ),
        }
    }

    /// The line the GPU view shows: the adapter, its backend, which path runs, and its
    /// arithmetic ([`Self::arithmetic_line`]).
    pub fn adapter_line(&self, path: GpuPath) -> String {
        format!(
            "{} — {} ({} path, {} shader); hardware ray queries: {}; {}",
            self.ctx.adapter_name(),
            if self.acceleration.is_some() {
                "hardware ray queries (BLAS/TLAS), WGSL intersection and shading"
            } else {
                "software ray tracing in WGSL"
            },
            path.name(),
            match self.variant {
                ShaderVariant::Generated => "generated",
                ShaderVariant::Full => "full",
            },
            match (self.acceleration.is_some(), self.ctx.ray_query) {
                (true, _) => "in use",
                (false, true) => "offered by the adapter, not enabled on this device",
                (false, false) => "not offered by this adapter",
            },
            self.arithmetic_line(path)
        )
    }

    /// Records one frame into `encoder`: the trace pass by `path` into the linear image, then
    /// the sRGB encoding into [`Self::display_view`]. For the app: record into its own encoder
    /// (e.g. in an egui_wgpu callback's `prepare`); nothing here blocks but the first frame by
    /// `path`, which compiles its pipeline.
    pub fn encode(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        path: GpuPath,
    ) -> Result<(), GpuError> {
        self.pipeline(path.into())?;
        self.encode_trace(encoder, path);
        self.encode_display(encoder);
        Ok(())
    }

    /// Compiles the pipeline `path` traces with, which the first frame by `path` would otherwise
    /// do: for a caller that times its set-up apart from its frames (`raystep render --gpu`).
    pub fn prepare(&mut self, path: GpuPath) -> Result<(), GpuError> {
        self.pipeline(path.into())
    }

    /// Makes `kernel`'s pipeline if it is not made yet (inside an error scope: a driver's
    /// refusal is an error, not wgpu's panic).
    pub(crate) fn pipeline(&mut self, kernel: Kernel) -> Result<(), GpuError> {
        let p = &mut self.pipelines;
        let made = match kernel {
            Kernel::Fragment => p.fragment.is_some(),
            Kernel::Compute => p.compute.is_some(),
            Kernel::Debug => p.debug.is_some(),
        };
        if made {
            return Ok(());
        }
        let device = self.ctx.device.clone();
        let what = match kernel {
            Kernel::Fragment => "creating the GPU tracer's fragment pipeline",
            Kernel::Compute => "creating the GPU tracer's compute pipeline",
            Kernel::Debug => "creating the GPU tracer's debug-pixel pipeline",
        };
        let wgsl = &self.wgsl;
        self.ctx.checked(what, || match kernel {
            Kernel::Fragment => {
                let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some("raystep tracer"),
                    source: wgpu::ShaderSource::Wgsl(wgsl.as_str().into()),
                });
                p.fragment = Some(full_screen_pipeline(
                    &device,
                    "raystep fragment",
                    &p.fragment_layout,
                    &module,
                    "fs_main",
                    LINEAR_FORMAT,
                ));
            }
            // The compute path: SPIR-V with NoContraction where the device takes passthrough.
            Kernel::Compute | Kernel::Debug => {
                let entry = if kernel == Kernel::Compute {
                    "cs_main"
                } else {
                    "debug_main"
                };
                let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(&p.compute_layout),
                    module: &p.compute_module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                });
                if kernel == Kernel::Compute {
                    p.compute = Some(pipeline);
                } else {
                    p.debug = Some(pipeline);
                }
            }
        })
    }

    /// Records the trace pass; its pipeline must be made ([`Self::pipeline`]), else nothing is
    /// recorded.
    fn encode_trace(&self, encoder: &mut wgpu::CommandEncoder, path: GpuPath) {
        let t = &self.target;
        match path {
            GpuPath::Fragment => {
                if let Some(fragment) = &self.pipelines.fragment {
                    full_screen_pass(
                        encoder,
                        "raystep trace (fragment)",
                        &t.linear_view,
                        fragment,
                        &[&self.scene_group, &t.accum_group],
                    )
                }
            }
            GpuPath::Compute => {
                if let Some(compute) = &self.pipelines.compute {
                    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("raystep trace (compute)"),
                        timestamp_writes: None,
                    });
                    pass.set_pipeline(compute);
                    pass.set_bind_group(0, &self.scene_group, &[]);
                    pass.set_bind_group(1, &t.output_group, &[]);
                    pass.dispatch_workgroups(t.width.div_ceil(8), t.height.div_ceil(8), 1);
                }
            }
        }
    }

    fn encode_display(&self, encoder: &mut wgpu::CommandEncoder) {
        let t = &self.target;
        full_screen_pass(
            encoder,
            "raystep display",
            &t.display_view,
            &self.display_pipeline,
            &[&t.display_group],
        );
    }

    /// The sRGB-encoded image of the last frame, `Rgba8Unorm`: register it with
    /// `egui_wgpu::Renderer::register_native_texture(device, view, FilterMode::Nearest)`.
    pub fn display_view(&self) -> &wgpu::TextureView {
        &self.target.display_view
    }

    /// The display texture itself (`Rgba8Unorm`, `TEXTURE_BINDING | COPY_SRC`).
    pub fn display_texture(&self) -> &wgpu::Texture {
        &self.target.display
    }

    /// Traces one frame and waits for it: returns the trace pass's time from submit to
    /// completion. The display texture is updated too (untimed).
    pub fn trace(&mut self, path: GpuPath) -> Result<Duration, GpuError> {
        self.pipeline(path.into())?;
        let device = self.ctx.device.clone();
        let mut encoder = device.create_command_encoder(&Default::default());
        self.encode_trace(&mut encoder, path);
        let commands = encoder.finish();
        let time = self.ctx.checked("tracing a frame", || {
            let start = Instant::now();
            self.ctx.queue.submit([commands]);
            let waited = self.ctx.wait();
            (start.elapsed(), waited)
        })?;
        time.1?;
        let mut encoder = device.create_command_encoder(&Default::default());
        self.encode_display(&mut encoder);
        self.ctx.checked("encoding the display image", || {
            self.ctx.queue.submit([encoder.finish()]);
        })?;
        Ok(time.0)
    }

    /// The median frame time of `frames` frames after `warmup` untimed ones.
    pub fn time_frames(
        &mut self,
        path: GpuPath,
        warmup: usize,
        frames: usize,
    ) -> Result<Duration, GpuError> {
        for _ in 0..warmup {
            self.trace(path)?;
        }
        let mut times = vec![];
        for _ in 0..frames.max(1) {
            times.push(self.trace(path)?);
        }
        times.sort();
        Ok(times[times.len() / 2])
    }

    /// Renders by `path` progressively, as the CPU's `render_progressive` does: passes of 1, 1,
    /// 2, 4, … samples per pixel, each adding its samples to every pixel's running sum on the
    /// GPU in sample order (the compute shader, or on the fragment path the fragment shader,
    /// keeps the sums in a storage buffer), so the last pass's image is the one-shot
    /// [`Self::render`]'s by the same path, bit for bit; after each pass
    /// `after_pass(samples so far, image)` gets the running mean (sum / samples so far).
    pub fn render_progressive(
        &mut self,
        path: GpuPath,
        mut after_pass: impl FnMut(u32, &GpuFrame),
    ) -> Result<GpuFrame, GpuError> {
        let spp = self.scene.settings.spp.max(1);
        let ends = crate::render::passes::pass_ends(spp);
        let mut start = 0;
        let mut result = Err(GpuError::Scene("no pass".into()));
        for end in ends {
            self.pass = [start, end - start];
            self.write_params();
            result = self.render(path);
            match &result {
                Ok(frame) => after_pass(end, frame),
                Err(_) => break,
            }
            start = end;
        }
        self.pass = [0, spp];
        self.write_params();
        result
    }

    /// Traces samples `first .. first + count` of every pixel by `path`, adding them to the
    /// running sums the passes before left (`first` = 0 starts afresh), and shows the running
    /// mean in the display texture: one pass of [`Self::render_progressive`], for a caller that
    /// shows each pass as it comes (the app's GPU tab, a pass a frame). `count` is kept within
    /// the scene's spp; `first` past it traces all the samples ([`Self::trace`]).
    pub fn trace_pass(
        &mut self,
        path: GpuPath,
        first: u32,
        count: u32,
    ) -> Result<Duration, GpuError> {
        let spp = self.scene.settings.spp.max(1);
        if first >= spp {
            return self.trace(path);
        }
        self.pass = [first, count.clamp(1, spp - first)];
        self.write_params();
        let time = self.trace(path);
        self.pass = [0, spp];
        self.write_params();
        time
    }

    /// Traces one frame by `path` and reads the linear image back.
    pub fn render(&mut self, path: GpuPath) -> Result<GpuFrame, GpuError> {
        let time = self.trace(path)?;
        let pixels = self.read_linear()?;
        Ok(GpuFrame {
            width: self.target.width,
            height: self.target.height,
            pixels,
            time,
            path,
        })
    }
}
