//! Answers: what the tracer says, what a student wrote, and marking one against the other.

use crate::record::Tolerance;
use crate::record::number::{Style, fmt, fmt64};
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

/// A number of an answer as the trace prints it ([`Style::Exact`]): the tracer's f32 values in
/// their shortest form (`5.573929`, not the f64 widening `5.5739288330078125`), counts as
/// integers.
fn answer_number(x: f64) -> String {
    if (x as f32) as f64 == x {
        fmt(x as f32, Style::Exact)
    } else {
        fmt64(x, Style::Exact)
    }
}

/// An answer as the trace writes its numbers (see [`crate::record::number`]), so `--solutions`
/// and the feedback quote the digits `raystep trace` prints.
impl std::fmt::Display for Answer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Answer::Number(x) => f.write_str(&answer_number(*x)),
            Answer::Vector([x, y, z]) => write!(
                f,
                "{}, {}, {}",
                answer_number(*x),
                answer_number(*y),
                answer_number(*z)
            ),
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
    /// given − expected, per component (one for a number, three for a vector), when both are
    /// numbers: what the `direction` feedback reads.
    pub difference: Option<Vec<f64>>,
    /// Why it is wrong, without giving the answer away (every wrong mark has one): "no answer",
    /// "not a number", "not within the tolerance", …
    pub note: Option<String>,
    /// The answer is missing or cannot be read as the kind asked for (a problem with the
    /// submission, which `grade` reports, rather than a wrong answer).
    pub unreadable: bool,
    /// The classic mistake the wrong answer matches (see [`super::mistakes::annotate`]).
    pub mistake: Option<super::Mistake>,
}

impl Mark {
    fn wrong(note: impl Into<String>) -> Mark {
        Mark {
            right: false,
            abs_error: None,
            rel_error: None,
            difference: None,
            note: Some(note.into()),
            unreadable: false,
            mistake: None,
        }
    }
    fn unreadable(note: impl Into<String>) -> Mark {
        Mark {
            unreadable: true,
            ..Mark::wrong(note)
        }
    }
    fn right() -> Mark {
        Mark {
            right: true,
            abs_error: None,
            rel_error: None,
            difference: None,
            note: None,
            unreadable: false,
            mistake: None,
        }
    }
}

/// How much a sheet tells a student about a wrong answer (the sheet's `feedback` key). Every
/// policy says *why* an answer is wrong when it is not a matter of distance (unreadable, `none`
/// where the tracer computed a value, …).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Feedback {
    /// Right or wrong only (the default: it never gives the answer away).
    #[default]
    RightWrong,
    /// Also whether a number is too high or too low (for a vector: its farthest component).
    Direction,
    /// Also how far off, absolute and relative (narrows the answer down at once).
    Distance,
    /// Right or wrong, and the tracer's answer once the student has tried this many times.
    ShowAfter(u32),
}

impl Feedback {
    /// The name used in sheets (`right_wrong`, `direction`, `distance`, `show_after = N`).
    pub fn describe(self) -> String {
        match self {
            Feedback::RightWrong => "right_wrong".into(),
            Feedback::Direction => "direction".into(),
            Feedback::Distance => "distance".into(),
            Feedback::ShowAfter(n) => format!("show_after = {n}"),
        }
    }

    /// What to tell the student about `m` after `tries` checks (the one being reported included)
    /// of an answer whose expected value is `expected`; empty for a right answer with nothing to add.
    pub fn explain(self, m: &Mark, expected: &Answer, tries: u32) -> String {
        let mut parts: Vec<String> = vec![];
        if let Some(n) = &m.note {
            parts.push(n.clone());
        }
        match self {
            Feedback::RightWrong => {}
            Feedback::Direction if !m.right => {
                if let Some(d) = &m.difference {
                    parts.push(direction(d));
                }
            }
            Feedback::Direction => {}
            Feedback::Distance => {
                if let Some(a) = m.abs_error {
                    let mut s = format!("off by {}", short(a));
                    if let Some(r) = m.rel_error {
                        s += &format!(" ({}%)", short(r * 100.0));
                    }
                    parts.push(s);
                }
            }
            Feedback::ShowAfter(n) => {
                if !m.right && tries >= n {
                    parts.push(format!("the tracer's answer is {}", show(expected)));
                } else if !m.right {
                    let left = n - tries;
                    parts.push(format!(
                        "the answer is shown after {left} more tr{}",
                        if left == 1 { "y" } else { "ies" }
                    ));
                }
            }
        }
        parts.join("; ")
    }
}

