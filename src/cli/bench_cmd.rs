//! `raystep bench`.

use std::path::PathBuf;

/// Arguments of `raystep bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// Scene files (default: every scenes/*.toml in the current directory, else the built-in scene).
    pub scenes: Vec<PathBuf>,
    /// Which figures.
    #[arg(long, value_enum, default_value_t = Section::All)]
    pub section: Section,
    /// Timed repetitions per figure (the median is printed).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub reps: u32,
    /// For `scene`: time brute force on every k-th row only, and scale up.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub brute_rows: u32,
    /// For `traversal`: which traversal to run (one side alone is for instruction counting).
    #[arg(long, value_enum, default_value_t = crate::bench::Side::Both)]
    pub side: crate::bench::Side,
    /// For `rays`: also write the scene's finite primitives, the rays and raystep's answers to
    /// this file, for `tools/embree-compare` (one scene only).
    #[arg(long)]
    pub export: Option<PathBuf>,
    /// Run the BVH's baseline x86-64 build only, not its AVX2 + FMA build (the answers are the
    /// same; this measures what the wider instructions buy).
    #[arg(long)]
    pub baseline: bool,
}

/// Benchmark sections.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Section {
    /// Tracer throughput: silent vs recorder, specialized vs all stages.
    Tracer,
    /// Brute force vs BVH by primitive count.
    Accel,
    /// Every accelerator on every scene (the shipped ones and SPD balls, tetra and mount at two
    /// sizes each): build time, memory, tests and visits per ray, rays per second, speed-up.
    AccelCompare,
    /// Where the time goes: camera rays, traversal, primitive tests, shading and spawning, for
    /// every accelerator (measured by replaying one captured render; the same scenes as
    /// accel-compare).
    Stages,
    /// The uniform grid's resolution: λ (cells per primitive) from 0.5 to 32 on the
    /// accel-compare scenes: cells, references, tests and cells per ray, speed relative to λ = 4.
    GridLambda,
    /// Per-scene figures: build, threads, BVH vs brute force, traversal vs obvhs, one pixel.
    Scene,
    /// Drawing every diagram of one step.
    Diagram,
    /// Only raystep's BVH traversal against obvhs's (see --side).
    Traversal,
    /// The app, headless: UI frame times during a render and click-to-trace latency.
    App,
    /// The GPU view at 1280×720: fragment vs compute, generated vs full shader, shader sizes
    /// (the scenes plus the sphereflake, SPD balls size 3).
    Gpu,
    /// The 3D view at 1280×720 (with and without the 8×8 fan) and the time from an edit to the
    /// updated trace, on the scenes and the 7,381-sphere sphereflake (SPD balls size 4).
    View3d,
    /// How the cost of a ray grows with the number of primitives: SPD balls, tetra and mount
    /// from tens to a million primitives with the BVH (build, depth, visits, tests, time per ray
    /// and time per ray ÷ log₂ n), brute force beside it up to 1,000 primitives.
    Growth,
    /// Rays per second on a fixed set: the camera's 2560×1440 primary rays and one shadow ray
    /// per hit, 1 and 2 threads, finite primitives only, with the BVH's build time and SAH cost
    /// (`--export FILE` writes the set for Embree to trace: `tools/embree-compare`).
    Rays,
    /// The BVH's build qualities (low, medium, high) side by side on the rays' set: build
    /// time, SAH cost, node visits per ray and single-thread rates.
    Build,
    /// Two threads against one: full renders of the scenes and SPD balls, tetra and mount at
    /// two sizes each, shadows and reflections included.
    Threads,
    /// The path tracer: Mrays/s with the BVH on 1 and 2 threads, and the time to equal error
    /// against Mitsuba 3 (`scalar_rgb`, via `python3`) on the same scene (the first path-traced
    /// scene given, `scenes/cornell-area.toml` by default) at 128×128.
    Path,
    /// Monte Carlo against Mitsuba 3 (`scalar_rgb`, via `python3`), one thread each: every
    /// Monte Carlo scene given (the shipped ones by default) path-traced at 96 pixels wide, 64
    /// spp, rendered `--reps` times (at least 2) with `[render] seed` 0, 1, … (other random
    /// numbers), raystep keeping no statistics (Mitsuba keeps none): time per sample, MSE
    /// against Mitsuba at 1024 spp, efficiency 1 / (MSE × time), the ratios, and where
    /// raystep's time goes.
    Mc,
    /// Everything.
    All,
}

