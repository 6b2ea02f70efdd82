//! Generators for the stiff-case catalogue S1–S25 of docs/NUMERICS.md.
//!
//! Every generated number is rounded to f32 (unless the case is *about* f64-only inputs), so the
//! f32 and f64 kernels see exactly the same inputs and share one exact reference. Where an input
//! is not representable in f32 (S2 at 1e12, S4's 1e-3 above 1e5), each precision gets the input
//! rounded to it, and its own exact reference: a kernel is judged against the truth of what it
//! was given. Leak tests (S12, S13, S18, S24) aim rays at a shared edge or vertex as
//! tests/stiff.rs does (the aim rounded to f32, so the exact ray passes within an ulp of it).

use super::{Options, Primitive};
use crate::scene::Shape;
use glam::Vec3;

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

fn far_sphere(
    id: &'static str,
    title: &'static str,
    opts: &Options,
    rng: &mut Rng,
    n: usize,
    distances: &[f64],
) -> Case {
    let mut q = vec![];
    for dist in pick(opts, distances) {
        for _ in 0..n {
            // Orthographic rays along w across a unit sphere `dist` away: origins spread over
            // ±1.3 radii, so about half the rays hit.
            let w = rng.unit();
            let (e1, e2) = basis(w);
            let center = v32(scale(w, dist));
            let o = v32(add(
                scale(e1, rng.range(-1.3, 1.3)),
                scale(e2, rng.range(-1.3, 1.3)),
            ));
            q.push(query(
                Geometry::Sphere {
                    center,
                    radius: 1.0,
                },
                o,
                v32(w),
            ));
        }
    }
    rays(id, title, Primitive::Sphere, Kind::Classify, q)
}

fn ground_sphere(
    id: &'static str,
    title: &'static str,
    opts: &Options,
    rng: &mut Rng,
    n: usize,
    sizes: &[(f64, f64)],
) -> Case {
    let mut q = vec![];
    for (big_r, h) in pick(opts, sizes) {
        for _ in 0..n {
            // The sphere's top is at y = 0, the origin h above it; rays go downward at slopes
            // from steep to grazing. Inputs are not rounded to f32 here: f32 rounds h away at
            // the floor (S4), and gets its own reference.
            let center = [0.0, -big_r, 0.0];
            let o = [rng.range(-0.5, 0.5) * h, h, rng.range(-0.5, 0.5) * h];
            let d = [
                rng.range(-1.0, 1.0),
                -rng.range(0.02, 1.0),
                rng.range(-1.0, 1.0),
            ];
            q.push(query(
                Geometry::Sphere {
                    center,
                    radius: big_r,
                },
                o,
                d,
            ));
        }
    }
    rays(id, title, Primitive::Sphere, Kind::Classify, q)
}

fn on_sphere(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    // Points exactly on spheres: Pythagorean quadruples (3,4,0)/5, (1,2,2)/3, (2,3,6)/7 scaled by
    // powers of two, around integer centres: f·f − r² is exactly 0.
    let triples: [([f64; 3], f64); 3] =
        [([3., 4., 0.], 5.), ([1., 2., 2.], 3.), ([2., 3., 6.], 7.)];
    let mut q = vec![];
    for k in pick(opts, &[-10, 0, 10, 20]) {
        let s = 2f64.powi(k);
        for _ in 0..n {
            let (p, r) = triples[rng.int(0, 2) as usize];
            let mut p = p;
            for c in p.iter_mut() {
                if rng.f() < 0.5 {
                    *c = -*c;
                }
            }
            let rot = rng.int(0, 2) as usize;
            p.rotate_left(rot);
            let center = scale(rng.ints(-100, 100), s);
            let o = add(center, scale(p, s));
            q.push(query(
                Geometry::Sphere {
                    center,
                    radius: r * s,
                },
                o,
                v32(rng.unit()),
            ));
        }
    }
    rays(
        "S5",
        "origin exactly on the surface",
        Primitive::Sphere,
        Kind::Classify,
        q,
    )
}

