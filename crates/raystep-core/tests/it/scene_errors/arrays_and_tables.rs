//! Arrays of the wrong length are errors, not silently cut or padded; errors name the table
//! they are in, not the one before it.

use super::*;

#[test]
fn a_centre_with_four_numbers_is_refused() {
    let (w, e) = fail(&[
        "[[sphere]]",             // 1
        "name = \"ball\"",        // 2
        "center = [0, 0, 0, 99]", // 3: the array starts at column 10
    ]);
    check(
        &w,
        &e,
        (3, 10),
        "sphere \"ball\"",
        "center",
        &["3 numbers", "found 4"],
    );
}

#[test]
fn a_colour_with_five_numbers_is_refused() {
    let (w, e) = fail(&[
        "[[material]]",                 // 1
        "name = \"red\"",               // 2
        "color = [1, 0, 0, 0.5, 0.25]", // 3: the array starts at column 9
    ]);
    check(
        &w,
        &e,
        (3, 9),
        "material \"red\"",
        "color",
        &["3 numbers", "found 5"],
    );
}

#[test]
fn a_colour_with_two_numbers_is_refused() {
    let (w, e) = fail(&[
        "[[light]]",      // 1
        "name = \"key\"", // 2
        "color = [1, 1]", // 3
    ]);
    check(
        &w,
        &e,
        (3, 9),
        "light \"key\"",
        "color",
        &["3 numbers", "found 2"],
    );
}

#[test]
fn a_triangle_vertex_with_four_numbers_is_refused() {
    let (w, e) = fail(&[
        "[[triangle]]",                                     // 1
        "name = \"t\"",                                     // 2
        "vertices = [[0, 1, 0], [-1, 0, 0, 7], [1, 0, 0]]", // 3: the array is column 12
    ]);
    check(
        &w,
        &e,
        (3, 12),
        "triangle \"t\"",
        "vertices",
        &["3 numbers", "vertex 2", "found 4"],
    );
}

#[test]
fn a_triangle_with_four_vertices_is_refused() {
    let (w, e) = fail(&[
        "[[triangle]]",                                             // 1
        "vertices = [[0, 1, 0], [-1, 0, 0], [1, 0, 0], [0, 0, 1]]", // 2: column 12
    ]);
    check(
        &w,
        &e,
        (2, 12),
        "triangle",
        "vertices",
        &["3 vertices", "found 4"],
    );
}

#[test]
fn a_plane_normal_with_two_numbers_is_refused() {
    let (w, e) = fail(&[
        "[[plane]]",        // 1
        "name = \"floor\"", // 2
        "normal = [0, 1]",  // 3: column 10
    ]);
    check(
        &w,
        &e,
        (3, 10),
        "plane \"floor\"",
        "normal",
        &["3 numbers", "found 2"],
    );
}

// ---------------------------------------------------------------------------------------------
// Errors name the table they are in, not the one before it

#[test]
fn a_triangle_without_vertices_is_blamed_on_the_triangle() {
    let (w, e) = fail(&[
        "[[light]]",      // 1
        "name = \"key\"", // 2
        "",               // 3
        "[[triangle]]",   // 4
        "name = \"t\"",   // 5
    ]);
    assert_eq!(e.line, Some(4), "{e}");
    assert_field(&e, "triangle \"t\"", "triangle");
    assert!(!e.to_string().contains("light"), "{e}");
    assert_says(&e, &["vertices"]);
    assert_at(&w, &e, 4, 1);
}

#[test]
fn a_misspelt_table_after_the_camera_is_named_itself() {
    let (w, e) = fail(&[
        "[camera]",    // 1
        "fov = 40",    // 2
        "",            // 3
        "[[spheres]]", // 4: `spheres` starts at column 3
        "radius = 2",  // 5
    ]);
    assert_at(&w, &e, 4, 3);
    let f = e.field.as_deref().unwrap_or("");
    assert!(f.contains("spheres"), "{e}");
    assert!(!f.contains("camera"), "{e}");
    assert_says(&e, &["spheres"]);
}

#[test]
fn a_mesh_without_obj_is_blamed_on_the_mesh() {
    let (w, e) = fail(&[
        "[[sphere]]",       // 1
        "name = \"ball\"",  // 2
        "[[mesh]]",         // 3
        "name = \"bunny\"", // 4
        "scale = 2",        // 5
    ]);
    assert_at(&w, &e, 3, 1);
    assert_field(&e, "mesh \"bunny\"", "mesh");
    assert!(!e.to_string().contains("ball"), "{e}");
    assert_says(&e, &["obj"]);
}

#[test]
fn duplicate_light_names_are_refused_where_they_repeat() {
    let (w, e) = fail(&[
        "[[light]]",            // 1
        "name = \"key\"",       // 2
        "[[light]]",            // 3
        "name = \"key\"",       // 4
        "position = [1, 2, 3]", // 5
    ]);
    check(
        &w,
        &e,
        (4, 1),
        "light \"key\"",
        "name",
        &["already defined"],
    );
}

#[test]
fn columns_count_characters_not_bytes() {
    // Each of 球, é is one character (three and two bytes in UTF-8).
    let (w, e) = fail(&[
        "title = \"é\"",                                       // 1
        "sphere = [{ name = \"球\", center = [0, 0, 0, 9] }]", // 2: the array is character 34
    ]);
    // An inline table has no header: the error names the key its line starts with.
    check(&w, &e, (2, 34), "sphere", "sphere", &["found 4"]);
    let (w, e) = fail(&["title = \"héllo\" x"]); // the stray `x` is character 17 (byte 18)
    assert_at(&w, &e, 1, 17);
}

// ---------------------------------------------------------------------------------------------
