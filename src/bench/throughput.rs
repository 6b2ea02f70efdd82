//! Rays per second on a fixed set of rays, and the export that lets Embree trace the very same
//! rays (`tools/embree-compare/`, see book/performance.md).
//!
//! The set: the scene's camera at 2560×1440, one ray through each pixel centre (closest hit),
//! then for each primary hit one shadow ray towards the first light, spawned exactly as the
//! Whitted tracer spawns it (offset origin, t in (0, 1 − 10⁻⁴)), traced as any-hit. Only the
//! finite primitives take part (infinite planes have no Embree counterpart): the scene is traced
//! without them, on raystep's BVH with the silent observer — the render's own traversal.

use super::median_time;
use crate::accel::bvh::shape_bounds;
use crate::accel::{Accelerator, Bvh, Hit};
use crate::math::Ray;
use crate::record::Silent;
use crate::scene::{Scene, Shape};
use crate::trace::Tracer;
use crate::trace::interaction::{interact, spawn_origin};
use crate::trace::tracer::SHADOW_EPSILON;
use rayon::prelude::*;
use std::path::Path;
use std::time::{Duration, Instant};

/// The primary rays' image size.
pub const SIZE: (u32, u32) = (2560, 1440);

/// What tracing the set found: hits and the sum of their t (primary), blocked (shadow).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Found {
    hits: usize,
    t_sum: f64,
}

/// Traces each of `rays` with `trace` into its slot of `out`, on `pool`'s threads or, with none,
/// on the calling thread. The results go to a buffer allocated before the clock starts, as
/// `embree_compare.c`'s do: a fresh 70 MB vector per pass would time the first touch of its
/// memory (page faults, which two threads take in turn) along with the rays. Pieces of 1,024 to
/// 4,096 rays, as `embree_compare.c` hands out 4,096 at a time: left to itself rayon stops
/// splitting after a few halvings, and a thread done with the cheap rays of the sky could not
/// share the other's last run of several hundred thousand (see the render's tiles).
fn trace_into<T: Send>(
    rays: &[Ray<f32>],
    out: &mut [T],
    pool: Option<&rayon::ThreadPool>,
    trace: impl Fn(&Ray<f32>) -> T + Sync,
) {
    let one = |(o, r): (&mut T, &Ray<f32>)| *o = trace(r);
    match pool {
        None => out.iter_mut().zip(rays).for_each(one),
        Some(p) => p.install(|| {
            out.par_iter_mut()
                .zip(rays)
                .with_min_len(1024)
                .with_max_len(4096)
                .for_each(one)
        }),
    }
}

/// Traces `rays` for the closest hit into `out` (see [`trace_into`]).
fn closest_into(
    scene: &Scene,
    bvh: &Bvh,
    rays: &[Ray<f32>],
    out: &mut [Option<Hit>],
    pool: Option<&rayon::ThreadPool>,
) {
    trace_into(rays, out, pool, |r| bvh.closest(scene, r, &mut Silent));
}

/// Traces `rays` for any hit (occlusion) into `out` (see [`trace_into`]).
fn any_into(
    scene: &Scene,
    bvh: &Bvh,
    rays: &[Ray<f32>],
    out: &mut [bool],
    pool: Option<&rayon::ThreadPool>,
) {
    trace_into(rays, out, pool, |r| {
        bvh.any(scene, r, &mut Silent).is_some()
    });
}

/// The closest hits of `rays`, on the calling thread.
fn closest_all(scene: &Scene, bvh: &Bvh, rays: &[Ray<f32>]) -> Vec<Option<Hit>> {
    let mut out = vec![None; rays.len()];
    closest_into(scene, bvh, rays, &mut out, None);
    out
}

/// Whether each of `rays` is blocked, on the calling thread.
fn any_all(scene: &Scene, bvh: &Bvh, rays: &[Ray<f32>]) -> Vec<bool> {
    let mut out = vec![false; rays.len()];
    any_into(scene, bvh, rays, &mut out, None);
    out
}

