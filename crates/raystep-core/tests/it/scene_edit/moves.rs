//! Moving objects: only the touched values change, numbers keep their style and lose their
//! binary noise, a missing field is added.

use super::*;

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

#[test]
fn moving_any_object_of_a_shipped_scene_changes_one_line() {
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
