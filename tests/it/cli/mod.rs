//! The `raystep` command line, driven as a user drives it (assert_cmd): the `intersect`
//! calculator against hand-derived numbers and The Ray Tracer Challenge's published vectors
//! (Jamis Buck, Pragmatic Bookshelf 2019: ch. 5 spheres, ch. 9 planes, ch. 12 cubes; the
//! triangle of the "Triangles" bonus chapter), `trace` (JSON, tree, --save), `scene check`,
//! help, and bad input, which must give a clear message and a non-zero exit, never a panic.
//!
//! Every expected number here is worked out by hand in the comment next to it; none is copied
//! from the program's output.
//!
//! Command lines are written as one string split at whitespace; a file path is passed as `@`
//! and substituted whole, so paths with spaces are safe.

use assert_cmd::Command;
use predicates::prelude::*;
use serde_json::{Value, json};
use std::ffi::OsString;
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// A command line: `line` split at whitespace, each `@` replaced by the next of `paths`.
#[derive(Debug, Clone)]
struct Cli(Vec<OsString>);

impl Cli {
    fn new(line: &str) -> Cli {
        Cli::with(line, &[])
    }

    fn with(line: &str, paths: &[&dyn AsRef<Path>]) -> Cli {
        let mut paths = paths.iter();
        let args = line
            .split_whitespace()
            .map(|w| match w {
                "@" => paths.next().expect("a path for each @").as_ref().into(),
                _ => w.into(),
            })
            .collect();
        assert!(paths.next().is_none(), "more paths than @ in {line:?}");
        Cli(args)
    }

    /// Appends more whitespace-separated arguments.
    fn and(mut self, more: &str) -> Cli {
        self.0.extend(more.split_whitespace().map(OsString::from));
        self
    }
}

fn raystep() -> Command {
    Command::cargo_bin("raystep").expect("the raystep binary is built")
}

/// Runs raystep, expects success, returns stdout.
fn ok(cli: &Cli) -> String {
    let out = raystep()
        .args(&cli.0)
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    String::from_utf8(out).expect("stdout is UTF-8")
}

/// Runs raystep and parses its stdout as JSON.
fn json_of(cli: &Cli) -> Value {
    let text = ok(cli);
    serde_json::from_str(&text)
        .unwrap_or_else(|e| panic!("{cli:?}: stdout is not JSON ({e}):\n{text}"))
}

/// Runs raystep, expects a non-zero exit without a panic and an error message on stderr that
/// contains every string in `expect`; returns stderr.
fn fails(cli: &Cli, expect: &[&str]) -> String {
    let out = raystep()
        .args(&cli.0)
        .assert()
        .failure()
        .get_output()
        .clone();
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(!stderr.contains("panicked"), "{cli:?} panicked:\n{stderr}");
    assert!(!stderr.trim().is_empty(), "{cli:?}: no error message");
    for e in expect {
        assert!(stderr.contains(e), "{cli:?}: stderr lacks {e:?}:\n{stderr}");
    }
    stderr
}

/// A JSON number as f64 (panics naming the key otherwise).
fn num(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("\"{key}\" is not a number in {v}"))
}

/// A JSON array of numbers.
fn nums(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap_or_else(|| panic!("not a number: {x}")))
        .collect()
}

fn close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got}, want {want} (± {tol})"
    );
}

const METHODS: [&str; 2] = ["textbook", "stable"];
const PRECISIONS: [&str; 2] = ["f32", "f64"];

/// `intersect sphere` on the unit sphere at the origin with a ray and extra flags, as JSON.
fn unit_sphere(origin: &str, dir: &str, extra: &str) -> Value {
    json_of(&Cli::new(&format!(
        "intersect sphere --center 0,0,0 --radius 1 --origin {origin} --dir {dir} --json {extra}"
    )))
}

/// The index of the first line whose trimmed text starts with `prefix`.
fn line_index(text: &str, prefix: &str) -> Option<usize> {
    text.lines()
        .position(|l| l.trim_start().starts_with(prefix))
}

/// Asserts that lines starting with each prefix exist, in this order.
fn assert_in_order(text: &str, prefixes: &[&str]) {
    let mut last: Option<(usize, &str)> = None;
    for p in prefixes {
        let i = line_index(text, p)
            .unwrap_or_else(|| panic!("no line starting with {p:?} in:\n{text}"));
        if let Some((prev, prev_p)) = last {
            assert!(
                i > prev,
                "{p:?} (line {i}) should come after {prev_p:?} (line {prev}):\n{text}"
            );
        }
        last = Some((i, p));
    }
}

/// One unit sphere "ball" at the origin, a light, and a camera at (0, 0, −5) looking at the
/// origin, 101×101 pixels (so that pixel 50 is the exact centre).
const ONE_SPHERE: &str = r#"# One sphere, written by tests/it/cli/mod.rs.
[camera]
from = [0, 0, -5]
at = [0, 0, 0]
up = [0, 1, 0]
fov = 60
width = 101
height = 101

[[light]]
name = "lamp"
position = [-10, 10, -10]

[[sphere]]
name = "ball"
center = [0, 0, 0]
radius = 1
"#;

fn write_scene(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write the scene");
    p
}

/// A temporary directory holding ONE_SPHERE as one.toml.
fn one_sphere() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let scene = write_scene(dir.path(), "one.toml", ONE_SPHERE);
    (dir, scene)
}

fn three_spheres() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join("three-spheres.toml")
}

fn file_names(dir: &Path) -> Vec<OsString> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    v.sort();
    v
}

mod bad_input;
mod book_commands;
mod builtin;
mod fixed;

/// The Ray Tracer Challenge's triangle: P0 = (0, 1, 0), P1 = (−1, 0, 0), P2 = (1, 0, 0).
const TRI: &str = "intersect triangle --p0 0,1,0 --p1 -1,0,0 --p2 1,0,0";

/// The unit cube of The Ray Tracer Challenge (ch. 12).
const CUBE: &str = "intersect box --min -1,-1,-1 --max 1,1,1";

/// `intersect sphere` with its four arguments.
fn sphere(center: &str, radius: &str, origin: &str, dir: &str) -> Cli {
    Cli::new(&format!(
        "intersect sphere --center {center} --radius {radius} --origin {origin} --dir {dir}"
    ))
}

mod intersect;
mod scene_and_help;
mod trace;
