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

use super::state::{AppState, Command, StepMove};
use crate::explain::diff::compare;
use crate::gpu::trace_log::DEFAULT_LOG_WORDS;
use crate::gpu::{Difference, GpuContext, GpuPath, GpuTracer, PixelDebug, ShaderVariant};
use crate::record::Step;
use crate::record::Tolerance;
use crate::record::number::num;
use crate::scene::Scene;
use crate::trace::PreparedScene;
use crate::view3d::camera::Orbit;
use eframe::egui_wgpu::{self, wgpu};
use egui::{Color32, RichText, Sense};
use std::sync::Arc;
use std::time::Duration;

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

/// A comparison and its image on the GPU.
type Compared = (Difference, egui::TextureHandle);

/// What the GPU traced for the scene as the app prepared it.
struct Traced {
    /// The prepared scene it was made for (pointer identity).
    key: usize,
    tracer: GpuTracer,
    /// egui's id of the tracer's display texture, and the size it was registered at.
    texture: Option<(egui::TextureId, [u32; 2])>,
    /// The orbit the last frame was traced with, how long the trace pass took, and the samples
    /// per pixel the image holds so far (a Monte Carlo scene comes in passes of 1, 1, 2, 4, …
    /// samples, one a frame, on either path).
    frame: Option<(Orbit, GpuPath, Duration, u32)>,
    /// The debug pixel of (pixel, path), at the scene camera.
    pick: Option<([u32; 2], Result<PixelDebug, String>)>,
    /// The comparison with the CPU render, for (the render it was made against, the GPU path).
    diff: Option<((u64, GpuPath), Result<Compared, String>)>,
    /// The GPU's own trace of a pixel.
    gpu_trace: Option<GpuTraced>,
}

/// The GPU's own trace of (pixel, sample), and how it compares with the CPU's.
struct GpuTraced {
    pixel: [u32; 2],
    sample: u32,
    path: GpuPath,
    result: Result<GpuTraceShown, String>,
}

struct GpuTraceShown {
    trace: Arc<crate::record::Trace>,
    /// "the traces are equal: …" or "first divergence: step K (…)".
    verdict: String,
    /// The first step where it parts from the CPU's trace.
    divergence: Option<usize>,
    /// The log ran out.
    truncated: bool,
}

/// The GPU view's state (part of [`super::panels::Panels`]).
pub struct GpuView {
    /// eframe's wgpu device (None: no GPU view).
    pub render_state: Option<egui_wgpu::RenderState>,
    /// The tab shown in the central panel.
    pub tab: CentralTab,
    /// Fragment (rasterizer-interpolated primary rays) or compute.
    pub path: GpuPath,
    /// The camera orbit of the GPU view ([`Orbit::move_camera`]; [`Orbit::IDENTITY`] at first).
    pub orbit: Orbit,
    /// Show the generated WGSL.
    pub show_wgsl: bool,
    traced: Option<Traced>,
    /// Why the GPU view could not be made for the current scene.
    pub error: Option<(usize, String)>,
    /// Where the GPU image was drawn last frame (screen rect in points).
    pub image_rect: Option<egui::Rect>,
}

impl Default for GpuView {
    fn default() -> Self {
        GpuView {
            render_state: None,
            tab: CentralTab::default(),
            path: GpuPath::default(),
            orbit: Orbit::IDENTITY,
            show_wgsl: false,
            traced: None,
            error: None,
            image_rect: None,
        }
    }
}

impl GpuView {
    /// Whether the app has a GPU view at all.
    pub fn available(&self) -> bool {
        self.render_state.is_some()
    }

    /// The last GPU frame's trace time and path.
    pub fn frame_time(&self) -> Option<(GpuPath, Duration)> {
        let t = self.traced.as_ref()?;
        t.frame.map(|(_, p, d, _)| (p, d))
    }

    /// The samples per pixel the GPU image holds so far, and the scene's spp.
    pub fn samples_so_far(&self) -> Option<(u32, u32)> {
        let t = self.traced.as_ref()?;
        let spp = t.tracer.spp();
        t.frame.map(|(.., done)| (done, spp))
    }

    /// The path the image on screen was traced by, once there is one.
    pub fn frame_path(&self) -> Option<GpuPath> {
        self.traced.as_ref()?.frame.map(|(_, path, ..)| path)
    }

    /// The adapter line (adapter, backend, path), once a tracer exists.
    pub fn adapter_line(&self) -> Option<String> {
        Some(self.traced.as_ref()?.tracer.adapter_line(self.path))
    }

