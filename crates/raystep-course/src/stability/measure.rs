//! Running the kernels on a case, judging each answer against its exact reference, and timing.

use super::cases::{Case, CaseData, Geometry, Kind, Query, SpawnMode, SpawnQuery};
use super::exact::{self, BoxRef, Dd, PlaneRef, SphereRef, TriangleRef};
use super::stats::{percentile, time_per_item, ulp};
use super::{CostPoint, Method, Options, Precision, Primitive, Row};
use crate::accel::Hit;
use crate::math::{Ray, Real, Vector};
use crate::scene::{OffsetPolicy, Shape};
use crate::shapes::{aabb, plane, sphere, triangle};
use crate::trace::interaction::{interact_shape, spawn_origin};
use crate::trace::shading::reflect;
use glam::Vec3;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::hint::black_box;

/// Every t error (in ulps) per primitive × method × precision, for the plots' percentiles.
#[derive(Debug, Default)]
pub(super) struct Samples(BTreeMap<(Primitive, Method, Precision), Vec<f64>>);

/// The exact answer for one query in one precision.
#[derive(Debug, Clone)]
enum Ref {
    Sphere(SphereRef),
    Tris(Vec<TriangleRef>),
    Plane(PlaneRef),
    Box(BoxRef),
}

fn reference(q: &Query, p: Precision) -> Ref {
    let u = p.unit_roundoff();
    let r = |v: [f64; 3]| match p {
        Precision::F32 => v.map(|x| x as f32 as f64),
        Precision::F64 => v,
    };
    let s = |x: f64| match p {
        Precision::F32 => x as f32 as f64,
        Precision::F64 => x,
    };
    let (o, d) = (r(q.origin), r(q.dir));
    match &q.geometry {
        Geometry::Sphere { center, radius } => {
            Ref::Sphere(exact::sphere(r(*center), s(*radius), o, d, u))
        }
        Geometry::Triangles(ts) => Ref::Tris(
            ts.iter()
                .map(|t| exact::triangle([r(t[0]), r(t[1]), r(t[2])], o, d, u))
                .collect(),
        ),
        Geometry::Plane { normal, offset, .. } => {
            Ref::Plane(exact::plane(r(*normal), s(*offset), o, d, u))
        }
        Geometry::Aabb { lo, hi } => Ref::Box(exact::aabb(r(*lo), r(*hi), o, d, u)),
    }
}

/// The exact answer to one query, flattened: hit, t, the other root (spheres), u and v
/// (triangles), in the band.
type Answer = (bool, Option<Dd>, Option<Dd>, Option<(Dd, Dd)>, bool);

/// A query converted to precision T, ready for the kernels (None: `Ray::new` rejected it).
enum Prepared<T: Real> {
    Sphere(Ray<T>, T::V, T),
    Tris(Ray<T>, Vec<[T::V; 3]>),
    Plane(Ray<T>, T::V, T, Option<usize>),
    Box(Ray<T>, T::V, T::V, T::V),
}

fn v<T: Real>(a: [f64; 3]) -> T::V {
    crate::math::vec_from_f64::<T>(a)
}

fn prepare<T: Real>(q: &Query) -> Option<Prepared<T>> {
    let ray = Ray::<T>::new(v::<T>(q.origin), v::<T>(q.dir), T::zero(), T::infinity()).ok()?;
    Some(match &q.geometry {
        Geometry::Sphere { center, radius } => {
            Prepared::Sphere(ray, v::<T>(*center), T::from_f64(*radius))
        }
        Geometry::Triangles(ts) => Prepared::Tris(
            ray,
            ts.iter()
                .map(|t| [v::<T>(t[0]), v::<T>(t[1]), v::<T>(t[2])])
                .collect(),
        ),
        Geometry::Plane {
            normal,
            offset,
            axis,
        } => Prepared::Plane(ray, v::<T>(*normal), T::from_f64(*offset), *axis),
        Geometry::Aabb { lo, hi } => {
            let inv = T::V::new(
                T::one() / ray.dir.at(0),
                T::one() / ray.dir.at(1),
                T::one() / ray.dir.at(2),
            );
            Prepared::Box(ray, v::<T>(*lo), v::<T>(*hi), inv)
        }
    })
}

/// What a kernel answered: t (and u, v and which triangle, for triangles), widened to f64,
/// and how many kernel calls it took (several for the leak tests' triangle pairs and fans).
#[derive(Debug, Clone, Copy, Default)]
struct Outcome {
    t: Option<f64>,
    uv: Option<(usize, f64, f64)>,
    tests: u32,
}

