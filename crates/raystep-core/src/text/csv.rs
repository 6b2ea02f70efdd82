//! A small CSV reader and writer (RFC 4180: double-quoted fields with `""` escapes, LF or CRLF
//! line ends), with the separator detected — commas, or the semicolons and tabs of spreadsheets
//! set to a language whose decimal mark is a comma and of learning platforms' exports. Kept by
//! hand rather than the `csv` crate because its errors must name the row *and column* of a
//! stray quote, which that crate's positions (byte, line, record) do not give.

/// A CSV file that could not be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: row {row}, column {column}: {message}")]
pub struct CsvError {
    /// The file.
    pub file: String,
    /// 1-based row (the header is row 1).
    pub row: usize,
    /// 1-based column.
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

/// The separator of a CSV file: whichever of `,`, `;` and tab occurs most often outside quotes
/// on its first line (`,` when none does).
pub fn detect_separator(text: &str) -> char {
    let mut counts = [0usize; 3];
    let mut quoted = false;
    for c in text.chars() {
        match c {
            '"' => quoted = !quoted,
            '\n' if !quoted => break,
            ',' if !quoted => counts[0] += 1,
            ';' if !quoted => counts[1] += 1,
            '\t' if !quoted => counts[2] += 1,
            _ => {}
        }
    }
    let best = (0..3).max_by_key(|&i| (counts[i], 2 - i)).unwrap_or(0);
    if counts[best] == 0 {
        ','
    } else {
        [',', ';', '\t'][best]
    }
}

/// Parses CSV text into rows of fields, the separator detected (`detect_separator`). Blank
/// lines are skipped.
pub fn parse_csv(text: &str, file: &str) -> Result<Vec<Vec<String>>, CsvError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let sep = detect_separator(text);
    let mut rows = vec![];
    let mut row: Vec<String> = vec![];
    let mut field = String::new();
    let mut chars = text.chars().peekable();
    let mut quoted_field = false;
    let mut in_quotes = false;
    let end_row = |row: &mut Vec<String>, rows: &mut Vec<Vec<String>>| {
        let r = std::mem::take(row);
        if !(r.len() == 1 && r[0].trim().is_empty()) {
            rows.push(r);
        }
    };
    while let Some(c) = chars.next() {
        if in_quotes {
            match c {
                '"' if chars.peek() == Some(&'"') => {
                    chars.next();
                    field.push('"');
                }
                '"' => in_quotes = false,
                c => field.push(c),
            }
            continue;
        }
        match c {
            '"' if field.trim().is_empty() && !quoted_field => {
                field.clear();
                in_quotes = true;
                quoted_field = true;
            }
            '"' => {
                return Err(CsvError {
                    file: file.into(),
                    row: rows.len() + 1,
                    column: row.len() + 1,
                    message: "a quote inside an unquoted field (quote the whole field and double the quote)".into(),
                });
            }
            c if c == sep => {
                row.push(std::mem::take(&mut field));
                quoted_field = false;
            }
            '\r' if chars.peek() == Some(&'\n') => {}
            '\n' => {
                row.push(std::mem::take(&mut field));
                quoted_field = false;
                end_row(&mut row, &mut rows);
            }
            c if quoted_field && !c.is_whitespace() => {
                return Err(CsvError {
                    file: file.into(),
                    row: rows.len() + 1,
                    column: row.len() + 1,
                    message: format!("unexpected `{c}` after a closing quote"),
                });
            }
            _ if quoted_field => {}
            c => field.push(c),
        }
    }
    if in_quotes {
        return Err(CsvError {
            file: file.into(),
            row: rows.len() + 1,
            column: row.len() + 1,
            message: "a quoted field is never closed".into(),
        });
    }
    if !field.is_empty() || !row.is_empty() || quoted_field {
        row.push(field);
        end_row(&mut row, &mut rows);
    }
    Ok(rows)
}

fn quote(f: &str) -> String {
    if f.contains([',', '"', '\n', '\r']) || f.trim() != f {
        format!("\"{}\"", f.replace('"', "\"\""))
    } else {
        f.to_string()
    }
}

/// A text cell (a name, a note) as a spreadsheet may safely read it: one that starts like a
/// formula (`=`, `+`, `-`, `@`, a tab or a carriage return) gets a leading `'`, so a student
/// folder named `=HYPERLINK(…)` is shown as text, never run (CSV injection, as OWASP describes it).
/// Numbers are not text cells: write them as they are.
pub fn text_cell(s: &str) -> String {
    if s.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        format!("'{s}")
    } else {
        s.to_string()
    }
}

/// Writes rows as CSV (LF line ends; fields quoted where needed).
pub fn write_csv(rows: &[Vec<String>]) -> String {
    let mut out = String::new();
    for r in rows {
        out += &r.iter().map(|f| quote(f)).collect::<Vec<_>>().join(",");
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_errors() {
        let rows = vec![
            vec!["a".to_string(), "b, c".into(), "say \"hi\"".into()],
            vec!["".into(), "x".into(), "".into()],
        ];
        assert_eq!(parse_csv(&write_csv(&rows), "f").unwrap(), rows);
        assert_eq!(
            parse_csv("a,b\r\n1,2\r\n\r\n", "f").unwrap(),
            vec![vec!["a", "b"], vec!["1", "2"]]
        );
        let e = parse_csv("a,b\n1,\"2\n", "f.csv").unwrap_err();
        assert_eq!((e.row, e.column), (2, 2));
        let e = parse_csv("a,b\n1,2\"x\n", "f.csv").unwrap_err();
        assert_eq!((e.row, e.column), (2, 2));
    }

    #[test]
    fn the_separator_is_detected() {
        assert_eq!(detect_separator("student;q1;q2\nann;1,5;2\n"), ';');
        assert_eq!(detect_separator("student\tq1\n"), '\t');
        assert_eq!(detect_separator("student,q1\n"), ',');
        assert_eq!(detect_separator("\"a;b\",c\n"), ',');
        assert_eq!(detect_separator("student\n"), ',');
        assert_eq!(
            parse_csv("Student;Q1\r\nann;\"1,5\"\r\n", "f").unwrap(),
            vec![vec!["Student", "Q1"], vec!["ann", "1,5"]]
        );
    }

    #[test]
    fn formula_like_text_is_quoted_as_text() {
        for f in ["=HYPERLINK(\"x\")", "+1", "-2+3", "@SUM(A1)", "\tx", "\rx"] {
            assert_eq!(text_cell(f), format!("'{f}"));
        }
        for t in ["ada", "1.5", "", " =x", "a=b"] {
            assert_eq!(text_cell(t), t);
        }
    }
}
