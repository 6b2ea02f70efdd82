//! The BVH's ray–box tests: the ray prepared for SIMD slab tests, the 128-bit test (ordered or
//! with NaN handling), and the AVX test of two siblings at once.

use super::Node;
use crate::math::Ray;
use crate::math::gamma;
use glam::{BVec3A, Vec3, Vec3A};

/// The ray, prepared for SIMD slab tests: lane for lane the same IEEE operations as
/// [`crate::shapes::aabb::slab_robust`] (difference, product by the reciprocal, selection of entry
/// and exit by the reciprocal's sign bit, exit × (1 + 2γ₃), NaN-ignoring max/min), so every
/// traversal decision agrees with the recorded scalar test.
pub(crate) struct FastRay {
    origin: Vec3A,
    inv: Vec3A,
    negative: BVec3A,
    enlarge: Vec3A,
    t_min: Vec3A,
}

impl FastRay {
    #[inline(always)]
    pub(crate) fn new(ray: &Ray<f32>, inv: Vec3) -> FastRay {
        let bits = Vec3A::from(inv).is_negative_bitmask();
        FastRay {
            origin: Vec3A::from(ray.origin),
            inv: Vec3A::from(inv),
            negative: BVec3A::new(bits & 1 != 0, bits & 2 != 0, bits & 4 != 0),
            enlarge: Vec3A::splat(1.0 + 2.0 * gamma::<f32>(3)),
            t_min: Vec3A::splat(ray.t_min),
        }
    }

    /// (t_near, t_far) of the node's box, with `t_max` the ray's t_max in every lane.
    ///
    /// `ORDERED`: every slab distance is a number (no NaN), so entry and exit are simply the
    /// smaller and the larger of the two — what the sign select gives, in two instructions
    /// instead of six. The caller chooses it only when the direction, its reciprocals, the
    /// origin and every box are finite (a difference, finite or overflowed to ±∞, times a
    /// finite non-zero reciprocal is never NaN).
    #[inline(always)]
    pub(crate) fn interval<const ORDERED: bool>(&self, node: &Node, t_max: Vec3A) -> (f32, f32) {
        let t0 = (node.min - self.origin) * self.inv;
        let t1 = (node.max - self.origin) * self.inv;
        let (entry, exit) = if ORDERED {
            (t0.min(t1), t0.max(t1))
        } else {
            (
                Vec3A::select(self.negative, t1, t0),
                Vec3A::select(self.negative, t0, t1),
            )
        };
        let exit = exit * self.enlarge;
        // A NaN slab distance (a ray lying in a face plane, 0·∞) imposes no limit — the scalar
        // test gets this from f32::max ignoring NaN. Here each lane is first limited by t_min
        // (t_max), a NaN lane becoming t_min (t_max), which cannot change the result.
        let entry = max_or_second(entry, self.t_min);
        let exit = min_or_second(exit, t_max);
        (entry.max_element(), exit.min_element())
    }
}

impl FastRay {
    /// Both siblings' `interval::<true>` at once: on the AVX path the two boxes share one
    /// 256-bit register, so each operation of the ordered slab test runs once for the pair. The
    /// same IEEE operations in the same operand order, lane for lane, as [`FastRay::interval`]
    /// (its `MINPS`/`MAXPS` and glam's horizontal max/min shuffles), so the same values bit for
    /// bit — `tests` compares the two on random boxes. Only called with `WIDE`, which only the
    /// AVX2 build of the query sets.
    #[inline(always)]
    #[allow(unsafe_code)] // calling the AVX function; reached only from the AVX2 build
    pub(in crate::accel::bvh) fn interval_pair(
        &self,
        a: &Node,
        b: &Node,
        t_max: Vec3A,
    ) -> ((f32, f32), (f32, f32)) {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: `WIDE` is true only inside `closest_avx2`/`any_avx2`, which run only after
            // `avx2_fma()` found AVX2 (hence AVX) on this CPU.
            unsafe { wide::interval_pair(self, a, b, t_max) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            (
                self.interval::<true>(a, t_max),
                self.interval::<true>(b, t_max),
            )
        }
    }
}

/// The AVX form of the pair test.
#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
pub(super) mod wide {
    use super::{FastRay, Node};
    use glam::Vec3A;
    use std::arch::x86_64::*;

    /// See [`FastRay::interval_pair`].
    ///
    /// Not a `#[target_feature]` function: those cannot be `#[inline(always)]`, and left to the
    /// compiler's inliner one of its callers got it as a call per sibling pair (a change of the
    /// node layout once made that the shadow-ray query: 20 % more instructions). Always
    /// inlined, it is compiled as part of `closest_avx2`/`any_avx2`, whose AVX2 + FMA features
    /// its intrinsics then use.
    ///
    /// # Safety
    ///
    /// The CPU must have AVX (only the AVX2 build of the query calls this).
    #[inline(always)]
    pub(in crate::accel::bvh) unsafe fn interval_pair(
        ray: &FastRay,
        a: &Node,
        b: &Node,
        t_max: Vec3A,
    ) -> ((f32, f32), (f32, f32)) {
        // SAFETY: the caller guarantees AVX (see above).
        unsafe {
            let pair = |x: Vec3A, y: Vec3A| _mm256_set_m128(y.into(), x.into());
            let origin = pair(ray.origin, ray.origin);
            let inv = pair(ray.inv, ray.inv);
            let t0 = _mm256_mul_ps(_mm256_sub_ps(pair(a.min, b.min), origin), inv);
            let t1 = _mm256_mul_ps(_mm256_sub_ps(pair(a.max, b.max), origin), inv);
            let entry = _mm256_min_ps(t0, t1);
            let exit = _mm256_mul_ps(_mm256_max_ps(t0, t1), pair(ray.enlarge, ray.enlarge));
            let entry = _mm256_max_ps(entry, pair(ray.t_min, ray.t_min));
            let exit = _mm256_min_ps(exit, pair(t_max, t_max));
            // glam's max_element / min_element, in each half.
            let e = _mm256_max_ps(entry, _mm256_permute_ps::<0b00_00_10_10>(entry));
            let e = _mm256_max_ps(e, _mm256_permute_ps::<0b00_00_00_01>(e));
            let x = _mm256_min_ps(exit, _mm256_permute_ps::<0b01_01_10_10>(exit));
            let x = _mm256_min_ps(x, _mm256_permute_ps::<0b00_00_00_01>(x));
            let low = |v: __m256| _mm_cvtss_f32(_mm256_castps256_ps128(v));
            let high = |v: __m256| _mm_cvtss_f32(_mm256_extractf128_ps::<1>(v));
            ((low(e), low(x)), (high(e), high(x)))
        }
    }
}

/// Lane-wise `a > b ? a : b`: the larger, and `b` where `a` is NaN. On x86 this is exactly
/// `MAXPS a, b`, which returns its second operand when either is NaN (Intel SDM), so it is one
/// instruction; elsewhere (NEON's `vmaxq` propagates NaN) it is written out as a select.
#[inline(always)]
fn max_or_second(a: Vec3A, b: Vec3A) -> Vec3A {
    #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
    {
        a.max(b)
    }
    #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
    {
        Vec3A::select(a.cmpgt(b), a, b)
    }
}

/// Lane-wise `a < b ? a : b`: the smaller, and `b` where `a` is NaN (`MINPS a, b` on x86).
#[inline(always)]
fn min_or_second(a: Vec3A, b: Vec3A) -> Vec3A {
    #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
    {
        a.min(b)
    }
    #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
    {
        Vec3A::select(a.cmplt(b), a, b)
    }
}
