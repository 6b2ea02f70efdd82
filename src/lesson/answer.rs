//! Answers: what the tracer says, what a student wrote, and marking one against the other.

use super::Tolerance;
use std::collections::BTreeMap;

/// The kind of answer a quantity has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AnswerKind {
    /// A number.
    Number,
    /// Three numbers.
    Vector,
    /// Yes or no.
    YesNo,
    /// An object's name.
    Name,
}

impl AnswerKind {
    /// How to write it, for students.
    pub fn describe(self) -> &'static str {
        match self {
            AnswerKind::Number => "a number",
            AnswerKind::Vector => "a vector x, y, z",
            AnswerKind::YesNo => "yes or no",
            AnswerKind::Name => "an object's name",
        }
    }
}

/// An expected answer, computed by the tracer.
#[derive(Debug, Clone, PartialEq)]
pub enum Answer {
    /// A number.
    Number(f64),
    /// A vector.
    Vector([f64; 3]),
    /// Yes / no.
    YesNo(bool),
    /// An object's name.
    Name(String),
    /// The tracer never computed the quantity (the ray missed, the test stopped early).
    None,
}

impl std::fmt::Display for Answer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Answer::Number(x) => write!(f, "{x}"),
            Answer::Vector([x, y, z]) => write!(f, "{x}, {y}, {z}"),
            Answer::YesNo(b) => f.write_str(if *b { "yes" } else { "no" }),
            Answer::Name(n) => f.write_str(n),
            Answer::None => f.write_str("none"),
        }
    }
}

/// The marking of one answer.
#[derive(Debug, Clone, PartialEq)]
pub struct Mark {
    /// Right or wrong.
    pub right: bool,
    /// How far off (numbers: |given − expected|; vectors: the Euclidean distance).
    pub abs_error: Option<f64>,
    /// `abs_error / |expected|` (when expected ≠ 0).
    pub rel_error: Option<f64>,
    /// Why it is wrong when it isn't a matter of distance ("missing", "not a number", …).
    pub note: Option<String>,
}

impl Mark {
    fn wrong(note: impl Into<String>) -> Mark {
        Mark {
            right: false,
            abs_error: None,
            rel_error: None,
            note: Some(note.into()),
        }
    }
    fn exact(right: bool) -> Mark {
        Mark {
            right,
            abs_error: None,
            rel_error: None,
            note: None,
        }
    }
}

fn unquote(s: &str) -> &str {
    let s = s.trim();
    for q in ['"', '\''] {
        if s.len() >= 2 && s.starts_with(q) && s.ends_with(q) {
            return s[1..s.len() - 1].trim();
        }
    }
    s
}

fn is_none(s: &str) -> bool {
    matches!(
        s.to_ascii_lowercase().as_str(),
        "none" | "miss" | "-" | "n/a" | "nothing"
    )
}

fn number(s: &str) -> Option<f64> {
    s.trim().parse::<f64>().ok().filter(|x| x.is_finite())
}

fn vector(s: &str) -> Option<[f64; 3]> {
    let s = s.trim();
    let s = s
        .strip_prefix('(')
        .and_then(|s| s.strip_suffix(')'))
        .or_else(|| s.strip_prefix('[').and_then(|s| s.strip_suffix(']')))
        .unwrap_or(s);
    let parts: Vec<&str> = if s.contains(',') {
        s.split(',').collect()
    } else {
        s.split_whitespace().collect()
    };
    if parts.len() != 3 {
        return None;
    }
    Some([number(parts[0])?, number(parts[1])?, number(parts[2])?])
}

fn yes_no(s: &str) -> Option<bool> {
    match s.to_ascii_lowercase().as_str() {
        "yes" | "y" | "true" => Some(true),
        "no" | "n" | "false" => Some(false),
        _ => None,
    }
}

fn by_distance(d: f64, scale: f64, tol: Tolerance) -> Mark {
    let rel = (scale != 0.0).then(|| d / scale);
    Mark {
        right: d <= tol.abs || rel.is_some_and(|r| r <= tol.rel),
        abs_error: Some(d),
        rel_error: rel,
        note: None,
    }
}