fn tangent_sphere(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for delta in pick(opts, &[1e-3, 1e-6, 1e-9]) {
        for _ in 0..n {
            // Rays passing at ρ = r(1 ± δ) from the centre.
            let center = v32(scale(rng.unit(), rng.range(0.0, 10.0)));
            let r = r32(rng.range(0.5, 2.0));
            let w = rng.unit();
            let (e1, _) = basis(w);
            let rho = r * (1.0 + if rng.f() < 0.5 { delta } else { -delta });
            let o = v32(add(center, add(scale(w, -5.0 * r), scale(e1, rho))));
            q.push(query(Geometry::Sphere { center, radius: r }, o, v32(w)));
        }
    }
    for _ in 0..n / 4 + 1 {
        // The origin at the tangent point, the direction tangent: q = 0 (0/0 in c/q).
        let mut o = [0.0, 0.0, 0.0];
        let axis = rng.int(0, 2) as usize;
        o[axis] = if rng.f() < 0.5 { 1.0 } else { -1.0 };
        let mut d = v32(rng.unit());
        d[axis] = 0.0;
        if d == [0.0; 3] {
            d[(axis + 1) % 3] = 1.0;
        }
        q.push(query(
            Geometry::Sphere {
                center: [0.0; 3],
                radius: 1.0,
            },
            o,
            d,
        ));
    }
    rays(
        "S6",
        "tangent rays ρ = r(1 ± δ), δ 1e-3…1e-9; q = 0",
        Primitive::Sphere,
        Kind::Classify,
        q,
    )
}

fn inside_sphere(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    // Origin just inside a glass sphere (depth ε·r), rays at the critical angle of glass
    // (n = 1.5: 41.81°) to the normal, ±1°: the exit root, never the entry one.
    let mut q = vec![];
    for eps in pick(opts, &[1e-2, 1e-4, 1e-6]) {
        for _ in 0..n {
            let center = v32(scale(rng.unit(), rng.range(0.0, 10.0)));
            let r = r32(rng.range(0.5, 2.0));
            let nrm = rng.unit();
            let (t1, _) = basis(nrm);
            let theta = (41.81 + rng.range(-1.0, 1.0)).to_radians();
            let d = add(scale(nrm, theta.cos()), scale(t1, theta.sin()));
            let o = v32(add(center, scale(nrm, r * (1.0 - eps))));
            q.push(query(Geometry::Sphere { center, radius: r }, o, v32(d)));
        }
    }
    rays(
        "S8",
        "origin inside, rays at the critical angle",
        Primitive::Sphere,
        Kind::Classify,
        q,
    )
}

fn plane_parallel(rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for k in 0..n {
        // y = c, direction with d_y = +0 or −0, origin on the plane or 1 above: a miss, never NaN.
        let c = if k % 2 == 0 { 0.0 } else { 1.0 };
        let dy = if (k / 2) % 2 == 0 { 0.0 } else { -0.0 };
        let oy = if (k / 4) % 2 == 0 { c } else { c + 1.0 };
        let o = [r32(rng.range(-5.0, 5.0)), oy, r32(rng.range(-5.0, 5.0))];
        let d = [r32(rng.range(-1.0, 1.0)), dy, 1.0];
        q.push(query(
            Geometry::Plane {
                normal: [0.0, 1.0, 0.0],
                offset: c,
                axis: Some(1),
            },
            o,
            d,
        ));
    }
    rays(
        "S9",
        "ray parallel to a plane, d·n = ±0",
        Primitive::Plane,
        Kind::Classify,
        q,
    )
}

fn plane_grazing(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for slope in pick(opts, &[1e-7, 1e-20, 1e-40]) {
        for _ in 0..n {
            // Origin 0.5…2 above y = 0, falling at `slope`: t ≈ h/slope, beyond f32's range at
            // 1e-40 (then a clean miss is the right f32 answer).
            let o = [0.0, r32(rng.range(0.5, 2.0)), 0.0];
            let d = [
                1.0,
                r32(-slope * rng.range(1.0, 2.0)),
                r32(rng.range(-0.5, 0.5)),
            ];
            q.push(query(
                Geometry::Plane {
                    normal: [0.0, 1.0, 0.0],
                    offset: 0.0,
                    axis: Some(1),
                },
                o,
                d,
            ));
        }
    }
    rays(
        "S10",
        "grazing slopes 1e-7, 1e-20, 1e-40",
        Primitive::Plane,
        Kind::Classify,
        q,
    )
}

