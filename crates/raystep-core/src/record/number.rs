//! One number formatter, with named styles, for everything that shows a recorded number: the
//! math panel, the diagrams, the command line, the lessons and the exercise feedback.
//!
//! Every style writes infinities as `∞` / `-∞` and NaN as `NaN`, and uses the ASCII minus sign,
//! so a number copied from any of them pastes into a calculator or a Python prompt.
//!
//! ```
//! use raystep_core::record::number::{Style, fmt, num};
//!
//! assert_eq!(num(0.1), "0.1"); // the shortest text that reads back as the same f32
//! assert_eq!(num(1e-6), "1e-6");
//! assert_eq!(num(f32::NEG_INFINITY), "-∞");
//! assert_eq!(fmt(2.0f32 / 3.0, Style::Label), "0.6667");
//! assert_eq!(fmt(4.0, Style::Label), "4"); // exact, so no zeros
//! assert_eq!(fmt(-0.0001, Style::Decimals(3)), "0"); // never "-0" on a drawing
//! ```

/// How a number is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// The shortest text that reads back as the same value (every digit the renderer used);
    /// scientific for magnitudes below 10⁻⁴ or from 10⁹ up, which would otherwise print as
    /// dozens of zeros. `-0` stays `-0`: the sign of zero decides a slab's direction. For the
    /// math panel, the command line and the trace tree.
    Exact,
    /// Four significant digits for labels on a drawing; trailing zeros dropped only when what is
    /// left is the exact value (so `4` means 4 and `4.000` means about 4); exponent form outside
    /// 10⁻³ … 10⁵.
    Label,
    /// At most this many decimals, trailing zeros dropped, `-0` written `0`: coordinates and
    /// angles on small drawings.
    Decimals(u8),
}

/// A single-precision number in a style.
pub fn fmt(x: f32, style: Style) -> String {
    match style {
        Style::Exact => match special(x as f64) {
            Some(s) => s.into(),
            None if x != 0.0 && (x.abs() < 1e-4 || x.abs() >= 1e9) => format!("{x:e}"),
            None => format!("{x}"),
        },
        // A label for an f32 is exact when it reads back as that f32.
        Style::Label => significant4(x as f64, |s| s.parse::<f32>().is_ok_and(|p| p == x)),
        Style::Decimals(_) => fmt64(x as f64, style),
    }
}

/// A double-precision number in a style.
pub fn fmt64(x: f64, style: Style) -> String {
    match style {
        Style::Exact => match special(x) {
            Some(s) => s.into(),
            None if x != 0.0 && (x.abs() < 1e-4 || x.abs() >= 1e9) => format!("{x:e}"),
            None => format!("{x}"),
        },
        Style::Label => significant4(x, |s| s.parse::<f64>() == Ok(x)),
        Style::Decimals(n) => {
            if let Some(s) = special(x) {
                return s.into();
            }
            let n = n as usize;
            let s = format!("{x:.n$}");
            let s = if s.contains('.') {
                s.trim_end_matches('0').trim_end_matches('.')
            } else {
                &s
            };
            if s == "-0" { "0".into() } else { s.into() }
        }
    }
}

/// [`Style::Exact`] for an f32: the math panel's and the command line's numbers.
pub fn num(x: f32) -> String {
    fmt(x, Style::Exact)
}

/// [`Style::Label`] for an f32: numbers written on a drawing.
pub fn label(x: f32) -> String {
    fmt(x, Style::Label)
}

/// A vector in [`Style::Exact`], e.g. `(0, 1.5, -5)`.
pub fn v3(v: [f32; 3]) -> String {
    v3_in(v, Style::Exact)
}

/// A vector in a named style, e.g. `(0.63, 0.065, 0.05)` in `Style::Decimals(3)`.
pub fn v3_in(v: [f32; 3], style: Style) -> String {
    format!(
        "({}, {}, {})",
        fmt(v[0], style),
        fmt(v[1], style),
        fmt(v[2], style)
    )
}

/// An optional number: `—` when the record has none (an older trace, or a step that did not
/// compute it).
pub fn opt(x: Option<f32>) -> String {
    x.map_or("—".into(), num)
}

fn special(x: f64) -> Option<&'static str> {
    if x.is_nan() {
        Some("NaN")
    } else if x == f64::INFINITY {
        Some("∞")
    } else if x == f64::NEG_INFINITY {
        Some("-∞")
    } else {
        None
    }
}

/// Four significant digits; `reads_back` says whether a trimmed text is the exact value.
fn significant4(x: f64, reads_back: impl Fn(&str) -> bool) -> String {
    if let Some(s) = special(x) {
        return s.into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let a = x.abs();
    let s = if (1e-3..1e5).contains(&a) {
        // 3 − ⌊log₁₀ a⌋ lies in 0 … 6 inside this range; the constant bounds only guard rounding.
        let decimals = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.3e}")
    };
    let (mantissa, exp) = match s.split_once('e') {
        Some((m, e)) => (m.to_string(), format!("e{e}")),
        None => (s.clone(), String::new()),
    };
    let trimmed = if mantissa.contains('.') {
        mantissa.trim_end_matches('0').trim_end_matches('.')
    } else {
        &mantissa
    };
    let exact = format!("{trimmed}{exp}");
    if reads_back(&exact) {
        exact
    } else {
        format!("{mantissa}{exp}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_style_writes_the_same_infinities_and_nan() {
        for style in [
            Style::Exact,
            Style::Label,
            Style::Decimals(1),
            Style::Decimals(3),
        ] {
            assert_eq!(fmt(f32::INFINITY, style), "∞");
            assert_eq!(fmt(f32::NEG_INFINITY, style), "-∞");
            assert_eq!(fmt(f32::NAN, style), "NaN");
            assert_eq!(fmt64(f64::NEG_INFINITY, style), "-∞");
        }
    }

    #[test]
    fn exact_reads_back_bit_for_bit() {
        for x in [
            0.1f32,
            -3.25,
            1e-7,
            6.02e23,
            f32::MIN_POSITIVE,
            -0.0,
            123456.79,
        ] {
            let back: f32 = num(x).parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{x} → {}", num(x));
        }
        assert_eq!(num(-0.0), "-0");
        assert_eq!(num(2.5e12), "2.5e12");
    }

    #[test]
    fn labels_and_decimals_by_hand() {
        assert_eq!(fmt(1.0 / 3.0, Style::Label), "0.3333");
        assert_eq!(fmt(12345.678, Style::Label), "12346");
        assert_eq!(fmt(-2.5, Style::Label), "-2.5");
        assert_eq!(fmt64(123456.0, Style::Label), "1.235e5");
        assert_eq!(fmt(1.23456, Style::Decimals(1)), "1.2");
        assert_eq!(fmt(-1.25, Style::Decimals(3)), "-1.25");
        assert_eq!(fmt(7.0, Style::Decimals(3)), "7");
        assert_eq!(fmt(-0.04, Style::Decimals(1)), "0");
    }
}
