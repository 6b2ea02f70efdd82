//! Benchmarks behind `raystep bench`: they print figures; nothing here asserts a speed.
//!
//! Each figure is the median of several timed repetitions on this machine, single-threaded
//! unless it says otherwise.

use crate::accel::{Accelerator, BruteForce, Bvh, SceneAccel, test_object};
use crate::math::Ray;
use crate::record::{Counter, RayKind, Silent};
use crate::render::{RenderOptions, render};
use crate::scene::{AccelChoice, Scene, load_str};
use crate::trace::{PreparedScene, Tracer};
use glam::{Vec3, Vec3A};
use std::time::{Duration, Instant};

mod accelerators;
pub mod mc;
pub mod path;
mod throughput;
mod view3d;

pub use accelerators::{accel_compare, grid_lambda, growth, stages};
pub(crate) use accelerators::{measure_stages, profile_size};
pub use throughput::{build_qualities, throughput};
pub use view3d::view3d;

/// Median wall time of `reps` runs of `f`.
pub fn median_time(reps: usize, mut f: impl FnMut()) -> Duration {
    let mut t: Vec<Duration> = (0..reps.max(1))
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed()
        })
        .collect();
    t.sort();
    t[t.len() / 2]
}

/// Counts the rays one full render of the tracer's scene casts (all kinds).
fn count_rays<A: Accelerator>(tracer: &Tracer<'_, A>) -> Counter {
    let mut c = Counter::default();
    for y in 0..tracer.camera.height {
        for x in 0..tracer.camera.width {
            tracer.trace_pixel(x, y, &mut c);
        }
    }
    c
}

fn all_pixels<A: Accelerator>(tracer: &Tracer<'_, A>) {
    for y in 0..tracer.camera.height {
        for x in 0..tracer.camera.width {
            std::hint::black_box(tracer.trace_pixel(x, y, &mut Silent));
        }
    }
}

/// Tracer throughput: one thread, rays per second with the silent observer (specialized and with
/// every stage compiled in) and with the recorder (a full step trace per pixel).
pub fn tracer(scenes: &[Scene], reps: usize) {
    crate::io::outln!("## Tracer throughput, one thread (Mrays/s, all ray kinds)");
    crate::io::outln!(
        "| scene | rays/frame | silent, specialized | silent, all stages | recorder (trace per pixel) | recorder cost |"
    );
    crate::io::outln!("|---|---|---|---|---|---|");
    for scene in scenes {
        let prepared = PreparedScene::new(scene.clone());
        let tracer = prepared.tracer();
        let generic = prepared.tracer().unspecialized();
        let rays = count_rays(&tracer).rays() as f64;
        let t_silent = median_time(reps, || all_pixels(&tracer));
        let t_generic = median_time(reps, || all_pixels(&generic));
        let spp = scene.settings.spp;
        let t_rec = median_time(reps, || {
            for y in 0..tracer.camera.height {
                for x in 0..tracer.camera.width {
                    for k in 0..spp {
                        std::hint::black_box(tracer.record(x, y, k));
                    }
                }
            }
        });
        let m = |t: Duration| rays / t.as_secs_f64() / 1e6;
        crate::io::outln!(
            "| {} | {} | {:.2} | {:.2} | {:.3} | {:.0}× |",
            scene.name,
            rays as u64,
            m(t_silent),
            m(t_generic),
            m(t_rec),
            t_rec.as_secs_f64() / t_silent.as_secs_f64()
        );
    }
}

fn spheres_scene(n: usize) -> Scene {
    // n spheres on a jittered grid in front of the camera, one light, 160×120.
    let mut t = String::from(
        "[camera]\nfrom = [0, 0, -30]\nwidth = 160\nheight = 120\nfov = 40\n[[light]]\nposition = [-20, 20, -30]\n",
    );
    let side = (n as f32).sqrt().ceil() as usize;
    for i in 0..n {
        let (gx, gy) = ((i % side) as f32, (i / side) as f32);
        let s = 16.0 / side as f32;
        let x = (gx - side as f32 / 2.0 + 0.5) * s;
        let y = (gy - side as f32 / 2.0 + 0.5) * s;
        t += &format!(
            "[[sphere]]\ncenter = [{x}, {y}, {}]\nradius = {}\n",
            (i % 3) as f32,
            s * 0.4
        );
    }
    load_str(&t, "spheres.toml", None).expect("generated scene is valid")
}

