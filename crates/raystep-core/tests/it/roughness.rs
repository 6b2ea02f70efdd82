//! A glossy BSDF's roughness texture (`[[material]] roughness_texture`): its green channel scales
//! the material's roughness at each hit, under the Monte Carlo integrators. Checked against the
//! same scene without the texture: a texture whose every texel has green g renders bit for bit
//! as the material with roughness × g (0.5 × 0.8 = 0.4, exact in f32), and one below the least
//! roughness as a mirror; the recorded step, its words and its math panel.

use raystep_core::accel::SceneAccel;
use raystep_core::explain::describe::describe;
use raystep_core::explain::formula::explain;
use raystep_core::record::texturing::RoughnessRead;
use raystep_core::record::{RayKind, Step, Trace};
use raystep_core::render::cpu::{RenderOptions, render};
use raystep_core::scene::{Integrator, Scene, load_str};
use raystep_core::trace::Tracer;

const SCENE: &str = include_str!("../../../../tests/scenes/rough-glossy.toml");

fn scene(text: &str) -> Scene {
    load_str(text, "rough-glossy.toml", None).unwrap()
}

fn pixels(scene: &Scene) -> Vec<[u32; 3]> {
    let (accel, _) = SceneAccel::build(scene);
    render(&Tracer::new(scene, &accel), &RenderOptions::default())
        .unwrap()
        .pixels
        .iter()
        .map(|c| c.to_array().map(f32::to_bits))
        .collect()
}

const COLORS: &str = "colors = [[1, 0.8, 1], [1, 0.02, 1]]";

#[test]
fn a_roughness_texture_renders_as_the_roughness_it_gives() {
    for integrator in [Integrator::Path, Integrator::Distribution] {
        let with = |text: String| {
            let mut s = scene(&text);
            s.settings.integrator = integrator;
            pixels(&s)
        };
        // Green 0.8 everywhere: roughness 0.5 × 0.8 = 0.4.
        let textured = with(SCENE.replace(COLORS, "colors = [[1, 0.8, 1], [0, 0.8, 0]]"));
        let plain = with(
            SCENE
                .replace("roughness = 0.5", "roughness = 0.4")
                .replace("roughness_texture = \"roughness\"", ""),
        );
        assert!(textured == plain, "{integrator:?}: 0.5 × 0.8 is not 0.4");
        // Green 0.02 everywhere: 0.01, below the least roughness (0.03): a mirror.
        let textured = with(SCENE.replace(COLORS, "colors = [[1, 0.02, 1], [1, 0.02, 1]]"));
        let mirror = with(
            SCENE
                .replace("bsdf = \"glossy\"", "bsdf = \"mirror\"")
                .replace("roughness_texture = \"roughness\"", ""),
        );
        assert!(textured == mirror, "{integrator:?}: 0.01 is not a mirror");
        // And the checker of the two is neither.
        let both = with(SCENE.to_string());
        assert!(both != plain && both != mirror);
    }
}

/// The roughness texture's step: after the hit, with the material's roughness and the
/// texel's green channel; read back from JSON; said in words and in the math panel. Whitted's
/// Phong has no roughness: no such step there.
#[test]
fn the_roughness_read_is_recorded_said_and_explained() {
    let s = scene(SCENE);
    let (accel, _) = SceneAccel::build(&s);
    let tracer = Tracer::new(&s, &accel);
    // (24, 32) looks at an even square of the floor (green 0.8); (24, 26) at an odd one.
    for (x, y, green, roughness, alpha) in [
        (24, 32, 0.8f32, 0.4f32, "0.16"),
        (24, 26, 0.02, 0.01, "a mirror"),
    ] {
        let trace = tracer.record(x, y, 0);
        let again = Trace::from_json(&trace.to_json(), "t.json").unwrap();
        assert_eq!(again.root, trace.root);
        // The camera ray's hit reads it (the first ray of sample 0's path).
        let path = &trace.root;
        let step = path
            .steps
            .iter()
            .map(|s| &s.step)
            .find(|s| {
                matches!(
                    s,
                    Step::Texture {
                        roughness: Some(_),
                        ..
                    }
                )
            })
            .unwrap_or_else(|| panic!("({x}, {y}): no roughness step"));
        let Step::Texture {
            texture,
            texel,
            roughness: Some(r),
            color,
            ..
        } = step
        else {
            unreachable!()
        };
        assert_eq!(texture, "roughness");
        assert_eq!(texel[1], green);
        assert_eq!(
            r,
            &RoughnessRead {
                material: 0.5,
                roughness
            }
        );
        assert_eq!(color, &[roughness; 3]);
        let words = describe(step, RayKind::Primary);
        assert!(
            words.starts_with("roughness texture \"roughness\"")
                && words.ends_with(&format!("roughness 0.5 × green {green} = {roughness}")),
            "{words}"
        );
        let e = explain(&trace, path, step);
        assert!(
            e.title.starts_with("Roughness texture \"roughness\""),
            "{}",
            e.title
        );
        let line = |n: &str| e.lines.iter().find(|l| l.name == n).unwrap();
        assert_eq!(line("r").value, roughness.to_string());
        assert!(line("α").value.starts_with(alpha), "{}", line("α").value);
    }
    let mut whitted = s.clone();
    whitted.settings.integrator = Integrator::Whitted;
    let (accel, _) = SceneAccel::build(&whitted);
    let trace = Tracer::new(&whitted, &accel).record(24, 32, 0);
    assert!(
        trace
            .root
            .steps
            .iter()
            .all(|s| !matches!(s.step, Step::Texture { .. }))
    );
}

#[test]
fn an_unknown_roughness_texture_is_named_with_its_field() {
    let e = load_str(
        &SCENE.replace(
            "roughness_texture = \"roughness\"",
            "roughness_texture = \"rough\"",
        ),
        "rough-glossy.toml",
        None,
    )
    .unwrap_err();
    assert_eq!(
        e.field.as_deref(),
        Some("material \"plate\" → roughness_texture")
    );
    assert!(
        e.message
            .contains("unknown texture \"rough\" (known: \"roughness\")"),
        "{e:?}"
    );
}
