//! `raystep diagram`: draw a traced pixel's diagrams to PNG, or every step as an animated GIF or
//! numbered PNG frames. Works from a scene (tracing the pixel) or from a saved trace.

use super::{SettingsArgs, parse_pixel};
use crate::diagram::{self, DiagramKind, Theme, ViewOptions};
use crate::record::Trace;
use crate::trace::PreparedScene;
use std::path::{Path, PathBuf};

/// Arguments of `raystep diagram`.
#[derive(Debug, clap::Args)]
pub struct DiagramArgs {
    /// A scene file (.toml) or a saved trace (.json).
    pub input: PathBuf,
    /// The pixel X,Y to trace (scenes only).
    #[arg(long, value_parser = parse_pixel)]
    pub pixel: Option<[u32; 2]>,
    /// Which sample of the pixel (scenes only).
    #[arg(long, default_value_t = 0)]
    pub sample: u32,
    /// Highlight step K: the `[K]` that `raystep trace` prints before the step (counted from 0,
    /// as in the app's step list); default: the whole trace.
    #[arg(long)]
    pub step: Option<usize>,
    /// The diagram kind (default: the one that best explains the step, else the slice).
    #[arg(long, value_enum)]
    pub kind: Option<DiagramKind>,
    /// Output file: .png, or .gif with --animate.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Image size WxH.
    #[arg(long, default_value = "800x600", value_parser = parse_size)]
    pub size: [u32; 2],
    /// Colour theme.
    #[arg(long, value_enum, default_value_t = ThemeArg::Light)]
    pub theme: ThemeArg,
    /// Slice: rotate the cutting plane about the ray by this many degrees.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub angle: f32,
    /// Slice: view from above.
    #[arg(long)]
    pub top_down: bool,
    /// Every step in order as an animated GIF (-o OUT.gif).
    #[arg(long)]
    pub animate: bool,
    /// Every step as numbered PNGs in this directory (made if missing).
    #[arg(long)]
    pub frames: Option<PathBuf>,
    /// With --animate or --frames: only steps A to B, both included (A..B; A.. runs to the last
    /// step, ..B starts at step 0), numbered as `raystep trace` prints them ([K]) and as --step
    /// takes them. Default: every step.
    #[arg(long, value_name = "A..B")]
    pub steps: Option<String>,
    /// With --animate: how long the GIF shows each step, in milliseconds (20 … 60000; the last
    /// step is held for at least 3 s).
    #[arg(long, default_value_t = diagram::DEFAULT_DELAY_MS, value_parser = parse_delay)]
    pub delay_ms: u32,
    /// Text and line scale (1 = normal; 1.6 reads from the back of a classroom), 0.25 … 8.
    #[arg(long, default_value_t = 1.0, value_parser = parse_scale)]
    pub scale: f32,
    /// Setting overrides (scenes only).
    #[command(flatten)]
    pub settings: SettingsArgs,
}

/// Colour themes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ThemeArg {
    /// Dark on white.
    Light,
    /// Light on dark.
    Dark,
}

fn parse_delay(s: &str) -> Result<u32, String> {
    let ms: u32 = s
        .trim()
        .parse()
        .map_err(|_| format!("\"{s}\" is not a whole number of milliseconds"))?;
    if !diagram::DELAY_RANGE_MS.contains(&ms) {
        return Err(format!(
            "{ms} ms: the frame delay must be between {} and {} ms",
            diagram::DELAY_RANGE_MS.start(),
            diagram::DELAY_RANGE_MS.end()
        ));
    }
    Ok(ms)
}

fn parse_scale(s: &str) -> Result<f32, String> {
    let k: f32 = s
        .trim()
        .parse()
        .map_err(|_| format!("\"{s}\" is not a number"))?;
    if !(0.25..=8.0).contains(&k) {
        return Err(format!("{s}: the scale must be between 0.25 and 8"));
    }
    Ok(k)
}

fn parse_size(s: &str) -> Result<[u32; 2], String> {
    super::parse_size_within(s, diagram::MAX_SIDE)
}

/// The timeline steps `--steps` names (`A..B`, both ends included; `A..`; `..B`) in a trace of
/// `len` steps, as a range with its end excluded; a message naming the option and the trace's
/// steps when it is not a range, runs backwards or reaches past the last step.
pub fn parse_steps(s: &str, len: usize) -> Result<std::ops::Range<usize>, String> {
    let valid = match len {
        0 => "this trace has no steps".to_string(),
        _ => format!("this trace's steps are 0 … {}", len - 1),
    };
    let bad = || {
        format!(
            "--steps {s}: not a step range: write A..B (steps A to B, both included), A.. or \
             ..B; {valid}"
        )
    };
    let (a, b) = s.trim().split_once("..").ok_or_else(bad)?;
    let num = |x: &str, default: usize| -> Result<usize, String> {
        let x = x.trim();
        if x.is_empty() {
            Ok(default)
        } else if x.bytes().all(|c| c.is_ascii_digit()) {
            // All digits: too large to count is past the last step.
            Ok(x.parse().unwrap_or(usize::MAX))
        } else {
            Err(bad())
        }
    };
    let (a, b) = (num(a, 0)?, num(b, len.saturating_sub(1))?);
    if a > b {
        return Err(format!(
            "--steps {s}: the range runs backwards (step {a} comes after step {b}); {valid}"
        ));
    }
    if b >= len {
        return Err(format!("--steps {s}: step {b} does not exist: {valid}"));
    }
    Ok(a..b + 1)
}