/// The brute-force / BVH crossover that sets [`crate::accel::AUTO_BVH_THRESHOLD`].
pub fn accel_threshold(reps: usize) {
    crate::io::outln!("## Brute force vs BVH by primitive count (160×120, one light, one thread)");
    crate::io::outln!("| spheres | brute force (ms) | BVH (ms) | BVH speed-up |");
    crate::io::outln!("|---|---|---|---|");
    for n in [1, 2, 4, 8, 12, 16, 24, 32, 64, 128, 256] {
        let mut scene = spheres_scene(n);
        scene.settings.accel = AccelChoice::None;
        let (brute, _) = SceneAccel::build(&scene);
        scene.settings.accel = AccelChoice::Bvh;
        let (bvh, _) = SceneAccel::build(&scene);
        let tb = median_time(reps, || all_pixels(&Tracer::new(&scene, &brute)));
        let tv = median_time(reps, || all_pixels(&Tracer::new(&scene, &bvh)));
        crate::io::outln!(
            "| {n} | {:.2} | {:.2} | {:.2}× |",
            tb.as_secs_f64() * 1e3,
            tv.as_secs_f64() * 1e3,
            tb.as_secs_f64() / tv.as_secs_f64()
        );
    }
}

/// Figures for one (large) scene: BVH build, render Mrays/s on one and on all threads,
/// BVH vs brute force (brute force timed on every k-th row and scaled up), traversal vs obvhs's
/// own, and tracing + recording one pixel.
pub fn scene_figures(scene: &Scene, reps: usize, brute_rows: u32) {
    crate::io::outln!(
        "## {} ({} primitives, {}×{})",
        scene.name,
        scene.features.primitives,
        scene.camera.width,
        scene.camera.height
    );
    let mut s = scene.clone();
    s.settings.accel = AccelChoice::Bvh;
    let t0 = Instant::now();
    let bvh = Bvh::build(&s);
    let build = t0.elapsed();
    crate::io::outln!(
        "- BVH build: {:.1} ms ({} nodes, depth {})",
        build.as_secs_f64() * 1e3,
        bvh.nodes.len(),
        bvh.max_depth
    );
    let tracer = Tracer::new(&s, &bvh);
    let counted = render(
        &tracer,
        &RenderOptions {
            threads: Some(1),
            progress: false,
            count: true,
            ..Default::default()
        },
    )
    .expect("render");
    let rays = counted.stats.counts.rays() as f64;
    let mut per_threads = vec![];
    for threads in [1usize, 2] {
        let t = median_time(reps, || {
            std::hint::black_box(
                render(
                    &tracer,
                    &RenderOptions {
                        threads: Some(threads),
                        ..Default::default()
                    },
                )
                .expect("render"),
            );
        });
        per_threads.push(t);
        crate::io::outln!(
            "- render, {threads} thread{}: {:.1} ms, {:.2} Mrays/s",
            if threads == 1 { "" } else { "s" },
            t.as_secs_f64() * 1e3,
            rays / t.as_secs_f64() / 1e6
        );
    }
    crate::io::outln!(
        "- two threads vs one: {:.2}×",
        per_threads[0].as_secs_f64() / per_threads[1].as_secs_f64()
    );
    // Brute force on every `brute_rows`-th row, scaled to the whole image.
    // Rows spread over the image, starting half a stride down (row 0 is often all sky).
    let k = brute_rows.max(1);
    let rows: Vec<u32> = (k / 2..s.camera.height).step_by(k as usize).collect();
    let time_rows = |a: &dyn Fn(u32, u32)| {
        let st = Instant::now();
        for &y in &rows {
            for x in 0..s.camera.width {
                a(x, y);
            }
        }
        st.elapsed()
    };
    let brute_tracer = Tracer::new(&s, &BruteForce);
    let tb = time_rows(&|x, y| {
        std::hint::black_box(brute_tracer.trace_pixel(x, y, &mut Silent));
    });
    let tv = time_rows(&|x, y| {
        std::hint::black_box(tracer.trace_pixel(x, y, &mut Silent));
    });
    crate::io::outln!(
        "- BVH vs brute force (one thread, {} of {} rows): {:.1}× faster ({:.1} ms vs {:.1} ms)",
        rows.len(),
        s.camera.height,
        tb.as_secs_f64() / tv.as_secs_f64(),
        tv.as_secs_f64() * 1e3,
        tb.as_secs_f64() * 1e3
    );
    traversal_vs_obvhs(&s, &bvh, reps, Side::Both);
    let (cx, cy) = hit_pixel_near_centre(&tracer);
    let t = median_time(reps.max(21), || {
        std::hint::black_box(tracer.record(cx, cy, 0));
    });
    let steps = tracer.record(cx, cy, 0).timeline().len();
    crate::io::outln!(
        "- trace and record pixel ({cx}, {cy}): {:.3} ms ({steps} steps)",
        t.as_secs_f64() * 1e3
    );
}

