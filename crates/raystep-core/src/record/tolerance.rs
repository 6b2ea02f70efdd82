//! When two numbers are equal enough: one [`Tolerance`] type, with the rule named.
//!
//! raystep compares numbers in three places, and each has its own, deliberately different rule
//! ([`Rule`]):
//!
//! | rule | passes when | used by |
//! |------|-------------|---------|
//! | [`Rule::RelativeToLarger`] | \|a − b\| ≤ max(abs, rel·max(\|a\|, \|b\|)) | `raystep diff` ([`crate::explain::diff`]): neither trace is the reference |
//! | [`Rule::AbsPlusRel`] | \|got − want\| ≤ abs + rel·\|want\| | `raystep grade-tracer` ([`crate::student::compare`]): raystep's number is the reference |
//! | [`Rule::WithinEither`] | \|got − want\| ≤ abs, or \|got − want\| / \|want\| ≤ rel | exercise sheets ([`crate::lesson::mark`]): a student's hand-typed answer |
//!
//! ```
//! use raystep_core::record::Tolerance;
//!
//! // 1.0015 against 1: 0.0015 off.
//! assert!(!Tolerance::relative_to_larger(1e-3, 1e-3).allows(1.0015, 1.0)); // max(1e-3, ~1e-3)
//! assert!(Tolerance::abs_plus_rel(1e-3, 1e-3).allows(1.0015, 1.0)); // 1e-3 + 1e-3
//! assert!(!Tolerance::within_either(1e-3, 1e-3).allows(1.0015, 1.0)); // neither part alone
//! ```

use serde::Serialize;

/// Which formula a [`Tolerance`] applies (see the [module](self) table).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Rule {
    /// |a − b| ≤ max(abs, rel·max(|a|, |b|)): symmetric, the relative part scales with the larger
    /// magnitude. For [`Tolerance::allows`], NaN equals NaN and ±∞ equals only the same
    /// infinity (a trace may hold either, and two equal traces must compare equal).
    RelativeToLarger,
    /// |got − want| ≤ abs + rel·|want|: the two parts add, the relative part scales with the
    /// reference value. NaN and ∞ never pass (the arithmetic says so).
    AbsPlusRel,
    /// |got − want| ≤ abs, or (want ≠ 0 and) |got − want| / |want| ≤ rel: right when close in
    /// either sense alone. NaN never passes.
    WithinEither,
}

/// How close two numbers must be, and by which [`Rule`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Tolerance {
    /// The absolute part.
    pub abs: f64,
    /// The relative part (a fraction of the magnitude the rule names).
    pub rel: f64,
    /// How the two parts combine.
    pub rule: Rule,
}

impl Tolerance {
    /// Exact comparison ([`Rule::RelativeToLarger`] with both parts 0): equal numbers only,
    /// 0 equal to −0, NaN equal to NaN, each infinity equal to itself.
    pub const EXACT: Tolerance = Tolerance::relative_to_larger(0.0, 0.0);

    /// |a − b| ≤ max(abs, rel·max(|a|, |b|)) ([`Rule::RelativeToLarger`]).
    pub const fn relative_to_larger(abs: f64, rel: f64) -> Tolerance {
        Tolerance {
            abs,
            rel,
            rule: Rule::RelativeToLarger,
        }
    }

    /// |got − want| ≤ abs + rel·|want| ([`Rule::AbsPlusRel`]).
    pub const fn abs_plus_rel(abs: f64, rel: f64) -> Tolerance {
        Tolerance {
            abs,
            rel,
            rule: Rule::AbsPlusRel,
        }
    }

    /// |got − want| ≤ abs, or |got − want| / |want| ≤ rel ([`Rule::WithinEither`]).
    pub const fn within_either(abs: f64, rel: f64) -> Tolerance {
        Tolerance {
            abs,
            rel,
            rule: Rule::WithinEither,
        }
    }

    /// The same rule and relative part with another absolute part.
    pub const fn with_abs(self, abs: f64) -> Tolerance {
        Tolerance { abs, ..self }
    }

    /// Whether `got` is close enough to `want` (for [`Rule::RelativeToLarger`] the order does
    /// not matter).
    pub fn allows(&self, got: f64, want: f64) -> bool {
        match self.rule {
            Rule::RelativeToLarger => {
                if got.is_nan() || want.is_nan() {
                    return got.is_nan() && want.is_nan();
                }
                if got.is_infinite() || want.is_infinite() {
                    return got == want;
                }
                self.allows_distance((got - want).abs(), got.abs().max(want.abs()))
            }
            Rule::AbsPlusRel | Rule::WithinEither => {
                self.allows_distance((got - want).abs(), want.abs())
            }
        }
    }

    /// Whether a `distance` (|got − want|, or the Euclidean distance of two vectors) is close
    /// enough, the relative part scaling `size`: the reference's magnitude (|want|, or the
    /// vector's length) for [`Rule::AbsPlusRel`] and [`Rule::WithinEither`], the larger of the
    /// two magnitudes for [`Rule::RelativeToLarger`]. A NaN distance never passes.
    pub fn allows_distance(&self, distance: f64, size: f64) -> bool {
        match self.rule {
            Rule::RelativeToLarger => distance <= self.abs.max(self.rel * size),
            Rule::AbsPlusRel => distance <= self.abs + self.rel * size,
            Rule::WithinEither => {
                distance <= self.abs
                    || Self::relative_error(distance, size).is_some_and(|r| r <= self.rel)
            }
        }
    }

    /// distance / size, the relative error [`Rule::WithinEither`] compares with `rel`; None when
    /// `size` is 0 (every relative error of a zero reference is infinite or undefined).
    pub fn relative_error(distance: f64, size: f64) -> Option<f64> {
        (size != 0.0).then(|| distance / size)
    }
}
