//! The Ray Tracer Challenge's published world-level test vectors (Jamis Buck, *The Ray Tracer
//! Challenge*, Pragmatic Bookshelf 2019: chapter 7 "Making a Scene", chapter 8 "Shadows",
//! chapter 11 "Reflection and Refraction"), expressed as raystep TOML scenes and traced with the
//! one Whitted tracer; plus the tracer's own contracts: a recorded trace's colour is the silent
//! render's colour bit for bit, and a trace survives a JSON round trip with clear errors for bad
//! files.
//!
//! RTC's "default world": a white point light at (−10, 10, −10); an outer unit sphere at the
//! origin with colour (0.8, 1.0, 0.6), diffuse 0.7, specular 0.2; an inner sphere at the origin
//! scaled by 0.5 (here: radius 0.5) with the default material. RTC's `shade_hit(world, comps,
//! remaining)` starts with remaining = 5, which is raystep's `max_depth = 5` with the primary ray
//! at depth 0. RTC's `over_point` is `offset = "fixed"` with `epsilon = 1e-4`; every vector is
//! checked with that policy and with raystep's default `robust` offset.

use glam::Vec3;
use raystep_core::accel::BruteForce;
use raystep_core::math::Ray;
use raystep_core::record::{RayKind, RayRecord, Recorder, Silent, Step, Trace, TraceError};
use raystep_core::scene::{OffsetPolicy, Scene, load_file, load_str};
use raystep_core::trace::Tracer;
use std::path::Path;

/// RTC compares colours with EPSILON = 0.0001 and prints five significant digits; raystep works
/// in f32, so the world vectors are checked to 1e-4 (the book's own tolerance) unless noted.
const TOL: f32 = 1e-4;

/// RTC's `over_point` policy and raystep's default.
const OFFSETS: [&str; 2] = ["fixed", "robust"];

const S2: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// The default world with a configurable light position, extra lines for the two materials and
/// extra tables (more materials and objects) appended after the spheres.
fn default_world(
    offset: &str,
    light: &str,
    outer_extra: &str,
    inner_extra: &str,
    extra: &str,
) -> String {
    format!(
        r#"title = "RTC default world"

[render]
max_depth = 5
offset = "{offset}"
epsilon = 1e-4

[[light]]
name = "light"
position = {light}
color = [1, 1, 1]

[[material]]
name = "outer"
color = [0.8, 1.0, 0.6]
diffuse = 0.7
specular = 0.2
{outer_extra}

[[material]]
name = "inner"
{inner_extra}

[[sphere]]
name = "outer"
center = [0, 0, 0]
radius = 1
material = "outer"

[[sphere]]
name = "inner"
center = [0, 0, 0]
radius = 0.5
material = "inner"
{extra}
"#
    )
}

fn world(offset: &str) -> String {
    default_world(offset, "[-10, 10, -10]", "", "", "")
}

fn load(text: &str) -> Scene {
    load_str(text, "rtc.toml", None).unwrap_or_else(|e| panic!("scene does not load: {e}\n{text}"))
}

/// Traces `o + t·d` through `scene` silently and recorded; checks the two colours agree bit for
/// bit and returns the colour with the recorded ray tree.
fn trace(scene: &Scene, o: [f32; 3], d: [f32; 3]) -> (Vec3, RayRecord) {
    let tracer = Tracer::new(scene, &BruteForce);
    let ray = Ray::<f32>::infinite(Vec3::from(o), Vec3::from(d)).unwrap();
    let silent = tracer.trace_ray(&ray, &mut Silent);
    let mut rec = Recorder::new();
    let recorded = tracer.trace_ray(&ray, &mut rec);
    assert_eq!(
        silent.to_array(),
        recorded.to_array(),
        "recorded and silent colours differ"
    );
    let root = rec.finish().expect("the ray ends");
    assert_eq!(root.color, silent.to_array());
    (silent, root)
}

