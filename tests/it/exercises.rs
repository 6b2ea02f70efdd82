//! Exercise sheets (`raystep exercise`, `check`, `grade`): every shipped sheet is marked against
//! answers read straight out of a recorded trace's timeline (not through raystep's own
//! extraction), perturbed answers fail, variants differ between students and repeat for one, a
//! quantity is checked against a hand computation, a class is graded with malformed rows, and bad
//! input exits non-zero with a located message.

use assert_cmd::Command;
use raystep::lesson::{self, ExerciseSheet, Question, SceneSource};
use raystep::record::{RayKind, Step, Trace};
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
fn record(sheet: &ExerciseSheet, q: &Question, student: &str) -> Trace {
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
        "Diffuse" => RayKind::Diffuse,
        "Glossy" => RayKind::Glossy,
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
        "light_pdf" | "mis_weight" => steps
            .iter()
            .find_map(|s| match s {
                Step::LightSample {
                    pdf, mis_weight, ..
                } => Some(A::Num(if q.quantity.name() == "light_pdf" {
                    *pdf as f64
                } else {
                    *mis_weight as f64
                })),
                _ => None,
            })
            .unwrap_or(A::None),
        "light_contribution" => steps
            .iter()
            .find_map(|s| match s {
                Step::LightSample { contribution, .. } => Some(vec(*contribution)),
                _ => None,
            })
            .unwrap_or(A::None),
        "bsdf_pdf" | "throughput" | "sample_direction" => steps
            .iter()
            .find_map(|s| match s {
                Step::BsdfSample {
                    pdf,
                    throughput,
                    direction,
                    ..
                } => Some(match q.quantity.name() {
                    "bsdf_pdf" => num(*pdf),
                    "throughput" => vec(*throughput),
                    _ => vec(*direction),
                }),
                _ => None,
            })
            .unwrap_or(A::None),
        "roulette_probability" => steps
            .iter()
            .find_map(|s| match s {
                Step::RussianRoulette { probability, .. } => Some(A::Num(*probability as f64)),
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
        let sheet = lesson::load_exercise_sheet(p).unwrap_or_else(|e| panic!("{e}"));
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
        let sheet = lesson::load_exercise_sheet(&path).unwrap();
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
        let sheet = lesson::load_exercise_sheet(&path).unwrap();
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
    let sheet = lesson::load_exercise_sheet(&path).unwrap();
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
feedback = "distance"
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
    let sheet = lesson::load_exercise_sheet(&sheet_path).unwrap();
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
    let sheet = lesson::load_exercise_sheet(&path).unwrap();
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
    // The notes: the short row, then why each wrong answer is wrong (here: none given).
    want += &format!(
        "ben,1,1,{},2,{out_of},\"row 3: 3 columns, expected {}: columns 4–{} missing; {}\"\n",
        vec!["0"; n - 2].join(","),
        n + 1,
        n + 1,
        ids[2..]
            .iter()
            .map(|id| format!("{id}: no answer"))
            .collect::<Vec<_>>()
            .join("; ")
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
    // A scene that does not load (checked when the sheet is loaded): the sheet, the question's
    // header and the scene's error.
    let p = write(
        "scene.toml",
        "[[question]]\nid = \"a\"\ntext = \"t\"\nscene_toml = \"\"\"\n[[sphere]]\nradius = {r}\n\"\"\"\npixel = [0, 0]\nquantity = \"closest_t\"\nparams = { r = [-2, -1] }\n",
    );
    fails(
        &ex(&p),
        &["scene.toml:1:1: question \"a\" → scene_toml", "radius"],
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
    // A malformed class CSV names the row and column.
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
    // (A column that is no question is ignored and listed: tests/it/class_path.rs.) A header with
    // no student column is an error naming the header.
    let csv = write("cols.csv", "name,disc\n");
    fails(
        &[
            "grade".as_ref(),
            sheet.as_os_str(),
            csv.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ],
        &[
            "cols.csv: row 1: no column holds the student's id",
            "\"name\", \"disc\"",
        ],
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

/// A number as a sheet would write it: integers without a decimal point.
fn fmt_num(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{}", x as i64)
    } else {
        format!("{x}")
    }
}

fn toml_num(v: &toml::Value) -> Option<f64> {
    v.as_float().or_else(|| v.as_integer().map(|i| i as f64))
}

fn toml_vec(v: &toml::Value) -> Option<Vec<f64>> {
    v.as_array()?.iter().map(toml_num).collect()
}

/// The text as the checks read it: Unicode minus signs as `-`, no whitespace, lower case.
fn squash(s: &str) -> String {
    s.replace('−', "-")
        .chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_lowercase)
        .collect()
}

/// Whether `text` (squashed) has the number `x` as a whole token (not part of a longer number).
fn has_number(text: &str, x: f64) -> bool {
    let n = fmt_num(x);
    let bytes = text.as_bytes();
    text.match_indices(&n).any(|(i, _)| {
        let before = i.checked_sub(1).map(|j| bytes[j]);
        let after = bytes.get(i + n.len()).copied();
        let after2 = bytes.get(i + n.len() + 1).copied();
        let digit = |c: Option<u8>| c.is_some_and(|c| c.is_ascii_digit());
        // "-5" must not match inside "-0.5" (a leading minus is part of `n` when negative), nor
        // "2" inside "2.5"; a full stop ending the sentence is fine.
        let glued_before =
            digit(before) || before == Some(b'.') || (x >= 0.0 && before == Some(b'-'));
        let glued_after = digit(after) || (after == Some(b'.') && digit(after2));
        !glued_before && !glued_after
    })
}

/// Whether `text` (squashed) writes the vector `v` as `(a,b,c)` or `[a,b,c]`.
fn has_vector(text: &str, v: &[f64]) -> bool {
    let inner: Vec<String> = v.iter().map(|x| fmt_num(*x)).collect();
    let inner = inner.join(",");
    text.contains(&format!("({inner})")) || text.contains(&format!("[{inner}]"))
}

/// The shipped scene file the text names (`three-spheres.toml`), parsed: a parameter equal to
/// that file's counts as stated (the student can read it there).
fn named_scene(text: &str) -> Option<toml::Table> {
    let dir = root().join("scenes");
    let mut names: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    names.sort();
    let p = names
        .into_iter()
        .find(|p| text.contains(&*p.file_name().unwrap().to_string_lossy()))?;
    Some(toml::from_str(&std::fs::read_to_string(p).unwrap()).unwrap())
}

/// The value of `key` in the table of `kind` (`camera`, or the `[[kind]]` named `name`) of a
/// named shipped scene.
fn in_named(
    named: Option<&toml::Table>,
    kind: &str,
    name: Option<&str>,
    key: &str,
) -> Option<toml::Value> {
    let named = named?;
    if kind == "camera" {
        return named.get("camera")?.get(key).cloned();
    }
    named
        .get(kind)?
        .as_array()?
        .iter()
        .find(|o| o.get("name").and_then(|n| n.as_str()) == name)?
        .get(key)
        .cloned()
}

/// The scene parameters a question's text must state (those that differ from the scene format's
/// documented defaults, for the camera and the objects the question relies on), each checked in
/// the variant's text — or in the shipped scene file the text names, when the value is that
/// file's. Returns what is missing.
fn unstated(q: &Question, text: &str, scene_toml: &str) -> Vec<String> {
    let t = squash(text);
    let named = named_scene(text);
    let named = named.as_ref();
    let same = |kind: &str, name: Option<&str>, key: &str, v: &toml::Value| {
        in_named(named, kind, name, key).is_some_and(|n| {
            n == *v
                || (toml_vec(&n).is_some() && toml_vec(&n) == toml_vec(v))
                || (toml_num(&n).is_some() && toml_num(&n) == toml_num(v))
        })
    };
    let mut missing = vec![];
    let scene: toml::Table = toml::from_str(scene_toml).expect("the variant's scene is TOML");
    // The camera (defaults from README "The scene format").
    let cam = scene.get("camera").and_then(|c| c.as_table());
    let get = |k: &str| cam.and_then(|c| c.get(k));
    for (k, default) in [
        ("from", [0.0, 0.0, -5.0]),
        ("at", [0.0, 0.0, 0.0]),
        ("up", [0.0, 1.0, 0.0]),
    ] {
        if let Some(raw) = get(k)
            && let Some(v) = toml_vec(raw)
            && v != default
            && !has_vector(&t, &v)
            && !same("camera", None, k, raw)
        {
            missing.push(format!("camera.{k} = {v:?}"));
        }
    }
    if let Some(fov) = get("fov").and_then(toml_num)
        && fov != 60.0
        && !same("camera", None, "fov", get("fov").unwrap())
    {
        let n = fmt_num(fov);
        let said = [
            format!("{n}°"),
            format!("fov{n}"),
            format!("fov={n}"),
            format!("fovof{n}"),
            format!("fieldofview{n}"),
            format!("fieldofviewof{n}"),
            format!("fieldofviewis{n}"),
        ];
        if !said.iter().any(|s| t.contains(s)) {
            missing.push(format!("camera.fov = {n}"));
        }
    }
    let w = get("width").and_then(toml_num).unwrap_or(320.0);
    let h = get("height").and_then(toml_num).unwrap_or(240.0);
    let named_size = get("width").is_none_or(|v| same("camera", None, "width", v))
        && get("height").is_none_or(|v| same("camera", None, "height", v))
        && named.is_some();
    if (w, h) != (320.0, 240.0) && !named_size {
        let (w, h) = (fmt_num(w), fmt_num(h));
        if ![format!("{w}×{h}"), format!("{w}x{h}")]
            .iter()
            .any(|s| t.contains(s))
        {
            missing.push(format!("camera width × height = {w} × {h}"));
        }
    }
    // The objects: the one named by `object`, else every object (which one is hit, where, and
    // what blocks a shadow ray depend on all of them).
    let relied = |name: Option<&str>| match (&q.object, name) {
        (Some(o), Some(n)) => o == n,
        (Some(_), None) => false,
        (None, _) => true,
    };
    let tables = |key: &str| -> Vec<toml::Table> {
        scene
            .get(key)
            .and_then(|v| v.as_array())
            .map(|a| a.iter().filter_map(|t| t.as_table().cloned()).collect())
            .unwrap_or_default()
    };
    for s in tables("sphere") {
        let name = s.get("name").and_then(|n| n.as_str());
        if !relied(name) {
            continue;
        }
        let label = name.unwrap_or("sphere");
        if let Some(c) = s.get("center").and_then(toml_vec)
            && c != [0.0, 0.0, 0.0]
            && !has_vector(&t, &c)
            && !same("sphere", name, "center", &s["center"])
        {
            missing.push(format!("{label}.center = {c:?}"));
        }
        if let Some(r) = s.get("radius").and_then(toml_num)
            && r != 1.0
            && !has_number(&t, r)
            && !same("sphere", name, "radius", &s["radius"])
        {
            missing.push(format!("{label}.radius = {r}"));
        }
    }
    for p in tables("plane") {
        let name = p.get("name").and_then(|n| n.as_str());
        if !relied(name) {
            continue;
        }
        let label = name.unwrap_or("plane");
        if let Some(axis) = p.get("axis").and_then(|a| a.as_str()) {
            let off = p.get("offset").and_then(toml_num).unwrap_or(0.0);
            let stated = p
                .get("offset")
                .is_some_and(|o| same("plane", name, "offset", o));
            if !t.contains(&format!("{axis}={}", fmt_num(off))) && !stated {
                missing.push(format!("{label}: the plane {axis} = {}", fmt_num(off)));
            }
        } else {
            for (k, default) in [("point", [0.0, 0.0, 0.0]), ("normal", [0.0, 1.0, 0.0])] {
                if let Some(v) = p.get(k).and_then(toml_vec)
                    && v != default
                    && !has_vector(&t, &v)
                {
                    missing.push(format!("{label}.{k} = {v:?}"));
                }
            }
        }
    }
    for tri in tables("triangle") {
        let name = tri.get("name").and_then(|n| n.as_str());
        if !relied(name) {
            continue;
        }
        let label = name.unwrap_or("triangle");
        if let Some(vs) = tri.get("vertices").and_then(|v| v.as_array()) {
            for v in vs.iter().filter_map(toml_vec) {
                if !has_vector(&t, &v) {
                    missing.push(format!("{label}: vertex {v:?}"));
                }
            }
        }
    }
    if q.quantity == lesson::Quantity::ShadowBlocked {
        let lights = tables("light");
        if let Some(l) = lights.get(q.light as usize)
            && let Some(p) = l.get("position").and_then(toml_vec)
            && !has_vector(&t, &p)
            && !named
                .and_then(|n| {
                    n.get("light")?
                        .as_array()?
                        .get(q.light as usize)?
                        .get("position")
                })
                .is_some_and(|np| toml_vec(np).as_deref() == Some(&p[..]))
        {
            missing.push(format!("light {}: position {p:?}", q.light));
        }
    }
    if matches!(
        q.quantity,
        lesson::Quantity::RefractedDirection | lesson::Quantity::TotalInternalReflection
    ) {
        for m in tables("material") {
            if let Some(n) = m.get("refractive_index").and_then(toml_num)
                && n != 1.0
                && !has_number(&t, n)
            {
                missing.push(format!("refractive_index = {n}"));
            }
        }
    }
    missing
}

#[test]
fn every_question_states_what_differs_from_the_defaults() {
    let mut problems = vec![];
    for path in sheets() {
        let sheet = lesson::load_exercise_sheet(&path).unwrap();
        for q in &sheet.questions {
            for student in STUDENTS {
                let v = sheet.variant(q, student);
                let missing = match (&q.scene, &v.scene_toml) {
                    (SceneSource::Inline(_), Some(scene)) => unstated(q, &v.text, scene),
                    // A shipped scene file: the text must name it (the file states the rest).
                    (SceneSource::File(p), _) => {
                        let name = p.file_name().unwrap().to_string_lossy().into_owned();
                        if v.text.contains(&name) {
                            vec![]
                        } else {
                            vec![format!("the scene file's name {name}")]
                        }
                    }
                    (SceneSource::Inline(_), None) => unreachable!("inline scenes are filled"),
                };
                if !missing.is_empty() {
                    problems.push(format!(
                        "{} question \"{}\" (student {student}): the text does not state {}",
                        path.file_name().unwrap().to_string_lossy(),
                        q.id,
                        missing.join("; ")
                    ));
                    break;
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_checker_finds_an_unstated_field_of_view() {
    // The check itself, on the case that was wrong: fov 45 not in the text.
    let sheet = lesson::parse_exercise_sheet(
        "[[question]]\nid = \"q\"\ntext = \"Camera at (0, 0, -5), 64 × 48 pixels, ball of radius 2.\"\n\
         scene_toml = \"\"\"\n[camera]\nfov = 45\nwidth = 64\nheight = 48\n[[sphere]]\nname = \"ball\"\nradius = 2\n\"\"\"\n\
         pixel = [1, 1]\nquantity = \"discriminant\"\nobject = \"ball\"\n",
        "t.toml",
        None,
        "t",
    )
    .unwrap();
    let q = &sheet.questions[0];
    let v = sheet.variant(q, "s");
    let missing = unstated(q, &v.text, v.scene_toml.as_ref().unwrap());
    assert_eq!(missing, ["camera.fov = 45"]);
    let fixed = v.text.replace("Camera", "Camera (field of view 45°)");
    assert!(unstated(q, &fixed, v.scene_toml.as_ref().unwrap()).is_empty());
}

/// A one-question sheet over a small inline scene with `extra` lines in the question.
fn small_sheet(head: &str, extra: &str) -> String {
    format!(
        "{head}[[question]]\nid = \"q\"\ntext = \"Camera at (0, 0, -5).\"\n\
         scene_toml = \"\"\"\n[[light]]\nname = \"key\"\nposition = [0, 5, -5]\n\
         [[sphere]]\nname = \"ball\"\n\"\"\"\npixel = [160, 120]\n{extra}\n"
    )
}

#[test]
fn a_sheet_naming_an_object_or_light_its_scene_lacks_is_refused_with_its_place() {
    // The object: line 13, column 10 is where "bal" starts (after `object = `).
    let text = small_sheet("", "quantity = \"discriminant\"\nobject = \"bal\"");
    let e = lesson::parse_exercise_sheet(&text, "s.toml", None, "s").unwrap_err();
    let msg = e.to_string();
    assert_eq!((e.line, e.column), (Some(13), Some(10)), "{msg}");
    assert!(
        msg.contains("object") && msg.contains("\"bal\"") && msg.contains("ball"),
        "{msg}"
    );
    // The light: the scene has one light (index 0), the question asks for light 1.
    let text = small_sheet("", "quantity = \"shadow_blocked\"\nlight = 1");
    let e = lesson::parse_exercise_sheet(&text, "s.toml", None, "s").unwrap_err();
    let msg = e.to_string();
    assert_eq!((e.line, e.column), (Some(13), Some(9)), "{msg}");
    assert!(msg.contains("1 light") && msg.contains("light 1"), "{msg}");
    // The same sheet with names the scene has loads.
    let ok = small_sheet("", "quantity = \"discriminant\"\nobject = \"ball\"");
    assert!(lesson::parse_exercise_sheet(&ok, "s.toml", None, "s").is_ok());
}

#[test]
fn error_columns_count_characters_not_bytes() {
    // Multi-byte characters (Δ, –) before the error: the column counts characters. Where the
    // error is comes from the TOML parser itself (a byte offset); the column is converted.
    let char_col = |text: &str| {
        let at = toml::from_str::<toml::Table>(text)
            .unwrap_err()
            .span()
            .expect("a located TOML error")
            .start;
        (at + 1, text[..at].chars().count() + 1)
    };
    let text = "title = \"Δ–Δ\"; x = 7\n";
    let (byte_col, want) = char_col(text);
    assert_ne!(
        byte_col, want,
        "the test needs multi-byte characters before the error"
    );
    let e = lesson::parse_exercise_sheet(text, "s.toml", None, "s").unwrap_err();
    assert_eq!((e.line, e.column), (Some(1), Some(want)), "{e}");
    // A lesson's front matter (its line 1 is the file's line 2).
    let fm = "title = \"Δ–Δ\"; scene = 3\n";
    let (_, want) = char_col(fm);
    let l = format!("+++\n{fm}+++\n");
    let e = lesson::parse_lesson(&l, Path::new("l.md")).unwrap_err();
    assert!(e.starts_with(&format!("l.md:2:{want}:")), "{e}");
}

#[test]
fn feedback_is_the_sheets_choice_and_defaults_to_right_or_wrong() {
    let parse = |head: &str| {
        lesson::parse_exercise_sheet(
            &small_sheet(head, "quantity = \"closest_t\""),
            "s.toml",
            None,
            "s",
        )
    };
    assert_eq!(parse("").unwrap().feedback, lesson::Feedback::RightWrong);
    assert_eq!(
        parse("feedback = \"direction\"\n").unwrap().feedback,
        lesson::Feedback::Direction
    );
    assert_eq!(
        parse("feedback = \"distance\"\n").unwrap().feedback,
        lesson::Feedback::Distance
    );
    assert_eq!(
        parse("feedback = { show_after = 3 }\n").unwrap().feedback,
        lesson::Feedback::ShowAfter(3)
    );
    let e = parse("feedback = \"loud\"\n").unwrap_err();
    assert_eq!((e.line, e.column), (Some(1), Some(12)), "{e}");
    assert!(parse("feedback = { show_after = 0 }\n").is_err());
    // Every shipped sheet keeps the default or says which policy it uses.
    for path in sheets() {
        lesson::load_exercise_sheet(&path).unwrap();
    }
}

#[test]
fn check_uses_the_sheets_feedback_and_a_byte_order_mark_is_fine() {
    let dir = tempfile::tempdir().unwrap();
    let sheet_path = dir.path().join("hand.toml");
    // The hand sheet with the default feedback: right or wrong and why, no distance.
    std::fs::write(
        &sheet_path,
        HAND_SHEET.replace("feedback = \"distance\"\n", ""),
    )
    .unwrap();
    let answers = dir.path().join("a.txt");
    std::fs::write(&answers, "\u{feff}disc = 5\nt = none\n").unwrap();
    let out = raystep()
        .args(["check".as_ref(), sheet_path.as_os_str()])
        .args(["--student", "x", "--answers"])
        .arg(&answers)
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let out = String::from_utf8(out).unwrap();
    // Δ = 4, the answer 5: wrong, not within the tolerance — and nothing that gives 4 away.
    let disc = out.lines().find(|l| l.starts_with("disc")).unwrap();
    assert!(
        disc.contains("wrong") && disc.contains("tolerance"),
        "{out}"
    );
    assert!(!disc.contains("off by"), "{out}");
    let t = out.lines().find(|l| l.starts_with("t ")).unwrap();
    assert!(t.contains("wrong") && t.contains("not none"), "{out}");
}

#[test]
fn a_student_on_two_rows_is_an_error() {
    let path = root().join("lessons/exercises/02-sphere.toml");
    let sheet = lesson::load_exercise_sheet(&path).unwrap();
    let csv = "student,disc\nann,1\nben,2\n ann ,3\n";
    let e = lesson::grade_answers_csv(&sheet, csv, "class.csv").unwrap_err();
    assert!(e.starts_with("class.csv: row 4, column 1:"), "{e}");
    assert!(e.contains("\"ann\"") && e.contains("row 2"), "{e}");
}

/// `raystep exercise 02-sphere` takes a built-in sheet by name, from any folder, as scenes are
/// taken by name; `check` and `grade` too. A name that is no sheet lists the names.
#[test]
fn a_built_in_sheet_is_taken_by_name_from_any_folder() {
    let dir = tempfile::tempdir().unwrap();
    let json = |sheet: &str, cwd: &Path| -> Value {
        let out = raystep()
            .current_dir(cwd)
            .args(["exercise", sheet, "--student", "s1001", "--json"])
            .assert()
            .success()
            .get_output()
            .stdout
            .clone();
        serde_json::from_slice(&out).unwrap()
    };
    let by_file = json("lessons/exercises/02-sphere.toml", &root());
    for name in ["02-sphere", "02-sphere.toml", "exercises/02-sphere.toml"] {
        let by_name = json(name, dir.path());
        assert_eq!(by_name["title"], by_file["title"], "{name}");
        let texts = |v: &Value| -> Vec<Value> {
            v["questions"]
                .as_array()
                .unwrap()
                .iter()
                .map(|q| q["text"].clone())
                .collect()
        };
        assert_eq!(texts(&by_name), texts(&by_file), "{name}");
    }
    let answers = dir.path().join("answers.txt");
    std::fs::write(&answers, "disc = 1\n").unwrap();
    raystep()
        .current_dir(dir.path())
        .args(["check", "02-sphere", "--student", "s1001", "--answers"])
        .arg(&answers)
        .assert()
        .success();
    let class = dir.path().join("class.csv");
    std::fs::write(&class, "student,disc\ns1001,1\n").unwrap();
    raystep()
        .current_dir(dir.path())
        .args(["grade", "02-sphere"])
        .arg(&class)
        .args(["-o", "grades.csv"])
        .assert()
        .success();
    assert!(dir.path().join("grades.csv").is_file());
    fails(
        &[
            "exercise".as_ref(),
            "02-spheres".as_ref(),
            "--student".as_ref(),
            "s".as_ref(),
        ],
        &["02-spheres", "built-in sheets: 01-camera, 02-sphere"],
    );
}

/// `--solutions` writes each number with the digits `raystep trace` prints for it (5.573929,
/// not the f64 widening 5.5739288330078125): each numeric solution appears, as written, in the
/// trace of its question's pixel.
#[test]
fn solutions_are_written_as_the_trace_writes_them() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    let mut numbers = 0;
    for sheet in ["02-sphere", "04-triangle", "09-refraction"] {
        let path = format!("lessons/exercises/{sheet}.toml");
        let out = raystep()
            .args([
                "exercise",
                &path,
                "--student",
                "s1001",
                "--solutions",
                "--json",
            ])
            .arg("--scenes")
            .arg(&scenes)
            .assert()
            .success()
            .get_output()
            .stdout
            .clone();
        let v: Value = serde_json::from_slice(&out).unwrap();
        for q in v["questions"].as_array().unwrap() {
            let solution = q["solution"].as_str().unwrap();
            let parts: Vec<&str> = solution.split(", ").collect();
            if !parts.iter().all(|p| p.parse::<f64>().is_ok()) {
                continue; // a name, yes/no or none
            }
            let scene = q["scene"].as_str().expect("a scene to trace");
            let pixel = format!("{},{}", q["pixel"][0], q["pixel"][1]);
            let trace = raystep()
                .args(["trace", scene, "--pixel", &pixel])
                .assert()
                .success()
                .get_output()
                .stdout
                .clone();
            let trace = String::from_utf8(trace).unwrap();
            for p in parts {
                // Not a prefix of a longer number: "4.5" must not match "4.55".
                let found = trace.match_indices(p).any(|(k, _)| {
                    let next = trace[k + p.len()..].chars().next();
                    let prev = trace[..k].chars().last();
                    !next.is_some_and(|c| c.is_ascii_digit() || c == '.' || c == 'e')
                        && !prev.is_some_and(|c| c.is_ascii_digit() || c == '.')
                });
                assert!(
                    found,
                    "{sheet} {}: the solution's {p} is not in the trace of {scene} {pixel}:\n{trace}",
                    q["id"]
                );
                numbers += 1;
            }
        }
    }
    assert!(
        numbers >= 10,
        "only {numbers} numeric solutions were compared"
    );
}