/// Loads or makes the trace the command draws.
pub fn input_trace(
    input: &Path,
    pixel: Option<[u32; 2]>,
    sample: u32,
    settings: &SettingsArgs,
) -> Result<Trace, String> {
    if input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        return Trace::load(input).map_err(|e| e.to_string());
    }
    let scene = super::load_scene(Some(&input.to_path_buf()), settings)?;
    let [x, y] = pixel.ok_or("--pixel X,Y is needed to trace a scene")?;
    let c = &scene.camera;
    if x >= c.width || y >= c.height {
        return Err(format!(
            "--pixel {x},{y} is outside the {}×{} image",
            c.width, c.height
        ));
    }
    if sample >= scene.settings.spp {
        return Err(format!(
            "--sample {sample} does not exist: the scene takes {} samples per pixel",
            scene.settings.spp
        ));
    }
    Ok(PreparedScene::new(scene).record(x, y, sample))
}

/// Runs `raystep diagram`.
pub fn run(args: &DiagramArgs) -> Result<(), String> {
    if let Some(o) = &args.output {
        crate::io::check_outputs(&[("the input", &args.input)], &[("-o", o)])?;
    }
    let trace = input_trace(&args.input, args.pixel, args.sample, &args.settings)?;
    let steps = trace.timeline().len();
    if let Some(k) = args.step
        && k >= steps
    {
        return Err(format!(
            "--step {k} does not exist: this trace has {steps} steps (0 … {})",
            steps - 1
        ));
    }
    let base = ViewOptions {
        width: args.size[0],
        height: args.size[1],
        theme: if args.theme == ThemeArg::Dark {
            Theme::DARK
        } else {
            Theme::LIGHT
        },
        focus: args.step,
        slice_angle: args.angle,
        top_down: args.top_down,
        scale: args.scale,
    };
    let kind_for = |k: Option<usize>| -> DiagramKind {
        args.kind.unwrap_or_else(|| match k {
            Some(k) => diagram::kinds_for_step(&trace, k)[0],
            None => DiagramKind::Slice,
        })
    };
    if let Some(kind) = args.kind
        && !diagram::available(&trace).contains(&kind)
    {
        return diagram::draw(&trace, kind, &base).map(|_| ());
    }
    if args.steps.is_some() && !(args.animate || args.frames.is_some()) {
        return Err(
            "--steps needs --animate or --frames (for one step's diagram, use --step K)".into(),
        );
    }
    if args.animate || args.frames.is_some() {
        // Checked before anything is made or written.
        let range = match &args.steps {
            Some(s) => parse_steps(s, steps)?,
            None => 0..steps,
        };
        let out = if args.animate {
            let out = args.output.as_ref().ok_or("--animate needs -o OUT.gif")?;
            if !out
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("gif"))
            {
                return Err(format!(
                    "{}: an animation is written as a .gif file",
                    out.display()
                ));
            }
            Some(out)
        } else {
            None
        };
        if let Some(dir) = &args.frames {
            // Made if missing (with its parents), like `-o`'s file.
            if dir.exists() && !dir.is_dir() {
                return Err(format!(
                    "--frames {}: exists and is not a directory",
                    dir.display()
                ));
            }
            std::fs::create_dir_all(dir)
                .map_err(|e| format!("--frames {}: cannot create: {e}", dir.display()))?;
        }
        // One frame at a time: each is written (and encoded) as soon as it is drawn.
        let (gif, n) = diagram::animate_steps(
            &trace,
            args.kind,
            &base,
            range,
            out.map(|_| args.delay_ms),
            |k, f| match &args.frames {
                Some(dir) => {
                    crate::io::write_atomic(&dir.join(format!("step-{k:04}.png")), &f.png())
                }
                None => Ok(()),
            },
        )?;
        if let Some(dir) = &args.frames {
            super::emit(&format!("wrote {n} frames to {}\n", super::full_path(dir)))?;
        }
        if let Some(out) = out {
            crate::io::write_atomic(out, &gif)?;
            super::emit(&format!(
                "wrote {} ({n} frame{})\n",
                super::full_path(out),
                if n == 1 { "" } else { "s" }
            ))?;
        }
        return Ok(());
    }
    let out = args.output.as_ref().ok_or("-o OUT.png is needed")?;
    if !out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        return Err(format!(
            "{}: a diagram is written as a .png file (use --animate for .gif)",
            out.display()
        ));
    }
    let canvas = diagram::draw(&trace, kind_for(args.step), &base)?;
    crate::io::write_atomic(out, &canvas.png())?;
    super::emit(&format!("wrote {}\n", super::full_path(out)))
}
