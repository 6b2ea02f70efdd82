//! The `raystep` command line (clap). Every command returns a plain error message; [`main`]
//! prints it and exits non-zero. No command panics on bad input.

mod bench_cmd;
mod compare_cmd;
mod converge_cmd;
mod diagram_cmd;
mod diff_cmd;
mod examples_cmd;
mod exercise_cmd;
mod grade_tracer_cmd;
mod intersect;
mod render_cmd;
mod scene_cmd;
mod stability_cmd;
mod trace_cmd;
mod view_cmd;

use crate::scene::{AccelChoice, BvhQuality, OffsetPolicy, Scene};
use crate::shapes::{SphereMethod, TriangleMethod};
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

/// raystep: ray tracing, stepped through one pixel at a time.
#[derive(Debug, Parser)]
#[command(name = "raystep", version, about, long_about = None)]
pub struct Cli {
    /// What to do (with no command: the app on the built-in scene).
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Test one ray against one primitive and explain every intermediate (a calculator to check
    /// hand computations against).
    #[command(subcommand)]
    Intersect(intersect::Shape),
    /// Trace one pixel of a scene and print every step.
    Trace(trace_cmd::TraceArgs),
    /// Render a scene in parallel to a PNG, with statistics (on the GPU with --gpu).
    Render(render_cmd::RenderArgs),
    /// Render a scene on the CPU and on the GPU: both times, the error figures (RMSE, max error,
    /// differing pixels) and a difference image.
    Compare(compare_cmd::CompareArgs),
    /// Print performance figures (medians of timed repetitions).
    Bench(bench_cmd::BenchArgs),
    /// The numerical stability lab: every intersection method in f32 and f64 on the stiff cases
    /// S1–S25, against exact references; Markdown, CSV and error-vs-time plots.
    Stability(stability_cmd::StabilityArgs),
    /// Render a scene at spp 1, 2, 4, … with several seeds against a high-spp reference; error
    /// against spp and trace time (Markdown, CSV, plots).
    Converge(converge_cmd::ConvergeArgs),
    /// Draw the 3D scene view — the scene, the camera with its image plane and a pixel's rays up
    /// to a step — into a PNG (on the GPU adapter; lavapipe on a machine without a GPU).
    View(view_cmd::ViewArgs),
    /// Draw a traced pixel's diagrams (PNG), or every step as an animated GIF or PNG frames.
    Diagram(diagram_cmd::DiagramArgs),
    /// Compare two saved traces step by step and report the first divergence (exit 0 equal,
    /// 1 different, 2 bad input).
    Diff(diff_cmd::DiffArgs),
    /// Work with scene files.
    #[command(subcommand)]
    Scene(scene_cmd::SceneCmd),
    /// Print a student's variant of an exercise sheet's questions.
    Exercise(exercise_cmd::ExerciseArgs),
    /// Mark one student's answers to an exercise sheet against the tracer.
    Check(exercise_cmd::CheckArgs),
    /// Mark a class's answers (CSV) to an exercise sheet; write a grades CSV.
    Grade(exercise_cmd::GradeArgs),
    /// Run a student's own ray tracer on scenes and pixels and check the trace it prints (the
    /// student trace format) against raystep's, stage by stage; text, Gradescope JSON, or a
    /// class's grades CSV.
    GradeTracer(grade_tracer_cmd::GradeTracerArgs),
    /// List the scenes, lessons and exercise sheets built into raystep, or write them to a folder.
    Examples(examples_cmd::ExamplesArgs),
    /// Open the app on a scene (.toml, or a glTF model: .gltf, .glb), a built-in scene by name (`cornell`) or a saved trace
    /// (.json).
    Open {
        /// The scene or trace file, or a built-in scene's name.
        file: PathBuf,
        /// Write a screenshot of the window to this PNG once the render is done, then close.
        #[arg(long)]
        screenshot: Option<PathBuf>,
        /// Select this pixel X,Y once the render is done.
        #[arg(long, value_parser = parse_pixel)]
        pixel: Option<[u32; 2]>,
        /// Then show this step of the pixel's trace (the `[K]` that `raystep trace` prints).
        #[arg(long, requires = "pixel")]
        step: Option<usize>,
    },
}

/// Settings that override the scene's `[render]` table.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct SettingsArgs {
    /// Samples per pixel.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub spp: Option<u32>,
    /// Recursion limit for reflection and refraction.
    #[arg(long, value_parser = clap::value_parser!(u32).range(0..=64))]
    pub max_depth: Option<u32>,
    /// Ray–sphere method.
    #[arg(long, value_enum)]
    pub sphere_method: Option<SphereMethod>,
    /// Ray–triangle method.
    #[arg(long, value_enum)]
    pub triangle_method: Option<TriangleMethod>,
    /// Ray-origin offset for shadow, reflection and refraction rays.
    #[arg(long, value_enum)]
    pub offset: Option<OffsetPolicy>,
    /// Acceleration structure.
    #[arg(long, value_enum)]
    pub accel: Option<AccelChoice>,
    /// Build quality of the BVH (more build time for fewer node visits per ray).
    #[arg(long, value_enum)]
    pub bvh_quality: Option<BvhQuality>,
    /// Seed for the antialiasing jitter and every Monte Carlo random number.
    #[arg(long)]
    pub seed: Option<u32>,
    /// Light transport: whitted, distribution (soft shadows, glossy, depth of field) or path.
    #[arg(long, value_enum)]
    pub integrator: Option<crate::scene::Integrator>,
    /// The path tracer's estimator for direct light: mis (both, power heuristic), light (light
    /// sampling alone) or bsdf (BSDF sampling alone).
    #[arg(long, value_enum)]
    pub strategy: Option<crate::scene::Strategy>,
    /// The Monte Carlo integrators' 2D samples: independent, or stratified over the pixel's
    /// samples.
    #[arg(long, value_enum)]
    pub sampler: Option<crate::scene::SamplerKind>,
    /// Where rays leave smooth-shaded triangles: none (the flat triangle: a jagged shadow
    /// terminator) or hanika (Hanika's lift towards the smooth surface).
    #[arg(long, value_enum)]
    pub terminator: Option<crate::scene::Terminator>,
    /// Look through a camera of the scene's glTF files, by its name in the file (the image's
    /// size stays the scene's).
    #[arg(long, value_name = "NAME")]
    pub camera: Option<String>,
}

