//! Bad scene files: every error names the file, the line and column of the offending field (as
//! written in the text), the object and field, and says what is wrong — and nothing panics.
//!
//! Each test writes its scene one line per array element, so the expected line is the element's
//! index + 1; columns are counted by hand from the same text.

use raystep_core::scene::{SceneError, load_file};
use std::path::{Path, PathBuf};
use tempfile::TempDir;

/// A scene written into a fresh temporary directory (kept alive with the paths).
struct Written {
    _dir: TempDir,
    path: PathBuf,
}

/// Writes `lines` as `scene.toml`, plus any `extra` files (name, contents) beside it.
fn write(lines: &[&str], extra: &[(&str, &str)]) -> Written {
    let dir = TempDir::new().unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    for (name, text) in extra {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    Written { _dir: dir, path }
}

/// Loads a scene that must fail.
fn fail_with(lines: &[&str], extra: &[(&str, &str)]) -> (Written, SceneError) {
    let w = write(lines, extra);
    let e = match load_file(&w.path) {
        Ok(_) => panic!("this scene should not load:\n{}", lines.join("\n")),
        Err(e) => e,
    };
    (w, e)
}

fn fail(lines: &[&str]) -> (Written, SceneError) {
    fail_with(lines, &[])
}

/// The error names the file, the line and column, and its Display says `file:line:col`.
fn assert_at(w: &Written, e: &SceneError, line: usize, column: usize) {
    let file = w.path.display().to_string();
    assert_eq!(e.file, file, "{e}");
    assert_eq!((e.line, e.column), (Some(line), Some(column)), "{e}");
    let shown = e.to_string();
    assert!(
        shown.contains(&format!("{file}:{line}:{column}")),
        "Display lacks {file}:{line}:{column}: {shown}"
    );
}

/// The error names the object (`sphere "ball"`) and its field (`radius`).
fn assert_field(e: &SceneError, object: &str, field: &str) {
    let f = e
        .field
        .as_deref()
        .unwrap_or_else(|| panic!("no object/field named: {e}"));
    assert!(
        f.contains(object),
        "field {f:?} does not name {object}: {e}"
    );
    assert!(f.contains(field), "field {f:?} does not name {field}: {e}");
    assert!(e.to_string().contains(f), "Display omits the field: {e}");
}

/// The message mentions every one of `parts`.
fn assert_says(e: &SceneError, parts: &[&str]) {
    for p in parts {
        assert!(e.message.contains(p), "message does not mention {p:?}: {e}");
    }
}

/// Everything at once, for the common case.
fn check(
    w: &Written,
    e: &SceneError,
    (line, column): (usize, usize),
    object: &str,
    field: &str,
    says: &[&str],
) {
    assert_at(w, e, line, column);
    assert_field(e, object, field);
    assert_says(e, says);
}

// ---------------------------------------------------------------------------------------------
// TOML itself

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
// Names

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
// Numbers

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
// OBJ meshes

fn mesh_scene() -> [&'static str; 4] {
    [
        "[[mesh]]",              // 1
        "name = \"teapot\"",     // 2
        "obj = \"bad.obj\"",     // 3
        "translate = [0, 1, 0]", // 4
    ]
}

/// The message names the OBJ file and the line in it that is wrong (`bad.obj:4` or `line 4`).
fn says_obj_line(e: &SceneError, line: usize) {
    assert_says(e, &["bad.obj"]);
    assert!(
        e.message.contains(&format!("bad.obj:{line}"))
            || e.message.contains(&format!("line {line}")),
        "message does not give the OBJ line {line}: {e}"
    );
}

#[test]
fn missing_obj_file() {
    let (w, e) = fail(&mesh_scene());
    check(
        &w,
        &e,
        (3, 1),
        "mesh \"teapot\"",
        "obj",
        &["bad.obj", "does not exist"],
    );
}

#[test]
fn obj_face_refers_to_missing_vertex() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n"; // line 4 refers to vertex 99 of 3
    let (w, e) = fail_with(&mesh_scene(), &[("bad.obj", obj)]);
    check(&w, &e, (3, 1), "mesh \"teapot\"", "obj", &["99"]);
    says_obj_line(&e, 4);
}

