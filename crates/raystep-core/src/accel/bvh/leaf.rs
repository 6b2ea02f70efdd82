//! What the traversal does with the primitives of a leaf it reaches: the closest hit or the
//! first hit, one primitive at a time through the shared kernels, or four triangles at a time
//! from the four-lane watertight test's lanes.

// The four-lane triangle test runs on x86-64's AVX2 + FMA only: elsewhere (an ARM Mac, the
// browser's wasm32) its parts are not called.
#![cfg_attr(not(target_arch = "x86_64"), allow(dead_code, unused_imports))]

use crate::accel::{
    Hit, PerRay, accept, test_any_shape, test_closest_shape, tie_ray, triangle_step,
};
use crate::math::Ray;
use crate::record::Observer;
use crate::scene::{Scene, Shape};
use crate::shapes::triangle::{self, Shear, TriangleMethod};
use glam::Vec3;

/// What the traversal does with each primitive of a leaf it reaches. A trait with always-inlined
/// methods rather than a closure, so that the whole query — traversal, leaf tests and kernels —
/// is one function, compiled once more for AVX2 and FMA (see [`super::Bvh`]'s `closest`).
pub(super) trait LeafTest<O: Observer> {
    /// Tests object `id` (whose shape is `shape`) against `ray` (shrinking its t_max on a closer hit); false stops the
    /// traversal.
    fn test(&mut self, id: u32, shape: &Shape, ray: &mut Ray<f32>, obs: &mut O) -> bool;
    /// Takes a triangle that the four-lane test has tested (see [`LaneHit`]) as [`Self::test`]
    /// would have taken its scalar test; false stops the traversal.
    fn lane(
        &mut self,
        id: u32,
        shape: &Shape,
        found: LaneHit,
        ray: &mut Ray<f32>,
        obs: &mut O,
    ) -> bool;
    /// Reports triangles that the four-lane test found all missed, whatever t_max (recorded
    /// with the scalar test's records, as [`Self::test`] would have).
    fn misses(&mut self, ids: &[u32], shapes: &[Shape], ray: &Ray<f32>, obs: &mut O);
    /// The scene being traced.
    fn scene(&self) -> &Scene;
    /// What the query computes once per ray.
    fn per(&mut self) -> &mut PerRay;
    /// Whether triangles take the watertight test (the one the four-lane test computes).
    #[inline(always)]
    fn watertight(&self) -> bool {
        self.scene().settings.triangle_method == TriangleMethod::Watertight
    }
    /// Whether the traversal visits the farther of two sibling boxes first (shadow rays) rather
    /// than the nearer (closest hits). See [`AnyHit`].
    #[inline(always)]
    fn farther_first(&self) -> bool {
        false
    }
    /// The ray's shear for the watertight test (computed once per query).
    #[inline(always)]
    fn shear(&mut self, ray: &Ray<f32>) -> Shear<f32> {
        self.per().shear(ray)
    }
}

/// One lane of the four-lane watertight test: the scalar test's t, u and v, and whether the
/// triangle passed every check but t < t_max (which the taker checks against its t_max).
#[derive(Debug, Clone, Copy)]
pub(super) struct LaneHit {
    pub(super) t: f32,
    pub(super) u: f32,
    pub(super) v: f32,
    pub(super) pass: bool,
}

impl LaneHit {
    /// The hit on object `id` if the lane passed and t is below `ray`'s t_max — what the scalar
    /// test gives for that ray. The recorded step is the scalar test's own record, and debug
    /// builds check that the two agree bit for bit.
    #[inline(always)]
    fn take<O: Observer>(
        self,
        scene: &Scene,
        id: u32,
        shape: &Shape,
        ray: &Ray<f32>,
        shear: &Shear<f32>,
        obs: &mut O,
    ) -> Option<Hit> {
        if !self.pass {
            // The common case, kept short: a miss whatever t_max.
            if let Shape::Triangle { p } = *shape {
                let scalar = || triangle::watertight_sheared(ray, shear, p);
                debug_assert_eq!(scalar().t, None, "four-lane test missed object {id}");
                obs.prim_test(|| triangle_step(scene, id, p, scalar()));
            }
            return None;
        }
        let hit = (self.t < ray.t_max).then_some(Hit {
            object: id,
            t: self.t,
            u: self.u,
            v: self.v,
            instance: crate::scene::NO_INSTANCE,
        });
        if let Shape::Triangle { p } = *shape {
            let scalar = || triangle::watertight_sheared(ray, shear, p);
            debug_assert_eq!(
                scalar().t.map(f32::to_bits),
                hit.map(|h| h.t.to_bits()),
                "four-lane and scalar watertight tests disagree on object {id}"
            );
            debug_assert!(
                hit.is_none_or(|h| scalar().u.map(f32::to_bits) == Some(h.u.to_bits())
                    && scalar().v.map(f32::to_bits) == Some(h.v.to_bits()))
            );
            obs.prim_test(|| triangle_step(scene, id, p, scalar()));
        }
        hit
    }
}