/// "too high" / "too low" for a number; for a vector, its component farthest off.
fn direction(d: &[f64]) -> String {
    let word = |x: f64| if x > 0.0 { "too high" } else { "too low" };
    match d {
        [x] => word(*x).into(),
        _ => {
            let (i, x) = d
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
                .map_or((0, 0.0), |(i, x)| (i, *x));
            let axis = ["x", "y", "z"].get(i).copied().unwrap_or("a component");
            format!("{axis} is farthest off: {}", word(x))
        }
    }
}

/// An expected answer for a student: the tracer's numbers are f32, so they print as f32.
pub fn show(a: &Answer) -> String {
    let f = |x: f64| crate::record::number::num(x as f32);
    match a {
        Answer::Number(x) => f(*x),
        Answer::Vector(v) => format!("({}, {}, {})", f(v[0]), f(v[1]), f(v[2])),
        other => other.to_string(),
    }
}

/// A number with three significant digits (the exercise feedback's and the app's point counts).
pub fn short(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&x.abs()) {
        let decimals = (2 - x.abs().log10().floor() as i32).clamp(0, 5) as usize;
        let s = format!("{x:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{x:.2e}")
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

/// A number, with a decimal point or, as a class in much of Europe writes it, one decimal comma
/// (`1,5`: a single comma between digits; a vector's commas separate its components instead).
fn number(s: &str) -> Option<f64> {
    let s = s.trim();
    let comma = match s.split_once(',') {
        Some((a, b))
            if !b.contains(',')
                && !s.contains('.')
                && a.trim_start_matches(['-', '+'])
                    .chars()
                    .all(|c| c.is_ascii_digit())
                && !a.trim_start_matches(['-', '+']).is_empty()
                && !b.is_empty()
                && b.chars().all(|c| c.is_ascii_digit()) =>
        {
            Some(format!("{a}.{b}"))
        }
        _ => None,
    };
    comma
        .as_deref()
        .unwrap_or(s)
        .parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
}

/// Three numbers; or a lone 0, the zero vector (as a sheet's "0 if the shadow ray is blocked"
/// invites).
fn vector(s: &str) -> Option<[f64; 3]> {
    let s = s.trim();
    if number(s) == Some(0.0) {
        return Some([0.0; 3]);
    }
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

fn by_distance(d: f64, scale: f64, difference: Vec<f64>, tol: Tolerance) -> Mark {
    let rel = Tolerance::relative_error(d, scale);
    let right = tol.allows_distance(d, scale);
    Mark {
        right,
        abs_error: Some(d),
        rel_error: rel,
        difference: Some(difference),
        unreadable: false,
        mistake: None,
        note: (!right).then(|| format!("not within the tolerance ({})", describe_tolerance(tol))),
    }
}

/// A number the student typed, taken as the tracer's f32 when it rounds to that very f32. The
/// key prints an f32 result in its shortest digits (`0.51621705`), and those digits read as an
/// f64 are not the f32's value (0.516217052936553955078125): a sheet whose tolerance is 0, or
/// finer than an f32's precision, marked the key's own answer wrong (found by the `sheet`
/// fuzzer). An expected value that is no f32 (an f64 result, printed in its own shortest
/// digits) or is not finite is compared as typed.
fn as_tracer_f32(given: f64, expected: f64) -> f64 {
    let tracer_f32 = expected.is_finite() && f64::from(expected as f32) == expected;
    if tracer_f32 && f64::from(given as f32) == expected {
        expected
    } else {
        given
    }
}

/// A tolerance in words: "± 0.001 or 0.1%", or only the part that is set.
pub fn describe_tolerance(tol: Tolerance) -> String {
    match (tol.abs > 0.0, tol.rel > 0.0) {
        (true, true) => format!("± {} or {}%", short(tol.abs), short(tol.rel * 100.0)),
        (true, false) => format!("± {}", short(tol.abs)),
        (false, true) => format!("{}%", short(tol.rel * 100.0)),
        (false, false) => "exactly".into(),
    }
}

/// Marks a student's answer (raw text; `None` or blank = missing) against the expected one.
/// Never fails: a missing or unreadable answer is wrong, and every wrong mark says why (without
/// giving the answer away: see [`Feedback`] for what else a student is told).
pub fn mark(expected: &Answer, kind: AnswerKind, given: Option<&str>, tol: Tolerance) -> Mark {
    let Some(given) = given.map(unquote).filter(|s| !s.is_empty()) else {
        return Mark::unreadable("no answer");
    };
    if is_none(given) {
        return match expected {
            Answer::None => Mark::right(),
            _ => Mark::wrong(
                "not none: the tracer does compute this quantity for your pixel (the ray gets \
                 that far)",
            ),
        };
    }
    let unreadable = || Mark::unreadable(format!("\"{given}\" is not {}", kind.describe()));
    let readable = match kind {
        AnswerKind::Number => number(given).is_some(),
        AnswerKind::Vector => vector(given).is_some(),
        AnswerKind::YesNo => yes_no(given).is_some(),
        AnswerKind::Name => true,
    };
    if !readable {
        return unreadable();
    }
    match expected {
        // Worded like any other wrong answer: saying that the tracer computes nothing here
        // would give the answer ("none") away.
        Answer::None => Mark::wrong("not what the tracer found for your pixel"),
        Answer::Number(e) => match number(given) {
            Some(g) => {
                let g = as_tracer_f32(g, *e);
                by_distance((g - e).abs(), e.abs(), vec![g - e], tol)
            }
            None => unreadable(),
        },
        Answer::Vector(e) => match vector(given) {
            Some(g) => {
                let diff: Vec<f64> = (0..3).map(|i| as_tracer_f32(g[i], e[i]) - e[i]).collect();
                let d = diff.iter().map(|c| c * c).sum::<f64>().sqrt();
                let n = e.iter().map(|c| c * c).sum::<f64>().sqrt();
                by_distance(d, n, diff, tol)
            }
            None => unreadable(),
        },
        Answer::YesNo(e) => match yes_no(given) {
            Some(g) if g == *e => Mark::right(),
            Some(_) => Mark::wrong("not what the tracer found"),
            None => unreadable(),
        },
        // Names in any case (`Middle` for `middle`), Unicode included.
        Answer::Name(e) if given.to_lowercase() == e.trim().to_lowercase() => Mark::right(),
        Answer::Name(_) => Mark::wrong(format!(
            "the ray does not hit an object called \"{given}\" (names are the scene's `name`s, \
             in any case)"
        )),
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
    // A byte-order mark (editors on Windows write one) is not part of the first key.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
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

    /// The f32 nearest 0.51621705 is 0.516217052936553955078125 (bits 0x3F0426CD; Python's
    /// `struct` and `decimal` modules, outside this code); its shortest digits, typed back, are
    /// that f32 at any tolerance, 0 included, though as an f64 they are another number.
    #[test]
    fn the_digits_the_key_prints_are_right_at_a_zero_tolerance() {
        let e = 0.516_217_052_936_554_f64;
        assert_eq!(f64::from(0.51621705_f32), e);
        let exact = Tolerance::within_either(0.0, 0.0);
        let number = |given: &str| mark(&Answer::Number(e), AnswerKind::Number, Some(given), exact);
        assert_eq!(Answer::Number(e).to_string(), "0.51621705");
        assert!(number("0.51621705").right);
        assert!(number("0.516217052936553955078125").right);
        // The neighbouring f32s, and digits between two f32s that round to the other, are not.
        assert!(!number("0.5162171").right);
        assert!(!number("0.51621699").right);
        let m = number("0.516217");
        assert!(!m.right && m.abs_error.is_some_and(|d| d > 5e-8));
        let v = [e, -2.5, 1.0e-3_f32 as f64];
        let vector = |given: &str| mark(&Answer::Vector(v), AnswerKind::Vector, Some(given), exact);
        assert_eq!(Answer::Vector(v).to_string(), "0.51621705, -2.5, 0.001");
        assert!(vector("0.51621705, -2.5, 0.001").right);
        assert!(!vector("0.51621705, -2.5, 0.0011").right);
        // An f64 result is printed in its own shortest digits and compared as typed.
        let f = 0.1_f64 + 0.2;
        let key = Answer::Number(f).to_string();
        assert!(mark(&Answer::Number(f), AnswerKind::Number, Some(&key), exact).right);
        assert!(!mark(&Answer::Number(f), AnswerKind::Number, Some("0.3"), exact).right);
    }

    #[test]
    fn numbers_vectors_names_and_none() {
        let t = crate::lesson::DEFAULT_TOLERANCE;
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
    fn names_in_any_case_and_every_wrong_mark_says_why() {
        let t = crate::lesson::DEFAULT_TOLERANCE;
        let middle = Answer::Name("middle".into());
        assert!(mark(&middle, AnswerKind::Name, Some("Middle"), t).right);
        assert!(mark(&middle, AnswerKind::Name, Some("MIDDLE"), t).right);
        assert!(
            mark(
                &Answer::Name("Kugel-Ä".into()),
                AnswerKind::Name,
                Some("kugel-ä"),
                t
            )
            .right
        );
        let cases = [
            (middle.clone(), AnswerKind::Name, "floor"),
            (middle.clone(), AnswerKind::Name, "none"),
            (Answer::None, AnswerKind::Number, "2.5"),
            (Answer::None, AnswerKind::Name, "middle"),
            (Answer::Number(4.0), AnswerKind::Number, "none"),
            (Answer::Number(4.0), AnswerKind::Number, "5"),
            (Answer::YesNo(true), AnswerKind::YesNo, "no"),
            (
                Answer::Vector([0.0, 0.0, 1.0]),
                AnswerKind::Vector,
                "0, 1, 0",
            ),
        ];
        for (e, k, g) in cases {
            let m = mark(&e, k, Some(g), t);
            assert!(!m.right, "{g} for {e}");
            let note = m.note.unwrap_or_default();
            assert!(!note.is_empty(), "no reason for {g} against {e}");
            // The reason never contains the expected number.
            if let Answer::Number(x) = e {
                assert!(!note.contains(&format!("{x}")), "{note}");
            }
        }
    }

    #[test]
    fn feedback_policies() {
        let t = crate::lesson::DEFAULT_TOLERANCE;
        let e = Answer::Number(3.65);
        let m = mark(&e, AnswerKind::Number, Some("1"), t);
        let rw = Feedback::RightWrong.explain(&m, &e, 1);
        assert!(
            !rw.contains("2.65") && !rw.contains("3.65") && !rw.contains("72"),
            "{rw}"
        );
        assert!(rw.contains("tolerance"), "{rw}");
        assert!(Feedback::Direction.explain(&m, &e, 1).contains("too low"));
        let high = mark(&e, AnswerKind::Number, Some("9"), t);
        assert!(
            Feedback::Direction
                .explain(&high, &e, 1)
                .contains("too high")
        );
        // 3.65 − 1 = 2.65 off, 72.6 % of 3.65.
        let d = Feedback::Distance.explain(&m, &e, 1);
        assert!(d.contains("off by 2.65") && d.contains("72.6%"), "{d}");
        let s = Feedback::ShowAfter(3);
        assert!(!s.explain(&m, &e, 2).contains("3.65"));
        assert!(s.explain(&m, &e, 2).contains("1 more try"));
        assert!(s.explain(&m, &e, 3).contains("3.65"));
        let v = Answer::Vector([0.0, 0.0, 1.0]);
        let mv = mark(&v, AnswerKind::Vector, Some("0, -0.5, 1"), t);
        assert_eq!(
            Feedback::Direction.explain(&mv, &v, 1).split("; ").last(),
            Some("y is farthest off: too low")
        );
    }

    #[test]
    fn a_byte_order_mark_is_not_part_of_the_first_key() {
        let ok = parse_answers("\u{feff}a = 1\nb = 2\n", "ans.txt", &["a", "b"]).unwrap();
        assert_eq!(ok["a"], "1");
    }

    #[test]
    fn answers_file_errors_name_the_line() {
        let e = parse_answers("a = 1\nb 2\n", "ans.txt", &["a", "b"]).unwrap_err();
        assert!(e.starts_with("ans.txt:2:"), "{e}");
        let ok = parse_answers("# c\na = 1 # why\nb = \"x # y\"\n", "f", &["a", "b"]).unwrap();
        assert_eq!(ok["a"], "1");
        assert_eq!(ok["b"], "\"x # y\"");
    }

    #[test]
    fn answers_print_their_numbers_as_the_trace_does() {
        // The tracer's f32, widened to f64 for marking: printed as the trace prints the f32.
        let t = 5.573929f32;
        assert_eq!(Answer::Number(t as f64).to_string(), "5.573929");
        assert_eq!(
            Answer::Number(t as f64).to_string(),
            crate::record::number::num(t)
        );
        assert_eq!(
            Answer::Vector([0.1f32 as f64, -0.0, 2.5e-7f32 as f64]).to_string(),
            "0.1, -0, 2.5e-7"
        );
        // A count, and a number no f32 holds, keep every digit they have.
        assert_eq!(Answer::Number(7.0).to_string(), "7");
        assert_eq!(Answer::Number(0.1).to_string(), "0.1");
        assert_eq!(Answer::Number(1.0 / 3.0).to_string(), "0.3333333333333333");
    }
}
