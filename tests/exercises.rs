//! Exercise sheets (`raystep exercise`, `check`, `grade`): every shipped sheet is marked against
//! answers read straight out of a recorded trace's timeline (not through raystep's own
//! extraction), perturbed answers fail, variants differ between students and repeat for one, a
//! quantity is checked against a hand computation, a class is graded with malformed rows, and bad
//! input exits non-zero with a located message.

use assert_cmd::Command;
use raystep::lesson::{self, Question, SceneSource, Sheet};
use raystep::trace::record::{RayKind, Step, Trace};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn sheets() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("lessons/exercises"))
        .expect("lessons/exercises exists")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

fn raystep() -> Command {
    Command::cargo_bin("raystep").expect("the raystep binary is built")
}

const STUDENTS: [&str; 4] = ["s1001", "alice@example.org", "Bob Smith", "42"];

/// Records the question's variant with the library directly.
fn record(sheet: &Sheet, q: &Question, student: &str) -> Trace {
    let v = sheet.variant(q, student);
    let scene = match &q.scene {
        SceneSource::File(p) => raystep::scene::load_file(p).unwrap(),
        SceneSource::Inline(_) => {
            raystep::scene::load_str(v.scene_toml.as_ref().unwrap(), "inline", None).unwrap()
        }
    };
    let (accel, _) = raystep::accel::SceneAccel::build(&scene);
    raystep::trace::Tracer::new(&scene, &accel).record(v.pixel[0], v.pixel[1], 0)
}

/// An answer read from the timeline, independently of raystep's extraction code.
#[derive(Debug, Clone, PartialEq)]
enum A {
    Num(f64),
    Vec([f64; 3]),
    Bool(bool),
    Name(String),
    None,
}

impl A {
    fn text(&self) -> String {
        match self {
            A::Num(x) => format!("{x}"),
            A::Vec([x, y, z]) => format!("({x}, {y}, {z})"),
            A::Bool(b) => if *b { "yes" } else { "no" }.into(),
            A::Name(n) => format!("\"{n}\""),
            A::None => "none".into(),
        }
    }

    /// An answer just beyond the tolerance (or simply different).
    fn perturbed(&self, abs: f64, rel: f64) -> String {
        let off = |x: f64| 2.0 * (abs + rel * x.abs()) + 0.01;
        match self {
            A::Num(x) => format!("{}", x + off(*x)),
            A::Vec([x, y, z]) => {
                let n = (x * x + y * y + z * z).sqrt();
                format!("{}, {y}, {z}", x + off(n))
            }
            A::Bool(b) => if *b { "no" } else { "yes" }.into(),
            A::Name(_) => "no-such-object".into(),
            A::None => "1, 2, 3".into(),
        }
    }
}

