//! The GPU view in the app: the open scene traced by [`crate::gpu::GpuTracer`] on eframe's own
//! wgpu device, beside the CPU render. Drag to orbit the camera, scroll to move closer (each
//! change re-traces at once); the adapter line says which adapter, backend and path run; the
//! selected pixel is traced into the GPU's debug buffer and shown next to the CPU trace's values;
//! the difference tab compares the two images pixel by pixel; the generated WGSL can be read.
//! "GPU trace" puts the GPU's own step trace of the selected pixel into the stepper, math panel
//! and diagrams ("CPU trace" brings the CPU's back), with the first divergence named and marked.
//!
//! Nothing here is needed: without a wgpu render state (the glow backend, a test harness
//! without `.wgpu()`) the tabs are left out and the app shows the CPU render alone.
//!
//! In a web page the same tabs run on WebGPU where the browser offers it; with WebGL2 they say
//! what they need.
//!
//! The tracer, its frame and the answers asked of the GPU are the app state's
//! ([`crate::state::gpu::GpuState`]), asked for with [`GpuCmd`]s; this view keeps only what the
//! screen needs: the tab shown, egui's textures of the images, and where the image was drawn.

mod tabs;

pub use tabs::{difference_tab, gpu_tab, tabs};

use super::state::gpu::{GpuCmd, GpuState, NO_WEBGPU};
use super::state::{AppState, Command, StepMove};
use crate::gpu::GpuPath;
use crate::record::Step;
use crate::record::number::num;
use crate::scene::Scene;
use crate::view3d::camera::Orbit;
use eframe::egui_wgpu::{self, wgpu};
use egui::{Color32, RichText, Sense};

/// Which view the central panel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CentralTab {
    /// The CPU render (click a pixel to trace it).
    #[default]
    Cpu,
    /// The GPU render.
    Gpu,
    /// CPU − GPU, pixel by pixel.
    Difference,
    /// The scene in 3D with the pixel's rays, and the editor.
    Scene3d,
}

/// What the GPU tabs keep between frames (part of [`super::panels::Panels`]): display caches
/// only.
#[derive(Default)]
pub struct GpuView {
    /// eframe's wgpu device (None: no GPU view).
    pub render_state: Option<egui_wgpu::RenderState>,
    /// The tab shown in the central panel.
    pub tab: CentralTab,
    /// Show the generated WGSL.
    pub show_wgsl: bool,
    /// Natively: egui's id of the tracer's display texture, and the key it was registered for
    /// ([`GpuState::display_key`]).
    texture: Option<(egui::TextureId, (usize, [u32; 2]))>,
    /// In a web page: the image read back, as an egui texture, and its generation.
    shown: Option<(u64, egui::TextureHandle)>,
    /// The difference image as an egui texture, and the comparison's generation.
    difference: Option<(u64, egui::TextureHandle)>,
    /// Where the GPU image was drawn last frame (screen rect in points).
    pub image_rect: Option<egui::Rect>,
}

impl GpuView {
    /// Whether the app has a GPU view at all.
    pub fn available(&self) -> bool {
        self.render_state.is_some()
    }

    /// The GPU image as egui shows it, once there is one. Natively the tracer's own display
    /// texture, registered with egui's renderer (again when the tracer or its size changes); in
    /// a web page, where the tracer's device is not the page's, the image read back after each
    /// traced frame (the last one read shows until the next comes).
    fn image(
        &mut self,
        ctx: &egui::Context,
        gpu: &GpuState,
    ) -> Option<(egui::TextureId, [u32; 2])> {
        if crate::platform::IN_BROWSER {
            let img = gpu.shown()?;
            let stale = self
                .shown
                .as_ref()
                .is_none_or(|(g, _)| *g != img.generation);
            if stale {
                let [w, h] = img.size;
                let image =
                    egui::ColorImage::from_rgba_unmultiplied([w as usize, h as usize], &img.rgba);
                match &mut self.shown {
                    Some((g, handle)) => {
                        handle.set(image, egui::TextureOptions::NEAREST);
                        *g = img.generation;
                    }
                    None => {
                        let handle =
                            ctx.load_texture("gpu-render", image, egui::TextureOptions::NEAREST);
                        self.shown = Some((img.generation, handle));
                    }
                }
            }
            return self.shown.as_ref().map(|(_, h)| {
                let [w, h2] = h.size();
                (h.id(), [w as u32, h2 as u32])
            });
        }
        let key = gpu.display_key()?;
        match self.texture {
            Some((id, k)) if k == key => Some((id, key.1)),
            old => {
                let rs = self.render_state.as_ref()?;
                let mut renderer = rs.renderer.write();
                if let Some((id, _)) = old {
                    renderer.free_texture(&id);
                }
                let id = renderer.register_native_texture(
                    &rs.device,
                    gpu.display_view()?,
                    wgpu::FilterMode::Nearest,
                );
                self.texture = Some((id, key));
                Some((id, key.1))
            }
        }
    }

    /// The difference image of the comparison numbered `generation`, as an egui texture (made
    /// once per comparison).
    fn difference_texture(
        &mut self,
        ctx: &egui::Context,
        d: &crate::gpu::Difference,
        generation: u64,
    ) -> &egui::TextureHandle {
        if self
            .difference
            .as_ref()
            .is_none_or(|(g, _)| *g != generation)
        {
            let img = egui::ColorImage::from_rgb(
                [d.image.width() as usize, d.image.height() as usize],
                d.image.as_raw(),
            );
            let tex = ctx.load_texture("gpu-difference", img, egui::TextureOptions::NEAREST);
            self.difference = Some((generation, tex));
        }
        &self.difference.as_ref().expect("made above").1
    }
}
