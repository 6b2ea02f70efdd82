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
const ONE_SPHERE: &str = r#"# One sphere, written by tests/it/cli.rs.
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

// ---------------------------------------------------------------------------------------------
// intersect sphere
// ---------------------------------------------------------------------------------------------

/// S = (0, 0, −5), Q = (0, 0, 1), unit sphere at the origin (RTC ch. 5 "A ray intersects a
/// sphere at two points"): f = S − G = (0, 0, −5), a = Q·Q = 1, b = 2 f·Q = −10,
/// c = f·f − r² = 25 − 1 = 24, Δ = b² − 4ac = 100 − 96 = 4 (stable: b′ = −f·Q = 5,
/// Δ′ = r² − ‖f + (b′/a)Q‖² = 1 − ‖(0, 0, 0)‖² = 1, 4aΔ′ = 4), roots (10 ∓ 2)/2 = 4, 6; t = 4.
/// All are small integers, exact in f32 and f64, so they are compared exactly.
#[test]
fn sphere_enter_exit_all_methods_and_precisions() {
    for m in METHODS {
        for p in PRECISIONS {
            let v = unit_sphere("0,0,-5", "0,0,1", &format!("--method {m} --precision {p}"));
            let what = format!("{m} {p}: {v}");
            assert_eq!(num(&v, "a"), 1.0, "{what}");
            assert_eq!(num(&v, "b"), -10.0, "{what}");
            assert_eq!(num(&v, "c"), 24.0, "{what}");
            assert_eq!(num(&v, "discriminant"), 4.0, "{what}");
            assert_eq!(nums(&v["roots"]), [4.0, 6.0], "{what}");
            assert_eq!(v["case"], "enter-exit", "{what}");
            assert_eq!(num(&v, "t"), 4.0, "{what}");
            assert_eq!(v["hit"], true, "{what}");
        }
    }
}

/// S = (0, 1, −5) (RTC "A ray intersects a sphere at a tangent"): f = (0, 1, −5), b = −10,
/// c = 1 + 25 − 1 = 25, Δ = 100 − 100 = 0 (stable: f + 5Q = (0, 1, 0), Δ′ = 1 − 1 = 0);
/// the double root is 10/2 = 5.
#[test]
fn sphere_tangent() {
    for m in METHODS {
        for p in PRECISIONS {
            let v = unit_sphere("0,1,-5", "0,0,1", &format!("--method {m} --precision {p}"));
            let what = format!("{m} {p}: {v}");
            assert_eq!(num(&v, "c"), 25.0, "{what}");
            assert_eq!(num(&v, "discriminant"), 0.0, "{what}");
            assert_eq!(v["case"], "tangent", "{what}");
            assert_eq!(nums(&v["roots"]), [5.0, 5.0], "{what}");
            assert_eq!(num(&v, "t"), 5.0, "{what}");
        }
    }
}

/// S = (0, 2, −5) (RTC "A ray misses a sphere"): c = 4 + 25 − 1 = 28,
/// Δ = b² − 4ac = 100 − 4·1·28 = −12 (stable: f + 5Q = (0, 2, 0), Δ′ = 1 − 4 = −3, 4aΔ′ = −12).
#[test]
fn sphere_miss() {
    for m in METHODS {
        for p in PRECISIONS {
            let v = unit_sphere("0,2,-5", "0,0,1", &format!("--method {m} --precision {p}"));
            let what = format!("{m} {p}: {v}");
            assert_eq!(num(&v, "c"), 28.0, "{what}");
            assert!(num(&v, "discriminant") < 0.0, "{what}");
            assert_eq!(num(&v, "discriminant"), -12.0, "{what}");
            assert_eq!(v["case"], "miss", "{what}");
            assert_eq!(v["roots"], json!([]), "{what}");
            assert!(v["t"].is_null(), "{what}");
            assert_eq!(v["hit"], false, "{what}");
        }
    }
}

/// S = origin (RTC "A ray originates inside a sphere"): f = 0, a = 1, b = 0, c = −1,
/// Δ = 0 + 4 = 4, roots (0 ∓ 2)/2 = −1, 1; −1 is behind the origin, so t = 1 (the far root).
/// S = (0, 0, 5) (RTC "A sphere is behind a ray"): b = 10, c = 24, roots (−10 ∓ 2)/2 = −6, −4:
/// both behind, no hit.
#[test]
fn sphere_inside_and_behind() {
    for m in METHODS {
        for p in PRECISIONS {
            let flags = format!("--method {m} --precision {p}");
            let v = unit_sphere("0,0,0", "0,0,1", &flags);
            let what = format!("{m} {p}: {v}");
            assert_eq!(num(&v, "b"), 0.0, "{what}");
            assert_eq!(num(&v, "c"), -1.0, "{what}");
            assert_eq!(nums(&v["roots"]), [-1.0, 1.0], "{what}");
            assert_eq!(num(&v, "t"), 1.0, "{what}");
            assert_eq!(v["hit"], true, "{what}");

            let v = unit_sphere("0,0,5", "0,0,1", &flags);
            let what = format!("{m} {p}: {v}");
            assert_eq!(nums(&v["roots"]), [-6.0, -4.0], "{what}");
            assert!(v["t"].is_null(), "{what}");
            assert_eq!(v["hit"], false, "{what}");
        }
    }
}

/// With --tmin 4.5 the near root 4 is ignored (hits at t ≤ tmin do not count) and the far
/// root 6 is taken.
#[test]
fn sphere_tmin_picks_the_far_root() {
    for m in METHODS {
        let v = unit_sphere("0,0,-5", "0,0,1", &format!("--method {m} --tmin 4.5"));
        assert_eq!(nums(&v["roots"]), [4.0, 6.0], "{m}: {v}");
        assert_eq!(num(&v, "t"), 6.0, "{m}: {v}");
        assert_eq!(v["hit"], true, "{m}: {v}");
    }
}

/// The far sphere (docs/NUMERICS.md S1): unit sphere at the origin, S = (0.5, 0, −4100),
/// Q = (0, 0, 1). Exactly: f = S, b = −8200, c = 0.25 + 4100² − 1 = 16 809 999.25,
/// Δ = 8200² − 4c = 67 240 000 − 67 239 997 = 3, near root (8200 − √3)/2 = 4100 − √0.75
/// ≈ 4099.13397. f64 holds all of these exactly.
/// In f32, 4100² = 16 810 000 lies in [2²⁴, 2²⁵) where the spacing is 2: f·f = 16 810 000.25
/// rounds to 16 810 000; minus 1 gives 16 809 999, a tie that rounds to the even 16 810 000 —
/// so the textbook Δ = 67 240 000 − 67 240 000 = 0 (both exact at spacing 8): the radius is
/// lost and the root is 4100, not 4099.134. The stable form gets Δ′ = r² − ‖(0.5, 0, 0)‖² = 0.75
/// from a vector difference and keeps the near root to within the f32 spacing at 4100 (2⁻¹¹).
#[test]
fn far_sphere_f32_textbook_loses_the_radius() {
    let exact = 4100.0 - 0.75f64.sqrt();
    let run = |m: &str, p: &str| {
        unit_sphere(
            "0.5,0,-4100",
            "0,0,1",
            &format!("--method {m} --precision {p}"),
        )
    };

    let tb64 = run("textbook", "f64");
    close(num(&tb64, "discriminant"), 3.0, 1e-9, "f64 textbook Δ");
    close(num(&tb64, "t"), exact, 1e-6, "f64 textbook near root");

    let tb32 = run("textbook", "f32");
    let t = tb32["t"].as_f64();
    assert!(
        t.is_none_or(|t| (t - exact).abs() > 0.1),
        "f32 textbook should not find the near root {exact}: {tb32}"
    );

    let st32 = run("stable", "f32");
    close(num(&st32, "discriminant"), 3.0, 1e-3, "f32 stable Δ");
    close(num(&st32, "t"), exact, 1e-3, "f32 stable near root");

    let st64 = run("stable", "f64");
    close(num(&st64, "t"), exact, 1e-9, "f64 stable near root");
}