    /// The GPU debug buffer of the selected pixel, once traced.
    pub fn pick(&self) -> Option<&Result<PixelDebug, String>> {
        self.traced.as_ref()?.pick.as_ref().map(|(_, r)| r)
    }

    /// The CPU − GPU comparison, once made, and the GPU path it compares.
    pub fn difference(&self) -> Option<Result<&Difference, &String>> {
        let d = &self.traced.as_ref()?.diff.as_ref()?.1;
        Some(d.as_ref().map(|(d, _)| d))
    }

    /// The GPU path of the comparison [`GpuView::difference`] holds.
    pub fn difference_path(&self) -> Option<GpuPath> {
        Some(self.traced.as_ref()?.diff.as_ref()?.0.1)
    }

    /// The tracer for the prepared scene, made (shader generated and compiled, scene uploaded)
    /// the first time it is needed.
    fn tracer_for(&mut self, prepared: &PreparedScene) -> Result<&mut Traced, String> {
        let key = Arc::as_ptr(prepared.scene_arc()) as usize;
        if let Some((k, e)) = &self.error
            && *k == key
        {
            return Err(e.clone());
        }
        if self.traced.as_ref().is_none_or(|t| t.key != key) {
            let rs = self
                .render_state
                .as_ref()
                .ok_or("the app has no wgpu device")?;
            let ctx = GpuContext::from_device(
                rs.device.clone(),
                rs.queue.clone(),
                rs.adapter.get_info(),
                rs.adapter.features(),
            );
            if let Some(old) = self.traced.take()
                && let Some((id, _)) = old.texture
            {
                rs.renderer.write().free_texture(&id);
            }
            match GpuTracer::new(ctx, prepared, ShaderVariant::Generated) {
                Ok(tracer) => {
                    self.traced = Some(Traced {
                        key,
                        tracer,
                        texture: None,
                        frame: None,
                        pick: None,
                        diff: None,
                        gpu_trace: None,
                    })
                }
                Err(e) => {
                    self.error = Some((key, e.to_string()));
                    return Err(e.to_string());
                }
            }
        }
        Ok(self.traced.as_mut().expect("made above"))
    }

    /// Traces a frame when the orbit, the path or the scene changed, and keeps the texture
    /// registered with egui.
    fn frame(&mut self, prepared: &PreparedScene) -> Result<(egui::TextureId, [u32; 2]), String> {
        let (orbit, path) = (self.orbit, self.path);
        let rs = self
            .render_state
            .clone()
            .ok_or("the app has no wgpu device")?;
        let t = self.tracer_for(prepared)?;
        let settings = &prepared.scene().settings;
        let spp = settings.spp.max(1);
        // A Monte Carlo image builds up a pass a frame on either path, as the CPU's does.
        let progressive = settings.integrator != crate::scene::Integrator::Whitted && spp > 1;
        match t.frame {
            Some((o, p, _, done)) if o == orbit && p == path => {
                if done < spp {
                    let time = t
                        .tracer
                        .trace_pass(path, done, done)
                        .map_err(|e| e.to_string())?;
                    t.frame = Some((orbit, path, time, (done * 2).min(spp)));
                }
            }
            _ => {
                t.tracer
                    .set_camera(&orbit.move_camera(&prepared.scene().camera))
                    .map_err(|e| e.to_string())?;
                let (time, done) = if progressive {
                    let time = t.tracer.trace_pass(path, 0, 1);
                    (time, 1)
                } else {
                    (t.tracer.trace(path), spp)
                };
                t.frame = Some((orbit, path, time.map_err(|e| e.to_string())?, done));
            }
        }
        let size = [t.tracer.camera().width, t.tracer.camera().height];
        match t.texture {
            Some((id, s)) if s == size => Ok((id, size)),
            old => {
                let mut renderer = rs.renderer.write();
                if let Some((id, _)) = old {
                    renderer.free_texture(&id);
                }
                let id = renderer.register_native_texture(
                    &rs.device,
                    t.tracer.display_view(),
                    wgpu::FilterMode::Nearest,
                );
                t.texture = Some((id, size));
                Ok((id, size))
            }
        }
    }

