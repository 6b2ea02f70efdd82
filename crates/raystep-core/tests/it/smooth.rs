//! Smooth shading: vertex normals blended with the hit's barycentrics. Expected values come from
//! a hand computation, from the OBJ file's own text re-read here in f64, and from the symmetry
//! of a regular icosahedron; never from the loader or the tracer under test.

use glam::Vec3;
use raystep_core::accel::{Hit, SceneAccel};
use raystep_core::math::Ray;
use raystep_core::record::{Step, Trace};
use raystep_core::scene::{Scene, load_file, load_str};
use raystep_core::trace::Tracer;
use raystep_core::trace::interaction::interact;
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes")).to_path_buf()
}

/// One triangle in the plane z = 0 with a normal given at each corner, seen from −z.
const HAND: &str = r#"
[camera]
from = [0.25, 0.25, -5]
at = [0.25, 0.25, 0]
width = 8
height = 8
[[triangle]]
name = "t"
vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
normals = [[0, 0, -1], [1, 0, -1], [0, 1, -1]]
"#;

/// The ray along +z through (x, y) of the plane z = 0, and its hit on HAND's triangle (whose
/// u and v are x and y there: P = (1 − u − v)·(0, 0, 0) + u·(1, 0, 0) + v·(0, 1, 0)).
fn hand_hit(x: f32, y: f32) -> (Ray<f32>, Hit) {
    let ray = Ray::new(Vec3::new(x, y, -5.0), Vec3::Z, 0.0, f32::INFINITY).unwrap();
    let hit = Hit {
        object: 0,
        t: 5.0,
        u: x,
        v: y,
        instance: raystep_core::scene::NO_INSTANCE,
    };
    (ray, hit)
}

#[test]
fn a_shading_normal_computed_by_hand() {
    let scene = load_str(HAND, "hand.toml", None).unwrap();
    assert_eq!(scene.features.smooth, 1);
    let (ray, hit) = hand_hit(0.25, 0.25);
    let it = interact(&scene, &hit, &ray);
    // E1 × E2 = (0, 0, 1) points away from the eye at −z: flipped to (0, 0, −1).
    assert_eq!(it.normal, Vec3::new(0.0, 0.0, -1.0));
    // By hand: b₀ = 0.5; n₁ = (1, 0, −1)/√2, n₂ = (0, 1, −1)/√2;
    // s = 0.5·(0, 0, −1) + 0.25·n₁ + 0.25·n₂ = (0.1767767, 0.1767767, −0.8535534),
    // |s| = 0.8894118, s/|s| = (0.1987569, 0.1987569, −0.9596830), 16.324950° from (0, 0, −1).
    let want = [0.198_756_85, 0.198_756_85, -0.959_682_98];
    for (got, want) in it.shading_normal.to_array().iter().zip(want) {
        assert!((*got as f64 - want).abs() < 2e-7, "{:?}", it.shading_normal);
    }
    let angle = raystep_core::trace::interaction::angle_deg(it.shading_normal, it.normal);
    assert!((angle as f64 - 16.324_950).abs() < 1e-4, "{angle}");
}

#[test]
fn normals_that_cancel_fall_back_to_the_flat_normal_and_a_reversed_winding_is_turned() {
    // n₁ and n₂ opposite, n₀ zero weight at u = v = 0.5: the blend is (0, 0, 0).
    let text = HAND.replace(
        "normals = [[0, 0, -1], [1, 0, -1], [0, 1, -1]]",
        "normals = [[0, 0, -1], [0, 0, 1], [0, 0, -1]]",
    );
    let scene = load_str(&text, "cancel.toml", None).unwrap();
    let (ray, hit) = hand_hit(0.5, 0.5);
    let it = interact(&scene, &hit, &ray);
    assert_eq!(it.shading_normal, it.normal);
    // All three normals pointing away from the eye (+z): the blend is turned to face it.
    let text = HAND.replace(
        "normals = [[0, 0, -1], [1, 0, -1], [0, 1, -1]]",
        "normals = [[0, 0, 1], [0, 0, 1], [0, 0, 1]]",
    );
    let scene = load_str(&text, "away.toml", None).unwrap();
    let it = interact(&scene, &hit, &ray);
    assert_eq!(it.shading_normal, Vec3::new(0.0, 0.0, -1.0));
}

