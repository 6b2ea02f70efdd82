//! Groups map to the file's entries as the loader numbers them; an edit the loader rejects, or
//! a bad index, leaves the document as it was.

use super::*;

#[test]
fn every_shipped_scene_maps_its_groups_to_their_entries() {
    let mut n = 0;
    for f in std::fs::read_dir(scenes_dir()).unwrap() {
        let path = f.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        if text_includes_gltf(&text) {
            let e = SceneDoc::parse(&text, "x", path.parent()).err().unwrap();
            assert!(e.contains("is edited in its text"), "{e}");
            continue;
        }
        let d = SceneDoc::parse(&text, "x", path.parent()).unwrap();
        let scene = load_file(&path).unwrap();
        assert!(same(&scene, &d.scene().unwrap()));
        check_mapping(&d, &scene);
        n += 1;
    }
    assert!(n >= 9, "only {n} scenes");
}

#[test]
fn interleaved_kinds_map_in_file_order() {
    let d = SceneDoc::parse(INTERLEAVED, "i.toml", Some(&scenes_dir())).unwrap();
    let scene = d.scene().unwrap();
    let names: Vec<&str> = scene.groups.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "triangle 0",
            "sphere 0",
            "plane 0",
            "named",
            "mesh 0",
            "second triangle",
            "sphere 2",
            "ico",
            "plane 1"
        ]
    );
    use EntryKind::*;
    let e = |kind, index| EntryRef { kind, index };
    assert_eq!(
        d.entries(),
        [
            e(Triangle, 0),
            e(Sphere, 0),
            e(Plane, 0),
            e(Sphere, 1),
            e(Mesh, 0),
            e(Triangle, 1),
            e(Sphere, 2),
            e(Mesh, 1),
            e(Plane, 1)
        ]
    );
    check_mapping(&d, &scene);
    // And an edit of a group edits that entry.
    let mut d = d;
    let s = d
        .apply(&Edit::Move {
            group: 6,
            by: [0.0, 0.0, 1.0],
        })
        .unwrap();
    assert_eq!(sphere(&s, "sphere 2").0, Vec3::new(0.0, 0.0, 1.0));
    assert!(d.text().contains("radius = 0.5\ncenter = [0, 0, 1]\n"));
}

#[test]
fn inline_arrays_of_entries_map_and_edit_too() {
    let text = "sphere = [{ name = \"a\", center = [0, 0, 0] }, { radius = 2 }]\n\n[[triangle]]\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n";
    let mut d = doc(text);
    let scene = d.scene().unwrap();
    check_mapping(&d, &scene);
    let s = d
        .apply(&Edit::Move {
            group: 0,
            by: [1.0, 0.0, 0.0],
        })
        .unwrap();
    assert_eq!(sphere(&s, "a").0, Vec3::X);
    let s = d
        .apply(&Edit::SetMaterial {
            group: 1,
            field: MaterialField::Diffuse,
            value: MaterialValue::Number(0.5),
        })
        .unwrap();
    assert_eq!(material(&s, "sphere 1").diffuse, 0.5);
    assert!(
        d.text()
            .starts_with("sphere = [{ name = \"a\", center = [1, 0, 0] }, "),
        "{}",
        d.text()
    );
}

#[test]
fn an_edit_the_loader_rejects_leaves_the_document_unchanged() {
    let mut d = doc(BALL);
    let g = group(&d.scene().unwrap(), "ball");
    for radius in [-1.0, 0.0, f64::NAN, f64::INFINITY] {
        let err = d.apply(&Edit::SetRadius { group: g, radius }).unwrap_err();
        assert!(err.contains("radius"), "{err}");
        assert_eq!(d.text(), BALL);
    }
    // Rejected by the loader itself: a reflectance above 1, a negative colour.
    let err = d
        .apply(&Edit::SetMaterial {
            group: g,
            field: MaterialField::Reflective,
            value: MaterialValue::Number(2.0),
        })
        .unwrap_err();
    assert!(
        err.contains("reflective") && err.contains("[0, 1]"),
        "{err}"
    );
    let err = d
        .apply(&Edit::SetLight {
            light: 0,
            field: LightField::Color,
            value: [-1.0, 0.0, 0.0],
        })
        .unwrap_err();
    assert!(err.contains("negative"), "{err}");
    // Not finite, or past the loader's limits.
    assert!(
        d.apply(&Edit::Move {
            group: g,
            by: [f64::NAN, 0.0, 0.0]
        })
        .is_err()
    );
    assert!(
        d.apply(&Edit::Move {
            group: g,
            by: [1e300, 0.0, 0.0]
        })
        .is_err()
    );
    assert!(
        d.apply(&Edit::Move {
            group: g,
            by: [f64::MAX, 0.0, 0.0]
        })
        .is_err()
    );
    assert_eq!(d.text(), BALL);
    assert!(!d.can_undo() && !d.dirty());
}

#[test]
fn bad_indices_and_kinds_are_errors() {
    let mut d = doc(BALL);
    let scene = d.scene().unwrap();
    let n = scene.groups.len() as u32;
    let floor = group(&scene, "floor");
    for e in [
        Edit::Move {
            group: n,
            by: [1.0; 3],
        },
        Edit::Move {
            group: u32::MAX,
            by: [1.0; 3],
        },
        Edit::SetRadius {
            group: n,
            radius: 1.0,
        },
        Edit::SetRadius {
            group: floor,
            radius: 1.0,
        },
        Edit::SetMaterial {
            group: n,
            field: MaterialField::Ambient,
            value: MaterialValue::Number(0.5),
        },
        Edit::SetMaterial {
            group: 0,
            field: MaterialField::Color,
            value: MaterialValue::Number(0.5),
        },
        Edit::SetMaterial {
            group: 0,
            field: MaterialField::Ambient,
            value: MaterialValue::Color([0.5; 3]),
        },
        Edit::SetMaterial {
            group: 0,
            field: MaterialField::Ambient,
            value: MaterialValue::Number(f64::NEG_INFINITY),
        },
        Edit::SetLight {
            light: 1,
            field: LightField::Position,
            value: [0.0; 3],
        },
        Edit::SetLight {
            light: 0,
            field: LightField::Position,
            value: [0.0, f64::NAN, 0.0],
        },
    ] {
        let err = d.apply(&e).unwrap_err();
        assert!(!err.is_empty());
    }
    assert_eq!(d.text(), BALL);
    assert_eq!(d.material_users(n), None);
    // A document that is not TOML is refused; one that does not load cannot be edited.
    assert!(SceneDoc::parse("[[sphere]\n", "x.toml", None).is_err());
    let mut bad = doc("[[sphere]]\nradius = -1\n");
    assert!(bad.scene().is_err());
    let err = bad
        .apply(&Edit::Move {
            group: 0,
            by: [1.0, 0.0, 0.0],
        })
        .unwrap_err();
    assert!(err.contains("radius"), "{err}");
    // Nothing to undo, redo or end.
    assert!(bad.undo().is_none() && bad.redo().is_none());
    bad.end_gesture();
}
