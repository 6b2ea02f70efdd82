//! `raystep trace`.

use super::{SettingsArgs, load_scene, parse_pixel};
use crate::explain::describe;
use crate::trace::PreparedScene;
use std::path::PathBuf;

/// Arguments of `raystep trace`.
#[derive(Debug, clap::Args)]
pub struct TraceArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// The pixel X,Y (x from the left, y from the top).
    #[arg(long, value_parser = parse_pixel)]
    pub pixel: [u32; 2],
    /// Which sample of the pixel (0 … spp − 1).
    #[arg(long, default_value_t = 0)]
    pub sample: u32,
    /// Print the trace as JSON instead of a tree.
    #[arg(long, conflicts_with = "format")]
    pub json: bool,
    /// Print the trace in another format: `student`, the JSON Lines a student's own tracer
    /// writes for `raystep grade-tracer` (lessons/starter/README.md).
    #[arg(long, value_enum)]
    pub format: Option<TraceFormat>,
    /// Also save the trace as JSON to this file (written atomically).
    #[arg(long)]
    pub save: Option<PathBuf>,
    /// Setting overrides.
    #[command(flatten)]
    pub settings: SettingsArgs,
}

/// The formats `trace --format` prints.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum TraceFormat {
    /// raystep's trace in the student trace format.
    Student,
}

/// Runs `raystep trace`.
pub fn run(args: &TraceArgs) -> Result<(), String> {
    let scene = load_scene(Some(&args.scene), &args.settings)?;
    let [x, y] = args.pixel;
    let c = &scene.camera;
    if x >= c.width || y >= c.height {
        return Err(format!(
            "--pixel {x},{y} is outside the {}×{} image (x < {}, y < {})",
            c.width, c.height, c.width, c.height
        ));
    }
    if args.sample >= scene.settings.spp {
        return Err(format!(
            "--sample {} does not exist: the scene takes {} sample{} per pixel (0 … {})",
            args.sample,
            scene.settings.spp,
            if scene.settings.spp == 1 { "" } else { "s" },
            scene.settings.spp - 1
        ));
    }
    // The same accelerator the render would use, so its node or cell visits appear in the trace.
    let prepared = PreparedScene::new(scene);
    let trace = prepared.record(x, y, args.sample);
    if let Some(k) = trace.truncated_at() {
        eprintln!(
            "warning: the trace was cut at step {k}: a trace keeps at most {} steps (the colours are exact; lower max_depth to see the whole tree)",
            crate::record::observer::MAX_TRACE_STEPS
        );
    }
    let json = trace.to_json();
    if let Some(path) = &args.save {
        crate::io::write_atomic(path, json.as_bytes())?;
        // On stderr: stdout is the trace (often piped).
        eprintln!("wrote {}", super::full_path(path));
    }
    if args.format == Some(TraceFormat::Student) {
        let ours = crate::student::expected::expected(&trace);
        super::emit(&crate::student::format::write(&ours.pixel))
    } else if args.json {
        super::emit(&(json + "\n"))
    } else {
        super::emit(&describe::tree(&trace))
    }
}