fn read_quantity(trace: &Trace, q: &Question) -> A {
    let kind = match format!("{:?}", q.ray).as_str() {
        "Primary" => RayKind::Primary,
        "Shadow" => RayKind::Shadow,
        "Reflection" => RayKind::Reflection,
        "Refraction" => RayKind::Refraction,
        other => panic!("ray {other}"),
    };
    let timeline = trace.timeline();
    // The first ray of that kind in the order steps happened.
    let Some(first) = timeline
        .iter()
        .find(|(r, _)| r.kind == kind)
        .map(|(r, _)| *r)
    else {
        return A::None;
    };
    let steps: Vec<&Step> = timeline
        .iter()
        .filter(|(r, _)| std::ptr::eq(*r, first))
        .map(|(_, s)| &s.step)
        .collect();
    let obj = q.object.as_deref();
    let accepted = steps.iter().rev().find_map(|s| match s {
        Step::Accept { name, t, .. } => Some((name.clone(), *t)),
        _ => None,
    });
    let sphere = steps.iter().find_map(|s| match s {
        Step::Sphere { name, test, .. } if Some(name.as_str()) == obj => Some(*test),
        _ => None,
    });
    let num = |x: Option<f32>| x.map_or(A::None, |x| A::Num(x as f64));
    let vec = |v: [f32; 3]| A::Vec(v.map(|c| c as f64));
    let triangle = || {
        let target = obj
            .map(String::from)
            .or_else(|| accepted.as_ref().map(|a| a.0.clone()))?;
        steps.iter().find_map(|s| match s {
            Step::Triangle { name, test, .. } if *name == target => Some(*test),
            _ => None,
        })
    };
    match q.quantity.name() {
        "discriminant" => num(sphere.map(|t| t.discriminant)),
        "near_root" => num(sphere.and_then(|t| t.roots).map(|r| r[0])),
        "far_root" => num(sphere.and_then(|t| t.roots).map(|r| r[1])),
        "closest_t" => num(accepted.map(|a| a.1)),
        "hit_object" => accepted.map_or(A::None, |a| A::Name(a.0)),
        "triangle_u" => num(triangle().and_then(|t| t.u)),
        "triangle_v" => num(triangle().and_then(|t| t.v)),
        "bvh_nodes_visited" => {
            A::Num(steps.iter().filter(|s| matches!(s, Step::Node(_))).count() as f64)
        }
        "shadow_blocked" => steps
            .iter()
            .find_map(|s| match s {
                Step::Light { light, blocked, .. } if *light == q.light => Some(A::Bool(*blocked)),
                _ => None,
            })
            .unwrap_or(A::None),
        "reflected_direction" => steps
            .iter()
            .find_map(|s| match s {
                Step::Reflect { direction, .. } => Some(vec(*direction)),
                _ => None,
            })
            .unwrap_or(A::None),
        "hit_point" | "normal" => steps
            .iter()
            .find_map(|s| match s {
                Step::Surface { point, normal, .. } => {
                    Some(vec(if q.quantity.name() == "normal" {
                        *normal
                    } else {
                        *point
                    }))
                }
                _ => None,
            })
            .unwrap_or(A::None),
        "refracted_direction" => steps
            .iter()
            .find_map(|s| match s {
                Step::Refract { direction, .. } => Some(direction.map_or(A::None, vec)),
                _ => None,
            })
            .unwrap_or(A::None),
        "total_internal_reflection" => steps
            .iter()
            .find_map(|s| match s {
                Step::Refract {
                    total_internal_reflection,
                    ..
                } => Some(A::Bool(*total_internal_reflection)),
                _ => None,
            })
            .unwrap_or(A::None),
        "color" => steps
            .iter()
            .rev()
            .find_map(|s| match s {
                Step::Color { color } => Some(vec(*color)),
                _ => None,
            })
            .unwrap_or(A::None),
        other => panic!("the test reads no {other}: add it"),
    }
}

/// Writes an answers file and runs `raystep check --json`; returns the parsed marks.
fn check(sheet: &Path, student: &str, answers: &str) -> Value {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("answers.txt");
    std::fs::write(&f, answers).unwrap();
    let out = raystep()
        .arg("check")
        .arg(sheet)
        .args(["--student", student, "--json", "--answers"])
        .arg(&f)
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    serde_json::from_slice(&out).expect("check --json prints JSON")
}

#[test]
fn at_least_three_sheets_ship_and_load() {
    let s = sheets();
    assert!(s.len() >= 3, "{s:?}");
    for p in &s {
        let sheet = lesson::load_sheet(p).unwrap_or_else(|e| panic!("{e}"));
        assert!(!sheet.questions.is_empty());
        for q in &sheet.questions {
            assert!(
                !q.hints.is_empty(),
                "{}: {} has no hints",
                p.display(),
                q.id
            );
        }
    }
}

