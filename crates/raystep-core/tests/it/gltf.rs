//! glTF 2.0 scenes: the shipped models (written by tools/make-gltf.py, checked with Khronos's
//! validator) read as their files say, worked out by hand; `.gltf` and `.glb` read alike; a
//! `[[gltf]]` table places a file; bad files name the JSON path, and nothing panics.

use base64::Engine;
use glam::Vec3;
use proptest::prelude::*;
use raystep_core::scene::{BsdfKind, Integrator, Scene, SceneError, Shape, load_file};
use std::path::{Path, PathBuf};
use tempfile::TempDir;

fn root() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).to_path_buf()
}

fn load(rel: &str) -> Scene {
    load_file(&root().join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// The triangles of the group `name`.
fn triangles(s: &Scene, name: &str) -> Vec<[Vec3; 3]> {
    let g = s
        .find_group(name)
        .unwrap_or_else(|| panic!("no group {name}"));
    (g.first..g.first + g.count)
        .map(|i| match s.objects[i as usize].shape {
            Shape::Triangle { p } => p,
            other => panic!("{other:?}"),
        })
        .collect()
}

/// The triangles an instance places: its prototype's, carried to the world by its matrix.
fn placed(s: &Scene, name: &str) -> Vec<[Vec3; 3]> {
    let inst = s
        .instances
        .iter()
        .find(|i| i.name == name)
        .unwrap_or_else(|| panic!("no instance {name}"));
    let g = &s.groups[inst.group as usize];
    (g.first..g.first + g.count)
        .map(|i| match s.objects[i as usize].shape {
            Shape::Triangle { p } => p.map(|v| inst.to_world.point(v)),
            other => panic!("{other:?}"),
        })
        .collect()
}

fn bounds(tris: &[[Vec3; 3]]) -> (Vec3, Vec3) {
    let all = tris.iter().flatten();
    let lo = all.clone().fold(Vec3::INFINITY, |a, &b| a.min(b));
    let hi = all.fold(Vec3::NEG_INFINITY, |a, &b| a.max(b));
    (lo, hi)
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

/// table.gltf opened as a scene, against its file (tools/make-gltf.py) worked by hand.
#[test]
fn the_table_reads_as_its_file_says() {
    let s = load("scenes/gltf/table.gltf");
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    assert_eq!(s.settings.integrator, Integrator::Path);
    // Named by the file's bytes (`sha256sum scenes/gltf/table.gltf`), not the text that
    // includes it.
    assert_eq!(
        s.source_hash,
        "13375f593336968c02e5e4bb107b8b8512de08cb7e70ae3d500e930f9de37773"
    );
    // The camera node: at (0, 1.3, 2.6), turned −12° about x. Looking down −z turned by −12°
    // about x: (0, sin(−12°), −cos 12°) = (0, −0.2079117, −0.9781476). yfov 0.7 rad = 40.107°;
    // aspect 4/3 on the opening scene's 360 rows: 480 columns.
    let c = &s.camera;
    assert!(close(c.from, Vec3::new(0.0, 1.3, 2.6), 1e-6));
    assert!(close(
        c.at - c.from,
        Vec3::new(0.0, -0.207_911_7, -0.978_147_6),
        1e-6
    ));
    assert!(close(c.up, Vec3::new(0.0, 0.978_147_6, -0.207_911_7), 1e-6));
    assert!((c.fov - 40.107_04).abs() < 1e-4, "{}", c.fov);
    assert_eq!((c.width, c.height), (480, 360));
    // The point light: colour (1, 0.95, 0.9) × intensity 6, at its node.
    assert_eq!(s.lights.len(), 1);
    assert_eq!(s.lights[0].name, "table/lamp");
    assert!(close(s.lights[0].position, Vec3::new(1.0, 2.2, 1.5), 1e-6));
    assert!(close(s.lights[0].color, Vec3::new(6.0, 5.7, 5.4), 1e-5));
    // One box mesh, five nodes: one prototype of 12 triangles (the unit box, in the mesh's own
    // space) and five instances; the 12 × 8 sphere 168 triangles; the pane 2.
    let unit = triangles(&s, "table/box");
    assert_eq!(unit.len(), 12);
    let (lo, hi) = bounds(&unit);
    assert!(close(lo, Vec3::splat(-0.5), 0.0) && close(hi, Vec3::splat(0.5), 0.0));
    assert_eq!(s.objects.len(), 12 + 168 + 2);
    assert_eq!(s.features.meshes, 3);
    assert_eq!((s.instances.len(), s.prototypes.len()), (5, 1));
    // The top: the unit box scaled (1.2, 0.08, 0.8), moved up 0.74 (its parent, "table", has no
    // transform): x ∈ ±0.6, y ∈ 0.74 ± 0.04, z ∈ ±0.4. Its 6 faces are 12 triangles.
    let top = placed(&s, "table/top");
    assert_eq!(top.len(), 12);
    let (lo, hi) = bounds(&top);
    assert!(close(lo, Vec3::new(-0.6, 0.70, -0.4), 1e-6), "{lo}");
    assert!(close(hi, Vec3::new(0.6, 0.78, 0.4), 1e-6), "{hi}");
    // A leg: scaled (0.08, 0.7, 0.08), at (0.5, 0.35, 0.3).
    let (lo, hi) = bounds(&placed(&s, "table/leg +1+1"));
    assert!(close(lo, Vec3::new(0.46, 0.0, 0.26), 1e-6), "{lo}");
    assert!(close(hi, Vec3::new(0.54, 0.7, 0.34), 1e-6), "{hi}");
    // The pane: the unit quad scaled (0.35, 0.4, 1), turned 30° about y, at (−0.25, 0.98, 0).
    // Its corner (0.5, 0.5, 0) → (0.175, 0.2, 0) → (0.175·cos 30°, 0.2, −0.175·sin 30°) + t.
    let pane = triangles(&s, "table/pane");
    let corner = Vec3::new(
        -0.25 + 0.175 * 30f32.to_radians().cos(),
        0.98 + 0.2,
        -0.175 * 0.5,
    );
    assert!(
        pane.iter().flatten().any(|&p| close(p, corner, 1e-6)),
        "{pane:?}"
    );
    // Its normals: (0, 0, 1) turned 30° about y = (sin 30°, 0, cos 30°) (the scale leaves z).
    let g = s.find_group("table/pane").unwrap();
    let n = s.vertex_normals_of(g.first).expect("the pane has NORMAL");
    assert!(close(n[0], Vec3::new(0.5, 0.0, 0.866_025_4), 1e-6), "{n:?}");
    // Its uvs: glTF's (0, 1) at the corner (−0.5, −0.5) is the image's bottom-left, raystep's
    // (0, 0); glTF's (1, 0), the top-right, is raystep's (1, 1).
    let uv = s.vertex_uvs_of(g.first).expect("the pane has TEXCOORD_0");
    assert_eq!(uv[0], [0.0, 0.0]);
    assert_eq!(uv[2], [1.0, 1.0]);
}

/// The materials of table.gltf, by the mapping of README.md's *glTF scenes*.
#[test]
fn the_tables_materials_map_as_documented() {
    let s = load("scenes/gltf/table.gltf");
    let m = |n: &str| {
        s.materials
            .iter()
            .find(|m| m.name == n)
            .unwrap_or_else(|| panic!("no material {n}"))
    };
    // Wood: metallic 0, roughness 0.8, base colour (0.9, 0.75, 0.55) × the tiles image.
    let wood = m("table/wood");
    assert_eq!(wood.bsdf, Some(BsdfKind::Diffuse));
    assert_eq!(wood.color, Vec3::new(0.9, 0.75, 0.55));
    let t = &s.textures[wood.texture.unwrap() as usize];
    assert_eq!(t.name, "table/tiles");
    assert_eq!(t.levels()[0].width, 8);
    // Phong: diffuse 0.9·(1 − 0·0.2) = 0.9, specular 0.9·0.2 = 0.18, reflective 0.
    assert!((wood.diffuse - 0.9).abs() < 1e-6 && (wood.specular - 0.18).abs() < 1e-6);
    assert_eq!(wood.reflective, 0.0);
    // Steel: metallic 1, roughness 0.3: glossy with roughness 0.3; Phong diffuse 0.9·0.3 = 0.27,
    // specular 0.9·0.7 = 0.63, reflective 0.7² = 0.49, shininess 2/α² − 2, α = 0.09: 244.91.
    let steel = m("table/steel");
    assert_eq!(steel.bsdf, Some(BsdfKind::Glossy));
    assert!((steel.roughness - 0.3).abs() < 1e-7);
    assert!((steel.diffuse - 0.27).abs() < 1e-6);
    assert!((steel.specular - 0.63).abs() < 1e-6);
    assert!((steel.reflective - 0.49).abs() < 1e-6);
    assert!(
        (steel.shininess - 244.913_58).abs() < 1e-2,
        "{}",
        steel.shininess
    );
    // Glass: transmission 1, ior 1.45.
    let glass = m("table/glass");
    assert_eq!(glass.bsdf, Some(BsdfKind::Glass));
    assert_eq!((glass.transparency, glass.refractive_index), (1.0, 1.45));
}

/// The GLB (its buffer in the binary chunk, its image in a buffer view) reads as the .gltf
/// with its .bin and its PNG beside it: the same triangles, normals, uvs, materials and texels.
#[test]
fn a_glb_reads_as_its_gltf() {
    let a = load("scenes/gltf/table.gltf");
    let b = load("tests/gltf/table.glb");
    assert_eq!(a.objects, b.objects);
    assert_eq!(a.vertex_normals, b.vertex_normals);
    assert_eq!(a.vertex_uvs, b.vertex_uvs);
    assert_eq!(a.camera, b.camera);
    assert_eq!(a.lights, b.lights);
    let colours = |s: &Scene| s.materials.iter().map(|m| m.color).collect::<Vec<_>>();
    assert_eq!(colours(&a), colours(&b));
    let (ta, tb) = (&a.textures[0], &b.textures[0]);
    for (x, y) in [(0, 0), (3, 5), (7, 7)] {
        assert_eq!(ta.texel(x, y), tb.texel(x, y));
    }
}

/// lamp.gltf: a quad under a 4 × 4 matrix (+90° about x, then up 2), under a parent scaled
/// (2, 1, 0.5); emissive (1, 0.5, 0.25) × strength 4. Opened alone: no camera (the view is
/// framed, said in a warning), and something emits, so no headlight.
#[test]
fn a_matrix_under_a_scaled_parent_and_an_emissive_material() {
    let s = load("tests/gltf/lamp.gltf");
    // The matrix's columns (1,0,0), (0,0,1), (0,−1,0), (0,2,0): (x, y, z) → (x, 2 − z, y); the
    // quad's corners (±0.5, ±0.5, 0) → (±0.5, 2, ±0.5); scaled: (±1, 2, ±0.25).
    let (lo, hi) = bounds(&triangles(&s, "lamp/panel"));
    assert_eq!(
        (lo, hi),
        (Vec3::new(-1.0, 2.0, -0.25), Vec3::new(1.0, 2.0, 0.25))
    );
    // Its normal (0, 0, 1) → (0, −1, 0): it faces down, and the scale leaves it so.
    let n = s.vertex_normals_of(0).unwrap();
    assert!(close(n[0], Vec3::new(0.0, -1.0, 0.0), 1e-7), "{n:?}");
    assert_eq!(s.materials[0].emission, Vec3::new(4.0, 2.0, 1.0));
    assert_eq!(s.features.emitters, 2);
    assert!(s.lights.is_empty(), "something emits: no headlight");
    // Framed: the box's centre (0, 2, 0), its half-diagonal |(2, 0, 0.5)|/2 = 1.0307764; at
    // 1.0307764/sin 22.5° × 1.1 = 1.0307764/0.3826834 × 1.1 = 2.9629034 from it, towards +z and
    // 20° up: (0, 2 + 2.9629034·sin 20°, 2.9629034·cos 20°) = (0, 3.0133726, 2.7842185).
    assert!(close(s.camera.at, Vec3::new(0.0, 2.0, 0.0), 1e-6));
    assert!(
        close(
            s.camera.from,
            Vec3::new(0.0, 3.013_372_6, 2.784_218_5),
            1e-5
        ),
        "{}",
        s.camera.from
    );
    assert_eq!(s.camera.fov, 45.0);
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("no perspective camera")),
        "{:?}",
        s.warnings
    );
}

/// A glTF file written from parts: `json` with `BUFFER` replaced by a data: URI of `bytes`.
fn gltf_text(json: &str, bytes: &[u8]) -> String {
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes)
    );
    json.replace("BUFFER", &uri)
}

fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// One triangle with vertex normals along (1, 1, 0)/√2, under a node scaled (2, 1, 1).
const SHEARED: &str = r#"{
 "asset": {"version": "2.0"},
 "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"name": "wide", "mesh": 0, "scale": [2, 1, 1]}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}}]}],
 "accessors": [
  {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]},
  {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"}
 ],
 "bufferViews": [{"buffer": 0, "byteLength": 72}],
 "buffers": [{"byteLength": 72, "uri": "BUFFER"}]
}"#;

fn sheared_bytes() -> Vec<u8> {
    let h = std::f32::consts::FRAC_1_SQRT_2;
    f32s(&[
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, // positions
        h, h, 0.0, h, h, 0.0, h, h, 0.0, // normals
    ])
}

/// Written into a fresh folder as `name`, loaded (the folder is kept while the result lives).
fn load_text(name: &str, text: &str) -> (TempDir, Result<Scene, SceneError>) {
    let dir = TempDir::new().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    let r = load_file(&path);
    (dir, r)
}

/// Normals go by the inverse transpose: (1, 1, 0) under diag(2, 1, 1) is (1/2, 1, 0),
/// normalised (0.4472136, 0.8944272, 0) — the matrix itself would give (2, 1, 0)/√5, wrong.
/// Nothing lights it and nothing emits: the opening scene adds a headlight at the camera.
#[test]
fn normals_go_by_the_inverse_transpose() {
    let (_d, s) = load_text("wide.gltf", &gltf_text(SHEARED, &sheared_bytes()));
    let s = s.unwrap();
    let n = s.vertex_normals_of(0).unwrap();
    assert!(
        close(n[0], Vec3::new(0.447_213_6, 0.894_427_2, 0.0), 1e-6),
        "{n:?}"
    );
    assert_eq!(triangles(&s, "wide/wide")[0][1], Vec3::new(2.0, 0.0, 0.0));
    assert_eq!(s.lights.len(), 1);
    assert_eq!(s.lights[0].position, s.camera.from);
    assert!(
        s.warnings.iter().any(|w| w.contains("headlight")),
        "{:?}",
        s.warnings
    );
}

