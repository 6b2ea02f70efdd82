//! The scenes shipped in `scenes/`: every one loads, and each has exactly the features counted by
//! hand from its file (so a changed scene, or a changed loader, is noticed).

use raystep_core::accel::BruteForce;
use raystep_core::record::Silent;
use raystep_core::scene::{Features, Scene, load_file};
use raystep_core::trace::Tracer;
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("scenes")
}

fn load(name: &str) -> Scene {
    let path = scenes_dir().join(name);
    load_file(&path).unwrap_or_else(|e| panic!("{name} does not load: {e}"))
}

/// Each shipped scene with its features, counted by hand from the file.
fn expected() -> Vec<(&'static str, Features)> {
    vec![
        (
            // Area lights only (no point lights): a light quad of 2 triangles and 5 walls of 2; a white and a mirror ball.
            "cornell-area.toml",
            Features {
                spheres: 2,
                planes: 0,
                triangles: 12,
                smooth: 0,
                textured: 0,
                meshes: 0,
                lights: 0,
                reflective: false,
                transparent: false,
                emitters: 2,
                primitives: 14,
                instances: 0,
            },
        ),
        (
            // The Cornell box's 12 triangles around scenes/gltf/table.gltf: one box mesh of 12
            // triangles (textured) that five nodes place — one prototype, five instances —, a
            // 12 × 8 sphere (12 + 12 + 6 × 24 = 168) and a pane (2), all with NORMAL (smooth);
            // steel reflects, the pane is glass; the file's point light left out
            // (`lights = false`). Three meshes read: the box once.
            "gltf-table.toml",
            Features {
                spheres: 0,
                planes: 0,
                triangles: 194,
                smooth: 182,
                textured: 12,
                meshes: 3,
                lights: 0,
                reflective: true,
                transparent: true,
                emitters: 2,
                primitives: 194,
                instances: 5,
            },
        ),
        (
            // A ball and two sphere lights over a floor plane.
            "soft-shadows.toml",
            Features {
                spheres: 3,
                planes: 1,
                triangles: 0,
                smooth: 0,
                textured: 0,
                meshes: 0,
                lights: 0,
                reflective: false,
                transparent: false,
                emitters: 2,
                primitives: 4,
                instances: 0,
            },
        ),
        (
            // Five balls and a sphere light (the sun) over a floor plane.
            "depth-of-field.toml",
            Features {
                spheres: 6,
                planes: 1,
                triangles: 0,
                smooth: 0,
                textured: 0,
                meshes: 0,
                lights: 0,
                reflective: false,
                transparent: false,
                emitters: 1,
                primitives: 7,
                instances: 0,
            },
        ),
        (
            // Four sphere lights, four plates of 2 triangles, a floor plane.
            "veach-mis.toml",
            Features {
                spheres: 4,
                planes: 1,
                triangles: 8,
                smooth: 0,
                textured: 0,
                meshes: 0,
                lights: 0,
                reflective: false,
                transparent: false,
                emitters: 4,
                primitives: 13,
                instances: 0,
            },
        ),
        (
            // One red ball 4100 units away, one light, nothing reflects.
            "far-sphere.toml",
            Features {
                spheres: 1,
                planes: 0,
                triangles: 0,
                smooth: 0,
                textured: 0,
                meshes: 0,
                lights: 1,
                reflective: false,
                transparent: false,
                emitters: 0,
                primitives: 1,
                instances: 0,
            },
        ),
        (
            // 120 teapot spheres and 4 floodlight balls, 10 stadium triangles; nothing reflects.
            "teapot-stadium.toml",
            Features {
                spheres: 124,
                planes: 0,
                triangles: 10,
                smooth: 0,
                textured: 0,
                meshes: 0,
                lights: 1,
                reflective: false,
                transparent: false,
                emitters: 0,
                primitives: 134,
                instances: 0,
            },
        ),
        (
            // middle, mirror, small on a floor plane; the "mirror" material reflects.
            "three-spheres.toml",
            Features {
                spheres: 3,
                planes: 1,
                triangles: 0,
                smooth: 0,
                textured: 0,
                meshes: 0,
                lights: 1,
                reflective: true,
                transparent: false,
                emitters: 0,
                primitives: 4,
                instances: 0,
            },
        ),
        (
            // ball.
            "first-sphere.toml",
            Features {
                spheres: 1,
                planes: 0,
                triangles: 0,
                smooth: 0,
                textured: 0,
                meshes: 0,
                lights: 1,
                reflective: false,
                transparent: false,
                emitters: 0,
                primitives: 1,
                instances: 0,
            },
        ),
        (
            // mirror, glass, bubble, red ball, gold ball, blue ball; floor, wall.
            "mirror-glass.toml",
            Features {
                spheres: 6,
                planes: 2,
                triangles: 0,
                smooth: 0,
                textured: 0,
                meshes: 0,
                lights: 1,
                reflective: true,
                transparent: true,
                emitters: 0,
                primitives: 8,
                instances: 0,
            },
        ),
        (
            // The 80-triangle sphere twice, flat and smooth (the file's vertex normals); floor;
            // key and fill lights.
            "smooth-shading.toml",
            Features {
                spheres: 0,
                planes: 1,
                triangles: 160,
                smooth: 80,
                textured: 0,
                meshes: 2,
                lights: 2,
                reflective: false,
                transparent: false,
                emitters: 0,
                primitives: 161,
                instances: 0,
            },
        ),
        (
            // Two floors of two textured triangles each (bilinear, trilinear); the sun.
            "mipmap.toml",
            Features {
                spheres: 0,
                planes: 0,
                triangles: 4,
                smooth: 0,
                textured: 4,
                meshes: 0,
                lights: 1,
                reflective: false,
                transparent: false,
                emitters: 0,
                primitives: 4,
                instances: 0,
            },
        ),
        (
            // A checker floor, a textured globe and two textured triangles; one light.
            "textures.toml",
            Features {
                spheres: 1,
                planes: 1,
                triangles: 2,
                smooth: 0,
                textured: 4,
                meshes: 0,
                lights: 1,
                reflective: false,
                transparent: false,
                emitters: 0,
                primitives: 4,
                instances: 0,
            },
        ),
        (
            // Four pyramid faces + the icosahedron's 20 faces; floor; key and fill lights.
            "triangles.toml",
            Features {
                spheres: 0,
                planes: 1,
                triangles: 24,
                smooth: 0,
                textured: 0,
                meshes: 1,
                lights: 2,
                reflective: false,
                transparent: false,
                emitters: 0,
                primitives: 25,
                instances: 0,
            },
        ),
        (
            // floor, ceiling, back wall, left wall, right wall; mirror ball, glass ball.
            "cornell.toml",
            Features {
                spheres: 2,
                planes: 5,
                triangles: 0,
                smooth: 0,
                textured: 0,
                meshes: 0,
                lights: 1,
                reflective: true,
                transparent: true,
                emitters: 0,
                primitives: 7,
                instances: 0,
            },
        ),
        (
            // ball; floor (a general plane). Spawned rays with no offset: acne.
            "acne.toml",
            Features {
                spheres: 1,
                planes: 1,
                triangles: 0,
                smooth: 0,
                textured: 0,
                meshes: 0,
                lights: 1,
                reflective: false,
                transparent: false,
                emitters: 0,
                primitives: 2,
                instances: 0,
            },
        ),
        (
            // Four loose triangles around one vertex; lamp.
            "leaky-edge.toml",
            Features {
                spheres: 0,
                planes: 0,
                triangles: 4,
                smooth: 0,
                textured: 0,
                meshes: 0,
                lights: 1,
                reflective: false,
                transparent: false,
                emitters: 0,
                primitives: 4,
                instances: 0,
            },
        ),
        (
            // One icosahedron (20 triangles) and one unit sphere, prototypes placed by seven
            // instances, on the floor plane; two lights.
            "instances.toml",
            Features {
                spheres: 1,
                planes: 1,
                triangles: 20,
                smooth: 0,
                textured: 0,
                meshes: 1,
                lights: 2,
                reflective: false,
                transparent: false,
                emitters: 0,
                primitives: 22,
                instances: 7,
            },
        ),
    ]
}