/// The OBJ file's vertices and normals, and its faces' normal indices, read here in f64.
fn read_obj(path: &Path) -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut normals = vec![];
    let mut faces = vec![];
    for line in text.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.first() {
            Some(&"vn") => normals.push([1, 2, 3].map(|i| w[i].parse::<f64>().unwrap())),
            Some(&"f") => faces.push(
                [1, 2, 3].map(|i| w[i].split("//").nth(1).unwrap().parse::<usize>().unwrap() - 1),
            ),
            _ => {}
        }
    }
    (normals, faces)
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / l)
}

fn record(scene: &Scene, x: u32, y: u32) -> Trace {
    let (accel, _) = SceneAccel::build(scene);
    Tracer::new(scene, &accel).record(x, y, 0)
}

#[test]
fn the_smooth_sphere_blends_the_files_normals_and_lights_with_the_blend() {
    let scene = load_file(&scenes_dir().join("smooth-shading.toml")).unwrap();
    let (vn, faces) = read_obj(&scenes_dir().join("low-poly-sphere.obj"));
    let smooth = scene.find_group("smooth sphere").unwrap().clone();
    let flat = scene.find_group("flat sphere").unwrap().clone();
    assert_eq!((smooth.count, flat.count), (80, 80));
    for k in 0..80 {
        assert!(scene.vertex_normals_of(flat.first + k).is_none());
        assert!(scene.vertex_normals_of(smooth.first + k).is_some());
    }
    let (mut checked, mut lights) = (0, 0);
    for y in (4..240).step_by(8) {
        for x in (4..320).step_by(8) {
            let trace = record(&scene, x, y);
            let steps = &trace.root.steps;
            let Some(hit) = &trace.root.hit else { continue };
            let at = steps
                .iter()
                .position(|s| matches!(s.step, Step::ShadingNormal { .. }));
            let on_smooth = (smooth.first..smooth.first + 80).contains(&hit.object);
            assert_eq!(at.is_some(), on_smooth, "pixel ({x}, {y})");
            let Some(at) = at else { continue };
            let Step::ShadingNormal {
                vertex_normals,
                u,
                v,
                normal,
                angle_deg,
                ..
            } = &steps[at].step
            else {
                unreachable!()
            };
            let Step::Surface {
                point,
                normal: geometric,
                ..
            } = &steps[at - 1].step
            else {
                panic!("the shading normal follows the surface")
            };
            let face = faces[(hit.object - smooth.first) as usize];
            let n = face.map(|i| unit(vn[i]));
            for (rec, file) in vertex_normals.iter().zip(n) {
                for c in 0..3 {
                    assert!((rec[c] as f64 - file[c]).abs() < 1e-6, "{rec:?} {file:?}");
                }
            }
            // In f64 from the file's normals and the recorded u, v.
            let (u, v) = (*u as f64, *v as f64);
            let want = unit([0, 1, 2].map(|c| (1.0 - u - v) * n[0][c] + u * n[1][c] + v * n[2][c]));
            for c in 0..3 {
                assert!(
                    (normal[c] as f64 - want[c]).abs() < 1e-6,
                    "{normal:?} {want:?}"
                );
            }
            let g = geometric.map(|c| c as f64);
            let cos = want[0] * g[0] + want[1] * g[1] + want[2] * g[2];
            assert!(
                (*angle_deg as f64 - cos.min(1.0).acos().to_degrees()).abs() < 1e-3,
                "{angle_deg} vs cos {cos}"
            );
            // Phong's l·n is taken with the shading normal.
            for s in &steps[at..] {
                if let Step::Light { light, l_dot_n, .. } = &s.step {
                    let lp = scene.lights[*light as usize].position.as_dvec3().to_array();
                    let d = unit([0, 1, 2].map(|c| lp[c] - point[c] as f64));
                    let ldn = d[0] * want[0] + d[1] * want[1] + d[2] * want[2];
                    assert!((*l_dot_n as f64 - ldn).abs() < 1e-5, "{l_dot_n} vs {ldn}");
                    lights += 1;
                }
            }
            checked += 1;
        }
    }
    assert!(
        checked > 50 && lights > 50,
        "{checked} hits, {lights} lights"
    );
}

