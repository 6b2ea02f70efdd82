//! A trace file is input from outside: a field out of range (a plane axis of 7, a BVH whose
//! children form a cycle, an index that points nowhere, a child spawned twice) is an error naming
//! the file and the field, and `diff` / `diagram` exit 2 / 1 on it instead of panicking or
//! hanging. And the tracer's own bounds: a trace stops at its step limit and says where, rays
//! whose share of the pixel is below 1/512 are not spawned and the trace says so, and a depth-64
//! mirror-and-glass pixel finishes with the render's colour.

use assert_cmd::Command;
use raystep::accel::SceneAccel;
use raystep::record::observer::MAX_TRACE_STEPS;
use raystep::record::{RayKind, Recorder, Silent, Step, Trace, TraceError};
use raystep::scene::{self, Scene};
use raystep::trace::Tracer;
use raystep::trace::tracer::WEIGHT_CUTOFF;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::time::Duration;

fn raystep() -> Command {
    let mut c = Command::cargo_bin("raystep").expect("the raystep binary is built");
    // A hang is a failure, not a stuck test run.
    c.timeout(Duration::from_secs(120));
    c
}

fn load(name: &str) -> Scene {
    scene::load_file(Path::new("scenes").join(name).as_path()).expect("scene loads")
}

fn record(scene: &Scene, x: u32, y: u32) -> Trace {
    let (accel, _) = SceneAccel::build(scene);
    Tracer::new(scene, &accel).record(x, y, 0)
}

fn json(t: &Trace) -> Value {
    serde_json::from_str(&t.to_json()).expect("a trace is JSON")
}

fn read(v: &Value) -> Result<Trace, TraceError> {
    Trace::from_json(&serde_json::to_string_pretty(v).unwrap(), "planted.json")
}

/// The error's text, which must name the file and the field.
fn invalid(v: &Value, field: &str) -> String {
    let e = read(v).expect_err("the planted trace is rejected");
    let text = e.to_string();
    assert!(
        matches!(e, TraceError::Invalid { .. }),
        "an Invalid error, got {text}"
    );
    assert!(
        text.starts_with("planted.json: field `") && text.contains(field),
        "names the file and `{field}`: {text}"
    );
    text
}

/// The JSON paths of every step, depth first, with the step.
fn steps_mut<'a>(ray: &'a mut Value, path: String, out: &mut Vec<(String, &'a mut Value)>) {
    let Value::Object(m) = ray else { return };
    let (steps, children) = {
        let mut steps = None;
        let mut children = None;
        for (k, v) in m.iter_mut() {
            match k.as_str() {
                "steps" => steps = Some(v),
                "children" => children = Some(v),
                _ => {}
            }
        }
        (steps, children)
    };
    if let Some(Value::Array(s)) = steps {
        for (i, st) in s.iter_mut().enumerate() {
            out.push((format!("{path}.steps[{i}]"), st));
        }
    }
    if let Some(Value::Array(c)) = children {
        for (i, ch) in c.iter_mut().enumerate() {
            steps_mut(ch, format!("{path}.children[{i}]"), out);
        }
    }
}

fn write(dir: &Path, name: &str, v: &Value) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string_pretty(v).unwrap()).unwrap();
    p
}