/// What a file holds and raystep does not read is named in one warning (with a second for the
/// headlight this file, with no light raystep reads, is given).
#[test]
fn what_is_not_read_is_named_in_one_warning() {
    let json = SHEARED
        .replace(
            r#""scene": 0, "scenes": [{"nodes": [0]}],"#,
            r#""extensionsUsed": ["KHR_texture_transform", "KHR_lights_punctual"],
 "extensions": {"KHR_lights_punctual": {"lights": [{"type": "spot", "spot": {}}, {"type": "directional"}]}},
 "scene": 0, "scenes": [{"nodes": [0, 1, 2]}, {"nodes": [0]}],"#,
        )
        .replace(
            r#""nodes": [{"name": "wide", "mesh": 0, "scale": [2, 1, 1]}],"#,
            r#""nodes": [{"name": "wide", "mesh": 0}, {"extensions": {"KHR_lights_punctual": {"light": 0}}}, {"extensions": {"KHR_lights_punctual": {"light": 1}}}],"#,
        )
        .replace(
            r#"{"attributes": {"POSITION": 0, "NORMAL": 1}}]"#,
            r#"{"attributes": {"POSITION": 0, "NORMAL": 1}}, {"attributes": {"POSITION": 0}, "mode": 1}]"#,
        );
    let (_d, s) = load_text("odd.gltf", &gltf_text(&json, &sheared_bytes()));
    let s = s.unwrap();
    let not_read: Vec<&String> = s
        .warnings
        .iter()
        .filter(|w| w.contains("not read"))
        .collect();
    assert_eq!(not_read.len(), 1, "{:?}", s.warnings);
    for part in [
        "not read: extension KHR_texture_transform",
        "scenes other than the default (2 in the file)",
        "primitives that are not triangles (meshes[0].primitives[1] (Lines))",
        "1 directional light (",
        "1 spot light (",
    ] {
        assert!(not_read[0].contains(part), "{part}: {}", not_read[0]);
    }
    assert_eq!(s.objects.len(), 1, "the triangles are read");
    assert!(
        s.warnings.iter().any(|w| w.contains("headlight")),
        "{:?}",
        s.warnings
    );
}

