//! Generators for the stiff-case catalogue S1–S29 of docs/NUMERICS.md: the intersection cases
//! S1–S25 ([`catalogue`]) and the Monte Carlo sampling cases S26–S29 ([`mc_catalogue`]).
//!
//! Every generated number is rounded to f32 (unless the case is *about* f64-only inputs), so the
//! f32 and f64 kernels see exactly the same inputs and share one exact reference. Where an input
//! is not representable in f32 (S2 at 1e12, S4's 1e-3 above 1e5), each precision gets the input
//! rounded to it, and its own exact reference: a kernel is judged against the truth of what it
//! was given. Leak tests (S12, S13, S18, S24) aim rays at a shared edge or vertex as
//! crates/raystep-core/tests/it/stiff.rs does (the aim rounded to f32, so the exact ray passes within an ulp of it).

use super::{Options, Primitive};
use crate::scene::Shape;
use glam::Vec3;

mod mc;
mod plane;
mod rays;
mod slab;
mod sphere;
mod triangle;

use mc::*;
use plane::*;
use rays::*;
use slab::*;
use sphere::*;
use triangle::*;

/// The geometry one ray is tested against (f64 values; see the module docs for rounding).
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    /// A sphere.
    Sphere {
        /// Centre.
        center: [f64; 3],
        /// Radius.
        radius: f64,
    },
    /// One triangle, or several sharing an edge or vertex (leak tests).
    Triangles(Vec<[[f64; 3]; 3]>),
    /// The plane X·normal = offset; `axis` when it is also the axis-aligned plane X_axis = offset
    /// (then both plane methods apply, otherwise only the general one).
    Plane {
        /// Normal.
        normal: [f64; 3],
        /// Offset c.
        offset: f64,
        /// The axis, for axis-aligned planes.
        axis: Option<usize>,
    },
    /// The closed box [lo, hi].
    Aabb {
        /// Minimum corner.
        lo: [f64; 3],
        /// Maximum corner.
        hi: [f64; 3],
    },
}

/// One ray against one geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct Query {
    /// What the ray is tested against.
    pub geometry: Geometry,
    /// Ray origin.
    pub origin: [f64; 3],
    /// Ray direction.
    pub dir: [f64; 3],
    /// Whether the inputs are exactly representable in f32 (else f32 rounds them, and gets its
    /// own reference).
    pub f32_exact: bool,
}

/// What a case checks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Hit or miss, and t, against the exact reference.
    Classify,
    /// Rays exactly at a shared edge or vertex: a leak is a ray the exact reference sees hit
    /// at least one of the triangles, while the method hits none.
    Leak,
    /// Rays at a shared edge of triangles whose vertices no longer agree (lossy compression,
    /// S24): every ray that hits none of them goes through a crack in the data — the crack rate.
    Crack,
    /// Invalid rays (NaN, ∞, zero direction): they must be rejected where rays are made.
    Reject,
}

/// How a spawned ray leaves the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpawnMode {
    /// Mirror reflection (a shadow ray towards a light on the same side behaves alike).
    Reflect,
    /// Straight on through the surface (refraction with equal indices).
    Continue,
}

/// One spawned-ray test: a primary ray hits `shape`, a ray is spawned by each offset policy, and
/// it must not hit `shape` again, and must reach `second` when there is one.
#[derive(Debug, Clone, PartialEq)]
pub struct SpawnQuery {
    /// The surface hit first (f32: this is the renderer's own code).
    pub shape: Shape,
    /// A surface the spawned ray must reach (S7's outer sphere).
    pub second: Option<Shape>,
    /// Primary ray origin.
    pub origin: Vec3,
    /// Primary ray direction.
    pub dir: Vec3,
    /// How the spawned ray leaves.
    pub mode: SpawnMode,
}

/// The rays of a case.
#[derive(Debug, Clone)]
pub enum CaseData {
    /// Kernel-level rays.
    Rays {
        /// What is checked.
        kind: Kind,
        /// The rays.
        queries: Vec<Query>,
    },
    /// Spawned rays.
    Spawn(Vec<SpawnQuery>),
    /// Whole scenes traced through the BVH and by brute force (f32, the renderer's own
    /// accelerators): the answers must be identical (S23).
    Scenes(Vec<(crate::scene::Scene, Vec<crate::math::Ray<f32>>)>),
}

/// One stiff case of the catalogue.
#[derive(Debug, Clone)]
pub struct Case {
    /// "S1" … "S25".
    pub id: &'static str,
    /// What it is, in a few words.
    pub title: &'static str,
    /// The primitive it tests.
    pub primitive: Primitive,
    /// Its rays.
    pub data: CaseData,
}

impl Case {
    /// Number of rays.
    pub fn len(&self) -> usize {
        match &self.data {
            CaseData::Rays { queries, .. } => queries.len(),
            CaseData::Spawn(q) => q.len(),
            CaseData::Scenes(s) => s.iter().map(|(_, r)| r.len()).sum(),
        }
    }
    /// Whether the case has no rays.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A small deterministic generator (SplitMix64).
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// Seeded.
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x9E37_79B9_7F4A_7C15)
    }
    /// Uniform 64 bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn f(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.f()
    }
    /// Uniform integer in [a, b].
    pub fn int(&mut self, a: i64, b: i64) -> i64 {
        a + (self.next_u64() % (b - a + 1) as u64) as i64
    }
    /// A uniformly random unit vector.
    pub fn unit(&mut self) -> [f64; 3] {
        loop {
            let v = [
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            ];
            let l2 = dot(v, v);
            if l2 > 1e-4 && l2 <= 1.0 {
                return scale(v, 1.0 / l2.sqrt());
            }
        }
    }
    fn ints(&mut self, a: i64, b: i64) -> [f64; 3] {
        [
            self.int(a, b) as f64,
            self.int(a, b) as f64,
            self.int(a, b) as f64,
        ]
    }
}

