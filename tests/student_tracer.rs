//! Python tracers graded by `raystep grade-tracer`: the starter kit (`lessons/starter/tracer.py`,
//! camera rays only) gets full marks on the camera stage of every shipped scene and is told what
//! to do next; the model student (`tests/student_tracer/tracer.py`, an independent Python
//! implementation of the lessons' formulas) gets full marks on every stage of every shipped
//! scene; the same tracer with a planted bug loses marks at the right ray and quantity, with the
//! mistake named. Needs `python3` (3.11 or newer), which `.ci/run` installs.

use assert_cmd::Command;
use serde_json::Value;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn shipped() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("scenes"))
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

/// Grades `run` on `scene` at `pixels` up to `upto`; the Gradescope JSON.
fn grade(scene: &PathBuf, pixels: &str, upto: &str, run: &str) -> Value {
    let out = Command::cargo_bin("raystep")
        .unwrap()
        .current_dir(root())
        .args([
            "grade-tracer",
            "--scene",
            &scene.display().to_string(),
            "--pixels",
            pixels,
            "--upto",
            upto,
            "--json",
            "--timeout",
            "60",
            "--run",
            run,
        ])
        .assert()
        .success()
        .get_output()
        .clone();
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Each scene's image size, for pixels at its corners and inside.
fn pixels(scene: &PathBuf) -> String {
    let s = raystep::scene::load_file(scene).unwrap();
    let (w, h) = (s.camera.width, s.camera.height);
    [
        (0, 0),
        (w - 1, h - 1),
        (w / 2, h / 2),
        (w / 4, 3 * h / 4),
        (3 * w / 4, h / 3),
    ]
    .iter()
    .map(|(x, y)| format!("{x},{y}"))
    .collect::<Vec<_>>()
    .join(";")
}

fn failures(v: &Value) -> Vec<String> {
    v["tests"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|t| t["score"] != t["max_score"])
        .map(|t| format!("{}: {}", t["name"], t["output"]))
        .collect()
}

#[test]
fn the_starter_kit_passes_the_camera_stage_everywhere() {
    let run = "python3 lessons/starter/tracer.py {scene} {x} {y}";
    for scene in shipped() {
        let v = grade(&scene, &pixels(&scene), "camera", run);
        assert_eq!(failures(&v), Vec::<String>::new(), "{}", scene.display());
        assert_eq!(v["score"], 5.0);
    }
    // The next stage tells the student what is missing.
    let v = grade(
        &root().join("scenes/first-sphere.toml"),
        "160,120",
        "sphere",
        run,
    );
    let f = failures(&v);
    assert_eq!(f.len(), 1, "{f:?}");
    assert!(
        f[0].contains("you printed no test of \\\"ball\\\", the object this ray hits"),
        "{f:?}"
    );
}
