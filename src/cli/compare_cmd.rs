//! `raystep compare`: the same scene on the CPU and on the GPU, timed, with the error figures and
//! a difference image.

use super::SettingsArgs;
use super::render_cmd::GPU_FRAMES;
use crate::accel::SceneAccel;
use crate::gpu::{GpuContext, GpuPath, GpuTracer, ShaderVariant, difference};
use crate::render::{RenderOptions, image, render};
use crate::trace::PreparedScene;
use std::path::PathBuf;

/// Arguments of `raystep compare`.
#[derive(Debug, clap::Args)]
pub struct CompareArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// Write the difference image here (PNG): equal pixels dim grey, differing ones dark red
    /// (one 8-bit step) to yellow (16 or more).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// How the GPU makes primary rays.
    #[arg(long, value_enum, default_value_t = GpuPath::Fragment)]
    pub gpu_path: GpuPath,
    /// The shader generated for the scene's features, or the one with every feature.
    #[arg(long, value_enum, default_value_t = ShaderVariant::Generated)]
    pub gpu_shader: ShaderVariant,
    /// Image width (default: the scene's).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: Option<u32>,
    /// Image height (default: the scene's).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: Option<u32>,
    /// Setting overrides.
    #[command(flatten)]
    pub settings: SettingsArgs,
}

/// Runs `raystep compare`.
pub fn run(args: &CompareArgs) -> Result<(), String> {
    if let Some(p) = &args.output {
        super::check_png_path(p)?;
        crate::io::check_outputs(&[("the scene", &args.scene)], &[("-o", p)])?;
    }
    let mut scene = super::load_scene(Some(&args.scene), &args.settings)?;
    if let Some(w) = args.width {
        scene.camera.width = w;
    }
    if let Some(h) = args.height {
        scene.camera.height = h;
    }
    let prepared = PreparedScene::new(scene);
    let scene = prepared.scene();
    let ctx = GpuContext::headless().map_err(|e| e.to_string())?;
    let mut gpu = GpuTracer::new(ctx, &prepared, args.gpu_shader).map_err(|e| e.to_string())?;
    let gpu_time = gpu
        .time_frames(args.gpu_path, 1, GPU_FRAMES)
        .map_err(|e| e.to_string())?;
    let frame = gpu.render(args.gpu_path).map_err(|e| e.to_string())?;
    let cpu = render(&prepared.tracer(), &RenderOptions::default())?;
    let d = difference(cpu.width, cpu.height, &cpu.pixels, &frame.pixels)?;
    crate::io::outln!(
        "compared \"{}\" at {}×{}, CPU against GPU",
        scene.name,
        cpu.width,
        cpu.height
    );
    crate::io::outln!("  adapter  {}", gpu.adapter_line(args.gpu_path));
    crate::io::outln!(
        "  CPU      {:.2} ms ({}, {} thread{})",
        cpu.stats.trace.as_secs_f64() * 1e3,
        accel_name(prepared.accel()),
        cpu.stats.threads,
        if cpu.stats.threads == 1 { "" } else { "s" }
    );
    crate::io::outln!(
        "  GPU      {:.2} ms ({} path, median of {GPU_FRAMES} frames)",
        gpu_time.as_secs_f64() * 1e3,
        args.gpu_path.name()
    );
    crate::io::outln!(
        "  error    RMSE {:.2e} ({:.3}/255), max error {}/255, {} of {} pixels differ",
        d.rmse,
        d.rmse * 255.0,
        d.max_error,
        d.differing_pixels,
        d.pixels
    );
    if let Some(p) = &args.output {
        image::write_png(p, &d.image)?;
        crate::io::outln!("wrote {}", super::full_path(p));
    }
    Ok(())
}

fn accel_name(a: &SceneAccel) -> &'static str {
    use crate::accel::Accelerator;
    a.name()
}
