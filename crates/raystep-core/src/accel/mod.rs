//! Finding the closest hit (and, for shadow rays, any hit), observed.
//!
//! [`test_object`] is the one place a primitive is tested: it runs the scene's chosen kernel and
//! hands the full test record to the observer. [`BruteForce`] is the lecture notes' naive loop
//! (docs/SOURCES.md) — "for each ray, for each primitive" — behind the [`Accelerator`] trait that
//! the BVH also implements.

/// The two builds of an accelerator's queries, as the BVH's have them: `$t`'s inherent
/// `closest_in` and `any_in` (`#[inline(always)]`, generic over the observer) compiled for the
/// baseline x86-64 and again for AVX2 + FMA, and `closest_fastest` / `any_fastest`, which take
/// the second when the CPU has both (see [`avx2_fma`]). The answers are the same bit for bit (the
/// only fused operations are the triangle test's explicit `mul_add`s, correctly rounded either
/// way; see [`Bvh`]'s `Accelerator` impl), but the baseline build calls `fmaf` six times a
/// triangle test and saves and reloads its registers around each call: brute force over the
/// soft-shadow scene's triangle floor ran 11.7 % more instructions in that build, the bounding
/// spheres over the Cornell box 5.2 %. (The grid, given the same two builds, ran 8.5 % more
/// instructions in the second: it has only the first.)
macro_rules! two_builds {
    ($t:ty) => {
        impl $t {
            /// `closest_in` compiled for AVX2 and FMA.
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx2,fma")]
            fn closest_avx2<O: $crate::record::Observer>(
                &self,
                scene: &$crate::scene::Scene,
                ray: &$crate::math::Ray<f32>,
                obs: &mut O,
            ) -> Option<$crate::accel::Hit> {
                self.closest_in(scene, ray, obs)
            }

            /// `any_in` compiled for AVX2 and FMA.
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx2,fma")]
            fn any_avx2<O: $crate::record::Observer>(
                &self,
                scene: &$crate::scene::Scene,
                ray: &$crate::math::Ray<f32>,
                obs: &mut O,
            ) -> Option<$crate::accel::Hit> {
                self.any_in(scene, ray, obs)
            }

            /// `closest_in` in the fastest build this CPU runs.
            #[inline]
            #[allow(unsafe_code)] // calling a #[target_feature] function, after checking the CPU
            fn closest_fastest<O: $crate::record::Observer>(
                &self,
                scene: &$crate::scene::Scene,
                ray: &$crate::math::Ray<f32>,
                obs: &mut O,
            ) -> Option<$crate::accel::Hit> {
                #[cfg(target_arch = "x86_64")]
                if $crate::accel::avx2_fma() {
                    // SAFETY: the CPU has AVX2 and FMA (just checked).
                    return unsafe { self.closest_avx2(scene, ray, obs) };
                }
                self.closest_in(scene, ray, obs)
            }

            /// `any_in` in the fastest build this CPU runs.
            #[inline]
            #[allow(unsafe_code)] // calling a #[target_feature] function, after checking the CPU
            fn any_fastest<O: $crate::record::Observer>(
                &self,
                scene: &$crate::scene::Scene,
                ray: &$crate::math::Ray<f32>,
                obs: &mut O,
            ) -> Option<$crate::accel::Hit> {
                #[cfg(target_arch = "x86_64")]
                if $crate::accel::avx2_fma() {
                    // SAFETY: the CPU has AVX2 and FMA (just checked).
                    return unsafe { self.any_avx2(scene, ray, obs) };
                }
                self.any_in(scene, ray, obs)
            }
        }
    };
}

mod brute;
pub mod bvh;
pub mod grid;
pub mod spheres;
pub mod two_level;

pub use brute::BruteForce;
pub use bvh::Bvh;
pub use grid::Grid;
pub use spheres::SphereTree;
pub use two_level::TwoLevel;