#[track_caller]
fn assert_color(got: Vec3, expect: [f32; 3], tol: f32, what: &str) {
    let err = (got - Vec3::from(expect)).abs().max_element();
    assert!(
        err <= tol,
        "{what}: got {got:?}, RTC expects {expect:?} (max error {err:e} > {tol:e})"
    );
}

fn steps(r: &RayRecord) -> impl Iterator<Item = &Step> {
    r.steps.iter().map(|s| &s.step)
}

fn child(r: &RayRecord, kind: RayKind) -> &RayRecord {
    r.children
        .iter()
        .find(|c| c.kind == kind)
        .unwrap_or_else(|| {
            panic!(
                "no {kind:?} child in {:?}",
                r.children.iter().map(|c| c.kind).collect::<Vec<_>>()
            )
        })
}

fn all_rays(r: &RayRecord) -> Vec<&RayRecord> {
    let mut out = vec![r];
    for c in &r.children {
        out.extend(all_rays(c));
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Chapter 7, "Making a Scene".

/// RTC ch. 7 "The color when a ray misses": ray (0, 0, −5) → (0, 1, 0) gives color(0, 0, 0).
#[test]
fn color_when_a_ray_misses() {
    for offset in OFFSETS {
        let scene = load(&world(offset));
        let (c, root) = trace(&scene, [0., 0., -5.], [0., 1., 0.]);
        assert_eq!(c, Vec3::ZERO, "{offset}");
        assert!(root.hit.is_none());
        assert!(steps(&root).any(|s| matches!(s, Step::Miss { .. })));
        assert!(root.children.is_empty());
    }
}

/// RTC ch. 7 "The color when a ray hits": ray (0, 0, −5) → (0, 0, 1) gives
/// color(0.38066, 0.47583, 0.2855).
#[test]
fn color_when_a_ray_hits() {
    for offset in OFFSETS {
        let scene = load(&world(offset));
        let (c, root) = trace(&scene, [0., 0., -5.], [0., 0., 1.]);
        assert_color(c, [0.38066, 0.47583, 0.2855], TOL, offset);
        let hit = root.hit.as_ref().expect("hit");
        assert_eq!(hit.name, "outer");
        assert!(
            (hit.t - 4.0).abs() < 1e-6,
            "RTC: the outer sphere is hit at t = 4, got {}",
            hit.t
        );
        // The light at (−10, 10, −10) is visible from (0, 0, −1).
        let shadow = child(&root, RayKind::Shadow);
        assert!(shadow.hit.is_none());
    }
}

/// RTC ch. 7 "Shading an intersection from the inside": light at (0, 0.25, 0), ray from the
/// origin along +z, hit on the inner sphere at t = 0.5, gives color(0.90498, 0.90498, 0.90498).
/// (The book's value predates shadows; chapter 8 keeps it: the light is inside the inner sphere,
/// so nothing lies between the point and the light.)
#[test]
fn shading_an_intersection_from_the_inside() {
    for offset in OFFSETS {
        let scene = load(&default_world(offset, "[0, 0.25, 0]", "", "", ""));
        let (c, root) = trace(&scene, [0., 0., 0.], [0., 0., 1.]);
        assert_color(c, [0.90498, 0.90498, 0.90498], TOL, offset);
        let hit = root.hit.as_ref().expect("hit");
        assert_eq!(hit.name, "inner");
        assert!((hit.t - 0.5).abs() < 1e-6);
        // RTC's comps.inside = true and the normal flips to (0, 0, −1).
        let surface = steps(&root)
            .find_map(|s| match s {
                Step::Surface { inside, normal, .. } => Some((*inside, *normal)),
                _ => None,
            })
            .expect("surface step");
        assert!(surface.0, "{offset}: the hit is from the inside");
        assert_eq!(surface.1, [0., 0., -1.]);
        let light = steps(&root)
            .find(|s| matches!(s, Step::Light { .. }))
            .unwrap();
        assert!(
            matches!(light, Step::Light { blocked: false, .. }),
            "{light:?}"
        );
    }
}

/// RTC ch. 7 "The color with an intersection behind the ray": both materials ambient 1, ray from
/// (0, 0, 0.75) along −z: the colour is the inner sphere's colour, (1, 1, 1).
#[test]
fn color_with_an_intersection_behind_the_ray() {
    for offset in OFFSETS {
        let scene = load(&default_world(
            offset,
            "[-10, 10, -10]",
            "ambient = 1",
            "ambient = 1",
            "",
        ));
        let (c, root) = trace(&scene, [0., 0., 0.75], [0., 0., -1.]);
        assert_color(c, [1., 1., 1.], 1e-6, offset);
        assert_eq!(root.hit.as_ref().unwrap().name, "inner");
    }
}

// ---------------------------------------------------------------------------------------------
// Chapter 8, "Shadows".

/// RTC ch. 8 "shade_hit() is given an intersection in shadow": light at (0, 0, −10), a sphere at
/// the origin and a second at (0, 0, 10), ray (0, 0, 5) → (0, 0, 1), hit at t = 4 on the second:
/// color(0.1, 0.1, 0.1), and the trace names the first sphere as the blocker.
#[test]
fn shade_hit_in_shadow() {
    for offset in OFFSETS {
        let text = format!(
            r#"[render]
offset = "{offset}"
epsilon = 1e-4

[[light]]
name = "light"
position = [0, 0, -10]

[[sphere]]
name = "s1"
center = [0, 0, 0]

[[sphere]]
name = "s2"
center = [0, 0, 10]
"#
        );
        let scene = load(&text);
        let (c, root) = trace(&scene, [0., 0., 5.], [0., 0., 1.]);
        assert_color(c, [0.1, 0.1, 0.1], TOL, offset);
        let hit = root.hit.as_ref().unwrap();
        assert_eq!(hit.name, "s2");
        assert!((hit.t - 4.0).abs() < 1e-6);
        let light = steps(&root)
            .find_map(|s| match s {
                Step::Light {
                    blocked,
                    blocker,
                    diffuse,
                    specular,
                    ..
                } => Some((*blocked, blocker.clone(), *diffuse, *specular)),
                _ => None,
            })
            .expect("a Light step");
        assert!(light.0, "{offset}: the light must be blocked");
        assert_eq!(light.1.as_deref(), Some("s1"));
        assert_eq!(
            (light.2, light.3),
            ([0.0; 3], [0.0; 3]),
            "in shadow: ambient only"
        );
        assert!(steps(&root).any(|s| matches!(s, Step::ShadowRay { .. })));
        let shadow = child(&root, RayKind::Shadow);
        assert_eq!(shadow.hit.as_ref().map(|h| h.name.as_str()), Some("s1"));
    }
}

// ---------------------------------------------------------------------------------------------
// Chapter 11, "Reflection and Refraction".

const DOWN: [f32; 3] = [0., -S2, S2];

fn reflective_floor(offset: &str, max_depth: u32) -> String {
    world(offset).replace("max_depth = 5", &format!("max_depth = {max_depth}"))
        + r#"
[[material]]
name = "mirror-ish"
reflective = 0.5

[[plane]]
name = "floor"
axis = "y"
offset = -1
material = "mirror-ish"
"#
}

/// RTC ch. 11 "shade_hit() with a reflective material": the default world plus a plane at
/// y = −1 with reflective 0.5; ray (0, 0, −3) → (0, −√2/2, √2/2) hits it at t = √2:
/// color(0.87677, 0.92436, 0.82918). "The reflected color for a reflective material" is
/// color(0.19032, 0.2379, 0.14274): the reflection ray's colour times 0.5.
#[test]
fn shade_hit_with_a_reflective_material() {
    for offset in OFFSETS {
        let scene = load(&reflective_floor(offset, 5));
        let (c, root) = trace(&scene, [0., 0., -3.], DOWN);
        assert_color(c, [0.87677, 0.92436, 0.82918], TOL, offset);
        let hit = root.hit.as_ref().unwrap();
        assert_eq!(hit.name, "floor");
        assert!((hit.t - 2f32.sqrt()).abs() < 1e-6);
        assert!(
            steps(&root)
                .any(|s| matches!(s, Step::Reflect { reflective, .. } if *reflective == 0.5))
        );
        let refl = child(&root, RayKind::Reflection);
        assert_eq!(refl.depth, 1);
        assert_eq!(refl.weight, 0.5);
        let weighted = Vec3::from(refl.color) * refl.weight;
        assert_color(
            weighted,
            [0.19032, 0.2379, 0.14274],
            TOL,
            "reflected colour",
        );
    }
}

/// RTC ch. 11 "The reflected color at the maximum recursive depth": with no recursion left the
/// reflected colour is black, so the floor shows its own Phong colour only — and the trace says
/// the depth limit stopped it. The book prints that colour in the transparent-floor vector below:
/// same point, same Phong terms, and the refracted red ball adds nothing to green and blue, so
/// its G and B, 0.68642, are the floor alone (0.87677 − 0.19032 = 0.68645 agrees to 3e-5).
#[test]
fn reflected_color_at_the_maximum_recursive_depth() {
    for offset in OFFSETS {
        let scene = load(&reflective_floor(offset, 0));
        let (c, root) = trace(&scene, [0., 0., -3.], DOWN);
        assert_color(c, [0.68642, 0.68642, 0.68642], TOL, offset);
        assert!(root.children.iter().all(|c| c.kind != RayKind::Reflection));
        assert!(steps(&root).any(|s| matches!(s, Step::DepthLimit { max_depth: 0 })));
    }
}

/// RTC ch. 11 "The reflected color for a nonreflective material": ray from the origin along +z,
/// inner sphere ambient 1: the reflected colour is black — in raystep, no reflection ray at all.
#[test]
fn nonreflective_surface_has_no_reflection_ray() {
    for offset in OFFSETS {
        let scene = load(&default_world(
            offset,
            "[-10, 10, -10]",
            "",
            "ambient = 1",
            "",
        ));
        let (_, root) = trace(&scene, [0., 0., 0.], [0., 0., 1.]);
        assert_eq!(root.hit.as_ref().unwrap().name, "inner");
        for r in all_rays(&root) {
            assert_ne!(r.kind, RayKind::Reflection);
            assert!(!steps(r).any(|s| matches!(s, Step::Reflect { .. } | Step::DepthLimit { .. })));
        }
    }
}

/// RTC ch. 11 "color_at() with mutually reflective surfaces": light at the origin, two perfect
/// mirrors at y = −1 and y = 1, ray from the origin along +y: the recursion terminates.
#[test]
fn mutually_reflective_surfaces_terminate() {
    for offset in OFFSETS {
        let text = format!(
            r#"[render]
max_depth = 5
offset = "{offset}"
epsilon = 1e-4

[[light]]
position = [0, 0, 0]

[[material]]
name = "mirror"
reflective = 1

[[plane]]
name = "lower"
axis = "y"
offset = -1
material = "mirror"

[[plane]]
name = "upper"
axis = "y"
offset = 1
material = "mirror"
"#
        );
        let scene = load(&text);
        let (c, root) = trace(&scene, [0., 0., 0.], [0., 1., 0.]);
        assert!(c.is_finite(), "{offset}: {c:?}");
        // The chain bounces upper, lower, upper, … until depth 5, where the limit stops it.
        let mut r = &root;
        let mut names = vec![];
        loop {
            names.push(
                r.hit
                    .as_ref()
                    .expect("every bounce hits a mirror")
                    .name
                    .clone(),
            );
            match r.children.iter().find(|c| c.kind == RayKind::Reflection) {
                Some(c) => r = c,
                None => break,
            }
        }
        assert_eq!(r.depth, 5);
        assert_eq!(
            names,
            ["upper", "lower", "upper", "lower", "upper", "lower"]
        );
        assert!(steps(r).any(|s| matches!(s, Step::DepthLimit { max_depth: 5 })));
    }
}

fn glass_floor(offset: &str, reflective: f32) -> String {
    world(offset)
        + &format!(
            r#"
[[material]]
name = "floor"
transparency = 0.5
refractive_index = 1.5
reflective = {reflective:?}

[[material]]
name = "red"
color = [1, 0, 0]
ambient = 0.5

[[plane]]
name = "floor"
axis = "y"
offset = -1
material = "floor"

[[sphere]]
name = "ball"
center = [0, -3.5, -0.5]
radius = 1
material = "red"
"#
        )
}

/// Checks the refraction branch both glass-floor vectors share: Snell at the floor from air
/// (n1 = 1) into glass (n2 = 1.5), the refracted ray hitting the ball, which the floor shadows
/// (RTC has no transparent shadows), so the ball shows its ambient (0.5, 0, 0).
fn check_refraction_branch(root: &RayRecord, offset: &str) {
    let refract = steps(root)
        .find_map(|s| match s {
            Step::Refract {
                n1,
                n2,
                cos_i,
                total_internal_reflection,
                direction,
                ..
            } => Some((*n1, *n2, *cos_i, *total_internal_reflection, *direction)),
            _ => None,
        })
        .expect("a Refract step");
    assert_eq!((refract.0, refract.1), (1.0, 1.5), "{offset}: n1, n2");
    assert!(
        (refract.2 - S2).abs() < 1e-6,
        "cos θᵢ = √2/2, got {}",
        refract.2
    );
    assert!(!refract.3);
    assert!(refract.4.is_some());
    let refr = child(root, RayKind::Refraction);
    assert_eq!(refr.weight, 0.5);
    assert_eq!(
        refr.hit.as_ref().map(|h| h.name.as_str()),
        Some("ball"),
        "{offset}"
    );
    assert_color(
        Vec3::from(refr.color),
        [0.5, 0., 0.],
        1e-6,
        "the ball in the floor's shadow",
    );
    let ball_light = steps(refr)
        .find_map(|s| match s {
            Step::Light {
                blocked, blocker, ..
            } => Some((*blocked, blocker.clone())),
            _ => None,
        })
        .expect("the ball is lit");
    assert_eq!(ball_light, (true, Some("floor".to_string())));
}

/// RTC ch. 11 "shade_hit() with a transparent material": the default world plus a floor at
/// y = −1 (transparency 0.5, refractive index 1.5) and a red ball (ambient 0.5) at
/// (0, −3.5, −0.5); ray (0, 0, −3) → (0, −√2/2, √2/2): color(0.93642, 0.68642, 0.68642).
#[test]
fn shade_hit_with_a_transparent_material() {
    for offset in OFFSETS {
        let scene = load(&glass_floor(offset, 0.0));
        let (c, root) = trace(&scene, [0., 0., -3.], DOWN);
        assert_color(c, [0.93642, 0.68642, 0.68642], TOL, offset);
        assert_eq!(root.hit.as_ref().unwrap().name, "floor");
        check_refraction_branch(&root, offset);
        assert!(!steps(&root).any(|s| matches!(s, Step::Schlick { .. } | Step::Reflect { .. })));
    }
}

/// RTC ch. 11 "shade_hit() with a reflective, transparent material": the same floor also
/// reflective 0.5, blended by Schlick: color(0.93391, 0.69643, 0.69243).
#[test]
fn shade_hit_with_a_reflective_transparent_material() {
    for offset in OFFSETS {
        let scene = load(&glass_floor(offset, 0.5));
        let (c, root) = trace(&scene, [0., 0., -3.], DOWN);
        assert_color(c, [0.93391, 0.69643, 0.69243], TOL, offset);
        check_refraction_branch(&root, offset);
        // Schlick from air into n = 1.5 at cos θᵢ = √2/2 (RTC's formula, not a printed value):
        // r0 = (0.5/2.5)² = 0.04, R = r0 + (1 − r0)(1 − √2/2)⁵ = 0.0420695.
        let reflectance = steps(&root)
            .find_map(|s| match s {
                Step::Schlick { reflectance, .. } => Some(*reflectance),
                _ => None,
            })
            .expect("a Schlick step");
        assert!((reflectance - 0.0420695).abs() < 1e-5, "{reflectance}");
        let refl = child(&root, RayKind::Reflection);
        // The reflected ray sees what the reflective-floor vector's reflection ray saw.
        assert_color(
            Vec3::from(refl.color) * 0.5,
            [0.19032, 0.2379, 0.14274],
            TOL,
            "reflected colour",
        );
        let kinds: Vec<RayKind> = root.children.iter().map(|c| c.kind).collect();
        assert_eq!(
            kinds,
            [RayKind::Shadow, RayKind::Reflection, RayKind::Refraction]
        );
    }
}

// ---------------------------------------------------------------------------------------------
// One tracer: the recorded colour is the rendered colour, bit for bit.

/// Every scene in `scenes/`, shrunk to 40×30.
fn shipped_scenes() -> Vec<(String, Scene)> {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("scenes");
    let mut out = vec![];
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scene = load_file(&path).unwrap_or_else(|e| panic!("{e}"));
            out.push((path.display().to_string(), scene));
        }
    }
    assert!(!out.is_empty(), "no scenes in {}", dir.display());
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// The book's worlds seen through raystep's default camera (reflection, refraction, Schlick).
fn rtc_scenes() -> Vec<(String, Scene)> {
    ["fixed", "robust"]
        .iter()
        .flat_map(|o| {
            [
                (format!("default world ({o})"), world(o)),
                (format!("reflective floor ({o})"), reflective_floor(o, 5)),
                (format!("glass floor ({o})"), glass_floor(o, 0.0)),
                (format!("glass mirror floor ({o})"), glass_floor(o, 0.5)),
            ]
        })
        .map(|(name, text)| (name, load(&text)))
        .collect()
}

fn assert_bit_identical(name: &str, scene: &Scene) {
    let tracer = Tracer::new(scene, &BruteForce);
    let spp = scene.settings.spp;
    for y in 0..scene.camera.height {
        for x in 0..scene.camera.width {
            let mut sum = Vec3::ZERO;
            for k in 0..spp {
                let trace = tracer.record(x, y, k);
                let silent = tracer.trace_sample(x, y, k, &mut Silent);
                assert_eq!(
                    trace.color,
                    silent.to_array(),
                    "{name}: pixel ({x}, {y}) sample {k}"
                );
                assert_eq!(trace.root.color, trace.color);
                assert_eq!((trace.pixel, trace.sample), ([x, y], k));
                sum += Vec3::from(trace.color);
            }
            let pixel = tracer.trace_pixel(x, y, &mut Silent);
            assert_eq!(
                (sum / spp as f32).to_array(),
                pixel.to_array(),
                "{name}: pixel ({x}, {y}) mean"
            );
        }
    }
}

#[test]
fn recorded_color_is_rendered_color_bit_for_bit() {
    for (name, mut scene) in shipped_scenes().into_iter().chain(rtc_scenes()) {
        scene.camera.width = 40;
        scene.camera.height = 30;
        for policy in [
            OffsetPolicy::None,
            OffsetPolicy::Fixed,
            OffsetPolicy::Robust,
        ] {
            scene.settings.offset = policy;
            for spp in [1, 4] {
                scene.settings.spp = spp;
                assert_bit_identical(&format!("{name} offset {policy:?} spp {spp}"), &scene);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Saved traces.

fn sample_traces() -> Vec<Trace> {
    let mut out = vec![];
    for (_, mut scene) in shipped_scenes() {
        scene.camera.width = 40;
        scene.camera.height = 30;
        let tracer = Tracer::new(&scene, &BruteForce);
        out.push(tracer.record(20, 15, 0));
        out.push(tracer.record(0, 0, 0));
    }
    // A trace with shadow, reflection and refraction branches: the camera at (0, 0, −3) looking
    // along RTC's ray (0, −√2/2, √2/2), centre pixel.
    let text = glass_floor("robust", 0.5)
        + "\n[camera]\nfrom = [0, 0, -3]\nat = [0, -1, -2]\nwidth = 3\nheight = 3\n";
    let scene = load(&text);
    let trace = Tracer::new(&scene, &BruteForce).record(1, 1, 0);
    assert_color(
        Vec3::from(trace.color),
        [0.93391, 0.69643, 0.69243],
        5e-4,
        "camera-traced RTC ray",
    );
    assert!(trace.rays().iter().any(|r| r.kind == RayKind::Refraction));
    out.push(trace);
    out
}

#[test]
fn trace_json_round_trip() {
    for trace in sample_traces() {
        let json = trace.to_json();
        let back = Trace::from_json(&json, "trace.json")
            .unwrap_or_else(|e| panic!("a trace written by to_json must load back: {e}"));
        assert_eq!(back, trace);
        // Writing the loaded trace again gives the same text.
        assert_eq!(back.to_json(), json);
    }
}

#[test]
fn trace_of_another_version_is_a_version_error() {
    let trace = sample_traces().remove(0);
    let mut value: serde_json::Value = serde_json::from_str(&trace.to_json()).unwrap();
    value["version"] = serde_json::json!(999);
    let text = serde_json::to_string_pretty(&value).unwrap();
    match Trace::from_json(&text, "future.json") {
        Err(e @ TraceError::Version { found: 999, .. }) => {
            let msg = e.to_string();
            assert!(
                msg.contains("future.json") && msg.contains("999") && msg.contains("version"),
                "{msg}"
            );
        }
        other => panic!("expected a version error, got {other:?}"),
    }
}

#[test]
fn truncated_or_foreign_text_is_corrupt_with_line_and_column() {
    let json = sample_traces().remove(0).to_json();
    let mut cut = json.len() / 2;
    while !json.is_char_boundary(cut) {
        cut -= 1;
    }
    let truncated = &json[..cut];
    // The line the input ends on: one past the last newline (`lines()` would miss the empty last
    // line when the cut falls just after a newline, as it does for the first shipped scene).
    let expect_line = truncated.split('\n').count();
    match Trace::from_json(truncated, "cut.json") {
        Err(e @ TraceError::Corrupt { line, column, .. }) => {
            // serde_json reports the end of the input: the last line of what is left.
            assert_eq!(line, expect_line, "{e}");
            assert!(column >= 1);
            let msg = e.to_string();
            assert!(
                msg.starts_with(&format!("cut.json:{line}:{column}:")),
                "{msg}"
            );
        }
        other => panic!("expected a corrupt-trace error, got {other:?}"),
    }
    for (text, line) in [
        ("this is not a trace", 1),
        ("", 1),
        ("{\n  \"version\": 1,\n  \"pixel\": [", 3),
    ] {
        match Trace::from_json(text, "junk.json") {
            Err(TraceError::Corrupt {
                file,
                line: l,
                column,
                ..
            }) => {
                assert_eq!(file, "junk.json");
                assert_eq!(l, line, "{text:?}");
                assert!(column >= 1, "{text:?}");
            }
            other => panic!("{text:?}: expected a corrupt-trace error, got {other:?}"),
        }
    }
    // Valid JSON that is not a trace is corrupt too (missing fields), never a panic.
    for text in [
        "{}",
        "[1, 2, 3]",
        "{\"version\": 1}",
        "{\"version\": \"1\"}",
    ] {
        assert!(
            matches!(
                Trace::from_json(text, "x.json"),
                Err(TraceError::Corrupt { .. })
            ),
            "{text}"
        );
    }
}
