//! Traces written before an intermediate was recorded: its lines show dashes, never wrong
//! numbers.

use super::*;

/// A trace saved before the watertight test recorded its shear still loads, and its explanation
/// shows — where those numbers would be (never NaN, never a recomputed value).
#[test]
fn an_older_trace_without_the_shear_shows_dashes() {
    let trace = record(&triangle_scene([0.2, 0.3, -2.0], "watertight"), 1, 1);
    let mut json: serde_json::Value = serde_json::from_str(&trace.to_json()).unwrap();
    let removed = strip(&mut json, &["shear", "sheared", "z_scaled"]);
    assert!(
        removed >= 3 && removed.is_multiple_of(3),
        "three fields a watertight test: {removed}"
    );
    let old = Trace::from_json(&json.to_string(), "old.json").expect("an older trace loads");
    let (_, e) = triangle_step(&old);
    assert_eq!(get(&e, "Sx, Sy, Sz").value, "—, —, —");
    assert_eq!(get(&e, "P′0").value, "(—, —, —)");
    assert!(get(&e, "e0").substituted.starts_with("—·—"), "{e:#?}");
    assert!(!format!("{e:?}").contains("NaN"), "{e:#?}");
    // What the record has is shown as before.
    let (_, now) = triangle_step(&trace);
    assert_eq!(get(&e, "e0").value, get(&now, "e0").value);
    assert_eq!(get(&e, "t").value, get(&now, "t").value);
}

/// Likewise a sphere test saved before f, b′, l, √Δ and the roots as computed were recorded.
#[test]
fn an_older_trace_without_the_sphere_intermediates_shows_dashes() {
    for method in [SphereMethod::Textbook, SphereMethod::Stable] {
        let mut scene = shipped("first-sphere.toml");
        scene.settings.sphere_method = method;
        let trace = record(&scene, 160, 120);
        let mut json: serde_json::Value = serde_json::from_str(&trace.to_json()).unwrap();
        let keys = ["f", "b_half", "l", "sqrt_discriminant", "computed_roots"];
        assert!(strip(&mut json, &keys) >= 2, "{method:?}");
        let old = Trace::from_json(&json.to_string(), "old.json").expect("an older trace loads");
        let (ray, step) = old
            .timeline()
            .into_iter()
            .find(|(_, s)| matches!(s.step, Step::Sphere { .. }))
            .expect("a sphere test");
        let e = explain(&old, ray, &step.step);
        assert_eq!(get(&e, "f").value, "—", "{method:?}");
        assert!(!format!("{e:?}").contains("NaN"), "{e:#?}");
        match method {
            SphereMethod::Textbook => assert_eq!(get(&e, "√Δ").value, "—"),
            _ => {
                assert_eq!(get(&e, "b′").value, "—");
                assert_eq!(get(&e, "c/q").value, "—");
                assert!(!has(&e, "l"), "no l line without l");
            }
        }
    }
}

/// Likewise a Möller–Trumbore test saved before E1, E2 and T were recorded.
#[test]
fn an_older_trace_without_the_moller_trumbore_vectors_shows_dashes() {
    let trace = record(&triangle_scene([0.2, 0.3, -2.0], "moller-trumbore"), 1, 1);
    let mut json: serde_json::Value = serde_json::from_str(&trace.to_json()).unwrap();
    assert!(strip(&mut json, &["e1", "e2", "t_vec"]) >= 3);
    let old = Trace::from_json(&json.to_string(), "old.json").expect("an older trace loads");
    let (_, e) = triangle_step(&old);
    assert_eq!(get(&e, "E1").value, "—");
    assert_eq!(get(&e, "T").value, "—");
    assert!(!format!("{e:?}").contains("NaN"), "{e:#?}");
    let (_, now) = triangle_step(&trace);
    assert_eq!(get(&e, "D0").value, get(&now, "D0").value);
}

/// Likewise a BVH node visit saved before the slab's plane distances were recorded.
#[test]
fn an_older_trace_without_the_slab_planes_shows_dashes() {
    let mut scene = shipped("three-spheres.toml");
    scene.settings.accel = AccelChoice::Bvh;
    let trace = record(&scene, 150, 110);
    let mut json: serde_json::Value = serde_json::from_str(&trace.to_json()).unwrap();
    assert!(strip(&mut json, &["planes"]) >= 3);
    let old = Trace::from_json(&json.to_string(), "old.json").expect("an older trace loads");
    let (ray, step) = old
        .timeline()
        .into_iter()
        .find(|(_, s)| matches!(s.step, Step::Node(_)))
        .expect("a node visit");
    let e = explain(&old, ray, &step.step);
    assert_eq!(get(&e, "t0x, t1x").value, "—, —");
    assert!(!format!("{e:?}").contains("NaN"), "{e:#?}");
}

/// A trace saved before the shading intermediates were recorded still loads and explains, with
/// — where they would be.
#[test]
fn an_older_trace_without_the_shading_intermediates_shows_dashes() {
    let scene = shipped("mirror-glass.toml");
    let (x, y) = (scene.camera.width / 2, scene.camera.height / 2);
    let trace = record(&scene, x, y);
    let mut json: serde_json::Value = serde_json::from_str(&trace.to_json()).unwrap();
    let keys = [
        "light_dir",
        "reflected",
        "eye",
        "total",
        "d_dot_n",
        "eta",
        "cos_t",
        "r0",
        "cos",
    ];
    assert!(strip(&mut json, &keys) >= 4);
    let old = Trace::from_json(&json.to_string(), "old.json").expect("an older trace loads");
    for (_, step, e) in explained(&old) {
        assert!(!format!("{e:?}").contains("NaN"), "{e:#?}");
        match step {
            Step::Light { .. } => assert_eq!(get(&e, "total").value, "—"),
            Step::Refract {
                total_internal_reflection: false,
                ..
            } => {
                assert_eq!(get(&e, "η").value, "—");
                assert_eq!(get(&e, "cos θₜ").value, "—");
            }
            _ => {}
        }
    }
}