#[test]
fn obj_garbage_line() {
    let obj = "v 0 0 0\nv 1 x 2\nv 0 1 0\nf 1 2 3\n"; // line 2 is not a vertex
    let (w, e) = fail_with(&mesh_scene(), &[("bad.obj", obj)]);
    check(&w, &e, (3, 1), "mesh \"teapot\"", "obj", &[]);
    says_obj_line(&e, 2);
}

#[test]
fn obj_without_faces() {
    let obj = "# three points, no faces\nv 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let (w, e) = fail_with(&mesh_scene(), &[("bad.obj", obj)]);
    check(
        &w,
        &e,
        (3, 1),
        "mesh \"teapot\"",
        "obj",
        &["bad.obj", "no faces"],
    );
}

// ---------------------------------------------------------------------------------------------
// The scene file itself

#[test]
fn missing_scene_file() {
    let dir = TempDir::new().unwrap();
    let path = dir.path().join("nowhere.toml");
    let e = load_file(&path).unwrap_err();
    let file = path.display().to_string();
    assert_eq!(e.file, file);
    assert_eq!((e.line, e.column, e.field.as_deref()), (None, None, None));
    assert!(e.to_string().starts_with(&format!("{file}: ")), "{e}");
    assert_says(&e, &["cannot read"]);
}

#[test]
fn directory_as_scene_file() {
    let dir = TempDir::new().unwrap();
    let path: &Path = dir.path();
    let e = load_file(path).unwrap_err();
    let file = path.display().to_string();
    assert_eq!(e.file, file);
    assert_eq!((e.line, e.column, e.field.as_deref()), (None, None, None));
    assert!(e.to_string().starts_with(&format!("{file}: ")), "{e}");
    assert_says(&e, &["cannot read"]);
}

// ---------------------------------------------------------------------------------------------
// Arrays of the wrong length are errors, not silently cut or padded

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
// Numbers where single-precision tracing stays finite

/// A scene with one camera line (the rest default) must fail naming `field` of the camera.
fn camera_fails(lines: &[&str], field: &str, says: &[&str]) {
    let mut all = vec!["[camera]"];
    all.extend_from_slice(lines);
    let (w, e) = fail(&all);
    let line = lines
        .iter()
        .position(|l| l.starts_with(field))
        .map_or(1, |i| i + 2);
    check(&w, &e, (line, 1), "camera", field, says);
}

#[test]
fn cameras_whose_rays_would_be_nan_are_refused() {
    // `at` 1e-30 from `from`: fine in f64, but |from − at|² underflows to 0 in f32.
    camera_fails(
        &["from = [0, 0, 0]", "at = [0, 0, 1e-30]"],
        "at",
        &["too close"],
    );
    // `up` of length 1e-30: up × w underflows the same way.
    camera_fails(&["up = [0, 1e-30, 0]"], "up", &["too short"]);
    // |from − at|² = 4e38 overflows f32.
    camera_fails(&["from = [2e19, 0, 0]"], "from", &["too large", "1e19"]);
    // Within the bound, but |from − at|² = 4e38 overflows f32: the basis check catches it.
    camera_fails(
        &["from = [1e19, 0, 0]", "at = [-1e19, 0, 0]"],
        "at",
        &["too close"],
    );
    camera_fails(
        &["from = [3e38, 0, 0]", "at = [-3e38, 0, 0]"],
        "from",
        &["too large"],
    );
}

#[test]
fn a_sphere_too_large_to_trace_is_refused() {
    let (w, e) = fail(&[
        "[[sphere]]",     // 1
        "name = \"sky\"", // 2
        "radius = 1e20",  // 3
    ]);
    check(
        &w,
        &e,
        (3, 1),
        "sphere \"sky\"",
        "radius",
        &["too large", "1e19"],
    );
}

