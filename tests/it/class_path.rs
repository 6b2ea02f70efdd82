//! The student's and the teacher's path through raystep: the grader's feedback points at
//! commands that run, and camera mistakes are named on any camera.

use raystep::student::compare::{Stage, TracerTolerances, grade};
use raystep::student::expected::{Expected, expected};
use raystep::student::format::{parse, write};

use crate::common::scenes;
use scenes::root;

fn traced(scene: &str, x: u32, y: u32) -> Expected {
    let s = raystep::scene::load_file(&root().join(scene)).unwrap();
    expected(&raystep::PreparedScene::new(s).record(x, y, 0))
}

/// The camera stage's message when the student's primary ray at (x, y) is raystep's primary ray
/// of pixel `other`.
fn camera_message(scene: &str, (x, y): (u32, u32), other: (u32, u32)) -> String {
    let e = traced(scene, x, y);
    let mut mine = e.pixel.clone();
    mine.rays.truncate(1);
    mine.rays[0].direction = traced(scene, other.0, other.1).pixel.rays[0].direction;
    let checks = grade(
        &e,
        &parse(&write(&mine)).unwrap(),
        Stage::Camera,
        &TracerTolerances::default(),
    );
    assert!(!checks[0].pass, "{scene}");
    checks[0].message.clone()
}

/// A vertically flipped image is the ray of the row mirrored about the centre (y → H − 1 − y),
/// a horizontally flipped one the column's (x → W − 1 − x): built here from raystep's own rays
/// of those pixels. Both are named on a level camera (first-sphere) and on a camera that looks
/// down (three-spheres, the starter sheet's scene), where world y alone cannot tell.
#[test]
fn flipped_images_are_named_on_level_and_tilted_cameras() {
    for scene in ["scenes/first-sphere.toml", "scenes/three-spheres.toml"] {
        let s = raystep::scene::load_file(&root().join(scene)).unwrap();
        let (w, h) = (s.camera.width, s.camera.height);
        for (x, y) in [(40, 30), (250, 200), (10, 120)] {
            let m = camera_message(scene, (x, y), (x, h - 1 - y));
            assert!(m.contains("y is flipped"), "{scene} ({x}, {y}): {m}");
            let m = camera_message(scene, (x, y), (w - 1 - x, y));
            assert!(m.contains("x is flipped"), "{scene} ({x}, {y}): {m}");
            let m = camera_message(scene, (x, y), (w - 1 - x, h - 1 - y));
            assert!(m.contains("both flipped"), "{scene} ({x}, {y}): {m}");
        }
        // A ray of another pixel altogether is not called a flip.
        let m = camera_message(scene, (40, 30), (41, 30));
        assert!(!m.contains("flipped"), "{scene}: {m}");
    }
}

/// A class CSV exported from a learning platform: a Timestamp and an Email column first, the
/// header capitalised, semicolons between fields and decimal commas. Every right answer counts,
/// the extra columns are listed (not refused), and a wrong answer's reason is in the notes.
#[test]
fn a_learning_platforms_class_csv_is_read() {
    use raystep::lesson::{Answer, grade_answers_csv, load_exercise_sheet};
    let path = root().join("lessons/exercises/02-sphere.toml");
    let sheet = load_exercise_sheet(&path).unwrap();
    let answer = |q: &raystep::lesson::Question, who: &str| -> String {
        match sheet.expected(q, &sheet.variant(q, who)).unwrap() {
            // As a spreadsheet in much of Europe writes it.
            Answer::Number(x) => format!("{x}").replace('.', ","),
            a => a.to_string(),
        }
    };
    let mut text = String::from("Timestamp;Email;Student");
    for q in &sheet.questions {
        text += &format!(";{}", q.id.to_uppercase());
    }
    text += "\r\n";
    for who in ["ada", "bob"] {
        text += &format!("2026-11-26 10:00;{who}@example.org;{who}");
        for (k, q) in sheet.questions.iter().enumerate() {
            // Bob gets the first question wrong.
            let a = if who == "bob" && k == 0 {
                "12345".to_string()
            } else {
                answer(q, who)
            };
            text += &format!(";\"{a}\"");
        }
        text += "\r\n";
    }
    let report = grade_answers_csv(&sheet, &text, "export.csv").unwrap();
    assert_eq!(report.students, 2);
    let rows: Vec<&str> = report.csv.lines().collect();
    let out_of = report.out_of;
    let first = sheet.questions[0].points;
    assert!(rows[1].starts_with("ada,"), "{}", report.csv);
    assert!(
        rows[1].contains(&format!(",{out_of},{out_of},")),
        "ada has every answer right: {}",
        report.csv
    );
    assert!(
        rows[2].contains(&format!(",{},{out_of},", out_of - first)),
        "{}",
        report.csv
    );
    let id = &sheet.questions[0].id;
    assert!(
        rows[2].ends_with(&format!("{id}: not within the tolerance"))
            || rows[2].contains(&format!("{id}: ")),
        "bob's note says why {id} is wrong: {}",
        rows[2]
    );
    assert!(!rows[2].contains("12345"), "{}", rows[2]);
    let w = report.warnings.join("\n");
    assert!(
        w.contains("\"Timestamp\" (column 1)") && w.contains("\"Email\" (column 2)"),
        "{w}"
    );
    // No student column at all: the message says so and lists the header.
    let e = grade_answers_csv(&sheet, "Name;Disc\nann;1\n", "x.csv").unwrap_err();
    assert!(
        e.contains("no column holds the student's id") && e.contains("\"Name\""),
        "{e}"
    );
}

