//! Files that are not regular files (devices), or too large.

use super::*;

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