/// The scene without its infinite planes (the set traces finite primitives only).
pub fn finite_only(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.objects.retain(|o| shape_bounds(&o.shape).is_some());
    s.camera.width = SIZE.0;
    s.camera.height = SIZE.1;
    s
}

/// The primary rays (row by row) of `scene`'s camera.
fn primary_rays(scene: &Scene, bvh: &Bvh) -> Vec<Ray<f32>> {
    let tracer = Tracer::new(scene, bvh);
    (0..scene.camera.height)
        .flat_map(|y| (0..scene.camera.width).map(move |x| (x, y)))
        .map(|(x, y)| tracer.camera.ray(x, y, [0.5, 0.5]).0)
        .collect()
}

/// One shadow ray towards the first light from each primary hit that faces it.
fn shadow_rays(scene: &Scene, rays: &[Ray<f32>], hits: &[Option<Hit>]) -> Vec<Ray<f32>> {
    let Some(light) = scene.lights.first() else {
        return vec![];
    };
    let s = &scene.settings;
    rays.iter()
        .zip(hits)
        .filter_map(|(r, h)| {
            let it = interact(scene, h.as_ref()?, r);
            let to_light = light.position - it.point;
            if to_light.dot(it.normal) <= 0.0 {
                return None;
            }
            let o = spawn_origin(s.offset, s.epsilon, &it, to_light);
            Ray::new(o, light.position - o, 0.0, 1.0 - SHADOW_EPSILON).ok()
        })
        .collect()
}

/// Node visits and primitive tests per ray (closest hits, or any hit for `shadows`), counted
/// on a pass of their own.
fn per_ray(scene: &Scene, bvh: &Bvh, rays: &[Ray<f32>], shadows: bool) -> (f64, f64) {
    let mut c = crate::record::Counter::default();
    for r in rays {
        if shadows {
            bvh.any(scene, r, &mut c);
        } else {
            bvh.closest(scene, r, &mut c);
        }
    }
    let n = rays.len().max(1) as f64;
    (c.node_visits as f64 / n, c.prim_tests as f64 / n)
}

/// The heading of a scene's figures: its name and the set's size.
fn heading(name: &str, finite: &Scene, primary: usize, shadow: usize, note: &str) {
    crate::io::outln!(
        "## {name} — {} finite primitives, {primary} primary rays ({}×{}), {shadow} shadow rays{note}",
        finite.objects.len(),
        SIZE.0,
        SIZE.1,
    );
}

fn found(hits: &[Option<Hit>]) -> Found {
    Found {
        hits: hits.iter().flatten().count(),
        t_sum: hits.iter().flatten().map(|h| f64::from(h.t)).sum(),
    }
}

fn rate(n: usize, t: Duration) -> f64 {
    n as f64 / t.as_secs_f64().max(1e-9) / 1e6
}

