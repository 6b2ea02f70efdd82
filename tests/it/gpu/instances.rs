//! Instances on the GPU: the compute path walks the TLAS and each entered instance's BLAS in
//! WGSL, in the CPU's order and arithmetic; hardware ray queries build one BLAS per prototype and
//! a TLAS with the instances' matrices. Expected values come from the CPU tracer (its two-level
//! walk, `crates/raystep-core/src/accel/two_level.rs`): on an exact compute path the linear
//! image and the traces are the CPU's, bit for bit.

use super::*;
use raystep::explain::diff::compare;
use raystep::gpu::trace_log::DEFAULT_LOG_WORDS;
use raystep::record::{Tolerance, Trace};

/// 96 × 72 pixels: a floor, a light, and 96 placed copies of two prototypes — 80 gems (the
/// 20-triangle icosahedron) turned about all three axes and scaled unevenly, and 16 eggs (the
/// unit sphere scaled unevenly, textured with a mip-mapped image, so that a ray cone's level of
/// detail is taken on a stretched instance) — so the TLAS is several levels deep and rays enter
/// many instances.
fn many_instances() -> Scene {
    let mut t = String::from(
        r#"[camera]
from = [0, 7, -13]
at = [0, 0.5, 0]
fov = 50
width = 96
height = 72

[[light]]
position = [-6, 12, -8]
color = [1, 1, 1]

[[material]]
name = "floor"
color = [0.8, 0.8, 0.8]

[[material]]
name = "gem"
color = [0.9, 0.5, 0.2]
specular = 0.6
shininess = 40

[[texture]]
name = "checks"
image = "textures/checks-64x64.png"
filter = "trilinear"

[[material]]
name = "egg"
color = [0.3, 0.6, 0.9]
texture = "checks"

[[plane]]
name = "floor"
axis = "y"
offset = 0
material = "floor"

[[mesh]]
name = "gem"
obj = "icosahedron.obj"
material = "gem"
translate = [0, 0, 0]

[[sphere]]
name = "ball"
center = [0, 0, 0]
radius = 1
material = "egg"
"#,
    );
    for i in 0..10 {
        for j in 0..8 {
            let (x, z) = (-6.75 + 1.5 * i as f64, -4.0 + 1.5 * j as f64);
            let s = 0.35 + 0.04 * ((i * 7 + j * 3) % 5) as f64;
            t += &format!(
                "\n[[instance]]\nname = \"gem {i} {j}\"\nof = \"gem\"\nscale = [{s}, {}, {s}]\nrotate = [{}, {}, {}]\ntranslate = [{x}, {}, {z}]\n",
                s * 1.3,
                (i * 17) % 90,
                (j * 29) % 180,
                ((i + j) * 11) % 60,
                s * 1.3 + 0.05,
            );
        }
    }
    for k in 0..16 {
        let (x, z) = (-6.0 + 0.8 * k as f64, 6.5 - 0.3 * (k % 3) as f64);
        t += &format!(
            "\n[[instance]]\nname = \"egg {k}\"\nof = \"ball\"\nscale = [0.3, {}, 0.3]\nrotate = [0, 0, {}]\ntranslate = [{x}, 0.6, {z}]\n",
            0.45 + 0.02 * k as f64,
            7 * k
        );
    }
    load_str(
        &t,
        "many-instances.toml",
        Some(&scenes::root().join("scenes")),
    )
    .unwrap()
}

fn tlas_nodes(prepared: &PreparedScene) -> usize {
    match prepared.accel() {
        SceneAccel::TwoLevel(t) => t.tlas.nodes.len(),
        _ => 0,
    }
}

fn timeline(t: &Trace) -> Vec<&Step> {
    t.timeline().into_iter().map(|(_, s)| &s.step).collect()
}