fn plane_far(rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    let p = [1e6, 1e6, 1e6];
    for k in 0..n {
        if k % 2 == 0 {
            // General plane through (1e6, 1e6, 1e6) with a tilted normal, origin 1e-3 above
            // (not representable in f32 at 1e6: f32 gets its own reference).
            let nrm = v32(rng.unit());
            let offset = r32(dot(p, nrm));
            let o = add(add(p, scale(nrm, 1e-3)), scale(rng.unit(), 1e-3));
            let mut d = rng.unit();
            if dot(d, nrm) > 0.0 {
                d = scale(d, -1.0);
            }
            q.push(query(
                Geometry::Plane {
                    normal: nrm,
                    offset,
                    axis: None,
                },
                o,
                v32(d),
            ));
        } else {
            // The axis-aligned plane y = 1e6, origin 1e-3 above.
            let o = [rng.range(-1.0, 1.0), 1e6 + 1e-3, rng.range(-1.0, 1.0)];
            let d = [
                rng.range(-1.0, 1.0),
                -rng.range(0.05, 1.0),
                rng.range(-1.0, 1.0),
            ];
            q.push(query(
                Geometry::Plane {
                    normal: [0.0, 1.0, 0.0],
                    offset: 1e6,
                    axis: Some(1),
                },
                o,
                v32(d),
            ));
        }
    }
    rays(
        "S11",
        "plane through (1e6,1e6,1e6), origin 1e-3 above",
        Primitive::Plane,
        Kind::Classify,
        q,
    )
}

/// Rounds each component of `v` to 11 significant bits (the mantissa of an f16; the exponent
/// range is not modelled): the lossy edge storage of compressed BVH triangles (docs/NUMERICS.md S24).
fn f16ish(v: [f64; 3]) -> [f64; 3] {
    v.map(|x| {
        if x == 0.0 {
            return 0.0;
        }
        let e = x.abs().log2().floor();
        let step = 2f64.powf(e - 10.0);
        (x / step).round() * step
    })
}

/// Stores a triangle as P0 plus f16 edges (each triangle relative to its own first vertex, so
/// shared vertices no longer agree).
fn compress(t: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [
        t[0],
        add(t[0], f16ish(sub(t[1], t[0]))),
        add(t[0], f16ish(sub(t[2], t[0]))),
    ]
}

/// A random f32 vector in [−1, 1)³.
fn rvec(rng: &mut Rng) -> Vec3 {
    Vec3::new(
        rng.range(-1.0, 1.0) as f32,
        rng.range(-1.0, 1.0) as f32,
        rng.range(-1.0, 1.0) as f32,
    )
}

