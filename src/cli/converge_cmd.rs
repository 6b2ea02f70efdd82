//! `raystep converge`: image error against spp and trace time.

use crate::stability::converge::{ConvergeOptions, Progress, csv, markdown, plots, run_observed};
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
    /// The light transport to measure (default: the scene's).
    #[arg(long, value_enum)]
    pub integrator: Option<crate::scene::Integrator>,
    /// The Monte Carlo integrators' 2D samples: independent or stratified (default: the
    /// scene's).
    #[arg(long, value_enum)]
    pub sampler: Option<crate::scene::SamplerKind>,
    /// Compare the path tracer's estimators, each against one reference: a comma-separated list
    /// of mis, light and bsdf (writes a row per strategy, the plots with a series each, and
    /// converge-STRATEGY.png, the picture of each at the top spp).
    #[arg(long, value_enum, value_delimiter = ',', conflicts_with = "gpu")]
    pub strategy: Vec<crate::scene::Strategy>,
    /// With --strategy: the relMSE whose time to reach is reported. Default: one that every
    /// strategy crosses between its first and its last level (so each time is measured, not
    /// bounded); when there is none the table says so and this must be given.
    #[arg(long, requires = "strategy")]
    pub target_relmse: Option<f64>,
}

/// Runs `raystep converge`.
pub fn run_cmd(args: &ConvergeArgs) -> Result<(), String> {
    // The first folder of `--out` that does not exist yet: made by this run, so removed (with
    // what this run put in it) if the run fails — a failing command leaves no folder behind.
    let made = std::path::absolute(&args.out).ok().and_then(|abs| {
        abs.ancestors()
            .take_while(|a| !a.exists())
            .last()
            .map(|p| p.to_path_buf())
    });
    let result = run_in(args);
    if result.is_err()
        && let Some(dir) = made
    {
        let _ = std::fs::remove_dir_all(dir);
    }
    result
}

fn run_in(args: &ConvergeArgs) -> Result<(), String> {
    let opts = ConvergeOptions {
        max_spp: args.max_spp,
        seeds: args.seeds,
        reference_factor: args.reference_factor,
        threads: args.threads.map(|t| t as usize),
        progress: true,
        reference: None,
    };
    if let Some(t) = args.target_relmse
        && !(t.is_finite() && t > 0.0)
    {
        return Err(format!("--target-relmse {t}: give a positive number"));
    }
    // Too many samples is refused, with the limit, before anything is loaded or created.
    crate::stability::converge::reference_spp(&opts)?;
    let t0 = Instant::now();
    let mut scene = crate::assets::load_scene(&args.scene)?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("{}: cannot create the directory: {e}", args.out.display()))?;
    if let Some(i) = args.integrator {
        scene.settings.integrator = i;
    }
    if let Some(k) = args.sampler {
        scene.settings.sampler = k;
    }
    let load = t0.elapsed().as_secs_f64();
    let mut observe = |p: &Progress| show_progress(p, t0.elapsed());
    if !args.strategy.is_empty() {
        return run_strategies_cmd(args, &scene, &opts, load, &mut observe);
    }
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
        run_observed(
            &scene,
            &opts,
            Some((line.as_str(), &mut level)),
            &mut observe,
        )?
    } else {
        run_observed(&scene, &opts, None, &mut observe)?
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

/// `converge --strategy …`: each strategy against one reference, a summary row each.
fn run_strategies_cmd(
    args: &ConvergeArgs,
    scene: &crate::scene::Scene,
    opts: &ConvergeOptions,
    load: f64,
    observe: &mut dyn FnMut(&Progress),
) -> Result<(), String> {
    use crate::stability::converge as cv;
    let mut strategies = args.strategy.clone();
    strategies.dedup();
    let runs = cv::run_strategies(scene, opts, &strategies, observe)?;
    let target = cv::Target::of(&runs, args.target_relmse);
    if target == cv::Target::Missing {
        use std::io::Write;
        // A note only: a closed or full stderr must not stop the run.
        let _ = writeln!(
            std::io::stderr(),
            "converge: {}",
            cv::target_words(&runs, target)
        );
    }
    let md = cv::strategies_markdown(&runs, target, load);
    crate::io::write_atomic(&args.out.join("converge.md"), md.as_bytes())?;
    crate::io::write_atomic(
        &args.out.join("converge.csv"),
        cv::strategies_csv(&runs).as_bytes(),
    )?;
    let (a, b) = cv::strategies_plots(&runs, target);
    crate::io::write_atomic(&args.out.join("converge-spp.png"), &a)?;
    crate::io::write_atomic(&args.out.join("converge-time.png"), &b)?;
    let mut pictures = vec![];
    for r in &runs {
        let name = format!("converge-{}.png", cv::strategy_name(r.strategy));
        let [w, h] = r.report.size;
        let img = crate::render::image::to_rgb8(w, h, &r.report.image, false);
        crate::render::image::write_png(&args.out.join(&name), &img)?;
        pictures.push(name);
    }
    super::emit(&format!(
        "{md}\nwrote converge.md, converge.csv, converge-spp.png, converge-time.png, {} in {}\n",
        pictures.join(", "),
        super::full_path(&args.out)
    ))
}

/// One line on stderr per stage: what finished, how much of the work is done, and about how
/// long the rest will take (from the trace speeds measured so far; the first estimate comes
/// after the first render, before the reference, which is most of the work).
fn show_progress(p: &Progress, elapsed: std::time::Duration) {
    use std::io::Write;
    let [done, all] = p.samples;
    let percent = if all == 0 {
        100.0
    } else {
        done as f64 * 100.0 / all as f64
    };
    let left = std::time::Duration::from_secs_f64(p.seconds_left.max(0.0));
    let line = if p.renders[0] >= p.renders[1] {
        format!(
            "converge: {} done ({} renders, {} in all)",
            p.finished,
            p.renders[1],
            indicatif::HumanDuration(elapsed)
        )
    } else {
        format!(
            "converge: {} done after {}; render {} of {}, {percent:.1}% of the {all} samples; \
             about {} left, {} in all (estimated from the speed so far)",
            p.finished,
            indicatif::HumanDuration(elapsed),
            p.renders[0],
            p.renders[1],
            indicatif::HumanDuration(left),
            indicatif::HumanDuration(elapsed + left)
        )
    };
    // Progress only: a closed or full stderr must not stop the run.
    let _ = writeln!(std::io::stderr(), "{line}");
}