fn r32(x: f64) -> f64 {
    x as f32 as f64
}
fn v32(v: [f64; 3]) -> [f64; 3] {
    [r32(v[0]), r32(v[1]), r32(v[2])]
}
fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: [f64; 3]) -> [f64; 3] {
    scale(a, 1.0 / dot(a, a).sqrt())
}
/// Two unit vectors completing `w` to an orthonormal basis.
fn basis(w: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let h = if w[0].abs() < 0.6 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let e1 = unit(cross(w, h));
    (e1, cross(w, e1))
}
fn is_f32(v: [f64; 3]) -> bool {
    v32(v) == v
}
fn geometry_f32(g: &Geometry) -> bool {
    match g {
        Geometry::Sphere { center, radius } => is_f32(*center) && r32(*radius) == *radius,
        Geometry::Triangles(ts) => ts.iter().all(|t| t.iter().all(|p| is_f32(*p))),
        Geometry::Plane { normal, offset, .. } => is_f32(*normal) && r32(*offset) == *offset,
        Geometry::Aabb { lo, hi } => is_f32(*lo) && is_f32(*hi),
    }
}
fn query(geometry: Geometry, origin: [f64; 3], dir: [f64; 3]) -> Query {
    let f32_exact = geometry_f32(&geometry) && is_f32(origin) && is_f32(dir);
    Query {
        geometry,
        origin,
        dir,
        f32_exact,
    }
}

/// The scales a case runs at: all of them, or for the quick suite the first, a middle one and the
/// last.
fn pick<T: Copy>(opts: &Options, all: &[T]) -> Vec<T> {
    if !opts.quick || all.len() <= 3 {
        return all.to_vec();
    }
    vec![all[0], all[all.len() / 2], all[all.len() - 1]]
}

fn rays(id: &'static str, title: &'static str, p: Primitive, kind: Kind, q: Vec<Query>) -> Case {
    Case {
        id,
        title,
        primitive: p,
        data: CaseData::Rays { kind, queries: q },
    }
}

/// Every case of the catalogue, generated for `opts` (deterministic in `opts.seed`).
pub fn catalogue(opts: &Options) -> Vec<Case> {
    let n = opts.rays.max(1);
    let mut rng = Rng::new(opts.seed);
    let mut out = vec![
        far_sphere(
            "S1",
            "far unit sphere, 1e2…1e4 away",
            opts,
            &mut rng,
            n,
            &[1e2, 1e3, 4100.0, 1e4],
        ),
        far_sphere(
            "S2",
            "far unit sphere, 1e8…1e12 away",
            opts,
            &mut rng,
            n,
            &[1e8, 1e10, 1e12],
        ),
        ground_sphere(
            "S3",
            "huge sphere, origin just above",
            opts,
            &mut rng,
            n,
            &[(1e2, 1.0), (1e3, 1e-1), (1e4, 1e-1), (1e5, 1e-2)],
        ),
        ground_sphere(
            "S4",
            "below the precision floor (R 1e5, h 1e-3)",
            opts,
            &mut rng,
            n,
            &[(1e5, 1e-3)],
        ),
        on_sphere(opts, &mut rng, n),
        tangent_sphere(opts, &mut rng, n),
        inside_sphere(opts, &mut rng, n),
        plane_parallel(&mut rng, n),
        plane_grazing(opts, &mut rng, n),
        plane_far(&mut rng, n),
        edge_leaks(
            "S12",
            "rays exactly at a shared edge",
            opts,
            &mut rng,
            n,
            &[(0.0, 1e-3), (0.0, 1.0), (0.0, 1e3), (0.0, 1e5)],
            false,
        ),
        vertex_leaks(
            "S13",
            "rays exactly at a shared vertex (fan of 6)",
            opts,
            &mut rng,
            n,
            false,
        ),
        triangle_slopes(opts, &mut rng, n),
        triangle_degenerate(&mut rng, n),
        triangle_tiny(opts, &mut rng, n),
        triangle_needle(&mut rng, n),
        edge_leaks(
            "S18",
            "shared edges at coordinates 1e6…1e8",
            opts,
            &mut rng,
            n,
            &[(1e6, 10.0), (1e7, 100.0), (1e8, 1000.0)],
            false,
        ),
        box_signed_zero(&mut rng, n),
        box_near_parallel(opts, &mut rng, n),
        box_flat(&mut rng, n),
        edge_leaks(
            "S24",
            "shared edges after f16 edge compression",
            opts,
            &mut rng,
            n,
            &[(0.0, 1.0)],
            true,
        ),
        vertex_leaks(
            "S24",
            "shared vertices after f16 edge compression",
            opts,
            &mut rng,
            n,
            true,
        ),
    ];
    out.push(bvh_scenes(&mut rng, n));
    out.extend(invalid_rays());
    out.push(spawn_s7(&mut rng, n));
    out.push(spawn_s19(opts, &mut rng, n));
    out
}

/// The Monte Carlo cases S26–S29, generated for `opts` (deterministic in `opts.seed`, from a
/// generator of their own: adding them left S1–S25's rays as they were).
pub fn mc_catalogue(opts: &Options) -> Vec<crate::stability::mc::McCase> {
    let n = opts.rays.max(1);
    let mut rng = Rng::new(opts.seed ^ 0x4D43_5F53_3236);
    vec![
        sphere_lights(opts, &mut rng, n),
        ggx_near_mirror(opts, &mut rng, n),
        grazing(opts, &mut rng, n),
        emitter_areas(opts, &mut rng, n),
    ]
}
