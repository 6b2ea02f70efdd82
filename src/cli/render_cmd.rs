//! `raystep render`.

use super::{SettingsArgs, scene_cmd::value_name};
use crate::accel::SceneAccel;
use crate::render::{RenderOptions, image, render};
use crate::trace::Tracer;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `raystep render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// The PNG to write (atomically).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Write linear values instead of sRGB-encoded ones.
    #[arg(long)]
    pub linear: bool,
    /// Also write the BVH node visits per pixel as a colour-mapped PNG with a legend.
    #[arg(long)]
    pub heatmap: Option<PathBuf>,
    /// Setting overrides.
    #[command(flatten)]
    pub settings: SettingsArgs,
}

/// Runs `raystep render`.
pub fn run(args: &RenderArgs) -> Result<(), String> {
    // Check the output paths before spending time on the render.
    for p in std::iter::once(&args.output).chain(args.heatmap.as_ref()) {
        if p.extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
            != Some("png")
        {
            return Err(format!("{}: the output must be a .png file", p.display()));
        }
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
    }
    let t0 = Instant::now();
    let scene = super::load_scene(Some(&args.scene), &args.settings)?;
    let load = t0.elapsed();
    let (accel, build) = SceneAccel::build(&scene);
    let tracer = Tracer::new(&scene, &accel);
    let opts = RenderOptions {
        threads: args.threads.map(|t| t as usize),
        progress: true,
        count: true,
        ..Default::default()
    };
    let out = render(&tracer, &opts)?;
    let img = image::to_rgb8(out.width, out.height, &out.pixels, args.linear);
    image::write_png(&args.output, &img)?;
    if let Some(h) = &args.heatmap {
        let hm = image::heatmap(&out).expect("counted render has visits");
        image::write_png(h, &hm)?;
    }
    let s = &out.stats;
    let c = &s.counts;
    let rays = c.rays().max(1) as f64;
    let accel_desc = match &accel {
        SceneAccel::Brute(_) => "brute force (every primitive for every ray)".to_string(),
        SceneAccel::Bvh(b) => format!("BVH ({} nodes, depth {})", b.nodes.len(), b.max_depth),
    };
    println!(
        "rendered \"{}\" at {}×{}, {} sample{} per pixel, {}, {} thread{}",
        scene.name,
        out.width,
        out.height,
        scene.settings.spp,
        if scene.settings.spp == 1 { "" } else { "s" },
        accel_desc,
        s.threads,
        if s.threads == 1 { "" } else { "s" }
    );
    println!(
        "  methods  sphere {}, triangle {}, offset {}",
        value_name(&scene.settings.sphere_method),
        value_name(&scene.settings.triangle_method),
        value_name(&scene.settings.offset)
    );
    println!(
        "  time     load {:.1} ms, build {:.1} ms, trace {:.1} ms",
        load.as_secs_f64() * 1e3,
        build.as_secs_f64() * 1e3,
        s.trace.as_secs_f64() * 1e3
    );
    println!(
        "  rays     {} primary, {} shadow, {} reflection, {} refraction ({} in all)",
        c.primary,
        c.shadow,
        c.reflection,
        c.refraction,
        c.rays()
    );
    println!(
        "  tests    {:.1} primitive tests and {:.1} box tests per ray",
        c.prim_tests as f64 / rays,
        c.node_visits as f64 / rays
    );
    println!("  speed    {:.2} Mrays/s", s.mrays_per_s());
    println!("wrote {}", args.output.display());
    if let Some(h) = &args.heatmap {
        println!("wrote {}", h.display());
    }
    Ok(())
}
