//! The Standard Procedural Databases generators: primitive counts, loading, determinism, limits.

use raystep_core::scene::spd::{SpdOutput, SpdScene, generate};
use raystep_core::scene::{Scene, Shape, load_file, load_str};
use tempfile::TempDir;

/// Writes the generated files into a fresh folder and loads the scene from there, as a user would.
fn load(out: &SpdOutput, name: &str) -> Scene {
    let dir = TempDir::new().unwrap();
    let path = dir.path().join(format!("{name}.toml"));
    std::fs::write(&path, &out.toml).unwrap();
    if let Some((obj_name, obj)) = &out.obj {
        std::fs::write(dir.path().join(obj_name), obj).unwrap();
    }
    load_file(&path).unwrap_or_else(|e| panic!("{name} does not load: {e}"))
}

fn spheres(scene: &Scene) -> Vec<(glam::Vec3, f32)> {
    scene
        .objects
        .iter()
        .filter_map(|o| match o.shape {
            Shape::Sphere { center, radius } => Some((center, radius)),
            _ => None,
        })
        .collect()
}

#[test]
fn balls_have_the_sphereflake_counts() {
    for d in 1..=4u32 {
        let out = generate(SpdScene::Balls, d).unwrap();
        assert!(out.obj.is_none());
        let scene = load_str(&out.toml, "balls.toml", None).unwrap();
        let expected: usize = (0..=d).map(|k| 9usize.pow(k)).sum();
        assert_eq!(scene.features.spheres, expected, "size {d}");
        assert_eq!(scene.features.planes, 1);
        assert_eq!(scene.features.lights, 3);
        assert!(scene.features.reflective);
        assert_eq!(scene.features.primitives, out.primitives);
    }
    let scene = load_str(
        &generate(SpdScene::Balls, 4).unwrap().toml,
        "balls.toml",
        None,
    )
    .unwrap();
    assert_eq!(scene.features.spheres, 7381);
}

#[test]
fn balls_children_touch_their_parent_on_its_upper_half() {
    let scene = load_str(
        &generate(SpdScene::Balls, 2).unwrap().toml,
        "balls.toml",
        None,
    )
    .unwrap();
    let s = spheres(&scene);
    assert_eq!(s[0], (glam::Vec3::ZERO, 0.5));
    // The first child and its own nine children, then the next child: depth-first order.
    let children: Vec<_> = s.iter().skip(1).step_by(10).collect();
    assert_eq!(children.len(), 9);
    let mut equator = 0;
    for (c, r) in &children {
        assert!((r - 0.5 / 3.0).abs() < 1e-6);
        assert!(
            (c.length() - (0.5 + r)).abs() < 1e-5,
            "child at {c} does not touch the parent"
        );
        assert!(c.z > -1e-5, "child at {c} is on the lower half");
        equator += usize::from(c.z.abs() < 1e-5);
    }
    assert_eq!(equator, 6, "six children on the equator, three above");
    // The whole flake stays inside the unit sphere and above the floor at z = -1/2.
    for (c, r) in &s {
        assert!(c.length() + r <= 1.0 + 1e-5);
        assert!(c.z - r >= -0.5 - 1e-5);
    }
}

#[test]
fn tetra_has_four_to_the_size_plus_one_triangles() {
    for d in 1..=6u32 {
        let out = generate(SpdScene::Tetra, d).unwrap();
        let (obj_name, _) = out.obj.as_ref().expect("tetra is a mesh");
        assert_eq!(obj_name, &format!("tetra-{d}.obj"));
        assert!(out.toml.contains(&format!("obj = \"{obj_name}\"")));
        let scene = load(&out, &format!("tetra-{d}"));
        assert_eq!(scene.features.triangles, 4usize.pow(d + 1), "size {d}");
        assert_eq!(scene.features.meshes, 1);
        assert_eq!(scene.features.primitives, out.primitives);
        for o in &scene.objects {
            let Shape::Triangle { p } = o.shape else {
                panic!("only triangles")
            };
            assert!(p.iter().all(|v| v.abs().max_element() <= 1.0));
        }
    }
}

#[test]
fn mount_has_two_times_four_to_the_size_triangles_and_four_spheres() {
    for n in 1..=6u32 {
        let out = generate(SpdScene::Mount, n).unwrap();
        assert_eq!(out.obj.as_ref().unwrap().0, format!("mount-{n}.obj"));
        let scene = load(&out, &format!("mount-{n}"));
        assert_eq!(scene.features.triangles, 2 * 4usize.pow(n), "size {n}");
        assert_eq!(scene.features.spheres, 4);
        assert!(scene.features.transparent && scene.features.reflective);
        assert_eq!(scene.features.primitives, out.primitives);
        // The spheres float clear of the mountain.
        let balls = spheres(&scene);
        for o in &scene.objects {
            if let Shape::Triangle { p } = o.shape {
                for v in p {
                    for (c, r) in &balls {
                        assert!(
                            v.distance(*c) > *r,
                            "size {n}: the mountain pierces a sphere"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn larger_sizes_generate_quickly_enough_to_count() {
    let out = generate(SpdScene::Tetra, 7).unwrap();
    let obj = &out.obj.unwrap().1;
    assert_eq!(
        obj.lines().filter(|l| l.starts_with("f ")).count(),
        4usize.pow(8)
    );
    assert_eq!(
        obj.lines().filter(|l| l.starts_with("v ")).count(),
        4usize.pow(8)
    );
    let out = generate(SpdScene::Mount, 8).unwrap();
    let obj = &out.obj.unwrap().1;
    assert_eq!(
        obj.lines().filter(|l| l.starts_with("f ")).count(),
        2 * 4usize.pow(8)
    );
    assert_eq!(
        obj.lines().filter(|l| l.starts_with("v ")).count(),
        257 * 257
    );
}

#[test]
fn generation_is_deterministic() {
    for scene in [SpdScene::Balls, SpdScene::Tetra, SpdScene::Mount] {
        let a = generate(scene, 3).unwrap();
        let b = generate(scene, 3).unwrap();
        assert_eq!(a, b, "{scene:?}");
    }
}

#[test]
fn sizes_out_of_range_are_errors_naming_the_limit() {
    // The largest sizes raystep loads (tests/it/hostile_cli.rs works them out from the limits).
    for (scene, max) in [
        (SpdScene::Balls, 5),
        (SpdScene::Tetra, 9),
        (SpdScene::Mount, 9),
    ] {
        assert_eq!(scene.max_size(), max);
        for bad in [0, max + 1, 1000] {
            let e = generate(scene, bad).unwrap_err();
            assert!(e.contains(&max.to_string()), "{e}");
            assert!(e.contains(scene.name()), "{e}");
        }
    }
}

#[test]
fn a_larger_mountain_only_adds_detail() {
    let heights = |n: u32| -> Vec<String> {
        let (_, obj) = generate(SpdScene::Mount, n).unwrap().obj.unwrap();
        obj.lines()
            .filter_map(|l| l.strip_prefix("v "))
            .map(|l| l.to_string())
            .collect()
    };
    let (small, large) = (heights(3), heights(4));
    let (rs, rl) = (9, 17);
    assert_eq!((small.len(), large.len()), (rs * rs, rl * rl));
    for y in 0..rs {
        for x in 0..rs {
            assert_eq!(
                small[y * rs + x],
                large[2 * y * rl + 2 * x],
                "grid point ({x}, {y})"
            );
        }
    }
}
