//! Undo and redo restore the text byte for byte, a gesture is one step, and saving writes text
//! that loads to the edited scene (line endings, byte order mark and final newline kept).

use super::*;

#[test]
fn undo_and_redo_restore_the_text_bit_for_bit() {
    let mut d = shipped("mirror-glass.toml");
    let original = d.text().to_string();
    let s0 = d.scene().unwrap();
    let red = group(&s0, "red ball");
    let s1 = d
        .apply(&Edit::Move {
            group: red,
            by: [0.3, 0.0, -0.7],
        })
        .unwrap();
    let t1 = d.text().to_string();
    let s2 = d
        .apply(&Edit::SetMaterial {
            group: red,
            field: MaterialField::Specular,
            value: MaterialValue::Number(0.9),
        })
        .unwrap();
    let t2 = d.text().to_string();
    assert!(same(&d.undo().unwrap().unwrap(), &s1));
    assert_eq!(d.text(), t1);
    assert!(same(&d.undo().unwrap().unwrap(), &s0));
    assert_eq!(d.text(), original);
    assert!(!d.can_undo() && d.can_redo() && !d.dirty());
    assert!(d.undo().is_none());
    assert!(same(&d.redo().unwrap().unwrap(), &s1));
    assert!(same(&d.redo().unwrap().unwrap(), &s2));
    assert_eq!(d.text(), t2);
    assert!(d.redo().is_none());
    // A new edit after an undo drops the redo.
    d.undo();
    d.apply(&Edit::SetRadius {
        group: red,
        radius: 0.5,
    })
    .unwrap();
    assert!(!d.can_redo());
    d.undo();
    d.undo();
    assert_eq!(d.text(), original);
}

#[test]
fn a_gesture_is_one_undo_step() {
    let mut d = doc(BALL);
    let g = group(&d.scene().unwrap(), "ball");
    // A gesture that applies nothing makes no step.
    d.begin_gesture();
    d.end_gesture();
    assert!(!d.can_undo());
    d.begin_gesture();
    for _ in 0..10 {
        d.apply(&Edit::Move {
            group: g,
            by: [0.05, 0.01, 0.0],
        })
        .unwrap();
    }
    assert!(d.in_gesture() && d.can_undo());
    d.end_gesture();
    assert!(
        d.text().contains("center = [0.5, 1.1, 0]  # the ball"),
        "{}",
        d.text()
    );
    let moved = d.text().to_string();
    assert!(d.undo().unwrap().is_ok());
    assert_eq!(d.text(), BALL);
    assert!(!d.can_undo());
    assert!(d.redo().unwrap().is_ok());
    assert_eq!(d.text(), moved);
    // A gesture that comes back to where it started makes no step, and keeps the redo.
    d.undo();
    d.begin_gesture();
    for by in [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]] {
        d.apply(&Edit::Move { group: g, by }).unwrap();
    }
    d.end_gesture();
    assert!(!d.can_undo() && d.can_redo());
    // Undo in the middle of a gesture ends it first.
    d.begin_gesture();
    d.apply(&Edit::Move {
        group: g,
        by: [0.0, 2.0, 0.0],
    })
    .unwrap();
    assert!(d.undo().is_some());
    assert!(!d.in_gesture());
    assert_eq!(d.text(), BALL);
}

#[test]
fn save_writes_the_text_and_it_loads_to_the_edited_scene() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ball.toml");
    std::fs::write(&path, BALL).unwrap();
    let mut d = SceneDoc::parse(BALL, &path.display().to_string(), Some(dir.path())).unwrap();
    assert!(!d.dirty());
    let g = group(&d.scene().unwrap(), "ball");
    let edited = d
        .apply(&Edit::Move {
            group: g,
            by: [0.0, 0.0, 2.0],
        })
        .unwrap();
    assert!(d.dirty());
    d.save(&path).unwrap();
    assert!(!d.dirty());
    assert_eq!(std::fs::read_to_string(&path).unwrap(), d.text());
    assert!(same(&load_file(&path).unwrap(), &edited));
    // No temporary file is left beside it.
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["ball.toml"]);
    // Undo makes it dirty again; redo back to the saved text makes it clean.
    d.undo();
    assert!(d.dirty());
    d.redo();
    assert!(!d.dirty());
    // A path that cannot be written is an error naming it, and the document stays dirty.
    d.undo();
    let bad = dir.path().join("no such folder").join("ball.toml");
    let err = d.save(&bad).unwrap_err();
    assert!(err.contains(&bad.display().to_string()), "{err}");
    assert!(d.dirty());
}

#[test]
fn saving_a_mesh_scene_beside_its_obj() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        scenes_dir().join("icosahedron.obj"),
        dir.path().join("icosahedron.obj"),
    )
    .unwrap();
    let path = dir.path().join("triangles.toml");
    let mut d = shipped("triangles.toml");
    let g = group(&d.scene().unwrap(), "icosahedron");
    let edited = d
        .apply(&Edit::Move {
            group: g,
            by: [0.5, 0.0, 0.0],
        })
        .unwrap();
    d.save(&path).unwrap();
    assert!(same(&load_file(&path).unwrap(), &edited));
}

#[test]
fn line_endings_byte_order_mark_and_final_newline_are_kept() {
    let mut lf = doc(BALL);
    two_edits(&mut lf);
    let edited = lf.text().to_string();
    let variants: [(String, String); 3] = [
        (BALL.replace('\n', "\r\n"), edited.replace('\n', "\r\n")),
        (format!("\u{feff}{BALL}"), format!("\u{feff}{edited}")),
        (
            BALL.trim_end().to_string(),
            edited.strip_suffix('\n').unwrap().to_string(),
        ),
    ];
    for (text, expected) in variants {
        let mut d = doc(&text);
        two_edits(&mut d);
        assert_eq!(d.text(), expected);
        d.undo();
        d.undo();
        assert_eq!(d.text(), text);
    }
}

#[test]
fn a_gesture_there_and_back_gives_the_file_back() {
    for name in [
        "acne.toml",
        "teapot-stadium.toml",
        "leaky-edge.toml",
        "triangles.toml",
    ] {
        let mut d = shipped(name);
        let text = d.text().to_string();
        let n = d.scene().unwrap().groups.len() as u32;
        d.begin_gesture();
        for by in [[0.5, -0.25, 1.0], [0.1, 0.2, 0.3], [-0.6, 0.05, -1.3]] {
            d.apply(&Edit::Move { group: n - 1, by }).unwrap();
        }
        d.end_gesture();
        assert_eq!(d.text(), text, "{name}");
        assert!(!d.can_undo() && !d.dirty());
    }
}
