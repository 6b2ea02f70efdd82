//! A traced pixel's numbers against their exact values (the lab panel's per-pixel view):
//! hand-computed exact cases, and the far sphere where the textbook quadratic in f32 loses the
//! radius (docs/NUMERICS.md S1) while the stable form keeps it.

use raystep_core::accel::SceneAccel;
use raystep_core::scene::{Scene, load_file, load_str};
use raystep_core::trace::Tracer;
use raystep_course::stability::pixel::{ExactValue, exact_values};
use std::path::Path;

fn values(scene: &Scene, x: u32, y: u32) -> Vec<ExactValue> {
    let (accel, _) = SceneAccel::build(scene);
    let trace = Tracer::new(scene, &accel).record(x, y, 0);
    exact_values(&trace, Some(scene))
}

fn find<'a>(v: &'a [ExactValue], object: &str, quantity: &str) -> &'a ExactValue {
    v.iter()
        .find(|e| e.object == object && e.quantity == quantity)
        .unwrap_or_else(|| panic!("no {quantity} of {object} in {v:?}"))
}

#[test]
fn the_unit_sphere_and_a_floor_by_hand() {
    // The middle pixel of a 3×3 image from (0, 0, −5) looking at the origin: the ray is exactly
    // O = (0, 0, −5), d = (0, 0, 1). Against the unit sphere at the origin: f = (0, 0, −5),
    // a = 1, b = 2 f·d = −10, c = 24, Δ = 100 − 96 = 4, roots (10 ∓ 2)/2 = 4 and 6. Every number
    // is exact in f32, so the errors are 0 ulps.
    let scene = load_str(
        r#"
[camera]
from = [0, 0, -5]
at = [0, 0, 0]
width = 3
height = 3
[render]
sphere_method = "textbook"
[[light]]
position = [-10, 10, -10]
[[sphere]]
name = "ball"
[[triangle]]
name = "card"
vertices = [[-1, -1, -2], [3, -1, -2], [-1, 3, -2]]
"#,
        "hand.toml",
        None,
    )
    .unwrap();
    let v = values(&scene, 1, 1);
    let disc = find(&v, "ball", "discriminant");
    assert_eq!((disc.recorded, disc.exact, disc.ulps), (4.0, 4.0, 0.0));
    assert_eq!(find(&v, "ball", "t₀").exact, 4.0);
    assert_eq!(find(&v, "ball", "t₁").exact, 6.0);
    // The card in the plane z = −2 in front of the ball (tested after it, so the ball's roots
    // are all computed): the ray meets it at t = 3, at (0, 0) — u = (0 − (−1))/4 = 1/4 along
    // p0→p1 and v = 1/4 along p0→p2.
    let t = find(&v, "card", "t");
    assert_eq!(t.exact, 3.0);
    assert_eq!(find(&v, "card", "u").exact, 0.25);
    assert_eq!(find(&v, "card", "v").exact, 0.25);
    // The shadow ray's numbers start from a computed (rounded) hit point: a few ulps at most.
    assert!(v.iter().all(|e| e.ulps < 4.0), "{v:?}");
    assert!(
        v.iter().any(|e| e.step > 3),
        "the shadow ray's tests are compared too"
    );
}

#[test]
fn the_far_sphere_loses_its_radius_only_with_the_textbook_formula() {
    let path =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("scenes/far-sphere.toml");
    let mut scene = load_file(&path).unwrap();
    let worst = |scene: &Scene| {
        values(scene, 32, 32)
            .iter()
            .filter(|e| e.quantity == "discriminant")
            .map(|e| e.ulps)
            .fold(0.0, f64::max)
    };
    scene.settings.sphere_method = raystep_core::shapes::SphereMethod::Textbook;
    let textbook = worst(&scene);
    scene.settings.sphere_method = raystep_core::shapes::SphereMethod::Stable;
    let stable = worst(&scene);
    // f·f ≈ 1.7e7 has an f32 spacing of 2: c = f·f − 1 is off by up to 1 in 1, so Δ = b² − 4ac
    // is wrong in its leading digits — millions of ulps — where the stable form is within a few.
    assert!(textbook > 1e4, "textbook: {textbook} ulps");
    assert!(stable < 64.0, "stable: {stable} ulps");
}
