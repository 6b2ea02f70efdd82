//! The app's state: one [`AppState`] owns everything — the open scene or trace, the live
//! settings, the background render, the selected pixel's trace and the step being shown. Panels
//! read it and return [`Command`]s; [`AppState::apply`] is the only place that changes it.

mod command;
pub mod editing;
pub mod gpu;
pub mod lab;
pub mod learn;
mod save;

use super::job::{JobEvent, RenderJob, is_cancelled};
use super::layout::Layout;
pub use super::prefs::{DiagramChoice, PRESENTATION_HEIGHT, Prefs, SavedLayout, ThemeChoice};
pub use super::stepping::Stepping;
use super::watch::{Watch, modified};
use crate::diagram::{self, DiagramKind, ViewOptions};
use crate::lesson::LessonSettings;
use crate::platform::{Duration, Instant};
use crate::record::Trace;
use crate::render::RenderOutput;
use crate::scene::{Scene, Settings};
use crate::trace::PreparedScene;
pub use command::{CONVERGE_PACE, Command, Dialog, SaveKind, StepMove};
use learn::Learn;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// What is open.
#[derive(Debug, Clone)]
pub enum Document {
    /// Nothing yet (only before the first open).
    Empty,
    /// A scene: the built-in one (`path` None) or a file.
    Scene {
        /// The scene as loaded (its own settings).
        scene: Arc<Scene>,
        /// Its file.
        path: Option<PathBuf>,
    },
    /// A saved trace, replayed without its scene.
    Trace {
        /// Its file.
        path: PathBuf,
    },
}

/// A message for the status line.
#[derive(Debug, Clone, PartialEq)]
pub struct Message {
    /// The text.
    pub text: String,
    /// Whether it reports a failure.
    pub error: bool,
}

/// The finished render.
#[derive(Debug, Clone)]
pub struct Rendered {
    /// The image, statistics and node visits.
    pub output: Arc<RenderOutput>,
    /// Time from the job's start to its end (prepare + build + trace).
    pub wall: Duration,
    /// Accelerator build time.
    pub build: Duration,
}

/// A scene file loading on a background thread.
struct Loading {
    path: PathBuf,
    keep: Option<(Option<[u32; 2]>, usize)>,
    result: std::sync::mpsc::Receiver<Result<Scene, String>>,
}

/// The whole state of the app.
pub struct AppState {
    /// Remembered preferences.
    pub prefs: Prefs,
    /// What is open.
    pub doc: Document,
    /// The live settings (start as the scene's own).
    pub settings: Settings,
    /// The scene ready to trace with the live settings (None while preparing).
    pub prepared: Option<Arc<PreparedScene>>,
    /// The running render.
    pub job: Option<RenderJob>,
    /// The last finished render (for the current settings once `job` is None).
    pub rendered: Option<Rendered>,
    /// How many renders were started (tests watch it restart).
    pub renders_started: u64,
    /// The selected pixel.
    pub pixel: Option<[u32; 2]>,
    /// The sample of the selected pixel.
    pub sample: u32,
    /// The selected pixel's trace.
    pub stepping: Option<Stepping>,
    /// The current step (timeline index).
    pub step: usize,
    /// Playing the steps.
    pub playing: bool,
    /// Adding the pixel's samples one at a time (the traced sample advances at the play speed).
    pub sample_playing: bool,
    /// The last load error (file:line:column and what is wrong), shown until a good load.
    pub load_error: Option<String>,
    /// The status line.
    pub message: Option<Message>,
    /// The open dialog.
    pub dialog: Option<Dialog>,
    /// Bumped whenever the trace changes (caches key on it).
    pub trace_generation: u64,
    /// The stepper shows the GPU's own trace of the pixel ([`Command::ShowGpuTrace`]), not the
    /// CPU's.
    pub showing_gpu_trace: bool,
    /// While the GPU's trace is shown: the first step where it parts from the CPU's.
    pub divergence: Option<usize>,
    /// The lessons and the exercise session.
    pub learn: Learn,
    /// The stability lab's runs (the suite, the comparison of strategies) and their results.
    pub lab: lab::Lab,
    /// The GPU view's tracer, its frame and the answers asked of the GPU.
    pub gpu: gpu::GpuState,
    /// The open scene's TOML document being edited (None: not editable, e.g. an exercise's
    /// variant or a saved trace).
    pub editor: Option<crate::scene::edit::SceneDoc>,
    /// The file the editor saves to (None: the built-in scene, saved with "Save as").
    pub editor_path: Option<PathBuf>,
    /// The selected object group (the 3D view and the editor).
    pub selected: Option<u32>,
    /// Embedded in a page (the book's live figures, `#embed&…`): the compact window — the
    /// render, the stepper and the diagram — with a link to the full app at this address.
    pub embed: Option<String>,
    /// How many edits were applied (views key their caches on it).
    pub edits: u64,
    /// Settings a lesson laid over the file it opened (kept when that file reloads).
    overrides: Option<(PathBuf, LessonSettings)>,
    last_play: Option<Instant>,
    last_sample_play: Option<Instant>,
    loading: Option<Loading>,
    exports: Vec<std::sync::mpsc::Receiver<Message>>,
    watch: Option<Watch>,
    /// The status message last seen by [`AppState::tick`] and when it appeared.
    message_seen: Option<(Message, Instant)>,
    repaint: Arc<dyn Fn() + Send + Sync>,
}