    /// The selected pixel traced into the GPU's debug buffer (at the scene's own camera, so it
    /// is the pixel the CPU traced).
    fn pick_pixel(&mut self, prepared: &PreparedScene, pixel: [u32; 2]) {
        let orbit = self.orbit;
        let Ok(t) = self.tracer_for(prepared) else {
            return;
        };
        if t.pick.as_ref().is_some_and(|(p, _)| *p == pixel) {
            return;
        }
        let result = (|| {
            if orbit != Orbit::IDENTITY {
                t.tracer
                    .set_camera(&prepared.scene().camera)
                    .map_err(|e| e.to_string())?;
                t.frame = None; // the display now needs the orbit again
            }
            t.tracer
                .debug_pixel(pixel[0], pixel[1])
                .map_err(|e| e.to_string())
        })();
        t.pick = Some((pixel, result));
    }

    /// The GPU's own trace of (pixel, sample), at the scene's camera, compared with the CPU's
    /// trace `cpu` (made once per pixel and sample).
    fn trace_on_gpu(
        &mut self,
        prepared: &PreparedScene,
        pixel: [u32; 2],
        sample: u32,
        cpu: &crate::record::Trace,
    ) -> Option<&Result<GpuTraceShown, String>> {
        let (orbit, path) = (self.orbit, self.path);
        let t = self.tracer_for(prepared).ok()?;
        let fresh = t
            .gpu_trace
            .as_ref()
            .is_some_and(|g| g.pixel == pixel && g.sample == sample && g.path == path);
        if !fresh {
            let result = (|| {
                if orbit != Orbit::IDENTITY {
                    t.tracer
                        .set_camera(&prepared.scene().camera)
                        .map_err(|e| e.to_string())?;
                    t.frame = None;
                }
                let g = t
                    .tracer
                    .trace_pixel_on(path, pixel[0], pixel[1], sample, DEFAULT_LOG_WORDS)
                    .map_err(|e| e.to_string())?;
                let cmp = compare(cpu, &g.trace, Tolerance::EXACT);
                let text = cmp.to_text(cpu, &g.trace, ["CPU", "GPU"]);
                let verdict = text
                    .lines()
                    .find(|l| {
                        l.starts_with("first divergence") || l.starts_with("the traces are equal")
                    })
                    .unwrap_or("compared")
                    .to_string();
                Ok(GpuTraceShown {
                    trace: Arc::new(g.trace),
                    verdict,
                    divergence: cmp.first().and_then(|d| d.actual_step.or(d.step)),
                    truncated: g.truncated,
                })
            })();
            t.gpu_trace = Some(GpuTraced {
                pixel,
                sample,
                path,
                result,
            });
        }
        t.gpu_trace.as_ref().map(|g| &g.result)
    }

    /// Renders on the GPU at the scene's camera and compares with the CPU render `render_id`.
    fn compare(&mut self, ctx: &egui::Context, prepared: &PreparedScene, state: &AppState) {
        let Some(rendered) = &state.rendered else {
            return;
        };
        let render_id = state.renders_started;
        let path = self.path;
        let Ok(t) = self.tracer_for(prepared) else {
            return;
        };
        if t.diff
            .as_ref()
            .is_some_and(|(k, _)| *k == (render_id, path))
        {
            return;
        }
        let out = &rendered.output;
        let result = (|| {
            t.tracer
                .set_camera(&prepared.scene().camera)
                .map_err(|e| e.to_string())?;
            t.frame = None;
            let frame = t.tracer.render(path).map_err(|e| e.to_string())?;
            let d = crate::gpu::difference(out.width, out.height, &out.pixels, &frame.pixels)?;
            let img = egui::ColorImage::from_rgb(
                [d.image.width() as usize, d.image.height() as usize],
                d.image.as_raw(),
            );
            let tex = ctx.load_texture("gpu-difference", img, egui::TextureOptions::NEAREST);
            Ok((d, tex))
        })();
        t.diff = Some(((render_id, path), result));
    }
}

/// The tab strip above the central view (only when the app has a GPU view).
pub fn tabs(ui: &mut egui::Ui, gpu: &mut GpuView) {
    ui.horizontal(|ui| {
        for (tab, label, hover) in [
            (
                CentralTab::Cpu,
                "CPU render",
                "the render on the CPU; click a pixel to trace it",
            ),
            (
                CentralTab::Gpu,
                "GPU render",
                "the same scene traced by a WGSL shader generated for it; drag to orbit",
            ),
            (
                CentralTab::Difference,
                "CPU − GPU",
                "where the two renders differ, and by how much",
            ),
            (
                CentralTab::Scene3d,
                "3D view",
                "the scene in space: the camera, its image plane and the pixel's rays; edit the scene",
            ),
        ] {
            if ui
                .selectable_label(gpu.tab == tab, label)
                .on_hover_text(hover)
                .clicked()
            {
                gpu.tab = tab;
            }
        }
    });
}