impl SettingsArgs {
    /// Applies the overrides to a scene's settings, with the lessons' `[settings]` rules (a value
    /// out of range is an error naming the setting).
    pub fn apply(&self, scene: &mut Scene) -> Result<(), String> {
        let overrides = crate::lesson::LessonSettings {
            spp: self.spp,
            max_depth: self.max_depth,
            sphere_method: self.sphere_method,
            triangle_method: self.triangle_method,
            offset: self.offset,
            accel: self.accel,
            bvh_quality: self.bvh_quality,
            seed: self.seed,
            integrator: self.integrator,
            strategy: self.strategy,
            sampler: self.sampler,
            terminator: self.terminator,
            ..Default::default()
        };
        overrides.apply(scene)?;
        if let Some(name) = &self.camera {
            scene.use_camera(name)?;
        }
        Ok(())
    }
}

/// Parses `X,Y,Z` into three finite numbers.
pub fn parse_vec3(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!("expected three numbers X,Y,Z, got \"{s}\""));
    }
    let mut out = [0.0; 3];
    for (o, p) in out.iter_mut().zip(&parts) {
        let v: f64 = p.parse().map_err(|_| format!("\"{p}\" is not a number"))?;
        if !v.is_finite() {
            return Err(format!("\"{p}\" is not a finite number"));
        }
        *o = v;
    }
    Ok(out)
}

/// Parses `WxH`, each side a whole number of pixels from 64 to `max`.
pub(crate) fn parse_size_within(s: &str, max: u32) -> Result<[u32; 2], String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WxH, got \"{s}\""))?;
    let w: u32 = w
        .trim()
        .parse()
        .map_err(|_| format!("\"{w}\" is not a width"))?;
    let h: u32 = h
        .trim()
        .parse()
        .map_err(|_| format!("\"{h}\" is not a height"))?;
    if !(64..=max).contains(&w) || !(64..=max).contains(&h) {
        return Err(format!(
            "{w}x{h}: each side must be a whole number of pixels from 64 to {max}"
        ));
    }
    Ok([w, h])
}

/// Parses `X,Y` into a pixel position.
pub fn parse_pixel(s: &str) -> Result<[u32; 2], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 2 {
        return Err(format!("expected a pixel X,Y, got \"{s}\""));
    }
    let x = parts[0]
        .parse()
        .map_err(|_| format!("\"{}\" is not a pixel coordinate", parts[0]))?;
    let y = parts[1]
        .parse()
        .map_err(|_| format!("\"{}\" is not a pixel coordinate", parts[1]))?;
    Ok([x, y])
}

/// Loads a scene file (or a built-in scene by name: `cornell`), or the built-in default scene for
/// `None`, and applies setting overrides.
pub fn load_scene(path: Option<&PathBuf>, overrides: &SettingsArgs) -> Result<Scene, String> {
    let mut scene = match path {
        Some(p) => crate::assets::load_scene(p)?,
        None => crate::scene::default_scene(),
    };
    overrides.apply(&mut scene)?;
    Ok(scene)
}

pub use crate::io::full_path;

/// Checks that an output path ends in `.png` and that its directory exists, before any work.
pub fn check_png_path(p: &std::path::Path) -> Result<(), String> {
    if p.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
        != Some("png")
    {
        return Err(format!("{}: the output must be a .png file", p.display()));
    }
    check_output_dir(p)
}