impl std::fmt::Debug for AppState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AppState")
            .field("doc", &self.doc)
            .field("pixel", &self.pixel)
            .field("step", &self.step)
            .finish_non_exhaustive()
    }
}

impl AppState {
    /// A state with nothing open. `repaint` wakes the UI (background jobs call it).
    pub fn new(prefs: Prefs, repaint: impl Fn() + Send + Sync + 'static) -> AppState {
        AppState {
            prefs: prefs.clone(),
            doc: Document::Empty,
            settings: Settings::default(),
            prepared: None,
            job: None,
            rendered: None,
            renders_started: 0,
            pixel: None,
            sample: 0,
            stepping: None,
            step: 0,
            playing: false,
            load_error: None,
            message: None,
            dialog: None,
            trace_generation: 0,
            showing_gpu_trace: false,
            divergence: None,
            learn: Learn::load(&prefs.student),
            lab: lab::Lab::default(),
            gpu: gpu::GpuState::default(),
            editor: None,
            editor_path: None,
            selected: None,
            embed: None,
            edits: 0,
            overrides: None,
            last_play: None,
            sample_playing: false,
            last_sample_play: None,
            loading: None,
            exports: vec![],
            watch: None,
            message_seen: None,
            repaint: Arc::new(repaint),
        }
    }

    /// The open scene, if a scene is open.
    pub fn scene(&self) -> Option<&Arc<Scene>> {
        match &self.doc {
            Document::Scene { scene, .. } => Some(scene),
            _ => None,
        }
    }

    /// The open file, if any.
    pub fn path(&self) -> Option<&Path> {
        match &self.doc {
            Document::Scene { path, .. } => path.as_deref(),
            Document::Trace { path } => Some(path),
            Document::Empty => None,
        }
    }

