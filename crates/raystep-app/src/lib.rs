//! The raystep app (eframe, wgpu renderer): click a pixel of the full render, then step through
//! everything the tracer did for it — the trace as a tree and a timeline, the formula of the
//! current step with its numbers, and the diagrams that explain it.
//!
//! [`state`] owns the data and is the only place it changes (through [`state::Command`]s);
//! [`panels`] draw read-only views of it and return commands, each panel in its own module
//! with what it keeps between frames; [`job`] renders in the background; [`view`] is the
//! zoomable render view, [`scene3d`] the 3D view and its editor; [`actions`] is the one table
//! of what the menus, the buttons and the keys do. [`RaystepApp::frame`] draws one whole
//! frame into any [`egui::Ui`], so tests (egui_kittest) and the benchmark drive the very UI
//! the window shows.
#![deny(unsafe_code)]
#![warn(missing_docs)]

// The layers below, by the names the modules use for them.
use raystep_core::{
    accel, assets, explain, io, math, platform, record, render, scene, shapes, text, trace,
};
use raystep_course::{lesson, stability};
use raystep_diagram as diagram;
use raystep_gpu as gpu;
use raystep_gpu::view3d;

pub mod actions;
pub mod crash;
pub mod files;
pub mod gpu_view;
pub mod job;
pub mod lab;
pub mod layout;
pub mod panels;
pub mod prefs;
pub mod scene3d;
pub mod state;
mod stepping;
pub mod view;

/// The lessons and exercises: their state ([`state::learn`]) and their panel
/// ([`panels::learn`]).
pub use layout::window_height_at_zoom_1;
pub use state::learn;
mod watch;
pub mod web;

use crate::platform::{Duration, Instant};
use state::{AppState, Command, Prefs, StepMove, ThemeChoice};
use std::path::PathBuf;

/// Where `raystep open` starts: a pixel to select and a step to show once the render has
/// finished (`--pixel`, `--step`: where the grader's feedback points a student), and maybe a
/// screenshot of the window to take then, after which the app closes (`--screenshot`: the real
/// window's picture, under Xvfb for example).
#[derive(Debug, Clone, Default)]
pub struct ScreenshotPlan {
    /// Where to write the PNG (None: no screenshot; the app stays open).
    pub path: Option<PathBuf>,
    /// The pixel to select first.
    pub pixel: Option<[u32; 2]>,
    /// The step to show.
    pub step: Option<usize>,
    settled: u32,
    requested: bool,
}

impl ScreenshotPlan {
    /// A plan to select `pixel`, go to `step`, then write `path` if given.
    pub fn new(path: Option<PathBuf>, pixel: Option<[u32; 2]>, step: Option<usize>) -> Self {
        ScreenshotPlan {
            path,
            pixel,
            step,
            ..Default::default()
        }
    }
}

/// The app.
pub struct RaystepApp {
    /// Everything it shows.
    pub state: AppState,
    /// The render view: its texture, zoom and pan (not persisted).
    pub render: view::RenderView,
    /// What the other panels keep between frames (not persisted, rebuilt on demand).
    pub panels: panels::Panels,
    applied: Option<(ThemeChoice, f32)>,
    fullscreen: bool,
    /// How long the last frames took to build (the UI's own time, without painting), newest last.
    pub frame_times: Vec<Duration>,
    /// A screenshot to take, if asked for.
    pub screenshot: Option<ScreenshotPlan>,
    /// The page address's `#…` last followed (the browser build; see [`web::follow`]).
    pub link: String,
}

impl std::fmt::Debug for RaystepApp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RaystepApp")
            .field("state", &self.state)
            .finish_non_exhaustive()
    }
}

/// The storage key of the preferences.
const PREFS_KEY: &str = "raystep-prefs";

