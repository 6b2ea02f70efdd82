//! The entry points the fuzzers (`fuzz/`, cargo-fuzz) and the property tests
//! (`tests/fuzz_props.rs`) drive with hostile input: the same code paths the command line takes
//! for a scene, a saved trace, and an exercise sheet with answers and a class CSV. Each returns
//! normally on every input; a panic, an abort or a hang is the finding.
//!
//! Inputs that carry several files separate them with marker lines: a scene's OBJ follows a line
//! [`OBJ_MARKER`]; a sheet's answers follow [`ANSWERS_MARKER`], its class CSV [`CSV_MARKER`].

use crate::diagram::{self, Theme, ViewOptions};
use crate::explain::describe;
use crate::explain::diff::{Tolerance, compare};
use crate::lesson;
use crate::record::Trace;
use crate::trace::PreparedScene;
use std::path::{Path, PathBuf};

/// The line that separates a scene's TOML from its OBJ file (written as `mesh.obj`).
pub const OBJ_MARKER: &str = "\n%%OBJ%%\n";
/// The line that separates a sheet's TOML from its answers file.
pub const ANSWERS_MARKER: &str = "\n%%ANSWERS%%\n";
/// The line that separates the answers file from the class CSV.
pub const CSV_MARKER: &str = "\n%%CSV%%\n";

/// Splits `text` at the first `marker`: (before, after), or (text, "") when there is none.
pub fn split_at_marker<'a>(text: &'a str, marker: &str) -> (&'a str, &'a str) {
    text.split_once(marker).unwrap_or((text, ""))
}

/// Loads a scene (TOML, then optionally [`OBJ_MARKER`] and an OBJ written as `mesh.obj` next to
/// it); when it loads, builds its accelerator, records the trace of the middle pixel and reads
/// the trace back from its JSON. Returns whether the scene loaded.
pub fn scene_input(data: &[u8]) -> bool {
    let text = String::from_utf8_lossy(data);
    let (toml, obj) = split_at_marker(&text, OBJ_MARKER);
    let dir = match tempfile::tempdir() {
        Ok(d) => d,
        Err(_) => return false,
    };
    if std::fs::write(dir.path().join("mesh.obj"), obj).is_err() {
        return false;
    }
    let Ok(scene) = crate::scene::load_str(toml, "fuzz.toml", Some(dir.path())) else {
        return false;
    };
    let (x, y) = (scene.camera.width / 2, scene.camera.height / 2);
    let trace = PreparedScene::new(scene).record(x, y, 0);
    // What the tracer writes, the reader must accept and read back unchanged.
    let json = trace.to_json();
    match Trace::from_json(&json, "fuzz.json") {
        Ok(back) => assert!(
            compare(&trace, &back, Tolerance::uniform(0.0)).is_equal(),
            "a recorded trace reads back different"
        ),
        Err(e) => panic!("a recorded trace does not read back: {e}"),
    }
    true
}

/// Reads a trace from JSON; when it loads, prints its tree, compares it with itself and with a
/// copy missing its last root step (`diff`), and draws every available diagram kind, unfocused
/// and focused on its middle step, at a small size. Returns whether the trace loaded.
pub fn trace_input(data: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(data) else {
        return false;
    };
    let Ok(trace) = Trace::from_json(text, "fuzz.json") else {
        return false;
    };
    let _ = describe::tree(&trace);
    let names = ["a.json", "b.json"];
    let same = compare(&trace, &trace, Tolerance::uniform(0.0));
    let _ = same.to_text(&trace, &trace, names);
    let mut shorter = trace.clone();
    shorter.root.steps.pop();
    for tol in [0.0, 1e-3] {
        let cmp = compare(&trace, &shorter, Tolerance::uniform(tol));
        let _ = cmp.to_text(&trace, &shorter, names);
        let _ = cmp.to_json(&trace, &shorter, names);
    }
    let steps = trace.timeline().len();
    let middle = (steps > 0).then_some(steps / 2);
    for kind in diagram::available(&trace) {
        for focus in [None, middle] {
            let opts = ViewOptions {
                width: 96,
                height: 72,
                theme: Theme::LIGHT,
                focus,
                slice_angle: 0.0,
                top_down: false,
                ..ViewOptions::default()
            };
            let _ = diagram::draw(&trace, kind, &opts);
        }
    }
    if let Some(k) = middle {
        let _ = diagram::kinds_for_step(&trace, k);
    }
    true
}

/// The shipped exercise sheets' folder: where a fuzzed sheet's scene paths start from.
pub fn exercises_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("lessons/exercises")
}

/// Parses a sheet (TOML, then [`ANSWERS_MARKER`] and an answers file, then [`CSV_MARKER`] and a
/// class CSV); when it parses, works out every question's expected answer for one student, marks
/// the answers file against them and grades the CSV. Returns whether the sheet parsed.
pub fn sheet_input(data: &[u8]) -> bool {
    let text = String::from_utf8_lossy(data);
    let (sheet_text, rest) = split_at_marker(&text, ANSWERS_MARKER);
    let (answers, csv) = split_at_marker(rest, CSV_MARKER);
    // CSV parsing stands on its own too (a CSV that no sheet accepts is still parsed).
    let _ = lesson::parse_csv(csv, "class.csv");
    let base = exercises_dir();
    let Ok(sheet) = lesson::parse_sheet(sheet_text, "sheet.toml", Some(&base), "sheet") else {
        return false;
    };
    let ids: Vec<&str> = sheet.questions.iter().map(|q| q.id.as_str()).collect();
    let given = lesson::parse_answers(answers, "answers.txt", &ids).unwrap_or_default();
    for q in &sheet.questions {
        let v = sheet.variant(q, "fuzz");
        if let Ok(expected) = sheet.expected(q, &v) {
            let _ = expected.to_string();
            let _ = lesson::mark(
                &expected,
                q.quantity.kind(),
                given.get(&q.id).map(String::as_str),
                q.tolerance,
            );
        }
    }
    let _ = lesson::grade_class(&sheet, csv, "class.csv");
    true
}