use crate::math::Ray;
use crate::platform::{Duration, Instant};
use crate::record::{Observer, Step};
use crate::scene::{AccelChoice, Scene, Shape};
use crate::shapes::triangle::TriangleMethod;
use crate::shapes::{SphereMethod, SphereTest, plane, sphere, triangle};

/// A hit: which object, where along the ray, and a triangle's barycentrics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Object id.
    pub object: u32,
    /// Distance along the ray.
    pub t: f32,
    /// Barycentric u (weight of P1) for triangles, 0 otherwise.
    pub u: f32,
    /// Barycentric v (weight of P2) for triangles, 0 otherwise.
    pub v: f32,
    /// The instance the object was met through ([`crate::scene::Scene::instances`]), or
    /// [`crate::scene::NO_INSTANCE`]: `object` is then a prototype's, in object space.
    pub instance: u32,
}

/// Something that finds hits along a ray.
pub trait Accelerator: Sync {
    /// The closest hit in (t_min, t_max), reporting every test to `obs`.
    fn closest<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit>;
    /// Any hit in (t_min, t_max) — the first found (shadow rays need no more).
    fn any<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit>;
    /// A short name for reports.
    fn name(&self) -> &'static str;
    /// The top `depth` levels of the hierarchy, for diagrams (None: no hierarchy).
    fn outline(&self, _depth: u32) -> Option<Vec<crate::record::OutlineNode>> {
        None
    }
    /// The uniform grid's box and cell counts, for diagrams (None: not a grid, or a grid of no
    /// cells).
    fn grid_outline(&self) -> Option<crate::record::GridOutline> {
        None
    }
}

/// Tests object `id` with the scene's chosen method and reports the test to `obs`.
#[inline(always)]
pub fn test_object<O: Observer>(
    scene: &Scene,
    id: u32,
    ray: &Ray<f32>,
    obs: &mut O,
) -> Option<Hit> {
    let shape = &scene.objects[id as usize].shape;
    test_shape(scene, id, shape, ray, &mut PerRay::default(), obs)
}

/// What the kernels compute once per ray rather than once per test — the watertight triangle
/// test's [`Shear`](crate::shapes::triangle::Shear) — filled on first use. The values are the
/// ones each test would compute, so the answers do not change.
#[derive(Debug, Default, Clone, Copy)]
pub struct PerRay {
    shear: Option<triangle::Shear<f32>>,
}

impl PerRay {
    /// The ray's shear (every ray of one query has the same direction).
    #[inline(always)]
    pub(crate) fn shear(&mut self, ray: &Ray<f32>) -> triangle::Shear<f32> {
        *self.shear.get_or_insert_with(|| triangle::Shear::of(ray))
    }
}