    /// Applies one command.
    pub fn apply(&mut self, cmd: Command) {
        match cmd {
            Command::Open(path) => {
                self.overrides = None;
                self.open(&path)
            }
            Command::OpenBuiltin => {
                self.set_scene(Arc::new(crate::scene::default_scene()), None);
                self.editor = Self::make_editor(crate::scene::DEFAULT_SCENE, None);
                self.editor_path = None;
            }
            Command::Reload => self.reload(),
            Command::SetSettings(s) => {
                if s != self.settings {
                    self.settings = s;
                    if self.sample >= self.settings.spp {
                        self.sample = 0;
                    }
                    self.restart_render();
                }
            }
            Command::ShowGpuTrace(trace, divergence) => {
                if self.pixel == Some(trace.pixel) {
                    let stepping = Stepping::new((*trace).clone(), Duration::ZERO);
                    self.step = self.step.min(stepping.len().saturating_sub(1));
                    self.stepping = Some(stepping);
                    self.trace_generation += 1;
                    self.showing_gpu_trace = true;
                    self.divergence = divergence;
                }
            }
            Command::ShowCpuTrace => {
                if self.showing_gpu_trace {
                    self.retrace(true);
                }
            }
            Command::SelectPixel(p) => {
                self.pixel = Some(p);
                self.playing = false;
                self.sample_playing = false;
                self.retrace(false);
            }
            Command::SetSample(s) => {
                self.sample = s.min(self.settings.spp.saturating_sub(1));
                self.retrace(true);
            }
            Command::Step(m) => {
                self.move_step(m);
                if m != StepMove::Next {
                    self.playing = false;
                }
            }
            Command::WatchConverge => self.restart_render_paced(Some(CONVERGE_PACE)),
            Command::ToggleSamplePlay => {
                self.sample_playing = !self.sample_playing;
                if self.sample_playing && self.sample + 1 >= self.settings.spp {
                    self.sample = 0;
                    self.retrace(true);
                }
                self.last_sample_play = None;
            }
            Command::TogglePlay => {
                self.playing = !self.playing;
                if self.playing
                    && let Some(s) = &self.stepping
                    && self.step + 1 >= s.len()
                {
                    self.step = 0;
                }
                self.last_play = None;
            }
            Command::SetPrefs(p) => {
                let on = p.presentation;
                let mut p = p;
                // The presentation switch goes through `with_presentation` from the old prefs,
                // so the layout it saves is the one that was on screen.
                if on != self.prefs.presentation {
                    p.presentation = self.prefs.presentation;
                    p = p.with_presentation(on);
                }
                self.prefs = p;
            }
            Command::DismissError => self.load_error = None,
            Command::ResetLayout => {
                self.prefs.layout = if self.prefs.presentation {
                    Layout::presentation()
                } else {
                    Layout::default()
                };
            }
            Command::Save(kind, path) => self.save(kind, &path),
            Command::ShowDialog(d) => self.dialog = Some(d),
            Command::CloseDialog => self.dialog = None,
            Command::ShowError(text) => self.message = Some(Message { text, error: true }),
            Command::Learn(c) => self.apply_learn(c),
            Command::Edit(c) => self.apply_edit(c),
            Command::Lab(lab::LabCmd::RunSuite) => self.lab.start_suite(Arc::clone(&self.repaint)),
            Command::Lab(lab::LabCmd::CompareStrategies) => {
                if let Some(p) = &self.prepared {
                    let scene = p.scene().clone();
                    self.lab.compare(scene, Arc::clone(&self.repaint));
                }
            }
            Command::Gpu(c) => self.apply_gpu(c),
        }
    }

    /// Applies a [`gpu::GpuCmd`].
    fn apply_gpu(&mut self, c: gpu::GpuCmd) {
        use gpu::GpuCmd;
        match c {
            GpuCmd::SetPath(p) => self.gpu.path = p,
            GpuCmd::SetOrbit(o) => self.gpu.orbit = o,
            GpuCmd::Frame => {
                if let Some(p) = self.prepared.clone() {
                    self.gpu.frame(&p, self.pixel);
                }
            }
            GpuCmd::Compare => {
                if self.job.is_none()
                    && self.rendered.is_some()
                    && let Some(p) = self.prepared.clone()
                {
                    self.gpu.compare(&p, self.renders_started);
                }
            }
            GpuCmd::TracePixel => {
                if let (Some(p), Some(pixel), Some(s)) =
                    (self.prepared.clone(), self.pixel, &self.stepping)
                {
                    let cpu = Arc::clone(&s.trace);
                    self.gpu.trace_pixel(&p, pixel, self.sample, &cpu);
                }
            }
        }
    }

    /// Opens a scene (.toml, .gltf, .glb) or saved trace (.json) file. A file that fails to load leaves what
    /// was open in place and shows the error.
    pub fn open(&mut self, path: &Path) {
        self.open_keeping(path, None);
    }

    /// Opens `path`; a scene loads on a background thread (a million-triangle OBJ takes most of
    /// a second) and replaces what is open when it arrives, keeping `keep` = (pixel, step).
    fn open_keeping(&mut self, path: &Path, keep: Option<(Option<[u32; 2]>, usize)>) {
        let overrides = self
            .overrides
            .as_ref()
            .filter(|(p, _)| p == path)
            .map(|(_, o)| o.clone());
        self.load_with(path, keep, overrides);
    }

    /// Opens the scene `path` with `overrides` laid over its settings (a lesson's), selecting
    /// `pixel` and going to `step` once it is traced.
    pub(super) fn open_prepared(
        &mut self,
        path: &Path,
        overrides: Option<LessonSettings>,
        pixel: Option<[u32; 2]>,
        step: usize,
    ) {
        self.overrides = overrides.clone().map(|o| (path.to_path_buf(), o));
        self.load_with(path, Some((pixel, step)), overrides);
    }

