//! `raystep render`.

use super::{SettingsArgs, scene_cmd::value_name};
use crate::accel::SceneAccel;
use crate::gpu::{GpuContext, GpuPath, GpuTracer, ShaderVariant};
use crate::render::{RenderOptions, image, render};
use crate::trace::PreparedScene;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `raystep render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// The image to write (atomically): .png (8-bit sRGB), or .exr (linear 32-bit float OpenEXR,
    /// the render's own numbers).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Write linear values instead of sRGB-encoded ones.
    #[arg(long)]
    pub linear: bool,
    /// Also write the accelerator visits per pixel (BVH nodes, bounding spheres, grid cells) as a
    /// colour-mapped PNG with a legend.
    #[arg(long, conflicts_with = "gpu")]
    pub heatmap: Option<PathBuf>,
    /// Also measure where the time goes (camera rays, traversal, primitive tests, shading and
    /// spawning) on one thread, by replaying a render of at most 160×120 pixels of the scene
    /// (the method of `raystep bench --section stages`; adds a few seconds).
    #[arg(long, conflicts_with = "gpu")]
    pub profile: bool,
    /// Count nothing: no rays by kind, primitive tests or box visits (the summary leaves them
    /// out). The render the app and this command count is the same image, bit for bit; counting
    /// costs small scenes a few per cent of their time (the Cornell box 6.5 % of its
    /// instructions). This is the render `raystep bench --section mc` times against Mitsuba.
    #[arg(long, conflicts_with_all = ["heatmap", "gpu"])]
    pub no_counts: bool,
    /// Render on the GPU (wgpu, offscreen) with the WGSL tracer generated for the scene.
    #[arg(long)]
    pub gpu: bool,
    /// With --gpu: make primary rays with a full-screen triangle (fragment) or a compute shader.
    #[arg(long, value_enum, default_value_t = GpuPath::Fragment, requires = "gpu")]
    pub gpu_path: GpuPath,
    /// With --gpu: the shader generated for the scene's features, or the one with every feature.
    #[arg(long, value_enum, default_value_t = ShaderVariant::Generated, requires = "gpu")]
    pub gpu_shader: ShaderVariant,
    /// Setting overrides.
    #[command(flatten)]
    pub settings: SettingsArgs,
}

/// Runs `raystep render`.
pub fn run(args: &RenderArgs) -> Result<(), String> {
    // Check the output paths before spending time on the render: never over the scene, never
    // the image and the heatmap in one file.
    let mut outputs = vec![("-o", args.output.as_path())];
    if let Some(h) = &args.heatmap {
        outputs.push(("--heatmap", h.as_path()));
    }
    crate::io::check_outputs(&[("the scene", &args.scene)], &outputs)?;
    for p in std::iter::once(&args.output).chain(args.heatmap.as_ref()) {
        if !(image::is_exr(p) && std::ptr::eq(p, &args.output) && !args.gpu) {
            super::check_png_path(p)?;
        } else {
            super::check_output_dir(p)?;
        }
    }
    let t0 = Instant::now();
    let scene = super::load_scene(Some(&args.scene), &args.settings)?;
    let load = t0.elapsed();
    let prepared = PreparedScene::new(scene);
    if args.gpu {
        return run_gpu(args, &prepared, load);
    }
    let (scene, accel, build) = (prepared.scene(), prepared.accel(), prepared.build_time());
    let tracer = prepared.tracer();
    let opts = RenderOptions {
        threads: args.threads.map(|t| t as usize),
        progress: true,
        count: !args.no_counts,
        ..Default::default()
    };
    // A Monte Carlo render accumulates in passes of 1, 1, 2, 4, … samples per pixel (the same
    // image, bit for bit), saying on stderr how far it is, as the app's counter does.
    let progressive = scene.settings.integrator.is_monte_carlo() && scene.settings.spp > 1;
    let out = if progressive {
        let spp = scene.settings.spp;
        let started = Instant::now();
        crate::render::render_progressive(
            &tracer,
            &RenderOptions {
                progress: false,
                ..opts
            },
            |done, _| {
                eprintln!(
                    "rendering {:.0}%: {done} of {spp} samples per pixel, {:.1} s",
                    100.0 * done as f64 / spp as f64,
                    started.elapsed().as_secs_f64()
                );
            },
        )?
    } else {
        render(&tracer, &opts)?
    };
    if image::is_exr(&args.output) {
        image::write_exr(&args.output, out.width, out.height, &out.pixels)?;
    } else {
        let img = image::to_rgb8(out.width, out.height, &out.pixels, args.linear);
        image::write_png(&args.output, &img)?;
    }
    if let Some(h) = &args.heatmap {
        let hm = crate::diagram::heatmap::heatmap(
            &out,
            match accel {
                SceneAccel::Brute(_) | SceneAccel::Bvh(_) => "BVH nodes",
                SceneAccel::TwoLevel(_) => "TLAS and BLAS nodes (and the world's)",
                SceneAccel::Spheres(_) => "bounding spheres",
                SceneAccel::Grid(_) => "grid cells",
            },
        )
        .expect("counted render has visits");
        image::write_png(h, &hm)?;
    }
    let s = &out.stats;
    let c = &s.counts;
    let accel_desc = match &accel {
        SceneAccel::Brute(_) => "brute force (every primitive for every ray)".to_string(),
        SceneAccel::Bvh(b) => format!("BVH ({} nodes, depth {})", b.nodes.len(), b.max_depth),
        SceneAccel::Spheres(s) => format!("bounding spheres ({} nodes)", s.nodes.len()),
        SceneAccel::Grid(g) => format!(
            "uniform grid ({}×{}×{} cells, {} references)",
            g.dims[0],
            g.dims[1],
            g.dims[2],
            g.references()
        ),
        SceneAccel::TwoLevel(t) => format!(
            "two-level BVH (TLAS of {} nodes over {} instances, {} BLAS of {} nodes in all)",
            t.tlas.nodes.len(),
            scene.instances.len(),
            t.blas.len(),
            t.blas.iter().map(|b| b.nodes.len()).sum::<usize>()
        ),
    };
    crate::io::outln!(
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
    crate::io::outln!(
        "  methods  sphere {}, triangle {}, offset {}",
        value_name(&scene.settings.sphere_method),
        value_name(&scene.settings.triangle_method),
        value_name(&scene.settings.offset)
    );
    crate::io::outln!(
        "  time     load {:.1} ms, build {:.1} ms, trace {:.1} ms",
        load.as_secs_f64() * 1e3,
        build.as_secs_f64() * 1e3,
        s.trace.as_secs_f64() * 1e3
    );
    if args.no_counts {
        crate::io::outln!("  rays     not counted (--no-counts)");
    } else {
        print_counts(c, accel, s);
    }
    if let Some(([x, y], k)) = s.first_bad_sample {
        crate::io::outln!(
            "  warning  {} sample{} had a NaN or infinite channel and were left out of their pixels; the first: pixel {x},{y}, sample {k} (raystep trace {} --pixel {x},{y} --sample {k})",
            s.bad_samples,
            if s.bad_samples == 1 { "" } else { "s" },
            args.scene.display()
        );
    }
    if s.nan_rays > 0 || s.nan_pixels > 0 {
        crate::io::outln!(
            "  warning  {} rays and {} pixels are NaN (not finite)",
            s.nan_rays,
            s.nan_pixels
        );
    }
    if args.profile {
        let small = crate::bench::profile_size(scene);
        // Five repetitions (medians) unless one replayed render would take over a second.
        let fraction = (small.camera.width * small.camera.height) as f64
            / (out.width * out.height).max(1) as f64;
        let one = s.trace.as_secs_f64() * s.threads as f64 * fraction;
        let m = crate::bench::measure_stages(&small, accel, if one < 1.0 { 5 } else { 1 });
        let [c, tr, te, sh] = m.shares();
        crate::io::outln!(
            "  profile  camera rays {c}, traversal {tr}, primitive tests {te}, shading and spawning {sh} (one thread, {}×{} replayed)",
            small.camera.width,
            small.camera.height
        );
    }
    crate::io::outln!("wrote {}", super::full_path(&args.output));
    if let Some(h) = &args.heatmap {
        crate::io::outln!("wrote {}", super::full_path(h));
    }
    Ok(())
}

/// The summary's counted lines: rays by kind, tests and visits per ray, and the rate.
fn print_counts(c: &crate::record::Counter, accel: &SceneAccel, s: &crate::render::RenderStats) {
    let rays = c.rays().max(1) as f64;
    crate::io::outln!(
        "  rays     {} primary, {} shadow, {} reflection, {} refraction{} ({} in all)",
        c.primary,
        c.shadow,
        c.reflection,
        c.refraction,
        if c.scattered > 0 {
            format!(", {} diffuse or glossy", c.scattered)
        } else {
            String::new()
        },
        c.rays()
    );
    let visits = match accel {
        SceneAccel::Brute(_) => "",
        SceneAccel::Bvh(_) => " and {} box tests",
        SceneAccel::Spheres(_) => " and {} bounding-sphere tests",
        SceneAccel::Grid(_) => " and {} cells walked",
        SceneAccel::TwoLevel(_) => " and {} node visits",
    }
    .replace("{}", &format!("{:.1}", c.node_visits as f64 / rays));
    crate::io::outln!(
        "  tests    {:.1} primitive tests{visits} per ray",
        c.prim_tests as f64 / rays,
    );
    crate::io::outln!("  speed    {:.2} Mrays/s", s.mrays_per_s());
}

/// Frames timed for `render --gpu` and `compare` (after one warm-up frame); the median is shown.
pub const GPU_FRAMES: usize = 5;

/// `raystep render --gpu`: offscreen on the GPU, read back, written like the CPU render.
fn run_gpu(
    args: &RenderArgs,
    prepared: &PreparedScene,
    load: std::time::Duration,
) -> Result<(), String> {
    let scene = prepared.scene();
    let t = Instant::now();
    let ctx = GpuContext::headless().map_err(|e| e.to_string())?;
    fits_adapter(&ctx, scene.camera.width, scene.camera.height)?;
    let mut gpu = GpuTracer::new(ctx, prepared, args.gpu_shader).map_err(|e| e.to_string())?;
    gpu.prepare(args.gpu_path).map_err(|e| e.to_string())?;
    let setup = t.elapsed();
    let frame_time = gpu
        .time_frames(args.gpu_path, 1, GPU_FRAMES)
        .map_err(|e| e.to_string())?;
    // A Monte Carlo scene, on either path: passes of 1, 1, 2, 4, … samples per pixel, as the
    // CPU's render, ending on the path's one-shot image, saying on stderr how far it is.
    let spp = scene.settings.spp;
    let frame = if scene.settings.integrator.is_monte_carlo() && spp > 1 {
        let started = Instant::now();
        gpu.render_progressive(args.gpu_path, |done, _| {
            eprintln!(
                "rendering on the GPU {:.0}%: {done} of {spp} samples per pixel, {:.1} s",
                100.0 * done as f64 / spp as f64,
                started.elapsed().as_secs_f64()
            );
        })
    } else {
        gpu.render(args.gpu_path)
    }
    .map_err(|e| e.to_string())?;
    let img = image::to_rgb8(frame.width, frame.height, &frame.pixels, args.linear);
    image::write_png(&args.output, &img)?;
    crate::io::outln!(
        "rendered \"{}\" at {}×{} on the GPU, {} sample{} per pixel",
        scene.name,
        frame.width,
        frame.height,
        scene.settings.spp,
        if scene.settings.spp == 1 { "" } else { "s" },
    );
    crate::io::outln!("  adapter  {}", gpu.adapter_line(args.gpu_path));
    crate::io::outln!(
        "  shader   {} bytes of WGSL ({} for every feature)",
        gpu.wgsl().len(),
        crate::gpu::full_wgsl(prepared).len()
    );
    crate::io::outln!(
        "  time     load {:.1} ms, set-up (device, BVH, shader) {:.1} ms, frame {:.2} ms (median of {GPU_FRAMES})",
        load.as_secs_f64() * 1e3,
        setup.as_secs_f64() * 1e3,
        frame_time.as_secs_f64() * 1e3
    );
    crate::io::outln!("wrote {}", super::full_path(&args.output));
    Ok(())
}

/// Bytes the GPU render keeps per pixel in its largest buffer (the running sums: four f32).
const GPU_BYTES_PER_PIXEL: u64 = 16;

/// Refuses, before anything is made on the GPU, an image past the adapter's limits, naming the
/// limit and the largest image of the same shape it takes (wgpu's own error was a bare
/// "Validation Error").
fn fits_adapter(ctx: &GpuContext, w: u32, h: u32) -> Result<(), String> {
    let lim = ctx.device.limits();
    let side = lim.max_texture_dimension_2d;
    let bytes = lim.max_buffer_size.min(lim.max_storage_buffer_binding_size);
    let pixels = bytes / GPU_BYTES_PER_PIXEL;
    let need = u64::from(w) * u64::from(h);
    if w <= side && h <= side && need <= pixels {
        return Ok(());
    }
    // The largest image of this shape within both limits.
    let by_area = (pixels as f64 / need as f64).sqrt();
    let by_side = f64::from(side) / f64::from(w.max(h));
    let s = by_area.min(by_side).min(1.0);
    let (lw, lh) = (
        ((f64::from(w) * s).floor() as u32).max(1),
        ((f64::from(h) * s).floor() as u32).max(1),
    );
    let why = if w > side || h > side {
        format!("its images are at most {side} pixels a side (max_texture_dimension_2d)")
    } else {
        format!(
            "its largest storage buffer is {bytes} bytes (max_storage_buffer_binding_size, max_buffer_size) and the render keeps {GPU_BYTES_PER_PIXEL} bytes a pixel: {} bytes for this image",
            need * GPU_BYTES_PER_PIXEL
        )
    };
    Err(format!(
        "render --gpu: a {w}×{h} image is past the limits of this GPU ({}): {why}; the largest image of this shape it renders is {lw}×{lh} (or render it on the CPU, without --gpu)",
        ctx.info.name
    ))
}