/// The explanation names the intermediates in the order they are computed.
#[test]
fn sphere_plain_output_names_the_intermediates_in_order() {
    for m in METHODS {
        let out = ok(&Cli::new(&format!(
            "intersect sphere --center 0,0,0 --radius 1 --origin 0,0,-5 --dir 0,0,1 --method {m}"
        )));
        assert_in_order(&out, &["a = ", "b = ", "c = ", "Δ = b² − 4ac"]);
    }
}

// ---------------------------------------------------------------------------------------------
// intersect plane
// ---------------------------------------------------------------------------------------------

/// RTC ch. 9 "Intersecting a plane from above": the plane y = 0 (point (0, 0, 0), normal
/// (0, 1, 0)), S = (0, 1, 0), Q = (0, −1, 0): denominator Q·n = −1, numerator
/// c − S·n = 0 − 1 = −1, t = 1. "From below": S = (0, −1, 0), Q = (0, 1, 0): numerator
/// 0 − (−1) = 1, denominator 1, t = 1.
#[test]
fn plane_general_rtc_vectors() {
    for p in PRECISIONS {
        let base = format!("intersect plane --point 0,0,0 --normal 0,1,0 --json --precision {p}");
        let v = json_of(&Cli::new(&base).and("--origin 0,1,0 --dir 0,-1,0"));
        assert_eq!(num(&v, "denominator"), -1.0, "{v}");
        assert_eq!(num(&v, "numerator"), -1.0, "{v}");
        assert_eq!(v["parallel"], false, "{v}");
        assert_eq!(num(&v, "t"), 1.0, "{v}");
        assert_eq!(v["hit"], true, "{v}");

        let v = json_of(&Cli::new(&base).and("--origin 0,-1,0 --dir 0,1,0"));
        assert_eq!(num(&v, "denominator"), 1.0, "{v}");
        assert_eq!(num(&v, "numerator"), 1.0, "{v}");
        assert_eq!(num(&v, "t"), 1.0, "{v}");
    }
}

/// The plane x + y + z = 6 given as point (1, 2, 3) and normal (1, 1, 1) (not unit length);
/// the ray S = (−1, 0, 0), Q = (1, 1, 1): −1 + t + t + t = 6, so t = 7/3. With the unit normal
/// n = (1, 1, 1)/√3: denominator Q·n = 3/√3 = √3, numerator c − S·n = 6/√3 + 1/√3 = 7/√3.
/// A negative vector component (--origin -1,0,0) is accepted as a value.
#[test]
fn plane_general_oblique_by_hand() {
    let run = |p: &str| {
        json_of(&Cli::new(&format!(
            "intersect plane --point 1,2,3 --normal 1,1,1 --origin -1,0,0 --dir 1,1,1 --precision {p} --json"
        )))
    };
    let v = run("f64");
    close(num(&v, "t"), 7.0 / 3.0, 1e-12, "f64 t");
    close(
        num(&v, "denominator"),
        3f64.sqrt(),
        1e-12,
        "f64 denominator",
    );
    close(
        num(&v, "numerator"),
        7.0 / 3f64.sqrt(),
        1e-12,
        "f64 numerator",
    );
    let v = run("f32");
    close(num(&v, "t"), 7.0 / 3.0, 1e-5, "f32 t");
    assert_eq!(v["hit"], true);
}

/// The axis-aligned shortcut y = −1 (`--offset -1`, a negative value), S = (−1, 3, 0),
/// Q = (0, −2, 0): denominator Q_y = −2, numerator c − S_y = −1 − 3 = −4, t = −4/−2 = 2.
#[test]
fn plane_axis_form_with_negative_offset() {
    let line = "intersect plane --axis y --offset -1 --origin -1,3,0 --dir 0,-2,0";
    let v = json_of(&Cli::new(line).and("--json"));
    assert_eq!(num(&v, "denominator"), -2.0, "{v}");
    assert_eq!(num(&v, "numerator"), -4.0, "{v}");
    assert_eq!(v["parallel"], false, "{v}");
    assert_eq!(num(&v, "t"), 2.0, "{v}");
    assert_eq!(v["hit"], true, "{v}");

    let out = ok(&Cli::new(line));
    assert!(
        out.contains("y = -1"),
        "the plane is named with its offset:\n{out}"
    );
    // The hit point S + 2Q = (−1, −1, 0).
    assert!(out.contains("(-1, -1, 0)"), "{out}");
}

/// Parallel rays: Q·n = 0 (RTC "Intersect with a ray parallel to the plane": S = (0, 10, 0),
/// Q = (0, 0, 1); "Intersect with a coplanar ray": S = (0, 0, 0)), and the axis form with
/// Q_y = 0. Never NaN: parallel true, hit false, t null.
#[test]
fn plane_parallel_rays_miss() {
    for origin in ["0,10,0", "0,0,0"] {
        let v = json_of(&Cli::new(&format!(
            "intersect plane --point 0,0,0 --normal 0,1,0 --origin {origin} --dir 0,0,1 --json"
        )));
        assert_eq!(num(&v, "denominator"), 0.0, "{origin}: {v}");
        assert_eq!(v["parallel"], true, "{origin}: {v}");
        assert_eq!(v["hit"], false, "{origin}: {v}");
        assert!(v["t"].is_null(), "{origin}: {v}");
    }
    let line = "intersect plane --axis y --offset -1 --origin -1,3,0 --dir 1,0,0";
    let v = json_of(&Cli::new(line).and("--json"));
    assert_eq!(num(&v, "denominator"), 0.0, "{v}");
    assert_eq!(v["parallel"], true, "{v}");
    assert_eq!(v["hit"], false, "{v}");
    assert!(v["t"].is_null(), "{v}");
    let out = ok(&Cli::new(line));
    assert!(out.contains("parallel"), "{out}");
}

/// S = (0, 1, 0) moving up, away from y = 0: t = (0 − 1)/1 = −1, behind the origin: no hit,
/// and not parallel either.
#[test]
fn plane_behind_the_origin() {
    let v = json_of(&Cli::new(
        "intersect plane --point 0,0,0 --normal 0,1,0 --origin 0,1,0 --dir 0,1,0 --json",
    ));
    assert_eq!(num(&v, "denominator"), 1.0, "{v}");
    assert_eq!(num(&v, "numerator"), -1.0, "{v}");
    assert_eq!(v["parallel"], false, "{v}");
    assert_eq!(v["hit"], false, "{v}");
    assert!(v["t"].is_null(), "{v}");
}

// ---------------------------------------------------------------------------------------------
// intersect triangle
// ---------------------------------------------------------------------------------------------

/// The Ray Tracer Challenge's triangle: P0 = (0, 1, 0), P1 = (−1, 0, 0), P2 = (1, 0, 0).
const TRI: &str = "intersect triangle --p0 0,1,0 --p1 -1,0,0 --p2 1,0,0";

fn triangle(origin: &str, dir: &str, flags: &str) -> Value {
    json_of(&Cli::new(TRI).and(&format!("--origin {origin} --dir {dir} --json {flags}")))
}

