//! The scene-editing model (`raystep_core::scene::edit`): edits change only the touched values of the
//! TOML text (comments and layout kept), the text loads to the edited scene, groups map to the
//! file's entries as the loader numbers them, and undo/redo restore the text byte for byte.

use glam::Vec3;
use proptest::prelude::*;
use raystep_core::scene::edit::{
    Edit, EntryKind, EntryRef, LightField, MaterialField, MaterialValue, SceneDoc,
};
use raystep_core::scene::{Material, Scene, Shape, load_file};
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("scenes")
}

/// A shipped scene as a document (OBJ paths relative to scenes/).
fn shipped(name: &str) -> SceneDoc {
    let path = scenes_dir().join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    SceneDoc::parse(&text, name, Some(&scenes_dir())).unwrap()
}

fn doc(text: &str) -> SceneDoc {
    SceneDoc::parse(text, "test.toml", None).unwrap()
}

/// Whether two scenes are the same for the tracer.
fn same(a: &Scene, b: &Scene) -> bool {
    a.camera == b.camera
        && a.settings == b.settings
        && a.lights == b.lights
        && a.materials == b.materials
        && a.objects == b.objects
        && a.groups == b.groups
}

fn group(scene: &Scene, name: &str) -> u32 {
    scene
        .groups
        .iter()
        .position(|g| g.name == name)
        .unwrap_or_else(|| panic!("no group {name}")) as u32
}

fn sphere(scene: &Scene, name: &str) -> (Vec3, f32) {
    let g = scene.find_group(name).unwrap();
    match scene.objects[g.first as usize].shape {
        Shape::Sphere { center, radius } => (center, radius),
        s => panic!("{name} is {s:?}"),
    }
}

fn material<'a>(scene: &'a Scene, name: &str) -> &'a Material {
    scene.material_of(scene.find_group(name).unwrap().first)
}

/// The lines of `after` that differ from `before` (which must have as many lines).
fn changed_lines(before: &str, after: &str) -> Vec<String> {
    let (b, a): (Vec<_>, Vec<_>) = (
        before.split_inclusive('\n').collect(),
        after.split_inclusive('\n').collect(),
    );
    assert_eq!(b.len(), a.len(), "line count changed:\n{after}");
    b.iter()
        .zip(&a)
        .filter(|(x, y)| x != y)
        .map(|(_, y)| y.to_string())
        .collect()
}

const BALL: &str = r#"# A ball on a floor.
title = "Ball"   # shown in the window

[camera]
from = [0, 1.5, -5]   # eye
at = [0, 1, 0]

[[light]]
name = "sun"
position = [-10, 10, -10]

[[material]]
name = "red"
color = [1, 0, 0]
diffuse = 0.7

# The ball itself.
[[sphere]]
name = "ball"
center = [0, 1, 0]  # the ball
radius = 1
material = "red"

[[plane]]
name = "floor"   # y = 0
axis = "y"
offset = 0

[[sphere]]
radius = 0.5
"#;

#[test]
fn moving_a_sphere_changes_only_its_center_and_keeps_the_comment() {
    let mut d = doc(BALL);
    let before = d.scene().unwrap();
    let g = group(&before, "ball");
    let scene = d
        .apply(&Edit::Move {
            group: g,
            by: [1.0, 0.0, 0.5],
        })
        .unwrap();
    assert_eq!(sphere(&scene, "ball").0, Vec3::new(1.0, 1.0, 0.5));
    assert_eq!(
        changed_lines(BALL, d.text()),
        ["center = [1, 1, 0.5]  # the ball\n"]
    );
    // The scene the caller got is the one the text loads to.
    assert!(same(&scene, &d.scene().unwrap()));
    // Nothing else moved.
    assert_eq!(sphere(&scene, "sphere 1"), sphere(&before, "sphere 1"));
    assert_eq!(scene.lights, before.lights);
    assert!(d.dirty() && d.can_undo() && !d.can_redo());
}

