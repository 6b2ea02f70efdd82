//! The accelerators compared: brute force, the BVH, the bounding-sphere tree and the grid on the
//! same scenes (`--section accel-compare`), where the time goes (`stages`), the grid's λ
//! (`grid-lambda`), and how the cost per ray grows with the scene (`growth`).

use super::*;

/// Brute force and every accelerator, in the order the comparisons print them.
const ACCELERATORS: [AccelChoice; 4] = [
    AccelChoice::None,
    AccelChoice::Bvh,
    AccelChoice::Spheres,
    AccelChoice::Grid,
];

/// The scene at the comparisons' size: at most 160×120 pixels (brute force on a million
/// triangles must finish).
fn comparison_size(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.camera.width = s.camera.width.min(160);
    s.camera.height = s.camera.height.min(120);
    s
}

/// Every accelerator on every scene, one thread, at most 160×120 pixels: build time, memory,
/// primitive tests and node or cell visits per ray, rays per second and the speed-up over brute
/// force (all ray kinds; the images are identical, which `crates/raystep-diagram/tests/it/accelerators.rs` checks).
pub fn accel_compare(scenes: &[Scene], reps: usize) {
    crate::io::outln!(
        "## Accelerators compared, one thread, at most 160×120 pixels (all ray kinds)"
    );
    crate::io::outln!(
        "| scene | primitives | accelerator | build (ms) | memory (KiB) | tests / ray | visits / ray | Mrays/s | speed-up |"
    );
    crate::io::outln!("|---|---|---|---|---|---|---|---|---|");
    // Brute force on the larger scenes takes a while: say where the comparison is (on a
    // terminal's stderr only, so the table on stdout stays clean).
    let bar = indicatif::ProgressBar::new((scenes.len() * ACCELERATORS.len()) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{spinner} {pos}/{len} {msg} ({elapsed})")
            .expect("valid template"),
    );
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    for scene in scenes {
        let mut s = comparison_size(scene);
        let mut brute_time = None;
        for choice in ACCELERATORS {
            s.settings.accel = choice;
            bar.set_message(format!("{}: {:?}", s.name, choice));
            bar.enable_steady_tick(Duration::from_millis(200));
            let builds: Vec<(SceneAccel, Duration)> = (0..reps.clamp(1, 3))
                .map(|_| SceneAccel::build(&s))
                .collect();
            let mut times: Vec<Duration> = builds.iter().map(|b| b.1).collect();
            times.sort();
            let build = times[times.len() / 2];
            let accel = &builds[0].0;
            let tracer = Tracer::new(&s, accel);
            let c = count_rays(&tracer);
            let rays = c.rays().max(1) as f64;
            let t = median_time(reps, || all_pixels(&tracer));
            let brute = *brute_time.get_or_insert(t);
            let n = |x: f64| crate::record::number::fmt64(x, crate::record::number::Style::Label);
            // Printed with the progress line out of the way.
            bar.suspend(|| {
                crate::io::outln!(
                    "| {} | {} | {} | {} | {} | {} | {} | {} | {}× |",
                    s.name,
                    s.features.primitives,
                    accel.name(),
                    n(build.as_secs_f64() * 1e3),
                    n(accel.memory() as f64 / 1024.0),
                    n(c.prim_tests as f64 / rays),
                    n(c.node_visits as f64 / rays),
                    n(rays / t.as_secs_f64() / 1e6),
                    n(brute.as_secs_f64() / t.as_secs_f64()),
                )
            });
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
}

/// The uniform grid's resolution swept: for each scene and λ (cells per primitive), the grid's
/// cells and references, primitive tests and cells walked per ray, and its speed relative to
/// λ = [`GRID_LAMBDA`](crate::accel::grid::GRID_LAMBDA), one thread, at most 160×120 pixels.
pub fn grid_lambda(scenes: &[Scene], reps: usize) {
    use crate::accel::grid::{GRID_LAMBDA, Grid};
    const LAMBDAS: [f32; 7] = [0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0];
    crate::io::outln!("## The grid's λ swept, one thread, at most 160×120 pixels (all ray kinds)");
    crate::io::outln!(
        "| scene | λ | cells | references | tests / ray | cells / ray | Mrays/s | speed vs λ = {GRID_LAMBDA} |"
    );
    crate::io::outln!("|---|---|---|---|---|---|---|---|");
    let n = |x: f64| crate::record::number::fmt64(x, crate::record::number::Style::Label);
    for scene in scenes {
        let s = comparison_size(scene);
        let rows: Vec<_> = LAMBDAS
            .iter()
            .map(|&lambda| {
                let grid = Grid::build_with_lambda(&s, lambda);
                let tracer = Tracer::new(&s, &grid);
                let c = count_rays(&tracer);
                let t = median_time(reps, || all_pixels(&tracer));
                (lambda, grid, c, t)
            })
            .collect();
        let base = rows
            .iter()
            .find(|r| r.0 == GRID_LAMBDA)
            .map_or(1.0, |r| r.3.as_secs_f64());
        for (lambda, grid, c, t) in rows {
            let rays = c.rays().max(1) as f64;
            crate::io::outln!(
                "| {} | {lambda} | {}×{}×{} | {} | {} | {} | {} | {}× |",
                s.name,
                grid.dims[0],
                grid.dims[1],
                grid.dims[2],
                grid.references(),
                n(c.prim_tests as f64 / rays),
                n(c.node_visits as f64 / rays),
                n(rays / t.as_secs_f64() / 1e6),
                n(base / t.as_secs_f64()),
            );
        }
    }
}

/// One render's work captured for replay: every ray the tracer cast (its kind decides the
/// accelerator query: any hit for shadow rays, the closest otherwise) and every primitive test
/// (which ray, which object). Capturing costs nothing in the timed runs: they replay the lists.
#[derive(Default)]
struct Capture {
    rays: Vec<(RayKind, Ray<f32>)>,
    open: Vec<u32>,
    tests: Vec<(u32, u32)>,
}

impl crate::record::Observer for Capture {
    const RECORDS: bool = false;
    fn begin_ray(&mut self, kind: RayKind, _: u32, ray: &Ray<f32>, _: f32) {
        self.open.push(self.rays.len() as u32);
        self.rays.push((kind, *ray));
    }
    fn prim_test(&mut self, step: impl FnOnce() -> crate::record::Step) {
        use crate::record::Step;
        if let (
            Step::Sphere { object, .. }
            | Step::Plane { object, .. }
            | Step::Triangle { object, .. },
            Some(&r),
        ) = (step(), self.open.last())
        {
            self.tests.push((r, object));
        }
    }
    fn end_ray(&mut self, _: impl FnOnce() -> Option<crate::record::HitRecord>, _: Vec3) {
        self.open.pop();
    }
}

/// Where one thread's render of a scene spends its time (see [`stages`] for the method).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Stages {
    /// The whole render, seconds.
    pub render: f64,
    /// Making the camera rays, seconds.
    pub camera: f64,
    /// Every accelerator query (traversal and tests), seconds.
    pub queries: f64,
    /// Every primitive test alone, seconds.
    pub tests: f64,
    /// Primitive tests per ray.
    pub tests_per_ray: f64,
}

impl Stages {
    fn share(&self, x: f64) -> String {
        let f = self.render.max(f64::MIN_POSITIVE);
        format!("{:.0} %", 100.0 * (x / f).clamp(0.0, 1.0))
    }
    /// The four shares as text: camera rays, traversal, primitive tests, shading and spawning.
    pub fn shares(&self) -> [String; 4] {
        [
            self.share(self.camera),
            self.share((self.queries - self.tests).max(0.0)),
            self.share(self.tests.min(self.queries)),
            self.share((self.render - self.camera - self.queries).max(0.0)),
        ]
    }
}

/// Measures [`Stages`] for `scene` traced with `accel` on one thread, each part the median of
/// `reps` runs.
pub(crate) fn measure_stages<A: Accelerator>(s: &Scene, accel: &A, reps: usize) -> Stages {
    use crate::trace::sampling::sample_offset;
    let tracer = Tracer::new(s, accel);
    let full = median_time(reps, || all_pixels(&tracer));
    let mut cap = Capture::default();
    for y in 0..s.camera.height {
        for x in 0..s.camera.width {
            tracer.trace_pixel(x, y, &mut cap);
        }
    }
    let st = &s.settings;
    let camera = median_time(reps, || {
        for y in 0..s.camera.height {
            for x in 0..s.camera.width {
                for k in 0..st.spp {
                    let offset = sample_offset(x, y, k, st.spp, st.seed);
                    std::hint::black_box(tracer.camera.ray(x, y, offset));
                }
            }
        }
    });
    let queries = median_time(reps, || {
        for (kind, ray) in &cap.rays {
            let h = if *kind == RayKind::Shadow {
                accel.any(s, ray, &mut Silent)
            } else {
                accel.closest(s, ray, &mut Silent)
            };
            std::hint::black_box(h);
        }
    });
    let tests = median_time(reps, || {
        for &(r, id) in &cap.tests {
            if let Some((_, ray)) = cap.rays.get(r as usize) {
                std::hint::black_box(test_object(s, id, ray, &mut Silent));
            }
        }
    });
    Stages {
        render: full.as_secs_f64(),
        camera: camera.as_secs_f64(),
        queries: queries.as_secs_f64(),
        tests: tests.as_secs_f64(),
        tests_per_ray: cap.tests.len() as f64 / cap.rays.len().max(1) as f64,
    }
}

/// The scene as [`stages`] and `render --profile` measure it: at most 160×120 pixels.
pub(crate) fn profile_size(scene: &Scene) -> Scene {
    comparison_size(scene)
}

/// Where the time goes: the share of one thread's render spent making camera rays, traversing
/// the accelerator, testing primitives, and shading and spawning secondary rays, for brute force
/// and each accelerator. Measured by replay, so no timer sits inside the loop it measures: the
/// full render is timed; then, from one captured render, the camera rays alone, every
/// accelerator query alone (traversal and tests) and every primitive test alone. Traversal is
/// the queries minus the tests; shading and spawning is the render minus the camera and the
/// queries. (Replayed tests see the ray's whole interval, not the shrinking t_max of the real
/// run, so they can cost a little more: the test share is an upper bound.)
pub fn stages(scenes: &[Scene], reps: usize) {
    // Scenes with instances get a table of their own, first (the SPD scenes' brute-force rows
    // below take minutes).
    let two_level: Vec<Scene> = scenes
        .iter()
        .filter(|s| !s.instances.is_empty())
        .map(comparison_size)
        .collect();
    if !two_level.is_empty() {
        two_levels(&two_level, reps);
        crate::io::outln!();
    }
    crate::io::outln!(
        "## Where the time goes, one thread, at most 160×120 pixels (share of the render)"
    );
    crate::io::outln!(
        "| scene | accelerator | render (ms) | camera rays | traversal | primitive tests | shading and spawning | tests / ray |"
    );
    crate::io::outln!("|---|---|---|---|---|---|---|---|");
    for scene in scenes {
        let mut s = comparison_size(scene);
        if !s.instances.is_empty() {
            continue;
        }
        for choice in ACCELERATORS {
            s.settings.accel = choice;
            let (accel, _) = SceneAccel::build(&s);
            let m = measure_stages(&s, &accel, reps);
            let [c, tr, te, sh] = m.shares();
            crate::io::outln!(
                "| {} | {} | {:.1} | {c} | {tr} | {te} | {sh} | {:.1} |",
                s.name,
                accel.name(),
                m.render * 1e3,
                m.tests_per_ray,
            );
        }
    }
}

/// The two levels of a scene with instances timed apart, by replaying one captured render's
/// rays (one thread): the world's own objects alone; the TLAS walk alone (every instance box
/// the ray reaches, none entered); the whole query. The BLAS walks (carrying the ray into each
/// instance's object space, its tree and tests) are the whole minus the other two. Printed with
/// the structures' build times and sizes.
fn two_levels(scenes: &[Scene], reps: usize) {
    crate::io::outln!(
        "## The two levels apart, one thread, at most 160×120 pixels (share of the queries)"
    );
    crate::io::outln!(
        "| scene | instances | prototypes | TLAS nodes | BLAS nodes | build TLAS / BLAS (ms) | memory (KiB) | queries (ms) | world | TLAS | BLAS | instances entered / ray |"
    );
    crate::io::outln!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for s in scenes {
        let (accel, _) = SceneAccel::build(s);
        let SceneAccel::TwoLevel(t) = &accel else {
            continue;
        };
        let tracer = Tracer::new(s, &accel);
        let mut cap = Capture::default();
        for y in 0..s.camera.height {
            for x in 0..s.camera.width {
                tracer.trace_pixel(x, y, &mut cap);
            }
        }
        let query = |f: &dyn Fn(RayKind, &Ray<f32>)| {
            median_time(reps, || {
                for (kind, ray) in &cap.rays {
                    f(*kind, ray);
                }
            })
            .as_secs_f64()
        };
        let whole = query(&|kind, ray| {
            let h = if kind == RayKind::Shadow {
                accel.any(s, ray, &mut Silent)
            } else {
                accel.closest(s, ray, &mut Silent)
            };
            std::hint::black_box(h);
        });
        let world = query(&|kind, ray| {
            let h = if kind == RayKind::Shadow {
                t.world.any(s, ray, &mut Silent)
            } else {
                t.world.closest(s, ray, &mut Silent)
            };
            std::hint::black_box(h);
        });
        let tlas = query(&|_, ray| {
            std::hint::black_box(t.instances_reached(ray));
        });
        let mut entered = 0u64;
        let mut counter = EnterCount(0);
        for (kind, ray) in &cap.rays {
            if *kind == RayKind::Shadow {
                accel.any(s, ray, &mut counter);
            } else {
                accel.closest(s, ray, &mut counter);
            }
        }
        entered += counter.0;
        let blas = (whole - world - tlas).max(0.0);
        let pct = |x: f64| format!("{:.0} %", 100.0 * x / whole.max(1e-12));
        crate::io::outln!(
            "| {} | {} | {} | {} | {} | {:.2} / {:.2} | {:.1} | {:.1} | {} | {} | {} | {:.2} |",
            s.name,
            s.instances.len(),
            s.prototypes.len(),
            t.tlas.nodes.len(),
            t.blas.iter().map(|b| b.nodes.len()).sum::<usize>(),
            t.tlas_time.as_secs_f64() * 1e3,
            t.blas_time.as_secs_f64() * 1e3,
            accel.memory() as f64 / 1024.0,
            whole * 1e3,
            pct(world),
            pct(tlas),
            pct(blas),
            entered as f64 / cap.rays.len().max(1) as f64,
        );
    }
}

/// Counts the instances a query enters (their `Instance` steps), recording nothing.
struct EnterCount(u64);

impl crate::record::Observer for EnterCount {
    const RECORDS: bool = false;
    fn step(&mut self, step: impl FnOnce() -> crate::record::Step) {
        if matches!(step(), crate::record::Step::Instance { .. }) {
            self.0 += 1;
        }
    }
}

/// How the cost of a ray grows with the scene: the SPD scenes from tens to a million primitives,
/// each with the BVH, one thread, at most 160×120 pixels, all ray kinds: the build, the tree's
/// depth, node visits and primitive tests per ray, time per ray, and time per ray divided by
/// log₂ n (flat where the cost is logarithmic). Brute force is timed where it finishes (up to
/// 1,000 primitives) to show the linear cost the tree avoids.
pub fn growth(reps: usize) -> Result<(), String> {
    use crate::scene::spd::{SpdScene, generate};
    crate::io::outln!(
        "## Cost per ray against the number of primitives (BVH, one thread, all ray kinds)"
    );
    crate::io::outln!(
        "| scene | primitives | build (ms) | depth | visits / ray | tests / ray | ns / ray | ns / ray ÷ log₂ n | brute force ns / ray |"
    );
    crate::io::outln!("|---|---|---|---|---|---|---|---|---|");
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let n = |x: f64| crate::record::number::fmt64(x, crate::record::number::Style::Label);
    let plan: [(SpdScene, &[u32]); 3] = [
        (SpdScene::Balls, &[1, 2, 3, 4, 5]),
        (SpdScene::Tetra, &[1, 2, 4, 6, 8, 9]),
        (SpdScene::Mount, &[1, 2, 4, 6, 8, 9]),
    ];
    for (kind, sizes) in plan {
        for &size in sizes {
            let out = generate(kind, size)?;
            if let Some((name, obj)) = &out.obj {
                std::fs::write(dir.path().join(name), obj).map_err(|e| e.to_string())?;
            }
            let name = format!("SPD {} {size}", kind.name());
            let mut s = load_str(&out.toml, &name, Some(dir.path())).map_err(|e| e.to_string())?;
            s.name = name;
            let mut s = comparison_size(&s);
            s.settings.accel = AccelChoice::Bvh;
            let mut builds: Vec<(SceneAccel, Duration)> = (0..reps.clamp(1, 3))
                .map(|_| SceneAccel::build(&s))
                .collect();
            builds.sort_by_key(|b| b.1);
            let build = builds[builds.len() / 2].1;
            let accel = &builds[0].0;
            let depth = match accel {
                SceneAccel::Bvh(b) => b.max_depth,
                _ => 0,
            };
            let tracer = Tracer::new(&s, accel);
            let c = count_rays(&tracer);
            let rays = c.rays().max(1) as f64;
            let t = median_time(reps, || all_pixels(&tracer));
            let per_ray = t.as_secs_f64() * 1e9 / rays;
            let prims = s.features.primitives.max(2) as f64;
            let brute = if s.features.primitives <= 1000 {
                s.settings.accel = AccelChoice::None;
                let (b, _) = SceneAccel::build(&s);
                let bt = Tracer::new(&s, &b);
                let tb = median_time(reps.min(3), || all_pixels(&bt));
                n(tb.as_secs_f64() * 1e9 / rays)
            } else {
                "—".into()
            };
            crate::io::outln!(
                "| {} | {} | {} | {depth} | {} | {} | {} | {} | {brute} |",
                s.name,
                s.features.primitives,
                n(build.as_secs_f64() * 1e3),
                n(c.node_visits as f64 / rays),
                n(c.prim_tests as f64 / rays),
                n(per_ray),
                n(per_ray / prims.log2()),
            );
        }
    }
    Ok(())
}
