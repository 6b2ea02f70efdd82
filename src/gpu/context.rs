//! The wgpu device raystep traces on: a headless one of its own, or the app's.

use super::tracer::GpuError;
use eframe::wgpu;

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
}

impl GpuContext {
    /// Creates an instance, picks the default adapter and opens a device on it, with no window.
    pub fn headless() -> Result<GpuContext, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let ray_query = adapter
            .features()
            .contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY);
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("raystep gpu"),
            required_features: if ray_query {
                wgpu::Features::EXPERIMENTAL_RAY_QUERY
            } else {
                wgpu::Features::empty()
            },
            required_limits: adapter.limits(),
            experimental_features: if ray_query {
                experimental_features()
            } else {
                wgpu::ExperimentalFeatures::disabled()
            },
            ..Default::default()
        }))
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
        GpuContext {
            device,
            queue,
            info,
            ray_query: adapter_features.contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY),
        }
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
        let v = pollster::block_on(validation.pop());
        let o = pollster::block_on(oom.pop());
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

    pub(crate) fn wait(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .map(|_| ())
            .map_err(|e| GpuError::Device(e.to_string()))
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