#[test]
fn repeated_moves_write_short_numbers() {
    let mut d = doc(BALL);
    let g = group(&d.scene().unwrap(), "ball");
    for _ in 0..3 {
        d.apply(&Edit::Move {
            group: g,
            by: [0.1, 0.0, 0.0],
        })
        .unwrap();
    }
    assert!(
        d.text().contains("center = [0.3, 1, 0]  # the ball\n"),
        "{}",
        d.text()
    );
    for _ in 0..3 {
        d.apply(&Edit::Move {
            group: g,
            by: [-0.1, 0.0, 0.0],
        })
        .unwrap();
    }
    assert!(
        d.text().contains("center = [0, 1, 0]  # the ball\n"),
        "{}",
        d.text()
    );
    // A drag that goes through f32 leaves no noise either.
    d.apply(&Edit::Move {
        group: g,
        by: [0.7_f32 as f64, 0.0, 0.0],
    })
    .unwrap();
    assert!(d.text().contains("center = [0.7, 1, 0]"), "{}", d.text());
}

#[test]
fn a_sphere_without_a_center_gets_one() {
    let mut d = doc(BALL);
    let g = group(&d.scene().unwrap(), "sphere 1");
    let scene = d
        .apply(&Edit::Move {
            group: g,
            by: [2.0, 0.25, 0.0],
        })
        .unwrap();
    assert_eq!(sphere(&scene, "sphere 1").0, Vec3::new(2.0, 0.25, 0.0));
    assert!(
        d.text()
            .ends_with("[[sphere]]\nradius = 0.5\ncenter = [2, 0.25, 0]\n"),
        "{}",
        d.text()
    );
}

#[test]
fn numbers_keep_the_style_they_were_written_in() {
    let mut d = shipped("teapot-stadium.toml");
    let scene = d.scene().unwrap();
    // `radius = 0.1600`: four decimals stay four.
    let teapot = group(&scene, "teapot 1");
    d.apply(&Edit::SetRadius {
        group: teapot,
        radius: 0.25,
    })
    .unwrap();
    // `-200.0`: a float stays a float, with at least its one decimal.
    let turf = group(&scene, "turf 1");
    d.apply(&Edit::Move {
        group: turf,
        by: [1.0, 0.0, 0.25],
    })
    .unwrap();
    let text = std::fs::read_to_string(scenes_dir().join("teapot-stadium.toml")).unwrap();
    assert_eq!(
        changed_lines(&text, d.text()),
        [
            "vertices = [[-199.0, -1.0, -199.75], [201.0, -1.0, -199.75], [201.0, -1.0, 200.25]]\n",
            "radius = 0.2500\n",
        ]
    );
    assert_eq!(sphere(&d.scene().unwrap(), "teapot 1").1, 0.25);
}

#[test]
fn set_values_lose_their_binary_noise_but_not_their_digits() {
    let mut d = doc(BALL);
    let g = group(&d.scene().unwrap(), "ball");
    d.apply(&Edit::SetRadius {
        group: g,
        radius: 0.1 + 0.2,
    })
    .unwrap();
    assert!(d.text().contains("\nradius = 0.3\n"), "{}", d.text());
    d.apply(&Edit::SetRadius {
        group: g,
        radius: 1.25e-7,
    })
    .unwrap();
    assert!(d.text().contains("\nradius = 1.25e-7\n"), "{}", d.text());
    d.apply(&Edit::SetMaterial {
        group: g,
        field: MaterialField::Color,
        value: MaterialValue::Color([0.8_f32 as f64, 0.5, 1.0]),
    })
    .unwrap();
    assert!(
        d.text().contains("\ncolor = [0.8, 0.5, 1]\n"),
        "{}",
        d.text()
    );
}

