//! raystep's own trace in the student format: what a student's tracer is checked against.
//!
//! Sphere and plane values are the ones raystep recorded (its course-notes-form a, b, c and
//! discriminant, its denominator); a test's `t` is the nearest root past t_min *ignoring* the
//! closest hit so far, because a student's loop usually tests every object against an open
//! interval and keeps the nearest afterwards. Triangles are given in Möller–Trumbore's terms
//! (lesson 4), computed in double precision from the recorded ray and vertices, whichever
//! method raystep used.

use super::format::{Hit, Pixel, Ray, Test};
use crate::record::{RayRecord, Step, Trace};

/// raystep's trace of one pixel in the student model, with where each part is in the trace's
/// timeline (for the `raystep open … --step K` links).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Expected {
    /// The pixel's rays.
    pub pixel: Pixel,
    /// Per ray: the timeline index of its first step.
    pub ray_step: Vec<usize>,
    /// Per ray, per test: the timeline index of the test.
    pub test_step: Vec<Vec<usize>>,
    /// Per ray: the timeline index of its surface (hit point and normal), if any.
    pub hit_step: Vec<Option<usize>>,
    /// Per ray, per light: the timeline index of the light's step.
    pub light_step: Vec<Vec<usize>>,
    /// Per ray: the reflection's or refraction's recorded numbers, for spotting mistakes.
    pub bends: Vec<Bend>,
    /// The camera and the primary ray's point inside the pixel (for naming camera mistakes).
    pub camera: Option<(crate::scene::Camera, [f32; 2])>,
    /// The name of every object of the scene (for telling a student that a name they printed
    /// is not one; empty: not checked). [`expected`] leaves it empty (a trace names only the
    /// objects it met); [`with_names`] fills it.
    pub names: Vec<String>,
}

/// `e` with the names of every object of `scene`.
pub fn with_names(mut e: Expected, scene: &crate::scene::Scene) -> Expected {
    e.names = (0..scene.objects.len() as u32)
        .map(|i| scene.object_name(i))
        .collect();
    e
}

/// What raystep recorded about a ray's reflection and refraction.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Bend {
    /// n1 / n2 of a refraction.
    pub eta: Option<f64>,
}

/// An f32 as the f64 with the same shortest decimal form (1.6f32 → 1.6, not 1.600000023841858),
/// so the format reads like the trace the app shows.
fn f(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(x as f64)
}

fn v64(a: [f32; 3]) -> [f64; 3] {
    a.map(f)
}

