//! Drawing the 3D view with wgpu into a texture of its own: the app shows that texture (egui's
//! `register_native_texture`), `raystep view` reads it back into a PNG. One pass, 4× multisampled,
//! depth-tested: opaque triangles and spheres, then the lines, then the translucent surfaces
//! (depth-tested, not written).

use super::camera::ViewCamera;
use super::geometry::{Geometry, Line3, SphereInstance, TriVertex};
use crate::platform::{Duration, Instant};
use crate::{GpuContext, GpuError};
use glam::{Vec3, Vec4};
use wgpu::util::DeviceExt;

const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// WebGPU guarantees 4× multisampling for these two formats on every adapter.
const SAMPLES: u32 = 4;
/// How far lines are pulled towards the eye, as a fraction of their distance from it, so a ray
/// lying on a surface (a plane's grid, a normal's foot) is not hidden by it.
const LINE_DEPTH_BIAS: f32 = 2e-3;
/// The largest picture side drawn (larger requests are refused with a message).
pub const MAX_SIDE: u32 = 8192;
/// The largest tile side a picture is drawn in when it is read back
/// ([`crate::view3d::render_image`]): the GPU then holds one tile's multisampled colour and
/// depth (36 bytes a pixel, 144 MiB at 2048²) rather than the whole picture's (2.3 GiB at
/// 8192², in main memory on a software adapter such as lavapipe).
pub const TILE_SIDE: u32 = 2048;

/// The 3D view's pipelines and target, on one device.
pub struct Renderer {
    ctx: GpuContext,
    layout: wgpu::BindGroupLayout,
    opaque_tri: wgpu::RenderPipeline,
    clear_tri: wgpu::RenderPipeline,
    opaque_sphere: wgpu::RenderPipeline,
    clear_sphere: wgpu::RenderPipeline,
    line: wgpu::RenderPipeline,
    target: Option<Target>,
    /// The shared sphere mesh, for the segment count it was made with.
    sphere_mesh: Option<(u32, wgpu::Buffer, wgpu::Buffer, u32)>,
    /// How long the last [`Renderer::draw`] took, submit to completion.
    pub last_frame: Duration,
}

struct Target {
    size: [u32; 2],
    msaa: wgpu::TextureView,
    resolve: wgpu::Texture,
    resolve_view: wgpu::TextureView,
    depth: wgpu::TextureView,
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("size", &self.target.as_ref().map(|t| t.size))
            .finish_non_exhaustive()
    }
}

fn floats(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|f| f.to_le_bytes()).collect()
}