#[test]
fn moving_a_triangle_moves_its_three_vertices() {
    let mut d = shipped("triangles.toml");
    let before = d.scene().unwrap();
    let g = group(&before, "pyramid east");
    let scene = d
        .apply(&Edit::Move {
            group: g,
            by: [-1.0, 0.5, 0.0],
        })
        .unwrap();
    let text = std::fs::read_to_string(scenes_dir().join("triangles.toml")).unwrap();
    assert_eq!(
        changed_lines(&text, d.text()),
        ["vertices = [[1.8, 0.5, -1], [0.8, 2.1, 0], [1.8, 0.5, 1]]\n"]
    );
    let obj = scene.groups[g as usize].first as usize;
    assert_eq!(
        scene.objects[obj].shape,
        Shape::Triangle {
            p: [
                Vec3::new(1.8, 0.5, -1.0),
                Vec3::new(0.8, 2.1, 0.0),
                Vec3::new(1.8, 0.5, 1.0)
            ]
        }
    );
}

#[test]
fn moving_a_mesh_changes_its_translate() {
    let mut d = shipped("triangles.toml");
    let before = d.scene().unwrap();
    let g = group(&before, "icosahedron");
    assert_eq!(before.groups[g as usize].count, 20);
    let scene = d
        .apply(&Edit::Move {
            group: g,
            by: [0.0, 1.0, 0.0],
        })
        .unwrap();
    let text = std::fs::read_to_string(scenes_dir().join("triangles.toml")).unwrap();
    assert_eq!(
        changed_lines(&text, d.text()),
        ["translate = [-1.6, 1.971, 0.3]\n"]
    );
    let grp = &scene.groups[g as usize];
    for k in grp.first..grp.first + grp.count {
        let (Shape::Triangle { p: a }, Shape::Triangle { p: b }) = (
            before.objects[k as usize].shape,
            scene.objects[k as usize].shape,
        ) else {
            panic!("not a triangle");
        };
        for (a, b) in a.iter().zip(&b) {
            assert!((*b - *a - Vec3::Y).length() < 1e-5, "{a} → {b}");
        }
    }
    // Every other object is where it was.
    for (k, (a, b)) in before.objects.iter().zip(&scene.objects).enumerate() {
        if a.group != g {
            assert_eq!(a, b, "object {k}");
        }
    }
}

#[test]
fn moving_planes() {
    let mut d = shipped("cornell.toml");
    let scene = d.scene().unwrap();
    let text = std::fs::read_to_string(scenes_dir().join("cornell.toml")).unwrap();
    // An axis plane: only the component along its axis counts.
    let floor = group(&scene, "floor");
    d.apply(&Edit::Move {
        group: floor,
        by: [5.0, 0.25, 7.0],
    })
    .unwrap();
    let right = group(&scene, "right wall");
    d.apply(&Edit::Move {
        group: right,
        by: [1.0, 3.0, 0.0],
    })
    .unwrap();
    // Along the other axes an axis plane does not move: no change, no undo step.
    let back = group(&scene, "back wall");
    d.apply(&Edit::Move {
        group: back,
        by: [1.0, 3.0, 0.0],
    })
    .unwrap();
    // A point + normal plane: its point moves.
    let ceiling = group(&scene, "ceiling");
    let after = d
        .apply(&Edit::Move {
            group: ceiling,
            by: [0.0, -0.5, 0.0],
        })
        .unwrap();
    assert_eq!(
        changed_lines(&text, d.text()),
        [
            "offset = 0.25\n",
            "point = [0, 4.5, 0]\n",
            "offset = -1.5\n"
        ]
    );
    let shape = |name: &str| after.objects[after.find_group(name).unwrap().first as usize].shape;
    assert_eq!(
        shape("floor"),
        Shape::AxisPlane {
            axis: 1,
            offset: 0.25
        }
    );
    assert_eq!(
        shape("right wall"),
        Shape::AxisPlane {
            axis: 0,
            offset: -1.5
        }
    );
    assert_eq!(
        shape("ceiling"),
        Shape::Plane {
            normal: Vec3::NEG_Y,
            offset: -4.5
        }
    );
    // Three steps (the back wall's move changed nothing).
    for _ in 0..3 {
        assert!(d.undo().unwrap().is_ok());
    }
    assert!(d.undo().is_none());
    assert_eq!(d.text(), text);
}