/// Prints raystep's rates on the set (1 and 2 threads, primary and shadow rays, medians of
/// `reps`), the build time, and optionally writes the set for `tools/embree-compare`.
pub fn throughput(scene: &Scene, reps: usize, export: Option<&Path>) -> Result<(), String> {
    let s = finite_only(scene);
    let start = Instant::now();
    let bvh = Bvh::build(&s);
    let build = start.elapsed();
    let primary = primary_rays(&s, &bvh);
    let hits = closest_all(&s, &bvh, &primary);
    let shadow = shadow_rays(&s, &primary, &hits);
    let blocked = any_all(&s, &bvh, &shadow);
    let f = found(&hits);
    // Two threads: one pool, started before the clock (as the C program's threads are started
    // per pass, but cost microseconds there).
    let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().ok();
    let (mut hit_buf, mut blocked_buf) = (hits.clone(), blocked.clone());
    let mut time = |pool: Option<&rayon::ThreadPool>, shadows: bool| {
        median_time(reps, || {
            if shadows {
                any_into(&s, &bvh, &shadow, &mut blocked_buf, pool);
            } else {
                closest_into(&s, &bvh, &primary, &mut hit_buf, pool);
            }
        })
    };
    let (p1, p2) = (time(None, false), time(two.as_ref(), false));
    let (s1, s2) = (time(None, true), time(two.as_ref(), true));
    std::hint::black_box((&hit_buf, &blocked_buf));
    let (pv, pt) = per_ray(&s, &bvh, &primary, false);
    let (sv, st) = per_ray(&s, &bvh, &shadow, true);
    heading(&scene.name, &s, primary.len(), shadow.len(), "");
    crate::io::outln!(
        "- build {:.0} ms (the tree {:.0} ms: PLOC, reinsertion, leaf collapse; then raystep's layout), SAH cost {:.1}",
        build.as_secs_f64() * 1e3,
        bvh.core_time.as_secs_f64() * 1e3,
        bvh.sah_cost()
    );
    crate::io::outln!(
        "- primary: {} hits, mean t {:.6}; {pv:.1} visits and {pt:.1} tests per ray; 1 thread {:.2} Mrays/s, 2 threads {:.2} Mrays/s ({:.2}×)",
        f.hits,
        f.t_sum / f.hits.max(1) as f64,
        rate(primary.len(), p1),
        rate(primary.len(), p2),
        p1.as_secs_f64() / p2.as_secs_f64().max(1e-9)
    );
    crate::io::outln!(
        "- shadow: {} blocked; {sv:.1} visits and {st:.1} tests per ray; 1 thread {:.2} Mrays/s, 2 threads {:.2} Mrays/s ({:.2}×)",
        blocked.iter().filter(|&&b| b).count(),
        rate(shadow.len(), s1),
        rate(shadow.len(), s2),
        s1.as_secs_f64() / s2.as_secs_f64().max(1e-9)
    );
    if let Some(path) = export {
        write_set(path, &s, &primary, &hits, &shadow, &blocked)?;
        crate::io::outln!("- wrote {}", path.display());
    }
    Ok(())
}

/// Writes the set in the little-endian layout `tools/embree-compare/embree_compare.c` reads:
/// magic `RSEMBRT1`, counts (u32: triangles, spheres, primary rays, shadow rays), triangles
/// (9 f32), spheres (centre, radius), primary rays (origin, direction), shadow rays (origin,
/// direction, t_min, t_max), then raystep's answers: per primary ray a hit byte and t (f32),
/// per shadow ray a blocked byte. Written by [`crate::io::write_atomic`], so a failed export
/// leaves no half-written file and is an error.
fn write_set(
    path: &Path,
    s: &Scene,
    primary: &[Ray<f32>],
    hits: &[Option<Hit>],
    shadow: &[Ray<f32>],
    blocked: &[bool],
) -> Result<(), String> {
    let mut tris = vec![];
    let mut spheres = vec![];
    for o in &s.objects {
        match o.shape {
            Shape::Triangle { p } => tris.extend(p.iter().flat_map(|v| v.to_array())),
            Shape::Sphere { center, radius } => {
                spheres.extend(center.to_array());
                spheres.push(radius);
            }
            Shape::Plane { .. } | Shape::AxisPlane { .. } => {}
        }
    }
    let mut out = Vec::with_capacity(64 + 4 * (tris.len() + spheres.len()) + primary.len() * 33);
    out.extend_from_slice(b"RSEMBRT1");
    for n in [
        tris.len() / 9,
        spheres.len() / 4,
        primary.len(),
        shadow.len(),
    ] {
        let n =
            u32::try_from(n).map_err(|_| "too many rays or primitives to export".to_string())?;
        out.extend_from_slice(&n.to_le_bytes());
    }
    let mut floats = |v: &[f32]| {
        v.iter()
            .for_each(|x| out.extend_from_slice(&x.to_le_bytes()))
    };
    floats(&tris);
    floats(&spheres);
    for r in primary {
        floats(&r.origin.to_array());
        floats(&r.dir.to_array());
    }
    for r in shadow {
        floats(&r.origin.to_array());
        floats(&r.dir.to_array());
        floats(&[r.t_min, r.t_max]);
    }
    for h in hits {
        out.push(u8::from(h.is_some()));
        out.extend_from_slice(&h.map_or(f32::INFINITY, |h| h.t).to_le_bytes());
    }
    out.extend(blocked.iter().map(|&b| u8::from(b)));
    // Whole or not at all, synced, written into a device or FIFO rather than replacing it, and
    // every write error reported (`/dev/full`, a full disk).
    crate::io::write_atomic(path, &out)
}