/// Runs `raystep bench`.
pub fn run(args: &BenchArgs) -> Result<(), String> {
    let mut paths = args.scenes.clone();
    if paths.is_empty()
        && let Ok(rd) = std::fs::read_dir("scenes")
    {
        paths = rd
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
        paths.sort();
    }
    let mut scenes = vec![];
    for p in &paths {
        scenes.push(crate::scene::load_file(p).map_err(|e| e.to_string())?);
    }
    if scenes.is_empty() {
        scenes.push(crate::scene::default_scene());
    }
    let reps = args.reps as usize;
    crate::accel::set_baseline_only(args.baseline);
    crate::io::outln!(
        "raystep {} bench, {} logical CPUs\n",
        env!("CARGO_PKG_VERSION"),
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    if matches!(args.section, Section::Tracer | Section::All) {
        crate::bench::tracer(&scenes, reps);
        crate::io::outln!();
    }
    if matches!(args.section, Section::Accel | Section::All) {
        crate::bench::accel_threshold(reps);
        crate::io::outln!();
    }
    if matches!(
        args.section,
        Section::AccelCompare | Section::Stages | Section::GridLambda | Section::Threads
    ) {
        use crate::scene::spd::{SpdScene, generate};
        let mut all = scenes.clone();
        let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
        for (kind, size) in [
            (SpdScene::Balls, 2),
            (SpdScene::Balls, 4),
            (SpdScene::Tetra, 3),
            (SpdScene::Tetra, 6),
            (SpdScene::Mount, 3),
            (SpdScene::Mount, 6),
        ] {
            let out = generate(kind, size)?;
            if let Some((name, obj)) = &out.obj {
                std::fs::write(dir.path().join(name), obj).map_err(|e| e.to_string())?;
            }
            let name = format!("SPD {} {size}", kind.name());
            let mut s = crate::scene::load_str(&out.toml, &name, Some(dir.path()))
                .map_err(|e| e.to_string())?;
            s.name = name;
            all.push(s);
        }
        if args.section == Section::Threads {
            crate::bench::threads(&all, reps);
        } else if args.section == Section::Stages {
            crate::bench::stages(&all, reps);
        } else if args.section == Section::GridLambda {
            crate::bench::grid_lambda(&all, reps);
        } else {
            crate::bench::accel_compare(&all, reps);
        }
        crate::io::outln!();
    }
    if matches!(args.section, Section::Diagram | Section::All) {
        crate::bench::diagrams(&scenes, reps);
        crate::io::outln!();
    }
    if args.section == Section::Traversal {
        for s in &scenes {
            let mut s = s.clone();
            s.settings.accel = crate::scene::AccelChoice::Bvh;
            let bvh = crate::accel::Bvh::build(&s);
            crate::io::outln!("## {}", s.name);
            crate::bench::traversal_vs_obvhs(&s, &bvh, reps, args.side);
        }
    }
    if args.section == Section::Rays {
        if args.export.is_some() && scenes.len() != 1 {
            return Err("--export needs exactly one scene".into());
        }
        for s in &scenes {
            crate::bench::throughput(s, reps, args.export.as_deref())?;
            crate::io::outln!();
        }
    }
    if args.section == Section::Build {
        for s in &scenes {
            crate::bench::build_qualities(s, reps);
            crate::io::outln!();
        }
    }
    if args.section == Section::Growth {
        crate::bench::growth(reps)?;
    }
    if args.section == Section::View3d {
        let mut inputs = vec![];
        for p in &paths {
            let text = crate::io::read_text(p, crate::io::limits::SCENE, "scene file")
                .map_err(|e| format!("{}: {e}", p.display()))?;
            let name = p.file_name().map_or_else(
                || p.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            );
            inputs.push((name, text, p.parent().map(std::path::Path::to_path_buf)));
        }
        if inputs.is_empty() {
            inputs.push((
                crate::scene::DEFAULT_SCENE_NAME.to_string(),
                crate::scene::DEFAULT_SCENE.to_string(),
                None,
            ));
        }
        let flake = crate::scene::spd::generate(crate::scene::spd::SpdScene::Balls, 4)?;
        inputs.push(("SPD balls 4 (sphereflake)".into(), flake.toml, None));
        crate::bench::view3d(&inputs, reps)?;
    }
    if args.section == Section::Gpu {
        let flake = crate::scene::spd::generate(crate::scene::spd::SpdScene::Balls, 3)?;
        let mut with_flake = scenes.clone();
        with_flake.push(
            crate::scene::load_str(&flake.toml, "balls-3.toml", None).map_err(|e| e.to_string())?,
        );
        crate::bench::gpu(&with_flake, reps)?;
        crate::io::outln!();
        crate::bench::gpu_monte_carlo(&scenes, reps)?;
        crate::io::outln!();
    }
    if args.section == Section::Path {
        let scene = scenes
            .iter()
            .find(|s| s.settings.integrator == crate::scene::Integrator::Path)
            .ok_or("--section path needs a path-traced scene (integrator = \"path\"), e.g. scenes/cornell-area.toml")?;
        crate::bench::path::path(scene, reps)?;
        crate::io::outln!();
    }
    if args.section == Section::Mc {
        crate::bench::mc::mc(&scenes, reps)?;
        crate::io::outln!();
    }
    if args.section == Section::App {
        for p in &paths {
            crate::bench::app(p);
            crate::io::outln!();
        }
    }
    if matches!(args.section, Section::Scene | Section::All) {
        for s in &scenes {
            crate::bench::scene_figures(s, reps, args.brute_rows);
            crate::io::outln!();
        }
    }
    Ok(())
}