#[test]
fn a_plane_without_an_offset_or_point_gets_one() {
    let text = "[[plane]]\naxis = \"z\"\n\n[[plane]]\nname = \"tilted\"\nnormal = [0, 1, 1]\n";
    let mut d = doc(text);
    d.apply(&Edit::Move {
        group: 0,
        by: [0.0, 0.0, 2.5],
    })
    .unwrap();
    let scene = d
        .apply(&Edit::Move {
            group: 1,
            by: [0.0, 1.0, 0.0],
        })
        .unwrap();
    assert_eq!(
        d.text(),
        "[[plane]]\naxis = \"z\"\noffset = 2.5\n\n[[plane]]\nname = \"tilted\"\nnormal = [0, 1, 1]\npoint = [0, 1, 0]\n"
    );
    assert_eq!(
        scene.objects[0].shape,
        Shape::AxisPlane {
            axis: 2,
            offset: 2.5
        }
    );
}

/// Each group's entry names it as the loader does: its `name`, else `kind index`.
fn check_mapping(d: &SceneDoc, scene: &Scene) {
    let entries = d.entries();
    assert_eq!(entries.len(), scene.groups.len());
    let doc: toml_edit::DocumentMut = d.text().parse().unwrap();
    for (g, e) in scene.groups.iter().zip(&entries) {
        let t = &doc[e.kind.key()][e.index];
        let name = t
            .get("name")
            .and_then(|n| n.as_str())
            .map_or_else(|| format!("{} {}", e.kind.key(), e.index), str::to_string);
        assert_eq!(g.name, name, "{e:?}");
        let kind = scene.objects[g.first as usize].shape.kind();
        let kind = if g.count > 1 || e.kind == EntryKind::Mesh {
            "mesh"
        } else {
            kind
        };
        assert_eq!(kind, e.kind.key(), "{}", g.name);
    }
}

#[test]
fn every_shipped_scene_maps_its_groups_to_their_entries() {
    let mut n = 0;
    for f in std::fs::read_dir(scenes_dir()).unwrap() {
        let path = f.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let d = SceneDoc::parse(&text, "x", path.parent()).unwrap();
        let scene = load_file(&path).unwrap();
        assert!(same(&scene, &d.scene().unwrap()));
        check_mapping(&d, &scene);
        n += 1;
    }
    assert!(n >= 9, "only {n} scenes");
}

const INTERLEAVED: &str = r#"
[[triangle]]
vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]

[[sphere]]
center = [0, 0, 5]

[[plane]]
axis = "y"
offset = -1

[[sphere]]
name = "named"
center = [2, 0, 5]

[[mesh]]
obj = "icosahedron.obj"
scale = 0.5

[[triangle]]
name = "second triangle"
vertices = [[0, 0, 1], [1, 0, 1], [0, 1, 1]]

[[sphere]]
radius = 0.5

[[mesh]]
name = "ico"
obj = "icosahedron.obj"
translate = [3, 0, 0]

[[plane]]
point = [0, 0, 10]
normal = [0, 0, -1]
"#;

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

#[test]
fn a_shared_material_is_edited_for_all_its_users() {
    let mut d = shipped("cornell.toml");
    let scene = d.scene().unwrap();
    let floor = group(&scene, "floor");
    assert_eq!(d.material_users(floor), Some(3)); // floor, ceiling, back wall
    assert_eq!(d.material_users(group(&scene, "left wall")), Some(1));
    let s = d
        .apply(&Edit::SetMaterial {
            group: floor,
            field: MaterialField::Color,
            value: MaterialValue::Color([0.5, 0.5, 0.5]),
        })
        .unwrap();
    for name in ["floor", "ceiling", "back wall"] {
        assert_eq!(material(&s, name).color, Vec3::splat(0.5), "{name}");
    }
    assert_eq!(material(&s, "left wall"), material(&scene, "left wall"));
    let text = std::fs::read_to_string(scenes_dir().join("cornell.toml")).unwrap();
    assert_eq!(
        changed_lines(&text, d.text()),
        ["color = [0.5, 0.5, 0.5]\n"]
    );
    assert_eq!(s.materials.len(), scene.materials.len());
}