impl Renderer {
    /// Compiles the pipelines on `ctx`'s device.
    pub fn new(ctx: GpuContext) -> Result<Renderer, GpuError> {
        let device = ctx.device.clone();
        ctx.checked("creating the 3D view's pipelines", || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("raystep 3D view"),
                source: wgpu::ShaderSource::Wgsl(include_str!("view3d.wgsl").into()),
            });
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("raystep 3D view globals"),
                entries: &[wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                }],
            });
            let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("raystep 3D view"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            let tri_attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4];
            let tri_buffers = [Some(wgpu::VertexBufferLayout {
                array_stride: 40,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &tri_attrs,
            })];
            let unit_attrs = wgpu::vertex_attr_array![0 => Float32x3];
            let inst_attrs = wgpu::vertex_attr_array![1 => Float32x4, 2 => Float32x4, 3 => Float32x4, 4 => Float32x4, 5 => Float32x4];
            let sphere_buffers = [
                Some(wgpu::VertexBufferLayout {
                    array_stride: 12,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &unit_attrs,
                }),
                Some(wgpu::VertexBufferLayout {
                    array_stride: 80,
                    step_mode: wgpu::VertexStepMode::Instance,
                    attributes: &inst_attrs,
                }),
            ];
            let line_attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Float32];
            let line_buffers = [Some(wgpu::VertexBufferLayout {
                array_stride: 48,
                step_mode: wgpu::VertexStepMode::Instance,
                attributes: &line_attrs,
            })];
            let make = |vs: &str,
                        fs: &str,
                        buffers: &[Option<wgpu::VertexBufferLayout>],
                        write_depth: bool| {
                device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(vs),
                    layout: Some(&pl),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some(vs),
                        compilation_options: Default::default(),
                        buffers,
                    },
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some(fs),
                        compilation_options: Default::default(),
                        targets: &[Some(wgpu::ColorTargetState {
                            format: COLOR,
                            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                            write_mask: wgpu::ColorWrites::ALL,
                        })],
                    }),
                    primitive: wgpu::PrimitiveState {
                        topology: wgpu::PrimitiveTopology::TriangleList,
                        cull_mode: None,
                        ..Default::default()
                    },
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH,
                        depth_write_enabled: Some(write_depth),
                        depth_compare: Some(wgpu::CompareFunction::LessEqual),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: wgpu::MultisampleState {
                        count: SAMPLES,
                        ..Default::default()
                    },
                    multiview_mask: None,
                    cache: None,
                })
            };
            Renderer {
                opaque_tri: make("vs_tri", "fs_shaded", &tri_buffers, true),
                clear_tri: make("vs_tri", "fs_shaded", &tri_buffers, false),
                opaque_sphere: make("vs_sphere", "fs_shaded", &sphere_buffers, true),
                clear_sphere: make("vs_sphere", "fs_shaded", &sphere_buffers, false),
                line: make("vs_line", "fs_flat", &line_buffers, true),
                layout,
                ctx: ctx.clone(),
                target: None,
                sphere_mesh: None,
                last_frame: Duration::ZERO,
            }
        })
    }

    /// The device it draws on.
    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// The picture of the last draw (RGBA8, display values), for egui to show.
    pub fn view(&self) -> Option<&wgpu::TextureView> {
        self.target.as_ref().map(|t| &t.resolve_view)
    }

    /// The size of the last draw.
    pub fn size(&self) -> Option<[u32; 2]> {
        self.target.as_ref().map(|t| t.size)
    }

    fn ensure_target(&mut self, size: [u32; 2]) -> Result<bool, GpuError> {
        if self.target.as_ref().is_some_and(|t| t.size == size) {
            return Ok(false);
        }
        let device = self.ctx.device.clone();
        let target = self.ctx.checked("creating the 3D view's picture", || {
            let extent = wgpu::Extent3d {
                width: size[0],
                height: size[1],
                depth_or_array_layers: 1,
            };
            let tex = |label, format, samples, usage| {
                device.create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: extent,
                    mip_level_count: 1,
                    sample_count: samples,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage,
                    view_formats: &[],
                })
            };
            let msaa = tex(
                "3D view msaa",
                COLOR,
                SAMPLES,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            );
            let depth = tex(
                "3D view depth",
                DEPTH,
                SAMPLES,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            );
            let resolve = tex(
                "3D view",
                COLOR,
                1,
                wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
            );
            Target {
                size,
                msaa: msaa.create_view(&Default::default()),
                resolve_view: resolve.create_view(&Default::default()),
                resolve,
                depth: depth.create_view(&Default::default()),
            }
        })?;
        self.target = Some(target);
        Ok(true)
    }

    /// Draws `geometry` seen by `camera` into a `size` picture on `background`; blocks until the
    /// GPU is done. Returns whether the picture's texture was made anew (the app then registers
    /// it with egui again).
    pub fn draw(
        &mut self,
        geometry: &Geometry,
        camera: &ViewCamera,
        size: [u32; 2],
        background: [f32; 4],
    ) -> Result<bool, GpuError> {
        self.draw_region(geometry, camera, size, [0, 0, size[0], size[1]], background)
    }

    /// Draws only `region` = [x, y, width, height] (pixels from the top-left) of the `size`
    /// picture [`Renderer::draw`] would draw, into a picture of the region's size: the same
    /// pixels, lines as wide. [`crate::view3d::render_image`] draws large pictures tile by tile
    /// this way.
    pub fn draw_region(
        &mut self,
        geometry: &Geometry,
        camera: &ViewCamera,
        size: [u32; 2],
        region: [u32; 4],
        background: [f32; 4],
    ) -> Result<bool, GpuError> {
        if size[0] == 0 || size[1] == 0 || size[0] > MAX_SIDE || size[1] > MAX_SIDE {
            return Err(GpuError::Scene(format!(
                "the 3D view's picture must be 1 to {MAX_SIDE} pixels a side, not {}×{}",
                size[0], size[1]
            )));
        }
        let [x0, y0, w, h] = region;
        if w == 0 || h == 0 || x0.saturating_add(w) > size[0] || y0.saturating_add(h) > size[1] {
            return Err(GpuError::Scene(format!(
                "the region {w}×{h} at ({x0}, {y0}) is not inside the {}×{} picture",
                size[0], size[1]
            )));
        }
        let start = Instant::now();
        let new_target = self.ensure_target([w, h])?;
        let segments = sphere_segments(geometry.spheres.len() + geometry.clear_spheres.len());
        if self.sphere_mesh.as_ref().is_none_or(|m| m.0 != segments) {
            let (verts, idx) = unit_sphere(segments);
            let device = &self.ctx.device;
            let vb = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("3D view sphere"),
                contents: &floats(&verts),
                usage: wgpu::BufferUsages::VERTEX,
            });
            let ib = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("3D view sphere indices"),
                contents: &idx
                    .iter()
                    .flat_map(|i| i.to_le_bytes())
                    .collect::<Vec<u8>>(),
                usage: wgpu::BufferUsages::INDEX,
            });
            self.sphere_mesh = Some((segments, vb, ib, idx.len() as u32));
        }
        let lines = clip_lines(&geometry.lines, camera);
        let device = self.ctx.device.clone();
        let queue = self.ctx.queue.clone();
        let (Some(t), Some((_, svb, sib, scount))) = (&self.target, &self.sphere_mesh) else {
            return Err(GpuError::Device(
                "the 3D view's picture was not made".into(),
            ));
        };
        let vp = region_matrix(size, region) * camera.view_proj();
        let mut globals = vp.to_cols_array().to_vec();
        globals.extend([camera.eye.x, camera.eye.y, camera.eye.z, 1.0]);
        // The region's size: the shader sizes lines in its pixels, which are the picture's.
        globals.extend([w as f32, h as f32, LINE_DEPTH_BIAS, 0.0]);
        self.ctx.checked("drawing the 3D view", || {
            let ub = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("3D view globals"),
                contents: &floats(&globals),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("3D view globals"),
                layout: &self.layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: ub.as_entire_binding(),
                }],
            });
            let buffer = |label: &str, bytes: Vec<u8>| {
                (!bytes.is_empty()).then(|| {
                    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some(label),
                        contents: &bytes,
                        usage: wgpu::BufferUsages::VERTEX,
                    })
                })
            };
            let tris = buffer("3D view triangles", tri_bytes(&geometry.tris));
            let clear_tris = buffer("3D view clear triangles", tri_bytes(&geometry.clear_tris));
            let spheres = buffer("3D view spheres", sphere_bytes(&geometry.spheres));
            let clear_spheres = buffer(
                "3D view clear spheres",
                sphere_bytes(&geometry.clear_spheres),
            );
            let line_buf = buffer("3D view lines", line_bytes(&lines));
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let [r, g, b, a] = background.map(f64::from);
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("3D view"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &t.msaa,
                        depth_slice: None,
                        resolve_target: Some(&t.resolve_view),
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                            store: wgpu::StoreOp::Discard,
                        },
                    })],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &t.depth,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(1.0),
                            store: wgpu::StoreOp::Discard,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_bind_group(0, &bind, &[]);
                let draw_tris =
                    |pass: &mut wgpu::RenderPass, p, b: &Option<wgpu::Buffer>, n: usize| {
                        if let Some(b) = b {
                            pass.set_pipeline(p);
                            pass.set_vertex_buffer(0, b.slice(..));
                            pass.draw(0..n as u32, 0..1);
                        }
                    };
                let draw_spheres =
                    |pass: &mut wgpu::RenderPass, p, b: &Option<wgpu::Buffer>, n: usize| {
                        if let Some(b) = b {
                            pass.set_pipeline(p);
                            pass.set_vertex_buffer(0, svb.slice(..));
                            pass.set_vertex_buffer(1, b.slice(..));
                            pass.set_index_buffer(sib.slice(..), wgpu::IndexFormat::Uint32);
                            pass.draw_indexed(0..*scount, 0, 0..n as u32);
                        }
                    };
                draw_tris(&mut pass, &self.opaque_tri, &tris, geometry.tris.len());
                draw_spheres(
                    &mut pass,
                    &self.opaque_sphere,
                    &spheres,
                    geometry.spheres.len(),
                );
                if let Some(b) = &line_buf {
                    pass.set_pipeline(&self.line);
                    pass.set_vertex_buffer(0, b.slice(..));
                    pass.draw(0..6, 0..lines.len() as u32);
                }
                draw_spheres(
                    &mut pass,
                    &self.clear_sphere,
                    &clear_spheres,
                    geometry.clear_spheres.len(),
                );
                draw_tris(
                    &mut pass,
                    &self.clear_tri,
                    &clear_tris,
                    geometry.clear_tris.len(),
                );
            }
            queue.submit([encoder.finish()]);
        })?;
        self.ctx.wait()?;
        self.last_frame = start.elapsed();
        Ok(new_target)
    }

    /// Reads the last draw back: RGBA8 rows from the top-left.
    pub fn read(&self) -> Result<image::RgbaImage, GpuError> {
        let Some(t) = &self.target else {
            return Err(GpuError::Device("nothing was drawn yet".into()));
        };
        let pixels = self.ctx.read_texture(&t.resolve, t.size, 4)?;
        image::RgbaImage::from_raw(t.size[0], t.size[1], pixels)
            .ok_or_else(|| GpuError::Device("the 3D view's readback has the wrong size".into()))
    }
}