/// A `[[gltf]]` table places the file by scale, rotate (x, then y, then z) and translate; its
/// `material` replaces the file's; `camera = "front"` takes that camera.
#[test]
fn a_scene_includes_a_gltf_file() {
    let dir = TempDir::new().unwrap();
    std::fs::write(
        dir.path().join("wide.gltf"),
        gltf_text(SHEARED, &sheared_bytes()),
    )
    .unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(
        &path,
        "[[material]]\nname = \"red\"\ncolor = [1, 0, 0]\n\n[[gltf]]\nname = \"w\"\nfile = \"wide.gltf\"\nscale = 3\nrotate = [0, 0, 90]\ntranslate = [0, 0, 5]\nmaterial = \"red\"\n",
    )
    .unwrap();
    let s = load_file(&path).unwrap();
    // (1, 0, 0) → wide (2, 0, 0) → scale 3: (6, 0, 0) → 90° about z: (0, 6, 0) → (0, 6, 5).
    let t = triangles(&s, "w/wide")[0];
    assert!(close(t[1], Vec3::new(0.0, 6.0, 5.0), 1e-5), "{t:?}");
    assert_eq!(s.material_of(0).name, "red");
    // The included file has no lights and the scene is not a glTF opened alone: no headlight.
    assert!(s.lights.is_empty());

    let table = root().join("scenes/gltf/table.gltf");
    std::fs::write(
        &path,
        format!(
            "[camera]\nwidth = 200\nheight = 100\n\n[[gltf]]\nfile = {:?}\ncamera = \"front\"\nlights = false\n",
            table.display().to_string()
        ),
    )
    .unwrap();
    let s = load_file(&path).unwrap();
    assert!(close(s.camera.from, Vec3::new(0.0, 1.3, 2.6), 1e-6));
    // The file's cameras stay known by name (`--camera`).
    assert_eq!(s.cameras.len(), 1);
    assert_eq!(s.cameras[0].name, "front");
    // The scene's [camera] keeps its size.
    assert_eq!((s.camera.width, s.camera.height), (200, 100));
    assert!(s.lights.is_empty());
}