#[test]
fn every_shipped_sheet_marks_answers_read_from_the_trace() {
    for path in sheets() {
        let sheet = lesson::load_sheet(&path).unwrap();
        for student in STUDENTS {
            let mut right = String::new();
            let mut wrong = String::new();
            for q in &sheet.questions {
                let a = read_quantity(&record(&sheet, q, student), q);
                right += &format!("{} = {}\n", q.id, a.text());
                wrong += &format!(
                    "{} = {}\n",
                    q.id,
                    a.perturbed(q.tolerance.abs, q.tolerance.rel)
                );
            }
            let marks = check(&path, student, &right);
            for m in marks["questions"].as_array().unwrap() {
                assert_eq!(
                    m["right"],
                    true,
                    "{} / {student}: {m}\nanswers:\n{right}",
                    path.display()
                );
            }
            assert_eq!(marks["score"], marks["out_of"]);
            let marks = check(&path, student, &wrong);
            for m in marks["questions"].as_array().unwrap() {
                assert_eq!(
                    m["right"],
                    false,
                    "{} / {student}: {m}\nanswers:\n{wrong}",
                    path.display()
                );
            }
            assert_eq!(marks["score"], 0.0);
        }
    }
}

#[test]
fn variants_differ_between_students_and_repeat_for_one() {
    for path in sheets() {
        let sheet = lesson::load_sheet(&path).unwrap();
        for q in &sheet.questions {
            let varied = !q.params.is_empty()
                || q.pixel
                    .iter()
                    .any(|c| matches!(c, lesson::Coord::Range(..)));
            let vs: Vec<_> = STUDENTS.iter().map(|s| sheet.variant(q, s)).collect();
            for (s, v) in STUDENTS.iter().zip(&vs) {
                assert_eq!(&sheet.variant(q, s), v, "{}: {}", path.display(), q.id);
            }
            if varied {
                assert!(
                    vs.iter().any(|v| v != &vs[0]),
                    "{}: {} is the same for every student",
                    path.display(),
                    q.id
                );
            }
        }
        // The command prints the same questions for the same id, different ones for another.
        let run = |s: &str| {
            raystep()
                .arg("exercise")
                .arg(&path)
                .args(["--student", s, "--json"])
                .assert()
                .success()
                .get_output()
                .stdout
                .clone()
        };
        assert_eq!(run("s1001"), run("s1001"));
        assert_ne!(run("s1001"), run("s1002"));
    }
}

#[test]
fn hints_are_revealed_one_at_a_time() {
    let path = root().join("lessons/exercises/02-sphere.toml");
    let json = |n: &str| -> Value {
        let out = raystep()
            .arg("exercise")
            .arg(&path)
            .args(["--student", "x", "--json", "--hints", n])
            .assert()
            .success()
            .get_output()
            .stdout
            .clone();
        serde_json::from_slice(&out).unwrap()
    };
    let sheet = lesson::load_sheet(&path).unwrap();
    for n in 0..3 {
        let doc = json(&n.to_string());
        for (q, j) in sheet
            .questions
            .iter()
            .zip(doc["questions"].as_array().unwrap())
        {
            let shown: Vec<&str> = j["hints"]
                .as_array()
                .unwrap()
                .iter()
                .map(|h| h.as_str().unwrap())
                .collect();
            let want: Vec<&str> = q.hints.iter().take(n).map(String::as_str).collect();
            assert_eq!(shown, want);
        }
    }
}

const HAND_SHEET: &str = r#"
title = "By hand"
[[question]]
id = "disc"
text = "Δ?"
scene_toml = """
[camera]
from = [0, 0, -5]
at = [0, 0, 0]
width = 1
height = 1
[render]
sphere_method = "textbook"
[[sphere]]
name = "ball"
"""
pixel = [0, 0]
quantity = "discriminant"
object = "ball"
tolerance = { abs = 1e-6, rel = 0 }
hints = ["b² − 4ac"]

[[question]]
id = "t"
text = "t?"
scene_toml = """
[camera]
from = [0, 0, -5]
at = [0, 0, 0]
width = 1
height = 1
[render]
sphere_method = "textbook"
[[sphere]]
name = "ball"
"""
pixel = [0, 0]
quantity = "closest_t"
tolerance = { abs = 1e-6, rel = 0 }
hints = ["(−b − √Δ)/2a"]
"#;

