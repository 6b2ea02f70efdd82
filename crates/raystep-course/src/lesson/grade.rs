//! Marking a whole class from a CSV of answers.

use super::{ExerciseSheet, mark};
use crate::text::csv::{parse_csv, text_cell, write_csv};

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

/// Header names that hold the student's id (compared without case, spaces and `_`).
const STUDENT_HEADERS: [&str; 4] = ["student", "studentid", "id", "username"];

/// Marks a class's typed answers (`raystep grade`): every row of a class CSV: a column for the student's id (headed `student`, `student id`,
/// `id` or `username`, in any case) and one per question (headed by its id, in any case), in any
/// order, separated by commas, semicolons or tabs (detected from the header). Other columns (a
/// learning platform's Timestamp, Email, …) are ignored and listed in `warnings`. Rows with too
/// few columns and unreadable or empty answers are graded (missing answers are wrong) and
/// reported in `warnings`; a file that is not CSV, a header with no student column or a question
/// twice, or a student on two rows is an error. An error from the sheet (a scene that doesn't
/// load) is an error. Each wrong answer's reason goes into the grades file's `notes`, so a
/// teacher has something to hand back per question.
pub fn grade_answers_csv(
    sheet: &ExerciseSheet,
    text: &str,
    file: &str,
) -> Result<GradeReport, String> {
    let rows = parse_csv(text, file).map_err(|e| e.to_string())?;
    let Some((header, body)) = rows.split_first() else {
        return Err(format!(
            "{file}: empty; expected a header `student,<question ids…>`"
        ));
    };
    let key = |h: &str| {
        h.trim()
            .chars()
            .filter(|c| !c.is_whitespace() && *c != '_')
            .flat_map(char::to_lowercase)
            .collect::<String>()
    };
    let Some(student_col) = header
        .iter()
        .position(|h| STUDENT_HEADERS.contains(&key(h).as_str()))
    else {
        let shown: Vec<String> = header.iter().map(|h| format!("\"{}\"", h.trim())).collect();
        return Err(format!(
            "{file}: row 1: no column holds the student's id: name one `student` (or `student id`, `id`, `username`); the header has {}",
            shown.join(", ")
        ));
    };
    // Which question each column answers (None: not a question; ignored).
    let mut columns: Vec<Option<usize>> = vec![None; header.len()];
    let mut ignored = vec![];
    for (i, h) in header.iter().enumerate() {
        if i == student_col {
            continue;
        }
        let Some(q) = sheet
            .questions
            .iter()
            .position(|q| q.id.eq_ignore_ascii_case(h.trim()))
        else {
            ignored.push(format!("\"{}\" (column {})", h.trim(), i + 1));
            continue;
        };
        if columns.contains(&Some(q)) {
            return Err(format!(
                "{file}: row 1, column {}: question \"{}\" appears twice",
                i + 1,
                h.trim()
            ));
        }
        columns[i] = Some(q);
    }
    let mut warnings = vec![];
    if !ignored.is_empty() {
        let ids: Vec<&str> = sheet.questions.iter().map(|q| q.id.as_str()).collect();
        warnings.push(format!(
            "{file}: row 1: ignored {} (not the student's id nor a question of this sheet: {})",
            ignored.join(", "),
            ids.join(", ")
        ));
    }
    for (qi, q) in sheet.questions.iter().enumerate() {
        if !columns.contains(&Some(qi)) {
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
    let id_col = student_col + 1;
    // A student on two rows would get two grades lines (which one counts?): refuse the file.
    let mut seen: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
    for (ri, row) in body.iter().enumerate() {
        let student = row.get(student_col).map_or("", |s| s.trim());
        if student.is_empty() {
            continue;
        }
        if let Some(first) = seen.insert(student, ri + 2) {
            return Err(format!(
                "{file}: row {}, column {id_col}: student \"{student}\" already has a row (row {first}); \
                 keep one row per student",
                ri + 2
            ));
        }
    }
    let mut total = 0.0;
    let mut students = 0;
    for (ri, row) in body.iter().enumerate() {
        let rn = ri + 2;
        let student = row.get(student_col).map_or("", |s| s.trim());
        if student.is_empty() {
            warnings.push(format!(
                "{file}: row {rn}, column {id_col}: no student id; row skipped"
            ));
            continue;
        }
        // Problems with the file (for the warnings), and why each answer is wrong (for the
        // student: the grades file's notes).
        let mut problems = vec![];
        let mut reasons = vec![];
        if row.len() < header.len() {
            problems.push(format!(
                "row {rn}: {} column{}, expected {}: columns {}–{} missing",
                row.len(),
                if row.len() == 1 { "" } else { "s" },
                header.len(),
                row.len() + 1,
                header.len()
            ));
        } else if row.len() > header.len() {
            problems.push(format!(
                "row {rn}: {} columns, expected {}: columns {}–{} ignored",
                row.len(),
                header.len(),
                header.len() + 1,
                row.len()
            ));
        }
        let mut line = vec![text_cell(student)];
        let mut score = 0.0;
        for (qi, q) in sheet.questions.iter().enumerate() {
            let col = columns.iter().position(|&c| c == Some(qi));
            let given = col.and_then(|c| row.get(c)).map(|s| s.as_str());
            let v = sheet.variant(q, student);
            let (expected, found) = sheet.expected_and_mistakes(q, &v)?;
            let mut m = mark(&expected, q.quantity.kind(), given, q.tolerance);
            super::mistakes::annotate(&mut m, q, given, &found);
            if m.right {
                score += q.points;
                line.push(format!("{}", q.points));
            } else {
                line.push("0".into());
                // The reason and what the sheet's feedback policy adds, as `check` tells it
                // (one try: the grades file is handed back after the quiz).
                let told = sheet.feedback.explain(&m, &expected, 1);
                let note = if told.is_empty() {
                    "wrong"
                } else {
                    told.as_str()
                };
                // Answers that cannot be read are a problem with the file too, located.
                if let (true, Some(c)) = (m.unreadable, col)
                    && c < row.len()
                {
                    let located = format!("row {rn}, column {} ({}): {note}", c + 1, q.id);
                    problems.push(located.clone());
                    reasons.push(located);
                } else {
                    reasons.push(format!("{}: {note}", q.id));
                }
            }
        }
        warnings.extend(problems.iter().map(|n| format!("{file}: {n}")));
        line.push(format!("{score}"));
        line.push(format!("{out_of}"));
        // The notes: a row that is short or long, then why each wrong answer is wrong.
        let notes: Vec<&String> = problems
            .iter()
            .filter(|p| !reasons.contains(p))
            .chain(&reasons)
            .collect();
        line.push(text_cell(
            &notes
                .iter()
                .map(|s| s.as_str())
                .collect::<Vec<_>>()
                .join("; "),
        ));
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