#[test]
fn an_object_without_a_material_gets_its_own() {
    let text = "[[material]]\nname = \"red\"\ncolor = [1, 0, 0]\n\n[[sphere]]\nname = \"ball\"\n\n[[sphere]]\nname = \"other\"\ncenter = [3, 0, 0]\n";
    let mut d = doc(text);
    let before = d.scene().unwrap();
    assert_eq!(material(&before, "ball"), &Material::default());
    let ball = group(&before, "ball");
    assert_eq!(d.material_users(ball), Some(1));
    let s = d
        .apply(&Edit::SetMaterial {
            group: ball,
            field: MaterialField::Diffuse,
            value: MaterialValue::Number(0.4),
        })
        .unwrap();
    assert_eq!(
        d.text(),
        "[[material]]\nname = \"red\"\ncolor = [1, 0, 0]\n\n[[material]]\nname = \"ball material\"\ndiffuse = 0.4\n\n[[sphere]]\nname = \"ball\"\nmaterial = \"ball material\"\n\n[[sphere]]\nname = \"other\"\ncenter = [3, 0, 0]\n"
    );
    // The ball's material is the default but for its diffuse; the other ball keeps the default.
    assert_eq!(
        material(&s, "ball"),
        &Material {
            name: "ball material".into(),
            diffuse: 0.4,
            ..Material::default()
        }
    );
    assert_eq!(material(&s, "other"), &Material::default());
    // A second edit edits that material.
    d.apply(&Edit::SetMaterial {
        group: ball,
        field: MaterialField::Color,
        value: MaterialValue::Color([0.0, 0.0, 1.0]),
    })
    .unwrap();
    assert!(
        d.text()
            .contains("name = \"ball material\"\ndiffuse = 0.4\ncolor = [0, 0, 1]\n")
    );
    // The name is unique.
    let other = group(&before, "other");
    let text2 = d.text().replace("\"ball material\"", "\"other material\"");
    let mut d2 = doc(&text2);
    d2.apply(&Edit::SetMaterial {
        group: other,
        field: MaterialField::Specular,
        value: MaterialValue::Number(0.0),
    })
    .unwrap();
    assert!(
        d2.text()
            .contains("[[material]]\nname = \"other material 2\"\nspecular = 0\n")
    );
    assert!(d2.text().ends_with("material = \"other material 2\"\n"));
    // Undo takes both the material and the key away.
    d.undo();
    d.undo();
    assert_eq!(d.text(), text);
}

#[test]
fn a_first_material_goes_before_the_objects() {
    let text =
        "# Lit.\n[[light]]\nposition = [0, 5, 0]\n\n# The objects.\n[[sphere]]\nradius = 2\n";
    let mut d = doc(text);
    let before = d.scene().unwrap();
    let s = d
        .apply(&Edit::SetMaterial {
            group: 0,
            field: MaterialField::Shininess,
            value: MaterialValue::Number(50.0),
        })
        .unwrap();
    assert_eq!(
        d.text(),
        "# Lit.\n[[light]]\nposition = [0, 5, 0]\n\n[[material]]\nname = \"sphere 0 material\"\nshininess = 50\n\n# The objects.\n[[sphere]]\nradius = 2\nmaterial = \"sphere 0 material\"\n"
    );
    assert_eq!(material(&s, "sphere 0").shininess, 50.0);
    assert_eq!(s.objects[0].shape, before.objects[0].shape);
}