/// Many instances: the compute path's image is the CPU's bit for bit, and so is the trace of
/// every pixel of a 4 × 3 grid (TLAS node visits, each instance entered, its BLAS nodes and
/// object-space tests, the hit carried back). Under ray queries (Mesa 25's lavapipe in CI) the
/// hardware's walk stands in for the TLAS and BLAS visits: the image is compared, and each
/// pixel's hit.
#[test]
fn many_instances_render_and_trace_as_on_the_cpu() {
    let _gpu = one_at_a_time();
    let test = "many_instances_render_and_trace_as_on_the_cpu";
    let Some(ctx) = context(test) else {
        return;
    };
    let scene = many_instances();
    assert_eq!((scene.instances.len(), scene.prototypes.len()), (96, 2));
    let prepared = prep(&scene);
    let nodes = tlas_nodes(&prepared);
    eprintln!(
        "TLAS: {nodes} nodes over {} instances",
        scene.instances.len()
    );
    assert!(nodes >= 15, "a TLAS of several levels: {nodes} nodes");
    let cpu = cpu_pixels(&scene);
    let mut gpu = GpuTracer::new(ctx, &prepared, ShaderVariant::Generated).unwrap();
    let frame = gpu.render(GpuPath::Compute).unwrap();
    let d = gpu::difference(frame.width, frame.height, &cpu, &frame.pixels).unwrap();
    let hardware = gpu.hardware_ray_queries();
    let exact = gpu.exact(GpuPath::Compute) && gpu.arithmetic().probe.subnormals_kept();
    eprintln!(
        "{} ({}): {}",
        scene.name,
        if hardware {
            "ray queries"
        } else {
            "WGSL TLAS/BLAS walk"
        },
        d.summary()
    );
    if exact {
        assert!(
            same_bits(&cpu, &frame.pixels),
            "exact arithmetic, yet the linear image differs: {}",
            d.summary()
        );
    } else {
        assert!(
            d.rmse < 1.0 / 255.0 && d.max_error <= MAX_ERROR,
            "{}",
            d.summary()
        );
    }
    // The instances hit: some pixels must show them.
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut on_instances = 0;
    let mut failures = vec![];
    for j in 1..=3 {
        for i in 1..=4 {
            let (x, y) = (w * i / 5, h * j / 4);
            let cpu = prepared.record(x, y, 0);
            let got = gpu.trace_pixel(x, y, 0, DEFAULT_LOG_WORDS).unwrap();
            assert!(!got.truncated, "({x}, {y}) ran out of log");
            Trace::from_json(&got.trace.to_json(), "gpu.json").unwrap();
            let hit = |t: &Trace| {
                t.root
                    .hit
                    .as_ref()
                    .map(|h| (h.object, h.instance, h.t.to_bits()))
            };
            on_instances += cpu.root.hit.as_ref().is_some_and(|h| h.instance.is_some()) as usize;
            // The app's GPU tab reads the debug pixel: its hit names the instance too.
            let pick = gpu.debug_pixel(x, y).unwrap();
            let placed = |t: &Trace| t.root.hit.as_ref().map(|h| (h.object, h.instance));
            if (pick.object, pick.instance)
                != placed(&cpu).map_or((None, None), |(o, i)| (Some(o), i))
            {
                failures.push(format!(
                    "({x}, {y}): the debug pixel hit {:?} in {:?}",
                    pick.object, pick.instance
                ));
            }
            if hardware || !exact {
                if hit(&cpu) != hit(&got.trace) {
                    failures.push(format!("({x}, {y}): another hit"));
                }
                continue;
            }
            let steps = timeline(&got.trace);
            if cpu.root.hit.as_ref().is_some_and(|h| h.instance.is_some()) {
                assert!(steps.iter().any(|s| matches!(s, Step::InstanceHit { .. })));
                assert!(steps.iter().any(|s| matches!(s, Step::Instance { .. })));
                assert!(
                    steps
                        .iter()
                        .any(|s| matches!(s, Step::Node(v) if v.instance.is_some()))
                );
            }
            assert!(steps.iter().any(|s| matches!(s, Step::TlasNode(_))));
            let cmp = compare(&cpu, &got.trace, Tolerance::EXACT);
            if !cmp.differences.is_empty() {
                failures.push(cmp.to_text(&cpu, &got.trace, ["cpu", "gpu"]));
            }
        }
    }
    assert!(
        on_instances >= 4,
        "{on_instances} of 12 pixels hit an instance"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The Cornell box with instances (a textured gem three times, a mirror ball and a mirror egg
/// from one sphere) under the path tracer: the GPU's linear image is the CPU's bit for bit on an
/// exact compute path (every bounce off an instance, every shadow ray through the TLAS), and the
/// trace of a pixel on the egg is the CPU's number for number.
#[test]
fn an_instanced_cornell_box_path_traces_as_on_the_cpu() {
    let _gpu = one_at_a_time();
    let test = "an_instanced_cornell_box_path_traces_as_on_the_cpu";
    let Some(ctx) = context(test) else {
        return;
    };
    let text = scenes::instanced_cornell("mirror");
    let mut scene = load_str(
        &text,
        "instanced-cornell.toml",
        Some(&scenes::root().join("scenes")),
    )
    .unwrap();
    scene.camera.width = 48;
    scene.camera.height = 48;
    scene.settings.spp = 2;
    let prepared = prep(&scene);
    let cpu = cpu_pixels(&scene);
    let mut gpu = GpuTracer::new(ctx, &prepared, ShaderVariant::Generated).unwrap();
    if !gpu.exact(GpuPath::Compute) {
        eprintln!("SKIPPED {test}: the compute path is not exact on this adapter");
        return;
    }
    let frame = gpu.render(GpuPath::Compute).unwrap();
    let d = gpu::difference(frame.width, frame.height, &cpu, &frame.pixels).unwrap();
    eprintln!("{}: {}", scene.name, d.summary());
    assert!(
        same_bits(&cpu, &frame.pixels),
        "the linear image differs: {}",
        d.summary()
    );
    if gpu.hardware_ray_queries() {
        return;
    }
    // A pixel whose camera ray ends on the egg (found by the CPU).
    let (x, y) = (0..48)
        .flat_map(|y| (0..48).map(move |x| (x, y)))
        .find(|&(x, y)| {
            let t = prepared.record(x, y, 0);
            t.root
                .hit
                .as_ref()
                .is_some_and(|h| h.name.starts_with("egg"))
        })
        .expect("the egg is in view");
    let cpu = prepared.record(x, y, 0);
    let got = gpu.trace_pixel(x, y, 0, DEFAULT_LOG_WORDS).unwrap();
    assert!(!got.truncated);
    let cmp = compare(&cpu, &got.trace, Tolerance::EXACT);
    assert!(
        cmp.differences.is_empty(),
        "({x}, {y}): {}",
        cmp.to_text(&cpu, &got.trace, ["cpu", "gpu"])
    );
    assert!(
        timeline(&got.trace)
            .iter()
            .any(|s| matches!(s, Step::InstanceHit { name, .. } if name == "egg"))
    );
}