fn f64x3(v: Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

#[allow(clippy::too_many_arguments)]
fn edge_leaks(
    id: &'static str,
    title: &'static str,
    opts: &Options,
    rng: &mut Rng,
    n: usize,
    scales: &[(f64, f64)],
    compressed: bool,
) -> Case {
    let mut q = vec![];
    for (base, s) in pick(opts, scales) {
        let base = Vec3::new(base as f32, (base * 0.75) as f32, (base * 0.5) as f32);
        let s = s as f32;
        for _ in 0..n {
            // As in tests/stiff.rs (and docs/NUMERICS.md's measurement): triangles (A, B, C1) and
            // (B, A, C2) share the edge A–B; the ray is aimed at A + r(B − A), computed in f32 —
            // on the edge up to that rounding, so the exact reference always hits at least one
            // of the two, and a ray that hits neither is a leak.
            let a = base + rvec(rng) * s;
            let b = base + rvec(rng) * s;
            let e = b - a;
            let side = e.cross(rvec(rng));
            if e == Vec3::ZERO || side.length() == 0.0 {
                continue;
            }
            let mid = (a + b) * 0.5;
            let side = side.normalize() * s;
            let (c1, c2) = (mid + side, mid - side);
            let target = a + e * rng.f() as f32;
            let normal = e.cross(c1 - a).normalize();
            let sign = if rng.f() < 0.5 { 1.0 } else { -1.0 };
            let origin = target + (normal * (2.0 * sign) + rvec(rng) * 0.5) * s;
            let d = target - origin;
            let mut tris = vec![
                [f64x3(a), f64x3(b), f64x3(c1)],
                [f64x3(b), f64x3(a), f64x3(c2)],
            ];
            if compressed {
                tris = tris.into_iter().map(compress).collect();
            }
            q.push(query(Geometry::Triangles(tris), f64x3(origin), f64x3(d)));
        }
    }
    let kind = if compressed { Kind::Crack } else { Kind::Leak };
    rays(id, title, Primitive::Triangle, kind, q)
}

fn vertex_leaks(
    id: &'static str,
    title: &'static str,
    opts: &Options,
    rng: &mut Rng,
    n: usize,
    compressed: bool,
) -> Case {
    let mut q = vec![];
    let scales: &[f32] = if compressed {
        &[1.0]
    } else {
        &[1e-3, 1.0, 1e3, 1e5]
    };
    for s in pick(opts, scales) {
        for _ in 0..n {
            // A fan of 6 triangles around V (as in tests/stiff.rs); rays aimed at V.
            let v = rvec(rng) * s;
            let nrm = rvec(rng);
            if nrm.length() < 1e-3 {
                continue;
            }
            let nrm = nrm.normalize();
            let t1 = nrm.any_orthonormal_vector();
            let t2 = nrm.cross(t1);
            let rim: Vec<Vec3> = (0..6)
                .map(|k| {
                    let ang = k as f32 * std::f32::consts::TAU / 6.0;
                    v + (t1 * ang.cos() + t2 * ang.sin()) * s
                })
                .collect();
            let sign = if rng.f() < 0.5 { 1.0 } else { -1.0 };
            let origin = v + (nrm * (2.0 * sign) + rvec(rng) * 0.5) * s;
            let mut tris: Vec<[[f64; 3]; 3]> = (0..6)
                .map(|k| [f64x3(v), f64x3(rim[k]), f64x3(rim[(k + 1) % 6])])
                .collect();
            if compressed {
                tris = tris.into_iter().map(compress).collect();
            }
            q.push(query(
                Geometry::Triangles(tris),
                f64x3(origin),
                f64x3(v - origin),
            ));
        }
    }
    let kind = if compressed { Kind::Crack } else { Kind::Leak };
    rays(id, title, Primitive::Triangle, kind, q)
}

fn triangle_slopes(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    let tri = [[-1.0, -1.0, 0.0], [2.0, -1.0, 0.0], [-1.0, 2.0, 0.0]];
    let mut q = vec![];
    for slope in pick(opts, &[1e-3, 1e-6, 1e-9, 0.0]) {
        for _ in 0..n {
            // Rays at `slope` to the plane z = 0 aimed at an interior point; slope 0: in the plane.
            let p = [rng.range(-0.5, 0.5), rng.range(-0.5, 0.5), 0.0];
            let phi = rng.range(0.0, std::f64::consts::TAU);
            let len = 3.0;
            let o = v32([p[0] - len * phi.cos(), p[1] - len * phi.sin(), len * slope]);
            let d = v32(sub(p, o));
            q.push(query(Geometry::Triangles(vec![tri]), o, d));
        }
    }
    rays(
        "S14",
        "rays at slopes 1e-3…1e-9 to the plane; in-plane",
        Primitive::Triangle,
        Kind::Classify,
        q,
    )
}

fn triangle_degenerate(rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for at in [1.0, 1e7] {
        for k in 0..n {
            let a = v32(add([at, at, at], rng.ints(-4, 4)));
            let b = v32(add(a, rng.ints(-4, 4)));
            let tri = match k % 3 {
                0 => [a, b, v32(add(a, scale(sub(b, a), 2.0)))],
                1 => [a, a, b],
                _ => [a, a, a],
            };
            let o = v32(add(a, scale(rng.unit(), 10.0)));
            let target = add(a, scale(sub(b, a), rng.range(0.0, 1.0)));
            q.push(query(
                Geometry::Triangles(vec![tri]),
                o,
                v32(sub(target, o)),
            ));
        }
    }
    rays(
        "S15",
        "degenerate triangles (collinear, repeated vertices), at 1 and 1e7",
        Primitive::Triangle,
        Kind::Classify,
        q,
    )
}

fn triangle_tiny(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for s in pick(opts, &[1e-3, 1e-8, 1e-15, 1e-25]) {
        for _ in 0..n {
            // A triangle of edge ≈ s near the origin, seen from distance 1 along z, aimed at an
            // interior point.
            let p = [
                v32([0.0, 0.0, 0.0]),
                v32([s * rng.range(0.5, 1.0), 0.0, 0.0]),
                v32([s * rng.range(-0.2, 0.2), s * rng.range(0.5, 1.0), 0.0]),
            ];
            let (b1, b2) = (rng.range(0.05, 0.45), rng.range(0.05, 0.45));
            let target = add(scale(sub(p[1], p[0]), b1), scale(sub(p[2], p[0]), b2));
            let o = v32([rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), -1.0]);
            q.push(query(Geometry::Triangles(vec![p]), o, v32(sub(target, o))));
        }
    }
    rays(
        "S16",
        "tiny triangles, edges 1e-3…1e-25",
        Primitive::Triangle,
        Kind::Classify,
        q,
    )
}