/// [`test_object`] with the object's shape given (an accelerator may keep its own copy, in the
/// order it visits them).
#[inline(always)]
pub fn test_shape<O: Observer>(
    scene: &Scene,
    id: u32,
    shape: &Shape,
    ray: &Ray<f32>,
    per: &mut PerRay,
    obs: &mut O,
) -> Option<Hit> {
    let s = &scene.settings;
    match *shape {
        Shape::Sphere { center, radius } => {
            // Each method reports its own record and hands on only t: the two records are
            // never merged into one value the render would have to carry.
            let report = |test: SphereTest<f32>, obs: &mut O| {
                obs.prim_test(|| Step::Sphere {
                    object: id,
                    name: scene.object_name(id),
                    test,
                });
                test.t
            };
            let t = match s.sphere_method {
                SphereMethod::Textbook => report(sphere::textbook(ray, center, radius), obs),
                SphereMethod::Stable => report(sphere::stable(ray, center, radius), obs),
            };
            t.map(|t| Hit {
                object: id,
                t,
                u: 0.0,
                v: 0.0,
                instance: crate::scene::NO_INSTANCE,
            })
        }
        Shape::Plane { normal, offset } => {
            let test = plane::general(ray, normal, offset);
            obs.prim_test(|| Step::Plane {
                object: id,
                name: scene.object_name(id),
                test,
            });
            test.t.map(|t| Hit {
                object: id,
                t,
                u: 0.0,
                v: 0.0,
                instance: crate::scene::NO_INSTANCE,
            })
        }
        Shape::AxisPlane { axis, offset } => {
            let test = plane::axis(ray, axis, offset);
            obs.prim_test(|| Step::Plane {
                object: id,
                name: scene.object_name(id),
                test,
            });
            test.t.map(|t| Hit {
                object: id,
                t,
                u: 0.0,
                v: 0.0,
                instance: crate::scene::NO_INSTANCE,
            })
        }
        Shape::Triangle { p } => {
            let test = match s.triangle_method {
                TriangleMethod::Watertight => triangle::watertight_sheared(ray, &per.shear(ray), p),
                TriangleMethod::MollerTrumbore => triangle::moller_trumbore(ray, p),
            };
            obs.prim_test(|| triangle_step(scene, id, p, test));
            test.t.map(|t| Hit {
                object: id,
                t,
                u: test.u.unwrap_or(0.0),
                v: test.v.unwrap_or(0.0),
                instance: crate::scene::NO_INSTANCE,
            })
        }
    }
}

/// The record of a triangle test of object `id` (vertices `p`).
#[inline(always)]
pub(crate) fn triangle_step(
    scene: &Scene,
    id: u32,
    p: [glam::Vec3; 3],
    test: triangle::TriangleTest<f32>,
) -> Step {
    Step::Triangle {
        object: id,
        name: scene.object_name(id),
        vertices: p.map(|v| v.to_array()),
        test,
    }
}

/// Records that `hit` became the closest so far.
#[inline(always)]
pub fn accept<O: Observer>(scene: &Scene, hit: &Hit, previous: f32, obs: &mut O) {
    obs.step(|| Step::Accept {
        object: hit.object,
        name: scene.object_name(hit.object),
        t: hit.t,
        previous,
    });
}

/// The ray object `id` is tested with for the closest hit once `best` is the closest so far.
///
/// Ties at exactly equal t go to the lower object id, whatever order an accelerator tests in:
/// brute force tests in id order against `t < t_max`, so of two objects at the same t the first
/// (lower id) keeps it. An accelerator may meet the higher id first; so an object with a lower
/// id than the closest so far is tested against `t ≤ t_max` (`t_max` raised to the next float),
/// one with a higher id against `t < t_max` as usual. The images then agree bit for bit with
/// brute force even on exact ties (duplicated objects, meshes sharing an edge). The ray's own
/// `t_max` stays the closest t: box and sphere culling already keep a node at exactly `t_max`.
#[inline(always)]
pub fn tie_ray(r: &Ray<f32>, id: u32, best: &Option<Hit>) -> Ray<f32> {
    match best {
        Some(b) if id < b.object => Ray {
            t_max: r.t_max.next_up(),
            ..*r
        },
        _ => *r,
    }
}

/// Tests object `id` for the closest hit: a hit becomes the closest so far (recorded, and the
/// ray's t_max shrinks to it, so farther candidates fail inside the kernels).
#[inline(always)]
pub fn test_closest<O: Observer>(
    scene: &Scene,
    id: u32,
    r: &mut Ray<f32>,
    best: &mut Option<Hit>,
    obs: &mut O,
) -> Option<Hit> {
    let shape = &scene.objects[id as usize].shape;
    test_closest_shape(scene, id, shape, r, best, &mut PerRay::default(), obs)
}

/// [`test_closest`] with the object's shape given.
#[inline(always)]
pub fn test_closest_shape<O: Observer>(
    scene: &Scene,
    id: u32,
    shape: &Shape,
    r: &mut Ray<f32>,
    best: &mut Option<Hit>,
    per: &mut PerRay,
    obs: &mut O,
) -> Option<Hit> {
    let h = test_shape(scene, id, shape, &tie_ray(r, id, best), per, obs)?;
    accept(scene, &h, r.t_max, obs);
    r.t_max = h.t;
    *best = Some(h);
    Some(h)
}

