//! Grading a class's CSV: malformed rows, a student on two rows.

use super::*;

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

#[test]
fn a_student_on_two_rows_is_an_error() {
    let path = root().join("lessons/exercises/02-sphere.toml");
    let sheet = lesson::load_exercise_sheet(&path).unwrap();
    let csv = "student,disc\nann,1\nben,2\n ann ,3\n";
    let e = lesson::grade_answers_csv(&sheet, csv, "class.csv").unwrap_err();
    assert!(e.starts_with("class.csv: row 4, column 1:"), "{e}");
    assert!(e.contains("\"ann\"") && e.contains("row 2"), "{e}");
}