/// E1 = P1 − P0 = (−1, −1, 0), E2 = P2 − P0 = (1, −1, 0),
/// E1 × E2 = (0, 0, (−1)(−1) − (−1)(1)) = (0, 0, 2). Ray S = (−0.2, 0.3, −2), Q = (0, 0, 1),
/// so −Q = (0, 0, −1): D0 = det(−Q, E1, E2) = −Q·(E1 × E2) = −2.
/// T = S − P0 = (−0.2, −0.7, −2); Dt = det(T, E1, E2) = T·(E1 × E2) = −4; t = −4/−2 = 2.
/// T × E2 = ((−0.7)(0) − (−2)(−1), (−2)(1) − (−0.2)(0), (−0.2)(−1) − (−0.7)(1)) = (−2, −2, 0.9):
/// Du = det(−Q, T, E2) = −Q·(T × E2) = −0.9, u = 0.45.
/// E1 × T = ((−1)(−2) − 0, 0 − (−1)(−2), (−1)(−0.7) − (−1)(−0.2)) = (2, −2, 0.5):
/// Dv = det(−Q, E1, T) = −0.5, v = 0.25. (0.2, 0.3 are inexact in binary: hence 1e-6.)
#[test]
fn triangle_hit_moller_trumbore_and_watertight() {
    for p in PRECISIONS {
        let v = triangle(
            "-0.2,0.3,-2",
            "0,0,1",
            &format!("--method moller-trumbore --precision {p}"),
        );
        let what = format!("{p}: {v}");
        assert_eq!(num(&v, "det"), -2.0, "{what}");
        close(num(&v, "dt"), -4.0, 1e-6, &what);
        close(num(&v, "du"), -0.9, 1e-6, &what);
        close(num(&v, "dv"), -0.5, 1e-6, &what);
        close(num(&v, "t"), 2.0, 1e-6, &what);
        close(num(&v, "u"), 0.45, 1e-6, &what);
        close(num(&v, "v"), 0.25, 1e-6, &what);
        assert_eq!(v["stopped_at"], 12, "{what}");
        assert_eq!(v["hit"], true, "{what}");

        let w = triangle(
            "-0.2,0.3,-2",
            "0,0,1",
            &format!("--method watertight --precision {p}"),
        );
        let what = format!("watertight {p}: {w}");
        // Q = (0, 0, 1): z is already the largest component (no permutation) and the shear is
        // Sx = Sy = −0/1 = 0, Sz = 1; the sheared vertices are Pᵢ − S = (0.2, 0.7, 2),
        // (−0.8, −0.3, 2), (1.2, −0.3, 2), and z′ = z·Sz = 2 for each.
        assert_eq!(w["permutation"], json!([0, 1, 2]), "{what}");
        assert_eq!(nums(&w["shear"]), [0.0, 0.0, 1.0], "{what}");
        let want = [[0.2, 0.7, 2.0], [-0.8, -0.3, 2.0], [1.2, -0.3, 2.0]];
        for (i, row) in want.iter().enumerate() {
            for (got, want) in nums(&w["sheared"][i]).iter().zip(row) {
                close(*got, *want, 1e-6, &what);
            }
        }
        assert_eq!(nums(&w["z_scaled"]), [2.0, 2.0, 2.0], "{what}");
        close(num(&w, "t"), 2.0, 1e-6, &what);
        close(num(&w, "u"), 0.45, 1e-6, &what);
        close(num(&w, "v"), 0.25, 1e-6, &what);
        assert_eq!(w["stopped_at"], 12, "{what}");
        assert_eq!(w["hit"], true, "{what}");
    }
}

/// A miss at each of the stop steps of Bailey's notes, with the intermediates after the stop null:
/// * step 2, parallel: Q = (0, 1, 0) lies in the triangle's plane z = 0: D0 = −Q·(0, 0, 2) = 0.
/// * step 5, behind: S = (0, 0.5, 2): T = (0, −0.5, 2), Dt = 2·2 = 4, t = 4/−2 = −2 ≤ 0.
/// * step 8, u out (RTC "A ray misses the p1-p3 edge"): S = (1, 1, −2): T = (1, 0, −2),
///   T × E2 = (−2, −2, −1), Du = 1, u = −0.5 < 0.
/// * step 11, v < 0 (RTC "misses the p1-p2 edge"): S = (−1, 1, −2): T = (−1, 0, −2),
///   T × E2 = (−2, −2, 1), Du = −1, u = 0.5; E1 × T = (2, −2, −1), Dv = 1, v = −0.5.
/// * step 11, u + v > 1 (RTC "misses the p2-p3 edge"): S = (0, −1, −2): T = (0, −2, −2),
///   T × E2 = (−2, −2, 2), Du = −2, u = 1; E1 × T = (2, −2, 2), Dv = −2, v = 1; u + v = 2.
///
/// In every case Dt = T·(0, 0, 2) = 2·T_z = −4 except where noted.
#[test]
fn triangle_misses_at_each_stop_step() {
    // (origin, dir, stopped_at, det, [dt, du, dv, u, v]); None = must be JSON null.
    type Case<'a> = (&'a str, &'a str, u64, f64, [Option<f64>; 5]);
    let cases: [Case; 5] = [
        ("0,-1,-2", "0,1,0", 2, 0.0, [None, None, None, None, None]),
        (
            "0,0.5,2",
            "0,0,1",
            5,
            -2.0,
            [Some(4.0), None, None, None, None],
        ),
        (
            "1,1,-2",
            "0,0,1",
            8,
            -2.0,
            [Some(-4.0), Some(1.0), None, Some(-0.5), None],
        ),
        (
            "-1,1,-2",
            "0,0,1",
            11,
            -2.0,
            [Some(-4.0), Some(-1.0), Some(1.0), Some(0.5), Some(-0.5)],
        ),
        (
            "0,-1,-2",
            "0,0,1",
            11,
            -2.0,
            [Some(-4.0), Some(-2.0), Some(-2.0), Some(1.0), Some(1.0)],
        ),
    ];
    for (origin, dir, step, det, values) in cases {
        let j = triangle(origin, dir, "--method moller-trumbore");
        let what = format!("S = {origin}, Q = {dir}: {j}");
        assert_eq!(j["stopped_at"], step, "{what}");
        assert_eq!(j["hit"], false, "{what}");
        assert!(j["t"].is_null(), "{what}");
        assert_eq!(num(&j, "det"), det, "{what}");
        for (key, want) in ["dt", "du", "dv", "u", "v"].into_iter().zip(values) {
            assert!(j.get(key).is_some(), "{what}: key {key} missing");
            match want {
                None => assert!(j[key].is_null(), "{what}: {key} should be null"),
                Some(w) => close(num(&j, key), w, 1e-6, &format!("{what}: {key}")),
            }
        }
        // The watertight test misses these rays too.
        let w = triangle(origin, dir, "--method watertight");
        assert_eq!(w["hit"], false, "watertight S = {origin}, Q = {dir}: {w}");
        assert!(w["t"].is_null(), "watertight S = {origin}, Q = {dir}: {w}");
    }
}

/// The numbered steps: all twelve for a hit, in order; after a stop, nothing further.
#[test]
fn triangle_plain_output_lists_steps_and_stops() {
    let run = |origin: &str, dir: &str| {
        ok(&Cli::new(TRI).and(&format!(
            "--origin {origin} --dir {dir} --method moller-trumbore"
        )))
    };
    let hit = run("-0.2,0.3,-2", "0,0,1");
    let steps: Vec<String> = (1..=12).map(|i| format!("{i}. ")).collect();
    let steps: Vec<&str> = steps.iter().map(String::as_str).collect();
    assert_in_order(&hit, &steps);

    let parallel = run("0,-1,-2", "0,1,0");
    assert!(line_index(&parallel, "2. ").is_some(), "{parallel}");
    for later in ["3. ", "4. ", "5. ", "12. "] {
        assert!(
            line_index(&parallel, later).is_none(),
            "step {later} after a stop at 2:\n{parallel}"
        );
    }
    assert!(parallel.contains("parallel"), "{parallel}");

    for (origin, last, next) in [
        ("0,0.5,2", "5. ", "6. "),
        ("1,1,-2", "8. ", "9. "),
        ("-1,1,-2", "11. ", "12. "),
    ] {
        let out = run(origin, "0,0,1");
        assert!(line_index(&out, last).is_some(), "{out}");
        assert!(
            line_index(&out, next).is_none(),
            "step {next} after a stop at {last}:\n{out}"
        );
        assert!(out.contains("no hit"), "{out}");
    }
}

// ---------------------------------------------------------------------------------------------
// intersect box
// ---------------------------------------------------------------------------------------------

const CUBE: &str = "intersect box --min -1,-1,-1 --max 1,1,1";

fn cube(origin: &str, dir: &str, method: &str, precision: &str) -> Value {
    json_of(&Cli::new(CUBE).and(&format!(
        "--origin {origin} --dir {dir} --method {method} --precision {precision} --json"
    )))
}

