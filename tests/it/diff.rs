//! `raystep diff` and `raystep::explain::diff`: a trace equals itself through save and load; a
//! planted numeric change, a missing shadow ray and a different sphere method are found and
//! reported in words at the right step; bad input exits 2 with the file named.

use assert_cmd::Command;
use raystep::accel::SceneAccel;
use raystep::explain::diff::{DiffKind, compare};
use raystep::record::Tolerance;
use raystep::record::{Step, Trace};
use raystep::scene::{self, Scene};
use raystep::trace::Tracer;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn raystep() -> Command {
    Command::cargo_bin("raystep").expect("the raystep binary is built")
}

fn record(scene: &Scene, x: u32, y: u32) -> Trace {
    let (accel, _) = SceneAccel::build(scene);
    Tracer::new(scene, &accel).record(x, y, 0)
}

fn three_spheres() -> Trace {
    let scene = scene::load_file(Path::new("scenes/three-spheres.toml")).expect("scene loads");
    record(&scene, 160, 120)
}

const LIT: &str = r#"
[[light]]
name = "key"
position = [-10, 10, -10]
[[sphere]]
name = "ball"
"#;

const DARK: &str = r#"
[[sphere]]
name = "ball"
"#;

fn inline(text: &str, file: &str) -> Trace {
    record(
        &scene::load_str(text, file, None).expect("scene loads"),
        160,
        120,
    )
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write");
    p
}

/// Runs `raystep diff` with extra arguments; returns (exit code, stdout, stderr).
fn diff(expected: &Path, actual: &Path, extra: &[&str]) -> (i32, String, String) {
    let out = raystep()
        .arg("diff")
        .arg(expected)
        .arg(actual)
        .args(extra)
        .output()
        .expect("raystep runs");
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(!stderr.contains("panicked"), "panicked:\n{stderr}");
    (
        out.status.code().expect("an exit code"),
        String::from_utf8_lossy(&out.stdout).to_string(),
        stderr,
    )
}

/// The timeline index of the first step matching `pred`.
fn timeline_index(t: &Trace, pred: impl Fn(&Step) -> bool) -> usize {
    t.timeline()
        .iter()
        .position(|(_, s)| pred(&s.step))
        .expect("a matching step")
}

#[test]
fn a_trace_equals_its_round_trip() {
    let t = three_spheres();
    let back = Trace::from_json(&t.to_json(), "t.json").expect("round trip");
    let c = compare(&t, &back, Tolerance::EXACT);
    assert!(c.is_equal(), "{:?}", c.first());
    assert!(c.header.is_empty());
    assert!(c.numbers_compared > 100, "{}", c.numbers_compared);
    let text = c.to_text(&t, &back, ["a", "b"]);
    assert!(text.contains("the traces are equal"), "{text}");
}

#[test]
fn saved_and_printed_traces_are_equal() {
    let dir = tempfile::tempdir().unwrap();
    let saved = dir.path().join("saved.json");
    let out = raystep()
        .args([
            "trace",
            "scenes/mirror-glass.toml",
            "--pixel",
            "240,140",
            "--json",
        ])
        .arg("--save")
        .arg(&saved)
        .output()
        .unwrap();
    assert!(out.status.success());
    let printed = dir.path().join("printed.json");
    std::fs::write(&printed, &out.stdout).unwrap();
    let (code, stdout, _) = diff(&saved, &printed, &[]);
    assert_eq!(code, 0, "{stdout}");
    assert!(stdout.contains("the traces are equal"), "{stdout}");
    let (code, stdout, _) = diff(&saved, &printed, &["--json"]);
    assert_eq!(code, 0);
    let v: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["equal"], true);
    assert_eq!(v["first_divergence"], Value::Null);
}

/// The header carries what the issue asks for.
#[test]
fn traces_carry_their_header() {
    let t = three_spheres();
    assert_eq!(t.scene, "Three spheres");
    assert_eq!(t.scene_hash.len(), 64);
    assert_eq!((t.pixel, t.sample), ([160, 120], 0));
    assert_eq!(t.raystep, env!("CARGO_PKG_VERSION"));
    let v: Value = serde_json::from_str(&t.to_json()).unwrap();
    for key in [
        "version",
        "raystep",
        "scene",
        "scene_hash",
        "pixel",
        "sample",
        "settings",
    ] {
        assert!(v.get(key).is_some(), "no {key}");
    }
}

/// Changes the discriminant of the primary ray's test of sphere `name` by `delta`.
fn plant_discriminant(json: &str, name: &str, delta: f64) -> (String, f64) {
    let mut v: Value = serde_json::from_str(json).unwrap();
    let steps = v["root"]["steps"].as_array_mut().unwrap();
    let s = steps
        .iter_mut()
        .find(|s| s["type"] == "sphere" && s["name"] == name)
        .expect("the sphere's test");
    let old = s["test"]["discriminant"].as_f64().unwrap();
    s["test"]["discriminant"] = serde_json::json!(old + delta);
    (serde_json::to_string_pretty(&v).unwrap(), old)
}