fn triangle_needle(rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for _ in 0..n {
        // Aspect 1e6: length 1, width 1e-6, randomly oriented; rays aimed at its bounding box.
        let w = rng.unit();
        let (e1, e2) = basis(w);
        let c = scale(rng.unit(), 2.0);
        let p = [
            v32(c),
            v32(add(c, e1)),
            v32(add(c, add(scale(e1, 0.5), scale(e2, 1e-6)))),
        ];
        let target = add(
            c,
            add(
                scale(e1, rng.range(0.0, 1.0)),
                scale(e2, rng.range(-0.5e-6, 1.5e-6)),
            ),
        );
        let o = v32(add(target, scale(add(w, scale(rng.unit(), 0.5)), 3.0)));
        q.push(query(Geometry::Triangles(vec![p]), o, v32(sub(target, o))));
    }
    rays(
        "S17",
        "needle triangles (aspect 1e6)",
        Primitive::Triangle,
        Kind::Classify,
        q,
    )
}

fn signed_zero(rng: &mut Rng) -> f64 {
    if rng.f() < 0.5 { 0.0 } else { -0.0 }
}

fn box_signed_zero(rng: &mut Rng, n: usize) -> Case {
    let (lo, hi) = ([-1.0; 3], [1.0; 3]);
    let mut q = vec![];
    for k in 0..n {
        let sgn = |r: &mut Rng| if r.f() < 0.5 { 1.0 } else { -1.0 };
        let (o, d) = match k % 3 {
            // Origin on the face x = ±1, direction in the face plane (d_x = ±0).
            0 => (
                [
                    sgn(rng),
                    r32(rng.range(-0.9, 0.9)),
                    r32(rng.range(-0.9, 0.9)),
                ],
                [signed_zero(rng), r32(rng.range(-1.0, 1.0)), 1.0],
            ),
            // Along an edge: x = ±1, y = ±1, direction along z.
            1 => (
                [sgn(rng), sgn(rng), r32(rng.range(-5.0, -2.0))],
                [signed_zero(rng), signed_zero(rng), 1.0],
            ),
            // From outside towards a corner, along the diagonal.
            _ => {
                let c = [sgn(rng), sgn(rng), sgn(rng)];
                (scale(c, 3.0), scale(c, -1.0))
            }
        };
        q.push(query(Geometry::Aabb { lo, hi }, o, d));
    }
    rays(
        "S20",
        "box: origin on a face, along an edge, at a corner; d = ±0",
        Primitive::Box,
        Kind::Classify,
        q,
    )
}