/// An error of a file opened alone: the glTF file named, then what is expected of the message.
fn gltf_fails(json: &str) -> SceneError {
    let (_d, r) = load_text("bad.gltf", json);
    let e = r.expect_err("this file should not load");
    assert!(e.file.ends_with("bad.gltf"), "{e}");
    e
}

#[test]
fn bad_gltf_files_name_the_json_path() {
    // A JSON syntax error: its line and column.
    let e = gltf_fails("{\n \"asset\": {\"version\": \"2.0\"},\n \"nodes\": [,]\n}\n");
    assert_eq!((e.line, e.column), (Some(3), Some(12)), "{e}");
    // An index past the end, found by the reader's validation: its JSON path.
    let e = gltf_fails(
        r#"{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {"POSITION": 4}}]}]}"#,
    );
    assert_eq!(
        e.field.as_deref(),
        Some("meshes[0].primitives[0].attributes[\"POSITION\"]"),
        "{e}"
    );
    assert!(e.message.contains("does not exist"), "{e}");
    // An accessor claiming more data than its buffer holds.
    let json = SHEARED.replace(
        "\"count\": 3, \"type\": \"VEC3\", \"min\"",
        "\"count\": 300, \"type\": \"VEC3\", \"min\"",
    );
    let e = gltf_fails(&gltf_text(&json, &sheared_bytes()));
    assert_eq!(e.field.as_deref(), Some("accessors[0].byteOffset"), "{e}");
    assert!(e.message.contains("do not fit"), "{e}");
    // NORMAL as VEC2 (POSITION's min and max make the validator check its type itself).
    let json = SHEARED.replacen(
        "\"byteOffset\": 36, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\"",
        "\"byteOffset\": 36, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC2\"",
        1,
    );
    let e = gltf_fails(&gltf_text(&json, &sheared_bytes()));
    assert_eq!(e.field.as_deref(), Some("accessors[1].type"), "{e}");
    assert!(
        e.message
            .contains("expected Vec3 of F32, found Vec2 of F32"),
        "{e}"
    );
    // A buffer file that is not there.
    let e = gltf_fails(&SHEARED.replace("BUFFER", "missing.bin"));
    assert_eq!(e.field.as_deref(), Some("buffers[0].uri"), "{e}");
    assert!(e.message.contains("missing.bin does not exist"), "{e}");
    // A node that is its own ancestor.
    let e = gltf_fails(
        r#"{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"children": [1]}, {"children": [0]}]}"#,
    );
    assert_eq!(e.field.as_deref(), Some("nodes[0]"), "{e}");
    // An image in a buffer view without its mimeType (the gltf crate would unwrap it: a panic).
    let e = gltf_fails(
        r#"{"asset": {"version": "2.0"}, "images": [{"bufferView": 0}], "bufferViews": [{"buffer": 0, "byteLength": 1}], "buffers": [{"byteLength": 1, "uri": "data:application/octet-stream;base64,AA=="}]}"#,
    );
    assert_eq!(e.field.as_deref(), Some("images[0].mimeType"), "{e}");
    // A GLB whose header declares fewer bytes than the header itself (the fuzzer's find: the
    // crate's subtraction overflowed).
    let mut glb = b"glTF".to_vec();
    glb.extend(2u32.to_le_bytes());
    glb.extend(4u32.to_le_bytes());
    glb.extend([0; 40]);
    let (_d, r) = load_text("short.glb", &String::from_utf8(glb).unwrap());
    let e = r.expect_err("a GLB of length 4");
    assert!(e.message.contains("a length of 4 bytes"), "{e}");
    // An extension raystep cannot read, required.
    let e = gltf_fails(
        r#"{"asset": {"version": "2.0"}, "extensionsRequired": ["KHR_draco_mesh_compression"], "extensionsUsed": ["KHR_draco_mesh_compression"]}"#,
    );
    assert!(
        e.field
            .as_deref()
            .unwrap_or("")
            .starts_with("extensionsRequired[0]"),
        "{e}"
    );
}

