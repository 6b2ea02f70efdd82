//! The naive loop: test every primitive.

use super::{Accelerator, Hit, accept, test_object};
use crate::math::Ray;
use crate::record::Observer;
use crate::scene::Scene;

/// Tests every object in scene order; the ray's t_max shrinks with each closer hit, so the kernels
/// themselves reject anything farther (the triangle test stops at step 5).
///
/// Like the BVH's queries, the loop is compiled twice: for the baseline x86-64 and, taken when
/// the CPU has them, for AVX2 and FMA. The answers are the same bit for bit (the only fused
/// operations are the triangle test's explicit `mul_add`s, correctly rounded either way; see
/// [`super::bvh::Bvh`]'s `Accelerator` impl), but the baseline build calls `fmaf` six times a
/// triangle test, and each call makes the loop save and reload its floating-point registers:
/// 10.5 % of a path-traced frame's instructions on the soft-shadow scene with its floor as a
/// triangle (callgrind).
#[derive(Debug, Default, Clone, Copy)]
pub struct BruteForce;

impl BruteForce {
    #[inline(always)]
    fn closest_in<O: Observer>(scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
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
    fn any_in<O: Observer>(scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        for id in 0..scene.world_objects {
            if let Some(h) = test_object(scene, id, ray, obs) {
                accept(scene, &h, ray.t_max, obs);
                return Some(h);
            }
        }
        None
    }

    /// [`BruteForce::closest_in`] compiled for AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn closest_avx2<O: Observer>(scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        Self::closest_in(scene, ray, obs)
    }

    /// [`BruteForce::any_in`] compiled for AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn any_avx2<O: Observer>(scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        Self::any_in(scene, ray, obs)
    }
}

impl Accelerator for BruteForce {
    #[inline]
    #[allow(unsafe_code)] // calling a #[target_feature] function, after checking the CPU has it
    fn closest<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        #[cfg(target_arch = "x86_64")]
        if super::avx2_fma() {
            // SAFETY: the CPU has AVX2 and FMA (just checked).
            return unsafe { Self::closest_avx2(scene, ray, obs) };
        }
        Self::closest_in(scene, ray, obs)
    }

    #[inline]
    #[allow(unsafe_code)] // calling a #[target_feature] function, after checking the CPU has it
    fn any<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        #[cfg(target_arch = "x86_64")]
        if super::avx2_fma() {
            // SAFETY: the CPU has AVX2 and FMA (just checked).
            return unsafe { Self::any_avx2(scene, ray, obs) };
        }
        Self::any_in(scene, ray, obs)
    }

    fn name(&self) -> &'static str {
        "brute force"
    }
}
