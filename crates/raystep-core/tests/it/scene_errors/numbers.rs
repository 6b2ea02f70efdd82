//! Numbers: NaN, infinities, values past f32, colours and settings out of range.

use super::*;

fn sphere_with(line3: &str) -> (Written, SceneError) {
    fail(&[
        "[[sphere]]",      // 1
        "name = \"ball\"", // 2
        line3,             // 3
    ])
}

#[test]
fn nan_in_a_vector() {
    let (w, e) = sphere_with("center = [0, nan, 0]");
    check(
        &w,
        &e,
        (3, 1),
        "sphere \"ball\"",
        "center",
        &["finite", "NaN"],
    );
}

#[test]
fn inf_in_a_vector() {
    let (w, e) = sphere_with("center = [inf, 0, 0]");
    check(
        &w,
        &e,
        (3, 1),
        "sphere \"ball\"",
        "center",
        &["finite", "inf"],
    );
}

#[test]
fn nan_in_a_scalar() {
    let (w, e) = sphere_with("radius = nan");
    check(
        &w,
        &e,
        (3, 1),
        "sphere \"ball\"",
        "radius",
        &["finite", "NaN"],
    );
}

#[test]
fn inf_in_a_scalar() {
    let (w, e) = sphere_with("radius = inf");
    check(
        &w,
        &e,
        (3, 1),
        "sphere \"ball\"",
        "radius",
        &["finite", "inf"],
    );
}

#[test]
fn negative_inf_in_a_scalar() {
    let (w, e) = sphere_with("radius = -inf");
    check(
        &w,
        &e,
        (3, 1),
        "sphere \"ball\"",
        "radius",
        &["finite", "-inf"],
    );
}

/// 1e39 is a finite number, but not an f32 (largest ≈ 3.4e38): the message must say so in a way
/// a student recognises (their number, and why it is refused), not call 1e39 "not finite".
fn says_too_large_for_f32(e: &SceneError) {
    assert!(
        e.message.contains("1e39") || e.message.contains("1e+39"),
        "message does not show 1e39 as written: {e}"
    );
    assert!(
        e.message.contains("f32") || e.message.contains("too large") || e.message.contains("3.4"),
        "message does not say the number is too large for f32: {e}"
    );
}

#[test]
fn scalar_overflowing_f32() {
    let (w, e) = sphere_with("radius = 1e39");
    assert_at(&w, &e, 3, 1);
    assert_field(&e, "sphere \"ball\"", "radius");
    says_too_large_for_f32(&e);
}

#[test]
fn vector_overflowing_f32() {
    let (w, e) = sphere_with("center = [0, 1e39, 0]");
    assert_at(&w, &e, 3, 1);
    assert_field(&e, "sphere \"ball\"", "center");
    says_too_large_for_f32(&e);
}

#[test]
fn negative_colour() {
    let (w, e) = fail(&[
        "[[material]]",         // 1
        "name = \"red\"",       // 2
        "color = [1, -0.5, 0]", // 3
    ]);
    check(
        &w,
        &e,
        (3, 1),
        "material \"red\"",
        "color",
        &["negative", "-0.5"],
    );
}

#[test]
fn reflective_above_one() {
    let (w, e) = fail(&[
        "[[material]]",      // 1
        "name = \"mirror\"", // 2
        "reflective = 1.5",  // 3
    ]);
    check(
        &w,
        &e,
        (3, 1),
        "material \"mirror\"",
        "reflective",
        &["[0, 1]", "1.5"],
    );
}

// ---------------------------------------------------------------------------------------------
// [render]

#[test]
fn unknown_sphere_method() {
    let (w, e) = fail(&[
        "[render]",                 // 1
        "max_depth = 3",            // 2
        "sphere_method = \"fast\"", // 3
    ]);
    check(
        &w,
        &e,
        (3, 1),
        "render",
        "sphere_method",
        &["\"fast\"", "\"textbook\"", "\"stable\""],
    );
}

#[test]
fn unknown_offset() {
    let (w, e) = fail(&[
        "[render]",          // 1
        "offset = \"tiny\"", // 2
    ]);
    check(
        &w,
        &e,
        (2, 1),
        "render",
        "offset",
        &["\"tiny\"", "\"none\"", "\"fixed\"", "\"robust\""],
    );
}

#[test]
fn unknown_accel() {
    let (w, e) = fail(&[
        "[render]",            // 1
        "spp = 1",             // 2
        "accel = \"kd-tree\"", // 3
    ]);
    check(
        &w,
        &e,
        (3, 1),
        "render",
        "accel",
        &["\"kd-tree\"", "\"auto\"", "\"bvh\""],
    );
}

#[test]
fn unknown_bvh_quality() {
    let (w, e) = fail(&[
        "[render]",               // 1
        "accel = \"bvh\"",        // 2
        "bvh_quality = \"best\"", // 3
    ]);
    check(
        &w,
        &e,
        (3, 1),
        "render",
        "bvh_quality",
        &["\"best\"", "\"low\"", "\"medium\"", "\"high\""],
    );
}

#[test]
fn spp_zero() {
    let (w, e) = fail(&[
        "[render]", // 1
        "spp = 0",  // 2
    ]);
    check(&w, &e, (2, 1), "render", "spp", &["got 0"]);
}

// ---------------------------------------------------------------------------------------------