#[test]
fn a_planted_discriminant_is_found_at_its_step() {
    let t = three_spheres();
    let k = timeline_index(
        &t,
        |s| matches!(s, Step::Sphere { name, .. } if name == "mirror"),
    );
    let dir = tempfile::tempdir().unwrap();
    let a = write(dir.path(), "a.json", &t.to_json());
    let (planted, old) = plant_discriminant(&t.to_json(), "mirror", 7e-6);
    let b = write(dir.path(), "b.json", &planted);

    let (code, stdout, _) = diff(&a, &b, &[]);
    assert_eq!(code, 1, "{stdout}");
    let want = format!(
        "first divergence: step {k} (primary ray, intersection): sphere \"mirror\": discriminant {old} vs "
    );
    assert!(stdout.contains(&want), "lacks {want:?}:\n{stdout}");
    assert!(stdout.contains("differs by 7e-6, tolerance 0"), "{stdout}");
    assert!(
        stdout.contains("1 difference (1 numeric) in 1 step"),
        "{stdout}"
    );

    // Within the tolerance (|Δ| = 7e-6 ≤ 1e-5 · max(|a|, |b|) ≈ 9e-5): equal.
    let (code, stdout, _) = diff(&a, &b, &["--tolerance", "1e-5"]);
    assert_eq!(code, 0, "{stdout}");
    assert!(stdout.contains("equal within tolerance 1e-5"), "{stdout}");
    assert!(stdout.contains("discriminant"), "{stdout}");
    // A tighter one catches it.
    let (code, stdout, _) = diff(&a, &b, &["--tolerance", "1e-7"]);
    assert_eq!(code, 1, "{stdout}");
    assert!(stdout.contains("tolerance 1e-7"), "{stdout}");

    let (code, stdout, _) = diff(&a, &b, &["--json"]);
    assert_eq!(code, 1);
    let v: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["equal"], false);
    let f = &v["first_divergence"];
    assert_eq!(f["kind"], "number");
    assert_eq!(f["step"], k);
    assert_eq!(f["actual_step"], k);
    assert_eq!(f["place"], "primary ray");
    assert_eq!(f["subject"], "sphere \"mirror\"");
    assert_eq!(f["field"], "discriminant");
    assert_eq!(f["expected"].as_f64(), Some(old));
    assert!((f["difference"].as_f64().unwrap() - 7e-6).abs() < 1e-7);
}

/// A changed t in a shadow ray's step names the path to the shadow ray and its timeline index.
#[test]
fn a_planted_t_in_a_shadow_ray_names_the_ray_path() {
    let t = three_spheres();
    let k = timeline_index(&t, |s| matches!(s, Step::Plane { .. }));
    let mut v: Value = serde_json::from_str(&t.to_json()).unwrap();
    // The shadow ray's plane test (the first plane test below the root).
    let shadow = &mut v["root"]["children"][0];
    assert_eq!(shadow["kind"], "shadow");
    let plane = shadow["steps"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|s| s["type"] == "plane")
        .unwrap();
    plane["test"]["t_raw"] = serde_json::json!(-0.25);
    let changed = Trace::from_json(&v.to_string(), "changed.json").unwrap();
    let shadow_k = changed
        .timeline()
        .iter()
        .enumerate()
        .filter(|(_, (r, s))| {
            r.kind == raystep::record::RayKind::Shadow && matches!(s.step, Step::Plane { .. })
        })
        .map(|(i, _)| i)
        .next()
        .unwrap();
    assert!(shadow_k > k);
    let c = compare(&t, &changed, Tolerance::EXACT);
    let f = c.first().expect("a difference");
    assert_eq!(f.kind, DiffKind::Number);
    assert_eq!(f.step, Some(shadow_k));
    assert!(
        f.message.starts_with(&format!(
            "step {shadow_k} (primary ray → shadow ray 0, intersection): plane \"floor\": t_raw "
        )),
        "{}",
        f.message
    );
    assert!(f.message.contains("vs -0.25"), "{}", f.message);
}

#[test]
fn a_scene_without_its_light_lacks_the_shadow_ray() {
    let lit = inline(LIT, "lit.toml");
    let dark = inline(DARK, "dark.toml");
    let c = compare(&lit, &dark, Tolerance::EXACT);
    // The scene text differs: said up front.
    assert!(
        c.header
            .iter()
            .any(|d| d.field.as_deref() == Some("scene_hash"))
    );
    let f = c.first().expect("they differ");
    assert_eq!(f.kind, DiffKind::Missing);
    assert_eq!(f.place, "primary ray");
    let k = timeline_index(&lit, |s| matches!(s, Step::ShadowRay { .. }));
    assert_eq!(f.step, Some(k));
    assert!(
        f.message.contains(
            "the expected trace has a shadow ray towards light \"key\" here (and 2 more steps"
        ) && f.message.ends_with("; the actual trace has none"),
        "{}",
        f.message
    );
    // The other way round it is an extra shadow ray.
    let c = compare(&dark, &lit, Tolerance::EXACT);
    let f = c.first().unwrap();
    assert_eq!(f.kind, DiffKind::Extra);
    assert!(
        f.message
            .contains("the actual trace has a shadow ray towards light \"key\" here"),
        "{}",
        f.message
    );
}