/// RTC ch. 12 "A ray intersects a cube": from each face, the slab along the ray's axis gives
/// 4 and 6 (e.g. S_x = 5, Q_x = −1: (1 − 5)/−1 = 4, (−1 − 5)/−1 = 6); the other two slabs are
/// (−∞, ∞) because S lies inside them and Q is 0 there. The plain test reports t_far = 6
/// exactly; the robust test enlarges t_far by (1 + 2γ₃), γ₃ = 3u/(1 − 3u), about 3.6e-7
/// relative in f32 (u = 2⁻²⁴), so t_far ∈ [6, 6·(1 + 1e-6)].
/// Inside (RTC's S = (0, 0.5, 0), Q = +z): the z slab is (−1, 1), so
/// t_near = max(t_min = 0, −1) = 0 and t_far ≈ 1.
#[test]
fn box_rtc_cube_hits() {
    let hits = [
        ("5,0.5,0", "-1,0,0"),
        ("-5,0.5,0", "1,0,0"),
        ("0.5,5,0", "0,-1,0"),
        ("0.5,-5,0", "0,1,0"),
        ("0.5,0,5", "0,0,-1"),
        ("0.5,0,-5", "0,0,1"),
    ];
    for m in ["plain", "robust"] {
        for p in PRECISIONS {
            for (o, d) in hits {
                let v = cube(o, d, m, p);
                let what = format!("{m} {p} S = {o}, Q = {d}: {v}");
                assert_eq!(v["hit"], true, "{what}");
                assert_eq!(num(&v, "t_near"), 4.0, "{what}");
                assert_eq!(num(&v, "t"), 4.0, "{what}");
                let far = num(&v, "t_far");
                if m == "plain" {
                    assert_eq!(far, 6.0, "{what}");
                } else {
                    assert!((6.0..=6.0 * (1.0 + 1e-6)).contains(&far), "{what}");
                }
            }
            let v = cube("0,0.5,0", "0,0,1", m, p);
            let what = format!("{m} {p} inside: {v}");
            assert_eq!(v["hit"], true, "{what}");
            assert_eq!(num(&v, "t_near"), 0.0, "{what}");
            close(num(&v, "t_far"), 1.0, 1e-6, &what);
        }
    }
}

/// RTC ch. 12 "A ray misses a cube": the slabs do not overlap (e.g. S = (2, 0, 2), Q = −z: a ray
/// at x = 2 with Q_x = 0 is never inside the x slab). Both methods miss; t is null.
#[test]
fn box_rtc_cube_misses() {
    let misses = [
        ("-2,0,0", "0.2673,0.5345,0.8018"),
        ("0,-2,0", "0.8018,0.2673,0.5345"),
        ("0,0,-2", "0.5345,0.8018,0.2673"),
        ("2,0,2", "0,0,-1"),
        ("0,2,2", "0,-1,0"),
        ("2,2,0", "-1,0,0"),
    ];
    for m in ["plain", "robust"] {
        for (o, d) in misses {
            let v = cube(o, d, m, "f32");
            assert_eq!(v["hit"], false, "{m} S = {o}, Q = {d}: {v}");
            assert!(v["t"].is_null(), "{m} S = {o}, Q = {d}: {v}");
        }
    }
}

/// A zero-thickness box (the quad z = 0, x, y ∈ [0, 1]) and the oblique ray S = (0.2, 0.3, −1),
/// Q = (0.3, 0.2, 1): the z slab gives t = (0 − (−1))/1 = 1 at both planes; x gives
/// (−0.2/0.3, 0.8/0.3) and y (−0.3/0.2, 0.7/0.2), both containing 1. So t_near = t_far = 1 and
/// the robust test (≤, t_far enlarged) hits at t = 1: the point (0.5, 0.5, 0), inside the quad.
#[test]
fn box_zero_thickness_hit_by_robust() {
    let v = json_of(&Cli::new(
        "intersect box --min 0,0,0 --max 1,1,0 --origin 0.2,0.3,-1 --dir 0.3,0.2,1 --method robust --json",
    ));
    assert_eq!(v["hit"], true, "{v}");
    close(num(&v, "t"), 1.0, 1e-6, "zero-thickness t");
}

#[test]
fn box_plain_output_names_the_slabs_in_order() {
    let out = ok(&Cli::new(CUBE).and("--origin 5,0.5,0 --dir -1,0,0"));
    assert_in_order(&out, &["x slab", "y slab", "z slab", "t_near", "t_far"]);
}

// ---------------------------------------------------------------------------------------------
// Bad input: a clear message and a non-zero exit, never a panic
// ---------------------------------------------------------------------------------------------

fn sphere(center: &str, radius: &str, origin: &str, dir: &str) -> Cli {
    Cli::new(&format!(
        "intersect sphere --center {center} --radius {radius} --origin {origin} --dir {dir}"
    ))
}

#[test]
fn bad_vectors_are_rejected() {
    fails(&sphere("0,0,0", "1", "0,0,-5", "0,0,0"), &["zero"]);
    fails(
        &sphere("0,0,0", "1", "0,0,-5", "0,0,nan"),
        &["--dir", "finite"],
    );
    fails(
        &sphere("0,0,0", "1", "0,0,-5", "0,0,inf"),
        &["--dir", "finite"],
    );
    fails(&sphere("0,0,0", "1", "0,0,-5", "0,1"), &["--dir", "three"]);
    fails(
        &sphere("0,0,0", "1", "0,0,-5", "0,1,2,3"),
        &["--dir", "three"],
    );
    fails(
        &sphere("0,0,0", "1", "a,b,c", "0,0,1"),
        &["--origin", "not a number"],
    );
    fails(&sphere("x,0,0", "1", "0,0,-5", "0,0,1"), &["--center"]);
    // The same checks guard every shape's vectors.
    fails(&Cli::new(TRI).and("--origin 0,0,-5 --dir 0,0,0"), &["zero"]);
    fails(
        &Cli::new(CUBE).and("--origin 0,0,-5 --dir nan,0,1"),
        &["--dir"],
    );
    fails(
        &Cli::new("intersect plane --axis y --offset 0 --origin 0,0,-5 --dir 0,0"),
        &["--dir"],
    );
}

#[test]
fn bad_sphere_radius_is_rejected() {
    for r in ["-1", "0", "nan", "inf", "one"] {
        fails(&sphere("0,0,0", r, "0,0,-5", "0,0,1"), &["--radius"]);
    }
}

#[test]
fn bad_plane_is_rejected() {
    let ray = "--origin 0,1,0 --dir 0,-1,0";
    fails(
        &Cli::new("intersect plane --point 0,0,0 --normal 0,0,0").and(ray),
        &["--normal"],
    );
    // --point without --normal; the two forms mixed; an unknown axis.
    fails(
        &Cli::new("intersect plane --point 0,0,0").and(ray),
        &["--normal"],
    );
    fails(
        &Cli::new("intersect plane --point 0,0,0 --normal 0,1,0 --axis y").and(ray),
        &["--axis"],
    );
    fails(&Cli::new("intersect plane --axis w").and(ray), &["--axis"]);
}

#[test]
fn bad_box_is_rejected() {
    let ray = "--origin 0,0,-5 --dir 0,0,1";
    fails(
        &Cli::new("intersect box --min 1,1,1 --max -1,-1,-1").and(ray),
        &["--min", "--max"],
    );
    // min > max on one axis only.
    fails(
        &Cli::new("intersect box --min -1,2,-1 --max 1,1,1").and(ray),
        &["--min"],
    );
}

#[test]
fn unknown_method_precision_or_command_is_rejected() {
    let ray = "--origin 0,0,-5 --dir 0,0,1";
    fails(
        &sphere("0,0,0", "1", "0,0,-5", "0,0,1").and("--method quadratic"),
        &["quadratic", "--method"],
    );
    fails(
        &Cli::new(TRI).and(ray).and("--method moller"),
        &["--method"],
    );
    fails(&Cli::new(CUBE).and(ray).and("--method fast"), &["--method"]);
    fails(
        &sphere("0,0,0", "1", "0,0,-5", "0,0,1").and("--precision f16"),
        &["--precision"],
    );
    fails(&Cli::new("intersect cone"), &["cone"]);
    fails(&Cli::new("frobnicate"), &["frobnicate"]);
}

