//! The GPU's own step trace (`raystep trace --gpu`, issue 33): the trace shader logs every step
//! one GPU invocation takes, read back into raystep's trace format and compared with the CPU's
//! trace by `raystep diff`.
//!
//! Expected values come from the CPU tracer (an independent implementation of the same
//! arithmetic, in Rust): where the adapter's compute path is exact, every shipped scene's GPU
//! trace must equal the CPU's, number for number. Skipped (with a message) where wgpu finds no
//! adapter, except under CI, which must run them (lavapipe).

use raystep::explain::diff::compare;
use raystep::gpu::trace_log::DEFAULT_LOG_WORDS;
use raystep::gpu::{GpuContext, GpuPath, GpuTracer, ShaderVariant};
use raystep::record::{Step, Tolerance, Trace};
use raystep::scene::Scene;
use raystep::trace::PreparedScene;
use std::path::Path;
use std::process::Command;

use crate::common::gpu as gpu_common;
use crate::common::scenes;
use gpu_common::{context, load_whitted, one_at_a_time};

/// The shipped scenes (scenes/*.toml), sorted; there are several.
fn scene_paths() -> Vec<std::path::PathBuf> {
    let v = scenes::shipped_for_gpu();
    assert!(v.len() >= 6, "the shipped scenes are found");
    v
}

/// The shipped scenes traced under hardware ray queries (see
/// `gpu_traces_equal_the_cpu_traces_on_every_shipped_scene`).
const RAY_QUERY_SCENES: [&str; 5] = [
    "three-spheres.toml",
    "triangles.toml",
    "mirror-glass.toml",
    "smooth-shading.toml",
    "textures.toml",
];

/// A shipped scene by file name, prepared, with its GPU tracer.
fn shipped(ctx: GpuContext, name: &str) -> (Scene, PreparedScene, GpuTracer) {
    let file = scene_paths()
        .into_iter()
        .find(|p| p.ends_with(name))
        .unwrap();
    let scene = load_whitted(&file);
    let prepared = PreparedScene::new(scene.clone());
    let gpu = GpuTracer::new(ctx, &prepared, ShaderVariant::Generated).unwrap();
    (scene, prepared, gpu)
}

/// The centre and a 3×3 grid of pixels.
fn pixels(scene: &Scene) -> Vec<[u32; 2]> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut v = vec![[w / 2, h / 2]];
    for j in [1, 3, 5] {
        for i in [1, 3, 5] {
            v.push([w * i / 6, h * j / 6]);
        }
    }
    v
}

fn steps(t: &Trace) -> Vec<&Step> {
    t.timeline().into_iter().map(|(_, s)| &s.step).collect()
}