/// The pixel nearest the image centre (on a 32×32 grid) whose primary ray hits something, so
/// "trace one pixel" measures real work.
fn hit_pixel_near_centre<A: Accelerator>(tracer: &Tracer<'_, A>) -> (u32, u32) {
    let (w, h) = (tracer.camera.width, tracer.camera.height);
    let mut best = (w / 2, h / 2);
    let mut best_d = u64::MAX;
    for gy in 0..32 {
        for gx in 0..32 {
            let (x, y) = ((gx * w + w / 2) / 32, (gy * h + h / 2) / 32);
            let ray = tracer.camera.ray(x, y, [0.5, 0.5]).0;
            if tracer
                .accel
                .closest(tracer.scene, &ray, &mut Silent)
                .is_some()
            {
                let d = (x as i64 - w as i64 / 2).pow(2) as u64
                    + (y as i64 - h as i64 / 2).pow(2) as u64;
                if d < best_d {
                    best_d = d;
                    best = (x, y);
                }
            }
        }
    }
    best
}

/// Which traversal to run. Running one side alone (one repetition) is for counting instructions:
/// `valgrind --tool=callgrind raystep bench SCENE --section traversal --reps 1 --side raystep`,
/// then `--side obvhs`, minus `--side none` (loading and building only).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Side {
    /// Both, timed against each other.
    Both,
    /// raystep's observed traversal only.
    Raystep,
    /// obvhs's `ray_traverse` only.
    Obvhs,
    /// Neither (the baseline: load, build, make the rays).
    None,
}

/// Closest-hit traversal of the primary rays: raystep's observed loop with the silent observer
/// against obvhs's `ray_traverse`, both calling raystep's kernels.
pub fn traversal_vs_obvhs(scene: &Scene, bvh: &Bvh, reps: usize, side: Side) {
    let tracer = Tracer::new(scene, bvh);
    let rays: Vec<Ray<f32>> = (0..scene.camera.height)
        .flat_map(|y| (0..scene.camera.width).map(move |x| (x, y)))
        .map(|(x, y)| tracer.camera.ray(x, y, [0.5, 0.5]).0)
        .collect();
    let finite: Vec<u32> = (0..scene.objects.len() as u32)
        .filter(|id| !bvh.planes.contains(id))
        .collect();
    let leaf_objects: Vec<u32> = bvh
        .obvhs
        .primitive_indices
        .iter()
        .map(|&i| finite[i as usize])
        .collect();
    // obvhs's tree in the depth-first order raystep's nodes have (obvhs's own reordering), so
    // the two walk the same tree laid out the same way.
    let mut tree = bvh.obvhs.clone();
    tree.reorder_in_stack_traversal_order();
    let run_ours = matches!(side, Side::Both | Side::Raystep);
    let run_theirs = matches!(side, Side::Both | Side::Obvhs);
    let ours = median_time(if run_ours { reps } else { 0 }, || {
        if !run_ours {
            return;
        }
        for r in &rays {
            std::hint::black_box(crate::accel::Accelerator::closest(
                bvh,
                scene,
                r,
                &mut Silent,
            ));
        }
    });
    let theirs = median_time(if run_theirs { reps } else { 0 }, || {
        if !run_theirs {
            return;
        }
        for r in &rays {
            let mut hit = obvhs::ray::RayHit::none();
            let oray = obvhs::ray::Ray::new(
                Vec3A::from(r.origin),
                Vec3A::from(r.dir),
                0.0,
                f32::INFINITY,
            );
            tree.ray_traverse(oray, &mut hit, |rr, slot| {
                let ray = Ray {
                    origin: Vec3::from(rr.origin),
                    dir: Vec3::from(rr.direction),
                    t_min: rr.tmin,
                    t_max: rr.tmax,
                };
                test_object(scene, leaf_objects[slot], &ray, &mut Silent)
                    .map_or(f32::INFINITY, |h| h.t)
            });
            std::hint::black_box(hit);
        }
    });
    if side != Side::Both {
        let t = if run_ours { ours } else { theirs };
        crate::io::outln!(
            "- closest-hit traversal of {} primary rays, {side:?} only: {:.1} ms",
            rays.len(),
            t.as_secs_f64() * 1e3
        );
        return;
    }
    crate::io::outln!(
        "- closest-hit traversal of {} primary rays: raystep (silent observer) {:.1} ms, obvhs ray_traverse {:.1} ms → raystep takes {:.2}× obvhs's time",
        rays.len(),
        ours.as_secs_f64() * 1e3,
        theirs.as_secs_f64() * 1e3,
        ours.as_secs_f64() / theirs.as_secs_f64()
    );
}

