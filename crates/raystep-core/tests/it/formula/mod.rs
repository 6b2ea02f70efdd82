//! The math panel (`raystep_core::explain::formula`): every step of real recorded traces is explained,
//! the printed numbers are the recorded ones, the substituted formulas use the very numbers their
//! values came from, and hand-computed cases come out as computed by hand.

use raystep_core::accel::SceneAccel;
use raystep_core::explain::formula::{Explanation, Formula, explain};
use raystep_core::record::number::num;
use raystep_core::record::{NodeAction, RayRecord, Step, Trace};
use raystep_core::scene::{AccelChoice, Scene, Shape, load_file, load_str};
use raystep_core::shapes::{SphereMethod, TriangleMethod};
use raystep_core::trace::Tracer;
use std::path::Path;

const SHIPPED: [&str; 8] = [
    "first-sphere.toml",
    "three-spheres.toml",
    "triangles.toml",
    "smooth-shading.toml",
    "textures.toml",
    "mirror-glass.toml",
    "cornell.toml",
    "instances.toml",
];

fn shipped(name: &str) -> Scene {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("scenes")
        .join(name);
    load_file(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn record(scene: &Scene, x: u32, y: u32) -> Trace {
    let (accel, _) = SceneAccel::build(scene);
    Tracer::new(scene, &accel).record(x, y, 0)
}

/// Pixels on a coarse grid (every `step` pixels, centred in the cells) plus the centre pixel.
fn grid(scene: &Scene, step: u32) -> Vec<(u32, u32)> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut out = vec![(w / 2, h / 2)];
    for y in (step / 2..h).step_by(step as usize) {
        for x in (step / 2..w).step_by(step as usize) {
            out.push((x, y));
        }
    }
    out
}

/// Every (ray, step) of a trace with its explanation.
fn explained(trace: &Trace) -> Vec<(&RayRecord, &Step, Explanation)> {
    trace
        .timeline()
        .into_iter()
        .map(|(r, s)| (r, &s.step, explain(trace, r, &s.step)))
        .collect()
}

fn get<'a>(e: &'a Explanation, name: &str) -> &'a Formula {
    e.lines
        .iter()
        .find(|l| l.name == name)
        .unwrap_or_else(|| panic!("no line {name:?} in {e:#?}"))
}

fn has(e: &Explanation, name: &str) -> bool {
    e.lines.iter().any(|l| l.name == name)
}

/// Parses a number as `describe::num` prints it (shortest round trip, so exact).
fn parse(s: &str) -> f32 {
    match s.trim() {
        "∞" => f32::INFINITY,
        "-∞" => f32::NEG_INFINITY,
        t => t
            .trim_start_matches('(')
            .trim_end_matches(')')
            .parse()
            .unwrap_or_else(|e| panic!("{t:?}: {e}")),
    }
}

/// The ASCII numbers in a substituted formula, in order (`-` only as a sign or in an exponent;
/// the operators use `−`).
fn numbers(s: &str) -> Vec<f32> {
    let mut out = vec![];
    let mut cur = String::new();
    let flush = |cur: &mut String, out: &mut Vec<f32>| {
        if cur.chars().any(|c| c.is_ascii_digit()) {
            out.push(
                cur.parse()
                    .unwrap_or_else(|e| panic!("{cur:?} in {s:?}: {e}")),
            );
        }
        cur.clear();
    };
    for c in s.chars() {
        // Scientific notation too (`7.1525574e-7`): `e` after a digit, `-` after that `e`.
        let exponent = c == 'e' && cur.ends_with(|d: char| d.is_ascii_digit());
        let exponent_sign = c == '-' && cur.ends_with('e');
        if c.is_ascii_digit()
            || c == '.'
            || (c == '-' && cur.is_empty())
            || exponent
            || exponent_sign
        {
            cur.push(c);
        } else {
            flush(&mut cur, &mut out);
        }
    }
    flush(&mut cur, &mut out);
    out
}

/// The arguments of `max(…)` / `min(…)` as printed.
fn args(s: &str) -> Vec<f32> {
    let inner = &s[s.find('(').unwrap() + 1..s.rfind(')').unwrap()];
    inner.split(", ").map(parse).collect()
}