#[test]
fn gpu_traces_equal_the_cpu_traces_on_every_shipped_scene() {
    let _gpu = one_at_a_time();
    let Some(ctx) = context("gpu_traces_equal_the_cpu_traces_on_every_shipped_scene") else {
        return;
    };
    let mut failures = vec![];
    let mut compared = 0usize;
    for file in scene_paths() {
        // Under hardware ray queries only the hit is compared below, and the image test
        // (gpu::gpu_matches_cpu_on_every_shipped_scene) compares every pixel of every scene
        // there; each scene's ray-query trace shader costs tens of seconds to compile on Mesa's
        // lavapipe (all sixteen: 280 s of CI's Mesa 25 run). So an adapter with ray queries
        // traces the scenes that between them hold every shape, a mesh, smooth shading,
        // textures, shadows, reflection and refraction.
        if ctx.ray_query && !RAY_QUERY_SCENES.iter().any(|n| file.ends_with(n)) {
            continue;
        }
        let scene = load_whitted(&file);
        let prepared = PreparedScene::new(scene.clone());
        let mut gpu = GpuTracer::new(ctx.clone(), &prepared, ShaderVariant::Generated).unwrap();
        let exact = gpu.exact(GpuPath::Compute) && gpu.arithmetic().probe.subnormals_kept();
        let hardware = gpu.hardware_ray_queries();
        let spawns = scene.features.reflective || scene.features.transparent;
        for [x, y] in pixels(&scene) {
            let cpu = prepared.record(x, y, 0);
            let got = gpu.trace_pixel(x, y, 0, DEFAULT_LOG_WORDS).unwrap();
            assert!(!got.truncated, "{}: ({x}, {y}) ran out of log", scene.name);
            // What the GPU wrote is a trace raystep reads back (the loader's checks).
            Trace::from_json(&got.trace.to_json(), "gpu.json").unwrap();
            let gs = steps(&got.trace);
            if hardware {
                // Ray queries: the hardware walks its own tree; the trace says so instead of
                // showing BVH nodes, and the primitives it reports are tested as on the CPU.
                let finite = scene.objects.iter().any(|o| !o.shape.is_infinite());
                assert!(
                    gs.iter().all(|s| !matches!(s, Step::Node(_))),
                    "{}: node visits under ray queries",
                    scene.name
                );
                assert_eq!(
                    finite,
                    gs.iter()
                        .any(|s| matches!(s, Step::HardwareTraversal { .. })),
                    "{}",
                    scene.name
                );
                let hit = |t: &Trace| t.root.hit.as_ref().map(|h| (h.object, h.t.to_bits()));
                if hit(&cpu) != hit(&got.trace) {
                    failures.push(format!("{} ({x}, {y}): another hit", scene.name));
                }
                continue;
            }
            let cmp = compare(&cpu, &got.trace, Tolerance::EXACT);
            compared += cmp.numbers_compared;
            // The pixel's colour is the GPU's own sum: it adds each ray's term, times its share,
            // in its ray stack's order, where the CPU nests the sums; with reflected or
            // refracted rays the last bits may differ (every ray's colour in the trace agrees).
            let summed_apart = |d: &raystep::explain::diff::Difference| {
                spawns
                    && d.step.is_none()
                    && d.field.as_deref().is_some_and(|f| f.starts_with("color"))
                    && d.difference.is_some_and(|e| e <= 1e-6)
            };
            if exact && !cmp.differences.iter().all(summed_apart) {
                failures.push(cmp.to_text(&cpu, &got.trace, ["cpu", "gpu"]));
            }
            // The same work, step for step, whatever the arithmetic: the same kinds of step.
            let kinds = |v: &[&Step]| {
                v.iter()
                    .map(|s| std::mem::discriminant(*s))
                    .collect::<Vec<_>>()
            };
            if exact {
                assert_eq!(kinds(&steps(&cpu)), kinds(&gs), "{}", scene.name);
            }
        }
    }
    eprintln!("{compared} numbers compared");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn a_planted_fused_dot_product_is_named_by_diff() {
    let _gpu = one_at_a_time();
    let Some(ctx) = context("a_planted_fused_dot_product_is_named_by_diff") else {
        return;
    };
    let (scene, prepared, mut gpu) = shipped(ctx, "three-spheres.toml");
    if !gpu.exact(GpuPath::Compute) || gpu.hardware_ray_queries() {
        // Under ray queries the GPU's trace takes other traversal steps than the CPU's anyway.
        eprintln!("SKIPPED: the adapter's compute path is not exact, or walks its own tree");
        return;
    }
    gpu.plant_fused_dot();
    // Dot products in the tests, the shading and the spawned rays: the first to round apart
    // from the CPU's unfused sum is named.
    let from_dot = [
        "a",
        "b",
        "c",
        "discriminant",
        "delta_prime",
        "l",
        "numerator",
        "denominator",
        "l_dot_n",
        "r_dot_e",
        "distance",
        "direction",
        "d_dot_n",
        "cos_i",
        "point",
        "normal",
        "over_point",
    ];
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut found = None;
    'scan: for y in (0..h).step_by(7) {
        for x in (0..w).step_by(11) {
            let cpu = prepared.record(x, y, 0);
            let got = gpu.trace_pixel(x, y, 0, DEFAULT_LOG_WORDS).unwrap();
            let cmp = compare(&cpu, &got.trace, Tolerance::EXACT);
            if !cmp.is_equal() {
                found = Some((cpu, got.trace, cmp));
                break 'scan;
            }
        }
    }
    let (cpu, got, cmp) = found.expect("a fused dot product rounds apart somewhere");
    let first = cmp.first().unwrap();
    let field = first.field.clone().unwrap_or_default();
    let name = field.split(['[', '.']).next().unwrap_or_default();
    assert!(first.step.is_some(), "{first:?}");
    assert!(from_dot.contains(&name), "{first:?}");
    let text = cmp.to_text(&cpu, &got, ["cpu.json", "gpu.json"]);
    eprintln!("{text}");
    let k = first.step.unwrap();
    assert!(
        text.contains(&format!("first divergence: step {k}")),
        "{text}"
    );
    assert!(text.contains(name), "{text}");
}

#[test]
fn a_trace_that_outgrows_its_log_ends_with_a_truncated_step() {
    let _gpu = one_at_a_time();
    let Some(ctx) = context("a_trace_that_outgrows_its_log_ends_with_a_truncated_step") else {
        return;
    };
    let (scene, _, mut gpu) = shipped(ctx, "mirror-glass.toml");
    let (x, y) = (scene.camera.width / 2, scene.camera.height / 2);
    let full = gpu.trace_pixel(x, y, 0, DEFAULT_LOG_WORDS).unwrap();
    // The smallest log holds the header and one record.
    let cut = gpu.trace_pixel(x, y, 0, 0).unwrap();
    assert!(!full.truncated && cut.truncated);
    assert!(cut.steps < full.steps, "{} of {}", cut.steps, full.steps);
    let last = steps(&cut.trace).last().copied().cloned();
    assert!(matches!(last, Some(Step::Truncated { .. })), "{last:?}");
    // The pixel colour is the GPU's either way (it is logged last, so it is lost: the root's).
    Trace::from_json(&cut.trace.to_json(), "cut.json").unwrap();
}

