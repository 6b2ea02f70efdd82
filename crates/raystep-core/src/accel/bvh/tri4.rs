//! The watertight triangle test on four triangles at once, for the BVH's AVX2 + FMA build.
//!
//! A leaf whose primitives are all triangles also keeps them in [`Tri4`] packs: four
//! triangles' nine coordinates, component by component, so one 128-bit operation does for four
//! triangles what [`crate::shapes::triangle::watertight_sheared`] does for one. Each lane runs
//! the scalar test's IEEE operations in the scalar test's order — the same subtractions, the
//! same products and sums (Rust never fuses them), the same three fused multiply-adds per edge
//! function (`VFMADD`/`VFMSUB`/`VFNMADD` round once, as `f32::mul_add` does) — so each lane's
//! t, u and v are the scalar test's bit for bit, and so is the decision. What a lane cannot
//! decide alone is left to the scalar test: an edge function exactly zero (the scalar test
//! recomputes it in f64) and the comparison with t_max, which changes as the leaf's hits are
//! taken one by one in leaf order. `tests` compares the two on random and on hard triangles.

// The four-lane triangle test runs on x86-64's AVX2 + FMA only: elsewhere (an ARM Mac, the
// browser's wasm32) its parts are not called.
#![cfg_attr(not(target_arch = "x86_64"), allow(dead_code, unused_imports))]

use super::Node;
use crate::scene::Shape;
use glam::Vec3;

/// Four triangles of a leaf, coordinate by coordinate: `v[3 * i + c]` holds component `c` of
/// vertex `i` of each of the four (unused lanes hold zeros and are never read back).
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(16))]
pub(super) struct Tri4 {
    pub(super) v: [[f32; 4]; 9],
}

impl Tri4 {
    /// Packs up to four triangles (vertices given as `[P0, P1, P2]`).
    pub(super) fn pack<'a>(tris: impl IntoIterator<Item = &'a [Vec3; 3]>) -> Tri4 {
        let mut v = [[0.0f32; 4]; 9];
        for (lane, p) in tris.into_iter().take(4).enumerate() {
            for (i, vertex) in p.iter().enumerate() {
                for (c, x) in vertex.to_array().into_iter().enumerate() {
                    if let Some(slot) = v.get_mut(3 * i + c).and_then(|l| l.get_mut(lane)) {
                        *slot = x;
                    }
                }
            }
        }
        Tri4 { v }
    }
}

/// Packs the triangles of every leaf whose primitives are all triangles, setting the leaf's
/// `pack` to the index of its first pack (its triangles fill ⌈count / 4⌉ packs in leaf order);
/// other leaves keep [`NO_PACK`]. The packs are filled in parallel on big trees: most of the
/// time goes into first touching their memory (36 MB for a million triangles).
pub(super) fn pack_leaves(nodes: &mut [Node], shapes: &[Shape]) -> Vec<Tri4> {
    fn vertices(s: &Shape) -> Option<&[Vec3; 3]> {
        match s {
            Shape::Triangle { p } => Some(p),
            _ => None,
        }
    }
    // Each pack's triangles: where they start in `shapes`, and how many (1 to 4).
    let mut spans: Vec<(usize, usize)> = Vec::with_capacity(shapes.len().div_ceil(4));
    for node in nodes.iter_mut().filter(|n| n.is_leaf()) {
        let (start, count) = (node.first as usize, node.count as usize);
        let Some(leaf) = shapes.get(start..start + count) else {
            continue;
        };
        if leaf.is_empty() || !leaf.iter().all(|s| vertices(s).is_some()) {
            continue;
        }
        let Ok(first) = u32::try_from(spans.len()) else {
            break;
        };
        node.pack = first;
        spans.extend(
            (0..count)
                .step_by(4)
                .map(|k| (start + k, (count - k).min(4))),
        );
    }
    super::parallel::map_in_order(&spans, |&(start, len)| {
        let leaf = shapes.get(start..start + len).unwrap_or_default();
        Tri4::pack(leaf.iter().filter_map(vertices))
    })
}

/// A leaf without packs (it holds a sphere, or no triangle at all).
pub(super) const NO_PACK: u32 = u32::MAX;

/// What four lanes found: t, u and v as the scalar test computes them, and which lanes passed
/// every check but t < t_max.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Lanes {
    /// The scalar test's t* (Σ eᵢ·zᵢ / det).
    pub(super) t: [f32; 4],
    /// Its u (e1 / det).
    pub(super) u: [f32; 4],
    /// Its v (e2 / det).
    pub(super) v: [f32; 4],
    /// Bit j: lane j is a hit if its t is below the ray's t_max.
    pub(super) pass: u32,
    /// Bit j: an edge function of lane j is exactly zero; the scalar test decides it.
    pub(super) exact: u32,
}

#[cfg(target_arch = "x86_64")]
pub(super) use wide::{Ray4, test4};

#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
mod wide {
    use super::{Lanes, Tri4};
    use crate::math::{Ray, gamma};
    use crate::shapes::triangle::Shear;
    use std::arch::x86_64::*;