#[test]
fn the_discriminant_and_t_match_a_hand_computation() {
    // The eye at (0, 0, −5) looks at a unit sphere at the origin through the centre of a 1 × 1
    // image, so d = (0, 0, 1): a = d·d = 1, f = (0, 0, −5), b = 2 f·d = −10, c = f·f − 1 = 24,
    // Δ = b² − 4ac = 100 − 96 = 4, and the near root t = (10 − √4)/2 = 4.
    let dir = tempfile::tempdir().unwrap();
    let sheet_path = dir.path().join("hand.toml");
    std::fs::write(&sheet_path, HAND_SHEET).unwrap();
    let sheet = lesson::load_sheet(&sheet_path).unwrap();
    let expected: Vec<lesson::Answer> = sheet
        .questions
        .iter()
        .map(|q| sheet.expected(q, &sheet.variant(q, "anyone")).unwrap())
        .collect();
    assert_eq!(
        expected,
        vec![lesson::Answer::Number(4.0), lesson::Answer::Number(4.0)]
    );
    let marks = check(&sheet_path, "anyone", "disc = 4\nt = 4.0\n");
    assert_eq!(marks["score"], 2.0, "{marks}");
    let marks = check(&sheet_path, "anyone", "disc = 4.01\nt = 3.99\n");
    assert_eq!(marks["score"], 0.0, "{marks}");
    let q = &marks["questions"][0];
    assert!(
        (q["abs_error"].as_f64().unwrap() - 0.01).abs() < 1e-9,
        "{q}"
    );
    assert!(
        (q["rel_error"].as_f64().unwrap() - 0.0025).abs() < 1e-9,
        "{q}"
    );
}

#[test]
fn grading_a_class_with_malformed_rows() {
    let path = root().join("lessons/exercises/02-sphere.toml");
    let sheet = lesson::load_sheet(&path).unwrap();
    let ids: Vec<&str> = sheet.questions.iter().map(|q| q.id.as_str()).collect();
    let answers = |student: &str| -> Vec<String> {
        sheet
            .questions
            .iter()
            .map(|q| {
                read_quantity(&record(&sheet, q, student), q)
                    .text()
                    .replace('"', "")
            })
            .collect()
    };
    let n = ids.len();
    let out_of = sheet.questions.iter().map(|q| q.points).sum::<f64>();
    let mut csv = format!("student,{}\n", ids.join(","));
    let mut want = format!("student,{},score,out_of,notes\n", ids.join(","));
    // Row 2: all right.
    csv += &format!("ann,{}\n", answers("ann").join(","));
    want += &format!("ann,{},{n},{out_of},\n", vec!["1"; n].join(","));
    // Row 3: too few columns: the first two answers only.
    csv += &format!("ben,{}\n", answers("ben")[..2].join(","));
    want += &format!(
        "ben,1,1,{},2,{out_of},\"row 3: 3 columns, expected {}: columns 4–{} missing\"\n",
        vec!["0"; n - 2].join(","),
        n + 1,
        n + 1
    );
    // Row 4: a non-numeric first answer.
    let mut cal = answers("cal");
    cal[0] = "abc".into();
    csv += &format!("cal,{}\n", cal.join(","));
    want += &format!(
        "cal,0,{},{},{out_of},\"row 4, column 2 ({}): \"\"abc\"\" is not a number\"\n",
        vec!["1"; n - 1].join(","),
        n - 1,
        ids[0]
    );
    // Row 5: an empty second answer.
    let mut dee = answers("dee");
    dee[1] = String::new();
    csv += &format!("dee,{}\n", dee.join(","));
    want += &format!(
        "dee,1,0,{},{},{out_of},\"row 5, column 3 ({}): no answer\"\n",
        vec!["1"; n - 2].join(","),
        n - 1,
        ids[1]
    );
    let dir = tempfile::tempdir().unwrap();
    let class = dir.path().join("class.csv");
    let grades = dir.path().join("grades.csv");
    std::fs::write(&class, &csv).unwrap();
    let assert = raystep()
        .arg("grade")
        .arg(&path)
        .arg(&class)
        .arg("-o")
        .arg(&grades)
        .assert()
        .success();
    let err = String::from_utf8(assert.get_output().stderr.clone()).unwrap();
    assert!(err.contains("row 3: 3 columns"), "{err}");
    assert!(err.contains("row 4, column 2"), "{err}");
    assert_eq!(
        std::fs::read_to_string(&grades).unwrap(),
        want,
        "input:\n{csv}"
    );
}