/// How a full render scales from one thread to two: each scene at its own size (shadows,
/// reflections and refractions included), the ratio of the two times. Renders of a few
/// milliseconds move by tens of per cent from one to the next on a shared machine, so each
/// sample renders the scene as many times as fill `SAMPLE` (60 ms) (the per-render time is printed),
/// and one-thread and two-thread samples alternate, so a slow spell on the machine falls on both.
///
/// A third sample runs two independent one-thread renders at once, one per core: nothing is
/// shared between them but the machine (caches, memory, a core's sibling if the cores are
/// hyper-threads), so `2 × one thread ÷ that` is the most two threads can give on this machine,
/// and the last column is how much of it the parallel render reaches.
pub fn threads(scenes: &[Scene], reps: usize) {
    /// The least time one sample takes.
    const SAMPLE: Duration = Duration::from_millis(60);
    crate::io::outln!(
        "| scene | primitives | size | rays | renders per sample | 1 thread (ms) | 2 threads (ms) | 2T / 1T | two 1-thread renders at once (ms each) | machine's limit | 2T / limit |"
    );
    crate::io::outln!("|---|---|---|---|---|---|---|---|---|---|---|");
    for scene in scenes {
        let (accel, _) = SceneAccel::build(scene);
        let tracer = Tracer::new(scene, &accel);
        let rays = count_rays(&tracer).rays();
        let once = |threads: usize| {
            std::hint::black_box(render(
                &tracer,
                &RenderOptions {
                    threads: Some(threads),
                    ..Default::default()
                },
            ))
            .ok();
        };
        // How many renders fill a sample, from one timed one-thread render (after a warm-up).
        once(1);
        let t = Instant::now();
        once(1);
        let per_sample = (SAMPLE.as_secs_f64() / t.elapsed().as_secs_f64().max(1e-6))
            .ceil()
            .clamp(1.0, 10_000.0) as usize;
        let sample = |threads: usize| {
            let t = Instant::now();
            for _ in 0..per_sample {
                once(threads);
            }
            t.elapsed() / per_sample as u32
        };
        // Two one-thread renders at once; the time each took.
        let side_by_side = || {
            let t = Instant::now();
            std::thread::scope(|s| {
                let other = s.spawn(|| {
                    for _ in 0..per_sample {
                        once(1);
                    }
                });
                for _ in 0..per_sample {
                    once(1);
                }
                other.join().ok();
            });
            t.elapsed() / per_sample as u32
        };
        let (mut one, mut two, mut both) = (vec![], vec![], vec![]);
        for _ in 0..reps.max(1) {
            one.push(sample(1));
            two.push(sample(2));
            both.push(side_by_side());
        }
        let median = |mut v: Vec<Duration>| {
            v.sort();
            v[v.len() / 2]
        };
        let (one, two, both) = (median(one), median(two), median(both));
        let limit = 2.0 * one.as_secs_f64() / both.as_secs_f64().max(1e-9);
        let speedup = one.as_secs_f64() / two.as_secs_f64().max(1e-9);
        crate::io::outln!(
            "| {} | {} | {}×{} | {} | {} | {:.2} | {:.2} | {:.2}× | {:.2} | {:.2}× | {:.0} % |",
            scene.name,
            scene.features.primitives,
            scene.camera.width,
            scene.camera.height,
            rays,
            per_sample,
            one.as_secs_f64() * 1e3,
            two.as_secs_f64() * 1e3,
            speedup,
            both.as_secs_f64() * 1e3,
            limit,
            100.0 * speedup / limit.max(1e-9)
        );
    }
}