#[test]
fn every_scene_file_loads_and_is_listed() {
    let mut found = vec![];
    for entry in std::fs::read_dir(scenes_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scene = load_file(&path).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(scene.path.as_deref(), Some(path.as_path()));
            found.push(path.file_name().unwrap().to_string_lossy().into_owned());
        }
    }
    found.sort();
    let mut listed: Vec<String> = expected().iter().map(|(n, _)| n.to_string()).collect();
    listed.sort();
    assert_eq!(
        found, listed,
        "every scene in scenes/ needs its features checked here"
    );
}

#[test]
fn features_match_the_files() {
    for (name, features) in expected() {
        assert_eq!(load(name).features, features, "{name}");
    }
}

#[test]
fn objects_are_named_as_the_lessons_expect() {
    let names = [
        ("first-sphere.toml", &["ball"][..]),
        (
            "mirror-glass.toml",
            &["mirror", "glass", "bubble", "floor", "wall"][..],
        ),
        (
            "triangles.toml",
            &["floor", "pyramid south", "icosahedron"][..],
        ),
        (
            "cornell.toml",
            &[
                "floor",
                "ceiling",
                "back wall",
                "left wall",
                "right wall",
                "mirror ball",
                "glass ball",
            ][..],
        ),
    ];
    for (scene, objects) in names {
        let s = load(scene);
        for o in objects {
            assert!(
                s.find_group(o).is_some(),
                "{scene} has no object named {o:?}"
            );
        }
    }
    let ico = load("triangles.toml");
    assert_eq!(ico.find_group("icosahedron").unwrap().count, 20);
}

