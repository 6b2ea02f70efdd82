//! The GPU's own step trace of Monte Carlo samples (`raystep trace --gpu` on a distribution or
//! path scene, issue 36 §4): the trace shader logs every step of the sample the GPU's integrator
//! takes (the lens, emission, light samples and their shadow rays, BSDF samples, Russian
//! roulette, each ray's radiance) and the summaries of the pixel's samples, read back into the
//! trace format.
//!
//! Expected values come from the CPU's Monte Carlo tracer (crates/raystep-core/src/mc/, an independent
//! implementation of the same arithmetic in Rust): where the adapter's compute path is exact
//! (lavapipe), the GPU's trace equals the CPU's, number for number. Skipped (with a message)
//! where wgpu finds no adapter, except under CI.

use raystep::explain::diff::compare;
use raystep::gpu::trace_log::DEFAULT_LOG_WORDS;
use raystep::gpu::{GpuPath, GpuTracer, ShaderVariant};
use raystep::record::{RayKind, Step, Tolerance, Trace};
use raystep::scene::{Integrator, Scene};
use raystep::trace::PreparedScene;
use std::collections::BTreeMap;
use std::process::Command;

use crate::common::gpu as gpu_common;
use crate::common::scenes;
use gpu_common::{context, one_at_a_time};

/// A shipped scene, with its integrator set where `integrator` says so.
fn scene(name: &str, integrator: Option<Integrator>) -> Scene {
    let mut s = raystep::scene::load_file(&scenes::root().join("scenes").join(name)).unwrap();
    if let Some(i) = integrator {
        s.settings.integrator = i;
    }
    assert_ne!(s.settings.integrator, Integrator::Whitted, "{name}");
    s
}

fn steps(t: &Trace) -> Vec<&Step> {
    t.timeline().into_iter().map(|(_, s)| &s.step).collect()
}

/// The name of each kind of step, counted (to show the traces hold the Monte Carlo steps).
fn tally(t: &Trace, into: &mut BTreeMap<&'static str, usize>) {
    for s in steps(t) {
        let name = match s {
            Step::Lens { .. } => "lens",
            Step::Emitted { .. } => "emitted",
            Step::LightSample { .. } => "light sample",
            Step::BsdfSample { .. } => "bsdf sample",
            Step::RussianRoulette { .. } => "roulette",
            Step::WeightCutoff { .. } => "cutoff",
            Step::DepthLimit { .. } => "depth limit",
            _ => continue,
        };
        *into.entry(name).or_default() += 1;
    }
    fn kinds(r: &raystep::record::RayRecord, into: &mut BTreeMap<&'static str, usize>) {
        let name = match r.kind {
            RayKind::Diffuse => "diffuse ray",
            RayKind::Glossy => "glossy ray",
            RayKind::Refraction => "refraction ray",
            RayKind::Reflection => "reflection ray",
            RayKind::Shadow => "shadow ray",
            RayKind::Primary => "primary ray",
        };
        *into.entry(name).or_default() += 1;
        for c in &r.children {
            kinds(c, into);
        }
    }
    kinds(&t.root, into);
}

/// Pixels spread over the image, and samples of each.
fn pixels(s: &Scene) -> Vec<([u32; 2], u32)> {
    let (w, h) = (s.camera.width, s.camera.height);
    let last = s.settings.spp - 1;
    vec![
        ([w / 2, h / 2], last),
        ([w / 3, h * 2 / 3], 1 % s.settings.spp),
        ([w * 4 / 5, h / 3], 0),
    ]
}