/// Marks a student's answer (raw text; `None` or blank = missing) against the expected one.
/// Never fails: a missing or unreadable answer is wrong, with a note saying why.
pub fn mark(expected: &Answer, kind: AnswerKind, given: Option<&str>, tol: Tolerance) -> Mark {
    let Some(given) = given.map(unquote).filter(|s| !s.is_empty()) else {
        return Mark::wrong("no answer");
    };
    if is_none(given) {
        return match expected {
            Answer::None => Mark::exact(true),
            _ => Mark::exact(false),
        };
    }
    let unreadable = || Mark::wrong(format!("\"{given}\" is not {}", kind.describe()));
    match expected {
        Answer::None => match kind {
            AnswerKind::Number if number(given).is_none() => unreadable(),
            AnswerKind::Vector if vector(given).is_none() => unreadable(),
            AnswerKind::YesNo if yes_no(given).is_none() => unreadable(),
            _ => Mark::exact(false),
        },
        Answer::Number(e) => match number(given) {
            Some(g) => by_distance((g - e).abs(), e.abs(), tol),
            None => unreadable(),
        },
        Answer::Vector(e) => match vector(given) {
            Some(g) => {
                let d = (0..3).map(|i| (g[i] - e[i]).powi(2)).sum::<f64>().sqrt();
                let n = e.iter().map(|c| c * c).sum::<f64>().sqrt();
                by_distance(d, n, tol)
            }
            None => unreadable(),
        },
        Answer::YesNo(e) => match yes_no(given) {
            Some(g) => Mark::exact(g == *e),
            None => unreadable(),
        },
        Answer::Name(e) => Mark::exact(given.eq_ignore_ascii_case(e.trim())),
    }
}

/// Parses an answers file: `id = value` lines, `#` comments, blank lines. `known` lists the
/// question ids; an unknown or repeated id or a line without `=` is an error naming the line.
pub fn parse_answers(
    text: &str,
    file: &str,
    known: &[&str],
) -> Result<BTreeMap<String, String>, String> {
    let mut out = BTreeMap::new();
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        let Some((k, v)) = t.split_once('=') else {
            return Err(format!(
                "{file}:{n}: expected `question-id = answer`, got \"{t}\""
            ));
        };
        let k = unquote(k);
        let v = v.trim();
        // A comment after the value, unless the value is quoted.
        let v = if v.starts_with('"') || v.starts_with('\'') {
            v
        } else {
            v.split_once('#').map_or(v, |(a, _)| a.trim())
        };
        if !known.contains(&k) {
            return Err(format!(
                "{file}:{n}: unknown question \"{k}\" (this sheet asks {})",
                known.join(", ")
            ));
        }
        if out.insert(k.to_string(), v.to_string()).is_some() {
            return Err(format!("{file}:{n}: question \"{k}\" is answered twice"));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_vectors_names_and_none() {
        let t = Tolerance::default();
        assert!(mark(&Answer::Number(4.0), AnswerKind::Number, Some("4.0001"), t).right);
        assert!(!mark(&Answer::Number(4.0), AnswerKind::Number, Some("4.1"), t).right);
        let m = mark(&Answer::Number(4.0), AnswerKind::Number, Some("four"), t);
        assert!(!m.right && m.note.is_some());
        assert!(!mark(&Answer::Number(4.0), AnswerKind::Number, Some(""), t).right);
        assert!(
            mark(
                &Answer::Vector([0.0, 0.0, 1.0]),
                AnswerKind::Vector,
                Some("(0, 0, 1)"),
                t
            )
            .right
        );
        assert!(
            mark(
                &Answer::Vector([0.0, 0.0, 1.0]),
                AnswerKind::Vector,
                Some("[0,0,1]"),
                t
            )
            .right
        );
        assert!(
            mark(
                &Answer::Name("Middle".into()),
                AnswerKind::Name,
                Some("\"middle\""),
                t
            )
            .right
        );
        assert!(mark(&Answer::None, AnswerKind::Number, Some("none"), t).right);
        assert!(!mark(&Answer::None, AnswerKind::Number, Some("3"), t).right);
        assert!(mark(&Answer::YesNo(true), AnswerKind::YesNo, Some("Yes"), t).right);
    }

    #[test]
    fn answers_file_errors_name_the_line() {
        let e = parse_answers("a = 1\nb 2\n", "ans.txt", &["a", "b"]).unwrap_err();
        assert!(e.starts_with("ans.txt:2:"), "{e}");
        let ok = parse_answers("# c\na = 1 # why\nb = \"x # y\"\n", "f", &["a", "b"]).unwrap();
        assert_eq!(ok["a"], "1");
        assert_eq!(ok["b"], "\"x # y\"");
    }
}