#[test]
fn bad_trace_arguments_are_rejected() {
    let (_dir, scene) = one_sphere();
    let trace = |more: &str| Cli::with("trace @", &[&scene]).and(more);
    // The image is 101×101: x and y run 0 … 100.
    fails(&trace("--pixel 101,0"), &["--pixel", "outside"]);
    fails(&trace("--pixel 0,101"), &["--pixel", "outside"]);
    fails(&trace("--pixel 1,2,3"), &["--pixel"]);
    fails(&trace("--pixel a,b"), &["--pixel"]);
    fails(&trace(""), &["--pixel"]);
    // One sample per pixel: sample 0 only; with --spp 4, samples 0 … 3.
    fails(&trace("--pixel 50,50 --sample 1"), &["--sample"]);
    fails(&trace("--pixel 50,50 --spp 4 --sample 4"), &["--sample"]);
    fails(&trace("--pixel 50,50 --spp 0"), &["--spp"]);
    fails(&trace("--pixel 50,50 --offset sideways"), &["--offset"]);
    fails(
        &trace("--pixel 50,50 --sphere-method quadratic"),
        &["--sphere-method"],
    );
}

#[test]
fn missing_scene_file_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("no-such-scene.toml");
    fails(
        &Cli::with("trace @ --pixel 0,0", &[&missing]),
        &["no-such-scene.toml"],
    );
    fails(
        &Cli::with("scene check @", &[&missing]),
        &["no-such-scene.toml"],
    );
}

/// A syntax error: the array on line 6 is not closed, so the parser meets `radius` at line 7,
/// column 1, where it expects `,` or `]`. A semantic error: `radius = -1` is line 4, column 1.
/// An unknown field: `colour` is line 4, column 1. Each message starts with file:line:column.
#[test]
fn malformed_scene_names_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let syntax = write_scene(
        dir.path(),
        "syntax.toml",
        "[camera]\nwidth = 10\n\n[[sphere]]\nname = \"a\"\ncenter = [0, 0\nradius = 1\n",
    );
    let at = format!("{}:7:1", syntax.display());
    fails(&Cli::with("scene check @", &[&syntax]), &[&at]);
    fails(&Cli::with("trace @ --pixel 0,0", &[&syntax]), &[&at]);

    let semantic = write_scene(
        dir.path(),
        "semantic.toml",
        "[[sphere]]\nname = \"a\"\ncenter = [0, 0, 0]\nradius = -1\n",
    );
    let at = format!("{}:4:1", semantic.display());
    fails(&Cli::with("scene check @", &[&semantic]), &[&at, "radius"]);

    let unknown = write_scene(
        dir.path(),
        "unknown.toml",
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\ncolour = 3\n",
    );
    let at = format!("{}:4:1", unknown.display());
    fails(&Cli::with("scene check @", &[&unknown]), &[&at, "colour"]);
}

#[test]
fn save_into_a_missing_directory_fails_and_creates_nothing() {
    let (dir, scene) = one_sphere();
    let missing_dir = dir.path().join("not-here");
    let target = missing_dir.join("trace.json");
    fails(
        &Cli::with("trace @ --pixel 50,50 --save @", &[&scene, &target]),
        &["not-here"],
    );
    assert!(!target.exists());
    assert!(!missing_dir.exists());
    // Saving onto an existing directory fails too, and leaves it alone.
    fails(
        &Cli::with("trace @ --pixel 50,50 --save @", &[&scene, &dir.path()]),
        &["directory"],
    );
    assert!(dir.path().is_dir());
    // A failed trace (bad pixel) writes no file.
    let never = dir.path().join("never.json");
    fails(
        &Cli::with("trace @ --pixel 500,0 --save @", &[&scene, &never]),
        &["--pixel"],
    );
    assert!(!never.exists());
    assert_eq!(
        file_names(dir.path()),
        ["one.toml"],
        "nothing but the scene is left"
    );
}

// ---------------------------------------------------------------------------------------------
// trace
// ---------------------------------------------------------------------------------------------

/// The camera at (0, 0, −5) looking at the origin: w = normalize(from − at) = (0, 0, −1),
/// u = normalize(up × w) = (0, 1, 0) × (0, 0, −1) = (−1, 0, 0), v = w × u = (0, 1, 0).
/// Pixel (50, 50) of 101×101 at its centre: sx = 2·50.5/101 − 1 = 0 and
/// sy = 1 − 2·50.5/101 = 0 (exact in f32), so the direction is normalize(−w) = (0, 0, 1) and
/// the ray meets the unit sphere where −5 + t = −1: t = 4 (the enter-exit case above).
#[test]
fn trace_json_centre_pixel_hits_the_sphere_at_t4() {
    let (_dir, scene) = one_sphere();
    let v = json_of(&Cli::with("trace @ --pixel 50,50 --json", &[&scene]));
    assert_eq!(v["version"], 1);
    assert_eq!(v["pixel"], json!([50, 50]));
    assert_eq!(v["sample"], 0);
    let root = &v["root"];
    assert_eq!(root["kind"], "primary");
    assert_eq!(root["depth"], 0);
    assert_eq!(nums(&root["origin"]), [0.0, 0.0, -5.0]);
    assert_eq!(nums(&root["direction"]), [0.0, 0.0, 1.0]);
    let camera = &root["steps"][0];
    assert_eq!(camera["type"], "camera");
    assert_eq!(camera["stage"], "ray-generation");
    assert_eq!(camera["pixel"], json!([50, 50]));
    assert_eq!(
        nums(&camera["offset"]),
        [0.5, 0.5],
        "spp = 1: the pixel centre"
    );
    assert_eq!(nums(&camera["screen"]), [0.0, 0.0]);
    assert_eq!(nums(&camera["direction"]), [0.0, 0.0, 1.0]);

    let steps = root["steps"].as_array().unwrap();
    let test = steps
        .iter()
        .find(|s| s["type"] == "sphere")
        .expect("a sphere test step");
    assert_eq!(test["stage"], "intersection");
    assert_eq!(test["name"], "ball");
    assert_eq!(num(&test["test"], "discriminant"), 4.0);
    assert_eq!(nums(&test["test"]["roots"]), [4.0, 6.0]);

    assert_eq!(root["hit"]["name"], "ball");
    assert_eq!(num(&root["hit"], "t"), 4.0);
    // The lit sphere sends a shadow ray towards "lamp".
    let children = root["children"].as_array().unwrap();
    assert!(children.iter().any(|c| c["kind"] == "shadow"), "{root}");
}

/// Pixel (0, 0) looks about 39° off the axis (sx ≈ sy ≈ ±0.99 times tan 30° ≈ 0.57 each), while
/// the sphere subtends asin(1/5) ≈ 11.5° from the camera: the primary ray misses and returns
/// the default black background.
#[test]
fn trace_json_corner_pixel_misses() {
    let (_dir, scene) = one_sphere();
    let v = json_of(&Cli::with("trace @ --pixel 0,0 --json", &[&scene]));
    let root = &v["root"];
    assert!(root["hit"].is_null(), "{root}");
    let steps = root["steps"].as_array().unwrap();
    assert!(
        steps
            .iter()
            .any(|s| s["type"] == "miss" && s["stage"] == "miss"),
        "{root}"
    );
    assert_eq!(nums(&v["color"]), [0.0, 0.0, 0.0]);
}

#[test]
fn trace_tree_names_rays_and_stages() {
    let (_dir, scene) = one_sphere();
    let out = ok(&Cli::with("trace @ --pixel 50,50", &[&scene]));
    for want in [
        "primary ray",
        "[ray-generation]",
        "[intersection]",
        "shadow ray",
        "[closest-hit] light",
        "\"ball\"",
    ] {
        assert!(out.contains(want), "tree lacks {want:?}:\n{out}");
    }
    assert_in_order(
        &out,
        &["primary ray", "[0] [ray-generation]", "[1] [intersection]"],
    );

    let out = ok(&Cli::with("trace @ --pixel 160,120", &[&three_spheres()]));
    for want in [
        "primary ray",
        "[ray-generation]",
        "[intersection]",
        "shadow ray",
        "[closest-hit] light",
    ] {
        assert!(
            out.contains(want),
            "three-spheres tree lacks {want:?}:\n{out}"
        );
    }
}