/// The BVH's three build qualities side by side on the set of [`throughput`]: build time
/// (builds alternated between qualities, medians of `reps`), obvhs's share, the tree's size,
/// depth and SAH cost, node visits per ray and single-thread rates. The trade-off a course
/// teaches: a better tree costs build time and saves traversal time.
pub fn build_qualities(scene: &Scene, reps: usize) {
    use crate::scene::BvhQuality;
    let qualities = [BvhQuality::Low, BvhQuality::Medium, BvhQuality::High];
    let mut s = finite_only(scene);
    let mut builds: Vec<Vec<(Duration, Duration)>> = vec![vec![]; qualities.len()];
    let mut trees = vec![];
    for rep in 0..reps.max(1) {
        for (i, &q) in qualities.iter().enumerate() {
            s.settings.bvh_quality = q;
            let start = Instant::now();
            let bvh = Bvh::build(&s);
            let took = start.elapsed();
            if let Some(b) = builds.get_mut(i) {
                b.push((took, bvh.core_time));
            }
            if rep == 0 {
                trees.push(bvh);
            }
        }
    }
    let Some(first) = trees.first() else {
        return;
    };
    let primary = primary_rays(&s, first);
    let hits = closest_all(&s, first, &primary);
    let shadow = shadow_rays(&s, &primary, &hits);
    let (mut hit_buf, mut blocked_buf) = (hits.clone(), vec![false; shadow.len()]);
    heading(&scene.name, &s, primary.len(), shadow.len(), ", 1 thread");
    crate::io::outln!();
    crate::io::outln!(
        "| quality | build ms | tree ms (PLOC, reinsertion, collapse) | nodes | depth | SAH cost | primary visits/ray | primary Mrays/s | shadow visits/ray | shadow Mrays/s |"
    );
    crate::io::outln!("|---|---|---|---|---|---|---|---|---|---|");
    for ((q, bvh), b) in qualities.iter().zip(&trees).zip(&mut builds) {
        b.sort();
        let (build, core) = b.get(b.len() / 2).copied().unwrap_or_default();
        let visits = |rays: &[Ray<f32>], shadows: bool| per_ray(&s, bvh, rays, shadows).0;
        let p = median_time(reps, || {
            closest_into(&s, bvh, &primary, &mut hit_buf, None);
        });
        let sh = median_time(reps, || {
            any_into(&s, bvh, &shadow, &mut blocked_buf, None);
        });
        std::hint::black_box((&hit_buf, &blocked_buf));
        crate::io::outln!(
            "| {} | {:.0} | {:.0} | {} | {} | {:.1} | {:.1} | {:.2} | {:.1} | {:.2} |",
            format!("{q:?}").to_lowercase(),
            build.as_secs_f64() * 1e3,
            core.as_secs_f64() * 1e3,
            bvh.nodes.len(),
            bvh.max_depth,
            bvh.sah_cost(),
            visits(&primary, false),
            rate(primary.len(), p),
            visits(&shadow, true),
            rate(shadow.len(), sh),
        );
    }
}
