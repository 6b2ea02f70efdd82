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
//! In a web page the same tabs run on WebGPU where the browser offers it (the page's wgpu
//! device is then a WebGPU one); with WebGL2 they say what they need. A page cannot wait for the
//! GPU, so every answer the view reads back (the arithmetic probe, the debug pixel, the GPU's
//! trace, the image for the difference) is asked for on one frame and taken on a later one
//! ([`crate::gpu::Readback`]); natively the view waits for it at once, as before.

mod tabs;

pub use tabs::{difference_tab, gpu_tab, tabs};

use super::state::{AppState, Command, StepMove};
use crate::explain::diff::compare;
use crate::gpu::trace_log::DEFAULT_LOG_WORDS;
use crate::gpu::{
    Difference, GpuContext, GpuPath, GpuTracer, PendingTrace, PixelDebug, Readback, ShaderVariant,
    TextureReadback,
};
use crate::platform::{Duration, Instant};
use crate::record::Step;
use crate::record::Tolerance;
use crate::record::number::num;
use crate::scene::Scene;
use crate::trace::PreparedScene;
use crate::view3d::camera::Orbit;
use eframe::egui_wgpu::{self, wgpu};
use egui::{Color32, RichText, Sense};
use std::sync::{Arc, Mutex};

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

/// A WebGPU device being opened in a web page: its answer, once come.
type Opening = Arc<Mutex<Option<Result<GpuContext, crate::gpu::GpuError>>>>;

/// An answer from the GPU: on its way (in a web page, for a frame or more), or come.
enum Answer<P, T> {
    /// Asked for; `P` is what is polled.
    Waiting(P),
    /// Come (or failed).
    Done(Result<T, String>),
}

impl<P, T> Answer<P, T> {
    /// The answer, once come.
    fn done(&self) -> Option<&Result<T, String>> {
        match self {
            Answer::Done(r) => Some(r),
            Answer::Waiting(_) => None,
        }
    }
}

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
    pick: Option<([u32; 2], Answer<Readback, PixelDebug>)>,
    /// The comparison with the CPU render, for (the render it was made against, the GPU path).
    diff: Option<((u64, GpuPath), Answer<TextureReadback, Compared>)>,
    /// The GPU's own trace of a pixel.
    gpu_trace: Option<GpuTraced>,
    /// In a web page (the tracer's device is not the page's): the display image read back, as
    /// an egui texture; the read on its way; whether a frame was traced since it was asked for.
    shown: Option<egui::TextureHandle>,
    display_read: Option<TextureReadback>,
    display_stale: bool,
}

/// The GPU's own trace of (pixel, sample), and how it compares with the CPU's.
struct GpuTraced {
    pixel: [u32; 2],
    sample: u32,
    path: GpuPath,
    result: Answer<(PendingTrace, Arc<crate::record::Trace>), GpuTraceShown>,
    /// Show it in the stepper when it comes (the button was pressed).
    show: bool,
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

/// What the GPU view shows, in words (the web page's status element carries it,
/// [`super::web::Status`]).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct GpuStatus {
    /// Empty until the view made something; then `waiting`, `ready`, `no-webgpu` or `error: …`.
    pub state: String,
    /// The adapter line.
    pub adapter: String,
    /// The debug pixel: `x,y object=NAME t=T` (or `object=nothing`).
    pub pick: String,
    /// The CPU − GPU summary, with its path first.
    pub diff: String,
}