/// `raystep trace` numbers every step `[K]` as the app's step list does: from 0, over the whole
/// timeline in the order it happened, the spawn steps included and a child ray's steps right
/// after its spawn step. The numbers are read against the JSON trace walked here, and against
/// what the app's step list shows for this pixel (its snapshot, tests/snapshots/
/// app-three-spheres-quadratic.png: "9. → child ray 0", then the shadow ray from 10 to 13);
/// the last K is one `diagram --step` takes, K + 1 is not.
#[test]
fn trace_numbers_every_step_as_the_app_and_step_arguments_do() {
    let scene = three_spheres();
    let text = ok(&Cli::with("trace @ --pixel 150,110", &[&scene]));
    let json = json_of(&Cli::with("trace @ --pixel 150,110 --json", &[&scene]));

    // The timeline from the JSON: (stage, type) of every step, children where spawned.
    fn walk(ray: &Value, out: &mut Vec<(String, String)>) {
        for s in ray["steps"].as_array().unwrap() {
            out.push((
                s["stage"].as_str().unwrap().to_string(),
                s["type"].as_str().unwrap().to_string(),
            ));
            if s["type"] == "spawn" {
                walk(&ray["children"][s["child"].as_u64().unwrap() as usize], out);
            }
        }
    }
    let mut timeline = vec![];
    walk(&json["root"], &mut timeline);

    // The step lines: "[K] [stage] …", indented under their ray.
    let steps: Vec<(usize, &str, &str)> = text
        .lines()
        .filter_map(|l| {
            let rest = l.trim_start().strip_prefix('[')?;
            let (k, rest) = rest.split_once("] [")?;
            let (stage, words) = rest.split_once("] ")?;
            Some((k.parse().ok()?, stage, words))
        })
        .collect();
    assert_eq!(
        steps.len(),
        timeline.len(),
        "one numbered line per step:\n{text}"
    );
    for (i, ((k, stage, words), (json_stage, kind))) in steps.iter().zip(&timeline).enumerate() {
        assert_eq!(*k, i, "the steps are numbered 0, 1, 2, … in order:\n{text}");
        assert_eq!(stage, json_stage, "step {k}");
        assert_eq!(
            kind == "spawn",
            words.starts_with("→ child ray"),
            "step {k}: {words}"
        );
    }
    assert_eq!(
        timeline.len(),
        16,
        "the app's list shows steps 0–15 for this pixel"
    );
    assert!(steps[9].2.starts_with("→ child ray 0"), "{text}");
    assert!(steps[11].2.starts_with("sphere \"middle\""), "{text}");
    // The child ray's header comes right after its spawn step, its first step right after it.
    let spawn = line_index(&text, "[9] [closest-hit]").expect("the spawn step's line");
    assert_eq!(line_index(&text, "shadow ray ("), Some(spawn + 1), "{text}");
    assert_eq!(
        line_index(&text, "[10] [intersection]"),
        Some(spawn + 2),
        "{text}"
    );

    // The printed numbers are the ones --step takes.
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("last.png");
    let last = timeline.len() - 1;
    ok(&Cli::with(
        &format!("diagram @ --pixel 150,110 --step {last} -o @"),
        &[&scene, &png],
    ));
    assert!(png.is_file());
    fails(
        &Cli::with(
            &format!("diagram @ --pixel 150,110 --step {} -o @", last + 1),
            &[&scene, &png],
        ),
        &["--step 16 does not exist", "16 steps (0 … 15)"],
    );
}

/// --save writes the very JSON that --json prints, complete, and nothing else beside it (the
/// write goes through a temporary file renamed over the target).
#[test]
fn trace_save_writes_the_same_json() {
    let (_dir, scene) = one_sphere();
    let out_dir = tempfile::tempdir().unwrap();
    let saved = out_dir.path().join("trace.json");
    let printed = json_of(&Cli::with(
        "trace @ --pixel 50,50 --json --save @",
        &[&scene, &saved],
    ));
    let text = std::fs::read_to_string(&saved).expect("the trace file exists");
    let from_file: Value = serde_json::from_str(&text).expect("the saved trace is complete JSON");
    assert_eq!(from_file, printed);
    assert_eq!(
        file_names(out_dir.path()),
        ["trace.json"],
        "no temporary file is left"
    );

    // Without --json the tree goes to stdout and the file still gets the JSON; overwriting works.
    let tree = ok(&Cli::with(
        "trace @ --pixel 50,50 --save @",
        &[&scene, &saved],
    ));
    assert!(tree.contains("primary ray"), "{tree}");
    let again: Value = serde_json::from_str(&std::fs::read_to_string(&saved).unwrap()).unwrap();
    assert_eq!(again, printed);
    assert_eq!(file_names(out_dir.path()), ["trace.json"]);
}

/// Deterministic (DESIGN principle 5): the same pixel and sample give the same trace, jittered
/// samples too; the sample's position inside the pixel lies in [0, 1)².
#[test]
fn trace_is_deterministic_and_samples_stay_in_the_pixel() {
    let (_dir, scene) = one_sphere();
    for sample in [0, 3] {
        let cli = Cli::with(
            &format!("trace @ --pixel 50,50 --spp 4 --sample {sample} --json"),
            &[&scene],
        );
        let a = ok(&cli);
        assert_eq!(a, ok(&cli), "sample {sample}");
        let v: Value = serde_json::from_str(&a).unwrap();
        assert_eq!(v["sample"], sample);
        assert_eq!(v["settings"]["spp"], 4);
        for o in nums(&v["root"]["steps"][0]["offset"]) {
            assert!((0.0..1.0).contains(&o), "sample {sample}: offset {o}");
        }
    }
}

/// Every offset policy, and other setting overrides, still give a trace that parses, with the
/// chosen settings recorded in it and a finite colour.
#[test]
fn trace_with_each_offset_policy_parses() {
    for offset in ["none", "fixed", "robust"] {
        let v = json_of(&Cli::with(
            &format!("trace @ --pixel 160,120 --offset {offset} --json"),
            &[&three_spheres()],
        ));
        assert_eq!(v["version"], 1, "{offset}");
        assert_eq!(v["settings"]["offset"], offset);
        assert_eq!(v["root"]["kind"], "primary");
        assert!(
            nums(&v["color"]).iter().all(|c| c.is_finite()),
            "{offset}: {}",
            v["color"]
        );
    }
    let v = json_of(&Cli::with(
        "trace @ --pixel 160,120 --sphere-method textbook --max-depth 0 --json",
        &[&three_spheres()],
    ));
    assert_eq!(v["settings"]["sphere_method"], "textbook");
    assert_eq!(v["settings"]["max_depth"], 0);
}

// ---------------------------------------------------------------------------------------------
// scene check
// ---------------------------------------------------------------------------------------------

/// Every shipped scene validates, and the primitive count printed agrees with --json.
#[test]
fn scene_check_accepts_every_shipped_scene() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        n += 1;
        let out = ok(&Cli::with("scene check @", &[&path]));
        let v = json_of(&Cli::with("scene check @ --json", &[&path]));
        let prims = v["primitives"]
            .as_u64()
            .unwrap_or_else(|| panic!("{}: {v}", path.display()));
        assert!(
            out.contains(&format!("primitives {prims}")),
            "{}:\n{out}",
            path.display()
        );
    }
    assert!(n >= 1, "no scenes in {}", dir.display());
}