#[test]
fn a_deleted_shadow_ray_is_reported_missing() {
    let lit = inline(LIT, "lit.toml");
    let mut v: Value = serde_json::from_str(&lit.to_json()).unwrap();
    let root = &mut v["root"];
    let spawn = root["steps"]
        .as_array()
        .unwrap()
        .iter()
        .position(|s| s["type"] == "spawn")
        .expect("a spawn step");
    root["steps"].as_array_mut().unwrap().remove(spawn);
    root["children"] = serde_json::json!([]);
    let dir = tempfile::tempdir().unwrap();
    let a = write(dir.path(), "lit.json", &lit.to_json());
    let b = write(dir.path(), "cut.json", &v.to_string());
    let (code, stdout, _) = diff(&a, &b, &[]);
    assert_eq!(code, 1, "{stdout}");
    let k = timeline_index(&lit, |s| matches!(s, Step::Spawn { .. }));
    let want = format!(
        "first divergence: step {k} (primary ray, closest-hit): the expected trace has a shadow ray towards light \"key\" (traced) here; the actual trace has none"
    );
    assert!(stdout.contains(&want), "lacks {want:?}:\n{stdout}");
    // The rest (the light step, the colour) is still compared and equal.
    assert!(stdout.contains("1 difference (0 numeric)"), "{stdout}");
}

#[test]
fn two_sphere_methods_differ_in_header_and_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let save = |method: &str| {
        let p = dir.path().join(format!("{method}.json"));
        raystep()
            .args(["trace", "scenes/three-spheres.toml", "--pixel", "160,120"])
            .args(["--sphere-method", method, "--save"])
            .arg(&p)
            .assert()
            .success();
        p
    };
    let (stable, textbook) = (save("stable"), save("textbook"));
    let (code, stdout, _) = diff(&stable, &textbook, &[]);
    assert_eq!(code, 1, "{stdout}");
    assert!(
        stdout.contains("the headers differ")
            && stdout.contains("settings.sphere_method \"stable\" vs \"textbook\""),
        "{stdout}"
    );
    // The first divergence is the method recorded in the first sphere test; the first number
    // that differs is that test's discriminant (a, b and c do not depend on the method).
    assert!(
        stdout.contains(
            "first divergence: step 3 (primary ray, intersection): sphere \"middle\": method \"stable\" vs \"textbook\""
        ),
        "{stdout}"
    );
    assert!(
        stdout.contains(
            "first numeric divergence: step 3 (primary ray, intersection): sphere \"middle\": discriminant "
        ),
        "{stdout}"
    );
    let (code, stdout, _) = diff(&stable, &textbook, &["--json"]);
    assert_eq!(code, 1);
    let v: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(
        v["header_differences"][0]["field"],
        "settings.sphere_method"
    );
    assert_eq!(v["first_numeric_divergence"]["field"], "discriminant");
}

#[test]
fn bad_input_exits_2_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let good = write(dir.path(), "good.json", &three_spheres().to_json());
    let missing = dir.path().join("missing.json");
    let (code, _, stderr) = diff(&good, &missing, &[]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("missing.json") && stderr.contains("cannot read"),
        "{stderr}"
    );

    let corrupt = write(
        dir.path(),
        "corrupt.json",
        "{\n  \"version\": 1,\n  \"raystep\": oops\n}",
    );
    let (code, _, stderr) = diff(&corrupt, &good, &[]);
    assert_eq!(code, 2);
    assert!(stderr.contains("corrupt.json:3:"), "{stderr}");

    let future = write(dir.path(), "future.json", r#"{"version": 99}"#);
    let (code, _, stderr) = diff(&good, &future, &[]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("future.json") && stderr.contains("version 99"),
        "{stderr}"
    );

    let partial = write(
        dir.path(),
        "partial.json",
        r#"{"version": 1, "raystep": "0.1.0"}"#,
    );
    let (code, _, stderr) = diff(&partial, &good, &[]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("partial.json:1:") && stderr.contains("missing field"),
        "{stderr}"
    );

    let not_a_trace = write(dir.path(), "list.json", "[1, 2, 3]");
    let (code, _, stderr) = diff(&not_a_trace, &good, &[]);
    assert_eq!(code, 2);
    assert!(stderr.contains("list.json"), "{stderr}");

    let (code, _, stderr) = diff(&good, &good, &["--tolerance=-1"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("tolerance"), "{stderr}");
}
