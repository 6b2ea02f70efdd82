//! Creating the tracer's GPU objects: the scene's buffers and bind groups, the pipelines of both
//! paths and the display pass, the per-size targets, and (for hardware ray queries) the BLAS and
//! TLAS.

use super::*;

/// Builds the acceleration structures for hardware ray queries, as the ray-tracing APIs' course
/// notes build them: one BLAS per bottom-level list of procedural primitives (`blas[0]` the
/// world's finite objects, then one per prototype in its object space; each primitive's box as
/// min xyz, max xyz in f32), and one TLAS of instances: the world's BLAS once with the identity
/// (custom index 0), then each scene instance of its prototype's BLAS with its matrix M (3 × 4
/// rows, as `VkTransformMatrixKHR`) and custom index i + 1, by which the shader finds its records.
fn build_acceleration(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    blas_data: &[RqBlas],
    scene: &Scene,
) -> (Vec<wgpu::Blas>, wgpu::Tlas) {
    use wgpu::util::DeviceExt;
    let mut built = vec![];
    for (k, b) in blas_data.iter().enumerate() {
        if b.count == 0 {
            built.push(None);
            continue;
        }
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("raystep aabbs"),
            contents: &b.aabbs,
            usage: wgpu::BufferUsages::BLAS_INPUT,
        });
        let size = wgpu::BlasAABBGeometrySizeDescriptor {
            primitive_count: b.count,
            flags: wgpu::AccelerationStructureGeometryFlags::OPAQUE,
        };
        let blas = device.create_blas(
            &wgpu::CreateBlasDescriptor {
                label: Some(if k == 0 {
                    "raystep world blas"
                } else {
                    "raystep prototype blas"
                }),
                flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
                update_mode: wgpu::AccelerationStructureUpdateMode::Build,
            },
            wgpu::BlasGeometrySizeDescriptors::AABBs {
                descriptors: vec![size.clone()],
            },
        );
        built.push(Some((blas, size, buffer)));
    }
    let world = built.first().and_then(Option::as_ref).is_some() as usize;
    let count = world + scene.instances.len();
    let mut tlas = device.create_tlas(&wgpu::CreateTlasDescriptor {
        label: Some("raystep tlas"),
        max_instances: count.max(1) as u32,
        flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
        update_mode: wgpu::AccelerationStructureUpdateMode::Build,
    });
    if let Some(Some((blas, _, _))) = built.first() {
        let identity = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        tlas[0] = Some(wgpu::TlasInstance::new(blas, identity, 0, 0xff));
    }
    for (i, inst) in scene.instances.iter().enumerate() {
        if let Some(Some((blas, _, _))) = built.get(inst.prototype as usize + 1) {
            let m = inst.to_world.0;
            let rows = [
                m[0][0], m[0][1], m[0][2], m[0][3], m[1][0], m[1][1], m[1][2], m[1][3], m[2][0],
                m[2][1], m[2][2], m[2][3],
            ];
            tlas[world + i] = Some(wgpu::TlasInstance::new(blas, rows, i as u32 + 1, 0xff));
        }
    }
    let entries: Vec<_> = built
        .iter()
        .flatten()
        .map(|(blas, size, buffer)| (blas, vec![size.clone()], buffer))
        .collect();
    let builds: Vec<_> = entries
        .iter()
        .map(|(blas, sizes, buffer)| wgpu::BlasBuildEntry {
            blas,
            geometry: wgpu::BlasGeometries::AabbGeometries(vec![wgpu::BlasAabbGeometry {
                size: &sizes[0],
                stride: wgpu::AABB_GEOMETRY_MIN_STRIDE,
                aabb_buffer: buffer,
                primitive_offset: 0,
            }]),
        })
        .collect();
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.build_acceleration_structures(builds.iter(), std::iter::once(&tlas));
    queue.submit([encoder.finish()]);
    (
        built.into_iter().flatten().map(|(b, _, _)| b).collect(),
        tlas,
    )
}