/// The GPU view's state (part of [`super::panels::Panels`]).
pub struct GpuView {
    /// eframe's wgpu device (None: no GPU view).
    pub render_state: Option<egui_wgpu::RenderState>,
    /// The tracing context, made once (its arithmetic probe runs once).
    context: Option<GpuContext>,
    /// In a web page: the WebGPU device being opened.
    opening: Option<Opening>,
    /// Why there is no tracing context (a browser without WebGPU).
    context_error: Option<String>,
    /// In a web page: the last frame's time from submit until the browser said the GPU was done.
    web_time: Arc<Mutex<Option<Duration>>>,
    /// Errors the browser reported late ([`GpuContext::late_errors`]), the last few.
    pub late_errors: Vec<String>,
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
            context: None,
            opening: None,
            context_error: None,
            web_time: Arc::default(),
            late_errors: vec![],
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
        let (_, path, time, _) = t.frame?;
        if crate::platform::IN_BROWSER {
            return Some((path, (*self.web_time.lock().ok()?)?));
        }
        Some((path, time))
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
        self.traced.as_ref()?.pick.as_ref()?.1.done()
    }

    /// The CPU − GPU comparison, once made, and the GPU path it compares.
    pub fn difference(&self) -> Option<Result<&Difference, &String>> {
        let d = self.traced.as_ref()?.diff.as_ref()?.1.done()?;
        Some(d.as_ref().map(|(d, _)| d))
    }

    /// What the view shows, in words.
    pub fn status(&self) -> GpuStatus {
        let mut s = GpuStatus::default();
        let Some(t) = &self.traced else {
            s.state = if self.context_error.is_some() {
                "no-webgpu".into()
            } else if let Some((_, e)) = &self.error {
                format!("error: {e}")
            } else if self.context.is_some() || self.opening.is_some() {
                "waiting".into()
            } else {
                String::new()
            };
            return s;
        };
        s.state = match (&self.error, t.frame) {
            (Some((_, e)), _) => format!("error: {e}"),
            (None, Some(_)) if !self.waiting() => "ready".into(),
            _ => "waiting".into(),
        };
        s.adapter = t.tracer.adapter_line(self.path);
        if let Some(([x, y], Answer::Done(r))) = &t.pick {
            s.pick = match r {
                Ok(p) => format!(
                    "{x},{y} object={} t={}",
                    p.object
                        .map_or("nothing".into(), |id| t.tracer.scene().object_name(id)),
                    num(p.t)
                ),
                Err(e) => format!("{x},{y} error: {e}"),
            };
        }
        if let Some(((_, path), Answer::Done(r))) = &t.diff {
            s.diff = match r {
                Ok((d, _)) => format!("{} path: {}", path.name(), d.summary()),
                Err(e) => format!("error: {e}"),
            };
        }
        s
    }

    /// Whether an answer from the GPU is on its way (the view asks again next frame).
    pub fn waiting(&self) -> bool {
        self.traced.as_ref().is_some_and(|t| {
            t.display_read.is_some()
                || matches!(t.pick, Some((_, Answer::Waiting(_))))
                || matches!(t.diff, Some((_, Answer::Waiting(_))))
                || t.gpu_trace
                    .as_ref()
                    .is_some_and(|g| matches!(g.result, Answer::Waiting(_)))
        })
    }

    /// The tracing context, made once: natively on eframe's device (the GPU image is then one
    /// of egui's textures as it is); in a web page on a WebGPU device of its own, opened in the
    /// background (`Ok(None)` until it is), while the page draws with WebGL2.
    fn context(&mut self) -> Result<Option<GpuContext>, String> {
        if let Some(c) = &self.context {
            return Ok(Some(c.clone()));
        }
        if let Some(e) = &self.context_error {
            return Err(e.clone());
        }
        if crate::platform::IN_BROWSER {
            let opening = self.opening.get_or_insert_with(|| {
                let slot = Arc::new(Mutex::new(None));
                let answer = Arc::clone(&slot);
                crate::platform::browser::spawn_local(async move {
                    let opened = GpuContext::open().await;
                    if let Ok(mut a) = answer.lock() {
                        *a = Some(opened);
                    }
                });
                slot
            });
            let opened = opening.lock().ok().and_then(|mut o| o.take());
            return match opened {
                None => Ok(None),
                Some(Ok(ctx)) => {
                    self.context = Some(ctx.clone());
                    Ok(Some(ctx))
                }
                Some(Err(_)) => {
                    // (wgpu's own words name native drivers: not useful in a page.)
                    self.context_error = Some(NO_WEBGPU.into());
                    Err(NO_WEBGPU.into())
                }
            };
        }
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
        self.context = Some(ctx.clone());
        Ok(Some(ctx))
    }

    /// Takes what has come back from the GPU (in a web page, between frames): the debug pixel,
    /// the comparison's image, the GPU's trace; and the errors the browser reported late. Returns
    /// whether something is still on its way.
    pub fn poll(&mut self, ctx: &egui::Context, state: &AppState) -> bool {
        if let Some(c) = &self.context {
            self.late_errors.extend(c.late_errors());
            let keep = self.late_errors.len().saturating_sub(4);
            self.late_errors.drain(..keep);
        }
        let Some(t) = self.traced.as_mut() else {
            return false;
        };
        if let Some((pixel, Answer::Waiting(r))) = &mut t.pick
            && let Some(bytes) = r.poll()
        {
            let pick = bytes
                .map(|b| t.tracer.debug_from(*pixel, &b))
                .map_err(|e| e.to_string());
            t.pick = Some((*pixel, Answer::Done(pick)));
        }
        if let Some((key, Answer::Waiting(r))) = &mut t.diff
            && let Some(bytes) = r.poll()
        {
            // Against the CPU render it was asked for (a newer one asks again).
            let cpu = state
                .rendered
                .as_ref()
                .filter(|_| key.0 == state.renders_started)
                .ok_or("the CPU render changed");
            let compared = bytes
                .map_err(|e| e.to_string())
                .and_then(|b| compared(ctx, &cpu?.output, &b));
            t.diff = Some((*key, Answer::Done(compared)));
        }
        if let Some(g) = &mut t.gpu_trace
            && let Answer::Waiting((pending, cpu)) = &mut g.result
            && let Some(bytes) = pending.readback.poll()
        {
            let shown = bytes
                .and_then(|b| t.tracer.finish_trace_of(pending, &b))
                .map_err(|e| e.to_string())
                .map(|g| shown(cpu, g));
            g.result = Answer::Done(shown);
        }
        let waiting = self.waiting();
        if waiting {
            ctx.request_repaint();
        }
        waiting
    }

    /// The GPU path of the comparison [`GpuView::difference`] holds.
    pub fn difference_path(&self) -> Option<GpuPath> {
        Some(self.traced.as_ref()?.diff.as_ref()?.0.1)
    }

    /// The tracer for the prepared scene, made (shader generated and compiled, scene uploaded)
    /// the first time it is needed; `None` while the device's arithmetic probe is on its way (in
    /// a web page: ask again next frame).
    fn tracer_for(&mut self, prepared: &PreparedScene) -> Result<Option<&mut Traced>, String> {
        let key = Arc::as_ptr(prepared.scene_arc()) as usize;
        if let Some((k, e)) = &self.error
            && *k == key
        {
            return Err(e.clone());
        }
        if self.traced.as_ref().is_none_or(|t| t.key != key) {
            let Some(ctx) = self.context()? else {
                return Ok(None);
            };
            if crate::platform::IN_BROWSER
                && ctx.info.device_type == wgpu::DeviceType::Cpu
                && prepared.scene().settings.integrator.is_monte_carlo()
            {
                let e = SOFTWARE_WEBGPU.to_string();
                self.error = Some((key, e.clone()));
                return Err(e);
            }
            match ctx.arithmetic_nowait() {
                None => return Ok(None),
                Some(Err(e)) => return Err(e.to_string()),
                Some(Ok(_)) => {}
            }
            if let Some(old) = self.traced.take()
                && let Some((id, _)) = old.texture
                && let Some(rs) = &self.render_state
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
                        shown: None,
                        display_read: None,
                        display_stale: false,
                    })
                }
                Err(e) => {
                    self.error = Some((key, e.to_string()));
                    return Err(e.to_string());
                }
            }
        }
        Ok(self.traced.as_mut())
    }

    /// Traces a frame when the orbit, the path or the scene changed, and keeps the texture
    /// registered with egui; `None` while the tracer waits for the device's probe.
    fn frame(
        &mut self,
        ctx: &egui::Context,
        prepared: &PreparedScene,
    ) -> Result<Option<(egui::TextureId, [u32; 2])>, String> {
        let (orbit, path) = (self.orbit, self.path);
        let rs = self
            .render_state
            .clone()
            .ok_or("the app has no wgpu device")?;
        let web_time = Arc::clone(&self.web_time);
        let Some(t) = self.tracer_for(prepared)? else {
            return Ok(None);
        };
        let start = Instant::now();
        let queue = t.tracer.context().queue.clone();
        let stale = &mut t.display_stale;
        // In a web page the time from submit until the browser says the GPU is done (the
        // frame's own wait returns at once there), and the display to read back.
        let time_it = move || {
            if crate::platform::IN_BROWSER {
                *stale = true;
                queue.on_submitted_work_done(move || {
                    if let Ok(mut t) = web_time.lock() {
                        *t = Some(start.elapsed());
                    }
                });
            }
        };
        let settings = &prepared.scene().settings;
        let spp = settings.spp.max(1);
        // A Monte Carlo image builds up a pass a frame on either path, as the CPU's does.
        let progressive = settings.integrator.is_monte_carlo() && spp > 1;
        match t.frame {
            Some((o, p, _, done)) if o == orbit && p == path => {
                if done < spp {
                    let end = crate::render::passes::next_pass_end(done, spp);
                    let time = t
                        .tracer
                        .trace_pass(path, done, end - done)
                        .map_err(|e| e.to_string())?;
                    t.frame = Some((orbit, path, time, end));
                    time_it();
                }
            }
            _ => {
                t.tracer
                    .set_camera(&orbit.move_camera(&prepared.scene().camera))
                    .map_err(|e| e.to_string())?;
                let (time, done) = if progressive {
                    let end = crate::render::passes::next_pass_end(0, spp);
                    (t.tracer.trace_pass(path, 0, end), end)
                } else {
                    (t.tracer.trace(path), spp)
                };
                t.frame = Some((orbit, path, time.map_err(|e| e.to_string())?, done));
                time_it();
            }
        }
        let size = [t.tracer.camera().width, t.tracer.camera().height];
        if crate::platform::IN_BROWSER {
            return browser_display(ctx, t);
        }
        match t.texture {
            Some((id, s)) if s == size => Ok(Some((id, size))),
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
                Ok(Some((id, size)))
            }
        }
    }

    /// The selected pixel traced into the GPU's debug buffer (at the scene's own camera, so it
    /// is the pixel the CPU traced). One at a time: a pixel picked while another's answer is on
    /// its way is traced once that has come.
    fn pick_pixel(&mut self, prepared: &PreparedScene, pixel: [u32; 2]) {
        let orbit = self.orbit;
        let Ok(Some(t)) = self.tracer_for(prepared) else {
            return;
        };
        match &t.pick {
            Some((p, _)) if *p == pixel => return,
            Some((_, Answer::Waiting(_))) => return,
            _ => {}
        }
        let asked = (|| {
            if orbit != Orbit::IDENTITY {
                t.tracer
                    .set_camera(&prepared.scene().camera)
                    .map_err(|e| e.to_string())?;
                t.frame = None; // the display now needs the orbit again
            }
            t.tracer
                .start_debug_pixel(pixel[0], pixel[1])
                .map_err(|e| e.to_string())
        })();
        t.pick = Some((
            pixel,
            match asked {
                Ok(r) => Answer::Waiting(r),
                Err(e) => Answer::Done(Err(e)),
            },
        ));
        settle(&t.tracer);
    }

    /// The GPU's own trace of (pixel, sample), at the scene's camera, compared with the CPU's
    /// trace `cpu` (made once per pixel and sample; `show`: put it in the stepper when it comes).
    fn trace_on_gpu(
        &mut self,
        prepared: &PreparedScene,
        pixel: [u32; 2],
        sample: u32,
        cpu: &Arc<crate::record::Trace>,
        show: bool,
    ) {
        let (orbit, path) = (self.orbit, self.path);
        let Ok(Some(t)) = self.tracer_for(prepared) else {
            return;
        };
        if let Some(g) = &mut t.gpu_trace
            && g.pixel == pixel
            && g.sample == sample
            && g.path == path
        {
            g.show |= show;
            return;
        }
        if t.gpu_trace
            .as_ref()
            .is_some_and(|g| matches!(g.result, Answer::Waiting(_)))
        {
            return; // one at a time
        }
        let asked = (|| {
            if orbit != Orbit::IDENTITY {
                t.tracer
                    .set_camera(&prepared.scene().camera)
                    .map_err(|e| e.to_string())?;
                t.frame = None;
            }
            t.tracer
                .start_trace_pixel(path, pixel[0], pixel[1], sample, DEFAULT_LOG_WORDS)
                .map_err(|e| e.to_string())
        })();
        t.gpu_trace = Some(GpuTraced {
            pixel,
            sample,
            path,
            result: match asked {
                Ok(p) => Answer::Waiting((p, Arc::clone(cpu))),
                Err(e) => Answer::Done(Err(e)),
            },
            show,
        });
        settle(&t.tracer);
    }

    /// Renders on the GPU at the scene's camera and compares with the CPU render `render_id`
    /// (once the image has come back).
    fn compare(&mut self, prepared: &PreparedScene, state: &AppState) {
        if state.rendered.is_none() {
            return;
        }
        let render_id = state.renders_started;
        let path = self.path;
        let Ok(Some(t)) = self.tracer_for(prepared) else {
            return;
        };
        match &t.diff {
            Some((k, _)) if *k == (render_id, path) => return,
            Some((_, Answer::Waiting(_))) => return,
            _ => {}
        }
        let asked = (|| {
            t.tracer
                .set_camera(&prepared.scene().camera)
                .map_err(|e| e.to_string())?;
            t.frame = None;
            t.tracer.trace(path).map_err(|e| e.to_string())?;
            t.tracer.start_read_linear().map_err(|e| e.to_string())
        })();
        t.diff = Some((
            (render_id, path),
            match asked {
                Ok(r) => Answer::Waiting(r),
                Err(e) => Answer::Done(Err(e)),
            },
        ));
        settle(&t.tracer);
    }
}