#[test]
fn smooth_normals_of_a_regular_icosahedron_point_at_its_vertices() {
    // The file has no vn: `shading = "smooth"` averages the faces around each vertex. Every
    // vertex of a regular icosahedron centred at the origin sees its five faces symmetrically,
    // so the average points along the vertex itself.
    let text = r#"
[[mesh]]
name = "ico"
obj = "icosahedron.obj"
shading = "smooth"
"#;
    let dir = scenes_dir();
    let scene = load_str(text, "ico.toml", Some(&dir)).unwrap();
    assert_eq!(scene.features.smooth, 20);
    for id in 0..20u32 {
        let raystep_core::scene::Shape::Triangle { p } = scene.objects[id as usize].shape else {
            panic!()
        };
        let n = scene.vertex_normals_of(id).unwrap();
        for (p, n) in p.iter().zip(n) {
            let want = unit(p.as_dvec3().to_array());
            for c in 0..3 {
                assert!((n[c] as f64 - want[c]).abs() < 1e-6, "{n:?} {want:?}");
            }
        }
    }
    // Flat by default (no vn) and when asked.
    for shading in ["", "shading = \"flat\"\n"] {
        let text = format!("[[mesh]]\nobj = \"icosahedron.obj\"\n{shading}");
        let scene = load_str(&text, "ico.toml", Some(&dir)).unwrap();
        assert_eq!(scene.features.smooth, 0);
        assert!(scene.vertex_normals.is_empty());
    }
}

#[test]
fn hanikas_lift_computed_by_hand() {
    let text = HAND.replace(
        "[[triangle]]",
        "[render]\nterminator = \"hanika\"\n[[triangle]]",
    );
    let scene = load_str(&text, "hand.toml", None).unwrap();
    let (ray, hit) = hand_hit(0.25, 0.25);
    let it = interact(&scene, &hit, &ray);
    // P = (0.25, 0.25, 0). Vertex 0's plane (normal (0, 0, −1)) passes through P: d₀ = 0. For
    // n₁ = (1, 0, −1)/√2: d₁ = (P − P₁)·n₁ = (−0.75, 0.25, 0)·(1, 0, −1)/√2 = −0.75/√2, raised
    // by −d₁·n₁ = (0.375, 0, −0.375); likewise vertex 2 by (0, 0.375, −0.375). Blended with
    // b = (0.5, 0.25, 0.25): P′ = P + (0.09375, 0.09375, −0.1875) = (0.34375, 0.34375, −0.1875),
    // towards the eye, where the normals say the surface bulges.
    let want = [0.34375, 0.34375, -0.1875];
    for (got, want) in it.lifted.to_array().iter().zip(want) {
        assert!((*got as f64 - want).abs() < 1e-6, "{:?}", it.lifted);
    }
    // Without the setting, or with normals that say the surface is flat, nothing moves.
    let plain = load_str(HAND, "hand.toml", None).unwrap();
    assert_eq!(interact(&plain, &hit, &ray).lifted, it.point);
    let flat = text.replace(
        "normals = [[0, 0, -1], [1, 0, -1], [0, 1, -1]]",
        "normals = [[0, 0, -1], [0, 0, -1], [0, 0, -1]]",
    );
    let flat = load_str(&flat, "flat.toml", None).unwrap();
    let it = interact(&flat, &hit, &ray);
    assert_eq!((it.lifted, it.lifted_error), (it.point, it.error));
}

/// Pixels on the smooth sphere whose key light the smooth normal faces (l·n_s > 0) but whose
/// shadow ray the sphere itself blocks: the jagged terminator.
fn self_shadowed(scene: &Scene) -> (usize, usize) {
    let smooth = scene.find_group("smooth sphere").unwrap().clone();
    let own = |name: &str| name.starts_with("smooth sphere");
    let (mut blocked, mut lit) = (0, 0);
    for y in (0..240).step_by(2) {
        for x in (0..320).step_by(2) {
            let trace = record(scene, x, y);
            let Some(hit) = &trace.root.hit else { continue };
            if !(smooth.first..smooth.first + smooth.count).contains(&hit.object) {
                continue;
            }
            let lifted = trace.root.steps.iter().any(|s| {
                matches!(
                    s.step,
                    Step::ShadingNormal {
                        lifted: Some(_),
                        ..
                    }
                )
            });
            assert_eq!(lifted, scene.settings.terminator != Default::default());
            for s in &trace.root.steps {
                if let Step::Light {
                    light: 0,
                    l_dot_n,
                    blocker,
                    ..
                } = &s.step
                    && *l_dot_n > 0.0
                {
                    lit += 1;
                    blocked += usize::from(blocker.as_deref().is_some_and(own));
                }
            }
        }
    }
    (blocked, lit)
}