impl RaystepApp {
    /// The app on `ctx`, with remembered preferences, opening `file` (a scene or a saved trace),
    /// else the last file opened (if it still loads), else the built-in scene.
    pub fn with_context(ctx: &egui::Context, prefs: Prefs, file: Option<PathBuf>) -> RaystepApp {
        install_fonts(ctx);
        let prefs = prefs.validated();
        let repaint_ctx = ctx.clone();
        let mut state = AppState::new(prefs, move || repaint_ctx.request_repaint());
        // A file that fails to load shows its error over the built-in scene.
        match file.or_else(|| {
            state
                .prefs
                .last_file
                .clone()
                .filter(|p| crate::platform::files::is_file(p))
        }) {
            Some(p) => state.open(&p),
            None => state.apply(Command::OpenBuiltin),
        }
        RaystepApp {
            state,
            render: view::RenderView::default(),
            panels: panels::Panels::default(),
            applied: None,
            fullscreen: false,
            frame_times: vec![],
            screenshot: None,
            link: String::new(),
        }
    }

    /// The app as eframe creates it.
    pub fn new(cc: &eframe::CreationContext<'_>, file: Option<PathBuf>) -> RaystepApp {
        let mut prefs = cc
            .storage
            .and_then(|s| eframe::get_value::<Prefs>(s, PREFS_KEY))
            .unwrap_or_default();
        // The place a crash saved last time, if any, wins over the remembered preferences.
        let dir = crash::state_dir();
        let place = dir.as_deref().and_then(crash::recover);
        let mut file = file;
        if let Some(p) = &place {
            prefs = p.prefs.clone();
            if file.is_none() {
                file = p.file.clone();
            }
        }
        let mut app = Self::with_context(&cc.egui_ctx, prefs, file.clone())
            .with_wgpu(cc.wgpu_render_state.clone());
        if let (Some(p), Some(dir)) = (place, dir) {
            if let (Some(f), Some(pixel)) = (&p.file, p.pixel)
                && file.as_ref() == Some(f)
            {
                app.state.open_prepared(f, None, Some(pixel), p.step);
            }
            app.state.message = Some(state::Message {
                text: format!(
                    "raystep stopped on an error last time: your place was taken back; the report is {}",
                    dir.join(crash::REPORT_FILE).display()
                ),
                error: true,
            });
        }
        app
    }

    /// Gives the app eframe's wgpu device, which turns on the GPU view (the tabs "GPU render"
    /// and "CPU − GPU" above the render).
    pub fn with_wgpu(mut self, render_state: Option<eframe::egui_wgpu::RenderState>) -> Self {
        // Natively the GPU view traces on eframe's own device; in a web page it opens a WebGPU
        // device of its own on first use (the page may draw with WebGL2).
        if let Some(rs) = &render_state
            && !crate::platform::IN_BROWSER
        {
            self.state.gpu.attach(crate::gpu::GpuContext::from_device(
                rs.device.clone(),
                rs.queue.clone(),
                rs.adapter.get_info(),
                rs.adapter.features(),
            ));
        }
        self.panels.gpu.render_state = render_state;
        self
    }