/// Diagram cost: drawing every diagram the trace offers for one step at 800×600.
pub fn diagrams(scenes: &[Scene], reps: usize) {
    use crate::diagram::{ViewOptions, available, draw};
    crate::io::outln!("## Diagrams: all kinds for one step at 800×600 (one thread)");
    crate::io::outln!("| scene | pixel | kinds | steps in trace | all kinds (ms) |");
    crate::io::outln!("|---|---|---|---|---|");
    for scene in scenes {
        let prepared = PreparedScene::new(scene.clone());
        let (x, y) = (scene.camera.width / 2, scene.camera.height / 2);
        let trace = prepared.record(x, y, 0);
        let steps = trace.timeline().len();
        let opts = ViewOptions {
            focus: Some(steps / 2),
            ..ViewOptions::default()
        };
        let kinds = available(&trace);
        let t = median_time(reps.max(11), || {
            for k in &kinds {
                std::hint::black_box(draw(&trace, *k, &opts).expect("offered kinds draw"));
            }
        });
        crate::io::outln!(
            "| {} | ({x}, {y}) | {} | {steps} | {:.2} |",
            scene.name,
            kinds
                .iter()
                .map(|k| k.name())
                .collect::<Vec<_>>()
                .join(", "),
            t.as_secs_f64() * 1e3
        );
    }
}

/// The app's responsiveness on one scene, run headless (egui without a window or GPU, so the
/// figures are the UI thread's own work: building the frame and tessellating it). Prints the
/// frame times while the background render runs (one frame every 16 ms, as a 60 Hz display asks
/// for them), and the time from a click on a pixel to the end of the frame that shows its
/// trace, math and diagram.
pub fn app(path: &std::path::Path) {
    use crate::app::RaystepApp;
    use crate::app::state::{Command, Prefs};
    let ctx = egui::Context::default();
    let mut app = RaystepApp::with_context(&ctx, Prefs::default(), Some(path.to_path_buf()));
    let frame = |app: &mut RaystepApp| {
        let t = Instant::now();
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(1400.0, 900.0),
            )),
            ..Default::default()
        };
        let out = ctx.run_ui(input, |ui| app.frame(ui));
        let _ = ctx.tessellate(out.shapes, out.pixels_per_point);
        t.elapsed()
    };
    let start = Instant::now();
    let mut during = vec![];
    while app.state.busy() && start.elapsed() < Duration::from_secs(300) {
        let t = frame(&mut app);
        during.push(t);
        std::thread::sleep(Duration::from_millis(16).saturating_sub(t));
    }
    let render_s = start.elapsed().as_secs_f64();
    if let Some(e) = &app.state.load_error {
        crate::io::outln!("## {}: {e}", path.display());
        return;
    }
    let name = app.state.scene().map_or(String::new(), |s| {
        format!(
            "{} ({} primitives, {}×{})",
            s.name, s.features.primitives, s.camera.width, s.camera.height
        )
    });
    crate::io::outln!("## app: {name}");

    during.sort();
    let pct = |q: f64| during[((during.len() - 1) as f64 * q) as usize].as_secs_f64() * 1e3;
    if !during.is_empty() {
        crate::io::outln!(
            "  UI frames while loading, building and rendering ({render_s:.1} s, {} frames): median {:.2} ms, p95 {:.2} ms, max {:.2} ms, {} over 16 ms",
            during.len(),
            pct(0.5),
            pct(0.95),
            pct(1.0),
            during.iter().filter(|d| d.as_millis() >= 16).count()
        );
    }
    let Some(scene) = app.state.scene().cloned() else {
        return;
    };
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut lat = vec![];
    for (fx, fy) in [(0.5, 0.5), (0.3, 0.6), (0.7, 0.4), (0.45, 0.55), (0.6, 0.7)] {
        let p = [(w as f32 * fx) as u32, (h as f32 * fy) as u32];
        let t = Instant::now();
        app.state.apply(Command::SelectPixel(p));
        frame(&mut app);
        let steps = app.state.stepping.as_ref().map_or(0, |s| s.len());
        lat.push((t.elapsed(), steps));
    }
    let ms: Vec<String> = lat
        .iter()
        .map(|(d, n)| format!("{:.1} ms ({n} steps)", d.as_secs_f64() * 1e3))
        .collect();
    crate::io::outln!(
        "  click → trace, math and diagram on screen: {}",
        ms.join(", ")
    );
    let mut idle = vec![];
    for _ in 0..30 {
        idle.push(frame(&mut app));
    }
    idle.sort();
    crate::io::outln!(
        "  UI frames idle: median {:.2} ms",
        idle[idle.len() / 2].as_secs_f64() * 1e3
    );
}

