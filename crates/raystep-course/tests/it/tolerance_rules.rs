//! The one `Tolerance` type gives the same pass or fail as each of the three rules it replaced,
//! on every input: each rule against its old formula, written out here as the three modules
//! had it (`explain::diff`, `student::compare`, `lesson::answer`), with NaN, ±∞, ±0, subnormal
//! and near-equal numbers in the mix.

use proptest::prelude::*;
use raystep_core::record::Tolerance;
use raystep_course::lesson::{Answer, AnswerKind, DEFAULT_TOLERANCE, mark};
use raystep_course::student::compare::TracerTolerances;

/// `explain::diff`'s rule: |a − b| ≤ max(abs, rel·max(|a|, |b|)); NaN = NaN; ±∞ only itself.
fn old_diff(abs: f64, rel: f64, a: f64, b: f64) -> bool {
    if a.is_nan() || b.is_nan() {
        return a.is_nan() && b.is_nan();
    }
    if a.is_infinite() || b.is_infinite() {
        return a == b;
    }
    (a - b).abs() <= abs.max(rel * a.abs().max(b.abs()))
}

/// `student::compare`'s rule: |yours − want| ≤ abs + rel·|want|.
fn old_student(abs: f64, rel: f64, yours: f64, want: f64) -> bool {
    (yours - want).abs() <= abs + rel * want.abs()
}

/// `student::compare`'s rule for vectors and for the discriminant: d ≤ abs + rel·size.
fn old_student_distance(abs: f64, rel: f64, d: f64, size: f64) -> bool {
    d <= abs + rel * size
}

/// `lesson::answer`'s rule: right when d ≤ abs, or d / scale ≤ rel (scale ≠ 0).
fn old_lesson(abs: f64, rel: f64, d: f64, scale: f64) -> bool {
    let r = if scale != 0.0 { Some(d / scale) } else { None };
    d <= abs || matches!(r, Some(r) if r <= rel)
}

/// Any f64 at all: NaN, ±∞, ±0, subnormals, normals.
fn any() -> impl Strategy<Value = f64> {
    prop_oneof![
        proptest::num::f64::ANY,
        Just(0.0),
        Just(-0.0),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(f64::NAN),
        -10.0..10.0f64,
    ]
}

/// A tolerance part: mostly the small non-negative values sheets use, sometimes anything.
fn part() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => 0.0..0.1f64,
        1 => Just(0.0),
        1 => any(),
    ]
}