/// Checks that an output path's directory exists.
pub fn check_output_dir(p: &std::path::Path) -> Result<(), String> {
    let dir = p
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(std::path::Path::new("."));
    if !dir.is_dir() {
        return Err(format!(
            "{}: the directory {} does not exist",
            p.display(),
            dir.display()
        ));
    }
    Ok(())
}

/// Writes command output to stdout and flushes it: a write error (a full disk, `/dev/full`) is
/// an error naming standard output; a closed pipe (`raystep trace … | head`) ends the output
/// quietly instead of panicking as `println!` would.
pub fn emit(text: &str) -> Result<(), String> {
    crate::io::out(format_args!("{text}"));
    crate::io::stdout_result()
}

/// Lets a closed pipe end a command-line command quietly, as it ends `cat` or `grep`: Rust
/// starts programs with SIGPIPE ignored, so a write to a closed pipe (`raystep bench | head`)
/// returns an error, and `println!` — which the benchmarks and reports use — panics on it. With
/// the default action restored the process simply ends. Not for the app, which writes nothing to
/// a pipe.
#[allow(unsafe_code)] // one libc call, before any thread exists
fn quiet_on_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: `signal` with SIG_DFL installs no handler code; it runs at the start of `main`,
    // before this process starts any thread.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Keeps the headless commands' GPU adapter from probing a window system. wgpu's Vulkan
/// instance always enables the Wayland and X11 surface extensions, and Mesa's device-selection
/// layer (VK_LAYER_MESA_device_select, loaded into every Vulkan program where Mesa is installed)
/// answers an instance with the Wayland extension by connecting to the Wayland compositor to
/// find its GPU — which, with no session (XDG_RUNTIME_DIR unset), makes libwayland print
/// "error: XDG_RUNTIME_DIR is invalid or not set in the environment." although nothing is
/// wrong. The commands only ever draw offscreen and choose their adapter by wgpu's power
/// preference, so the layer has nothing to do for them: it is turned off by the variable its
/// manifest names for that (`NODEVICE_SELECT=1`). Left alone when the user chose a device
/// (`MESA_VK_DEVICE_SELECT`, which the layer then follows without probing) or set
/// `NODEVICE_SELECT` already; the app, which opens a window, keeps the layer.
#[allow(unsafe_code)] // one environment variable, before any thread exists
fn headless_vulkan() {
    #[cfg(all(unix, not(target_os = "macos")))]
    if std::env::var_os("NODEVICE_SELECT").is_none()
        && std::env::var_os("MESA_VK_DEVICE_SELECT").is_none()
    {
        // SAFETY: called at the start of `main`, before this process starts any thread, so
        // nothing reads the environment concurrently.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
}

/// Runs the command line; returns the process exit code.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    if !matches!(cli.command, None | Some(Command::Open { .. })) {
        quiet_on_closed_pipe();
        headless_vulkan();
    }
    let result = match cli.command {
        None => crate::app::run(None, None),
        Some(Command::Open {
            file,
            screenshot,
            pixel,
            step,
        }) => crate::assets::resolve_scene(&file).and_then(|file| {
            crate::app::run(
                Some(file),
                (screenshot.is_some() || pixel.is_some())
                    .then(|| crate::app::ScreenshotPlan::new(screenshot, pixel, step)),
            )
        }),
        Some(Command::Examples(args)) => examples_cmd::run(&args),
        Some(Command::Intersect(shape)) => intersect::run(&shape),
        Some(Command::Trace(args)) => trace_cmd::run(&args),
        Some(Command::Scene(cmd)) => scene_cmd::run(&cmd),
        Some(Command::Render(args)) => render_cmd::run(&args),
        Some(Command::Compare(args)) => compare_cmd::run(&args),
        Some(Command::Bench(args)) => bench_cmd::run(&args),
        Some(Command::Diagram(args)) => diagram_cmd::run(&args),
        Some(Command::View(args)) => view_cmd::run(&args),
        Some(Command::Stability(args)) => stability_cmd::run_cmd(&args),
        Some(Command::Converge(args)) => converge_cmd::run_cmd(&args),
        // Its own exit status: 1 means "the traces differ", 2 bad input.
        Some(Command::Diff(args)) => return diff_cmd::run(&args),
        Some(Command::Exercise(args)) => exercise_cmd::run_exercise(&args),
        Some(Command::Check(args)) => exercise_cmd::run_check(&args),
        Some(Command::Grade(args)) => exercise_cmd::run_grade(&args),
        Some(Command::GradeTracer(args)) => grade_tracer_cmd::run(&args),
    };
    // What was printed must have arrived: a full disk or /dev/full is an error like any other.
    match result.and_then(|()| crate::io::stdout_result()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            use std::io::Write;
            // Nothing more can be done if stderr cannot be written either.
            let _ = writeln!(std::io::stderr(), "error: {msg}");
            ExitCode::FAILURE
        }
    }
}
