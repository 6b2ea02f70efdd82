//! The GPU view's live state, part of [`super::AppState`]: the tracing context, the open scene's
//! [`GpuTracer`], the frame it traced, and the answers asked of the GPU (the selected pixel's
//! debug buffer, the comparison with the CPU render, the GPU's own trace of the pixel). The GPU
//! tabs ask for work with [`GpuCmd`]s; [`super::AppState::tick`] takes the answers as they come.
//! What only the screen needs (egui's textures, the tab shown, where the image was drawn) stays
//! in the panel ([`crate::gpu_view::GpuView`]).
//!
//! In a web page the same tabs run on WebGPU where the browser offers it, on a device of their
//! own opened in the background. A page cannot wait for the GPU, so every answer (the arithmetic
//! probe, the debug pixel, the GPU's trace, the image for the difference, the displayed image) is
//! asked for on one frame and taken on a later one ([`crate::gpu::Readback`]); natively the
//! answer is waited for at once, as before.

use crate::explain::diff::compare;
use crate::gpu::trace_log::DEFAULT_LOG_WORDS;
use crate::gpu::{
    Difference, GpuContext, GpuPath, GpuTracer, PendingTrace, PixelDebug, Readback, ShaderVariant,
    TextureReadback,
};
use crate::platform::{Duration, Instant};
use crate::record::number::num;
use crate::record::{Tolerance, Trace};
use crate::render::RenderOutput;
use crate::trace::PreparedScene;
use crate::view3d::camera::Orbit;
use std::sync::{Arc, Mutex};

/// What the GPU tabs ask of the app's state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GpuCmd {
    /// The GPU render tab is on screen: trace its image for the prepared scene (again when the
    /// orbit, the path or the scene changed; a Monte Carlo scene's next pass while it has
    /// fewer samples than the scene asks for), and the selected pixel into the debug buffer.
    Frame,
    /// The difference tab is on screen: render on the GPU at the scene's camera and compare
    /// with the finished CPU render (once per render and path).
    Compare,
    /// Trace the selected pixel on the GPU (its own step trace, compared with the CPU's) and
    /// show it in the stepper when it comes.
    TracePixel,
    /// Fragment (rasterizer-interpolated primary rays) or compute.
    SetPath(GpuPath),
    /// The camera orbit of the GPU view.
    SetOrbit(Orbit),
}

