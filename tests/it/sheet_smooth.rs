//! Exercise sheet 17 (smooth shading) answered as a careful student would: every variant's shading
//! normal computed in double precision from the scene's own text (the camera of the book's (book/scenes.md)
//! conventions, Möller–Trumbore in f64 over every triangle, the vertex normals normalised and
//! blended), never from raystep's trace. For 300 students per question:
//! - the premise holds: the pixel's ray hits the triangle or the smooth sphere the text names;
//! - the f64 answer is marked right against raystep's f32 key (a right answer is never marked
//!   wrong).
//!
//! Then 40 students' f64 answers go through `raystep grade` as a class CSV: every one scores full
//! marks.

use std::path::PathBuf;

use crate::common::exact::{V, add, camera_ray, cross, dot, hit, mul, sub, unit, vec3};
use crate::common::grades::answer_every_variant;

const STUDENTS: usize = 300;
const CLASS: usize = 40;

/// A triangle with its vertex normals and a name.
struct Tri {
    name: String,
    p: [V; 3],
    n: Option<[V; 3]>,
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
    answer_every_variant(&path, STUDENTS, CLASS, |q, v, scene, base| {
        let (name, ns) = shading_normal(scene, base, v.pixel[0], v.pixel[1]);
        // The premise: the text says which object the ray hits.
        let expected = if q.id == "blend" {
            "tri"
        } else {
            "smooth sphere"
        };
        assert_eq!(name, expected, "{} {:?}", q.id, v.pixel);
        format!("{}, {}, {}", ns[0], ns[1], ns[2])
    });
}
