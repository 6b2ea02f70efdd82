//! The Monte Carlo exercise sheets (13–16) answered as a careful student would: every variant's
//! answer computed in double precision by an independent tracer (tests/student_tracer/
//! sheet_answers.py: the scene files and raystep's documented random numbers, never raystep's
//! trace), then marked. For 500 students per sheet:
//! - every premise the question's text states holds at the student's pixel, as the independent
//!   tracer sees it (the surface hit, the light sampled, a second diffuse surface, an MIS weight
//!   that tells the power heuristic from the balance heuristic and from 1);
//! - the f64 answer is marked right against raystep's f32 key (a right answer is never marked
//!   wrong);
//! - each classic mistake, worked out the wrong way, is marked wrong and named.
//!
//! Then 40 students' answers go through `raystep grade` as a class CSV: every right answer scores,
//! and a class that makes the classic mistakes scores 0 with the mistake named in grades.csv.

use raystep::lesson::{
    Answer, ExerciseSheet, Question, SceneSource, load_exercise_sheet, mark, mistakes,
};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::grades::grade_class;

const STUDENTS: usize = 500;
const CLASS: usize = 40;
const SHEETS: [&str; 4] = [
    "13-monte-carlo",
    "14-area-lights",
    "15-path-tracing",
    "16-mis",
];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn student(k: usize) -> String {
    format!("s{k:04}")
}

/// An answer as a student writes it: numbers with all their f64 digits.
fn written(v: &Value) -> Option<String> {
    match v {
        Value::Number(n) => Some(n.as_f64()?.to_string()),
        Value::Array(a) => {
            let c: Vec<String> = a
                .iter()
                .map(|x| x.as_f64().map(|x| x.to_string()))
                .collect::<Option<_>>()?;
            Some(c.join(", "))
        }
        _ => None,
    }
}

/// The independent tracer's answers (and path, light and mistakes) for every (question, student).
fn answers(sheet: &ExerciseSheet, dir: &Path) -> Vec<Vec<Value>> {
    let mut items = vec![];
    for (qi, q) in sheet.questions.iter().enumerate() {
        for k in 0..STUDENTS {
            let v = sheet.variant(q, &student(k));
            let scene = match (&q.scene, &v.scene_toml) {
                (SceneSource::File(p), _) => p.clone(),
                (SceneSource::Inline(_), Some(text)) => {
                    let p = dir.join(format!("{}-{qi}-{k}.toml", sheet.id));
                    std::fs::write(&p, text).unwrap();
                    p
                }
                (SceneSource::Inline(_), None) => unreachable!(),
            };
            items.push(json!({"question": q.id, "scene": scene, "pixel": v.pixel}));
        }
    }
    let input = dir.join(format!("{}-in.json", sheet.id));
    std::fs::write(&input, serde_json::to_vec(&items).unwrap()).unwrap();
    let out = Command::new("python3")
        .arg(root().join("tests/student_tracer/sheet_answers.py"))
        .stdin(std::fs::File::open(&input).unwrap())
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let all: Vec<Value> = serde_json::from_slice(&out.stdout).unwrap();
    all.chunks(STUDENTS).map(|c| c.to_vec()).collect()
}

/// What the question's text says the pixel shows, checked on the independent tracer's path.
fn premise_holds(q: &Question, a: &Value) -> Result<(), String> {
    let s = |i: usize, key: &str| a["surfaces"][i][key].as_str().unwrap_or("").to_string();
    let f = |key: &str| a["mistakes"][key].as_f64();
    let ok = match q.id.as_str() {
        "cone-pdf" | "estimate" => s(0, "name") == "floor" && a["light"] == "small light",
        "area-pdf" | "blocked" => s(0, "material") == "white",
        "cosine-pdf" => s(0, "material") == "red",
        "throughput" => s(0, "material") == "red" && s(1, "bsdf") == "diffuse",
        "roulette" => s(0, "name") == "floor",
        "glossy-pdf" => s(0, "bsdf") == "glossy",
        "power-heuristic" => {
            let w = a["answer"].as_f64().unwrap_or(1.0);
            let balance = f("balance-heuristic").unwrap_or(w);
            // At least 5 % apart, relative to the right answer (a hair less: raystep draws the
            // pixel with its f32 numbers, this is f64).
            s(0, "name") == "floor" && (1.0 - w) / w >= 0.0499 && (balance - w).abs() / w >= 0.0499
        }
        other => return Err(format!("no premise known for question {other}")),
    };
    if ok {
        Ok(())
    } else {
        Err(format!("premise of {} fails: {a}", q.id))
    }
}