#[test]
fn first_sphere_centre_ray_hits_the_ball() {
    let scene = load("first-sphere.toml");
    assert_eq!((scene.camera.width, scene.camera.height), (320, 240));
    assert_eq!(scene.camera.from.to_array(), [0.0, 0.0, -5.0]);
    assert_eq!(scene.camera.at.to_array(), [0.0, 0.0, 0.0]);
    let tracer = Tracer::new(&scene, &BruteForce);
    let trace = tracer.record(scene.camera.width / 2, scene.camera.height / 2, 0);
    let hit = trace.root.hit.expect("the centre ray hits something");
    assert_eq!(hit.name, "ball");
    // The ray is half a pixel off the z axis: it meets the ball's front at t just over 4.
    assert!((hit.t - 4.0).abs() < 1e-3, "t = {}", hit.t);
}

#[test]
fn shipped_scenes_render_finite_and_not_blank() {
    for (name, _) in expected() {
        let scene = load(name);
        let tracer = Tracer::new(&scene, &BruteForce);
        let (w, h) = (scene.camera.width, scene.camera.height);
        // Not blank: at least a tenth of the samples see something (first-sphere: about 15%).
        let mut hits = 0;
        for y in (0..h).step_by(8) {
            for x in (0..w).step_by(8) {
                let c = tracer.trace_pixel(x, y, &mut Silent);
                assert!(
                    c.is_finite() && c.min_element() >= 0.0,
                    "{name} ({x}, {y}): {c}"
                );
                hits += usize::from(c != scene.settings.background);
            }
        }
        let samples = w.div_ceil(8) as usize * h.div_ceil(8) as usize;
        assert!(
            hits * 10 > samples,
            "{name}: only {hits} of {samples} samples show an object"
        );
    }
}
