//! Exercise sheet 20 (instances) answered as a careful student would: every variant's answer
//! computed in double precision from the variant's own scene text (the camera of the book's (book/scenes.md)
//! conventions; M⁻¹ of the instance's scale and translation inverted by hand; the unit sphere met
//! in object space; the normal carried back by M⁻ᵀ), never from raystep's trace. For 300
//! students per question:
//! - the premise holds: the pixel's ray meets the egg (the quadratic has a root in front);
//! - the f64 answer is marked right against raystep's f32 key;
//! - and the classic mistakes (origin not translated, direction translated, normal by M) are
//!   marked wrong and named.
//!
//! Then 40 students' f64 answers go through `raystep grade` as a class CSV: every one scores full
//! marks.

use std::path::PathBuf;

use crate::common::exact::{V, add, camera_ray, dot, mul, unit, vec3};
use crate::common::grades::answer_every_variant;
use raystep::lesson::{load_exercise_sheet, mark};

const STUDENTS: usize = 300;
const CLASS: usize = 40;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The egg's scale and translation, read from the variant's scene text.
fn placement(scene: &toml::Value) -> (V, V) {
    let inst = &scene["instance"].as_array().unwrap()[0];
    assert_eq!(inst["of"].as_str(), Some("ball"));
    (vec3(&inst["scale"]), vec3(&inst["translate"]))
}

/// Everything the sheet asks, in f64: S′, Q′, t, the world normal, and the three mistakes'
/// answers (S′ without translation, Q′ translated, the normal by M).
struct Worked {
    origin: V,
    direction: V,
    t: f64,
    normal: V,
    origin_untranslated: V,
    direction_translated: V,
    normal_by_m: V,
}

fn work(scene: &toml::Value, x: u32, y: u32) -> Worked {
    let (s, q) = camera_ray(scene, x, y);
    let (k, tr) = placement(scene);
    // M = T·K (scale, then translate): M⁻¹p = (p − T)/K per axis; its linear part v/K.
    let inv_point = |p: V| [0, 1, 2].map(|i| (p[i] - tr[i]) / k[i]);
    let inv_vector = |v: V| [0, 1, 2].map(|i| v[i] / k[i]);
    let o = inv_point(s);
    let d = inv_vector(q);
    // |o + t·d|² = 1: a t² + 2 b′ t + c = 0, the nearer root in front.
    let (a, b, c) = (dot(d, d), dot(o, d), dot(o, o) - 1.0);
    let disc = b * b - a * c;
    assert!(
        disc > 0.0,
        "pixel ({x}, {y}): the ray misses the egg, the premise is false"
    );
    let t = (-b - disc.sqrt()) / a;
    assert!(t > 0.0, "pixel ({x}, {y}): the egg is behind the camera");
    let p_obj = add(o, mul(d, t));
    // The object normal is P′ itself (facing the camera here: the ray enters from outside);
    // M⁻ᵀ for a scale divides by it, M multiplies.
    let normal = unit([0, 1, 2].map(|i| p_obj[i] / k[i]));
    let normal_by_m = unit([0, 1, 2].map(|i| p_obj[i] * k[i]));
    Worked {
        origin: o,
        direction: d,
        t,
        normal,
        origin_untranslated: inv_vector(s),
        direction_translated: inv_point(q),
        normal_by_m,
    }
}

fn text(v: V) -> String {
    format!("{}, {}, {}", v[0], v[1], v[2])
}

#[test]
fn every_variant_of_the_instances_sheet_is_true_and_keyed_right() {
    let path = root().join("lessons/exercises/20-instances.toml");
    answer_every_variant(&path, STUDENTS, CLASS, |q, v, scene, _| {
        let [x, y] = v.pixel;
        let w = work(scene, x, y);
        match q.id.as_str() {
            "object_origin" => text(w.origin),
            "object_direction" => text(w.direction),
            "closest_t" => format!("{}", w.t),
            "normal" => text(w.normal),
            other => panic!("no f64 answer for question {other}"),
        }
    });
}

#[test]
fn the_classic_mistakes_are_marked_wrong_and_named() {
    let path = root().join("lessons/exercises/20-instances.toml");
    let sheet = load_exercise_sheet(&path).unwrap();
    for q in &sheet.questions {
        let (want, mistake_id) = match q.id.as_str() {
            "object_origin" => (0, "origin-not-translated"),
            "object_direction" => (1, "direction-translated"),
            "normal" => (2, "normal-by-matrix"),
            _ => continue,
        };
        for k in 0..60 {
            let v = sheet.variant(q, &format!("m{k:03}"));
            let scene: toml::Value = toml::from_str(v.scene_toml.as_ref().unwrap()).unwrap();
            let w = work(&scene, v.pixel[0], v.pixel[1]);
            let wrong = [w.origin_untranslated, w.direction_translated, w.normal_by_m][want];
            let (key, mistakes) = sheet.expected_and_mistakes(q, &v).unwrap();
            let given = text(wrong);
            let mut m = mark(&key, q.quantity.kind(), Some(&given), q.tolerance);
            assert!(
                !m.right,
                "{} {k}: the mistake {given} is marked right",
                q.id
            );
            raystep::lesson::mistakes::annotate(&mut m, q, Some(&given), &mistakes);
            assert_eq!(
                m.mistake.map(|x| x.id()),
                Some(mistake_id),
                "{} {k}: {given} is not named as {mistake_id}: {:?}",
                q.id,
                m.note
            );
        }
    }
}