#[test]
fn a_plane_axis_out_of_range_is_an_error_and_diff_does_not_panic() {
    let t = record(&load("three-spheres.toml"), 160, 120);
    let mut v = json(&t);
    let mut steps = vec![];
    steps_mut(&mut v["root"], "root".into(), &mut steps);
    let (path, step) = steps
        .into_iter()
        .find(|(_, s)| s["type"] == "plane" && s["test"]["form"]["form"] == "axis")
        .expect("three-spheres' primary ray tests an axis-aligned plane");
    step["test"]["form"]["axis"] = 7.into();
    let text = invalid(&v, &format!("{path}.test.form.axis"));
    assert!(text.contains("got 7"), "{text}");

    // The command line: exit 2 with the message, for both orders of the files.
    let dir = tempfile::tempdir().unwrap();
    let good = write(dir.path(), "good.json", &json(&t));
    let bad = write(dir.path(), "bad.json", &v);
    for (a, b) in [(&good, &bad), (&bad, &good)] {
        let out = raystep().arg("diff").arg(a).arg(b).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(
            err.contains("bad.json: field `") && err.contains("test.form.axis"),
            "{err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    // An object's axis-aligned plane as well.
    let mut v = json(&t);
    let objects = v["objects"].as_array_mut().unwrap();
    let k = objects
        .iter()
        .position(|o| o["shape"]["kind"] == "axis-plane")
        .expect("an axis-aligned plane among the objects");
    objects[k]["shape"]["axis"] = 3.into();
    invalid(&v, &format!("objects[{k}].shape.axis"));
}

#[test]
fn a_bvh_whose_children_form_a_cycle_is_rejected_and_diagram_finishes() {
    let t = record(&load("triangles.toml"), 160, 120);
    let mut v = json(&t);
    let outline = v["bvh"]
        .as_array_mut()
        .expect("triangles is traced with a BVH");
    // Node 0's first child points back at the root's other child's parent: root → a → root.
    let a = outline[0]["children"][0].as_u64().unwrap();
    let ka = outline
        .iter()
        .position(|n| n["node"].as_u64() == Some(a))
        .unwrap();
    let c = outline[ka]["children"].clone();
    assert!(c.is_array(), "the root's child is an inner node");
    outline[ka]["children"][1] = 0.into();
    let text = invalid(&v, "");
    assert!(text.contains("node "), "{text}");

    // A cycle below the root: a's child b lists a as its child.
    let mut v = json(&t);
    let outline = v["bvh"].as_array_mut().unwrap();
    let b = c[0].as_u64().unwrap();
    let kb = outline
        .iter()
        .position(|n| n["node"].as_u64() == Some(b))
        .unwrap();
    outline[kb]["children"] = serde_json::json!([a, b + 1000]);
    invalid(&v, "");

    let dir = tempfile::tempdir().unwrap();
    let bad = write(dir.path(), "cycle.json", &v);
    let png = dir.path().join("bvh.png");
    let out = raystep()
        .args(["diagram", "--kind", "bvh", "-o"])
        .arg(&png)
        .arg(&bad)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(err.contains("cycle.json: field `"), "{err}");
    assert!(!png.exists(), "no diagram written");
}

#[test]
fn indices_that_point_nowhere_are_errors_naming_the_field() {
    let t = record(&load("three-spheres.toml"), 160, 120);
    // A light index beyond the lights.
    let mut v = json(&t);
    let mut steps = vec![];
    steps_mut(&mut v["root"], "root".into(), &mut steps);
    let (path, step) = steps
        .into_iter()
        .find(|(_, s)| s["type"] == "light")
        .expect("a lit surface");
    step["light"] = 9.into();
    let text = invalid(&v, &format!("{path}.light"));
    assert!(text.contains("light 9 does not exist"), "{text}");

    // An object id the trace does not carry.
    let mut v = json(&t);
    let mut steps = vec![];
    steps_mut(&mut v["root"], "root".into(), &mut steps);
    let (path, step) = steps
        .into_iter()
        .find(|(_, s)| s["type"] == "sphere")
        .unwrap();
    step["object"] = 4000.into();
    invalid(&v, &format!("{path}.object"));

    // A child spawned twice (the timeline would walk it twice: exponential on a deep tree).
    let mut v = json(&t);
    let root_steps = v["root"]["steps"].as_array_mut().unwrap();
    let k = root_steps
        .iter()
        .position(|s| s["type"] == "spawn")
        .expect("the primary ray spawns a child");
    let spawn = root_steps[k].clone();
    root_steps.insert(k, spawn);
    invalid(&v, &format!("root.steps[{}].child", k + 1));

    // A pixel outside the image, a sample beyond spp.
    let mut v = json(&t);
    v["pixel"] = serde_json::json!([5000, 1]);
    invalid(&v, "pixel");
    let mut v = json(&t);
    v["sample"] = 3.into();
    invalid(&v, "sample");
}

#[test]
fn every_recorded_trace_of_a_shipped_scene_reads_back() {
    for name in [
        "three-spheres.toml",
        "triangles.toml",
        "mirror-glass.toml",
        "cornell.toml",
    ] {
        let s = load(name);
        for (x, y) in [
            (160, 120),
            (10, 10),
            (s.camera.width - 1, s.camera.height - 1),
        ] {
            let t = record(&s, x, y);
            let back = Trace::from_json(&t.to_json(), name).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(back, t, "{name} ({x}, {y})");
        }
    }
}

#[test]
fn a_trace_stops_at_its_step_limit_and_says_where_with_exact_colours() {
    let scene = load("mirror-glass.toml");
    let (accel, _) = SceneAccel::build(&scene);
    let tracer = Tracer::new(&scene, &accel);
    // The pixel of a coarse grid with the most steps (one through the glass ball).
    let (x, y) = (0..300)
        .step_by(20)
        .flat_map(|y| (0..400).step_by(20).map(move |x| (x, y)))
        .max_by_key(|&(x, y)| tracer.record(x, y, 0).timeline().len())
        .unwrap();
    let full = tracer.record(x, y, 0);
    let all = full.timeline().len();
    assert!(all > 60, "the glass pixel takes {all} steps");
    let mut rec = Recorder::with_limit(40);
    let color = tracer.trace_sample(x, y, 0, &mut rec);
    let root = rec.finish().expect("the primary ray ends");
    let mut cut = full.clone();
    cut.root = root;
    let tl = cut.timeline();
    // 40 steps kept, then the cut.
    assert_eq!(tl.len(), 41);
    assert_eq!(cut.truncated_at(), Some(40));
    assert!(matches!(tl[40].1.step, Step::Truncated { max_steps: 40 }));
    // The colours are the untruncated ones, bit for bit.
    assert_eq!(color.to_array(), full.color);
    assert_eq!(cut.root.color, full.root.color);
    // It reads back.
    Trace::from_json(&cut.to_json(), "cut.json").expect("a cut trace reads back");
    // The full trace is not cut.
    assert_eq!(full.truncated_at(), None);
}

/// Two facing mirrors of reflectivity ½ with the camera between them: the n-th reflection
/// carries 2⁻ⁿ of the pixel, so reflections 1 … 9 are traced (2⁻⁹ = 1/512 is not below the
/// cut-off) and the 10th (1/1024) is not, however deep the recursion may go.
#[test]
fn rays_below_the_weight_cut_off_are_not_spawned_and_the_trace_says_so() {
    let text = r#"
[camera]
from = [0, 0, -1]
at = [0, 0, 1]
fov = 10
width = 3
height = 3
[render]
max_depth = 64
[[material]]
name = "half-mirror"
reflective = 0.5
[[plane]]
name = "front"
point = [0, 0, 2]
normal = [0, 0, -1]
material = "half-mirror"
[[plane]]
name = "back"
point = [0, 0, -2]
normal = [0, 0, 1]
material = "half-mirror"
"#;
    let scene = scene::load_str(text, "mirrors.toml", None).expect("scene loads");
    let t = record(&scene, 1, 1);
    let rays = t.rays();
    let deepest = rays.iter().map(|r| r.depth).max().unwrap();
    assert_eq!(deepest, 9, "reflections 1 … 9 are traced");
    assert!(rays[1..].iter().all(|r| r.kind == RayKind::Reflection));
    let cuts: Vec<_> = t
        .timeline()
        .into_iter()
        .filter_map(|(r, s)| match s.step {
            Step::WeightCutoff {
                kind,
                contribution,
                cutoff,
            } => Some((r.depth, kind, contribution, cutoff)),
            _ => None,
        })
        .collect();
    assert_eq!(
        cuts,
        vec![(9, RayKind::Reflection, 1.0 / 1024.0, 1.0 / 512.0)]
    );
    assert_eq!(WEIGHT_CUTOFF, 1.0 / 512.0);
    // The render runs the same code: the same colour, bit for bit.
    let (accel, _) = SceneAccel::build(&scene);
    let c = Tracer::new(&scene, &accel).trace_sample(1, 1, 0, &mut Silent);
    assert_eq!(c.to_array(), t.color);
}

/// Depth 64 on the mirror-and-glass scene: before the cut-off a trace of a glass pixel at depth
/// 24 outgrew 8 GB. Now every pixel of a coarse grid records within the step limit, with the
/// render's colour.
#[test]
fn depth_64_mirror_glass_pixels_finish_within_the_step_limit() {
    let mut scene = load("mirror-glass.toml");
    scene.settings.max_depth = 64;
    let (accel, _) = SceneAccel::build(&scene);
    let tracer = Tracer::new(&scene, &accel);
    let mut cut_off = 0;
    for y in (0..300).step_by(50) {
        for x in (0..400).step_by(50) {
            let t = tracer.record(x, y, 0);
            assert!(t.timeline().len() <= MAX_TRACE_STEPS + 1);
            let c = tracer.trace_sample(x, y, 0, &mut Silent);
            assert_eq!(c.to_array(), t.color, "({x}, {y})");
            cut_off += t
                .timeline()
                .iter()
                .filter(|(_, s)| matches!(s.step, Step::WeightCutoff { .. }))
                .count();
        }
    }
    assert!(cut_off > 0, "the glass pixels meet the cut-off");
}

/// Found by the trace fuzzer on a seed: the quadratic diagram of a first-sphere pixel at a small
/// size (the command line accepts 64 × 64) panicked in `clamp` (the plot frame's left lay right
/// of its right).
#[test]
fn the_quadratic_diagram_of_a_small_canvas_does_not_panic() {
    use raystep::diagram::{self, DiagramKind, ViewOptions};
    let mut scene = load("first-sphere.toml");
    scene.settings.max_depth = 3;
    let t = record(&scene, 100, 150);
    for (width, height) in [(96, 72), (64, 64)] {
        let opts = ViewOptions {
            width,
            height,
            ..ViewOptions::default()
        };
        let c = diagram::draw(&t, DiagramKind::Quadratic, &opts).expect("a sphere test to plot");
        assert_eq!(c.to_rgba_image().dimensions(), (width, height));
    }
}