/// scenes/three-spheres.toml, counted from the file itself (read here as plain TOML, not by
/// raystep): at the time of writing 3 `[[sphere]]`, 1 `[[plane]]`, no `[[triangle]]` or
/// `[[mesh]]`, 1 `[[light]]`: 4 primitives; the sphere with material "mirror"
/// (reflective = 0.5) makes the scene reflective, and no material has transparency.
#[test]
fn scene_check_json_counts_three_spheres() {
    let text = std::fs::read_to_string(three_spheres()).unwrap();
    let file: toml::Table = toml::from_str(&text).unwrap();
    let tables = |k: &str| {
        file.get(k)
            .and_then(|v| v.as_array())
            .cloned()
            .unwrap_or_default()
    };
    assert!(
        tables("mesh").is_empty(),
        "this test counts triangles without reading OBJ files"
    );
    let materials = tables("material");
    let property = |name: &str, key: &str| {
        materials
            .iter()
            .find(|m| m.get("name").and_then(|n| n.as_str()) == Some(name))
            .and_then(|m| m.get(key))
            .and_then(|x| x.as_float().or_else(|| x.as_integer().map(|i| i as f64)))
            .unwrap_or(0.0)
    };
    let objects: Vec<toml::Value> = ["sphere", "plane", "triangle"]
        .iter()
        .flat_map(|k| tables(k))
        .collect();
    let used: Vec<&str> = objects
        .iter()
        .filter_map(|o| o.get("material").and_then(|m| m.as_str()))
        .collect();
    let reflective = used.iter().any(|m| property(m, "reflective") > 0.0);
    let transparent = used.iter().any(|m| property(m, "transparency") > 0.0);
    let (spheres, planes, triangles) = (
        tables("sphere").len(),
        tables("plane").len(),
        tables("triangle").len(),
    );
    // Sanity check of the counting against the file as written today.
    assert!(spheres >= 3 && planes >= 1 && reflective, "{text}");

    let v = json_of(&Cli::with("scene check @ --json", &[&three_spheres()]));
    assert_eq!(v["spheres"], spheres, "{v}");
    assert_eq!(v["planes"], planes, "{v}");
    assert_eq!(v["triangles"], triangles, "{v}");
    assert_eq!(v["meshes"], 0, "{v}");
    assert_eq!(v["lights"], tables("light").len(), "{v}");
    assert_eq!(v["primitives"], objects.len(), "{v}");
    assert_eq!(v["reflective"], reflective, "{v}");
    assert_eq!(v["transparent"], transparent, "{v}");

    let out = ok(&Cli::with("scene check @", &[&three_spheres()]));
    assert!(out.contains("ok"), "{out}");
    assert!(
        out.contains(&format!("primitives {}", objects.len())),
        "{out}"
    );
}

/// The one-sphere scene: 1 sphere, 1 light, nothing else; the default material neither
/// reflects nor transmits.
#[test]
fn scene_check_of_a_written_scene() {
    let (_dir, scene) = one_sphere();
    let v = json_of(&Cli::with("scene check @ --json", &[&scene]));
    assert_eq!(
        v,
        json!({
            "spheres": 1, "planes": 0, "triangles": 0, "meshes": 0, "lights": 1,
            "reflective": false, "transparent": false, "primitives": 1, "emitters": 0
        })
    );
    let out = ok(&Cli::with("scene check @", &[&scene]));
    assert!(out.contains("primitives 1"), "{out}");
}

// ---------------------------------------------------------------------------------------------
// Help and the bare command
// ---------------------------------------------------------------------------------------------

#[test]
fn help_and_no_arguments_succeed() {
    let out = ok(&Cli::new("--help"));
    for cmd in ["intersect", "trace", "scene"] {
        assert!(out.contains(cmd), "--help lacks {cmd}:\n{out}");
    }
    let out = ok(&Cli::new("intersect sphere --help"));
    for flag in [
        "--center",
        "--radius",
        "--origin",
        "--dir",
        "--method",
        "--precision",
        "--tmin",
        "--json",
    ] {
        assert!(
            out.contains(flag),
            "intersect sphere --help lacks {flag}:\n{out}"
        );
    }
    ok(&Cli::new("trace --help"));
    ok(&Cli::new("scene check --help"));
    // With no command raystep opens the app; without a display it says so and fails cleanly.
    raystep()
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .assert()
        .failure()
        .stderr(predicate::str::contains("cannot open the app window"))
        .stderr(predicate::str::contains("panicked").not());
    raystep()
        .args(["open", "no-such-scene.toml"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("no-such-scene.toml: no such file"));
}

// ---------------------------------------------------------------------------------------------
// Bugs found in src/ and fixed: each test names the command that showed it
// ---------------------------------------------------------------------------------------------

/// A saved trace must load back (DESIGN: "loading a trace needs no scene"). The first
/// closest-hit step records `previous` = ∞, which serde_json writes as `null`, and an `f32`
/// field does not deserialize from `null`:
/// `raystep trace scenes/three-spheres.toml --pixel 160,120 --save t.json`, then
/// `Trace::load("t.json")` → "not a raystep trace: invalid type: null, expected f32".
#[test]
fn saved_trace_loads_back() {
    let dir = tempfile::tempdir().unwrap();
    let saved = dir.path().join("t.json");
    ok(&Cli::with(
        "trace @ --pixel 160,120 --save @",
        &[&three_spheres(), &saved],
    ));
    raystep::record::Trace::load(&saved).unwrap_or_else(|e| panic!("{e}"));
}

/// `--offset` of the axis-aligned plane takes any f64, NaN and ∞ included, while the vector
/// arguments reject them: `raystep intersect plane --axis x --offset nan --origin 0,0,-5
/// --dir 1,0,1 --json` exits 0 with `"numerator": null`.
#[test]
fn non_finite_plane_offset_is_rejected() {
    for c in ["nan", "inf"] {
        fails(
            &Cli::new(&format!(
                "intersect plane --axis x --offset {c} --origin 0,0,-5 --dir 1,0,1"
            )),
            &["--offset"],
        );
    }
}

/// Shape parameters finite in f64 but beyond f32's range become ∞ in the default f32 precision,
/// and the calculator prints NaN intermediates with exit 0:
/// `raystep intersect sphere --center 1e300,0,0 --radius 1 --origin 0,0,-5 --dir 0,0,1 --json`
/// → `"b": null, "discriminant": null`. The ray's origin is rejected in the same situation.
#[test]
fn shape_parameters_overflowing_f32_are_rejected() {
    fails(&sphere("1e300,0,0", "1", "0,0,-5", "0,0,1"), &["--center"]);
    fails(
        &Cli::new(
            "intersect triangle --p0 1e300,0,0 --p1 0,1,0 --p2 0,0,1 --origin 0,0,-5 --dir 0,0,1",
        ),
        &["--p0"],
    );
}

/// `--accel bvh` is accepted by `trace` and recorded in the trace's settings, but the trace is
/// made by brute force (src/cli/trace_cmd.rs always passes `&BruteForce`): no BVH node steps.
#[test]
fn trace_with_bvh_records_node_visits() {
    let v = json_of(&Cli::with(
        "trace @ --pixel 160,120 --accel bvh --json",
        &[&three_spheres()],
    ));
    assert_eq!(v["settings"]["accel"], "bvh");
    let steps = v["root"]["steps"].as_array().unwrap();
    assert!(
        steps.iter().any(|s| s["type"] == "node"),
        "no BVH node steps in a BVH trace"
    );
}

// ---------------------------------------------------------------------------------------------
// Built-in scenes and lessons
// ---------------------------------------------------------------------------------------------

#[test]
fn examples_write_every_built_in_file_and_refuse_to_overwrite() {
    let dir = tempfile::tempdir().unwrap();
    let out = ok(&Cli::with("examples --write @", &[&dir.path()]));
    let root = std::fs::canonicalize(dir.path()).unwrap();
    // Every file of the repository's scenes/ and lessons/ folders (the starter kit too), byte
    // for byte, named with its full path.
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut count = 0;
    for sub in ["scenes", "lessons", "lessons/exercises", "lessons/starter"] {
        for e in std::fs::read_dir(repo.join(sub)).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                continue;
            }
            let rel = p.strip_prefix(repo).unwrap();
            let written = root.join(rel);
            assert_eq!(
                std::fs::read(&written).unwrap(),
                std::fs::read(&p).unwrap(),
                "{}",
                rel.display()
            );
            assert!(
                out.contains(&format!("wrote {}\n", written.display())),
                "{out}"
            );
            count += 1;
        }
    }
    assert!(count > 30, "{count}");
    assert!(out.contains(&format!("{count} files written")), "{out}");
    // A second time: refused, nothing changed; with --force: written again.
    let lesson = root.join("lessons/02-ray-sphere.md");
    std::fs::write(&lesson, "mine").unwrap();
    fails(
        &Cli::with("examples --write @", &[&dir.path()]),
        &["already exists", "--force"],
    );
    assert_eq!(std::fs::read_to_string(&lesson).unwrap(), "mine");
    ok(&Cli::with("examples --write @ --force", &[&dir.path()]));
    assert_ne!(std::fs::read_to_string(&lesson).unwrap(), "mine");
}