/// An error inside an included file names the glTF file and where the scene includes it; a
/// camera that is not there lists those that are.
#[test]
fn an_included_files_errors_say_where_it_is_included() {
    let dir = TempDir::new().unwrap();
    std::fs::write(
        dir.path().join("bad.gltf"),
        SHEARED.replace("BUFFER", "nothing.bin"),
    )
    .unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, "title = \"t\"\n\n[[gltf]]\nfile = \"bad.gltf\"\n").unwrap();
    let e = load_file(&path).unwrap_err();
    assert!(e.file.ends_with("bad.gltf"), "{e}");
    // Line 3 is the `[[gltf]]` header; the `file` field, line 4, is where the file is named.
    assert!(
        e.message
            .contains(&format!("included by {}:4:1", path.display())),
        "{e}"
    );

    let table = root().join("scenes/gltf/table.gltf");
    std::fs::write(
        &path,
        format!(
            "[[gltf]]\nfile = {:?}\ncamera = \"side\"\n",
            table.display().to_string()
        ),
    )
    .unwrap();
    let e = load_file(&path).unwrap_err();
    assert_eq!((e.line, e.column), (Some(3), Some(1)), "{e}");
    assert!(
        e.message
            .contains("no camera named \"side\" (known: \"front\")"),
        "{e}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]
    /// Any byte of the GLB changed, or the file cut short: an error or a scene, never a panic.
    #[test]
    fn a_damaged_glb_never_panics(at in 0usize..10_148, byte in any::<u8>(), cut in prop::option::of(0usize..10_148)) {
        let mut bytes = std::fs::read(root().join("tests/gltf/table.glb")).unwrap();
        let at = at % bytes.len();
        bytes[at] = byte;
        if let Some(c) = cut {
            bytes.truncate(c);
        }
        let dir = TempDir::new().unwrap();
        // The image it names is beside it (the GLB holds its own; this keeps a damaged URI local).
        let path = dir.path().join("t.glb");
        std::fs::write(&path, &bytes).unwrap();
        let _ = load_file(&path);
    }
}