/// Converts `trace` (one sample of one pixel) to the student model.
pub fn expected(trace: &Trace) -> Expected {
    let tl = trace.timeline();
    let index_of = |s: &crate::record::StepRecord| tl.iter().position(|(_, t)| std::ptr::eq(*t, s));
    let mut out = Expected {
        pixel: Pixel {
            at: Some(trace.pixel),
            rays: vec![],
        },
        ..Default::default()
    };
    fn walk(
        r: &RayRecord,
        parent: Option<usize>,
        light: Option<String>,
        out: &mut Expected,
        index_of: &dyn Fn(&crate::record::StepRecord) -> Option<usize>,
    ) {
        let me = out.pixel.rays.len();
        let mut ray = Ray {
            kind: r.kind.name().to_string(),
            depth: r.depth,
            origin: Some(v64(r.origin)),
            direction: Some(v64(r.direction)),
            light,
            parent,
            ..Default::default()
        };
        let mut tests = vec![];
        let mut hit_step = None;
        let mut lights = vec![];
        let mut shadow_lights = vec![];
        let mut bend = Bend::default();
        let (o, d) = (v64(r.origin), v64(r.direction));
        let mut point_normal = None;
        for s in &r.steps {
            let k = index_of(s).unwrap_or(0);
            match &s.step {
                Step::Sphere { name, test, .. } => {
                    let t = test
                        .roots
                        .and_then(|[lo, hi]| [lo, hi].into_iter().find(|t| *t > r.t_min))
                        .map(f);
                    ray.tests.push(Test::Sphere {
                        object: name.clone(),
                        abcd: [test.a, test.b, test.c, test.discriminant].map(|x| Some(f(x))),
                        t: Some(t),
                    });
                    tests.push(k);
                }
                Step::Plane { name, test, .. } => {
                    let t = test
                        .t_raw
                        .filter(|t| t.is_finite() && *t > r.t_min && !test.parallel)
                        .map(f);
                    ray.tests.push(Test::Plane {
                        object: name.clone(),
                        denominator: Some(f(test.denominator)),
                        t: Some(t),
                    });
                    tests.push(k);
                }
                Step::Triangle { name, vertices, .. } => {
                    let (det, uvt) = moller_trumbore(o, d, vertices.map(v64), r.t_min as f64);
                    ray.tests.push(Test::Triangle {
                        object: name.clone(),
                        det_u_v: [Some(det), uvt.map(|x| x.0), uvt.map(|x| x.1)],
                        t: Some(uvt.map(|x| x.2)),
                    });
                    tests.push(k);
                }
                Step::Surface { point, normal, .. } => {
                    point_normal = Some((v64(*point), v64(*normal)));
                    hit_step = Some(k);
                }
                Step::Light { name, blocked, .. } => {
                    ray.shadows.push((name.clone(), Some(*blocked)));
                    lights.push(k);
                }
                Step::ShadowRay { name, .. } => shadow_lights.push(name.clone()),
                Step::Refract { eta, n1, n2, .. } => {
                    bend.eta = Some(eta.map_or(f(*n1) / f(*n2), f));
                }
                _ => {}
            }
        }
        ray.hit = Some(r.hit.as_ref().map(|h| Hit {
            object: Some(h.name.clone()),
            t: Some(f(h.t)),
            point: point_normal.map(|p| p.0),
            normal: point_normal.map(|p| p.1),
        }));
        // A shadow ray's hit is "blocked or not", shown by the light's record instead; it
        // returns no colour.
        if r.kind == crate::record::RayKind::Shadow {
            ray.hit = None;
        } else {
            ray.color = Some(v64(r.color));
        }
        out.pixel.rays.push(ray);
        out.ray_step
            .push(r.steps.first().and_then(index_of).unwrap_or(0));
        out.test_step.push(tests);
        out.hit_step.push(hit_step);
        out.light_step.push(lights);
        out.bends.push(bend);
        let mut shadow_names = shadow_lights.into_iter();
        for c in &r.children {
            let light = (c.kind == crate::record::RayKind::Shadow)
                .then(|| shadow_names.next())
                .flatten();
            walk(c, Some(me), light, out, index_of);
        }
    }
    walk(&trace.root, None, None, &mut out, &index_of);
    let offset = trace.root.steps.iter().find_map(|s| match &s.step {
        Step::Camera { offset, .. } => Some(*offset),
        _ => None,
    });
    out.camera = Some((trace.camera.clone(), offset.unwrap_or([0.5, 0.5])));
    out
}

/// Möller–Trumbore in double precision (lesson 4): D0 = det(−Q, E1, E2), and (u, v, t) when the
/// ray hits the triangle past `t_min`.
pub fn moller_trumbore(
    s: [f64; 3],
    q: [f64; 3],
    p: [[f64; 3]; 3],
    t_min: f64,
) -> (f64, Option<(f64, f64, f64)>) {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (e1, e2) = (sub(p[1], p[0]), sub(p[2], p[0]));
    let nq = [-q[0], -q[1], -q[2]];
    // det(a, b, c) = a · (b × c)
    let det = |a, b, c| dot(a, cross(b, c));
    let d0 = det(nq, e1, e2);
    if d0 == 0.0 {
        return (d0, None);
    }
    let t_vec = sub(s, p[0]);
    let t = det(t_vec, e1, e2) / d0;
    let u = det(nq, t_vec, e2) / d0;
    let v = det(nq, e1, t_vec) / d0;
    let hit = t > t_min && u >= 0.0 && v >= 0.0 && u + v <= 1.0;
    (d0, hit.then_some((u, v, t)))
}
