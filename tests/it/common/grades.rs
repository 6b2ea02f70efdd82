//! A class graded through the command line: `raystep grade SHEET CLASS.csv -o GRADES.csv`, and
//! the grades file read back.

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