/// A sheet can hide the `raystep trace` command (which prints the answer) for a graded quiz,
/// and a wrong answer where the tracer computes nothing is not told "the answer is none".
#[test]
fn answers_do_not_leak() {
    use raystep::lesson::{Answer, AnswerKind, DEFAULT_TOLERANCE, mark};
    let dir = tempfile::tempdir().unwrap();
    let sheet = root().join("lessons/exercises/02-sphere.toml");
    let text = std::fs::read_to_string(&sheet).unwrap();
    let quiz = dir.path().join("quiz.toml");
    // Scenes named relative to the sheet stay found: the quiz sits beside it in the test's copy.
    let text = text.replace(
        "\"../../scenes/",
        &format!("\"{}/", root().join("scenes").display()),
    );
    std::fs::write(&quiz, format!("trace_command = false\n{text}")).unwrap();
    let run = |p: &std::path::Path| {
        let out = assert_cmd::Command::cargo_bin("raystep")
            .unwrap()
            .args(["exercise", &p.display().to_string(), "--student", "ada"])
            .assert()
            .success()
            .get_output()
            .clone();
        String::from_utf8(out.stdout).unwrap()
    };
    let open = run(&sheet);
    assert!(open.contains("trace it: raystep trace"), "{open}");
    let closed = run(&quiz);
    assert!(!closed.contains("raystep trace"), "{closed}");
    assert!(closed.contains("pixel"), "{closed}");
    let m = mark(
        &Answer::None,
        AnswerKind::Name,
        Some("tri"),
        DEFAULT_TOLERANCE,
    );
    assert!(!m.right);
    let note = m.note.unwrap();
    assert!(!note.contains("none"), "{note}");
}

/// A misnamed object and a stray debugging print are named as what they are.
#[test]
fn misnamed_objects_and_debug_prints_are_named() {
    use raystep::student::expected::with_names;
    let scene = raystep::scene::load_file(&root().join("scenes/first-sphere.toml")).unwrap();
    let e = with_names(
        expected(&raystep::PreparedScene::new(scene.clone()).record(160, 120, 0)),
        &scene,
    );
    let name = &e.pixel.rays[0].tests[0];
    let real = name.object().to_string();
    let text = write(&e.pixel).replace(&format!("\"{real}\""), "\"sphere\"");
    let checks = grade(
        &e,
        &parse(&text).unwrap(),
        Stage::Sphere,
        &TracerTolerances::default(),
    );
    let msg = &checks[1].message;
    assert!(
        !checks[1].pass && msg.contains("names \"sphere\", which is not an object of this scene"),
        "{msg}"
    );
    let err = parse("debug: here\n{\"type\":\"pixel\"}\n").unwrap_err();
    assert!(
        err.to_string()
            .contains("print debugging output to standard error"),
        "{err}"
    );
}

/// A built-in sheet's questions name their built-in scene by its name in the command beside them
/// (`raystep trace three-spheres …`), which works from any folder — not by the path of the
/// unpacked copy in the user's cache.
#[test]
fn a_builtin_sheet_names_its_scene_by_name() {
    let out = assert_cmd::Command::cargo_bin("raystep")
        .unwrap()
        .args(["exercise", "02-sphere", "--student", "s1001"])
        .assert()
        .success()
        .get_output()
        .clone();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("trace it: raystep trace three-spheres --pixel "),
        "{text}"
    );
    assert!(!text.contains("builtin-"), "{text}");
}

/// The grades file's notes tell each wrong answer what `check` would: the reason and what the
/// sheet's feedback policy adds ("too high" under `feedback = "direction"`), never the answer.
#[test]
fn grade_notes_follow_the_feedback_policy() {
    use raystep::lesson::{grade_answers_csv, parse_exercise_sheet};
    let scene = root().join("scenes/three-spheres.toml");
    let sheet = |feedback: &str| {
        let text = format!(
            "title = \"q\"\nfeedback = \"{feedback}\"\n[[question]]\nid = \"t\"\ntext = \"t?\"\n\
             scene = {scene:?}\npixel = [160, 120]\nquantity = \"closest_t\"\n",
            scene = scene.display().to_string()
        );
        parse_exercise_sheet(&text, "quiz.toml", None, "quiz").unwrap()
    };
    // Pixel (160, 120) hits "middle" at t = 4.6522236 (`raystep trace three-spheres --pixel
    // 160,120`, step [4]): 4.9 is too high, 4.1 too low.
    let csv = "student,t\nhigh,4.9\nlow,4.1\n";
    let direction = grade_answers_csv(&sheet("direction"), csv, "class.csv")
        .unwrap()
        .csv;
    let rows: Vec<&str> = direction.lines().collect();
    assert!(rows[1].ends_with("; too high"), "{direction}");
    assert!(rows[2].ends_with("; too low"), "{direction}");
    assert!(!direction.contains("4.652"), "{direction}");
    let plain = grade_answers_csv(&sheet("right_wrong"), csv, "class.csv")
        .unwrap()
        .csv;
    assert!(!plain.contains("too "), "{plain}");
    assert!(plain.contains("t: not within the tolerance"), "{plain}");
}