    /// Draws one frame into `ui` (the whole window) and applies what the user asked for.
    pub fn frame(&mut self, ui: &mut egui::Ui) {
        let start = Instant::now();
        let ctx = ui.ctx().clone();
        // In the browser, long jobs (the render's passes) take their steps between frames.
        if crate::platform::run_steps(Duration::from_millis(30)) {
            if crate::platform::steps_wait() {
                // The render's Web Workers trace: a look every 50 ms shows their tiles, and
                // leaves the page's core to the drawing (with a software GPU, drawing every
                // frame starved it: frames of 0.7 s while the Cornell box rendered).
                ctx.request_repaint_after(Duration::from_millis(50));
            } else {
                ctx.request_repaint();
            }
        }
        self.state.tick(start);
        self.apply_look(&ctx);
        let mut cmds = vec![];
        self.keyboard(&ctx, &mut cmds);
        self.dropped_files(&ctx, &mut cmds);
        panels::show(
            ui,
            &self.state,
            &mut self.render,
            &mut self.panels,
            &mut cmds,
        );
        let mut fullscreen_toggle = false;
        // The panels were drawn before the commands are applied, so a frame that applies any
        // asks for another one to show the result. Input brings a second pass anyway; a click
        // that becomes a selection on a timer (after the double-click time) does not, and its
        // pixel would otherwise wait for the next mouse move to appear.
        if !cmds.is_empty() {
            ctx.request_repaint();
        }
        for c in cmds {
            if let Command::SetPrefs(p) = &c
                && p.presentation != self.state.prefs.presentation
            {
                fullscreen_toggle = p.presentation != self.fullscreen;
            }
            self.state.apply(c);
        }
        crash::remember(&self.state);
        #[cfg(target_arch = "wasm32")]
        web::publish(&web::Status::of(&self.state));
        // A way to check the crash recovery end to end in a real window: debug builds only, and
        // only when asked for by the environment.
        #[cfg(debug_assertions)]
        if std::env::var_os("RAYSTEP_DEBUG_PANIC_KEY").is_some()
            && ctx.input(|i| i.key_pressed(egui::Key::F12))
        {
            panic!("a panic asked for with F12 (RAYSTEP_DEBUG_PANIC_KEY, debug builds only)");
        }
        if std::mem::take(&mut self.panels.toggle_fullscreen) {
            fullscreen_toggle = true;
        }
        if fullscreen_toggle {
            self.fullscreen = !self.fullscreen;
            ctx.send_viewport_cmd(egui::ViewportCommand::Fullscreen(self.fullscreen));
        }
        self.screenshot_step(&ctx);
        if self.state.busy() || self.state.exporting() {
            ctx.request_repaint_after(Duration::from_millis(100));
        } else if let Some(d) = self.state.next_wakeup() {
            ctx.request_repaint_after(d);
        }
        self.frame_times.push(start.elapsed());
        if self.frame_times.len() > 240 {
            self.frame_times.remove(0);
        }
    }

    /// Takes the planned screenshot once the render is done and the UI has settled, then closes.
    fn screenshot_step(&mut self, ctx: &egui::Context) {
        let Some(plan) = &mut self.screenshot else {
            return;
        };
        if plan.requested || self.state.busy() || self.state.prepared.is_none() {
            return;
        }
        if plan.settled == 0 {
            if let Some(p) = plan.pixel {
                self.state.apply(Command::SelectPixel(p));
            }
            if let Some(k) = plan.step {
                self.state.apply(Command::Step(StepMove::To(k)));
            }
        }
        plan.settled += 1;
        ctx.request_repaint();
        let Some(path) = plan.path.clone() else {
            // Only a place to start: done.
            self.screenshot = None;
            return;
        };
        // A few frames for panel sizes and textures to settle.
        if plan.settled < 10 {
            return;
        }
        plan.requested = true;
        let close = ctx.clone();
        ctx.request_screenshot(move |img| {
            let [w, h] = img.size;
            let bytes: Vec<u8> = img.pixels.iter().flat_map(|c| c.to_array()).collect();
            let result = image::RgbaImage::from_raw(w as u32, h as u32, bytes)
                .ok_or_else(|| "the screenshot has the wrong size".to_string())
                .and_then(|rgba| {
                    let mut png = vec![];
                    image::DynamicImage::ImageRgba8(rgba)
                        .to_rgb8()
                        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
                        .map_err(|e| format!("cannot encode PNG: {e}"))?;
                    crate::io::write_atomic(&path, &png)
                });
            match result {
                Ok(()) => eprintln!("wrote {} ({w}×{h})", crate::io::full_path(&path)),
                Err(e) => eprintln!("error: {}: {e}", path.display()),
            }
            close.send_viewport_cmd(egui::ViewportCommand::Close);
        });
    }

