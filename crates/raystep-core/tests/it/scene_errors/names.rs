//! Names: unknown materials (listing the known ones), duplicate objects, materials and lights.

use super::*;

#[test]
fn unknown_material_lists_the_known_ones() {
    let (w, e) = fail(&[
        "[[material]]",        // 1
        "name = \"red\"",      // 2
        "",                    // 3
        "[[material]]",        // 4
        "name = \"blue\"",     // 5
        "",                    // 6
        "[[sphere]]",          // 7
        "name = \"ball\"",     // 8
        "material = \"gold\"", // 9
    ]);
    check(
        &w,
        &e,
        (9, 1),
        "sphere \"ball\"",
        "material",
        &["\"gold\"", "\"red\"", "\"blue\""],
    );
}

#[test]
fn unknown_material_after_a_multiline_array() {
    // Vertices one per line is a natural way to write a triangle; the field after them must
    // still be found.
    let (w, e) = fail(&[
        "[[material]]",        // 1
        "name = \"red\"",      // 2
        "",                    // 3
        "[[triangle]]",        // 4
        "name = \"roof\"",     // 5
        "vertices = [",        // 6
        "  [0, 0, 0],",        // 7
        "  [1, 0, 0],",        // 8
        "  [0, 1, 0],",        // 9
        "]",                   // 10
        "material = \"gold\"", // 11
    ]);
    check(
        &w,
        &e,
        (11, 1),
        "triangle \"roof\"",
        "material",
        &["\"gold\"", "\"red\""],
    );
}

#[test]
fn unknown_material_after_an_unindented_multiline_array() {
    let (w, e) = fail(&[
        "[[triangle]]",        // 1
        "name = \"roof\"",     // 2
        "vertices = [",        // 3
        "[0, 0, 0],",          // 4: a line starting with `[` is not a table header
        "[1, 0, 0],",          // 5
        "[0, 1, 0],",          // 6
        "]",                   // 7
        "material = \"gold\"", // 8
    ]);
    check(
        &w,
        &e,
        (8, 1),
        "triangle \"roof\"",
        "material",
        &["\"gold\""],
    );
}

#[test]
fn duplicate_object_name() {
    let (w, e) = fail(&[
        "[[sphere]]",      // 1
        "name = \"ball\"", // 2
        "",                // 3
        "[[sphere]]",      // 4
        "name = \"ball\"", // 5: the duplicate
        "radius = 2",      // 6
    ]);
    check(
        &w,
        &e,
        (5, 1),
        "sphere \"ball\"",
        "name",
        &["\"ball\"", "already"],
    );
}

#[test]
fn duplicate_object_name_across_kinds_points_at_the_later_one() {
    let (w, e) = fail(&[
        "[[plane]]",       // 1
        "name = \"ball\"", // 2: the first "ball" in the file
        "axis = \"y\"",    // 3
        "",                // 4
        "[[sphere]]",      // 5
        "name = \"ball\"", // 6: the duplicate
    ]);
    check(
        &w,
        &e,
        (6, 1),
        "sphere \"ball\"",
        "name",
        &["\"ball\"", "already"],
    );
}

#[test]
fn duplicate_material_name() {
    let (w, e) = fail(&[
        "[[material]]",      // 1
        "name = \"red\"",    // 2
        "color = [1, 0, 0]", // 3
        "",                  // 4
        "[[material]]",      // 5
        "name = \"red\"",    // 6: the duplicate
    ]);
    check(
        &w,
        &e,
        (6, 1),
        "material \"red\"",
        "name",
        &["\"red\"", "already"],
    );
}

// ---------------------------------------------------------------------------------------------