/// The sheared triangle's mesh placed by four nodes: "wide" (its mesh's name too), "up" (moved
/// up 3), "flat" (scaled to nothing in z… and in y: no inverse) and "lit" (a second mesh of the
/// same triangle whose material emits). Two instances of one prototype, named after the nodes;
/// the flattened node and the emitting mesh's two nodes copied into the world.
const SHARED: &str = r#"{
 "asset": {"version": "2.0"},
 "scene": 0, "scenes": [{"nodes": [0, 1, 2, 3, 4]}],
 "nodes": [
  {"name": "wide", "mesh": 0, "scale": [2, 1, 1]},
  {"name": "up", "mesh": 0, "translation": [0, 3, 0]},
  {"name": "flat", "mesh": 0, "scale": [1, 0, 0]},
  {"name": "lit", "mesh": 1, "translation": [5, 0, 0]},
  {"name": "lit too", "mesh": 1, "translation": [7, 0, 0]}
 ],
 "meshes": [
  {"name": "wide", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}}]},
  {"name": "lamp", "primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}
 ],
 "materials": [{"name": "glow", "emissiveFactor": [1, 1, 1]}],
 "accessors": [
  {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]},
  {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"}
 ],
 "bufferViews": [{"buffer": 0, "byteLength": 72}],
 "buffers": [{"byteLength": 72, "uri": "BUFFER"}]
}"#;

