//! Every step of every shipped scene (Whitted and Monte Carlo) is explained, with the scene or
//! from a loaded trace alone.

use super::*;

/// Every step of the Monte Carlo scenes is explained, and each Monte Carlo step is among them.
#[test]
fn every_monte_carlo_step_is_explained() {
    let mut seen = std::collections::BTreeSet::new();
    for name in [
        "cornell-area.toml",
        "depth-of-field.toml",
        "soft-shadows.toml",
        "veach-mis.toml",
    ] {
        let mut scene = shipped(name);
        scene.settings.rr_depth = 0;
        for (x, y) in grid(&scene, 40) {
            check_all_steps(&record(&scene, x, y), &mut seen);
        }
    }
    for v in [
        "lens",
        "light-sample",
        "bsdf-sample",
        "emitted",
        "russian-roulette",
    ] {
        assert!(seen.contains(v), "{v} not seen: {seen:?}");
    }
}

#[test]
fn every_step_of_every_shipped_scene_is_explained() {
    let mut seen = std::collections::BTreeSet::new();
    for name in SHIPPED {
        let scene = shipped(name);
        let (w, h) = (scene.camera.width, scene.camera.height);
        check_all_steps(&record(&scene, w / 2, h / 2), &mut seen);
        if name == "instances.toml" {
            // a gem and the egg (lesson 20)
            for (x, y) in [(186, 110), (75, 95)] {
                check_all_steps(&record(&scene, x, y), &mut seen);
            }
        }
        // A coarse grid, with the BVH, and with a low recursion limit (depth-limit steps).
        for (x, y) in grid(&scene, 80) {
            check_all_steps(&record(&scene, x, y), &mut seen);
        }
        for accel in [AccelChoice::Bvh, AccelChoice::Spheres, AccelChoice::Grid] {
            let mut with = scene.clone();
            with.settings.accel = accel;
            for (x, y) in grid(&scene, 80) {
                check_all_steps(&record(&with, x, y), &mut seen);
            }
        }
        let mut shallow = scene.clone();
        shallow.settings.max_depth = 1;
        shallow.settings.sphere_method = SphereMethod::Textbook;
        shallow.settings.triangle_method = TriangleMethod::MollerTrumbore;
        for (x, y) in grid(&scene, 80) {
            check_all_steps(&record(&shallow, x, y), &mut seen);
        }
    }
    let all = [
        "camera",
        "node",
        "sphere-node",
        "cell",
        "mailbox-skip",
        "sphere",
        "plane",
        "triangle",
        "accept",
        "miss",
        "surface",
        "shading-normal",
        "texture",
        "shadow-ray",
        "light",
        "reflect",
        "refract",
        "schlick",
        "depth-limit",
        "spawn",
        "color",
        "tlas-node",
        "instance",
        "blas-node",
        "instance-hit",
    ];
    for v in all {
        assert!(seen.contains(v), "no {v} step seen: {seen:?}");
    }
}

#[test]
fn a_loaded_trace_explains_the_same_without_the_scene() {
    let scene = shipped("mirror-glass.toml");
    let trace = record(&scene, 260, 150);
    let loaded = Trace::from_json(&trace.to_json(), "t.json").unwrap();
    let a: Vec<Explanation> = explained(&trace).into_iter().map(|(_, _, e)| e).collect();
    let b: Vec<Explanation> = explained(&loaded).into_iter().map(|(_, _, e)| e).collect();
    assert_eq!(a, b);
    // A step handed in from a copy (not an element of the ray) is still found by value.
    let (ray, s) = trace.timeline()[3];
    let copy = s.step.clone();
    assert_eq!(explain(&trace, ray, &copy), explain(&trace, ray, &s.step));
}