/// The GPU render view (the central panel's "GPU render" tab).
pub fn gpu_tab(ui: &mut egui::Ui, state: &AppState, gpu: &mut GpuView, cmds: &mut Vec<Command>) {
    if crate::platform::IN_BROWSER {
        return not_in_browser(ui);
    }
    let Some(prepared) = &state.prepared else {
        ui.label("Preparing the scene…");
        return;
    };
    let prepared = Arc::clone(prepared);
    ui.horizontal_wrapped(|ui| {
        ui.radio_value(&mut gpu.path, GpuPath::Fragment, "fragment")
            .on_hover_text("a full-screen triangle: the rasterizer interpolates the primary rays");
        ui.radio_value(&mut gpu.path, GpuPath::Compute, "compute")
            .on_hover_text("a compute shader, one invocation per pixel");
        if ui
            .add_enabled(
                gpu.orbit != Orbit::IDENTITY,
                egui::Button::new("Reset view"),
            )
            .clicked()
        {
            gpu.orbit = Orbit::IDENTITY;
        }
        ui.toggle_value(&mut gpu.show_wgsl, "WGSL");
    });
    let frame = gpu.frame(&prepared);
    if let Some(line) = gpu.adapter_line() {
        ui.label(RichText::new(line).small());
    }
    let settings = &prepared.scene().settings;
    if settings.integrator != crate::scene::Integrator::Whitted {
        let name = clap::ValueEnum::to_possible_value(&settings.integrator)
            .map_or_else(String::new, |v| v.get_name().to_string());
        let so_far = match gpu.samples_so_far() {
            Some((done, spp)) if done < spp => {
                // The next pass is traced on the next frame.
                ui.ctx().request_repaint();
                format!("{done} of {spp} samples per pixel so far")
            }
            _ => format!("{} samples per pixel", settings.spp),
        };
        ui.label(
            RichText::new(format!(
                "{name} integrator on the GPU: {so_far}, the CPU's random numbers \
                 (the same image bit for bit where the arithmetic is exact)."
            ))
            .small(),
        );
    }
    let (id, size) = match frame {
        Ok(f) => f,
        Err(e) => {
            ui.colored_label(ui.visuals().error_fg_color, format!("GPU view: {e}"));
            return;
        }
    };
    if let Some((path, d)) = gpu.frame_time() {
        ui.label(format!(
            "{} path: {:.2} ms per frame (trace pass, submit to completion), {}×{}",
            path.name(),
            d.as_secs_f64() * 1e3,
            size[0],
            size[1]
        ));
    }
    if let Some([x, y]) = state.pixel {
        gpu.pick_pixel(&prepared, [x, y]);
        pick_table(ui, state, prepared.scene(), gpu);
        trace_switch(ui, state, &prepared, gpu, cmds);
    }
    if gpu.show_wgsl {
        if let Some(t) = &gpu.traced {
            let wgsl = t.tracer.wgsl();
            ui.label(format!(
                "Generated for this scene: {} lines, {} bytes (features the scene lacks are left out)",
                wgsl.lines().count(),
                wgsl.len()
            ));
            egui::ScrollArea::both()
                .id_salt("wgsl")
                .auto_shrink([false, false])
                .show(ui, |ui| {
                    ui.add(
                        egui::TextEdit::multiline(&mut wgsl.to_string())
                            .code_editor()
                            .interactive(false)
                            .desired_width(f32::INFINITY),
                    );
                });
        }
        return;
    }
    // The image, fitted, with drag to orbit and scroll to zoom.
    let avail = ui.available_size();
    let scale = (avail.x / size[0] as f32)
        .min(avail.y / size[1] as f32)
        .max(0.05);
    let shown = egui::vec2(size[0] as f32, size[1] as f32) * scale;
    let (rect, response) = ui.allocate_exact_size(shown, Sense::click_and_drag());
    gpu.image_rect = Some(rect);
    ui.painter().image(
        id,
        rect,
        egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
        Color32::WHITE,
    );
    let drag = response.drag_delta();
    if drag != egui::Vec2::ZERO {
        // 0.01 radians per point; the pitch within ±1.4 radians.
        let per_point = 0.01_f32.to_degrees();
        let limit = 1.4_f32.to_degrees();
        gpu.orbit.yaw -= drag.x * per_point;
        gpu.orbit.pitch = (gpu.orbit.pitch - drag.y * per_point).clamp(-limit, limit);
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0 {
            gpu.orbit.distance = (gpu.orbit.distance * (-scroll * 0.002).exp()).clamp(0.1, 10.0);
        }
    }
    if response.double_clicked() {
        gpu.orbit = Orbit::IDENTITY;
    }
}