/// Whether `m` applies to this prepared query (the axis-aligned plane method only to
/// axis-aligned planes).
fn applies<T: Real>(p: &Prepared<T>, m: Method) -> bool {
    !matches!((p, m), (Prepared::Plane(_, _, _, None), Method::PlaneAxis))
}

#[inline(always)]
fn eval<T: Real>(p: &Prepared<T>, m: Method) -> Outcome {
    match p {
        Prepared::Sphere(ray, c, r) => {
            let test = match m {
                Method::SphereTextbook => sphere::textbook(ray, *c, *r),
                _ => sphere::stable(ray, *c, *r),
            };
            Outcome {
                t: test.t.map(|t| t.to_f64()),
                uv: None,
                tests: 1,
            }
        }
        Prepared::Tris(ray, tris) => {
            for (k, tri) in tris.iter().enumerate() {
                let test = match m {
                    Method::MollerTrumbore => triangle::moller_trumbore(ray, *tri),
                    _ => triangle::watertight(ray, *tri),
                };
                if let Some(t) = test.t {
                    let (u, w) = (test.u.unwrap_or(T::nan()), test.v.unwrap_or(T::nan()));
                    return Outcome {
                        t: Some(t.to_f64()),
                        uv: Some((k, u.to_f64(), w.to_f64())),
                        tests: k as u32 + 1,
                    };
                }
            }
            Outcome {
                tests: tris.len() as u32,
                ..Outcome::default()
            }
        }
        Prepared::Plane(ray, n, c, axis) => {
            let test = match (m, axis) {
                (Method::PlaneAxis, Some(a)) => plane::axis(ray, *a, *c),
                _ => plane::general(ray, *n, *c),
            };
            Outcome {
                t: test.t.map(|t| t.to_f64()),
                uv: None,
                tests: 1,
            }
        }
        Prepared::Box(ray, lo, hi, inv) => {
            let test = match m {
                Method::SlabPlain => aabb::slab_plain(ray, *lo, *hi),
                _ => aabb::slab_robust(ray, *inv, *lo, *hi),
            };
            Outcome {
                t: test.hit.then(|| test.t_near.to_f64()),
                uv: None,
                tests: 1,
            }
        }
    }
}

fn methods(p: Primitive) -> Vec<Method> {
    Method::ALL
        .into_iter()
        .filter(|m| m.primitive() == p)
        .collect()
}

fn empty_row(case: &Case, method: Method, precision: Precision) -> Row {
    Row {
        case: case.id,
        title: case.title,
        primitive: case.primitive,
        method,
        precision,
        rays: 0,
        exact_hits: 0,
        in_band: 0,
        misclassified: 0,
        leak_rays: 0,
        leaks: 0,
        self_hits: 0,
        nonfinite: 0,
        compared: 0,
        t_max_ulps: 0.0,
        t_p99_ulps: 0.0,
        t_max_rel: 0.0,
        t_p99_rel: 0.0,
        uv_max_ulps: None,
        uv_p99_ulps: None,
        ns_per_test: 0.0,
    }
}

pub(super) fn run_case(case: &Case, opts: &Options, samples: &mut Samples) -> Vec<Row> {
    match &case.data {
        CaseData::Rays { kind, queries } => {
            let refs: Vec<(Ref, Ref)> = if *kind == Kind::Reject {
                vec![]
            } else {
                queries
                    .par_iter()
                    .map(|q| {
                        // Computed per precision even for inputs exact in f32: the answer is
                        // the same, but the rounding band is the precision's own.
                        (reference(q, Precision::F32), reference(q, Precision::F64))
                    })
                    .collect()
            };
            let mut rows = vec![];
            for m in methods(case.primitive) {
                rows.extend(rays_row::<f32>(
                    case,
                    *kind,
                    queries,
                    &refs,
                    m,
                    Precision::F32,
                    opts,
                    samples,
                ));
                rows.extend(rays_row::<f64>(
                    case,
                    *kind,
                    queries,
                    &refs,
                    m,
                    Precision::F64,
                    opts,
                    samples,
                ));
            }
            rows
        }
        CaseData::Scenes(scenes) => vec![scene_row(case, scenes, opts)],
        CaseData::Spawn(queries) => [
            (Method::OffsetNone, OffsetPolicy::None),
            (Method::OffsetFixed, OffsetPolicy::Fixed),
            (Method::OffsetErrorBound, OffsetPolicy::Robust),
        ]
        .into_iter()
        .map(|(m, policy)| spawn_row(case, queries, m, policy, opts))
        .collect(),
    }
}

