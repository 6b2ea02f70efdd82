//! Materials (shared, new, the first one) and lights.

use super::*;

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