/// The clip-space transform that makes `region` = [x, y, width, height] of a `size` picture
/// fill the whole viewport: the region's normalized device coordinates are scaled and moved to
/// −1 … 1 (applied before the perspective divide, as a multiple of w). The whole picture gives
/// exactly the identity.
pub fn region_matrix(size: [u32; 2], region: [u32; 4]) -> glam::Mat4 {
    let [width, height] = size.map(|v| v as f32);
    let [x0, y0, w, h] = region.map(|v| v as f32);
    // The region's centre in NDC (x to the right, y up; pixel rows count down from the top).
    let cx = (2.0 * x0 + w) / width - 1.0;
    let cy = 1.0 - (2.0 * y0 + h) / height;
    let (sx, sy) = (width / w, height / h);
    glam::Mat4::from_cols(
        Vec4::new(sx, 0.0, 0.0, 0.0),
        Vec4::new(0.0, sy, 0.0, 0.0),
        Vec4::Z,
        Vec4::new(-sx * cx, -sy * cy, 0.0, 1.0),
    )
}

/// Segments around a sphere: fewer when there are many spheres (a sphereflake's 7,381 would
/// otherwise be millions of triangles on a software rasterizer).
fn sphere_segments(count: usize) -> u32 {
    match count {
        0..=200 => 40,
        201..=2_000 => 20,
        _ => 10,
    }
}