    /// Shows a scene made here (an exercise's variant) at `pixel`, on `step` once it is traced.
    pub(super) fn show_scene(&mut self, scene: Scene, pixel: [u32; 2], step: usize) {
        self.overrides = None;
        self.set_scene(Arc::new(scene), None);
        self.pixel = Some(pixel);
        self.step = step;
    }

    fn load_with(
        &mut self,
        path: &Path,
        keep: Option<(Option<[u32; 2]>, usize)>,
        overrides: Option<LessonSettings>,
    ) {
        self.dialog = None;
        self.watch = Some(Watch::start(path, Arc::clone(&self.repaint)));
        let is_trace = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        if is_trace {
            let result = Trace::load(path)
                .map_err(|e| e.to_string())
                .map(|t| self.open_trace(t, path));
            self.loaded(path, result);
            return;
        }
        let (tx, rx) = std::sync::mpsc::channel();
        let file = path.to_path_buf();
        let repaint = Arc::clone(&self.repaint);
        let laid = overrides;
        crate::platform::spawn(move || {
            let loaded = crate::scene::load_file(&file)
                .map_err(|e| e.to_string())
                .and_then(|mut scene| {
                    if let Some(o) = &laid {
                        o.apply(&mut scene)?;
                    }
                    Ok(scene)
                });
            let _ = tx.send(loaded);
            repaint();
        });
        self.loading = Some(Loading {
            path: path.to_path_buf(),
            keep,
            result: rx,
        });
    }

    /// Records the outcome of opening `path`.
    fn loaded(&mut self, path: &Path, result: Result<(), String>) {
        match result {
            Ok(()) => {
                self.load_error = None;
                // Remembered absolute: the next start may be in another folder.
                let abs = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
                self.prefs.last_file = Some(abs.clone());
                self.prefs.recent.retain(|p| *p != abs);
                self.prefs.recent.insert(0, abs);
                self.prefs.recent.truncate(8);
            }
            Err(e) => {
                if matches!(self.doc, Document::Empty) {
                    // Nothing was open yet: show the error over the built-in scene (still
                    // watching the file, so fixing it opens it).
                    let watch = self.watch.take();
                    self.set_scene(Arc::new(crate::scene::default_scene()), None);
                    self.watch = watch;
                }
                // On stderr too: the terminal that started the app sees why it shows something else.
                eprintln!("error: {e}");
                self.load_error = Some(e);
            }
        }
    }

    /// Takes a finished background load.
    fn take_load(&mut self) {
        let Some(l) = &self.loading else {
            return;
        };
        let result = match l.result.try_recv() {
            Ok(r) => r,
            Err(std::sync::mpsc::TryRecvError::Empty) => return,
            Err(std::sync::mpsc::TryRecvError::Disconnected) => Err(format!(
                "{}: loading stopped unexpectedly",
                l.path.display()
            )),
        };
        let l = self.loading.take().expect("checked above");
        let result = result.map(|scene| {
            self.set_scene(Arc::new(scene), Some(l.path.clone()));
            if let Some((pixel, step)) = l.keep {
                self.pixel = pixel;
                self.step = step;
            }
        });
        self.loaded(&l.path, result);
    }

    /// Whether a scene is loading or a render is running.
    pub fn busy(&self) -> bool {
        self.loading.is_some() || self.job.is_some()
    }

    /// Opens again the file last asked for (the one a load error is about, else the open one).
    fn reload(&mut self) {
        let watched = self.watch.as_ref().map(|w| w.path.clone());
        match watched.or_else(|| self.path().map(Path::to_path_buf)) {
            Some(p) => {
                let same = self.path() == Some(p.as_path());
                let keep = same.then_some((self.pixel, self.step));
                self.open_keeping(&p, keep);
            }
            None => self.apply(Command::OpenBuiltin),
        }
    }

    /// The function that wakes the UI, for a background thread to call when it has news.
    pub(super) fn repaint_handle(&self) -> Arc<dyn Fn() + Send + Sync> {
        Arc::clone(&self.repaint)
    }