#[test]
fn editing_lights() {
    let mut d = shipped("triangles.toml");
    let scene = d.scene().unwrap();
    assert_eq!(scene.lights[1].name, "fill");
    let s = d
        .apply(&Edit::SetLight {
            light: 1,
            field: LightField::Position,
            value: [7.5, 4.0, -6.0],
        })
        .unwrap();
    assert_eq!(s.lights[1].position, Vec3::new(7.5, 4.0, -6.0));
    assert_eq!(s.lights[0], scene.lights[0]);
    let s = d
        .apply(&Edit::SetLight {
            light: 0,
            field: LightField::Color,
            value: [1.0, 0.5, 0.25],
        })
        .unwrap();
    assert_eq!(s.lights[0].color, Vec3::new(1.0, 0.5, 0.25));
    let text = std::fs::read_to_string(scenes_dir().join("triangles.toml")).unwrap();
    assert_eq!(
        changed_lines(&text, d.text()),
        ["color = [1, 0.5, 0.25]\n", "position = [7.5, 4, -6]\n"]
    );
    // A light with no colour gets one.
    let mut d = doc(BALL);
    d.apply(&Edit::SetLight {
        light: 0,
        field: LightField::Color,
        value: [0.5, 0.5, 0.5],
    })
    .unwrap();
    assert!(
        d.text()
            .contains("name = \"sun\"\nposition = [-10, 10, -10]\ncolor = [0.5, 0.5, 0.5]\n\n")
    );
}

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

/// The ball moved and the second sphere given a material of its own.
fn two_edits(d: &mut SceneDoc) {
    let scene = d.scene().unwrap();
    d.apply(&Edit::Move {
        group: group(&scene, "ball"),
        by: [1.0, 0.0, 0.5],
    })
    .unwrap();
    d.apply(&Edit::SetMaterial {
        group: group(&scene, "sphere 1"),
        field: MaterialField::Ambient,
        value: MaterialValue::Number(0.2),
    })
    .unwrap();
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
fn moving_any_object_of_a_shipped_scene_changes_one_line() {
    for f in std::fs::read_dir(scenes_dir()).unwrap() {
        let path = f.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let mut d = SceneDoc::parse(&text, "x", path.parent()).unwrap();
        // The document as opened is the file, byte for byte.
        assert_eq!(d.text(), text);
        let scene = d.scene().unwrap();
        for (g, e) in d.entries().into_iter().enumerate() {
            let s = d
                .apply(&Edit::Move {
                    group: g as u32,
                    by: [0.5, 0.25, -1.0],
                })
                .unwrap();
            let changed = changed_lines(&text, d.text());
            let key = match e.kind {
                EntryKind::Sphere => "center = [",
                EntryKind::Plane => "",
                EntryKind::Triangle => "vertices = [[",
                EntryKind::Mesh => "translate = [",
            };
            assert_eq!(changed.len(), 1, "{}: {changed:?}", path.display());
            assert!(changed[0].starts_with(key), "{changed:?}");
            // Only that group's objects changed.
            for (a, b) in scene.objects.iter().zip(&s.objects) {
                assert!(a.group == g as u32 || a == b);
            }
            assert!(same(&d.undo().unwrap().unwrap(), &scene));
            assert_eq!(d.text(), text, "{}", path.display());
        }
        assert!(!d.dirty() && !d.can_undo() && d.can_redo());
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

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Random moves of random objects, then as many undos: the original text, byte for byte;
    /// then as many redos: the text after the moves.
    #[test]
    fn moves_then_undos_give_back_the_original(
        moves in proptest::collection::vec(
            (0u32..64, proptest::array::uniform3(-2000i32..2000), 0u32..4),
            1..16,
        ),
        cornell in any::<bool>(),
    ) {
        let mut d = if cornell { shipped("cornell.toml") } else { shipped("triangles.toml") };
        let original = d.text().to_string();
        let n = d.scene().unwrap().groups.len() as u32;
        for &(g, by, scale) in &moves {
            let by = by.map(|c| c as f64 / 10f64.powi(scale as i32));
            let s = d.apply(&Edit::Move { group: g % n, by }).unwrap();
            prop_assert!(same(&s, &d.scene().unwrap()));
        }
        let after = d.text().to_string();
        for _ in 0..moves.len() {
            d.undo();
        }
        prop_assert_eq!(d.text(), original.as_str());
        prop_assert!(!d.can_undo());
        while d.redo().is_some() {}
        prop_assert_eq!(d.text(), after.as_str());
    }
}