#[test]
fn a_mesh_that_several_nodes_place_becomes_instances() {
    let (_d, s) = load_text("shared.gltf", &gltf_text(SHARED, &sheared_bytes()));
    let s = s.unwrap();
    // The prototype, named after its mesh and set apart from the node "wide".
    assert_eq!(s.prototypes.len(), 1);
    let proto = &s.groups[s.prototypes[0].group as usize];
    assert_eq!(proto.name, "shared/wide (mesh)");
    let names: Vec<&str> = s.instances.iter().map(|i| i.name.as_str()).collect();
    assert_eq!(names, ["shared/wide", "shared/up"]);
    // Placed as the nodes say: the wide one's far corner at (2, 0, 0), the other's top at (0, 4, 0).
    assert!(placed(&s, "shared/wide")[0].contains(&Vec3::new(2.0, 0.0, 0.0)));
    assert!(placed(&s, "shared/up")[0].contains(&Vec3::new(0.0, 4.0, 0.0)));
    // In object space the vertex normals are the file's; M⁻ᵀ carries them when a ray hits.
    let n = s.vertex_normals_of(proto.first).unwrap();
    let h = std::f32::consts::FRAC_1_SQRT_2;
    assert!(close(n[0], Vec3::new(h, h, 0.0), 1e-6));
    // Copied into the world: the node with no inverse, and both nodes of the emitting mesh.
    assert_eq!(triangles(&s, "shared/flat").len(), 1);
    assert_eq!(triangles(&s, "shared/lit")[0][0], Vec3::new(5.0, 0.0, 0.0));
    assert_eq!(
        triangles(&s, "shared/lit too")[0][0],
        Vec3::new(7.0, 0.0, 0.0)
    );
    assert_eq!(s.objects.len(), 4);
}

/// The table placed by instances renders as the table copied into the world: the same file
/// with its box mesh's five nodes given five meshes of their own (no mesh shared) is the
/// world-copy placement, raystep's reading before instances; the two images agree but for
/// pixels where the object-space and world-space arithmetic round an edge differently.
#[test]
fn the_instanced_table_renders_as_its_world_copies() {
    let text = std::fs::read_to_string(root().join("scenes/gltf/table.gltf")).unwrap();
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let box_mesh = json["meshes"][0].clone();
    let mut meshes = json["meshes"].as_array().unwrap().clone();
    let nodes = json["nodes"].as_array_mut().unwrap();
    for n in nodes.iter_mut().filter(|n| n["mesh"] == 0).skip(1) {
        n["mesh"] = serde_json::json!(meshes.len());
        meshes.push(box_mesh.clone());
    }
    json["meshes"] = serde_json::Value::Array(meshes);
    // Beside its buffer and its texture, as in scenes/.
    let dir = TempDir::new().unwrap();
    for f in ["gltf/table.bin", "textures/tiles-8x8.png"] {
        let to = dir.path().join(f);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(root().join("scenes").join(f), to).unwrap();
    }
    let copies_path = dir.path().join("gltf/table.gltf");
    std::fs::write(&copies_path, json.to_string()).unwrap();
    let mut copies = load_file(&copies_path).unwrap();
    let mut shared = load("scenes/gltf/table.gltf");
    assert_eq!((shared.instances.len(), copies.instances.len()), (5, 0));
    for s in [&mut copies, &mut shared] {
        s.camera.width = 96;
        s.camera.height = 72;
        s.settings.integrator = Integrator::Whitted;
    }
    let render = |s: &Scene| {
        let (accel, _) = raystep_core::accel::SceneAccel::build(s);
        let tracer = raystep_core::trace::Tracer::new(s, &accel);
        raystep_core::render::render(&tracer, &raystep_core::render::RenderOptions::default())
            .unwrap()
            .pixels
    };
    let (a, b) = (render(&shared), render(&copies));
    let off = a
        .iter()
        .zip(&b)
        .filter(|(x, y)| (**x - **y).abs().max_element() > 2.0 / 255.0)
        .count();
    let mean = |v: &[Vec3]| v.iter().copied().sum::<Vec3>() / v.len() as f32;
    assert!(off * 100 <= a.len(), "{off} of {} pixels differ", a.len());
    assert!(close(mean(&a), mean(&b), 1e-3), "{} {}", mean(&a), mean(&b));
}
