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

mod arrays_and_tables;
mod files;
mod finite;
mod names;
mod not_regular;
mod numbers;

/// An OBJ mesh read from `bad.obj`.
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

mod objects;
mod textures;