fn box_near_parallel(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    let (lo, hi) = ([-1.0; 3], [1.0; 3]);
    let mut q = vec![];
    for tiny in pick(opts, &[1e-9, 1e-20, 1e-38, 1e-45]) {
        for _ in 0..n {
            let o = [r32(rng.range(-0.9, 0.9)), r32(rng.range(-0.9, 0.9)), -5.0];
            let d = [r32(tiny * rng.range(-1.0, 1.0)), signed_zero(rng), 1.0];
            q.push(query(Geometry::Aabb { lo, hi }, o, d));
        }
    }
    rays(
        "S21",
        "box, near-parallel d = (1e-9…1e-45, 0, 1)",
        Primitive::Box,
        Kind::Classify,
        q,
    )
}

fn box_flat(rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for _ in 0..n {
        // A zero-thickness box (the quad z = 0.25), oblique rays through its interior.
        let (lo, hi) = ([-1.0, -1.0, 0.25], [1.0, 1.0, 0.25]);
        let target = [rng.range(-0.9, 0.9), rng.range(-0.9, 0.9), 0.25];
        let o = v32(add(
            target,
            scale(add([0.0, 0.0, -1.0], scale(rng.unit(), 0.7)), 3.0),
        ));
        q.push(query(Geometry::Aabb { lo, hi }, o, v32(sub(target, o))));
    }
    rays(
        "S22",
        "zero-thickness box, oblique rays",
        Primitive::Box,
        Kind::Classify,
        q,
    )
}

fn invalid_rays() -> Vec<Case> {
    let bad: Vec<([f64; 3], [f64; 3])> = vec![
        ([f64::NAN, 0.0, -5.0], [0.0, 0.0, 1.0]),
        ([0.0, f64::INFINITY, -5.0], [0.0, 0.0, 1.0]),
        ([0.0, 0.0, -5.0], [f64::NAN, 0.0, 1.0]),
        ([0.0, 0.0, -5.0], [0.0, f64::NEG_INFINITY, 1.0]),
        ([0.0, 0.0, -5.0], [0.0, 0.0, 0.0]),
        ([0.0, 0.0, -5.0], [-0.0, 0.0, -0.0]),
        // d·d underflows to zero in both precisions.
        ([0.0, 0.0, -5.0], [0.0, 0.0, 1e-200]),
        // d·d overflows in both precisions.
        ([0.0, 0.0, -5.0], [0.0, 0.0, 1e200]),
    ];
    let geos = [
        (
            Primitive::Sphere,
            Geometry::Sphere {
                center: [0.0; 3],
                radius: 1.0,
            },
        ),
        (
            Primitive::Triangle,
            Geometry::Triangles(vec![[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]]]),
        ),
        (
            Primitive::Plane,
            Geometry::Plane {
                normal: [0.0, 0.0, 1.0],
                offset: 0.0,
                axis: Some(2),
            },
        ),
        (
            Primitive::Box,
            Geometry::Aabb {
                lo: [-1.0; 3],
                hi: [1.0; 3],
            },
        ),
    ];
    geos.into_iter()
        .map(|(p, g)| {
            let q = bad
                .iter()
                .map(|&(o, d)| Query {
                    geometry: g.clone(),
                    origin: o,
                    dir: d,
                    f32_exact: false,
                })
                .collect();
            rays(
                "S25",
                "NaN, ±∞, zero, under/overflowing rays",
                p,
                Kind::Reject,
                q,
            )
        })
        .collect()
}

fn vec3(v: [f64; 3]) -> Vec3 {
    Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)
}

fn spawn_s7(rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for _ in 0..n {
        // Concentric spheres r = 1 and 1 + 4e-5; a ray from inside the inner one leaves it and
        // must hit the outer one 4e-5 further on (a fixed ε = 1e-4 jumps over it).
        let c = vec3(scale(rng.unit(), rng.range(0.0, 2.0)));
        let o = c + vec3(scale(rng.unit(), rng.range(0.0, 0.5)));
        q.push(SpawnQuery {
            shape: Shape::Sphere {
                center: c,
                radius: 1.0,
            },
            second: Some(Shape::Sphere {
                center: c,
                radius: 1.0 + 4e-5,
            }),
            origin: o,
            dir: vec3(rng.unit()),
            mode: SpawnMode::Continue,
        });
    }
    Case {
        id: "S7",
        title: "concentric spheres 4e-5 apart, ray leaving the inner",
        primitive: Primitive::Spawn,
        data: CaseData::Spawn(q),
    }
}