    /// Sets the egui theme and scale when the preferences change.
    fn apply_look(&mut self, ctx: &egui::Context) {
        let look = (
            self.state.prefs.effective_theme(),
            // Rounded, so a window resized by a few points does not restyle.
            (self
                .state
                .prefs
                .effective_scale_for(window_height_at_zoom_1(ctx))
                * 100.0)
                .round()
                / 100.0,
        );
        if self.applied == Some(look) {
            return;
        }
        self.applied = Some(look);
        let visuals = match look.0 {
            ThemeChoice::Light => egui::Visuals::light(),
            ThemeChoice::Dark => egui::Visuals::dark(),
            ThemeChoice::HighContrast => {
                let mut v = egui::Visuals::dark();
                v.override_text_color = Some(egui::Color32::WHITE);
                v.panel_fill = egui::Color32::BLACK;
                v.window_fill = egui::Color32::BLACK;
                v.extreme_bg_color = egui::Color32::BLACK;
                v.widgets.noninteractive.bg_stroke = egui::Stroke::new(1.5, egui::Color32::WHITE);
                v.selection.bg_fill = egui::Color32::from_rgb(0, 90, 200);
                v.selection.stroke = egui::Stroke::new(2.0, egui::Color32::YELLOW);
                v
            }
        };
        ctx.set_visuals(visuals);
        ctx.set_zoom_factor(look.1.clamp(0.5, 4.0));
    }

    /// The keys of the table of actions ([`actions`]), unless a text field has the keyboard.
    fn keyboard(&mut self, ctx: &egui::Context, cmds: &mut Vec<Command>) {
        let pressed = actions::pressed(ctx, &self.state);
        let to = &mut actions::Targets {
            state: &self.state,
            ctx,
            render: &mut self.render,
            toggle_fullscreen: &mut self.panels.toggle_fullscreen,
            lab_open: &mut self.panels.lab.open,
            cmds,
        };
        for a in pressed {
            a.perform(to);
        }
    }

    /// Files dropped on the window open like File → Open.
    fn dropped_files(&mut self, ctx: &egui::Context, cmds: &mut Vec<Command>) {
        // In the browser a dropped file has no path: its bytes are read (later: a browser reads
        // files asynchronously) into the page's memory, and it opens when it has arrived.
        #[cfg(target_arch = "wasm32")]
        for f in ctx.input(|i| i.raw.dropped_files.clone()) {
            let repaint = ctx.clone();
            crate::platform::browser::spawn_local(async move {
                let name = f.path().display().to_string();
                crate::platform::browser::receive(&name, f.bytes_async().await);
                repaint.request_repaint();
            });
        }
        // The files the browser's picker or a drop read in: the first scene or trace among them
        // opens (the others, an OBJ and its MTL, are there for it to read).
        let arrived = crate::platform::browser::arrived();
        let mut opened = false;
        for a in arrived {
            match a {
                Ok(p)
                    if !opened
                        && p.extension().is_some_and(|e| {
                            e == "toml" || e == "json" || e == "gltf" || e == "glb"
                        }) =>
                {
                    opened = true;
                    cmds.push(Command::Open(p));
                }
                Ok(_) => {}
                Err(e) => cmds.push(Command::ShowError(e)),
            }
        }
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .filter(|p| !p.as_os_str().is_empty())
                .collect()
        });
        if let Some(p) = dropped.into_iter().next() {
            cmds.push(Command::Open(p));
        }
    }
}

/// DejaVu Sans (and Sans Mono) first: they have every symbol the math panel writes — Greek,
/// sub- and superscripts (θᵢ, t₁, γ₃), arrows, √, ≤, ≫ — which egui's default fonts lack, and they
/// read well on a projector. egui's own fonts stay as fallbacks (icons).
fn install_fonts(ctx: &egui::Context) {
    use egui::{FontData, FontDefinitions, FontFamily};
    let mut fonts = FontDefinitions::default();
    fonts.font_data.insert(
        "dejavu-sans".into(),
        std::sync::Arc::new(FontData::from_static(dejavu::sans::regular())),
    );
    fonts.font_data.insert(
        "dejavu-sans-mono".into(),
        std::sync::Arc::new(FontData::from_static(dejavu::sans_mono::regular())),
    );
    // The emoji/icon font egui used to ship: the Markdown viewer's code-block copy button (🗐).
    fonts.font_data.insert(
        "emoji-icons".into(),
        std::sync::Arc::new(FontData::from_static(epaint_default_fonts::EMOJI_ICON)),
    );
    let prop = fonts.families.entry(FontFamily::Proportional).or_default();
    prop.insert(0, "dejavu-sans".into());
    prop.push("emoji-icons".into());
    let mono = fonts.families.entry(FontFamily::Monospace).or_default();
    mono.insert(0, "dejavu-sans-mono".into());
    mono.insert(1, "dejavu-sans".into());
    ctx.set_fonts(fonts);
}

