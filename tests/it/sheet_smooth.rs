//! Exercise sheet 17 (smooth shading) answered as a careful student would: every variant's shading
//! normal computed in double precision from the scene's own text (the camera of the README's
//! conventions, Möller–Trumbore in f64 over every triangle, the vertex normals normalised and
//! blended), never from raystep's trace. For 300 students per question:
//! - the premise holds: the pixel's ray hits the triangle or the smooth sphere the text names;
//! - the f64 answer is marked right against raystep's f32 key (a right answer is never marked
//!   wrong).
//!
//! Then 40 students' f64 answers go through `raystep grade` as a class CSV: every one scores full
//! marks.

use raystep::lesson::{SceneSource, load_exercise_sheet, mark};
use std::path::PathBuf;

use crate::common::grades::grade_class;

const STUDENTS: usize = 300;
const CLASS: usize = 40;

type V = [f64; 3];

fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn mul(a: V, s: f64) -> V {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: V) -> V {
    mul(a, 1.0 / dot(a, a).sqrt())
}

/// A triangle with its vertex normals and a name.
struct Tri {
    name: String,
    p: [V; 3],
    n: Option<[V; 3]>,
}

/// Möller–Trumbore in f64: (t, u, v) of a hit in front of the origin.
fn hit(o: V, d: V, p: &[V; 3]) -> Option<(f64, f64, f64)> {
    let (e1, e2) = (sub(p[1], p[0]), sub(p[2], p[0]));
    let h = cross(d, e2);
    let det = dot(e1, h);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = sub(o, p[0]);
    let u = dot(s, h) / det;
    let q = cross(s, e1);
    let v = dot(d, q) / det;
    let t = dot(e2, q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then_some((t, u, v))
}

fn vec3(v: &toml::Value) -> V {
    let a = v.as_array().unwrap();
    [0, 1, 2].map(|i| {
        a[i].as_float()
            .or(a[i].as_integer().map(|x| x as f64))
            .unwrap()
    })
}

/// The camera's ray through pixel (x, y), by the README's conventions.
fn camera_ray(scene: &toml::Value, x: u32, y: u32) -> (V, V) {
    let c = &scene["camera"];
    let num = |k: &str| {
        c[k].as_float()
            .or(c[k].as_integer().map(|x| x as f64))
            .unwrap()
    };
    let (from, at) = (vec3(&c["from"]), vec3(&c["at"]));
    let up = c.get("up").map_or([0.0, 1.0, 0.0], vec3);
    let (w_px, h_px) = (num("width"), num("height"));
    let w = unit(sub(from, at));
    let u = unit(cross(up, w));
    let v = cross(w, u);
    let hh = (num("fov").to_radians() / 2.0).tan();
    let hw = hh * w_px / h_px;
    let sx = 2.0 * (x as f64 + 0.5) / w_px - 1.0;
    let sy = 1.0 - 2.0 * (y as f64 + 0.5) / h_px;
    let d = unit(sub(add(mul(u, sx * hw), mul(v, sy * hh)), w));
    (from, d)
}

/// The scene's triangles: its `[[triangle]]`s and its meshes' faces (OBJ read here).
fn triangles(scene: &toml::Value, dir: &std::path::Path) -> Vec<Tri> {
    let mut out = vec![];
    for t in scene
        .get("triangle")
        .and_then(|t| t.as_array())
        .into_iter()
        .flatten()
    {
        let p = t["vertices"].as_array().unwrap();
        out.push(Tri {
            name: t["name"].as_str().unwrap().to_string(),
            p: [vec3(&p[0]), vec3(&p[1]), vec3(&p[2])],
            n: t.get("normals")
                .map(|n| {
                    n.as_array()
                        .unwrap()
                        .iter()
                        .map(|x| unit(vec3(x)))
                        .collect::<Vec<_>>()
                })
                .map(|n| [n[0], n[1], n[2]]),
        });
    }
    for m in scene
        .get("mesh")
        .and_then(|t| t.as_array())
        .into_iter()
        .flatten()
    {
        let text = std::fs::read_to_string(dir.join(m["obj"].as_str().unwrap())).unwrap();
        let translate = m.get("translate").map_or([0.0; 3], vec3);
        let flat = m.get("shading").and_then(|s| s.as_str()) == Some("flat");
        let (mut vs, mut vns) = (vec![], vec![]);
        for line in text.lines() {
            let w: Vec<&str> = line.split_whitespace().collect();
            let xyz = || [1, 2, 3].map(|i| w[i].parse::<f64>().unwrap());
            match w.first() {
                Some(&"v") => vs.push(add(xyz(), translate)),
                Some(&"vn") => vns.push(unit(xyz())),
                Some(&"f") => {
                    let idx: Vec<(usize, usize)> = w[1..]
                        .iter()
                        .map(|c| {
                            let mut it = c.split("//").map(|i| i.parse::<usize>().unwrap() - 1);
                            (it.next().unwrap(), it.next().unwrap())
                        })
                        .collect();
                    out.push(Tri {
                        name: m["name"].as_str().unwrap().to_string(),
                        p: [vs[idx[0].0], vs[idx[1].0], vs[idx[2].0]],
                        n: (!flat).then(|| [vns[idx[0].1], vns[idx[1].1], vns[idx[2].1]]),
                    });
                }
                _ => {}
            }
        }
    }
    out
}

/// The hit's object name and shading normal, in f64.
fn shading_normal(scene: &toml::Value, dir: &std::path::Path, x: u32, y: u32) -> (String, V) {
    let (o, d) = camera_ray(scene, x, y);
    let tris = triangles(scene, dir);
    let (t, u, v, tri) = tris
        .iter()
        .filter_map(|tri| hit(o, d, &tri.p).map(|(t, u, v)| (t, u, v, tri)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .expect("the ray hits a triangle");
    // A floor plane y = 0 nearer than the triangle would be the hit instead.
    if let Some(_floor) = scene.get("plane") {
        let tf = -o[1] / d[1];
        assert!(
            !(tf > 0.0 && tf < t),
            "the floor is nearer than the triangle"
        );
    }
    let n = tri.n.expect("a smooth triangle");
    let s = add(add(mul(n[0], 1.0 - u - v), mul(n[1], u)), mul(n[2], v));
    let ns = unit(s);
    // Turned to the side the ray came from, as the geometric normal facing the ray is.
    let g = cross(sub(tri.p[1], tri.p[0]), sub(tri.p[2], tri.p[0]));
    let facing = if dot(g, d) > 0.0 { mul(g, -1.0) } else { g };
    (
        tri.name.clone(),
        if dot(ns, facing) < 0.0 {
            mul(ns, -1.0)
        } else {
            ns
        },
    )
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn every_variant_of_the_smooth_shading_sheet_is_true_and_keyed_right() {
    let path = root().join("lessons/exercises/17-smooth-shading.toml");
    let sheet = load_exercise_sheet(&path).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut class: Vec<Vec<String>> = vec![vec![]; CLASS];
    for q in &sheet.questions {
        for k in 0..STUDENTS {
            let who = format!("s{k:04}");
            let v = sheet.variant(q, &who);
            let (text, base) = match (&q.scene, &v.scene_toml) {
                (SceneSource::File(p), _) => (
                    std::fs::read_to_string(p).unwrap(),
                    p.parent().unwrap().to_path_buf(),
                ),
                (SceneSource::Inline(_), Some(t)) => (t.clone(), dir.path().to_path_buf()),
                (SceneSource::Inline(_), None) => unreachable!(),
            };
            let scene: toml::Value = toml::from_str(&text).unwrap();
            let (name, ns) = shading_normal(&scene, &base, v.pixel[0], v.pixel[1]);
            // The premise: the text says which object the ray hits.
            let expected = if q.id == "blend" {
                "tri"
            } else {
                "smooth sphere"
            };
            assert_eq!(name, expected, "{} {who} {:?}", q.id, v.pixel);
            let given = format!("{}, {}, {}", ns[0], ns[1], ns[2]);
            let (key, _) = sheet.expected_and_mistakes(q, &v).unwrap();
            let m = mark(&key, q.quantity.kind(), Some(&given), q.tolerance);
            assert!(
                m.right,
                "{} {who} pixel {:?}: the f64 answer {given} is marked wrong against the key {key}: {:?}",
                q.id, v.pixel, m.note
            );
            if let Some(row) = class.get_mut(k) {
                row.push(given);
            }
        }
    }
    let mut csv = String::from("student");
    for q in &sheet.questions {
        csv += &format!(",{}", q.id);
    }
    csv += "\n";
    for (k, answers) in class.iter().enumerate() {
        csv += &format!("s{k:04}");
        for a in answers {
            csv += &format!(",\"{a}\"");
        }
        csv += "\n";
    }
    let (g, mut rows) = grade_class(&path, &csv, dir.path(), "17-smooth-shading");
    let header = rows.remove(0);
    let score = header.iter().position(|h| h == "score").unwrap();
    let out_of = header.iter().position(|h| h == "out_of").unwrap();
    assert_eq!(rows.len(), CLASS, "{g}");
    for row in &rows {
        assert_eq!(row[score], row[out_of], "{row:?}");
    }
}