/// The GPU debug buffer of the selected pixel beside the CPU trace's values.
fn pick_table(ui: &mut egui::Ui, state: &AppState, scene: &Scene, gpu: &GpuView) {
    let Some(pick) = gpu.pick() else {
        return;
    };
    let p = match pick {
        Ok(p) => p,
        Err(e) => {
            ui.colored_label(ui.visuals().error_fg_color, format!("debug pixel: {e}"));
            return;
        }
    };
    let cpu = state.stepping.as_ref().map(|s| &s.trace.root);
    let hit = cpu.and_then(|r| r.hit.as_ref());
    let hit_name = hit.map(|h| h.name.clone());
    // The CPU's test against the object it hit: the discriminant of a sphere, u and v of a
    // triangle.
    let (mut disc, mut u, mut v) = (None, None, None);
    if let (Some(r), Some(name)) = (cpu, &hit_name) {
        for s in &r.steps {
            match &s.step {
                Step::Sphere { name: n, test, .. } if n == name => disc = Some(test.discriminant),
                Step::Triangle { name: n, test, .. } if n == name => {
                    u = test.u;
                    v = test.v;
                }
                _ => {}
            }
        }
    }
    let nodes = cpu.map(|r| {
        r.steps
            .iter()
            .filter(|s| matches!(s.step, Step::Node(_)))
            .count()
    });
    let opt = |x: Option<f32>| x.map_or("—".to_string(), num);
    let gpu_name = p
        .object
        .map_or("nothing".into(), |id| scene.object_name(id));
    let rows: Vec<(&str, String, String)> = vec![
        (
            "hit object",
            hit_name.clone().unwrap_or_else(|| "nothing".into()),
            gpu_name,
        ),
        (
            "t",
            opt(hit.map(|h| h.t)),
            if p.object.is_some() {
                num(p.t)
            } else {
                "—".into()
            },
        ),
        ("discriminant", opt(disc), opt(p.discriminant)),
        ("u", opt(u), if u.is_some() { num(p.u) } else { "—".into() }),
        ("v", opt(v), if v.is_some() { num(p.v) } else { "—".into() }),
        (
            "BVH nodes visited",
            nodes.map_or("—".into(), |n| n.to_string()),
            p.nodes_text(),
        ),
    ];
    // Leave out what neither side computed (u and v off triangles, nodes without a BVH).
    let with_bvh = state
        .stepping
        .as_ref()
        .is_some_and(|s| s.trace.bvh.is_some());
    let rows: Vec<_> = rows
        .into_iter()
        .filter(|(name, c, g)| {
            if *name == "BVH nodes visited" {
                with_bvh || p.nodes_visited > 0 || p.hardware_traversal
            } else {
                !(c == "—" && g == "—")
            }
        })
        .collect();
    ui.label(
        RichText::new(format!(
            "Pixel ({}, {}), primary ray, traced on both:",
            p.pixel[0], p.pixel[1]
        ))
        .strong(),
    );
    egui::Grid::new("gpu-pick")
        .striped(true)
        .num_columns(3)
        .show(ui, |ui| {
            ui.label(RichText::new("quantity").strong());
            ui.label(RichText::new("CPU trace").strong());
            ui.label(RichText::new("GPU debug buffer").strong());
            ui.end_row();
            for (name, c, g) in rows {
                ui.label(name);
                ui.monospace(c);
                ui.monospace(g);
                ui.end_row();
            }
        });
}