#[test]
fn the_cli_saves_a_gpu_trace_that_diff_reads() {
    let _gpu = one_at_a_time();
    if context("the_cli_saves_a_gpu_trace_that_diff_reads").is_none() {
        return;
    }
    let bin = env!("CARGO_BIN_EXE_raystep");
    let dir = tempfile::tempdir().unwrap();
    let (cpu, gpu) = (dir.path().join("cpu.json"), dir.path().join("gpu.json"));
    let run = |args: &[&str]| Command::new(bin).args(args).output().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/triangles.toml");
    let scene = scene.to_str().unwrap();
    let g = run(&[
        "trace",
        scene,
        "--pixel",
        "160,120",
        "--gpu",
        "--save",
        gpu.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&g.stderr);
    assert!(g.status.success(), "{err}");
    assert!(
        err.contains("GPU trace: ") && err.contains("arithmetic"),
        "{err}"
    );
    let c = run(&[
        "trace",
        scene,
        "--pixel",
        "160,120",
        "--save",
        cpu.to_str().unwrap(),
    ]);
    assert!(c.status.success());
    let d = run(&["diff", cpu.to_str().unwrap(), gpu.to_str().unwrap()]);
    let out = String::from_utf8_lossy(&d.stdout);
    // Equal where the adapter is exact (exit 0), else a first divergence in words (exit 1).
    match d.status.code() {
        Some(0) => assert!(out.contains("the traces are equal"), "{out}"),
        Some(1) => assert!(out.contains("first divergence"), "{out}"),
        other => panic!("diff exited {other:?}: {out}"),
    }
    // The fragment path: traced too, with a note on where its primary ray comes from.
    let f = dir.path().join("f.json");
    let r = run(&[
        "trace",
        scene,
        "--pixel",
        "160,120",
        "--gpu",
        "--gpu-path",
        "fragment",
        "--save",
        f.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(r.status.success() && err.contains("interpolation"), "{err}");
    Trace::load(&f).unwrap();
    // --gpu-path without --gpu is refused by the argument parser.
    let r = run(&["trace", scene, "--pixel", "1,1", "--gpu-path", "compute"]);
    assert!(!r.status.success());
}

/// The fragment path's trace: the rasterizer's interpolated primary ray (its direction within a
/// few ulp of the CPU's; no screen position), then the same work: the same hit for a pixel away
/// from any edge.
#[test]
fn the_fragment_path_is_traced_with_its_interpolated_ray() {
    let _gpu = one_at_a_time();
    let Some(ctx) = context("the_fragment_path_is_traced_with_its_interpolated_ray") else {
        return;
    };
    let (scene, prepared, mut gpu) = shipped(ctx, "three-spheres.toml");
    let (x, y) = (scene.camera.width / 2, scene.camera.height / 2);
    let cpu = prepared.record(x, y, 0);
    let got = gpu
        .trace_pixel_on(GpuPath::Fragment, x, y, 0, DEFAULT_LOG_WORDS)
        .unwrap();
    let camera = |t: &Trace| {
        steps(t).into_iter().find_map(|s| match s {
            Step::Camera {
                pixel,
                screen,
                direction,
                ..
            } => Some((*pixel, *screen, *direction)),
            _ => None,
        })
    };
    let (cp, _, cd) = camera(&cpu).unwrap();
    let (gp, gs, gd) = camera(&got.trace).expect("a camera step");
    assert_eq!(cp, gp);
    assert!(gs.iter().all(|v| v.is_nan()), "{gs:?}");
    for (a, b) in cd.iter().zip(gd) {
        assert!((a - b).abs() <= 1e-5, "CPU {cd:?} GPU {gd:?}");
    }
    let hit = |t: &Trace| t.root.hit.as_ref().map(|h| h.object);
    assert_eq!(hit(&cpu), hit(&got.trace));
    Trace::from_json(&got.trace.to_json(), "fragment.json").unwrap();
    // Words and the math panel say where the direction came from, with no NaN in a formula.
    let step = &got.trace.root.steps[0].step;
    let words = raystep::explain::describe::describe(step, got.trace.root.kind);
    assert!(words.contains("interpolated by the rasterizer"), "{words}");
    let e = raystep::explain::formula::explain(&got.trace, &got.trace.root, step);
    assert!(e.conclusion.contains("never computed"), "{e:?}");
    assert!(!format!("{e:?}").contains("NaN"), "{e:?}");
}