    fn set_scene(&mut self, scene: Arc<Scene>, path: Option<PathBuf>) {
        let (w, h) = (scene.camera.width, scene.camera.height);
        self.settings = scene.settings.clone();
        let same_size = self
            .scene()
            .is_some_and(|s| s.camera.width == w && s.camera.height == h);
        self.doc = Document::Scene { scene, path };
        self.load_error = None;
        self.learn.explain = None;
        if !same_size || self.pixel.is_none() {
            // Start on the centre pixel so the panels have something to show.
            self.pixel = Some([w / 2, h / 2]);
            self.step = 0;
        }
        self.sample = 0;
        self.stepping = None;
        self.prepared = None;
        self.rendered = None;
        self.playing = false;
        if path_is_none(&self.doc) {
            self.watch = None;
        }
        let path = self.path().map(Path::to_path_buf);
        self.refresh_editor(path.as_deref());
        self.restart_render();
    }

    fn open_trace(&mut self, trace: Trace, path: &Path) {
        self.editor = None;
        self.editor_path = None;
        self.selected = None;
        self.job = None;
        self.prepared = None;
        self.rendered = None;
        self.pixel = Some(trace.pixel);
        self.sample = trace.sample;
        self.settings = trace.settings.clone();
        self.doc = Document::Trace {
            path: path.to_path_buf(),
        };
        self.stepping = Some(Stepping::new(trace, Duration::ZERO));
        self.trace_generation += 1;
        self.showing_gpu_trace = false;
        self.divergence = None;
        self.step = 0;
        self.playing = false;
    }

    /// Cancels the running render and starts a new one with the live settings.
    fn restart_render(&mut self) {
        self.restart_render_paced(None);
    }

    /// [`AppState::restart_render`], a progressive render's passes held on screen for `pace`.
    fn restart_render_paced(&mut self, pace: Option<Duration>) {
        let Some(scene) = self.scene().cloned() else {
            return;
        };
        let previous = self.prepared.take();
        self.job = None; // cancels the old one
        let repaint = Arc::clone(&self.repaint);
        self.job = Some(RenderJob::start(
            scene,
            self.settings.clone(),
            previous,
            pace,
            move || repaint(),
        ));
        self.renders_started += 1;
    }

    /// Records the selected pixel's trace again (after a new pixel, sample or settings). With
    /// `keep_step` the current step index is kept (clamped), so a teacher can flip a setting and
    /// compare the same step.
    fn retrace(&mut self, keep_step: bool) {
        self.showing_gpu_trace = false;
        self.divergence = None;
        let (Some(p), Some([x, y])) = (&self.prepared, self.pixel) else {
            return;
        };
        let c = &p.scene().camera;
        if x >= c.width || y >= c.height {
            self.pixel = None;
            return;
        }
        let start = Instant::now();
        let trace = p
            .tracer()
            .record(x, y, self.sample.min(p.scene().settings.spp - 1));
        let explain = self
            .learn
            .explain
            .take()
            .and_then(|q| crate::lesson::explaining_step(&trace, &q));
        let stepping = Stepping::new(trace, start.elapsed());
        self.step = if let Some(k) = explain {
            k
        } else if keep_step {
            self.step.min(stepping.len().saturating_sub(1))
        } else {
            0
        };
        self.stepping = Some(stepping);
        self.trace_generation += 1;
    }

    fn move_step(&mut self, m: StepMove) {
        let Some(s) = &self.stepping else {
            return;
        };
        let last = s.len().saturating_sub(1);
        self.step = match m {
            StepMove::First => 0,
            StepMove::Previous => self.step.saturating_sub(1),
            StepMove::Next => (self.step + 1).min(last),
            StepMove::Last => last,
            StepMove::To(k) => k.min(last),
        };
    }