/// Runs raystep, expects failure without a panic and every string of `expect` on stderr.
fn fails(args: &[&std::ffi::OsStr], expect: &[&str]) {
    let out = raystep().args(args).assert().failure().get_output().clone();
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(!err.contains("panicked"), "{err}");
    for e in expect {
        assert!(err.contains(e), "expected {e:?} in:\n{err}");
    }
}

#[test]
fn bad_input_exits_non_zero_with_a_located_message() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let write = |name: &str, text: &str| {
        let p = d.join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let ex = |p: &Path| {
        vec![
            "exercise".as_ref(),
            p.as_os_str().to_owned().leak() as &std::ffi::OsStr,
            "--student".as_ref(),
            "s".as_ref(),
        ]
    };
    // TOML syntax.
    let p = write("syntax.toml", "[[question]]\nid = \"a\"\ntext = \"oops\n");
    fails(&ex(&p), &["syntax.toml:3:"]);
    // A missing scene file, located at the `scene` key.
    let p = write(
        "missing.toml",
        "[[question]]\nid = \"a\"\ntext = \"t\"\nscene = \"nowhere.toml\"\npixel = [0, 0]\nquantity = \"closest_t\"\n",
    );
    fails(
        &ex(&p),
        &[
            "missing.toml:4:9",
            "question \"a\" → scene",
            "does not exist",
        ],
    );
    // An unknown quantity.
    let p = write(
        "quantity.toml",
        "[[question]]\nid = \"a\"\ntext = \"t\"\nscene = \"../x\"\npixel = [0, 0]\nquantity = \"colour\"\n",
    );
    fails(
        &ex(&p),
        &["quantity.toml:6:12", "quantity", "unknown variant `colour`"],
    );
    // A scene that does not load for the variant: the sheet, the question and the scene's error.
    let p = write(
        "scene.toml",
        "[[question]]\nid = \"a\"\ntext = \"t\"\nscene_toml = \"\"\"\n[[sphere]]\nradius = {r}\n\"\"\"\npixel = [0, 0]\nquantity = \"closest_t\"\nparams = { r = [-2, -1] }\n",
    );
    fails(
        &ex(&p),
        &["scene.toml:1: question \"a\" → scene_toml", "radius"],
    );
    // A pixel outside the image.
    let p = write(
        "pixel.toml",
        "[[question]]\nid = \"a\"\ntext = \"t\"\nscene_toml = \"\"\npixel = [400, 0]\nquantity = \"closest_t\"\n",
    );
    fails(&ex(&p), &["pixel 400,0 is outside the 320×240 image"]);
    // A question that needs an object.
    let p = write(
        "object.toml",
        "[[question]]\nid = \"a\"\ntext = \"t\"\nscene_toml = \"\"\npixel = [0, 0]\nquantity = \"discriminant\"\n",
    );
    fails(&ex(&p), &["object.toml:6:12", "needs `object"]);
    // A malformed class CSV names the row and column; so does an unknown question column.
    let sheet = root().join("lessons/exercises/02-sphere.toml");
    let out = d.join("g.csv");
    let csv = write("bad.csv", "student,disc\nann,1\nben,\"2\n");
    fails(
        &[
            "grade".as_ref(),
            sheet.as_os_str(),
            csv.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ],
        &["bad.csv: row 3, column 2", "never closed"],
    );
    let csv = write("cols.csv", "student,disc,bogus\n");
    fails(
        &[
            "grade".as_ref(),
            sheet.as_os_str(),
            csv.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ],
        &["cols.csv: row 1, column 3", "unknown question \"bogus\""],
    );
    assert!(!out.exists(), "no grades file on bad input");
    // An answers file with a line that isn't `id = value`.
    let ans = write("answers.txt", "disc = 1\nnear 2\n");
    fails(
        &[
            "check".as_ref(),
            sheet.as_os_str(),
            "--student".as_ref(),
            "s".as_ref(),
            "--answers".as_ref(),
            ans.as_os_str(),
        ],
        &["answers.txt:2:"],
    );
}