impl eframe::App for RaystepApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        // A link pasted into the page's address (only its `#…` changed) goes there.
        #[cfg(target_arch = "wasm32")]
        web::follow(self, &_frame.info().web_info.location.hash);
        self.frame(ui);
    }

    /// In the browser the answers and preferences are saved every few seconds: a page can be
    /// closed at any moment (natively they are saved on quitting too).
    fn auto_save_interval(&self) -> Duration {
        if crate::platform::IN_BROWSER {
            Duration::from_secs(3)
        } else {
            Duration::from_secs(30)
        }
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        // An embedded figure keeps nothing (see `web::follow`).
        if self.state.embed.is_some() {
            return;
        }
        eframe::set_value(storage, PREFS_KEY, &self.state.prefs);
    }
}

/// eframe's wgpu set-up with what the GPU view needs ([`gpu_view_device`]); everything else is
/// eframe's default (its limits, with 8192² textures for 4K displays).
pub fn wgpu_options() -> eframe::egui_wgpu::WgpuConfiguration {
    use eframe::egui_wgpu::{WgpuConfiguration, WgpuSetup, WgpuSetupCreateNew};
    WgpuConfiguration {
        wgpu_setup: gpu_view_device(WgpuSetup::CreateNew(
            WgpuSetupCreateNew::without_display_handle(),
        )),
        ..Default::default()
    }
}

/// `setup` (when it creates its own device) asking also for what the GPU view uses where the
/// adapter offers it: SPIR-V passthrough (the compute path then runs as SPIR-V with every float
/// result decorated `NoContraction`, the exact arithmetic `raystep compare` uses; see
/// `gpu::exact`), and as many storage buffers per shader stage as the adapter allows, up to 16
/// (the Monte Carlo tracer binds 9 or 10: the scene's buffers, its lights and BSDFs, the running
/// sums; WebGPU's default is 8).
pub fn gpu_view_device(setup: eframe::egui_wgpu::WgpuSetup) -> eframe::egui_wgpu::WgpuSetup {
    use eframe::egui_wgpu::{WgpuSetup, wgpu};
    let WgpuSetup::CreateNew(mut create) = setup else {
        return setup;
    };
    let base = create.device_descriptor.clone();
    create.device_descriptor = std::sync::Arc::new(move |adapter: &wgpu::Adapter| {
        let mut d = base(adapter);
        d.required_features |= adapter.features() & wgpu::Features::PASSTHROUGH_SHADERS;
        let offered = adapter.limits().max_storage_buffers_per_shader_stage;
        let l = &mut d.required_limits;
        l.max_storage_buffers_per_shader_stage =
            l.max_storage_buffers_per_shader_stage.max(offered.min(16));
        d
    });
    WgpuSetup::CreateNew(create)
}

/// Opens the app window on `file` (or the last/built-in scene) and runs until it is closed;
/// with a `screenshot` plan, writes it and closes. (In the browser: [`web::start`].)
#[cfg(not(target_arch = "wasm32"))]
pub fn run(file: Option<PathBuf>, screenshot: Option<ScreenshotPlan>) -> Result<(), String> {
    if let Some(p) = &file
        && !p.exists()
    {
        return Err(format!("{}: no such file", p.display()));
    }
    if let Some(dir) = crash::state_dir() {
        crash::install(dir);
    }
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("raystep")
            .with_inner_size([1440.0, 900.0])
            .with_min_inner_size([800.0, 500.0])
            .with_drag_and_drop(true),
        wgpu_options: wgpu_options(),
        ..Default::default()
    };
    eframe::run_native(
        "raystep",
        options,
        Box::new(move |cc| {
            let mut app = RaystepApp::new(cc, file);
            app.screenshot = screenshot;
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| {
        format!(
            "cannot open the app window: {e}\n  (the app needs a display; without one, use the command line — `raystep --help` — \
             or run it under Xvfb: `xvfb-run raystep`)"
        )
    })
}