/// Whether a leak-test ray is within rounding of an edge that no other triangle of the query
/// shares (the surface's outline, not a shared edge): missing there is not a leak.
fn outer_band(q: &Query, r: &Ref) -> bool {
    let (Geometry::Triangles(ts), Ref::Tris(refs)) = (&q.geometry, r) else {
        return false;
    };
    let shared = |a: [f64; 3], b: [f64; 3], me: usize| {
        ts.iter()
            .enumerate()
            .any(|(k, t)| k != me && t.contains(&a) && t.contains(&b))
    };
    ts.iter().zip(refs).enumerate().any(|(k, (t, tr))| {
        tr.band_edges
            .iter()
            .enumerate()
            .any(|(i, &b)| b && !shared(t[(i + 1) % 3], t[(i + 2) % 3], k))
    })
}

#[allow(clippy::too_many_arguments)]
fn rays_row<T: Real>(
    case: &Case,
    kind: Kind,
    queries: &[Query],
    refs: &[(Ref, Ref)],
    m: Method,
    p: Precision,
    opts: &Options,
    samples: &mut Samples,
) -> Option<Row> {
    let mut row = empty_row(case, m, p);
    let prepared: Vec<(usize, Prepared<T>)> = queries
        .iter()
        .enumerate()
        .filter_map(|(i, q)| prepare::<T>(q).map(|pq| (i, pq)))
        .filter(|(_, pq)| applies(pq, m))
        .collect();
    let t_limit = T::max_value().to_f64();
    let mut ulps = vec![];
    let mut rels = vec![];
    let mut uvs = vec![];
    if kind == Kind::Reject {
        row.rays = queries.len();
        // Accepting an invalid ray is the failure; whatever the kernel then does is counted too.
        row.misclassified = prepared.len();
        for (_, pq) in &prepared {
            let o = eval(pq, m);
            if o.t.is_some_and(|t| !t.is_finite()) {
                row.nonfinite += 1;
            }
        }
    } else {
        if prepared.is_empty() {
            return None;
        }
        row.rays = prepared.len();
        for (i, pq) in &prepared {
            let r = match p {
                Precision::F32 => &refs[*i].0,
                Precision::F64 => &refs[*i].1,
            };
            let o = eval(pq, m);
            if o.t.is_some_and(|t| !t.is_finite())
                || o.uv
                    .is_some_and(|(_, u, w)| !u.is_finite() || !w.is_finite())
            {
                row.nonfinite += 1;
            }
            // The exact answer: hit, t, the other root (spheres), u and v (triangles), band.
            let (mut hit, t, other, uv, band): Answer = match r {
                Ref::Sphere(s) => (s.hit, s.t, s.other, None, s.band),
                Ref::Plane(s) => (s.hit, s.t, None, None, s.band),
                Ref::Box(s) => (s.hit, s.t, None, None, s.band),
                Ref::Tris(ts) => {
                    // The triangle the kernel hit, else the first the reference hits.
                    let k =
                        o.uv.map(|(k, _, _)| k)
                            .or_else(|| ts.iter().position(|t| t.hit))
                            .unwrap_or(0);
                    let tr = &ts[k];
                    let any = ts.iter().any(|t| t.hit);
                    let uv = tr.u.zip(tr.v);
                    (any, tr.t, None, uv, ts.iter().any(|t| t.band))
                }
            };
            // A hit beyond the precision's largest float cannot be reported: a clean miss is
            // the right answer there (S10 at slope 1e-40 in f32).
            if hit && t.is_some_and(|t| t.hi > t_limit) {
                hit = false;
            }
            if hit {
                row.exact_hits += 1;
            }
            if band {
                row.in_band += 1;
            }
            // A leak: the exact surface is hit, the method finds nothing (rays aimed near the
            // ends of an edge, or through a gap of rounded, no longer coplanar vertices, can
            // miss both triangles exactly: not leaks). A crack (S24): any ray finding nothing.
            if kind == Kind::Crack || (kind == Kind::Leak && hit && !outer_band(&queries[*i], r)) {
                row.leak_rays += 1;
                if o.t.is_none() {
                    row.leaks += 1;
                }
            }
            match (hit, o.t) {
                (true, None) | (false, Some(_)) => {
                    if !band && kind == Kind::Classify {
                        row.misclassified += 1;
                    }
                }
                (true, Some(tm)) => {
                    let Some(te) = t else { continue };
                    let err = te.abs_error(tm);
                    if let Some(other) = other
                        && other.abs_error(tm) < err
                    {
                        // The other root of a sphere: wrong outside the band (S3's near-root
                        // cancellation, S5), legitimate inside it (S4); no t error either way.
                        if !band {
                            row.misclassified += 1;
                        }
                        continue;
                    }
                    row.compared += 1;
                    if te.hi != 0.0 {
                        ulps.push(err / ulp(te.hi, p));
                        rels.push(err / te.hi.abs());
                    } else if err != 0.0 {
                        // t_exact = 0 (a box entered from inside): no ulp scale; any error is
                        // infinitely many ulps of 0.
                        ulps.push(f64::INFINITY);
                        rels.push(f64::INFINITY);
                    } else {
                        ulps.push(0.0);
                        rels.push(0.0);
                    }
                    if let (Some((_, um, vm)), Some((ue, ve))) = (o.uv, uv) {
                        let one = ulp(1.0, p);
                        uvs.push(ue.abs_error(um).max(ve.abs_error(vm)) / one);
                    }
                }
                (false, None) => {}
            }
        }
    }
    let list: Vec<&Prepared<T>> = prepared.iter().map(|(_, pq)| pq).collect();
    // Per kernel call: a leak query tests up to 2 (edge) or 6 (fan) triangles.
    let calls: usize = list.iter().map(|pq| eval(pq, m).tests as usize).sum();
    row.ns_per_test = time_per_item(calls, opts.min_timing_s, || {
        for pq in &list {
            black_box(eval(black_box(*pq), m));
        }
    });
    let sort = |v: &mut Vec<f64>| v.sort_by(|a, b| a.total_cmp(b));
    sort(&mut ulps);
    sort(&mut rels);
    sort(&mut uvs);
    row.t_max_ulps = ulps.last().copied().unwrap_or(0.0);
    row.t_p99_ulps = percentile(&ulps, 0.99);
    row.t_max_rel = rels.last().copied().unwrap_or(0.0);
    row.t_p99_rel = percentile(&rels, 0.99);
    if case.primitive == Primitive::Triangle && kind != Kind::Reject {
        row.uv_max_ulps = Some(uvs.last().copied().unwrap_or(0.0));
        row.uv_p99_ulps = Some(percentile(&uvs, 0.99));
    }
    samples
        .0
        .entry((case.primitive, m, p))
        .or_default()
        .extend(ulps);
    Some(row)
}