#[test]
fn every_variant_of_the_monte_carlo_sheets_is_true_and_keyed_right() {
    let dir = tempfile::tempdir().unwrap();
    for name in SHEETS {
        let path = root().join(format!("lessons/exercises/{name}.toml"));
        let sheet = load_exercise_sheet(&path).unwrap();
        let by_question = answers(&sheet, dir.path());
        for (q, answers) in sheet.questions.iter().zip(&by_question) {
            let mut named = 0;
            for (k, a) in answers.iter().enumerate() {
                let who = student(k);
                let v = sheet.variant(q, &who);
                premise_holds(q, a).unwrap_or_else(|e| panic!("{name} {who} {:?}: {e}", v.pixel));
                let (key, found) = sheet.expected_and_mistakes(q, &v).unwrap();
                let given = written(&a["answer"])
                    .unwrap_or_else(|| panic!("{name} {} {who}: no answer: {a}", q.id));
                let m = mark(&key, q.quantity.kind(), Some(&given), q.tolerance);
                assert!(
                    m.right,
                    "{name} {} {who} pixel {:?}: the f64 answer {given} is marked wrong against the key {key}: {:?}",
                    q.id, v.pixel, m.note
                );
                for (id, wrong) in a["mistakes"].as_object().unwrap() {
                    let wrong = written(wrong).unwrap();
                    let mut m = mark(&key, q.quantity.kind(), Some(&wrong), q.tolerance);
                    let listed = q.mistakes.iter().any(|x| x.id() == id);
                    if listed {
                        assert!(
                            !m.right,
                            "{name} {} {who}: mistake {id} is marked right",
                            q.id
                        );
                    }
                    if m.right {
                        continue;
                    }
                    mistakes::annotate(&mut m, q, Some(&wrong), &found);
                    assert_eq!(
                        m.mistake.map(|x| x.id()),
                        Some(id.as_str()),
                        "{name} {} {who}: {wrong} is not named as {id}: {:?}",
                        q.id,
                        m.note
                    );
                    named += 1;
                }
            }
            if !q.mistakes.is_empty() {
                assert!(named >= STUDENTS, "{name} {}: {named} mistakes named", q.id);
            }
        }
        // The class: 40 students answer in f64 through `raystep grade`, and a second class
        // makes the first listed mistake of every question that lists one.
        for wrong in [false, true] {
            let qs: Vec<(usize, &Question)> = sheet
                .questions
                .iter()
                .enumerate()
                .filter(|(_, q)| !wrong || !q.mistakes.is_empty())
                .collect();
            let mut csv = String::from("student");
            for (_, q) in &qs {
                csv += &format!(",{}", q.id);
            }
            csv += "\n";
            for k in 0..CLASS {
                csv += &student(k);
                for (qi, q) in &qs {
                    let a = by_question[*qi].get(k).unwrap();
                    let v = if wrong {
                        &a["mistakes"][q.mistakes[0].id()]
                    } else {
                        &a["answer"]
                    };
                    csv += &format!(",\"{}\"", written(v).unwrap());
                }
                csv += "\n";
            }
            let (g, mut reader) = grade_class(&path, &csv, dir.path(), &format!("{name}-{wrong}"));
            let header = reader.remove(0);
            let score = header.iter().position(|h| h == "score").unwrap();
            let out_of = header.iter().position(|h| h == "out_of").unwrap();
            let notes = header.iter().position(|h| h == "notes").unwrap();
            assert_eq!(reader.len(), CLASS, "{g}");
            for row in &reader {
                if wrong {
                    assert_eq!(row[score], "0", "{name}: {row:?}");
                    for (_, q) in &qs {
                        let id = q.mistakes[0].id();
                        assert!(
                            row[notes].contains(&format!("[{id}]")),
                            "{name}: {} is not named in {row:?}",
                            id
                        );
                    }
                } else {
                    assert_eq!(row[score], row[out_of], "{name}: {row:?}");
                }
            }
        }
    }
}

/// A wrong answer's feedback names the classic mistake it matches, and a tolerance that has no
/// relative part is not described as "or 0%".
#[test]
fn feedback_names_the_mistake_and_only_the_tolerance_set() {
    let sheet = load_exercise_sheet(&root().join("lessons/exercises/16-mis.toml")).unwrap();
    let q = &sheet.questions[0];
    let v = sheet.variant(q, "alice");
    let (key, found) = sheet.expected_and_mistakes(q, &v).unwrap();
    let Answer::Number(_) = key else {
        panic!("{key:?}")
    };
    let mut m = mark(&key, q.quantity.kind(), Some("1"), q.tolerance);
    mistakes::annotate(&mut m, q, Some("1"), &found);
    assert!(!m.right);
    let note = m.note.unwrap();
    assert!(
        note.contains("[no-mis]") && note.contains(" or 0.1%)"),
        "{note}"
    );
    let abs_only = raystep::record::Tolerance::within_either(1e-3, 0.0);
    let m = mark(
        &Answer::Number(0.5),
        q.quantity.kind(),
        Some("0.7"),
        abs_only,
    );
    assert_eq!(
        m.note.as_deref(),
        Some("not within the tolerance (± 0.001)")
    );
    // A lone 0 answers a vector question (the sheets say "0 if blocked").
    let m = mark(
        &Answer::Vector([0.0; 3]),
        raystep::lesson::AnswerKind::Vector,
        Some("0"),
        abs_only,
    );
    assert!(m.right, "{m:?}");
}
