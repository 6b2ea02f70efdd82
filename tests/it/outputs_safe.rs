//! No output over an input, and no output over another output: `grade -o` onto the class's
//! answers, `trace --save` onto the scene, `render -o` and `--heatmap` onto one file are refused
//! before anything is written, by any name (a link, `..`); a trace raystep writes at the deepest
//! `max_depth` it accepts loads again; a CSV with old Mac line endings is graded and a UTF-16 one
//! refused with that reason; a failing `converge` leaves no folder behind.

use assert_cmd::Command;
use std::path::Path;

use crate::common::scenes;
use scenes::root;

fn raystep() -> Command {
    Command::cargo_bin("raystep").unwrap()
}

/// Runs raystep in `dir` and returns its stderr, asserting it failed.
fn fails(dir: &Path, args: &[&str]) -> String {
    let out = raystep()
        .current_dir(dir)
        .args(args)
        .assert()
        .failure()
        .get_output()
        .clone();
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn an_output_over_an_input_or_another_output_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let answers = "student,disc\ns1001,1\n";
    std::fs::write(d.join("answers.csv"), answers).unwrap();
    std::fs::create_dir(d.join("sub")).unwrap();
    std::os::unix::fs::symlink(d.join("answers.csv"), d.join("link.csv")).unwrap();
    for out in ["answers.csv", "sub/../answers.csv", "link.csv"] {
        let err = fails(d, &["grade", "02-sphere", "answers.csv", "-o", out]);
        assert!(
            err.contains(&format!(
                "-o {out} is the class's answers the command reads"
            )),
            "{out}: {err}"
        );
        assert_eq!(
            std::fs::read_to_string(d.join("answers.csv")).unwrap(),
            answers
        );
    }
    let scene_text = std::fs::read_to_string(root().join("scenes/first-sphere.toml")).unwrap();
    std::fs::write(d.join("s.toml"), &scene_text).unwrap();
    let err = fails(
        d,
        &["trace", "s.toml", "--pixel", "1,1", "--save", "s.toml"],
    );
    assert!(err.contains("--save s.toml is the scene"), "{err}");
    assert_eq!(
        std::fs::read_to_string(d.join("s.toml")).unwrap(),
        scene_text
    );
    let err = fails(
        d,
        &["render", "s.toml", "-o", "x.png", "--heatmap", "./x.png"],
    );
    assert!(
        err.contains("--heatmap ./x.png and -o x.png are the same file"),
        "{err}"
    );
    assert!(!d.join("x.png").exists());
    let err = fails(d, &["render", "s.toml", "-o", "s.toml"]);
    assert!(err.contains("-o s.toml is the scene"), "{err}");
    assert_eq!(
        std::fs::read_to_string(d.join("s.toml")).unwrap(),
        scene_text
    );
    // `diagram` and `compare` likewise (a scene file may have any extension).
    std::fs::write(d.join("s.png"), &scene_text).unwrap();
    let err = fails(d, &["diagram", "s.png", "--pixel", "1,1", "-o", "./s.png"]);
    assert!(err.contains("-o ./s.png is the input"), "{err}");
    let err = fails(d, &["compare", "s.png", "-o", "s.png"]);
    assert!(err.contains("-o s.png is the scene"), "{err}");
    assert_eq!(
        std::fs::read_to_string(d.join("s.png")).unwrap(),
        scene_text
    );
}

#[test]
fn a_trace_at_the_deepest_max_depth_loads_again() {
    // Two facing perfect mirrors: the ray bounces max_depth = 64 times (the most accepted).
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
name = "mirror"
reflective = 1
[[plane]]
name = "front"
point = [0, 0, 2]
normal = [0, 0, -1]
material = "mirror"
[[plane]]
name = "back"
point = [0, 0, -2]
normal = [0, 0, 1]
material = "mirror"
"#;
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("mirrors.toml"), text).unwrap();
    raystep()
        .current_dir(dir.path())
        .args([
            "trace",
            "mirrors.toml",
            "--pixel",
            "1,1",
            "--save",
            "deep.json",
        ])
        .assert()
        .success();
    let json = std::fs::read_to_string(dir.path().join("deep.json")).unwrap();
    let t = raystep::record::Trace::from_json(&json, "deep.json").expect("the deep trace loads");
    assert_eq!(t.rays().iter().map(|r| r.depth).max(), Some(64));
    // Read back by a command too.
    raystep()
        .current_dir(dir.path())
        .args(["diff", "deep.json", "deep.json"])
        .assert()
        .success();
    // A hostile file nested far deeper is refused with the reason, not a crash.
    let deep = format!(
        "{{\"version\":1,\"x\":{}1{}}}",
        "[".repeat(100_000),
        "]".repeat(100_000)
    );
    let err = raystep::record::Trace::from_json(&deep, "deep.json").unwrap_err();
    assert!(err.to_string().contains("nested more than"), "{err}");
}

#[test]
fn csv_line_endings_and_encodings() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Old Mac line endings (CR alone): graded like LF.
    std::fs::write(d.join("cr.csv"), "student,disc\rs1001,1\rs1002,2\r").unwrap();
    let out = raystep()
        .current_dir(d)
        .args(["grade", "02-sphere", "cr.csv", "-o", "grades.csv"])
        .assert()
        .success()
        .get_output()
        .clone();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("graded 2 students"), "{text}");
    // UTF-16 (with and without its byte order mark): refused, saying so.
    let utf16: Vec<u8> = "student,disc\ns1001,1\n"
        .encode_utf16()
        .flat_map(|u| u.to_le_bytes())
        .collect();
    for (name, bytes) in [
        ("bom.csv", [vec![0xFF, 0xFE], utf16.clone()].concat()),
        ("plain.csv", utf16),
    ] {
        std::fs::write(d.join(name), bytes).unwrap();
        let err = fails(d, &["grade", "02-sphere", name, "-o", "g2.csv"]);
        assert!(err.contains("looks like UTF-16"), "{name}: {err}");
        assert!(!d.join("g2.csv").exists());
    }
}

#[test]
fn a_failing_converge_leaves_no_folder() {
    let dir = tempfile::tempdir().unwrap();
    let err = fails(dir.path(), &["converge", "missing.toml", "--out", "D/E"]);
    assert!(err.contains("missing.toml"), "{err}");
    assert!(!dir.path().join("D").exists(), "{err}");
}