/// Two numbers, often close to each other so both outcomes occur.
fn pair() -> impl Strategy<Value = (f64, f64)> {
    prop_oneof![
        (any(), any()),
        (any(), -0.2..0.2f64).prop_map(|(a, d)| (a + d * a.abs().max(1.0), a)),
        (any(), -1e-3..1e-3f64).prop_map(|(a, d)| (a * (1.0 + d), a)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 4096, ..ProptestConfig::default() })]

    #[test]
    fn relative_to_larger_is_the_diff_rule(abs in part(), rel in part(), (a, b) in pair()) {
        let t = Tolerance::relative_to_larger(abs, rel);
        prop_assert_eq!(t.allows(a, b), old_diff(abs, rel, a, b));
        prop_assert_eq!(t.allows(b, a), old_diff(abs, rel, b, a));
    }

    #[test]
    fn abs_plus_rel_is_the_tracer_grading_rule(
        abs in part(), rel in part(), (y, w) in pair(), d in any(), size in any(),
    ) {
        let t = Tolerance::abs_plus_rel(abs, rel);
        prop_assert_eq!(t.allows(y, w), old_student(abs, rel, y, w));
        prop_assert_eq!(t.allows_distance(d, size), old_student_distance(abs, rel, d, size));
        // As the grader builds it from a sheet's `[tolerance]` (also at depth).
        let sheet = TracerTolerances { rel, abs, ..TracerTolerances::default() };
        prop_assert_eq!(sheet.numbers().allows(y, w), old_student(abs, rel, y, w));
        let k = 1.0 + 3.0;
        prop_assert_eq!(
            sheet.at_depth(3).numbers().allows(y, w),
            old_student(abs * k, rel * k, y, w)
        );
    }

    #[test]
    fn within_either_is_the_exercise_rule(
        abs in part(), rel in part(), (g, e) in pair(), d in any(), scale in any(),
    ) {
        let t = Tolerance::within_either(abs, rel);
        prop_assert_eq!(t.allows(g, e), old_lesson(abs, rel, (g - e).abs(), e.abs()));
        prop_assert_eq!(t.allows_distance(d, scale), old_lesson(abs, rel, d, scale));
    }

    /// End to end: `lesson::mark` on a typed number and on a typed vector agrees with the old
    /// rule (answers are finite: anything else is unreadable).
    #[test]
    fn marking_a_typed_answer_follows_the_exercise_rule(
        abs in 0.0..0.1f64, rel in 0.0..0.1f64,
        (g, e) in pair().prop_filter("finite", |(g, e)| g.is_finite() && e.is_finite()),
        (gy, ey) in (-10.0..10.0f64, -10.0..10.0f64),
    ) {
        let t = Tolerance::within_either(abs, rel);
        let m = mark(&Answer::Number(e), AnswerKind::Number, Some(&g.to_string()), t);
        prop_assert_eq!(m.right, old_lesson(abs, rel, (g - e).abs(), e.abs()));

        let (want, given) = ([e, ey, 1.0], [g, gy, 1.0]);
        let diff: Vec<f64> = (0..3).map(|i| given[i] - want[i]).collect();
        let d = diff.iter().map(|c| c * c).sum::<f64>().sqrt();
        let n = want.iter().map(|c| c * c).sum::<f64>().sqrt();
        let text = format!("{}, {}, {}", given[0], given[1], given[2]);
        let m = mark(&Answer::Vector(want), AnswerKind::Vector, Some(&text), t);
        prop_assert_eq!(m.right, old_lesson(abs, rel, d, n), "{}", text);
    }
}

/// Worked cases, figures by hand: 1.0015 against 1 is 0.0015 off, passing only the rule whose
/// two parts add; the sheets' default is ±0.001 or 0.1 %.
#[test]
fn the_three_rules_differ_where_they_should() {
    assert!(!Tolerance::relative_to_larger(1e-3, 1e-3).allows(1.0015, 1.0));
    assert!(Tolerance::abs_plus_rel(1e-3, 1e-3).allows(1.0015, 1.0));
    assert!(!Tolerance::within_either(1e-3, 1e-3).allows(1.0015, 1.0));
    // 1000.9 against 1000: 0.9 off, 0.09 %: within the relative part alone.
    assert!(Tolerance::within_either(1e-3, 1e-3).allows(1000.9, 1000.0));
    assert!(Tolerance::relative_to_larger(1e-3, 1e-3).allows(1000.9, 1000.0));
    // Only the diff rule has NaN equal NaN and ∞ equal ∞.
    for t in [
        Tolerance::abs_plus_rel(1.0, 1.0),
        Tolerance::within_either(1.0, 1.0),
    ] {
        assert!(!t.allows(f64::NAN, f64::NAN));
        assert!(!t.allows(f64::INFINITY, f64::INFINITY));
    }
    assert!(Tolerance::EXACT.allows(f64::NAN, f64::NAN));
    assert!(Tolerance::EXACT.allows(f64::INFINITY, f64::INFINITY));
    assert_eq!(DEFAULT_TOLERANCE, Tolerance::within_either(0.001, 0.001));
    // Within either, with a zero reference: only the absolute part can pass.
    assert!(DEFAULT_TOLERANCE.allows(0.0009, 0.0));
    assert!(!DEFAULT_TOLERANCE.allows(0.0011, 0.0));
}
