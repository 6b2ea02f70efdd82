//! TOML syntax, spheres, planes and the camera: each error at its field.

use super::*;

#[test]
fn toml_syntax_error_is_located() {
    let (w, e) = fail(&[
        "[camera]",      // 1
        "fov = 60",      // 2
        "width = = 320", // 3: the second `=` is column 9
    ]);
    // A syntax error has no object or field to name; file, line and column are what matter.
    assert_at(&w, &e, 3, 9);
    assert!(!e.message.is_empty());
}

#[test]
fn unknown_field_typo_is_named_with_its_object() {
    let (w, e) = fail(&[
        "[[sphere]]",         // 1
        "name = \"ball\"",    // 2
        "centre = [0, 0, 0]", // 3: the typo
        "radius = 1",         // 4
    ]);
    check(
        &w,
        &e,
        (3, 1),
        "sphere \"ball\"",
        "centre",
        &["centre", "center"],
    );
}

// ---------------------------------------------------------------------------------------------
// Spheres and planes

#[test]
fn negative_radius() {
    let (w, e) = fail(&[
        "[[sphere]]",         // 1
        "name = \"ball\"",    // 2
        "center = [0, 0, 0]", // 3
        "radius = -1",        // 4
    ]);
    check(
        &w,
        &e,
        (4, 1),
        "sphere \"ball\"",
        "radius",
        &["positive", "-1"],
    );
}

#[test]
fn zero_radius() {
    let (w, e) = fail(&[
        "[[sphere]]",         // 1
        "name = \"ball\"",    // 2
        "center = [0, 0, 0]", // 3
        "radius = 0",         // 4
    ]);
    check(&w, &e, (4, 1), "sphere \"ball\"", "radius", &["positive"]);
}

#[test]
fn zero_plane_normal() {
    let (w, e) = fail(&[
        "[[plane]]",          // 1
        "name = \"floor\"",   // 2
        "point = [0, 0, 0]",  // 3
        "normal = [0, 0, 0]", // 4
    ]);
    check(&w, &e, (4, 1), "plane \"floor\"", "normal", &["non-zero"]);
}

#[test]
fn plane_with_both_axis_and_point() {
    let (w, e) = fail(&[
        "[[plane]]",         // 1
        "name = \"floor\"",  // 2
        "point = [0, 0, 0]", // 3
        "axis = \"y\"",      // 4: the second form, where the conflict becomes visible
    ]);
    check(
        &w,
        &e,
        (4, 1),
        "plane \"floor\"",
        "axis",
        &["point", "axis", "not both"],
    );
}

#[test]
fn bad_axis_name() {
    let (w, e) = fail(&[
        "[[plane]]",        // 1
        "name = \"floor\"", // 2
        "axis = \"w\"",     // 3
        "offset = 0",       // 4
    ]);
    check(
        &w,
        &e,
        (3, 1),
        "plane \"floor\"",
        "axis",
        &["\"w\"", "\"x\""],
    );
}

// ---------------------------------------------------------------------------------------------
// Camera

#[test]
fn camera_up_parallel_to_view() {
    let (w, e) = fail(&[
        "[camera]",         // 1
        "from = [0, 5, 0]", // 2: straight above the origin
        "at = [0, 0, 0]",   // 3
        "up = [0, 1, 0]",   // 4: along the view direction
    ]);
    check(&w, &e, (4, 1), "camera", "up", &["parallel"]);
}

#[test]
fn camera_from_equals_at() {
    let (w, e) = fail(&[
        "[camera]",         // 1
        "from = [1, 2, 3]", // 2
        "at = [1, 2, 3]",   // 3
    ]);
    check(
        &w,
        &e,
        (3, 1),
        "camera",
        "at",
        &["from", "at", "same point"],
    );
}

#[test]
fn fov_zero() {
    let (w, e) = fail(&[
        "[camera]", // 1
        "fov = 0",  // 2
    ]);
    check(&w, &e, (2, 1), "camera", "fov", &["180", "got 0"]);
}

#[test]
fn fov_180() {
    let (w, e) = fail(&[
        "[camera]",  // 1
        "fov = 180", // 2
    ]);
    check(&w, &e, (2, 1), "camera", "fov", &["180", "got 180"]);
}

#[test]
fn width_zero() {
    let (w, e) = fail(&[
        "[camera]",    // 1
        "width = 0",   // 2
        "height = 10", // 3
    ]);
    check(&w, &e, (2, 1), "camera", "width", &["got 0"]);
}

#[test]
fn width_too_large() {
    let (w, e) = fail(&[
        "[camera]",       // 1
        "width = 100000", // 2
        "height = 10",    // 3
    ]);
    check(&w, &e, (2, 1), "camera", "width", &["16384", "100000"]);
}

#[test]
fn too_many_pixels() {
    let (w, e) = fail(&[
        "[camera]",       // 1
        "width = 16000",  // 2: each side is allowed ...
        "height = 16000", // 3: ... but 256 million pixels are not
    ]);
    check(
        &w,
        &e,
        (2, 1),
        "camera",
        "width",
        &["256000000", "40000000"],
    );
}

// ---------------------------------------------------------------------------------------------
