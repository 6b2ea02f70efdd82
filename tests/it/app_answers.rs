//! The exercise panel's answers: kept between runs (the preferences; in the browser, the page's
//! storage) and exported as a class CSV that `raystep grade` marks. The expected marks come from
//! the tracer's own solutions (`raystep exercise --solutions`), read from outside the app.

use assert_cmd::Command as Cmd;
use raystep::app::learn::LearnCmd;
use raystep::app::state::{AppState, Command, Prefs};
use std::path::Path;

const SHEET: &str = "lessons/exercises/02-sphere.toml";

/// The tracer's answer to question `id` for `student`, as `raystep exercise --solutions` prints.
fn solution(student: &str, n: usize) -> String {
    let out = Cmd::cargo_bin("raystep")
        .unwrap()
        .args(["exercise", SHEET, "--student", student, "--solutions"])
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    text.lines()
        .filter_map(|l| l.trim().strip_prefix("answer: "))
        .nth(n)
        .unwrap_or_else(|| panic!("no answer {n} in:\n{text}"))
        .to_string()
}

fn open(prefs: Prefs, student: &str) -> AppState {
    let mut s = AppState::new(prefs, || {});
    s.apply(Command::Learn(LearnCmd::OpenSheet(Path::new(SHEET).into())));
    s.apply(Command::Learn(LearnCmd::Student(student.into())));
    s
}

#[test]
fn exported_answers_are_marked_by_raystep_grade_and_kept_between_runs() {
    let right = solution("s1", 0);
    let mut s = open(Prefs::default(), "s1");
    s.apply(Command::Learn(LearnCmd::Answer(right.clone())));
    s.apply(Command::Learn(LearnCmd::Question(1)));
    s.apply(Command::Learn(LearnCmd::Answer("1000".into())));

    // Kept: a new session (the preferences saved and read back) finds both answers again.
    let saved = s.prefs.clone();
    let again = open(saved.clone(), "s1");
    assert_eq!(again.learn.attempts[0].answer, right);
    assert_eq!(again.learn.attempts[1].answer, "1000");
    // …for this student only.
    let other = open(saved, "s2");
    assert!(other.learn.attempts.iter().all(|a| a.answer.is_empty()));

    // Exported: one row that `raystep grade` reads, marking the first right and the second wrong.
    let csv = s.answers_csv().unwrap();
    assert!(csv.starts_with("student,disc,near,"), "{csv}");
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("answers.csv");
    std::fs::write(&file, &csv).unwrap();
    let grades = dir.path().join("grades.csv");
    Cmd::cargo_bin("raystep")
        .unwrap()
        .args(["grade", SHEET])
        .arg(&file)
        .arg("-o")
        .arg(&grades)
        .assert()
        .success();
    let g = std::fs::read_to_string(&grades).unwrap();
    let rows: Vec<Vec<&str>> = g.lines().map(|l| l.split(',').collect()).collect();
    let col = |name: &str| rows[0].iter().position(|h| *h == name).unwrap();
    assert_eq!(rows[1][col("student")], "s1");
    assert_eq!(rows[1][col("disc")], "1", "{g}");
    assert_eq!(rows[1][col("near")], "0", "{g}");
    assert_eq!(rows[1][col("score")], "1", "{g}");
}

#[test]
fn answers_are_not_exported_without_a_student_id() {
    let s = open(Prefs::default(), "  ");
    let e = s.answers_csv().unwrap_err();
    assert!(e.contains("student id"), "{e}");
}

/// A wrong answer that is a classic mistake is named in the app, as `raystep check` names it:
/// on sheet 16's MIS question (whose pixels are drawn where the power heuristic, the balance
/// heuristic and a bare 1 differ), the answer 1 is "no MIS".
#[test]
fn the_app_names_a_classic_mistake() {
    let mut s = AppState::new(Prefs::default(), || {});
    s.apply(Command::Learn(LearnCmd::OpenSheet(
        Path::new("lessons/exercises/16-mis.toml").into(),
    )));
    s.apply(Command::Learn(LearnCmd::Student("alice".into())));
    s.apply(Command::Learn(LearnCmd::Answer("1".into())));
    s.apply(Command::Learn(LearnCmd::Check));
    let start = std::time::Instant::now();
    while s.learn.attempts[0].mark.is_none() && start.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(20));
        s.tick(raystep::platform::Instant::now());
    }
    let m = s.learn.attempts[0]
        .mark
        .as_ref()
        .expect("the check finishes");
    assert!(!m.right);
    assert_eq!(m.mistake.map(|k| k.id()), Some("no-mis"), "{m:?}");
    assert!(m.note.as_deref().unwrap().contains("no MIS"), "{m:?}");
}