/// The GPU view's figures: for each scene at 1280×720 (and the first scene again at 3840×2160),
/// the WGSL's size generated for the scene and with every feature, the median frame time of the
/// fragment and compute paths with each shader (trace pass only, submit to completion, after one
/// warm-up frame) with the rays per second it makes (primary rays, and all rays: shadow,
/// reflection and refraction rays too, counted by a CPU render of the same frame), and the CPU
/// render on all cores for scale. Returns an error when there is no GPU adapter.
pub fn gpu(scenes: &[Scene], reps: usize) -> Result<(), String> {
    use crate::gpu::{GpuContext, GpuPath, GpuTracer, ShaderVariant};
    let ctx = GpuContext::headless().map_err(|e| e.to_string())?;
    crate::io::outln!(
        "## GPU view (frame times in ms, medians of {reps}; Mrays/s: primary / all rays)"
    );
    crate::io::outln!("adapter: {}", ctx.adapter_name());
    if let Ok(a) = ctx.arithmetic() {
        crate::io::outln!(
            "arithmetic of the compute path: {}; probe: {}",
            if a.exact() {
                "exact (SPIR-V, NoContraction)"
            } else {
                "as the driver compiles: last bits may differ"
            },
            a.probe.summary()
        );
    }
    crate::io::outln!(
        "\n| scene | size | WGSL bytes, generated | WGSL bytes, full | fragment, generated | compute, generated | fragment, full | compute, full | CPU, {} threads |",
        rayon::current_num_threads()
    );
    crate::io::outln!("|---|---|---|---|---|---|---|---|---|");
    // Monte Carlo scenes have their own table ([`gpu_monte_carlo`]).
    let whitted: Vec<&Scene> = scenes
        .iter()
        .filter(|s| !s.settings.integrator.is_monte_carlo())
        .collect();
    let sizes = whitted
        .iter()
        .map(|s| (*s, 1280, 720))
        .chain(whitted.first().map(|s| (*s, 3840, 2160)));
    for (scene, width, height) in sizes {
        let mut s = scene.clone();
        s.camera.width = width;
        s.camera.height = height;
        let prepared = PreparedScene::new(s);
        let tracer = prepared.tracer();
        let counts = render(
            &tracer,
            &RenderOptions {
                count: true,
                ..Default::default()
            },
        )
        .map_err(|e| e.to_string())?
        .stats
        .counts;
        let mrays = |t: std::time::Duration| {
            let secs = t.as_secs_f64().max(1e-9);
            format!(
                "{:.0} / {:.0}",
                counts.primary as f64 / secs / 1e6,
                counts.rays() as f64 / secs / 1e6
            )
        };
        let mut row = format!(
            "| {} | {width}×{height} | {} | {} |",
            prepared.scene().name,
            crate::gpu::generated_wgsl(&prepared).len(),
            crate::gpu::full_wgsl(&prepared).len()
        );
        for variant in [ShaderVariant::Generated, ShaderVariant::Full] {
            let mut gpu =
                GpuTracer::new(ctx.clone(), &prepared, variant).map_err(|e| e.to_string())?;
            for path in [GpuPath::Fragment, GpuPath::Compute] {
                let t = gpu.time_frames(path, 1, reps).map_err(|e| e.to_string())?;
                row += &format!(" {:.1} ({}) |", t.as_secs_f64() * 1e3, mrays(t));
            }
        }
        let cpu = median_time(reps.min(3), || {
            std::hint::black_box(render(&tracer, &RenderOptions::default()).expect("render"));
        });
        row += &format!(" {:.1} ({}) |", cpu.as_secs_f64() * 1e3, mrays(cpu));
        crate::io::outln!("{row}");
    }
    Ok(())
}