/// Also runs, on the tracers it makes, the checks below that need one (each tracer compiles its
/// shaders on lavapipe: seconds to tens of seconds on a CI machine).
///
/// The Cornell box is traced through its BVH (14 objects): the Monte Carlo trace shader with the
/// BVH's logged traversal is the costliest to compile (docs/ARCHITECTURE.md, *Lavapipe's shader
/// cache*: 34 s of CPU into an empty cache).
#[test]
fn gpu_traces_of_monte_carlo_samples_equal_the_cpu_traces() {
    let _gpu = one_at_a_time();
    let Some(ctx) = context("gpu_traces_of_monte_carlo_samples_equal_the_cpu_traces") else {
        return;
    };
    // Path: next-event estimation with MIS, a mirror ball, roulette; glossy plates. Distribution:
    // soft shadows, a lens and glossy balls. Glass under both (mirror-glass.toml): the
    // distribution tracer's two branches and cut-offs, the path tracer's lobe choice. Textures
    // under the path tracer.
    let cases = [
        ("cornell-area.toml", None),
        ("soft-shadows.toml", None),
        ("depth-of-field.toml", None),
        ("mirror-glass.toml", Some(Integrator::Distribution)),
        ("mirror-glass.toml", Some(Integrator::Path)),
        // Textures: a checker, a bilinear image on a sphere, a nearest one on triangles; the
        // texture step and the textured albedo.
        ("textures.toml", Some(Integrator::Path)),
    ];
    let mut failures = vec![];
    let mut seen = BTreeMap::new();
    let mut compared = 0usize;
    for (name, integrator) in cases {
        let s = scene(name, integrator);
        let prepared = PreparedScene::new(s.clone());
        // The BVH's traversal is traced in the Cornell box, brute force in the others.
        assert_eq!(
            prepared.bvh().is_some(),
            name == "cornell-area.toml",
            "{name}"
        );
        let mut gpu = GpuTracer::new(ctx.clone(), &prepared, ShaderVariant::Generated).unwrap();
        let exact = gpu.exact(GpuPath::Compute) && gpu.arithmetic().probe.subnormals_kept();
        if !exact || gpu.hardware_ray_queries() {
            eprintln!("SKIPPED {name}: the adapter's compute path is not exact");
            continue;
        }
        let mut px = pixels(&s);
        if name == "cornell-area.toml" {
            // And a pixel whose camera ray lands on the area light (found with the CPU's trace):
            // the emission step and its MIS weights.
            let (w, h) = (s.camera.width, s.camera.height);
            let on_light = (0..h).step_by(4).map(|y| [w / 2, y]).find(|&[x, y]| {
                prepared
                    .record(x, y, 0)
                    .root
                    .steps
                    .iter()
                    .any(|r| matches!(r.step, Step::Emitted { .. }))
            });
            px.push((on_light.expect("a pixel sees the light"), 0));
        }
        for ([x, y], k) in px {
            let cpu = prepared.record(x, y, k);
            let got = gpu.trace_pixel(x, y, k, DEFAULT_LOG_WORDS).unwrap();
            let at = format!("{name} {integrator:?} ({x}, {y}) sample {k}");
            assert!(!got.truncated && !got.summaries_truncated, "{at}");
            // Read back as raystep reads a saved trace (the loader's checks).
            Trace::from_json(&got.trace.to_json(), "gpu.json").unwrap();
            let mc = got
                .trace
                .monte_carlo
                .as_ref()
                .expect("a Monte Carlo record");
            assert_eq!(mc.samples.len() as u32, s.settings.spp.min(1024), "{at}");
            tally(&got.trace, &mut seen);
            let cmp = compare(&cpu, &got.trace, Tolerance::EXACT);
            compared += cmp.numbers_compared;
            if !cmp.is_equal() {
                failures.push(format!(
                    "{at}:\n{}",
                    cmp.to_text(&cpu, &got.trace, ["cpu", "gpu"])
                ));
            }
        }
        match name {
            "cornell-area.toml" => {
                a_perturbed_gpu_value_is_named_by_diff(&s, &prepared, &mut gpu);
                a_monte_carlo_trace_that_outgrows_its_log_says_where(&s, &mut gpu);
            }
            "soft-shadows.toml" => {
                the_fragment_path_traces_monte_carlo_samples(&s, &prepared, &mut gpu)
            }
            _ => {}
        }
    }
    eprintln!("{compared} numbers compared; steps seen: {seen:?}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    if compared > 0 {
        // Every kind of Monte Carlo step and ray was compared somewhere.
        for kind in [
            "lens",
            "emitted",
            "light sample",
            "bsdf sample",
            "roulette",
            "cutoff",
            "diffuse ray",
            "glossy ray",
            "refraction ray",
            "reflection ray",
            "shadow ray",
        ] {
            assert!(seen.contains_key(kind), "no {kind} in the traces: {seen:?}");
        }
    }
}

/// One GPU number changed (a summarised sample's value, a light sample's contribution) is a
/// difference `raystep diff` names: the comparison is not blind to what the GPU wrote.
/// (Part of the first test, which has the scene's tracer made: each tracer compiles its shaders
/// on lavapipe, seconds to tens of seconds each.)
fn a_perturbed_gpu_value_is_named_by_diff(
    s: &Scene,
    prepared: &PreparedScene,
    gpu: &mut GpuTracer,
) {
    let (x, y) = (s.camera.width / 2, s.camera.height * 3 / 4);
    let cpu = prepared.record(x, y, 2);
    let got = gpu.trace_pixel(x, y, 2, DEFAULT_LOG_WORDS).unwrap().trace;
    assert!(compare(&cpu, &got, Tolerance::EXACT).is_equal());
    let ulp = |v: &mut f32| *v = f32::from_bits(v.to_bits() + 1);

    // A later sample's value, one ulp off.
    let mut t = got.clone();
    let mc = t.monte_carlo.as_mut().unwrap();
    ulp(&mut mc.samples[5].color[1]);
    let cmp = compare(&cpu, &t, Tolerance::EXACT);
    assert!(!cmp.is_equal());
    let text = cmp.to_text(&cpu, &t, ["cpu", "gpu"]);
    assert!(text.contains("samples") && text.contains("color"), "{text}");

    // A light sample's contribution in the traced sample's steps.
    let mut t = got.clone();
    let mut changed = None;
    for (k, s) in t.root.steps.iter_mut().enumerate() {
        if let Step::LightSample { contribution, .. } = &mut s.step {
            ulp(&mut contribution[0]);
            changed = Some(k);
            break;
        }
    }
    assert!(changed.is_some(), "the camera ray's hit samples a light");
    let cmp = compare(&cpu, &t, Tolerance::EXACT);
    let first = cmp.first().expect("a difference");
    assert!(first.step.is_some(), "{first:?}");
    assert!(
        first
            .field
            .as_deref()
            .is_some_and(|f| f.starts_with("contribution")),
        "{first:?}"
    );
}