#[test]
fn hanikas_lift_clears_the_terminator_of_the_smooth_sphere() {
    let mut scene = load_file(&scenes_dir().join("smooth-shading.toml")).unwrap();
    let (before, lit) = self_shadowed(&scene);
    scene.settings.terminator = raystep_core::scene::Terminator::Hanika;
    let (after, lit_after) = self_shadowed(&scene);
    assert_eq!(lit, lit_after, "the same pixels face the light");
    eprintln!("self-shadowed: {before} of {lit} without the lift, {after} with it");
    // Measured (every other pixel): 84 of the 456 that face the key light self-shadowed
    // without the lift, none with it.
    assert!(
        before >= 40 && after * 10 <= before,
        "{before} → {after} of {lit}"
    );
}

/// `raystep scene mitsuba` writes a smooth triangle's vertex normals (`vn`, faces `a//a`, face
/// normals off) and leaves a flat one with face normals; the normals by hand are the scene's,
/// normalized: (0, 0, −1), (1, 0, −1)/√2, (0, 1, −1)/√2.
#[test]
fn the_mitsuba_export_carries_vertex_normals_and_only_where_the_scene_has_them() {
    let text = format!(
        "{HAND}\n[[triangle]]\nname = \"flat\"\nvertices = [[2, 0, 0], [3, 0, 0], [2, 1, 0]]\n"
    );
    let s = load_str(&text, "hand.toml", None).unwrap();
    let m = raystep_core::scene::mitsuba::to_mitsuba(&s, 4, "hand").unwrap();
    let obj = |name: &str| -> &str {
        let (_, t) = m.objs.iter().find(|(f, _)| f.as_str() == name).unwrap();
        t
    };
    let smooth = obj("hand-g0.obj");
    let vn: Vec<[f64; 3]> = smooth
        .lines()
        .filter_map(|l| l.strip_prefix("vn "))
        .map(|l| {
            let v: Vec<f64> = l.split(' ').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    let r = 0.5f64.sqrt();
    let expected = [[0.0, 0.0, -1.0], [r, 0.0, -r], [0.0, r, -r]];
    assert_eq!(vn.len(), 3, "{smooth}");
    for (got, want) in vn.iter().zip(expected) {
        for c in 0..3 {
            assert!((got[c] - want[c]).abs() < 1e-6, "{got:?} against {want:?}");
        }
    }
    assert!(smooth.contains("f 1//1 2//2 3//3"), "{smooth}");
    let flat = obj("hand-g1.obj");
    assert!(!flat.contains("vn ") && flat.contains("f 1 2 3"), "{flat}");
    let shapes: Vec<&str> = m
        .xml
        .lines()
        .filter(|l| l.contains("type=\"obj\""))
        .collect();
    assert_eq!(shapes.len(), 2);
    assert!(
        shapes[0].contains("hand-g0.obj") && shapes[0].contains("\"face_normals\" value=\"false\"")
    );
    assert!(
        shapes[1].contains("hand-g1.obj") && shapes[1].contains("\"face_normals\" value=\"true\"")
    );
}

/// The export's path integrator: Mitsuba 3's `max_depth` and `rr_depth` are raystep's plus one.
/// By hand, from Mitsuba 3's `src/integrators/path.cpp`: its depth is 0 at the camera ray's
/// hit and is raised before the roulette, which plays when depth ≥ `rr_depth`, and the path goes
/// on while depth + 1 < `max_depth`; raystep plays after `b` bounces when b + 1 > `rr_depth` and
/// stops at `max_depth` bounces. `max_depth = 6`, `rr_depth = 2` is Mitsuba's 7 and 3.
#[test]
fn the_mitsuba_export_plays_russian_roulette_at_the_same_depth() {
    let text = format!("[render]\nintegrator = \"path\"\nmax_depth = 6\nrr_depth = 2\n{HAND}");
    let s = load_str(&text, "hand.toml", None).unwrap();
    assert_eq!((s.settings.max_depth, s.settings.rr_depth), (6, 2));
    let m = raystep_core::scene::mitsuba::to_mitsuba(&s, 4, "hand").unwrap();
    let integrator = m.xml.lines().find(|l| l.contains("<integrator")).unwrap();
    assert_eq!(
        integrator.trim(),
        "<integrator type=\"path\"><integer name=\"max_depth\" value=\"7\"/><integer name=\"rr_depth\" value=\"3\"/></integrator>"
    );
}
