//! Files: OBJ meshes and the scene file itself.

use super::*;

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

// ---------------------------------------------------------------------------------------------
// Smooth shading: vertex normals

#[test]
fn obj_zero_vertex_normal_names_its_line() {
    // Line 6 is the second vn, (0, 0, 0): no direction to shade with.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 1\nvn 0 0 0\nf 1//1 2//2 3//3\n";
    let (w, e) = fail_with(&mesh_scene(), &[("bad.obj", obj)]);
    check(
        &w,
        &e,
        (3, 1),
        "mesh \"teapot\"",
        "obj",
        &["normal 3", "non-zero"],
    );
    says_obj_line(&e, 6);
}

#[test]
fn mesh_shading_must_be_flat_or_smooth() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let mut lines = mesh_scene().to_vec();
    lines.push("shading = \"round\""); // 5
    let (w, e) = fail_with(&lines, &[("bad.obj", obj)]);
    check(
        &w,
        &e,
        (5, 1),
        "mesh \"teapot\"",
        "shading",
        &["\"flat\"", "\"smooth\"", "round"],
    );
}

#[test]
fn triangle_normals_must_be_non_zero_and_three() {
    let (w, e) = fail(&[
        "[[triangle]]",                                 // 1
        "name = \"t\"",                                 // 2
        "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]", // 3
        "normals = [[0, 0, 1], [0, 0, 0], [0, 0, 1]]",  // 4: the second is zero
    ]);
    check(
        &w,
        &e,
        (4, 1),
        "triangle \"t\"",
        "normals",
        &["normal 2", "non-zero"],
    );
    let (w, e) = fail(&[
        "[[triangle]]",                                 // 1
        "name = \"t\"",                                 // 2
        "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]", // 3
        "normals = [[0, 0, 1], [0, 0, 1]]",             // 4: two, not three
    ]);
    assert_at(&w, &e, 4, 11);
    assert_says(&e, &["3 vertices", "2 values"]);
    let (w, e) = fail(&[
        "[[triangle]]",                                  // 1
        "name = \"t\"",                                  // 2
        "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]",  // 3
        "normals = [[0, 0, 1], [0, nan, 1], [0, 0, 1]]", // 4: not finite
    ]);
    check(&w, &e, (4, 1), "triangle \"t\"", "normals", &["finite"]);
}