/// A log too small for the trace ends the trace with a `truncated` step; one that holds the
/// traced sample but not every summary keeps the steps and says the summaries were cut. Either
/// trace loads; no panic.
/// (Part of the first test, on its Cornell tracer.)
fn a_monte_carlo_trace_that_outgrows_its_log_says_where(s: &Scene, gpu: &mut GpuTracer) {
    let (x, y) = (s.camera.width / 2, s.camera.height / 2);
    let full = gpu.trace_pixel(x, y, 0, DEFAULT_LOG_WORDS).unwrap();
    assert!(!full.truncated);
    let cut = gpu.trace_pixel(x, y, 0, 0).unwrap();
    assert!(cut.truncated && !cut.summaries_truncated);
    assert!(matches!(
        steps(&cut.trace).last(),
        Some(Step::Truncated { .. })
    ));
    Trace::from_json(&cut.trace.to_json(), "cut.json").unwrap();
    // The smallest log that holds everything, found by bisection; one word less loses the
    // last summary only.
    let (mut lo, mut hi) = (68usize, 1usize << 16);
    assert!(!gpu.trace_pixel(x, y, 0, hi).unwrap().truncated);
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if gpu.trace_pixel(x, y, 0, mid).unwrap().truncated {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let short = gpu.trace_pixel(x, y, 0, lo).unwrap();
    assert!(short.truncated && short.summaries_truncated, "{lo} words");
    // The traced sample's steps are all there; the summaries, one short, are left out (a record
    // holds them all or none), and the trace still loads.
    assert!(short.trace.monte_carlo.is_none() && full.trace.monte_carlo.is_some());
    assert!(
        !steps(&short.trace)
            .iter()
            .any(|s| matches!(s, Step::Truncated { .. }))
    );
    assert_eq!(short.trace.root, full.trace.root);
    Trace::from_json(&short.trace.to_json(), "short.json").unwrap();
}

/// The fragment path traces a Monte Carlo sample too (its primary ray interpolated by the
/// rasterizer): the same work, the same first hit for a pixel away from edges.
/// (Part of the first test, on its soft-shadows tracer.)
fn the_fragment_path_traces_monte_carlo_samples(
    s: &Scene,
    prepared: &PreparedScene,
    gpu: &mut GpuTracer,
) {
    let (x, y) = (s.camera.width / 2, s.camera.height * 3 / 4);
    let cpu = prepared.record(x, y, 0);
    let got = gpu
        .trace_pixel_on(GpuPath::Fragment, x, y, 0, DEFAULT_LOG_WORDS)
        .unwrap();
    assert!(!got.truncated);
    let hit = |t: &Trace| t.root.hit.as_ref().map(|h| h.object);
    assert_eq!(hit(&cpu), hit(&got.trace));
    let count = |t: &Trace| {
        steps(t)
            .iter()
            .filter(|s| matches!(s, Step::LightSample { .. }))
            .count()
    };
    assert!(count(&got.trace) > 0);
    assert_eq!(count(&cpu), count(&got.trace));
    let mc = got.trace.monte_carlo.as_ref().unwrap();
    assert_eq!(mc.samples.len() as u32, s.settings.spp);
    Trace::from_json(&got.trace.to_json(), "fragment.json").unwrap();
}

/// `raystep trace --gpu` on a path scene traces the path tracer (no note that Whitted stands in)
/// and `raystep diff` finds the CPU's trace of the same sample equal on an exact adapter.
#[test]
fn the_cli_traces_a_path_sample_on_the_gpu() {
    let _gpu = one_at_a_time();
    if context("the_cli_traces_a_path_sample_on_the_gpu").is_none() {
        return;
    }
    let bin = env!("CARGO_BIN_EXE_raystep");
    let dir = tempfile::tempdir().unwrap();
    let (cpu, gpu) = (dir.path().join("cpu.json"), dir.path().join("gpu.json"));
    let run = |args: &[&str]| Command::new(bin).args(args).output().unwrap();
    // The soft-shadows scene (spheres and a plane) set to the path tracer: its trace shader
    // compiles in about a quarter of the Cornell box's time on lavapipe (43 s of CPU against
    // 171 s); the Cornell box's own trace shader is compared step by step in the test above.
    let text = std::fs::read_to_string(scenes::root().join("scenes/soft-shadows.toml")).unwrap();
    assert!(text.contains("integrator = \"distribution\""));
    let scene = dir.path().join("soft-shadows-path.toml");
    std::fs::write(
        &scene,
        text.replace("integrator = \"distribution\"", "integrator = \"path\""),
    )
    .unwrap();
    let scene = scene.to_str().unwrap();
    let common = ["--pixel", "100,150", "--sample", "3", "--save"];
    let g = run(&[
        &["trace", scene, "--gpu"][..],
        &common,
        &[gpu.to_str().unwrap()],
    ]
    .concat());
    let err = String::from_utf8_lossy(&g.stderr);
    assert!(g.status.success(), "{err}");
    assert!(!err.contains("Whitted"), "{err}");
    let c = run(&[&["trace", scene][..], &common, &[cpu.to_str().unwrap()]].concat());
    assert!(c.status.success());
    let t = Trace::load(&gpu).unwrap();
    assert_eq!(t.settings.integrator, Integrator::Path);
    assert_eq!(t.sample, 3);
    let d = run(&["diff", cpu.to_str().unwrap(), gpu.to_str().unwrap()]);
    let out = String::from_utf8_lossy(&d.stdout);
    let exact = err.contains("arithmetic: exact");
    match d.status.code() {
        Some(0) => assert!(out.contains("the traces are equal"), "{out}"),
        Some(1) if !exact => assert!(out.contains("first divergence"), "{out}"),
        other => panic!("diff exited {other:?}: {out}"),
    }
}

/// A glossy BSDF's roughness texture on the GPU (tests/scenes/rough-glossy.toml: green 0.8 and
/// 0.02 squares, a glossy floor and a mirror one): the compute path's image is the CPU's bit
/// for bit under both Monte Carlo integrators, and the trace of a pixel on each kind of square
/// is the CPU's, its roughness step included.
#[test]
fn a_roughness_texture_renders_and_traces_as_on_the_cpu() {
    let _gpu = one_at_a_time();
    let test = "a_roughness_texture_renders_and_traces_as_on_the_cpu";
    let Some(ctx) = context(test) else {
        return;
    };
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/rough-glossy.toml");
    let base = raystep::scene::load_file(&path).unwrap();
    let mut failures = vec![];
    for integrator in [Integrator::Path, Integrator::Distribution] {
        let mut s = base.clone();
        s.settings.integrator = integrator;
        let prepared = PreparedScene::new(s.clone());
        let mut gpu = GpuTracer::new(ctx.clone(), &prepared, ShaderVariant::Generated).unwrap();
        if !gpu.exact(GpuPath::Compute) || gpu.hardware_ray_queries() {
            eprintln!("SKIPPED {test}: the adapter's compute path is not exact");
            return;
        }
        let cpu = raystep::render::render(
            &prepared.tracer(),
            &raystep::render::RenderOptions::default(),
        )
        .unwrap()
        .pixels;
        let frame = gpu.render(GpuPath::Compute).unwrap();
        let differ = cpu
            .iter()
            .zip(&frame.pixels)
            .filter(|(a, b)| a.to_array().map(f32::to_bits) != b.to_array().map(f32::to_bits))
            .count();
        if differ > 0 {
            failures.push(format!("{integrator:?}: {differ} pixels differ"));
        }
        // An even square (roughness 0.4) and an odd one (0.01: a mirror).
        for [x, y] in [[24, 32], [24, 26]] {
            let want = prepared.record(x, y, 0);
            let got = gpu.trace_pixel(x, y, 0, DEFAULT_LOG_WORDS).unwrap();
            assert!(!got.truncated);
            let read = steps(&got.trace).into_iter().any(|s| {
                matches!(
                    s,
                    Step::Texture {
                        roughness: Some(_),
                        ..
                    }
                )
            });
            assert!(
                read,
                "{integrator:?} ({x}, {y}): no roughness step in the GPU's trace"
            );
            let cmp = compare(&want, &got.trace, Tolerance::EXACT);
            if !cmp.is_equal() {
                failures.push(format!(
                    "{integrator:?} ({x}, {y}):\n{}",
                    cmp.to_text(&want, &got.trace, ["cpu", "gpu"])
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
