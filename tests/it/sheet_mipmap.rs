//! Exercise sheet 19 (mip-mapping and ray cones) answered as a careful student would: from the
//! scene's text in double precision — the camera ray of the book's conventions (book/scenes.md), where it meets
//! the floor y = 0, γ = atan(2·tan(fov/2) / height), W = γ·t, L = W·64 / |d_y|, λ = log₂ L and
//! the level ⌊λ⌋ held to 0 … 6 — never from raystep's trace. For 300 students per question the
//! premise holds (the ray meets the trilinear floor) and the f64 answer is marked right against
//! raystep's f32 key; 40 students' answers graded as a class CSV score full marks.
//!
//! And every pixel the `mip_level` question may draw is checked, not only those 300 students':
//! where λ is within the premise's margin of a whole number the question is not asked, and
//! everywhere else the f64 level and raystep's agree.

use std::path::PathBuf;

use crate::common::exact::camera_ray;
use crate::common::grades::answer_every_variant;
use raystep::accel::SceneAccel;
use raystep::lesson::{Answer, Coord, extract, load_exercise_sheet};
use raystep::trace::Tracer;

const STUDENTS: usize = 300;
const CLASS: usize = 40;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// (W, λ) of pixel (x, y)'s primary ray on the floor, in f64.
fn cone(scene: &toml::Value, x: u32, y: u32) -> (f64, f64) {
    let (o, d) = camera_ray(scene, x, y);
    let t = -o[1] / d[1];
    let c = &scene["camera"];
    let fov = c["fov"].as_integer().unwrap() as f64;
    let height = c["height"].as_integer().unwrap() as f64;
    let gamma = (2.0 * (fov.to_radians() / 2.0).tan() / height).atan();
    let w = gamma * t;
    (w, (w * 64.0 / d[1].abs()).log2())
}

#[test]
fn every_variant_of_the_mipmap_sheet_is_true_and_keyed_right() {
    let path = root().join("lessons/exercises/19-mipmap.toml");
    answer_every_variant(&path, STUDENTS, CLASS, |q, v, scene, _| {
        let [x, y] = v.pixel;
        let (o, d) = camera_ray(scene, x, y);
        // The premise: the ray meets the floor at x < 0 (the trilinear half, on the right).
        let t = -o[1] / d[1];
        let hit_x = o[0] + d[0] * t;
        assert!(
            t > 0.0 && hit_x < 0.0 && o[2] + d[2] * t < 200.0,
            "{} pixel ({x}, {y}): the premise is false (t = {t}, x = {hit_x})",
            q.id
        );
        let (w, lambda) = cone(scene, x, y);
        match q.id.as_str() {
            "cone_width" => format!("{w}"),
            "mip_lambda" => format!("{lambda}"),
            "mip_level" => format!("{}", lambda.clamp(0.0, 6.0).floor()),
            other => panic!("question {other}"),
        }
    });
}

#[test]
fn every_pixel_the_mip_level_question_may_draw_is_clear_cut() {
    let path = root().join("lessons/exercises/19-mipmap.toml");
    let sheet = load_exercise_sheet(&path).unwrap();
    let q = sheet
        .questions
        .iter()
        .find(|q| q.id == "mip_level")
        .unwrap();
    let scene_file = root().join("scenes/mipmap.toml");
    let text: toml::Value = toml::from_str(&std::fs::read_to_string(&scene_file).unwrap()).unwrap();
    let scene = raystep::scene::load_file(&scene_file).unwrap();
    let (accel, _) = SceneAccel::build(&scene);
    let tracer = Tracer::new(&scene, &accel);
    let premise = q.require.clone().unwrap();
    let range = |c: &Coord| match *c {
        Coord::Fixed(v) => v..=v,
        Coord::Range(a, b) => a..=b,
    };
    let (mut asked, mut skipped) = (0, 0);
    for y in range(&q.pixel[1]) {
        for x in range(&q.pixel[0]) {
            let trace = tracer.record(x, y, 0);
            let (_, lambda) = cone(&text, x, y);
            match premise.check(&trace, q) {
                Ok(()) => {
                    asked += 1;
                    let want = lambda.clamp(0.0, 6.0).floor();
                    assert_eq!(
                        extract(&trace, q),
                        Answer::Number(want),
                        "pixel ({x}, {y}): λ = {lambda}"
                    );
                }
                Err(why) => {
                    skipped += 1;
                    assert!(
                        (lambda - lambda.round()).abs() < 0.0101,
                        "pixel ({x}, {y}) not asked ({why}) though λ = {lambda}"
                    );
                }
            }
        }
    }
    println!("mip_level: {asked} pixels asked, {skipped} not clear-cut");
    assert!(asked > 1000 && skipped < asked / 20, "{asked} {skipped}");
}