fn spawn_s19(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for s in pick(opts, &[1e-3, 1.0, 1e3, 1e6]) {
        for k in 0..n {
            // A primary ray meets a sphere, plane or triangle at scale s at 1°…89° to the
            // surface; the reflected ray must not hit the surface again.
            let theta = rng.range(1.0, 89.0).to_radians();
            let nrm = rng.unit();
            let (t1, t2) = basis(nrm);
            let incoming = add(scale(nrm, -theta.sin()), scale(t1, theta.cos()));
            let p = scale(rng.unit(), s * rng.range(0.0, 3.0));
            let shape = match k % 3 {
                0 => Shape::Sphere {
                    center: vec3(sub(p, scale(nrm, s))),
                    radius: s as f32,
                },
                1 => {
                    let n32 = vec3(nrm).normalize();
                    Shape::Plane {
                        normal: n32,
                        offset: n32.dot(vec3(p)),
                    }
                }
                _ => Shape::Triangle {
                    p: [
                        vec3(add(p, scale(add(t1, t2), -s))),
                        vec3(add(p, scale(t1, 2.0 * s))),
                        vec3(add(p, scale(t2, 2.0 * s))),
                    ],
                },
            };
            let origin = vec3(sub(p, scale(incoming, 3.0 * s)));
            q.push(SpawnQuery {
                shape,
                second: None,
                origin,
                dir: vec3(incoming),
                mode: SpawnMode::Reflect,
            });
        }
    }
    Case {
        id: "S19",
        title: "reflected rays from spheres, planes, triangles at 1e-3…1e6, 1°…89°",
        primitive: Primitive::Spawn,
        data: CaseData::Spawn(q),
    }
}

fn toml_vec(v: Vec3) -> String {
    format!("[{:e}, {:e}, {:e}]", v.x, v.y, v.z)
}

fn bvh_scenes(rng: &mut Rng, n: usize) -> Case {
    use crate::math::Ray;
    let mut out = vec![];
    // A random scene of spheres and triangles scaled by 1e-5: no fixed t_min may creep into
    // the traversal.
    let s = 1e-5f32;
    let mut t = format!("[[plane]]\naxis = \"y\"\noffset = {:e}\n", -12.0 * s);
    for _ in 0..40 {
        t += &format!(
            "[[sphere]]\ncenter = {}\nradius = {:e}\n",
            toml_vec(rvec(rng) * 10.0 * s),
            rng.range(0.1, 1.5) as f32 * s
        );
        let c = rvec(rng) * 10.0;
        let p: Vec<Vec3> = (0..3).map(|_| (c + rvec(rng) * 2.0) * s).collect();
        t += &format!(
            "[[triangle]]\nvertices = [{}, {}, {}]\n",
            toml_vec(p[0]),
            toml_vec(p[1]),
            toml_vec(p[2])
        );
    }
    if let Ok(scene) = crate::scene::load_str(&t, "s23-tiny.toml", None) {
        let rays = (0..n)
            .filter_map(|_| {
                let o = rvec(rng) * 20.0 * s;
                let target = rvec(rng) * 10.0 * s;
                Ray::infinite(o, target - o).ok()
            })
            .collect();
        out.push((scene, rays));
    }
    // Two spheres whose surfaces are 5e-5 apart; rays from just inside the inner one outwards.
    let t = "[[sphere]]\nradius = 1\n[[sphere]]\nradius = 1.00005\n[[sphere]]\ncenter = [5, 0, 0]\n\
             [[sphere]]\ncenter = [-5, 0, 0]\n";
    if let Ok(scene) = crate::scene::load_str(t, "s23-close.toml", None) {
        let rays = (0..n)
            .filter_map(|_| {
                let d = rvec(rng);
                let o = d.normalize_or_zero() * 0.999;
                Ray::new(o, d, 0.0, f32::INFINITY).ok()
            })
            .collect();
        out.push((scene, rays));
    }
    Case {
        id: "S23",
        title: "BVH against brute force: scene scaled by 1e-5; surfaces 5e-5 apart",
        primitive: Primitive::Box,
        data: CaseData::Scenes(out),
    }
}