/// The renderer's default kernel for a shape (stable sphere, watertight triangle), f32.
fn test_shape(shape: &Shape, ray: &Ray<f32>) -> Option<Hit> {
    let hit = |t: Option<f32>, u: f32, v: f32| {
        t.map(|t| Hit {
            object: 0,
            t,
            u,
            v,
            instance: raystep_core::scene::NO_INSTANCE,
        })
    };
    match *shape {
        Shape::Sphere { center, radius } => hit(sphere::stable(ray, center, radius).t, 0.0, 0.0),
        Shape::Plane { normal, offset } => hit(plane::general(ray, normal, offset).t, 0.0, 0.0),
        Shape::AxisPlane { axis, offset } => hit(plane::axis(ray, axis, offset).t, 0.0, 0.0),
        Shape::Triangle { p } => {
            let t = triangle::watertight(ray, p);
            hit(t.t, t.u.unwrap_or(0.0), t.v.unwrap_or(0.0))
        }
    }
}

/// The spawned ray of one query by `policy`, through the renderer's own `interact` and
/// `spawn_origin` (f32, t_min = 0, as the renderer spawns them).
#[inline(always)]
fn spawn(sq: &SpawnQuery, ray: &Ray<f32>, hit: &Hit, policy: OffsetPolicy) -> Option<Ray<f32>> {
    let it = interact_shape(&sq.shape, hit, ray);
    let w: Vec3 = match sq.mode {
        SpawnMode::Reflect => reflect(ray.dir, it.normal),
        SpawnMode::Continue => ray.dir,
    };
    let o = spawn_origin(policy, crate::scene::Settings::default().epsilon, &it, w);
    Ray::new(o, w, 0.0, f32::INFINITY).ok()
}

