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
    /// Trace the pixel on the GPU: the trace shader logs every step the GPU takes into a bounded
    /// buffer, read back into the same trace format (compare it with the CPU's with
    /// `raystep diff`).
    #[arg(long)]
    pub gpu: bool,
    /// With --gpu: the GPU path to trace (default compute: the CPU's primary ray, per pixel;
    /// fragment: the rasterizer's interpolated primary ray, scissored to the pixel).
    #[arg(long, value_enum, requires = "gpu")]
    pub gpu_path: Option<crate::gpu::GpuPath>,
    /// With --gpu: the size of the GPU's step log, in MiB (a trace that outgrows it ends in a
    /// `truncated` step).
    #[arg(long, requires = "gpu", default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub gpu_log_mib: u32,
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
    if let Some(save) = &args.save {
        crate::io::check_outputs(&[("the scene", &args.scene)], &[("--save", save)])?;
    }
    let scene = load_scene(Some(&args.scene), &args.settings)?;
    if args.format == Some(TraceFormat::Student)
        && !matches!(
            scene.settings.integrator,
            crate::scene::Integrator::Whitted | crate::scene::Integrator::Path
        )
    {
        return Err(format!(
            "{}: the student trace format records Whitted's tracer (version 1) and the path tracer (version 2), and this scene is set to the {} integrator (add --integrator path or --integrator whitted)",
            args.scene.display(),
            super::scene_cmd::value_name(&scene.settings.integrator)
        ));
    }
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
    let trace = if args.gpu {
        gpu_trace(args, &prepared)?
    } else {
        prepared.record(x, y, args.sample)
    };
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
    if args.format == Some(TraceFormat::Student) && crate::student::path::applies(prepared.scene())
    {
        // The pixel's first samples, each path record by record (format version 2).
        let ours = crate::student::path::expected(&prepared, x, y);
        super::emit(&crate::student::path::write(&ours.pixel))
    } else if args.format == Some(TraceFormat::Student) {
        let ours = crate::student::expected::expected(&trace);
        super::emit(&crate::student::format::write(&ours.pixel))
    } else if args.json {
        super::emit(&(json + "\n"))
    } else {
        super::emit(&describe::tree(&trace))
    }
}

/// The GPU's own trace of the pixel (`--gpu`); says on stderr which adapter and arithmetic made
/// it, and where the log ran out.
fn gpu_trace(args: &TraceArgs, prepared: &PreparedScene) -> Result<crate::record::Trace, String> {
    use crate::gpu::{GpuContext, GpuPath, GpuTracer, ShaderVariant};
    let path = args.gpu_path.unwrap_or(GpuPath::Compute);
    let ctx = GpuContext::headless().map_err(|e| e.to_string())?;
    let mut gpu =
        GpuTracer::new(ctx, prepared, ShaderVariant::Generated).map_err(|e| e.to_string())?;
    eprintln!("GPU trace: {}", gpu.adapter_line(path));
    if path == GpuPath::Fragment {
        eprintln!(
            "note: on the fragment path the primary ray's direction is the rasterizer's interpolation (its screen position is not computed: NaN); the CPU computes it, so the last bits may differ from the first step on"
        );
    }
    let words = args.gpu_log_mib as usize * (1 << 18);
    let [x, y] = args.pixel;
    let t = gpu
        .trace_pixel_on(path, x, y, args.sample, words)
        .map_err(|e| e.to_string())?;
    if t.summaries_truncated {
        eprintln!(
            "warning: the GPU's step log ran out while it summarised the pixel's samples ({} MiB): the traced sample's steps are all kept, the pixel's sample summaries are not (raise --gpu-log-mib to keep them)",
            args.gpu_log_mib
        );
    } else if t.truncated {
        eprintln!(
            "warning: the GPU's step log ran out after {} steps ({} MiB): the steps after that were not kept (the colours are the GPU's; raise --gpu-log-mib to see them all)",
            t.steps, args.gpu_log_mib
        );
    }
    Ok(t.trace)
}
