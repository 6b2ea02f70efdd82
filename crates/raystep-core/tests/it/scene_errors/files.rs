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
