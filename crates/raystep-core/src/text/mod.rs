//! Plain-text helpers shared by the readers of hand-written files (scenes, exercise sheets,
//! lessons' front matter, tracer grading sheets, class CSVs): where a byte offset is, as an
//! editor shows it, and [`csv`] reading and writing.

pub mod csv;

/// 1-based line and column of byte `pos` in `text`, columns counted in characters as an editor
/// counts them, not bytes. A `pos` past the end means the end; one inside a character, that
/// character.
pub fn line_col(text: &str, pos: usize) -> (usize, usize) {
    let pos = text.floor_char_boundary(pos);
    let before = &text[..pos];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |nl| nl + 1);
    let col = before[line_start..].chars().count() + 1;
    (line, col)
}

/// A parser's message with every number longer than 24 characters (`0.000…0001`, as TOML's
/// reader quotes `1e-300` back) written in scientific notation, so an error line stays short.
pub fn shorten_numbers(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(start) = rest.find(|c: char| c.is_ascii_digit()) {
        let (before, from) = rest.split_at(start);
        out += before;
        let len = from
            .find(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-')))
            .unwrap_or(from.len());
        let (number, after) = from.split_at(len);
        match number.parse::<f64>() {
            Ok(x) if number.len() > 24 => out += &format!("{x:e}"),
            _ => out += number,
        }
        rest = after;
    }
    out + rest
}

/// The SHA-256 of `bytes` in lower-case hex: how a saved trace names the scene file it came
/// from.
pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::line_col;

    #[test]
    fn lines_and_columns_count_characters() {
        let text = "a = 1\nπ = \"x\"\n";
        assert_eq!(line_col(text, 0), (1, 1));
        assert_eq!(line_col(text, 6), (2, 1));
        // After "π = " (π is two bytes): the fifth character.
        assert_eq!(line_col(text, 6 + 2 + 3), (2, 5));
        // Inside π: π itself.
        assert_eq!(line_col(text, 7), (2, 1));
        assert_eq!(line_col(text, 1000), (3, 1));
    }
}
