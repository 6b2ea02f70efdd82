//! Numbers where single-precision tracing stays finite: the camera, huge spheres and meshes,
//! the bound itself.

use super::*;

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