fn same(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// f64 dot product.
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn f64x3(v: [f32; 3]) -> [f64; 3] {
    v.map(f64::from)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The unit sphere at the origin seen from (0, 0, −5) through the middle pixel of a 3×3 image:
/// the primary ray is exactly S = (0, 0, −5), Q = (0, 0, 1).
fn axis_scene(method: &str) -> Scene {
    let text = format!(
        r#"
[camera]
from = [0, 0, -5]
at = [0, 0, 0]
width = 3
height = 3

[render]
sphere_method = "{method}"

[[light]]
position = [-10, 10, -10]

[[sphere]]
name = "ball"
"#
    );
    load_str(&text, "axis.toml", None).unwrap()
}

/// The scene of RTC ch. 15's triangle P0 (0, 1, 0), P1 (−1, 0, 0), P2 (1, 0, 0), seen along +z
/// through the middle pixel of a 3×3 image from `from`.
fn triangle_scene(from: [f32; 3], method: &str) -> Scene {
    let text = format!(
        r#"
[camera]
from = [{}, {}, {}]
at = [{}, {}, {}]
width = 3
height = 3

[render]
triangle_method = "{method}"

[[light]]
position = [-10, 10, -10]

[[triangle]]
name = "rtc"
vertices = [[0, 1, 0], [-1, 0, 0], [1, 0, 0]]
"#,
        from[0],
        from[1],
        from[2],
        from[0],
        from[1],
        from[2] + 2.0
    );
    load_str(&text, "tri.toml", None).unwrap()
}

fn triangle_step(trace: &Trace) -> (&Step, Explanation) {
    let step = trace
        .root
        .steps
        .iter()
        .map(|s| &s.step)
        .find(|s| matches!(s, Step::Triangle { .. }))
        .expect("a triangle test");
    (step, explain(trace, &trace.root, step))
}

fn variant(s: &Step) -> &'static str {
    match s {
        Step::Camera { .. } => "camera",
        Step::Node(n) if n.instance.is_some() => "blas-node",
        Step::Node(_) => "node",
        Step::TlasNode(_) => "tlas-node",
        Step::Instance { .. } => "instance",
        Step::InstanceHit { .. } => "instance-hit",
        Step::SphereNode { .. } => "sphere-node",
        Step::Cell { .. } => "cell",
        Step::MailboxSkip { .. } => "mailbox-skip",
        Step::Sphere { .. } => "sphere",
        Step::Plane { .. } => "plane",
        Step::Triangle { .. } => "triangle",
        Step::Accept { .. } => "accept",
        Step::Miss { .. } => "miss",
        Step::Surface { .. } => "surface",
        Step::ShadingNormal { .. } => "shading-normal",
        Step::Texture { .. } => "texture",
        Step::ShadowRay { .. } => "shadow-ray",
        Step::Light { .. } => "light",
        Step::Reflect { .. } => "reflect",
        Step::Refract { .. } => "refract",
        Step::Schlick { .. } => "schlick",
        Step::DepthLimit { .. } => "depth-limit",
        Step::WeightCutoff { .. } => "weight-cutoff",
        Step::Truncated { .. } => "truncated",
        Step::HardwareTraversal { .. } => "hardware-traversal",
        Step::Spawn { .. } => "spawn",
        Step::Color { .. } => "color",
        Step::Lens { .. } => "lens",
        Step::LightSample { .. } => "light-sample",
        Step::BsdfSample { .. } => "bsdf-sample",
        Step::Emitted { .. } => "emitted",
        Step::RussianRoulette { .. } => "russian-roulette",
    }
}

fn check_all_steps(trace: &Trace, seen: &mut std::collections::BTreeSet<&'static str>) {
    for (_, step, e) in explained(trace) {
        seen.insert(variant(step));
        assert!(!e.title.trim().is_empty(), "{step:?}");
        assert!(!e.conclusion.trim().is_empty(), "{step:?}");
        if !format!("{step:?}").contains("NaN") {
            let text = format!("{e:?}");
            assert!(!text.contains("NaN"), "{step:?}\n{e:#?}");
        }
        for l in &e.lines {
            assert!(!l.name.is_empty() && !l.symbolic.is_empty(), "{e:#?}");
        }
    }
}

/// Removes the keys `keys` from every object in `v`; returns how many were removed.
fn strip(v: &mut serde_json::Value, keys: &[&str]) -> usize {
    match v {
        serde_json::Value::Object(m) => {
            let here = keys.iter().filter(|k| m.remove(**k).is_some()).count();
            here + m.values_mut().map(|x| strip(x, keys)).sum::<usize>()
        }
        serde_json::Value::Array(a) => a.iter_mut().map(|x| strip(x, keys)).sum(),
        _ => 0,
    }
}

/// The teapot's pixel (160, 150) under the BVH: its primary and shadow rays both leave nodes for
/// later.
fn teapot_under_the_bvh() -> Trace {
    let mut scene = shipped("teapot-stadium.toml");
    scene.settings.accel = AccelChoice::Bvh;
    record(&scene, 160, 150)
}

mod bvh;
mod coverage;
mod older_traces;
mod shading;
mod sphere;
mod triangle;