/// The record of a triangle the four-lane test found missed: the scalar test's own record
/// (debug builds check that it is a miss too).
#[inline(always)]
fn missed_step(
    scene: &Scene,
    id: u32,
    shape: Option<&Shape>,
    ray: &Ray<f32>,
    shear: &Shear<f32>,
) -> crate::record::Step {
    let p = match shape {
        Some(Shape::Triangle { p }) => *p,
        _ => [Vec3::ZERO; 3],
    };
    let test = triangle::watertight_sheared(ray, shear, p);
    debug_assert_eq!(test.t, None, "four-lane test missed object {id}");
    triangle_step(scene, id, p, test)
}

/// The closest hit so far.
pub(super) struct ClosestHit<'a> {
    pub(super) scene: &'a Scene,
    pub(super) best: Option<Hit>,
    pub(super) per: PerRay,
}

impl<O: Observer> LeafTest<O> for ClosestHit<'_> {
    #[inline(always)]
    fn test(&mut self, id: u32, shape: &Shape, ray: &mut Ray<f32>, obs: &mut O) -> bool {
        test_closest_shape(
            self.scene,
            id,
            shape,
            ray,
            &mut self.best,
            &mut self.per,
            obs,
        );
        true
    }

    /// As [`test_closest_shape`]: tested against the tie-adjusted ray, a hit recorded as
    /// accepted and made the closest so far.
    #[inline(always)]
    fn lane(
        &mut self,
        id: u32,
        shape: &Shape,
        found: LaneHit,
        ray: &mut Ray<f32>,
        obs: &mut O,
    ) -> bool {
        let shear = self.per.shear(ray);
        let tested = tie_ray(ray, id, &self.best);
        if let Some(h) = found.take(self.scene, id, shape, &tested, &shear, obs) {
            accept(self.scene, &h, ray.t_max, obs);
            ray.t_max = h.t;
            self.best = Some(h);
        }
        true
    }

    #[inline(always)]
    fn misses(&mut self, ids: &[u32], shapes: &[Shape], ray: &Ray<f32>, obs: &mut O) {
        let shear = self.per.shear(ray);
        let best = self.best;
        obs.prim_tests(ids.len(), |j| {
            let id = ids.get(j).copied().unwrap_or(0);
            missed_step(
                self.scene,
                id,
                shapes.get(j),
                &tie_ray(ray, id, &best),
                &shear,
            )
        });
    }

    #[inline(always)]
    fn scene(&self) -> &Scene {
        self.scene
    }

    #[inline(always)]
    fn per(&mut self) -> &mut PerRay {
        &mut self.per
    }
}

/// The first hit found (shadow rays).
///
/// Any blocker will do, so the order of the siblings only decides how soon one is found, and a
/// shadow ray takes the farther box first. It starts on a surface: the nearer box mostly holds
/// that surface and its neighbours, which it is leaving, while what can block it lies towards
/// the light. Measured (`raystep bench SCENE --section rays --reps 5`, two alternated rounds
/// against nearer first, 2026-11-26): the fractal mountain's shadow rays (SPD mount 8) 10.0 →
/// 8.8 primitive tests a ray and 3.71–3.75 → 3.87–3.96 million a second; the million-triangle
/// tetrahedron 45.4 → 41.9 visits, 4.8 → 3.8 tests, 2.51 → 2.72–2.74; the sphereflake, whose
/// blockers sit right beside the surface (the small balls on each ball), 33.5 → 34.2 visits and
/// 6.15–6.26 → 6.06–6.07, 2–3 % slower. Rays that nothing blocks visit the same boxes either
/// way.
pub(super) struct AnyHit<'a> {
    pub(super) scene: &'a Scene,
    pub(super) found: Option<Hit>,
    pub(super) per: PerRay,
}

impl<O: Observer> LeafTest<O> for AnyHit<'_> {
    #[inline(always)]
    fn farther_first(&self) -> bool {
        true
    }
    #[inline(always)]
    fn test(&mut self, id: u32, shape: &Shape, ray: &mut Ray<f32>, obs: &mut O) -> bool {
        test_any_shape(
            self.scene,
            id,
            shape,
            ray,
            &mut self.found,
            &mut self.per,
            obs,
        )
    }

    /// As [`test_any_shape`]: a hit is recorded as accepted and ends the search.
    #[inline(always)]
    fn lane(
        &mut self,
        id: u32,
        shape: &Shape,
        found: LaneHit,
        ray: &mut Ray<f32>,
        obs: &mut O,
    ) -> bool {
        let shear = self.per.shear(ray);
        match found.take(self.scene, id, shape, ray, &shear, obs) {
            Some(h) => {
                accept(self.scene, &h, ray.t_max, obs);
                self.found = Some(h);
                false
            }
            None => true,
        }
    }

    #[inline(always)]
    fn misses(&mut self, ids: &[u32], shapes: &[Shape], ray: &Ray<f32>, obs: &mut O) {
        let shear = self.per.shear(ray);
        obs.prim_tests(ids.len(), |j| {
            let id = ids.get(j).copied().unwrap_or(0);
            missed_step(self.scene, id, shapes.get(j), ray, &shear)
        });
    }

    #[inline(always)]
    fn scene(&self) -> &Scene {
        self.scene
    }

    #[inline(always)]
    fn per(&mut self) -> &mut PerRay {
        &mut self.per
    }
}
