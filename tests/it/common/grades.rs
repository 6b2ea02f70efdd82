//! A class graded through the command line: `raystep grade SHEET CLASS.csv -o GRADES.csv`, and
//! the grades file read back.

use raystep::lesson::{Question, SceneSource, Variant, load_exercise_sheet, mark};
use std::path::Path;
use std::process::Command;

/// Writes `class_csv` as `{name}-class.csv` in `dir`, grades it against `sheet` with the built
/// `raystep grade` (which must succeed) and returns the grades file's text and its rows (the
/// header first).
pub fn grade_class(
    sheet: &Path,
    class_csv: &str,
    dir: &Path,
    name: &str,
) -> (String, Vec<Vec<String>>) {
    let class = dir.join(format!("{name}-class.csv"));
    let grades = dir.join(format!("{name}-grades.csv"));
    std::fs::write(&class, class_csv).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_raystep"))
        .args([
            "grade",
            sheet.to_str().unwrap(),
            class.to_str().unwrap(),
            "-o",
        ])
        .arg(&grades)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&grades).unwrap();
    let rows = csv_rows(&text);
    (text, rows)
}

/// Grades a class whose student `s{k:04}` answered `class[k]` (one answer per question of
/// `ids`, in order) and asserts that every student scored full marks.
pub fn assert_full_marks(
    sheet: &Path,
    ids: &[String],
    class: &[Vec<String>],
    dir: &Path,
    name: &str,
) {
    let mut csv = String::from("student");
    for id in ids {
        csv += &format!(",{id}");
    }
    csv += "\n";
    for (k, answers) in class.iter().enumerate() {
        csv += &format!("s{k:04}");
        for a in answers {
            csv += &format!(",\"{a}\"");
        }
        csv += "\n";
    }
    let (g, mut rows) = grade_class(sheet, &csv, dir, name);
    let header = rows.remove(0);
    let score = header.iter().position(|h| h == "score").unwrap();
    let out_of = header.iter().position(|h| h == "out_of").unwrap();
    assert_eq!(rows.len(), class.len(), "{g}");
    for row in &rows {
        assert_eq!(row[score], row[out_of], "{row:?}");
    }
}

/// Answers every question of the sheet at `sheet` for `students` students with `answer` — a
/// careful student's own computation, given the question, the student's variant, the variant's
/// scene (parsed TOML) and the folder its files are relative to — and asserts that each answer
/// is marked right against raystep's key. Then the first `class` students' answers are graded
/// as a class CSV ([`assert_full_marks`]).
pub fn answer_every_variant(
    sheet: &Path,
    students: usize,
    class: usize,
    answer: impl Fn(&Question, &Variant, &toml::Value, &Path) -> String,
) {
    let loaded = load_exercise_sheet(sheet).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut rows: Vec<Vec<String>> = vec![vec![]; class];
    for q in &loaded.questions {
        for k in 0..students {
            let who = format!("s{k:04}");
            let v = loaded.variant(q, &who);
            let (text, base) = match (&q.scene, &v.scene_toml) {
                (SceneSource::File(p), _) => (
                    std::fs::read_to_string(p).unwrap(),
                    p.parent().unwrap().to_path_buf(),
                ),
                (SceneSource::Inline(_), Some(t)) => (t.clone(), dir.path().to_path_buf()),
                (SceneSource::Inline(_), None) => unreachable!(),
            };
            let scene: toml::Value = toml::from_str(&text).unwrap();
            let given = answer(q, &v, &scene, &base);
            let (key, _) = loaded.expected_and_mistakes(q, &v).unwrap();
            let m = mark(&key, q.quantity.kind(), Some(&given), q.tolerance);
            assert!(
                m.right,
                "{} {who} pixel {:?}: the f64 answer {given} is marked wrong against the key {key}: {:?}",
                q.id, v.pixel, m.note
            );
            if let Some(row) = rows.get_mut(k) {
                row.push(given);
            }
        }
    }
    let ids: Vec<String> = loaded.questions.iter().map(|q| q.id.clone()).collect();
    let name = sheet.file_stem().unwrap().to_string_lossy().into_owned();
    assert_full_marks(sheet, &ids, &rows, dir.path(), &name);
}

/// A minimal CSV reader for the grades file (quoted fields, doubled quotes).
pub fn csv_rows(text: &str) -> Vec<Vec<String>> {
    let mut rows = vec![];
    for line in text.lines().filter(|l| !l.is_empty()) {
        let mut row = vec![];
        let mut cell = String::new();
        let mut quoted = false;
        let mut chars = line.chars().peekable();
        while let Some(c) = chars.next() {
            match (c, quoted) {
                ('"', true) if chars.peek() == Some(&'"') => {
                    cell.push('"');
                    chars.next();
                }
                ('"', _) => quoted = !quoted,
                (',', false) => row.push(std::mem::take(&mut cell)),
                (c, _) => cell.push(c),
            }
        }
        row.push(cell);
        rows.push(row);
    }
    rows
}
