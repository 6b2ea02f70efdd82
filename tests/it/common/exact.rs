//! A careful student's arithmetic, in f64, from a scene file's own text: vector operations, the
//! camera ray of the book's conventions (book/scenes.md), and Möller–Trumbore. The exercise-sheet tests answer
//! every variant with it and check raystep's f32 keys against it.

/// A point or vector.
pub type V = [f64; 3];

pub fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub fn mul(a: V, s: f64) -> V {
    [a[0] * s, a[1] * s, a[2] * s]
}
pub fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub fn cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub fn unit(a: V) -> V {
    mul(a, 1.0 / dot(a, a).sqrt())
}

/// Möller–Trumbore in f64: (t, u, v) of a hit in front of the origin.
pub fn hit(o: V, d: V, p: &[V; 3]) -> Option<(f64, f64, f64)> {
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

pub fn vec3(v: &toml::Value) -> V {
    let a = v.as_array().unwrap();
    [0, 1, 2].map(|i| {
        a[i].as_float()
            .or(a[i].as_integer().map(|x| x as f64))
            .unwrap()
    })
}

/// The camera's ray through pixel (x, y), by the book's conventions (book/scenes.md).
pub fn camera_ray(scene: &toml::Value, x: u32, y: u32) -> (V, V) {
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