/// Tests each of `ids` for the closest hit, in order (the infinite planes an accelerator keeps
/// outside its structure).
#[inline(always)]
pub fn closest_of<O: Observer>(
    scene: &Scene,
    ids: &[u32],
    r: &mut Ray<f32>,
    best: &mut Option<Hit>,
    obs: &mut O,
) {
    for &id in ids {
        test_closest(scene, id, r, best, obs);
    }
}

/// Tests object `id` for any hit (shadow rays need no more): a hit is recorded and kept in
/// `found`. Returns whether to go on looking.
#[inline(always)]
pub fn test_any<O: Observer>(
    scene: &Scene,
    id: u32,
    ray: &Ray<f32>,
    found: &mut Option<Hit>,
    obs: &mut O,
) -> bool {
    let shape = &scene.objects[id as usize].shape;
    test_any_shape(scene, id, shape, ray, found, &mut PerRay::default(), obs)
}

/// [`test_any`] with the object's shape given.
#[inline(always)]
pub fn test_any_shape<O: Observer>(
    scene: &Scene,
    id: u32,
    shape: &Shape,
    ray: &Ray<f32>,
    found: &mut Option<Hit>,
    per: &mut PerRay,
    obs: &mut O,
) -> bool {
    match test_shape(scene, id, shape, ray, per, obs) {
        Some(h) => {
            accept(scene, &h, ray.t_max, obs);
            *found = Some(h);
            false
        }
        None => true,
    }
}

/// The first of `ids` the ray hits (any-hit).
#[inline(always)]
pub fn any_of<O: Observer>(scene: &Scene, ids: &[u32], ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
    let mut found = None;
    for &id in ids {
        if !test_any(scene, id, ray, &mut found, obs) {
            break;
        }
    }
    found
}

/// Whether an accelerator's queries may run the AVX2 + FMA build of the traversal and kernels
/// (x86-64 CPUs that have both, unless [`set_baseline_only`] turned it off). The answers are
/// identical either way.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(crate) fn avx2_fma() -> bool {
    !BASELINE_ONLY.load(std::sync::atomic::Ordering::Relaxed)
        && std::arch::is_x86_feature_detected!("avx2")
        && std::arch::is_x86_feature_detected!("fma")
}

static BASELINE_ONLY: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Makes every BVH built afterwards, and every brute-force and bounding-sphere query from now on,
/// run the baseline build only (`true`) or the fastest the CPU allows (`false`, the default) —
/// for the tests that compare the two and for benchmarks. Process-wide; a tree keeps the choice
/// made when it was built.
pub fn set_baseline_only(baseline: bool) {
    BASELINE_ONLY.store(baseline, std::sync::atomic::Ordering::Relaxed);
}

/// Below this many finite primitives the naive loop beats the BVH (a per-ray traversal set-up
/// and two box tests per level cost more than testing a handful of primitives directly).
/// Measured with `raystep bench --section accel` (160×120, one light, one thread, medians of 7):
/// at 1–2 spheres the two are even, at 4 brute force is 1.2× faster, from 8 the BVH wins
/// (1.21× at 8, 2.0× at 32, 6.5× at 256).
pub const AUTO_BVH_THRESHOLD: usize = 8;

/// The accelerator chosen for a scene.
pub enum SceneAccel {
    /// The naive loop.
    Brute(BruteForce),
    /// A BVH.
    Bvh(Box<Bvh>),
    /// A hierarchy of bounding spheres.
    Spheres(Box<SphereTree>),
    /// A uniform grid.
    Grid(Box<Grid>),
    /// The world's own accelerator (one of the above) with a TLAS over the scene's instances
    /// and a BLAS per prototype.
    TwoLevel(Box<TwoLevel>),
}

