//! Marking a whole class from a CSV of answers.

use super::{Sheet, mark, parse_csv, write_csv};

/// The result of grading a class.
#[derive(Debug, Clone, PartialEq)]
pub struct GradeReport {
    /// The grades file: `student,<question ids…>,score,out_of,notes`.
    pub csv: String,
    /// Problems with rows and answers (missing columns, unreadable answers), each naming the
    /// row and column.
    pub warnings: Vec<String>,
    /// Students graded.
    pub students: usize,
    /// Their mean score.
    pub mean: f64,
    /// The most points a student can get.
    pub out_of: f64,
}

/// Marks every row of a class CSV (header `student,<question ids…>`). Rows with too few or too
/// many columns and unreadable or empty answers are graded (missing answers are wrong) and
/// reported in `warnings`; a file that is not CSV, a header that is not `student` followed by
/// question ids, or a student on two rows is an error. An error from the sheet (a scene that doesn't load) is an error.
pub fn grade_class(sheet: &Sheet, text: &str, file: &str) -> Result<GradeReport, String> {
    let rows = parse_csv(text, file).map_err(|e| e.to_string())?;
    let Some((header, body)) = rows.split_first() else {
        return Err(format!(
            "{file}: empty; expected a header `student,<question ids…>`"
        ));
    };
    if header.first().map(|h| h.trim().to_ascii_lowercase()) != Some("student".into()) {
        return Err(format!(
            "{file}: row 1, column 1: the header must start with `student`, got \"{}\"",
            header.first().map_or("", |s| s.as_str())
        ));
    }
    // Which question each column answers.
    let mut columns: Vec<usize> = vec![];
    for (i, h) in header.iter().enumerate().skip(1) {
        let h = h.trim();
        let Some(q) = sheet.questions.iter().position(|q| q.id == h) else {
            let ids: Vec<&str> = sheet.questions.iter().map(|q| q.id.as_str()).collect();
            return Err(format!(
                "{file}: row 1, column {}: unknown question \"{h}\" (this sheet asks {})",
                i + 1,
                ids.join(", ")
            ));
        };
        if columns.contains(&q) {
            return Err(format!(
                "{file}: row 1, column {}: question \"{h}\" appears twice",
                i + 1
            ));
        }
        columns.push(q);
    }
    let mut warnings = vec![];
    for (qi, q) in sheet.questions.iter().enumerate() {
        if !columns.contains(&qi) {
            warnings.push(format!(
                "{file}: row 1: no column for question \"{}\": everyone's answer is missing",
                q.id
            ));
        }
    }
    let out_of: f64 = sheet.questions.iter().map(|q| q.points).sum();
    let mut out = vec![{
        let mut h = vec!["student".to_string()];
        h.extend(sheet.questions.iter().map(|q| q.id.clone()));
        h.extend(["score".into(), "out_of".into(), "notes".into()]);
        h
    }];
    // A student on two rows would get two grades lines (which one counts?): refuse the file.
    let mut seen: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
    for (ri, row) in body.iter().enumerate() {
        let student = row.first().map_or("", |s| s.trim());
        if student.is_empty() {
            continue;
        }
        if let Some(first) = seen.insert(student, ri + 2) {
            return Err(format!(
                "{file}: row {}, column 1: student \"{student}\" already has a row (row {first}); \
                 keep one row per student",
                ri + 2
            ));
        }
    }
    let mut total = 0.0;
    let mut students = 0;
    for (ri, row) in body.iter().enumerate() {
        let rn = ri + 2;
        let student = row.first().map_or("", |s| s.trim());
        if student.is_empty() {
            warnings.push(format!(
                "{file}: row {rn}, column 1: no student id; row skipped"
            ));
            continue;
        }
        let mut notes = vec![];
        if row.len() < header.len() {
            notes.push(format!(
                "row {rn}: {} column{}, expected {}: columns {}–{} missing",
                row.len(),
                if row.len() == 1 { "" } else { "s" },
                header.len(),
                row.len() + 1,
                header.len()
            ));
        } else if row.len() > header.len() {
            notes.push(format!(
                "row {rn}: {} columns, expected {}: columns {}–{} ignored",
                row.len(),
                header.len(),
                header.len() + 1,
                row.len()
            ));
        }
        let mut line = vec![student.to_string()];
        let mut score = 0.0;
        for (qi, q) in sheet.questions.iter().enumerate() {
            let col = columns.iter().position(|&c| c == qi);
            let given = col.and_then(|c| row.get(c + 1)).map(|s| s.as_str());
            let v = sheet.variant(q, student);
            let expected = sheet.expected(q, &v)?;
            let m = mark(&expected, q.quantity.kind(), given, q.tolerance);
            if m.right {
                score += q.points;
                line.push(format!("{}", q.points));
            } else {
                line.push("0".into());
                // Only answers that cannot be read are reported (a wrong answer is not a
                // problem with the file).
                if let (true, Some(note), Some(c)) = (m.unreadable, &m.note, col)
                    && c + 1 < row.len()
                {
                    notes.push(format!("row {rn}, column {} ({}): {note}", c + 2, q.id));
                }
            }
        }
        warnings.extend(notes.iter().map(|n| format!("{file}: {n}")));
        line.push(format!("{score}"));
        line.push(format!("{out_of}"));
        line.push(notes.join("; "));
        out.push(line);
        total += score;
        students += 1;
    }
    Ok(GradeReport {
        csv: write_csv(&out),
        warnings,
        students,
        mean: if students == 0 {
            0.0
        } else {
            total / students as f64
        },
        out_of,
    })
}