/// A unit sphere: positions (which are also the normals) and triangle indices.
fn unit_sphere(segments: u32) -> (Vec<f32>, Vec<u32>) {
    let rings = (segments / 2).max(3);
    let mut v = vec![];
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = std::f32::consts::TAU * s as f32 / segments as f32;
            v.extend([
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            ]);
        }
    }
    let mut idx = vec![];
    let row = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let a = r * row + s;
            let b = a + row;
            idx.extend([a, b, a + 1, a + 1, b, b + 1]);
        }
    }
    (v, idx)
}

fn tri_bytes(t: &[TriVertex]) -> Vec<u8> {
    let mut out = Vec::with_capacity(t.len() * 40);
    for v in t {
        for f in v.pos.iter().chain(&v.normal).chain(&v.color) {
            out.extend(f.to_le_bytes());
        }
    }
    out
}

fn sphere_bytes(s: &[SphereInstance]) -> Vec<u8> {
    let mut out = Vec::with_capacity(s.len() * 80);
    for i in s {
        for f in i.center.iter().chain([&i.radius]).chain(&i.color) {
            out.extend(f.to_le_bytes());
        }
        for a in &i.axes {
            for f in a.iter().chain([&0.0]) {
                out.extend(f.to_le_bytes());
            }
        }
    }
    out
}

fn line_bytes(l: &[Line3]) -> Vec<u8> {
    let mut out = Vec::with_capacity(l.len() * 48);
    for s in l {
        for f in
            s.a.iter()
                .chain(&s.b)
                .chain(&s.color)
                .chain([&s.width, &0.0])
        {
            out.extend(f.to_le_bytes());
        }
    }
    out
}

/// The lines cut to the part in front of the near plane (a line's quad is built from its
/// projected ends, which must be in front of the eye).
pub fn clip_lines(lines: &[Line3], camera: &ViewCamera) -> Vec<Line3> {
    let vp = camera.view_proj();
    let min_w = camera.near * 1.001;
    lines
        .iter()
        .filter_map(|l| {
            let (a, b) = (Vec3::from(l.a), Vec3::from(l.b));
            if !a.is_finite() || !b.is_finite() {
                return None;
            }
            let wa = (vp * Vec4::new(a.x, a.y, a.z, 1.0)).w;
            let wb = (vp * Vec4::new(b.x, b.y, b.z, 1.0)).w;
            match (wa >= min_w, wb >= min_w) {
                (true, true) => Some(*l),
                (false, false) => None,
                (ina, _) => {
                    let k = (min_w - wa) / (wb - wa);
                    let cut = a + (b - a) * k;
                    let mut out = *l;
                    if ina {
                        out.b = cut.to_array();
                    } else {
                        out.a = cut.to_array();
                    }
                    Some(out)
                }
            }
        })
        .collect()
}
