//! Exercise sheet 18 (textures) answered as a careful student would: every variant's answer
//! computed in double precision from the scene's own text (the camera of the book's (book/scenes.md)
//! conventions, Möller–Trumbore over the triangles, the ray against the sphere and the floor, the
//! texture coordinates blended, the texel position, the checker's parity), never from raystep's
//! trace. For 300 students per question:
//! - the premise holds: the pixel's ray hits the object the text names;
//! - the f64 answer is marked right against raystep's f32 key.
//!
//! Then 40 students' f64 answers go through `raystep grade` as a class CSV: every one scores full
//! marks.

use std::path::PathBuf;

use crate::common::exact::{V, add, camera_ray, dot, hit, mul, sub, vec3};
use crate::common::grades::answer_every_variant;

const STUDENTS: usize = 300;
const CLASS: usize = 40;

/// What the ray hits first, in f64: the name of a `[[triangle]]` with (u, v) mapped through its
/// `uvs`, or "globe" / "floor" with the hit point.
enum Hit {
    Triangle(String, [f64; 2]),
    Other(String, V),
}

fn uv_of(t: &toml::Value) -> [[f64; 2]; 3] {
    let a = t["uvs"].as_array().unwrap();
    [0, 1, 2].map(|i| {
        let p = a[i].as_array().unwrap();
        [0, 1].map(|k| {
            p[k].as_float()
                .or(p[k].as_integer().map(|x| x as f64))
                .unwrap()
        })
    })
}

fn first_hit(scene: &toml::Value, x: u32, y: u32) -> Hit {
    let (o, d) = camera_ray(scene, x, y);
    let mut best: Option<(f64, Hit)> = None;
    let mut consider = |t: f64, h: Hit| {
        if t > 0.0 && best.as_ref().is_none_or(|b| t < b.0) {
            best = Some((t, h));
        }
    };
    for tri in scene["triangle"].as_array().unwrap() {
        let p = tri["vertices"].as_array().unwrap();
        let p = [vec3(&p[0]), vec3(&p[1]), vec3(&p[2])];
        if let Some((t, u, v)) = hit(o, d, &p) {
            let uv = uv_of(tri);
            let b0 = 1.0 - u - v;
            let blend = [0, 1].map(|k| b0 * uv[0][k] + u * uv[1][k] + v * uv[2][k]);
            consider(
                t,
                Hit::Triangle(tri["name"].as_str().unwrap().into(), blend),
            );
        }
    }
    for s in scene
        .get("sphere")
        .and_then(|s| s.as_array())
        .into_iter()
        .flatten()
    {
        // |o + t·d − c|² = r², d a unit vector: the nearer root in front.
        let c = vec3(&s["center"]);
        let r = s["radius"]
            .as_float()
            .or(s["radius"].as_integer().map(|x| x as f64))
            .unwrap();
        let f = sub(o, c);
        let b = dot(f, d);
        let disc = b * b - (dot(f, f) - r * r);
        if disc >= 0.0 {
            let t = -b - disc.sqrt();
            consider(t, Hit::Other("globe".into(), add(o, mul(d, t))));
        }
    }
    if scene.get("plane").is_some() {
        // The floor, y = 0.
        let t = -o[1] / d[1];
        consider(t, Hit::Other("floor".into(), add(o, mul(d, t))));
    }
    best.expect("the ray hits something").1
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn every_variant_of_the_textures_sheet_is_true_and_keyed_right() {
    let path = root().join("lessons/exercises/18-textures.toml");
    answer_every_variant(&path, STUDENTS, CLASS, |q, v, scene, _| {
        let [x, y] = v.pixel;
        match (q.id.as_str(), first_hit(scene, x, y)) {
            ("uv_u", Hit::Triangle(name, uv)) if name == "tri" => format!("{}", uv[0]),
            ("uv_v", Hit::Triangle(name, uv)) if name == "tri" => format!("{}", uv[1]),
            // The tiles: 8 × 8 texels, nearest: (⌊8u⌋, ⌊8(1 − v)⌋).
            ("texel_column", Hit::Triangle(name, uv)) if name.starts_with("tiles") => {
                format!("{}", (uv[0] * 8.0).floor())
            }
            ("texel_row", Hit::Triangle(name, uv)) if name.starts_with("tiles") => {
                format!("{}", ((1.0 - uv[1]) * 8.0).floor())
            }
            // The floor's checker: one square per unit of (x, z).
            ("checker", Hit::Other(name, p)) if name == "floor" => {
                let odd = (p[0].floor() + p[2].floor()).rem_euclid(2.0) == 1.0;
                let c = if odd { 0.15 } else { 0.9 };
                format!("{c}, {c}, {c}")
            }
            (id, Hit::Triangle(name, _) | Hit::Other(name, _)) => {
                panic!("{id} pixel ({x}, {y}): the premise is false: the ray hits {name}")
            }
        }
    });
}