/// An answer from the GPU: on its way (in a web page, for a frame or more), or come.
pub(crate) enum Answer<P, T> {
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

/// The comparison with the CPU render: (the render it was made against, the GPU path), and the
/// answer (the difference and the number that tells it from the one before).
type Compared = ((u64, GpuPath), Answer<TextureReadback, (Difference, u64)>);

/// A WebGPU device being opened in a web page: its answer, once come.
type Opening = Arc<Mutex<Option<Result<GpuContext, crate::gpu::GpuError>>>>;

/// The image the GPU traced, read back in a web page (the tracer's device is not the page's):
/// RGBA bytes, its size, and a number that changes with each new image.
#[derive(Debug, Clone)]
pub struct DisplayImage {
    /// Width and height.
    pub size: [u32; 2],
    /// RGBA, 8 bits a channel, rows top to bottom.
    pub rgba: Vec<u8>,
    /// Bumped for each image read back.
    pub generation: u64,
}

/// What the GPU traced for the scene as the app prepared it.
struct Traced {
    /// The prepared scene it was made for (pointer identity).
    key: usize,
    tracer: GpuTracer,
    /// The orbit the last frame was traced with, how long the trace pass took, and the samples
    /// per pixel the image holds so far (a Monte Carlo scene comes in passes of 1, 1, 2, 4, …
    /// samples, one a frame, on either path).
    frame: Option<(Orbit, GpuPath, Duration, u32)>,
    /// The debug pixel of (pixel, path), at the scene camera.
    pick: Option<([u32; 2], Answer<Readback, PixelDebug>)>,
    /// The comparison with the CPU render, for (the render it was made against, the GPU path),
    /// and a number that changes with each comparison made.
    diff: Option<Compared>,
    /// The GPU's own trace of a pixel.
    gpu_trace: Option<GpuTraced>,
    /// In a web page: the display image read back, the read on its way, and whether a frame
    /// was traced since it was asked for.
    shown: Option<DisplayImage>,
    display_read: Option<TextureReadback>,
    display_stale: bool,
}

/// The GPU's own trace of (pixel, sample), and how it compares with the CPU's.
struct GpuTraced {
    pixel: [u32; 2],
    sample: u32,
    path: GpuPath,
    result: Answer<(PendingTrace, Arc<Trace>), GpuTraceShown>,
    /// Show it in the stepper when it comes (the button was pressed).
    show: bool,
}

/// The GPU's trace of the selected pixel, compared with the CPU's.
pub struct GpuTraceShown {
    /// The GPU's trace.
    pub trace: Arc<Trace>,
    /// "the traces are equal: …" or "first divergence: step K (…)".
    pub verdict: String,
    /// The first step where it parts from the CPU's trace.
    pub divergence: Option<usize>,
    /// The log ran out.
    pub truncated: bool,
}

/// What the GPU view shows, in words (the web page's status element carries it,
/// [`crate::web::Status`]).
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

/// The GPU view's live state (part of [`super::AppState`]).
pub struct GpuState {
    /// The tracing context, made once (its arithmetic probe runs once): natively the app's own
    /// wgpu device ([`GpuState::attach`]); in a web page a WebGPU device opened on first use.
    context: Option<GpuContext>,
    /// In a web page: the WebGPU device being opened.
    opening: Option<Opening>,
    /// Why there is no tracing context (a browser without WebGPU).
    context_error: Option<String>,
    /// In a web page: the last frame's time from submit until the browser said the GPU was done.
    web_time: Arc<Mutex<Option<Duration>>>,
    /// Errors the browser reported late ([`GpuContext::late_errors`]), the last few.
    pub late_errors: Vec<String>,
    /// Fragment (rasterizer-interpolated primary rays) or compute.
    pub path: GpuPath,
    /// The camera orbit of the GPU view ([`Orbit::move_camera`]; [`Orbit::IDENTITY`] at first).
    pub orbit: Orbit,
    traced: Option<Traced>,
    /// Why the GPU view could not be made for the prepared scene (its key, the reason).
    error: Option<(usize, String)>,
    /// Why the last frame could not be traced, for (scene key, orbit, path): asked again only
    /// when one of them changes.
    frame_error: Option<((usize, Orbit, GpuPath), String)>,
    /// Numbers the comparisons and the display images are told apart by.
    generation: u64,
}

impl Default for GpuState {
    fn default() -> Self {
        GpuState {
            context: None,
            opening: None,
            context_error: None,
            web_time: Arc::default(),
            late_errors: vec![],
            path: GpuPath::default(),
            orbit: Orbit::IDENTITY,
            traced: None,
            error: None,
            frame_error: None,
            generation: 0,
        }
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

impl GpuState {
    /// Natively: the app's own wgpu device (eframe's), on which the GPU view traces, so that its
    /// image is one of egui's textures as it is. (In a web page the view opens a WebGPU device
    /// of its own on first use instead.)
    pub fn attach(&mut self, ctx: GpuContext) {
        self.context = Some(ctx);
        self.context_error = None;
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

    /// The generated WGSL of the tracer, once it exists.
    pub fn wgsl(&self) -> Option<&str> {
        Some(self.traced.as_ref()?.tracer.wgsl())
    }

    /// The GPU debug buffer of the selected pixel, once traced.
    pub fn pick(&self) -> Option<&Result<PixelDebug, String>> {
        self.traced.as_ref()?.pick.as_ref()?.1.done()
    }

    /// The CPU − GPU comparison once made (with the number that tells it from the one before),
    /// or why it failed; `None` while none was asked for or it is on its way.
    pub fn difference(&self) -> Option<Result<(&Difference, u64), &String>> {
        let d = self.traced.as_ref()?.diff.as_ref()?.1.done()?;
        Some(d.as_ref().map(|(d, g)| (d, *g)))
    }

    /// Whether the comparison asked for is on its way.
    pub fn comparing(&self) -> bool {
        matches!(
            self.traced.as_ref().and_then(|t| t.diff.as_ref()),
            Some((_, Answer::Waiting(_)))
        )
    }

    /// The GPU path of the comparison [`GpuState::difference`] holds.
    pub fn difference_path(&self) -> Option<GpuPath> {
        Some(self.traced.as_ref()?.diff.as_ref()?.0.1)
    }

    /// The GPU's trace of (pixel, sample) on the current path: `None` when it was not asked for,
    /// `Some(None)` while it is on its way.
    pub fn gpu_trace(
        &self,
        pixel: [u32; 2],
        sample: u32,
    ) -> Option<Option<&Result<GpuTraceShown, String>>> {
        let g = self.traced.as_ref()?.gpu_trace.as_ref()?;
        (g.pixel == pixel && g.sample == sample && g.path == self.path).then(|| g.result.done())
    }

    /// The key of the tracer's display texture and its size, natively (where egui shows the
    /// tracer's own texture): changes when the tracer or the size does.
    pub fn display_key(&self) -> Option<(usize, [u32; 2])> {
        let t = self.traced.as_ref()?;
        t.frame?;
        Some((t.key, [t.tracer.camera().width, t.tracer.camera().height]))
    }

    /// The tracer's display texture (natively, egui shows it as it is).
    pub fn display_view(&self) -> Option<&eframe::egui_wgpu::wgpu::TextureView> {
        Some(self.traced.as_ref()?.tracer.display_view())
    }

    /// In a web page: the last image read back from the tracer's device.
    pub fn shown(&self) -> Option<&DisplayImage> {
        self.traced.as_ref()?.shown.as_ref()
    }

    /// Why the GPU view cannot show the prepared scene: no WebGPU in this browser, the tracer
    /// could not be made for it, or its frame could not be traced (at this orbit and path).
    pub fn error_for(&self, prepared: &PreparedScene) -> Option<&str> {
        if let Some(e) = &self.context_error {
            return Some(e);
        }
        let key = key_of(prepared);
        match (&self.error, &self.frame_error) {
            (Some((k, e)), _) if *k == key => Some(e),
            (_, Some((k, e))) if *k == (key, self.orbit, self.path) => Some(e),
            _ => None,
        }
    }

    /// Whether [`GpuCmd::Frame`] has work to do for `prepared` and the selected `pixel`: no
    /// tracer yet, no frame at this orbit and path, passes of a Monte Carlo image still to
    /// trace, or the pixel's debug buffer not asked for. (The tab asks only then, so that a
    /// finished image costs no frames.)
    pub fn needs_frame(&self, prepared: &PreparedScene, pixel: Option<[u32; 2]>) -> bool {
        if self.error_for(prepared).is_some() {
            return false;
        }
        let Some(t) = self.traced.as_ref().filter(|t| t.key == key_of(prepared)) else {
            return true;
        };
        let spp = prepared.scene().settings.spp.max(1);
        let frame_due = match t.frame {
            Some((o, p, _, done)) => o != self.orbit || p != self.path || done < spp,
            None => true,
        };
        let pick_due = pixel.is_some_and(|px| match &t.pick {
            Some((_, Answer::Waiting(_))) => false,
            Some((p, _)) => *p != px,
            None => true,
        });
        frame_due || pick_due
    }

    /// Whether [`GpuCmd::Compare`] has work to do: no comparison with the CPU render numbered
    /// `render_id` on the current path, and none on its way.
    pub fn needs_compare(&self, prepared: &PreparedScene, render_id: u64) -> bool {
        if self.error_for(prepared).is_some() {
            return false;
        }
        let Some(t) = self.traced.as_ref().filter(|t| t.key == key_of(prepared)) else {
            return true;
        };
        match &t.diff {
            Some((_, Answer::Waiting(_))) => false,
            Some((k, _)) => *k != (render_id, self.path),
            None => true,
        }
    }

    /// Whether the tracer for `prepared` exists.
    pub fn ready_for(&self, prepared: &PreparedScene) -> bool {
        self.traced
            .as_ref()
            .is_some_and(|t| t.key == key_of(prepared))
    }

    /// What the view shows, in words.
    pub fn status(&self) -> GpuStatus {
        let mut s = GpuStatus::default();
        let Some(t) = &self.traced else {
            s.state = if self.context_error.is_some() {
                "no-webgpu".into()
            } else if let Some((_, e)) = &self.error {
                format!("error: {e}")
            } else if self.opening.is_some() {
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

    /// Whether an answer from the GPU is on its way (the view asks again next frame), or the
    /// WebGPU device is being opened.
    pub fn waiting(&self) -> bool {
        self.opening.is_some() && self.context.is_none() && self.context_error.is_none()
            || self.traced.as_ref().is_some_and(|t| {
                t.display_read.is_some()
                    || matches!(t.pick, Some((_, Answer::Waiting(_))))
                    || matches!(t.diff, Some((_, Answer::Waiting(_))))
                    || t.gpu_trace
                        .as_ref()
                        .is_some_and(|g| matches!(g.result, Answer::Waiting(_)))
            })
    }

    /// The tracing context: natively the one [`GpuState::attach`] gave; in a web page a WebGPU
    /// device of its own, opened in the background (`Ok(None)` until it is), while the page
    /// draws with WebGL2.
    fn context(&mut self) -> Result<Option<GpuContext>, String> {
        if let Some(c) = &self.context {
            return Ok(Some(c.clone()));
        }
        if let Some(e) = &self.context_error {
            return Err(e.clone());
        }
        if !crate::platform::IN_BROWSER {
            return Err("the app has no wgpu device".into());
        }
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
        match opened {
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
        }
    }

    /// Takes what has come back from the GPU (in a web page, between frames): the debug pixel,
    /// the comparison's image (compared with `cpu`, the CPU render numbered `render_id`, if it
    /// is still the one asked for), the GPU's trace, the displayed image; and the errors the
    /// browser reported late. Returns the GPU's trace of the pixel when it has come and the
    /// button asked for it to be shown.
    pub(super) fn poll(
        &mut self,
        cpu: Option<(&RenderOutput, u64)>,
    ) -> Option<(Arc<Trace>, Option<usize>)> {
        if self.context.is_none() && self.opening.is_some() {
            // The WebGPU device may have come (it is taken here, or by the next command).
            let _ = self.context();
        }
        if let Some(c) = &self.context {
            self.late_errors.extend(c.late_errors());
            let keep = self.late_errors.len().saturating_sub(4);
            self.late_errors.drain(..keep);
        }
        self.generation += 1;
        let generation = self.generation;
        let t = self.traced.as_mut()?;
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
            let cpu = cpu
                .filter(|(_, id)| *id == key.0)
                .map(|(out, _)| out)
                .ok_or_else(|| "the CPU render changed".to_string());
            let compared = bytes.map_err(|e| e.to_string()).and_then(|b| {
                let pixels = crate::gpu::linear_from(&b);
                let out = cpu?;
                crate::gpu::difference(out.width, out.height, &out.pixels, &pixels)
                    .map(|d| (d, generation))
            });
            t.diff = Some((*key, Answer::Done(compared)));
        }
        if let Some(r) = &mut t.display_read
            && let Some(bytes) = r.poll()
        {
            let size = r.size();
            t.display_read = None;
            match bytes {
                Ok(rgba) => {
                    t.shown = Some(DisplayImage {
                        size,
                        rgba,
                        generation,
                    })
                }
                Err(e) => self.error = Some((t.key, e.to_string())),
            }
        }
        if crate::platform::IN_BROWSER
            && t.display_read.is_none()
            && std::mem::take(&mut t.display_stale)
        {
            match t.tracer.start_read_display() {
                Ok(r) => t.display_read = Some(r),
                Err(e) => self.error = Some((t.key, e.to_string())),
            }
        }
        let g = t.gpu_trace.as_mut()?;
        if let Answer::Waiting((pending, cpu)) = &mut g.result
            && let Some(bytes) = pending.readback.poll()
        {
            let shown = bytes
                .and_then(|b| t.tracer.finish_trace_of(pending, &b))
                .map_err(|e| e.to_string())
                .map(|g| shown(cpu, g));
            g.result = Answer::Done(shown);
        }
        match (&g.result, g.show) {
            (Answer::Done(Ok(s)), true) => {
                g.show = false;
                Some((Arc::clone(&s.trace), s.divergence))
            }
            _ => None,
        }
    }

    /// The tracer for the prepared scene, made (shader generated and compiled, scene uploaded)
    /// the first time it is needed; `None` while the device is being opened or its arithmetic
    /// probe is on its way (in a web page: ask again next frame).
    fn tracer_for(&mut self, prepared: &PreparedScene) -> Result<Option<&mut Traced>, String> {
        let key = key_of(prepared);
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
                && ctx.info.device_type == eframe::egui_wgpu::wgpu::DeviceType::Cpu
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
            self.traced = None;
            match GpuTracer::new(ctx, prepared, ShaderVariant::Generated) {
                Ok(tracer) => {
                    self.traced = Some(Traced {
                        key,
                        tracer,
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

    /// [`GpuCmd::Frame`]: traces a frame when the orbit, the path or the scene changed (or the
    /// next pass of a Monte Carlo image), then the selected pixel into the debug buffer.
    pub(super) fn frame(&mut self, prepared: &PreparedScene, pixel: Option<[u32; 2]>) {
        if let Err(e) = self.trace_frame(prepared) {
            self.frame_error = Some(((key_of(prepared), self.orbit, self.path), e));
            return;
        }
        self.frame_error = None;
        if let Some(p) = pixel {
            self.pick_pixel(prepared, p);
        }
    }

    fn trace_frame(&mut self, prepared: &PreparedScene) -> Result<(), String> {
        let (orbit, path) = (self.orbit, self.path);
        let web_time = Arc::clone(&self.web_time);
        let Some(t) = self.tracer_for(prepared)? else {
            return Ok(());
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
        Ok(())
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

    /// [`GpuCmd::TracePixel`]: the GPU's own trace of (pixel, sample), at the scene's camera,
    /// compared with the CPU's trace `cpu` (made once per pixel, sample and path), put in the
    /// stepper when it comes.
    pub(super) fn trace_pixel(
        &mut self,
        prepared: &PreparedScene,
        pixel: [u32; 2],
        sample: u32,
        cpu: &Arc<Trace>,
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
            g.show = true;
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
            show: true,
        });
        settle(&t.tracer);
    }

    /// [`GpuCmd::Compare`]: renders on the GPU at the scene's camera and compares with the CPU
    /// render numbered `render_id` (once the image has come back).
    pub(super) fn compare(&mut self, prepared: &PreparedScene, render_id: u64) {
        let path = self.path;
        let t = match self.tracer_for(prepared) {
            Ok(Some(t)) => t,
            Ok(None) => return,
            Err(e) => {
                self.error = Some((key_of(prepared), e));
                return;
            }
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

/// The key a tracer is made for: the prepared scene's identity.
fn key_of(prepared: &PreparedScene) -> usize {
    Arc::as_ptr(prepared.scene_arc()) as usize
}

/// Natively: waits for the GPU, so that what was just asked for is there at the next poll (as
/// the view always did). In a web page: nothing (the answer comes between frames).
fn settle(tracer: &GpuTracer) {
    if !crate::platform::IN_BROWSER {
        let _ = tracer.context().wait();
    }
}

/// The GPU's trace compared with the CPU's.
fn shown(cpu: &Trace, g: crate::gpu::GpuTrace) -> GpuTraceShown {
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
