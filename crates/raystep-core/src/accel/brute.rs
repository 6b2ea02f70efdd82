//! The naive loop: test every primitive.

use super::{Accelerator, Hit, accept, test_object};
use crate::math::Ray;
use crate::record::Observer;
use crate::scene::Scene;

/// Tests every object in scene order; the ray's t_max shrinks with each closer hit, so the kernels
/// themselves reject anything farther (the triangle test stops at step 5). Built twice, for the
/// baseline x86-64 and for AVX2 + FMA (see `two_builds`).
#[derive(Debug, Default, Clone, Copy)]
pub struct BruteForce;

impl BruteForce {
    #[inline(always)]
    fn closest_in<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        let mut r = *ray;
        let mut best = None;
        for id in 0..scene.world_objects {
            if let Some(h) = test_object(scene, id, &r, obs) {
                accept(scene, &h, r.t_max, obs);
                r.t_max = h.t;
                best = Some(h);
            }
        }
        best
    }

    #[inline(always)]
    fn any_in<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        for id in 0..scene.world_objects {
            if let Some(h) = test_object(scene, id, ray, obs) {
                accept(scene, &h, ray.t_max, obs);
                return Some(h);
            }
        }
        None
    }
}

two_builds!(BruteForce);

impl Accelerator for BruteForce {
    #[inline]
    fn closest<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        self.closest_fastest(scene, ray, obs)
    }

    #[inline]
    fn any<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        self.any_fastest(scene, ray, obs)
    }

    fn name(&self) -> &'static str {
        "brute force"
    }
}
