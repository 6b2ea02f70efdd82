//! Per-student draws: every student gets their own variant of an exercise sheet's questions
//! ([`crate::lesson`]: parameters and pixels) and of a tracer grading sheet's scenes
//! ([`crate::student`]: scene values and pixels), deterministically — the same student id always
//! draws the same numbers, different ids (almost always) different ones.
//!
//! A draw is SHA-256 of `raystep-exercise`, the sheet, the question (or scene file), the student
//! and the parameter's name, each followed by a zero byte; its first eight bytes, little-endian,
//! are the 64 bits [`uniform`] and [`pick_int`] turn into a number. Changing any of this changes
//! every student's variant, so it is fixed.

use sha2::{Digest, Sha256};

/// 64 random bits from the sheet, the question (or scene), the student and the parameter.
pub(crate) fn draw(sheet: &str, question: &str, student: &str, name: &str) -> u64 {
    let mut h = Sha256::new();
    for part in ["raystep-exercise", sheet, question, student, name] {
        h.update(part.as_bytes());
        h.update([0u8]);
    }
    let d = h.finalize();
    u64::from_le_bytes(d[..8].try_into().expect("eight bytes"))
}

/// A number in [0, 1) from a draw's top 53 bits.
pub(crate) fn uniform(bits: u64) -> f64 {
    (bits >> 11) as f64 / (1u64 << 53) as f64
}

/// An integer in `lo ..= hi` (lo ≤ hi) from a draw: the bits modulo the range's size.
pub(crate) fn pick_int(bits: u64, lo: i64, hi: i64) -> i64 {
    let span = (hi as i128 - lo as i128 + 1) as u128;
    (lo as i128 + (bits as u128 % span) as i128) as i64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn int_draws_cover_the_range() {
        let mut seen = [false; 3];
        for i in 0..100u64 {
            seen[(pick_int(i.wrapping_mul(0x9e3779b97f4a7c15), 1, 3) - 1) as usize] = true;
        }
        assert_eq!(seen, [true; 3]);
    }

    #[test]
    fn draws_are_fixed() {
        // `printf 'raystep-exercise\0s\0q\0ada\0r\0' | sha256sum` begins 8dceff87757977bc: its
        // first eight bytes, little-endian.
        let want = 0xbc77_7975_87ff_ce8d;
        assert_eq!(draw("s", "q", "ada", "r"), want);
        assert_eq!(uniform(0), 0.0);
        assert!(uniform(u64::MAX) < 1.0);
        assert_eq!(pick_int(u64::MAX, i64::MIN, i64::MAX), i64::MAX);
    }
}
