//! How deeply a JSON text nests, found without recursion, so that a trace can be loaded at every
//! depth raystep writes while a hostile file cannot make the parser recurse past the stack.
//!
//! serde_json stops at 128 levels by default: a trace of a ray 60 bounces deep (two levels a
//! bounce: the `children` list and the ray in it) went past it, and raystep could not load a
//! trace it had written (`--max-depth 64` is accepted). [`Trace::from_json`](super::Trace::from_json)
//! measures the nesting first and parses without serde_json's limit only below [`MAX_NESTING`].

/// The deepest nesting a trace file may have: a ray of depth 64 (the most `max_depth` allows)
/// nests 2 levels a bounce below the trace's own few, with room to spare; far below what the
/// parser's recursion can overflow a thread's stack with (a browser's 1 MiB included).
pub const MAX_NESTING: usize = 2 * 64 + 64;

/// The deepest nesting of objects and arrays in `text` (brackets inside strings, escapes
/// included, are not counted). Stops counting past `stop`.
pub fn depth(text: &str, stop: usize) -> usize {
    let (mut d, mut max) = (0usize, 0usize);
    let (mut in_string, mut escaped) = (false, false);
    for b in text.bytes() {
        if in_string {
            if escaped {
                escaped = false;
            } else if b == b'\\' {
                escaped = true;
            } else if b == b'"' {
                in_string = false;
            }
            continue;
        }
        match b {
            b'"' => in_string = true,
            b'{' | b'[' => {
                d += 1;
                if d > max {
                    max = d;
                    if max > stop {
                        return max;
                    }
                }
            }
            b'}' | b']' => d = d.saturating_sub(1),
            _ => {}
        }
    }
    max
}

/// Parses `text` without serde_json's recursion limit: only for a text whose [`depth`] was
/// checked against [`MAX_NESTING`].
pub fn parse<T: serde::de::DeserializeOwned>(text: &str) -> Result<T, serde_json::Error> {
    let mut de = serde_json::Deserializer::from_str(text);
    de.disable_recursion_limit();
    let v = T::deserialize(&mut de)?;
    de.end()?;
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nesting_counted_outside_strings() {
        assert_eq!(depth("{}", 10), 1);
        assert_eq!(depth("[[1,[2]],{\"a\":[3]}]", 10), 3);
        // Brackets in strings, and an escaped quote before them, do not count.
        assert_eq!(depth(r#"{"a":"[[[{{{\"[[["}"#, 10), 1);
        // It stops early on a deep text.
        assert_eq!(depth(&"[".repeat(1000), 5), 6);
    }
}
