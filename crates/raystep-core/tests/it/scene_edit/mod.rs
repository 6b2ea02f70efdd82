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
/// Whether a scene's text includes a glTF file (the editor refuses such a scene).
fn text_includes_gltf(text: &str) -> bool {
    text.lines().any(|l| l.trim() == "[[gltf]]")
}

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

mod mapping;
mod materials_and_lights;
mod moves;
mod undo_and_save;