impl GpuTracer {
    /// Creates every GPU object. `aabbs`: the finite objects' boxes when tracing with hardware
    /// ray queries (then the BLAS and TLAS are built and bound at binding 7).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn build(
        (compute_module, spirv): (wgpu::ShaderModule, bool),
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        data: &SceneData,
        blas: Option<&[RqBlas]>,
        scene: &Scene,
        width: u32,
        height: u32,
    ) -> Built {
        use wgpu::util::DeviceExt;
        let storage = |label: &str, bytes: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("raystep params"),
            size: PARAMS_SIZE,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let scene_buffers = [
            storage("objects", &data.objects),
            storage("materials", &data.materials),
            storage("lights", &data.lights),
            storage("nodes", &data.nodes),
            storage("leaf objects", &data.leaf_objects),
            storage("planes", &data.planes),
        ];
        // The Monte Carlo data: binding 7, or 8 after the ray queries' TLAS (no gap: the
        // passthrough SPIR-V reads the bindings as numbered, and Vulkan's are packed).
        let mc_buffer = storage("monte carlo", &data.mc);
        let mc_binding = if blas.is_some() { 8 } else { 7 };
        let both = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE;
        let mut entries = vec![wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: both | wgpu::ShaderStages::VERTEX,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }];
        for b in 1..=6 {
            entries.push(wgpu::BindGroupLayoutEntry {
                binding: b,
                visibility: both,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            });
        }
        entries.push(wgpu::BindGroupLayoutEntry {
            binding: mc_binding,
            visibility: both,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: true },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        });
        let acceleration = blas.map(|b| build_acceleration(device, queue, b, scene));
        if acceleration.is_some() {
            entries.push(wgpu::BindGroupLayoutEntry {
                binding: 7,
                visibility: both,
                ty: wgpu::BindingType::AccelerationStructure {
                    vertex_return: false,
                },
                count: None,
            });
        }
        let scene_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("raystep scene"),
            entries: &entries,
        });
        let mut group_entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: params.as_entire_binding(),
        }];
        for (k, b) in scene_buffers.iter().enumerate() {
            group_entries.push(wgpu::BindGroupEntry {
                binding: k as u32 + 1,
                resource: b.as_entire_binding(),
            });
        }
        group_entries.push(wgpu::BindGroupEntry {
            binding: mc_binding,
            resource: mc_buffer.as_entire_binding(),
        });
        if let Some((_, tlas)) = &acceleration {
            group_entries.push(wgpu::BindGroupEntry {
                binding: 7,
                resource: wgpu::BindingResource::AccelerationStructure(tlas),
            });
        }
        let scene_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("raystep scene"),
            layout: &scene_layout,
            entries: &group_entries,
        });
        let output_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("raystep output"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: LINEAR_FORMAT,
                        view_dimension: wgpu::TextureViewDimension::D2,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: false },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: false },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        });
        // The fragment path's running sums (binding 2, as the compute path's `running`).
        let accum_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("raystep running sums (fragment)"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: false },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let display_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("raystep display"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let display_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("raystep display"),
            source: wgpu::ShaderSource::Wgsl(shader::DISPLAY_WGSL.into()),
        });
        let layout = |label: &str, groups: &[Option<&wgpu::BindGroupLayout>]| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: groups,
                immediate_size: 0,
            })
        };
        let fragment_layout = layout(
            "raystep fragment",
            &[Some(&scene_layout), Some(&accum_layout)],
        );
        let compute_layout = layout(
            "raystep compute",
            &[Some(&scene_layout), Some(&output_layout)],
        );
        let display_pipeline_layout = layout("raystep display", &[Some(&display_layout)]);
        let render_pipeline = |label: &str,
                               layout: &wgpu::PipelineLayout,
                               module: &wgpu::ShaderModule,
                               format: wgpu::TextureFormat| {
            full_screen_pipeline(device, label, layout, module, "fs_main", format)
        };
        let display_pipeline = render_pipeline(
            "raystep display",
            &display_pipeline_layout,
            &display_module,
            DISPLAY_FORMAT,
        );
        let debug = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("raystep debug pixel"),
            size: DEBUG_SIZE,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let debug_readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("raystep debug readback"),
            size: DEBUG_SIZE,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let target = Self::make_target(
            device,
            &output_layout,
            &accum_layout,
            &display_layout,
            &debug,
            width,
            height,
        );
        Built {
            params,
            scene_layout,
            scene_group,
            output_layout,
            accum_layout,
            display_layout,
            compute_module,
            fragment_layout,
            compute_layout,
            display_pipeline,
            debug,
            debug_readback,
            target,
            acceleration,
            spirv,
        }
    }

    pub(super) fn make_target(
        device: &wgpu::Device,
        output_layout: &wgpu::BindGroupLayout,
        accum_layout: &wgpu::BindGroupLayout,
        display_layout: &wgpu::BindGroupLayout,
        debug: &wgpu::Buffer,
        width: u32,
        height: u32,
    ) -> Target {
        let texture = |label: &str, format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        use wgpu::TextureUsages as U;
        let linear = texture(
            "raystep linear image",
            LINEAR_FORMAT,
            U::RENDER_ATTACHMENT | U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC,
        );
        let display = texture(
            "raystep display image",
            DISPLAY_FORMAT,
            U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC,
        );
        let linear_view = linear.create_view(&Default::default());
        let accum = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("raystep running sums"),
            size: u64::from(width) * u64::from(height) * 16,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let display_view = display.create_view(&Default::default());
        let output_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("raystep output"),
            layout: output_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&linear_view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: debug.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: accum.as_entire_binding(),
                },
            ],
        });
        let accum_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("raystep running sums (fragment)"),
            layout: accum_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 2,
                resource: accum.as_entire_binding(),
            }],
        });
        let display_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("raystep display"),
            layout: display_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&linear_view),
            }],
        });
        Target {
            width,
            height,
            linear,
            linear_view,
            display,
            display_view,
            output_group,
            accum_group,
            display_group,
            _accum: accum,
        }
    }
}

/// A render pipeline that draws the full-screen triangle of `module`'s `vs_main` with its
/// fragment entry point `fragment` into one target of `format`.
pub(super) fn full_screen_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    fragment: &str,
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(fragment),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// One full-screen triangle drawn into `view` (cleared to black) with `pipeline` and its bind
/// groups (0, 1, …): the fragment trace path, and the sRGB display pass.
pub(super) fn full_screen_pass(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
    pipeline: &wgpu::RenderPipeline,
    groups: &[&wgpu::BindGroup],
) {
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        ..Default::default()
    });
    pass.set_pipeline(pipeline);
    for (i, g) in groups.iter().enumerate() {
        pass.set_bind_group(i as u32, *g, &[]);
    }
    pass.draw(0..3, 0..1);
}