    /// The ray as the four-lane test needs it, every value in all four lanes.
    #[derive(Clone, Copy)]
    pub(in crate::accel::bvh) struct Ray4 {
        origin: [__m128; 3],
        kz: usize,
        sx: __m128,
        sy: __m128,
        sz: __m128,
        t_min: __m128,
        g2: __m128,
        g3: __m128,
        g5: __m128,
    }

    impl Ray4 {
        /// # Safety
        ///
        /// The CPU must have AVX2 and FMA (only the AVX2 build of the query calls this).
        #[inline(always)]
        pub(in crate::accel::bvh) unsafe fn new(ray: &Ray<f32>, shear: &Shear<f32>) -> Ray4 {
            // SAFETY: the caller guarantees AVX2 and FMA; these are plain register operations.
            unsafe {
                let [sx, sy, sz] = shear.s;
                Ray4 {
                    origin: [
                        _mm_set1_ps(ray.origin.x),
                        _mm_set1_ps(ray.origin.y),
                        _mm_set1_ps(ray.origin.z),
                    ],
                    kz: shear.kz,
                    sx: _mm_set1_ps(sx),
                    sy: _mm_set1_ps(sy),
                    sz: _mm_set1_ps(sz),
                    t_min: _mm_set1_ps(ray.t_min),
                    g2: _mm_set1_ps(gamma::<f32>(2)),
                    g3: _mm_set1_ps(gamma::<f32>(3)),
                    g5: _mm_set1_ps(gamma::<f32>(5)),
                }
            }
        }
    }

    /// `max` of two lanes whose values are numbers (see [`test4`]: no lane that can pass
    /// carries a NaN here, and for the others the value is never read).
    #[inline(always)]
    unsafe fn max3(a: __m128, b: __m128, c: __m128) -> __m128 {
        // SAFETY: SSE, present on every x86-64 CPU.
        unsafe { _mm_max_ps(_mm_max_ps(a, b), c) }
    }

    /// |x|: the sign bit cleared, as `f32::abs` does.
    #[inline(always)]
    unsafe fn abs(x: __m128) -> __m128 {
        // SAFETY: SSE.
        unsafe { _mm_andnot_ps(_mm_set1_ps(-0.0), x) }
    }

    /// a·b − c·d as `difference_of_products` computes it: cd = c·d, a·b − cd and −c·d + cd
    /// each rounded once (fused), then their sum.
    #[inline(always)]
    unsafe fn difference_of_products(a: __m128, b: __m128, c: __m128, d: __m128) -> __m128 {
        // SAFETY: FMA, guaranteed by the callers (see `test4`).
        unsafe {
            let cd = _mm_mul_ps(c, d);
            let dop = _mm_fmsub_ps(a, b, cd);
            let err = _mm_fnmadd_ps(c, d, cd);
            _mm_add_ps(dop, err)
        }
    }