/// The Monte Carlo integrators on the GPU: for each scene set to `distribution` or `path` (and the
/// default scene under each, so there is always a row), at 1280×720 with one sample per pixel
/// per frame, the samples per second of the fragment and compute paths (median frame time of
/// `reps` after one warm-up, trace pass only) and of the CPU render on all cores. On a CPU
/// rasterizer (lavapipe) the "GPU" figures are CPU times too, and the table says so.
pub fn gpu_monte_carlo(scenes: &[Scene], reps: usize) -> Result<(), String> {
    use crate::gpu::{GpuContext, GpuPath, GpuTracer, ShaderVariant};
    use crate::scene::Integrator;
    let ctx = GpuContext::headless().map_err(|e| e.to_string())?;
    crate::io::outln!(
        "## Monte Carlo on the GPU (1280×720, 1 sample per pixel per frame; Msamples/s, medians of {reps})"
    );
    crate::io::outln!("adapter: {}", ctx.adapter_name());
    if ctx.info.device_type == eframe::wgpu::DeviceType::Cpu {
        crate::io::outln!(
            "note: this adapter is a CPU rasterizer, so the GPU columns are CPU times as well \
             (its threads against raystep's own)"
        );
    }
    let mut mc: Vec<Scene> = scenes
        .iter()
        .filter(|s| s.settings.integrator.is_monte_carlo())
        .cloned()
        .collect();
    for integrator in [Integrator::Distribution, Integrator::Path] {
        let mut s = crate::scene::default_scene();
        s.settings.integrator = integrator;
        mc.push(s);
    }
    crate::io::outln!(
        "\n| scene | integrator | fragment | compute | CPU, {} threads |",
        rayon::current_num_threads()
    );
    crate::io::outln!("|---|---|---|---|---|");
    for scene in mc {
        let mut s = scene;
        s.camera.width = 1280;
        s.camera.height = 720;
        s.settings.spp = 1;
        let samples = 1280.0 * 720.0;
        let prepared = PreparedScene::new(s);
        let msps = |t: Duration| samples / t.as_secs_f64().max(1e-9) / 1e6;
        let mut row = format!(
            "| {} | {} |",
            prepared.scene().name,
            clap::ValueEnum::to_possible_value(&prepared.scene().settings.integrator)
                .map_or_else(String::new, |v| v.get_name().to_string())
        );
        let mut gpu = GpuTracer::new(ctx.clone(), &prepared, ShaderVariant::Generated)
            .map_err(|e| e.to_string())?;
        for path in [GpuPath::Fragment, GpuPath::Compute] {
            let t = gpu.time_frames(path, 1, reps).map_err(|e| e.to_string())?;
            row += &format!(" {:.2} ({:.0} ms) |", msps(t), t.as_secs_f64() * 1e3);
        }
        let tracer = prepared.tracer();
        let cpu = median_time(reps.min(3), || {
            std::hint::black_box(render(&tracer, &RenderOptions::default()).expect("render"));
        });
        row += &format!(" {:.2} ({:.0} ms) |", msps(cpu), cpu.as_secs_f64() * 1e3);
        crate::io::outln!("{row}");
    }
    Ok(())
}