fn spawn_row(
    case: &Case,
    queries: &[SpawnQuery],
    m: Method,
    policy: OffsetPolicy,
    opts: &Options,
) -> Row {
    let mut row = empty_row(case, m, Precision::F32);
    let mut prepared = vec![];
    for sq in queries {
        let Ok(ray) = Ray::<f32>::infinite(sq.origin, sq.dir) else {
            continue;
        };
        let Some(hit) = test_shape(&sq.shape, &ray) else {
            continue;
        };
        prepared.push((sq, ray, hit));
    }
    for (sq, ray, hit) in &prepared {
        let Some(s) = spawn(sq, ray, hit, policy) else {
            continue;
        };
        row.rays += 1;
        if !s.origin.is_finite() {
            row.nonfinite += 1;
        }
        if test_shape(&sq.shape, &s).is_some() {
            row.self_hits += 1;
        }
        if let Some(second) = &sq.second {
            row.exact_hits += 1;
            if test_shape(second, &s).is_none() {
                row.misclassified += 1;
            }
        }
    }
    row.ns_per_test = time_per_item(prepared.len(), opts.min_timing_s, || {
        for (sq, ray, hit) in &prepared {
            if let Some(s) = spawn(sq, ray, hit, policy) {
                black_box(test_shape(&sq.shape, &s));
            }
        }
    });
    row
}

pub(super) fn points(rows: &[Row], samples: &Samples) -> Vec<CostPoint> {
    let mut out = vec![];
    for prim in Primitive::ALL {
        for m in methods(prim) {
            for p in [Precision::F32, Precision::F64] {
                let rs: Vec<&Row> = rows
                    .iter()
                    .filter(|r| r.method == m && r.precision == p && r.rays > 0)
                    .collect();
                if rs.is_empty() {
                    continue;
                }
                // Cost: kernel rows only (S25 rejects before any test; S23 times a whole BVH
                // traversal).
                let timed: Vec<&&Row> = rs
                    .iter()
                    .filter(|r| r.case != "S25" && r.case != "S23")
                    .collect();
                let n: usize = timed.iter().map(|r| r.rays).sum();
                let ns = timed
                    .iter()
                    .map(|r| r.ns_per_test * r.rays as f64)
                    .sum::<f64>()
                    / n.max(1) as f64;
                let mut s = samples.0.get(&(prim, m, p)).cloned().unwrap_or_default();
                s.sort_by(|a, b| a.total_cmp(b));
                out.push(CostPoint {
                    primitive: prim,
                    method: m,
                    precision: p,
                    ns_per_test: ns,
                    p99_ulps: percentile(&s, 0.99),
                    max_ulps: s.last().copied().unwrap_or(0.0),
                    misclassified: rs.iter().map(|r| r.misclassified).sum(),
                    // S24's cracks are in the (compressed) data, not the method: its rows
                    // report them, the method's total does not.
                    leaks: rs.iter().filter(|r| r.case != "S24").map(|r| r.leaks).sum(),
                    self_hits: rs.iter().map(|r| r.self_hits).sum(),
                    nonfinite: rs.iter().map(|r| r.nonfinite).sum(),
                });
            }
        }
    }
    out
}

/// S23: every ray traced through the BVH and by brute force; any difference in the object or t
/// found is a misclassification. The BVH's node test is the robust slab test (f32).
fn scene_row(case: &Case, scenes: &[(crate::scene::Scene, Vec<Ray<f32>>)], opts: &Options) -> Row {
    use crate::accel::{Accelerator, BruteForce, Bvh};
    use crate::record::Silent;
    let mut row = empty_row(case, Method::SlabRobust, Precision::F32);
    let mut total_ns = 0.0;
    for (scene, rays) in scenes {
        let bvh = Bvh::build(scene);
        for ray in rays {
            row.rays += 1;
            let a = BruteForce.closest(scene, ray, &mut Silent);
            let b = bvh.closest(scene, ray, &mut Silent);
            if a.is_some() {
                row.exact_hits += 1;
            }
            if a.map(|h| (h.object, h.t)) != b.map(|h| (h.object, h.t)) {
                row.misclassified += 1;
            }
            if b.is_some_and(|h| !h.t.is_finite()) {
                row.nonfinite += 1;
            }
        }
        total_ns += time_per_item(rays.len(), opts.min_timing_s, || {
            for ray in rays {
                black_box(bvh.closest(scene, black_box(ray), &mut Silent));
            }
        }) * rays.len() as f64;
    }
    row.ns_per_test = total_ns / row.rays.max(1) as f64;
    row
}