    /// The watertight test of the ray against the four triangles of `pack`, lane for lane the
    /// operations of `watertight_sheared` (whose comments say what each step is for).
    ///
    /// A lane that can pass has finite sheared coordinates and edge functions: a NaN or an
    /// infinity among a triangle's sheared coordinates makes an edge function NaN or infinite
    /// (each coordinate is a factor of two of them), hence det, and the lane fails the
    /// determinant check. So the `MAXPS` maxima, which differ from `f32::max` only on NaN,
    /// agree with the scalar test wherever it matters.
    ///
    /// # Safety
    ///
    /// The CPU must have AVX2 and FMA (only the AVX2 build of the query calls this).
    #[inline(always)]
    pub(in crate::accel::bvh) unsafe fn test4(r: &Ray4, pack: &Tri4) -> Lanes {
        // SAFETY: the caller guarantees AVX2 and FMA; loads read the pack's own arrays.
        unsafe {
            let load = |k: usize| match pack.v.get(k) {
                Some(l) => _mm_loadu_ps(l.as_ptr()),
                None => _mm_setzero_ps(),
            };
            let zero = _mm_setzero_ps();
            // Translate, then rotate so the ray's largest component is z.
            let mut q = [[zero; 3]; 3];
            for (i, qi) in q.iter_mut().enumerate() {
                let d = [
                    _mm_sub_ps(load(3 * i), r.origin[0]),
                    _mm_sub_ps(load(3 * i + 1), r.origin[1]),
                    _mm_sub_ps(load(3 * i + 2), r.origin[2]),
                ];
                *qi = match r.kz {
                    0 => [d[1], d[2], d[0]],
                    1 => [d[2], d[0], d[1]],
                    _ => d,
                };
            }
            // Shear: x + Sx·z, y + Sy·z (a product, then a sum).
            for qi in q.iter_mut() {
                qi[0] = _mm_add_ps(qi[0], _mm_mul_ps(r.sx, qi[2]));
                qi[1] = _mm_add_ps(qi[1], _mm_mul_ps(r.sy, qi[2]));
            }
            let [q0, q1, q2] = q;
            let e0 = difference_of_products(q1[0], q2[1], q1[1], q2[0]);
            let e1 = difference_of_products(q2[0], q0[1], q2[1], q0[0]);
            let e2 = difference_of_products(q0[0], q1[1], q0[1], q1[0]);
            let exact = _mm_movemask_ps(_mm_or_ps(
                _mm_or_ps(_mm_cmpeq_ps(e0, zero), _mm_cmpeq_ps(e1, zero)),
                _mm_cmpeq_ps(e2, zero),
            )) as u32;
            let any_negative = _mm_or_ps(
                _mm_or_ps(_mm_cmplt_ps(e0, zero), _mm_cmplt_ps(e1, zero)),
                _mm_cmplt_ps(e2, zero),
            );
            let any_positive = _mm_or_ps(
                _mm_or_ps(_mm_cmpgt_ps(e0, zero), _mm_cmpgt_ps(e1, zero)),
                _mm_cmpgt_ps(e2, zero),
            );
            let det = _mm_add_ps(_mm_add_ps(e0, e1), e2);
            // det ≠ 0 and finite (|det| < ∞ is false for NaN).
            let det_ok = _mm_and_ps(
                _mm_cmpneq_ps(det, zero),
                _mm_cmplt_ps(abs(det), _mm_set1_ps(f32::INFINITY)),
            );
            // Lanes still in the running: signs agree and det is usable. Most triangles a ray
            // reaches are missed here; when all four are, nothing more is computed.
            let candidates = _mm_andnot_ps(_mm_and_ps(any_negative, any_positive), det_ok);
            if _mm_movemask_ps(candidates) == 0 {
                return Lanes {
                    t: [f32::NAN; 4],
                    u: [0.0; 4],
                    v: [0.0; 4],
                    pass: 0,
                    exact,
                };
            }
            let max_z_unscaled = max3(abs(q0[2]), abs(q1[2]), abs(q2[2]));
            let z0 = _mm_mul_ps(q0[2], r.sz);
            let z1 = _mm_mul_ps(q1[2], r.sz);
            let z2 = _mm_mul_ps(q2[2], r.sz);
            let t_scaled = _mm_add_ps(
                _mm_add_ps(_mm_mul_ps(e0, z0), _mm_mul_ps(e1, z1)),
                _mm_mul_ps(e2, z2),
            );
            let inv_det = _mm_div_ps(_mm_set1_ps(1.0), det);
            let t = _mm_mul_ps(t_scaled, inv_det);
            let b1 = _mm_mul_ps(e1, inv_det);
            let b2 = _mm_mul_ps(e2, inv_det);
            // pbrt-v4's bound on t's rounding error.
            let max_zt = max3(abs(z0), abs(z1), abs(z2));
            let delta_z = _mm_mul_ps(r.g3, max_zt);
            let max_xt = max3(abs(q0[0]), abs(q1[0]), abs(q2[0]));
            let max_yt = max3(abs(q0[1]), abs(q1[1]), abs(q2[1]));
            let delta_x = _mm_mul_ps(r.g5, _mm_add_ps(max_xt, max_z_unscaled));
            let delta_y = _mm_mul_ps(r.g5, _mm_add_ps(max_yt, max_z_unscaled));
            let delta_e = _mm_mul_ps(
                _mm_set1_ps(2.0),
                _mm_add_ps(
                    _mm_add_ps(
                        _mm_mul_ps(_mm_mul_ps(r.g2, max_xt), max_yt),
                        _mm_mul_ps(delta_y, max_xt),
                    ),
                    _mm_mul_ps(delta_x, max_yt),
                ),
            );
            let max_e = max3(abs(e0), abs(e1), abs(e2));
            let delta_t = _mm_mul_ps(
                _mm_mul_ps(
                    _mm_set1_ps(3.0),
                    _mm_add_ps(
                        _mm_add_ps(
                            _mm_mul_ps(_mm_mul_ps(r.g3, max_e), max_zt),
                            _mm_mul_ps(delta_e, max_zt),
                        ),
                        _mm_mul_ps(delta_z, max_e),
                    ),
                ),
                abs(inv_det),
            );
            // Every check but t < t_max: signs agree, det usable, t > t_min, not t ≤ δt
            // (a NaN δt rejects nothing, as in the scalar test).
            let pass = _mm_and_ps(
                _mm_and_ps(candidates, _mm_cmpgt_ps(t, r.t_min)),
                _mm_cmp_ps::<_CMP_NLE_UQ>(t, delta_t),
            );
            let mut out = Lanes {
                t: [0.0; 4],
                u: [0.0; 4],
                v: [0.0; 4],
                pass: _mm_movemask_ps(pass) as u32,
                exact,
            };
            _mm_storeu_ps(out.t.as_mut_ptr(), t);
            _mm_storeu_ps(out.u.as_mut_ptr(), b1);
            _mm_storeu_ps(out.v.as_mut_ptr(), b2);
            out
        }
    }
}