    /// Work between frames: take what the render job reports, advance playback, watch the file.
    /// `now` is the UI clock.
    pub fn tick(&mut self, now: Instant) {
        self.take_load();
        self.take_check();
        while let Some(event) = self.job.as_ref().and_then(RenderJob::poll) {
            match event {
                JobEvent::Prepared(p) => {
                    self.prepared = Some(p);
                    self.retrace(true);
                }
                JobEvent::Done(result) => {
                    let job = self.job.take().expect("an event came from the job");
                    match result {
                        Ok(output) => {
                            self.rendered = Some(Rendered {
                                output,
                                wall: job.started.elapsed(),
                                build: self
                                    .prepared
                                    .as_ref()
                                    .map_or(Duration::ZERO, |p| p.build_time()),
                            })
                        }
                        Err(e) if is_cancelled(&e) => {}
                        Err(e) => {
                            self.message = Some(Message {
                                text: format!("render failed: {e}"),
                                error: true,
                            })
                        }
                    }
                }
            }
        }
        let speed = self.prefs.speed;
        if self.playing && play_due(&mut self.last_play, now, speed) {
            let at_end = self
                .stepping
                .as_ref()
                .is_none_or(|s| self.step + 1 >= s.len());
            if at_end {
                self.playing = false;
            } else {
                self.step += 1;
            }
        }
        if self.sample_playing && play_due(&mut self.last_sample_play, now, speed) {
            if self.pixel.is_none() || self.sample + 1 >= self.settings.spp {
                self.sample_playing = false;
            } else {
                self.sample += 1;
                self.retrace(true);
            }
        }
        self.exports.retain(|rx| match rx.try_recv() {
            Ok(m) => {
                self.message = Some(m);
                false
            }
            Err(std::sync::mpsc::TryRecvError::Empty) => true,
            Err(std::sync::mpsc::TryRecvError::Disconnected) => false,
        });
        self.lab.poll();
        let cpu = self
            .rendered
            .as_ref()
            .map(|r| (&*r.output, self.renders_started));
        if let Some((trace, divergence)) = self.gpu.poll(cpu) {
            self.apply(Command::ShowGpuTrace(trace, divergence));
        }
        self.check_file();
        self.expire_message(now);
    }

    /// Drops the status message once it has been shown long enough (an error longer).
    fn expire_message(&mut self, now: Instant) {
        let Some(m) = &self.message else {
            self.message_seen = None;
            return;
        };
        match &self.message_seen {
            Some((seen, since)) if seen == m => {
                if now.saturating_duration_since(*since) >= message_life(m) {
                    self.message = None;
                    self.message_seen = None;
                }
            }
            _ => self.message_seen = Some((m.clone(), now)),
        }
    }

    /// Reloads the open file when its watcher saw it change on disk.
    fn check_file(&mut self) {
        let Some(w) = &self.watch else {
            return;
        };
        let mut changed = false;
        while w.changed.try_recv().is_ok() {
            changed = true;
        }
        if changed && modified(&w.path).is_some() {
            self.reload();
            if self.load_error.is_none() {
                self.message = Some(Message {
                    text: "the file changed on disk: reloading".into(),
                    error: false,
                });
            }
        }
    }

    /// When the next [`AppState::tick`] has work to do by itself (playback, file watching).
    pub fn next_wakeup(&self) -> Option<Duration> {
        if self.playing || self.sample_playing {
            Some(Duration::from_secs_f32(
                1.0 / self.prefs.speed.clamp(0.1, 60.0) / 2.0,
            ))
        } else if let Some((m, since)) = &self.message_seen {
            Some(
                message_life(m)
                    .saturating_sub(since.elapsed())
                    .max(Duration::from_millis(50)),
            )
        } else {
            None
        }
    }

    /// The diagram kind the diagram panel shows now.
    pub fn diagram_kind(&self) -> Option<DiagramKind> {
        let s = self.stepping.as_ref()?;
        match self.prefs.diagram {
            DiagramChoice::Kind(k) if s.kinds.contains(&k) => Some(k),
            _ => Some(diagram::kinds_for_step(&s.trace, self.step)[0]),
        }
    }

    /// The view options of the diagram panel at a size.
    pub fn view_options(&self, width: u32, height: u32) -> ViewOptions {
        ViewOptions {
            width,
            height,
            theme: self.prefs.effective_theme().diagram_theme(),
            focus: Some(self.step),
            slice_angle: self.prefs.slice_angle,
            top_down: self.prefs.top_down,
            scale: 1.0,
        }
    }
}

/// How long a status message stays: errors longer than news.
fn message_life(m: &Message) -> Duration {
    if m.error {
        Duration::from_secs(20)
    } else {
        Duration::from_secs(8)
    }
}

fn path_is_none(doc: &Document) -> bool {
    matches!(doc, Document::Scene { path: None, .. })
}

/// Whether a playback (of steps, or of samples) moves on at `now`: one move per 1/`speed`
/// seconds of the UI clock; the first call only starts the clock (`last`).
fn play_due(last: &mut Option<Instant>, now: Instant, speed: f32) -> bool {
    let interval = Duration::from_secs_f64(1.0 / f64::from(speed.clamp(0.1, 60.0)));
    match *last {
        None => {
            *last = Some(now);
            false
        }
        Some(t) if now.duration_since(t) >= interval => {
            *last = Some(now);
            true
        }
        Some(_) => false,
    }
}