impl SceneAccel {
    /// Resolves `auto` by the scene's finite primitive count.
    pub fn resolve(scene: &Scene) -> AccelChoice {
        match scene.settings.accel {
            AccelChoice::Auto => {
                // The world's own objects (instances have their two-level tree whatever this
                // chooses).
                let finite = scene
                    .world()
                    .iter()
                    .filter(|o| !o.shape.is_infinite())
                    .count();
                if finite >= AUTO_BVH_THRESHOLD {
                    AccelChoice::Bvh
                } else {
                    AccelChoice::None
                }
            }
            other => other,
        }
    }

    /// Builds the scene's accelerator; returns it with its build time.
    pub fn build(scene: &Scene) -> (SceneAccel, Duration) {
        let start = Instant::now();
        let accel = match Self::resolve(scene) {
            AccelChoice::Bvh => SceneAccel::Bvh(Box::new(Bvh::build(scene))),
            AccelChoice::Spheres => SceneAccel::Spheres(Box::new(SphereTree::build(scene))),
            AccelChoice::Grid => SceneAccel::Grid(Box::new(Grid::build(scene))),
            AccelChoice::None | AccelChoice::Auto => SceneAccel::Brute(BruteForce),
        };
        let accel = if scene.instances.is_empty() {
            accel
        } else {
            SceneAccel::TwoLevel(Box::new(TwoLevel::build(scene, accel)))
        };
        (accel, start.elapsed())
    }
}

impl SceneAccel {
    /// Bytes the structure takes (the tree's nodes and object lists, the grid's cells and
    /// lists; 0 for brute force).
    pub fn memory(&self) -> usize {
        match self {
            SceneAccel::Brute(_) => 0,
            SceneAccel::Bvh(b) => b.memory(),
            SceneAccel::Spheres(s) => s.memory(),
            SceneAccel::Grid(g) => g.memory(),
            SceneAccel::TwoLevel(t) => t.memory(),
        }
    }
}

impl Accelerator for SceneAccel {
    #[inline]
    fn closest<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        match self {
            SceneAccel::Brute(b) => b.closest(scene, ray, obs),
            SceneAccel::Bvh(b) => b.closest(scene, ray, obs),
            SceneAccel::Spheres(s) => s.closest(scene, ray, obs),
            SceneAccel::Grid(g) => g.closest(scene, ray, obs),
            SceneAccel::TwoLevel(t) => t.closest(scene, ray, obs),
        }
    }
    #[inline]
    fn any<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        match self {
            SceneAccel::Brute(b) => b.any(scene, ray, obs),
            SceneAccel::Bvh(b) => b.any(scene, ray, obs),
            SceneAccel::Spheres(s) => s.any(scene, ray, obs),
            SceneAccel::Grid(g) => g.any(scene, ray, obs),
            SceneAccel::TwoLevel(t) => t.any(scene, ray, obs),
        }
    }
    fn name(&self) -> &'static str {
        match self {
            SceneAccel::Brute(b) => b.name(),
            SceneAccel::Bvh(b) => b.name(),
            SceneAccel::Spheres(s) => s.name(),
            SceneAccel::Grid(g) => g.name(),
            SceneAccel::TwoLevel(t) => t.name(),
        }
    }
    fn outline(&self, depth: u32) -> Option<Vec<crate::record::OutlineNode>> {
        match self {
            SceneAccel::Brute(_) | SceneAccel::Spheres(_) | SceneAccel::Grid(_) => None,
            SceneAccel::Bvh(b) => b.outline(depth),
            SceneAccel::TwoLevel(t) => t.outline(depth),
        }
    }
    fn grid_outline(&self) -> Option<crate::record::GridOutline> {
        match self {
            SceneAccel::Grid(g) => g.grid_outline(),
            SceneAccel::TwoLevel(t) => t.world.grid_outline(),
            _ => None,
        }
    }
}
