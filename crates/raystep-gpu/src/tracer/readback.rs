//! Reading the GPU's results back: the linear and display images and the debug pixel.

use super::*;
use crate::context::{Readback, TextureReadback};

impl GpuTracer {
    /// Copies `texture` (the target's size, `texel` bytes per pixel) into a buffer and returns
    /// its rows tightly packed, row-major from the top-left.
    fn read_texture(&self, texture: &wgpu::Texture, texel: u32) -> Result<Vec<u8>, GpuError> {
        self.ctx
            .read_texture(texture, [self.target.width, self.target.height], texel)
    }

    pub(super) fn read_linear(&self) -> Result<Vec<Vec3>, GpuError> {
        Ok(linear_from(&self.read_texture(&self.target.linear, 16)?))
    }

    /// The last frame's linear image on its way back: [`TextureReadback::poll`], then
    /// [`linear_from`] (for a caller that cannot wait: the app in a web page).
    pub fn start_read_linear(&self) -> Result<TextureReadback, GpuError> {
        self.ctx.start_read_texture(
            &self.target.linear,
            [self.target.width, self.target.height],
            16,
        )
    }

    /// The display texture ([`Self::display_view`]) on its way back: for a caller whose screen
    /// is drawn by another device (the app in a web page shows it as an egui texture).
    pub fn start_read_display(&self) -> Result<TextureReadback, GpuError> {
        self.ctx.start_read_texture(
            &self.target.display,
            [self.target.width, self.target.height],
            4,
        )
    }

    /// Reads back the display texture ([`Self::display_view`]: sRGB-encoded RGBA8, encoded on
    /// the GPU), row-major from the top-left.
    pub fn read_display(&self) -> Result<Vec<[u8; 4]>, GpuError> {
        let bytes = self.read_texture(&self.target.display, 4)?;
        Ok(bytes
            .chunks_exact(4)
            .map(|p| [p[0], p[1], p[2], p[3]])
            .collect())
    }

    /// Traces pixel (x, y) alone on the GPU (compute, the CPU's exact primary ray) into the
    /// debug storage buffer and reads it back.
    pub fn debug_pixel(&mut self, x: u32, y: u32) -> Result<PixelDebug, GpuError> {
        let readback = self.start_debug_pixel(x, y)?;
        let bytes = self.ctx.finish_read(readback)?;
        Ok(self.debug_from([x, y], &bytes))
    }

    /// [`Self::debug_pixel`] without waiting: the debug buffer on its way back; give its bytes to
    /// [`Self::debug_from`]. One at a time: the debug buffer is the tracer's own.
    pub fn start_debug_pixel(&mut self, x: u32, y: u32) -> Result<Readback, GpuError> {
        if x >= self.target.width || y >= self.target.height {
            return Err(GpuError::Scene(format!(
                "pixel ({x}, {y}) is outside the {}×{} image",
                self.target.width, self.target.height
            )));
        }
        self.pipeline(super::Kernel::Debug)?;
        self.debug_pixel = [x, y];
        self.write_params();
        let device = self.ctx.device.clone();
        self.ctx.checked("tracing the debug pixel", || {
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                if let Some(debug) = &self.pipelines.debug {
                    pass.set_pipeline(debug);
                    pass.set_bind_group(0, &self.scene_group, &[]);
                    pass.set_bind_group(1, &self.target.output_group, &[]);
                    pass.dispatch_workgroups(1, 1, 1);
                }
            }
            encoder.copy_buffer_to_buffer(&self.debug, 0, &self.debug_readback, 0, DEBUG_SIZE);
            self.ctx.queue.submit([encoder.finish()]);
        })?;
        Ok(self.ctx.start_read(&self.debug_readback))
    }

    /// The debug buffer's bytes `b` (of [`Self::start_debug_pixel`] for `pixel`) read.
    pub fn debug_from(&self, pixel: [u32; 2], b: &[u8]) -> PixelDebug {
        let [x, y] = pixel;
        let u = |i: usize| u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
        let f = |i: usize| f32::from_bits(u(i));
        let object = (u(0) != u32::MAX).then_some(u(0));
        let is_sphere = object.is_some_and(|id| {
            matches!(
                self.scene.objects.get(id as usize).map(|o| o.shape),
                Some(Shape::Sphere { .. })
            )
        });
        PixelDebug {
            pixel: [x, y],
            object,
            instance: (object.is_some() && u(24) != raystep_core::scene::NO_INSTANCE)
                .then_some(u(24)),
            t: f(8),
            u: f(12),
            v: f(16),
            discriminant: is_sphere.then_some(f(20)),
            aux: f(20),
            nodes_visited: u(4),
            hardware_traversal: self.acceleration.is_some(),
            color: Vec3::new(f(32), f(36), f(40)),
        }
    }
}

/// A linear image's rows (RGBA32F, tightly packed) as colours.
pub fn linear_from(bytes: &[u8]) -> Vec<Vec3> {
    let f = |c: &[u8]| f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
    bytes
        .chunks_exact(16)
        .map(|p| Vec3::new(f(&p[0..4]), f(&p[4..8]), f(&p[8..12])))
        .collect()
}