/// Why a Monte Carlo scene is not traced on a browser's software WebGPU adapter.
pub const SOFTWARE_WEBGPU: &str = "This browser's WebGPU runs on the CPU (a software adapter). \
     Compiling the Monte Carlo tracer there takes longer than the browser lets its GPU process \
     stall, and the page would lose its canvas (measured with Chromium's SwiftShader: over two \
     minutes). Whitted scenes trace here; Monte Carlo ones need a real GPU's WebGPU or the \
     desktop app.";

/// What the GPU tabs say in a browser without WebGPU (the start of their message).
pub const NO_WEBGPU: &str = "The GPU tracer needs WebGPU (compute shaders and storage buffers), which \
     this browser does not offer. Open the page in a browser with WebGPU (Chrome or Edge 113 or \
     newer, Safari 26, Firefox 141 on Windows), or run the desktop app.";

/// In a web page: the GPU image as egui shows it. The tracer's device is not the page's, so
/// the display texture is read back after each traced frame (one read at a time; a frame traced
/// meanwhile is read next) and shown as an egui texture; the last one read shows until then.
fn browser_display(
    ctx: &egui::Context,
    t: &mut Traced,
) -> Result<Option<(egui::TextureId, [u32; 2])>, String> {
    if let Some(r) = &mut t.display_read
        && let Some(bytes) = r.poll()
    {
        let size = r.size();
        t.display_read = None;
        let bytes = bytes.map_err(|e| e.to_string())?;
        let image =
            egui::ColorImage::from_rgba_unmultiplied([size[0] as usize, size[1] as usize], &bytes);
        match &mut t.shown {
            Some(h) => h.set(image, egui::TextureOptions::NEAREST),
            None => {
                t.shown =
                    Some(ctx.load_texture("gpu-render", image, egui::TextureOptions::NEAREST));
            }
        }
    }
    if t.display_read.is_none() && std::mem::take(&mut t.display_stale) {
        t.display_read = Some(t.tracer.start_read_display().map_err(|e| e.to_string())?);
    }
    if t.display_read.is_some() {
        ctx.request_repaint();
    }
    Ok(t.shown.as_ref().map(|h| {
        let [w, h2] = h.size();
        (h.id(), [w as u32, h2 as u32])
    }))
}

