//! `raystep converge`: image error against spp and trace time.

use crate::stability::converge::{ConvergeOptions, csv, markdown, plots, run};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `raystep converge`.
#[derive(Debug, clap::Args)]
pub struct ConvergeArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// The largest samples per pixel (levels 1, 2, 4, … up to it).
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub max_spp: u32,
    /// Independent seeds per level.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub seeds: u32,
    /// The reference renders at this many times the top spp (at least 16).
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(16..=1024))]
    pub reference_factor: u32,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Directory for converge.md, converge.csv, converge-spp.png and converge-time.png
    /// (created if missing).
    #[arg(long, default_value = "converge")]
    pub out: PathBuf,
    /// Render the levels on the GPU (the reference stays the CPU's): the same figures for the
    /// GPU, to set beside the CPU's.
    #[arg(long)]
    pub gpu: bool,
    /// With --gpu: how the GPU makes primary rays.
    #[arg(long, value_enum, default_value_t = crate::gpu::GpuPath::Compute, requires = "gpu")]
    pub gpu_path: crate::gpu::GpuPath,
}

/// Runs `raystep converge`.
pub fn run_cmd(args: &ConvergeArgs) -> Result<(), String> {
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("{}: cannot create the directory: {e}", args.out.display()))?;
    let t0 = Instant::now();
    let scene = crate::assets::load_scene(&args.scene)?;
    let load = t0.elapsed().as_secs_f64();
    let opts = ConvergeOptions {
        max_spp: args.max_spp,
        seeds: args.seeds,
        reference_factor: args.reference_factor,
        threads: args.threads.map(|t| t as usize),
    };
    let rep = if args.gpu {
        use crate::gpu::{GpuContext, GpuTracer, ShaderVariant};
        let ctx = GpuContext::headless().map_err(|e| e.to_string())?;
        // One BVH for every level: only the samples and the seed change.
        let base = crate::trace::PreparedScene::new(scene.clone());
        let mut level = |spp: u32, seed: u32| -> Result<(Vec<glam::Vec3>, f64), String> {
            let mut settings = base.scene().settings.clone();
            settings.spp = spp;
            settings.seed = seed;
            let s = crate::trace::PreparedScene::with_settings(
                base.scene_arc(),
                &settings,
                Some(&base),
            );
            let mut tracer = GpuTracer::new(ctx.clone(), &s, ShaderVariant::Generated)
                .map_err(|e| e.to_string())?;
            let frame = tracer.render(args.gpu_path).map_err(|e| e.to_string())?;
            Ok((frame.pixels, frame.time.as_secs_f64()))
        };
        let line = GpuTracer::new(ctx.clone(), &base, ShaderVariant::Generated)
            .map_err(|e| e.to_string())?
            .adapter_line(args.gpu_path);
        crate::stability::converge::run_on(&scene, &opts, &line, &mut level)?
    } else {
        run(&scene, &opts)?
    };
    let md = markdown(&rep, load);
    crate::io::write_atomic(&args.out.join("converge.md"), md.as_bytes())?;
    crate::io::write_atomic(&args.out.join("converge.csv"), csv(&rep).as_bytes())?;
    let (a, b) = plots(&rep);
    crate::io::write_atomic(&args.out.join("converge-spp.png"), &a)?;
    crate::io::write_atomic(&args.out.join("converge-time.png"), &b)?;
    super::emit(&format!(
        "{md}\nwrote converge.md, converge.csv, converge-spp.png, converge-time.png in {}\n",
        super::full_path(&args.out)
    ))
}