#[test]
fn numbers_at_the_bound_load_and_past_it_do_not() {
    let ok = write(
        &["[[sphere]]", "center = [1e19, 0, 0]", "radius = 1e19"],
        &[],
    );
    assert!(load_file(&ok.path).is_ok());
    let ok = write(
        &[
            "[[triangle]]",
            "vertices = [[1e8, 0, 0], [0, 1, 0], [0, 0, 1]]",
        ],
        &[],
    );
    assert!(load_file(&ok.path).is_ok());
    let (w, e) = fail(&[
        "[[triangle]]",
        "vertices = [[2e8, 0, 0], [0, 1, 0], [0, 0, 1]]",
    ]);
    check(
        &w,
        &e,
        (2, 1),
        "triangle",
        "vertices",
        &["too large", "1e8", "plane"],
    );
    let (w, e) = fail(&["[[light]]", "color = [1.00001e11, 1, 1]"]);
    check(&w, &e, (2, 1), "light", "color", &["too large"]);
}

#[test]
fn a_mesh_scaled_out_of_range_is_refused() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let (w, e) = fail_with(
        &[
            "[[mesh]]",                // 1
            "name = \"big\"",          // 2
            "obj = \"bad.obj\"",       // 3
            "scale = 1e8",             // 4
            "translate = [5e7, 0, 0]", // 5: vertex 2 lands at x = 1.5e8
        ],
        &[("bad.obj", obj)],
    );
    check(
        &w,
        &e,
        (3, 1),
        "mesh \"big\"",
        "obj",
        &["bad.obj", "vertex 2", "too large"],
    );
}

// ---------------------------------------------------------------------------------------------
// Files that are not regular files, or too large

#[cfg(unix)]
#[test]
fn a_device_as_obj_or_scene_is_refused_without_reading_it() {
    // /dev/zero is only read (or rather, not): it would otherwise be read until memory runs out.
    let (w, e) = fail(&["[[mesh]]", "name = \"z\"", "obj = \"/dev/zero\""]);
    check(
        &w,
        &e,
        (3, 1),
        "mesh \"z\"",
        "obj",
        &["/dev/zero", "character device"],
    );
    let e = load_file(Path::new("/dev/zero")).unwrap_err();
    assert_says(&e, &["character device", "regular file"]);
}

#[cfg(unix)]
#[test]
fn a_device_as_material_library_is_refused() {
    let obj = "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let (w, e) = fail_with(&mesh_scene(), &[("bad.obj", obj)]);
    check(
        &w,
        &e,
        (3, 1),
        "mesh \"teapot\"",
        "obj",
        &["material library", "character device"],
    );
    says_obj_line(&e, 1);
}

#[test]
fn a_missing_material_library_is_ignored_as_before() {
    let obj = "mtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let w = write(&mesh_scene(), &[("bad.obj", obj)]);
    let scene = load_file(&w.path).unwrap();
    assert_eq!(scene.objects.len(), 1);
}

#[test]
fn a_scene_file_past_the_limit_is_refused_with_the_limit() {
    let dir = TempDir::new().unwrap();
    let path = dir.path().join("huge.toml");
    let limit = raystep_core::io::limits::SCENE;
    let f = std::fs::File::create(&path).unwrap();
    f.set_len(limit + 1).unwrap(); // sparse: no disk used
    let e = load_file(&path).unwrap_err();
    assert_says(&e, &["more than the limit of 16 MiB for scene files"]);
}

/// A number TOML's reader quotes back in full (`spp = 1e-300` is a float where an integer
/// belongs, and the reader prints its 300 decimals) is shortened in the message.
#[test]
fn a_long_number_in_a_parse_error_is_shortened() {
    let (w, e) = fail(&["[render]", "spp = 1e-300"]);
    let msg = e.to_string();
    assert!(msg.len() < 200 && msg.contains("1e-300"), "{msg}");
    assert_at(&w, &e, 2, 7);
}