/// Natively: waits for the GPU, so that what was just asked for is there at the next poll (as
/// the view always did). In a web page: nothing (the answer comes between frames).
fn settle(tracer: &GpuTracer) {
    if !crate::platform::IN_BROWSER {
        let _ = tracer.context().wait();
    }
}

/// The comparison of the CPU render `out` with the GPU's linear image `bytes`.
fn compared(
    ctx: &egui::Context,
    out: &crate::render::RenderOutput,
    bytes: &[u8],
) -> Result<Compared, String> {
    let pixels = crate::gpu::linear_from(bytes);
    let d = crate::gpu::difference(out.width, out.height, &out.pixels, &pixels)?;
    let img = egui::ColorImage::from_rgb(
        [d.image.width() as usize, d.image.height() as usize],
        d.image.as_raw(),
    );
    let tex = ctx.load_texture("gpu-difference", img, egui::TextureOptions::NEAREST);
    Ok((d, tex))
}

/// The GPU's trace compared with the CPU's.
fn shown(cpu: &crate::record::Trace, g: crate::gpu::GpuTrace) -> GpuTraceShown {
    let cmp = compare(cpu, &g.trace, Tolerance::EXACT);
    let text = cmp.to_text(cpu, &g.trace, ["CPU", "GPU"]);
    let verdict = text
        .lines()
        .find(|l| l.starts_with("first divergence") || l.starts_with("the traces are equal"))
        .unwrap_or("compared")
        .to_string();
    GpuTraceShown {
        divergence: cmp.first().and_then(|d| d.actual_step.or(d.step)),
        trace: Arc::new(g.trace),
        verdict,
        truncated: g.truncated,
    }
}