/// CPU ⇄ GPU: which trace of the selected pixel the stepper, math panel and diagrams show. The
/// GPU's own trace is made on first use (the trace shader logs each step the compute path takes)
/// and compared with the CPU's; the first divergence is named, marked on the step bar, and one
/// click away.
fn trace_switch(
    ui: &mut egui::Ui,
    state: &AppState,
    prepared: &PreparedScene,
    gpu: &mut GpuView,
    cmds: &mut Vec<Command>,
) {
    let Some(pixel) = state.pixel else {
        return;
    };
    let Some(stepping) = &state.stepping else {
        return;
    };
    ui.horizontal_wrapped(|ui| {
        ui.label("Step through:");
        if ui
            .selectable_label(!state.showing_gpu_trace, "CPU trace")
            .on_hover_text("the CPU tracer's steps for this pixel")
            .clicked()
        {
            cmds.push(Command::ShowCpuTrace);
        }
        let gpu_button = ui
            .selectable_label(state.showing_gpu_trace, "GPU trace")
            .on_hover_text(
                "the GPU's own steps: the trace shader logs every step the chosen path (fragment \
                 or compute) takes for this pixel, read back into the same stepper, math panel \
                 and diagrams",
            );
        if gpu_button.clicked() {
            let cpu = Arc::clone(&stepping.trace);
            if let Some(Ok(g)) = gpu.trace_on_gpu(prepared, pixel, state.sample, &cpu) {
                cmds.push(Command::ShowGpuTrace(Arc::clone(&g.trace), g.divergence));
            }
        }
    });
    let shown = gpu
        .traced
        .as_ref()
        .and_then(|t| t.gpu_trace.as_ref())
        .filter(|g| g.pixel == pixel && g.sample == state.sample && g.path == gpu.path);
    match shown.map(|g| &g.result) {
        Some(Ok(g)) => {
            let colour = if g.divergence.is_some() {
                ui.visuals().warn_fg_color
            } else {
                ui.visuals().text_color()
            };
            ui.label(RichText::new(&g.verdict).color(colour));
            if g.truncated {
                ui.colored_label(
                    ui.visuals().warn_fg_color,
                    "The GPU's step log ran out: its trace stops early.",
                );
            }
            if let Some(k) = g.divergence
                && state.showing_gpu_trace
                && ui.button(format!("Go to step {k}")).clicked()
            {
                cmds.push(Command::Step(StepMove::To(k)));
            }
        }
        Some(Err(e)) => {
            ui.colored_label(ui.visuals().error_fg_color, format!("GPU trace: {e}"));
        }
        None => {}
    }
}

/// The difference tab: CPU − GPU as an image, with RMSE, max error and the count of differing
/// pixels.
pub fn difference_tab(ui: &mut egui::Ui, state: &AppState, gpu: &mut GpuView) {
    if crate::platform::IN_BROWSER {
        return not_in_browser(ui);
    }
    let Some(prepared) = &state.prepared else {
        ui.label("Preparing the scene…");
        return;
    };
    if state.job.is_some() || state.rendered.is_none() {
        ui.label("Waiting for the CPU render to finish…");
        return;
    }
    let prepared = Arc::clone(prepared);
    ui.horizontal(|ui| {
        ui.radio_value(&mut gpu.path, GpuPath::Fragment, "fragment");
        ui.radio_value(&mut gpu.path, GpuPath::Compute, "compute");
    });
    gpu.compare(ui.ctx(), &prepared, state);
    let Some(t) = &gpu.traced else {
        if let Some((_, e)) = &gpu.error {
            ui.colored_label(ui.visuals().error_fg_color, format!("GPU view: {e}"));
        }
        return;
    };
    match &t.diff {
        Some(((_, path), Ok((d, tex)))) => {
            ui.label(RichText::new(format!("{} path: {}", path.name(), d.summary())).strong());
            ui.label(
                "Equal pixels are dim grey; differing ones run from dark red (one 8-bit step) to \
                 yellow (16 or more). Both sides compute in f32; the GPU's pow, FMA contraction \
                 and the rasterizer's interpolated rays round differently in the last bits.",
            );
            let avail = ui.available_size();
            let size = tex.size_vec2();
            let scale = (avail.x / size.x).min(avail.y / size.y).max(0.05);
            ui.image((tex.id(), size * scale));
        }
        Some((_, Err(e))) => {
            ui.colored_label(ui.visuals().error_fg_color, e);
        }
        None => {}
    }
}

/// The GPU tabs in a web page: what they would show and why they cannot here.
fn not_in_browser(ui: &mut egui::Ui) {
    ui.vertical_centered(|ui| {
        ui.add_space(40.0);
        ui.heading("The GPU tracer runs in the desktop app");
        ui.add_space(8.0);
        ui.label(crate::gpu::NOT_IN_BROWSER);
        ui.add_space(8.0);
        ui.label(
            "The CPU render, the stepper, the diagrams, the 3D view, the lessons and the \
             exercises all work here.",
        );
    });
}