#[test]
fn a_built_in_scene_by_name_from_any_folder() {
    let dir = tempfile::tempdir().unwrap();
    // The triangles scene loads its OBJ from the built-in copy, in a folder with no scenes/.
    let out = raystep()
        .current_dir(dir.path())
        .args(["scene", "check", "triangles", "--json"])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let v: Value = serde_json::from_slice(&out).unwrap();
    // Four triangles, a plane and the 20 faces of icosahedron.obj.
    assert_eq!(v["primitives"], 25, "{v}");
    assert_eq!(v["triangles"], 24, "{v}");
    // `render` writes where it is told and says so with the full path.
    let out = raystep()
        .current_dir(dir.path())
        .args(["render", "first-sphere", "-o", "s.png"])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let out = String::from_utf8(out).unwrap();
    let full = std::fs::canonicalize(dir.path().join("s.png")).unwrap();
    assert!(out.contains(&format!("wrote {}", full.display())), "{out}");
    // An unknown name lists the built-in ones.
    let err = raystep()
        .current_dir(dir.path())
        .args(["render", "cornel", "-o", "c.png"])
        .assert()
        .failure()
        .get_output()
        .stderr
        .clone();
    let err = String::from_utf8(err).unwrap();
    assert!(
        err.contains("built-in scenes:") && err.contains("cornell"),
        "{err}"
    );
}

/// `diagram --animate --delay-ms` sets the GIF's frame delay (the last frame is held for at
/// least 3 s); the default is 800 ms; a delay outside 20 … 60000 ms or not a number is refused
/// with a message naming the option's range and no file written.
#[test]
fn animated_diagram_frame_delay() {
    use image::AnimationDecoder as _;
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/first-sphere.toml");
    let delays = |gif: &Path| -> Vec<u32> {
        let file = std::io::BufReader::new(std::fs::File::open(gif).unwrap());
        image::codecs::gif::GifDecoder::new(file)
            .unwrap()
            .into_frames()
            .map(|f| {
                let (n, d) = f.unwrap().delay().numer_denom_ms();
                n / d.max(1)
            })
            .collect()
    };
    let quick = dir.path().join("quick.gif");
    ok(&Cli::with(
        "diagram @ --pixel 160,120 --size 160x120 --animate --delay-ms 250 -o @",
        &[&scene, &quick],
    ));
    let d = delays(&quick);
    assert!(d.len() > 2, "{d:?}");
    assert!(d[..d.len() - 1].iter().all(|&ms| ms == 250), "{d:?}");
    assert!(d[d.len() - 1] >= 3000, "the last frame is held: {d:?}");
    let plain = dir.path().join("plain.gif");
    ok(&Cli::with(
        "diagram @ --pixel 160,120 --size 160x120 --animate -o @",
        &[&scene, &plain],
    ));
    assert_eq!(delays(&plain)[0], 800, "the default delay");
    let bad = dir.path().join("bad.gif");
    for (arg, msg) in [
        ("5", "between 20 and 60000 ms"),
        ("fast", "not a whole number"),
    ] {
        fails(
            &Cli::with(
                &format!("diagram @ --pixel 160,120 --animate --delay-ms {arg} -o @"),
                &[&scene, &bad],
            ),
            &["--delay-ms", msg],
        );
        assert!(!bad.exists(), "no file for a refused delay");
    }
}

/// `intersect sphere` prints the recorded intermediates: for S = (0, 0, −5), Q = (0, 0, 1) and
/// the unit sphere at the origin, by hand: f = S − G = (0, 0, −5), b = 2 f·Q = −10,
/// c = 25 − 1 = 24, Δ = 100 − 96 = 4, √Δ = 2, t = (10 ∓ 2)/2 = 4, 6; stable: b′ = −f·Q = 5,
/// l = f + (b′/a)Q = (0, 0, 0), Δ′ = r² − l·l = 1.
#[test]
fn intersect_sphere_prints_the_recorded_intermediates() {
    let line = "intersect sphere --center 0,0,0 --radius 1 --origin 0,0,-5 --dir 0,0,1 --method";
    let textbook = ok(&Cli::new(&format!("{line} textbook")));
    for want in [
        "f = S − G              = (0, 0, -5)",
        "b = 2 f·Q              = -10",
        "c = f·f − r²           = 24",
        "Δ = b² − 4ac           = 4",
        "√Δ                     = 2",
        "t = (−b ± √Δ) / 2a     = 4, 6",
    ] {
        assert!(textbook.contains(want), "{want:?} in\n{textbook}");
    }
    let stable = ok(&Cli::new(&format!("{line} stable")));
    for want in [
        "f = S − G              = (0, 0, -5)",
        "b′ = −f·Q              = 5",
        "l = f + (b′/a)Q        = (0, 0, 0)",
        "= 1   (distance² margin",
    ] {
        assert!(stable.contains(want), "{want:?} in\n{stable}");
    }
}

/// `render --profile` adds the stages line: four shares (each 0 … 100 %) naming camera rays,
/// traversal, primitive tests, and shading and spawning (their values are timings, so only their
/// form is checked; the figures are in `bench --section stages`). `render` says what the accelerator visited per ray in its own words.
#[test]
fn render_profile_prints_where_the_time_goes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/triangles.toml");
    let run = |accel: &str, profile: bool| {
        let mut args = vec![
            "render".to_string(),
            scene.display().to_string(),
            "-o".into(),
            dir.path().join("t.png").display().to_string(),
            "--accel".into(),
            accel.into(),
        ];
        if profile {
            args.push("--profile".into());
        }
        let out = raystep()
            .args(&args)
            .assert()
            .success()
            .get_output()
            .clone();
        String::from_utf8(out.stdout).unwrap()
    };
    let out = run("none", true);
    let line = out
        .lines()
        .find(|l| l.trim_start().starts_with("profile"))
        .unwrap_or_else(|| panic!("{out}"));
    let mut shares = vec![];
    for name in [
        "camera rays ",
        "traversal ",
        "primitive tests ",
        "shading and spawning ",
    ] {
        let at = line.find(name).unwrap_or_else(|| panic!("{name}: {line}"));
        let rest = &line[at + name.len()..];
        let pct: f64 = rest[..rest.find(" %").unwrap()].parse().unwrap();
        assert!((0.0..=100.0).contains(&pct), "{line}");
        shares.push(pct);
    }
    assert_eq!(shares.len(), 4);
    assert!(!run("bvh", false).contains("profile"));
    for (accel, words) in [
        ("bvh", "box tests per ray"),
        ("spheres", "bounding-sphere tests per ray"),
        ("grid", "cells walked per ray"),
    ] {
        let out = run(accel, false);
        assert!(out.contains(words), "{accel}: {out}");
    }
}

/// A reader that closes the pipe early (`raystep render … | head -1`) ends the command quietly,
/// as it ends `cat`: no panic message (Rust's `println!` panics on a closed pipe unless the
/// default SIGPIPE action is restored). The pipe is closed before the command writes a line,
/// so its first line already meets it.
#[cfg(unix)]
#[test]
fn a_closed_pipe_ends_a_command_without_a_panic() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("first.png");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_raystep"))
        .arg("render")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/first-sphere.toml"))
        .arg("-o")
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let done = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&done.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    // Ended by SIGPIPE (13), as `cat` is, or finished before writing anything that failed.
    assert!(
        done.status.success() || done.status.signal() == Some(13),
        "{:?}: {stderr}",
        done.status
    );
}
