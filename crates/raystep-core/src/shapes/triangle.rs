//! Ray–triangle intersection: Möller–Trumbore as Cramer's rule (the 12 steps of Mike Bailey's
//! Vulkan Ray Tracing notes, docs/SOURCES.md) and the watertight test of Woop, Benthin and Wald
//! (JCGT 2013), as in pbrt-v4's `IntersectTriangle`.

use crate::math::{Ray, Real, Vector, gamma, to_array};
use serde::{Deserialize, Serialize};

/// Which triangle test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum TriangleMethod {
    /// Möller–Trumbore via Cramer's rule, no ε on the determinant (the form of Bailey's notes).
    MollerTrumbore,
    /// Woop–Benthin–Wald watertight test. The renderer's default: docs/NUMERICS.md measured 7.4% of
    /// rays aimed exactly at a shared edge slipping between two Möller–Trumbore triangles in f32
    /// (4.1% at a shared vertex), and 0 leaks in 4.4 million such rays with this test; raystep's
    /// own `crates/raystep-core/tests/it/stiff.rs` repeats the edge measurement (S12) on every test run.
    // Why the default (`raystep stability`, full suite, f32, exact references): of 16 000 rays
    // aimed at shared edges (S12, scales 1e-3…1e5) Möller–Trumbore lets 1479 through both
    // triangles (9.2%), and 16 of 16 000 at a shared vertex (S13); this test lets none through,
    // there or at coordinates 1e6…1e8 (S18), with t within 2.3 ulps (p99). It costs about 3×
    // as much per call (≈ 55–80 ns against ≈ 19 ns in the lab's loop). scenes/leaky-edge.toml
    // shows the cracks.
    #[default]
    Watertight,
}

/// Every intermediate of one ray–triangle test.
///
/// For Möller–Trumbore the system S + tQ = P0 + u(P1 − P0) + v(P2 − P0), written
/// [−Q, E1, E2]·(t, u, v)ᵀ = T with T = S − P0, is solved by Cramer's rule:
/// D0 = det(−Q, E1, E2), Dt = det(T, E1, E2), Du = det(−Q, T, E2), Dv = det(−Q, E1, T),
/// t* = Dt/D0, u* = Du/D0, v* = Dv/D0. Bailey's 12 steps:
///
/// 1. E1 = P1 − P0, E2 = P2 − P0
/// 2. D0; if D0 = 0 the ray is parallel to the plane: **stop**
/// 3. T = S − P0
/// 4. Dt
/// 5. t* = Dt/D0; if t* ≤ t_min (behind) or t* ≥ t_max (farther than the closest hit): **stop**
/// 6. Du
/// 7. u* = Du/D0
/// 8. if u* < 0 or u* > 1: **stop**
/// 9. Dv
/// 10. v* = Dv/D0
/// 11. if v* < 0 or u* + v* > 1: **stop**
/// 12. hit at t*, with barycentrics (1 − u* − v*, u*, v*)
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(bound(
    serialize = "T: crate::jsonf::JsonFloat",
    deserialize = "T: crate::jsonf::JsonFloat"
))]
pub struct TriangleTest<T> {
    /// The method used.
    pub method: TriangleMethod,
    /// The determinant: D0 for Möller–Trumbore; e0 + e1 + e2 for watertight.
    #[serde(with = "crate::jsonf")]
    pub det: T,
    /// Möller–Trumbore: Dt (None if stopped before step 4). Watertight: the scaled t (Σ eᵢ·zᵢ).
    #[serde(with = "crate::jsonf")]
    pub dt: Option<T>,
    /// Möller–Trumbore: Du (None if stopped before step 6).
    #[serde(with = "crate::jsonf")]
    pub du: Option<T>,
    /// Möller–Trumbore: Dv (None if stopped before step 9).
    #[serde(with = "crate::jsonf")]
    pub dv: Option<T>,
    /// Watertight: the three edge functions e0, e1, e2 (barycentric weights of P0, P1, P2 times det).
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub edges: Option<[T; 3]>,
    /// Watertight: the ray-space permutation (kx, ky, kz), kz the largest |Q| component.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub permutation: Option<[usize; 3]>,
    /// Watertight: the shear (Sx, Sy, Sz) = (−Qx/Qz, −Qy/Qz, 1/Qz) of the permuted direction.
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub shear: Option<[T; 3]>,
    /// Watertight: the vertices P0, P1, P2 translated to the ray's origin, permuted and sheared,
    /// (x + Sx·z, y + Sy·z, z) — z not yet scaled.
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub sheared: Option<[[T; 3]; 3]>,
    /// Watertight: the vertices' z scaled into units of t, z′ = z·Sz (None if stopped before).
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub z_scaled: Option<[T; 3]>,
    /// Möller–Trumbore: E1 = P1 − P0.
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub e1: Option<[T; 3]>,
    /// Möller–Trumbore: E2 = P2 − P0.
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub e2: Option<[T; 3]>,
    /// Möller–Trumbore: T = S − P0, from the first vertex to the ray's origin (None if stopped
    /// at step 2).
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub t_vec: Option<[T; 3]>,
    /// t* (None if not reached).
    #[serde(with = "crate::jsonf")]
    pub t_star: Option<T>,
    /// u*, the weight of P1 (None if not reached).
    #[serde(with = "crate::jsonf")]
    pub u: Option<T>,
    /// v*, the weight of P2 (None if not reached).
    #[serde(with = "crate::jsonf")]
    pub v: Option<T>,
    /// The step (1–12, numbered as above) at which the test stopped; 12 means a hit.
    /// Watertight maps its rejections onto the same numbers: 2 parallel (det = 0), 5 t out of range,
    /// 8 mixed edge signs (outside).
    pub stopped_at: u8,
    /// The hit distance, if the test reached step 12.
    #[serde(with = "crate::jsonf")]
    pub t: Option<T>,
}

impl<T: Real> TriangleTest<T> {
    /// The hit distance, if any.
    #[inline(always)]
    pub fn hit(&self) -> Option<T> {
        self.t
    }
    /// The determinant, if the test got as far as computing it (the watertight test checks the
    /// edge functions' signs first, and one that stops there never sums them).
    pub fn det_computed(&self) -> Option<T> {
        let skipped = self.method == TriangleMethod::Watertight
            && (self.stopped_at == 8 || self.edges.is_none());
        (!skipped).then_some(self.det)
    }
    /// The words for where the test stopped.
    pub fn stop_reason(&self) -> &'static str {
        match self.stopped_at {
            2 => "parallel: the determinant is zero",
            5 => "t out of range: behind the origin or beyond the closest hit so far",
            8 if self.method == TriangleMethod::Watertight => {
                "outside: the edge functions differ in sign"
            }
            8 => "u out of [0, 1]: outside the triangle",
            11 => "v < 0 or u + v > 1: outside the triangle",
            12 => "hit",
            _ => "unknown",
        }
    }
}

/// Runs the chosen triangle test.
#[inline(always)]
pub fn intersect<T: Real>(ray: &Ray<T>, p: [T::V; 3], method: TriangleMethod) -> TriangleTest<T> {
    match method {
        TriangleMethod::MollerTrumbore => moller_trumbore(ray, p),
        TriangleMethod::Watertight => watertight(ray, p),
    }
}

/// det(a, b, c) = a·(b × c).
#[inline(always)]
fn det3<T: Real>(a: T::V, b: T::V, c: T::V) -> T {
    a.dot(b.cross(c))
}

/// Möller–Trumbore as Cramer's rule, stopping at the early exits of Bailey's 12 steps.
#[inline(always)]
pub fn moller_trumbore<T: Real>(ray: &Ray<T>, p: [T::V; 3]) -> TriangleTest<T> {
    let mut out = TriangleTest {
        method: TriangleMethod::MollerTrumbore,
        det: T::zero(),
        dt: None,
        du: None,
        dv: None,
        edges: None,
        permutation: None,
        shear: None,
        sheared: None,
        z_scaled: None,
        e1: None,
        e2: None,
        t_vec: None,
        t_star: None,
        u: None,
        v: None,
        stopped_at: 2,
        t: None,
    };
    // 1.
    let e1 = p[1] - p[0];
    let e2 = p[2] - p[0];
    out.e1 = Some(to_array::<T>(e1));
    out.e2 = Some(to_array::<T>(e2));
    let nq = -ray.dir;
    // 2. (no ε: an ε on D0 rejects head-on hits on small triangles, docs/NUMERICS.md S14/S16)
    let d0 = det3::<T>(nq, e1, e2);
    out.det = d0;
    if d0 == T::zero() || !d0.is_finite() {
        return out;
    }
    // 3.–5.
    let tv = ray.origin - p[0];
    out.t_vec = Some(to_array::<T>(tv));
    let dt = det3::<T>(tv, e1, e2);
    out.dt = Some(dt);
    let t = dt / d0;
    out.t_star = Some(t);
    if !ray.accepts(t) {
        out.stopped_at = 5;
        return out;
    }
    // 6.–8.
    let du = det3::<T>(nq, tv, e2);
    out.du = Some(du);
    let u = du / d0;
    out.u = Some(u);
    if u < T::zero() || u > T::one() {
        out.stopped_at = 8;
        return out;
    }
    // 9.–11.
    let dv = det3::<T>(nq, e1, tv);
    out.dv = Some(dv);
    let v = dv / d0;
    out.v = Some(v);
    if v < T::zero() || u + v > T::one() {
        out.stopped_at = 11;
        return out;
    }
    // 12.
    out.stopped_at = 12;
    out.t = Some(t);
    out
}

/// a·b − c·d with the error of c·d recovered by an FMA (Kahan's algorithm, pbrt-v4).
#[inline(always)]
fn difference_of_products<T: Real>(a: T, b: T, c: T, d: T) -> T {
    let cd = c * d;
    let dop = a.mul_add(b, -cd);
    let err = (-c).mul_add(d, cd);
    dop + err
}

/// The part of the watertight test that depends on the ray alone: which axis becomes z (the
/// largest |Q| component), the direction permuted, and the shear (Sx, Sy, Sz). A renderer
/// computes it once per ray ([`watertight_sheared`]); [`watertight`] computes it per test. The
/// values are the same either way, so are the answers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shear<T> {
    /// The axis that becomes z.
    pub kz: usize,
    /// Sx = −Qx/Qz, Sy = −Qy/Qz, Sz = 1/Qz (permuted components).
    pub s: [T; 3],
}

impl<T: Real> Shear<T> {
    /// The ray's shear.
    #[inline(always)]
    pub fn of(ray: &Ray<T>) -> Shear<T> {
        let d = ray.dir;
        let ad = d.abs();
        let kz = if ad.at(0) > ad.at(1) {
            if ad.at(0) > ad.at(2) { 0 } else { 2 }
        } else if ad.at(1) > ad.at(2) {
            1
        } else {
            2
        };
        // [d.at(kx), d.at(ky), d.at(kz)], as a rotation of the components.
        let dp = d.rotate_last(kz);
        Shear {
            kz,
            s: [-dp[0] / dp[2], -dp[1] / dp[2], T::one() / dp[2]],
        }
    }
}

/// The watertight test (Woop, Benthin, Wald 2013; pbrt-v4 `IntersectTriangle`).
#[inline(always)]
pub fn watertight<T: Real>(ray: &Ray<T>, p: [T::V; 3]) -> TriangleTest<T> {
    watertight_sheared(ray, &Shear::of(ray), p)
}

/// [`watertight`] with the ray's [`Shear`] computed beforehand (it must be `Shear::of(ray)`).
#[inline(always)]
pub fn watertight_sheared<T: Real>(
    ray: &Ray<T>,
    shear: &Shear<T>,
    p: [T::V; 3],
) -> TriangleTest<T> {
    let mut out = TriangleTest {
        method: TriangleMethod::Watertight,
        det: T::zero(),
        dt: None,
        du: None,
        dv: None,
        edges: None,
        permutation: None,
        shear: None,
        sheared: None,
        z_scaled: None,
        e1: None,
        e2: None,
        t_vec: None,
        t_star: None,
        u: None,
        v: None,
        stopped_at: 2,
        t: None,
    };
    // Translate so the origin is at 0, permute so z is the largest |Q| component.
    let kz = shear.kz;
    let kx = if kz == 2 { 0 } else { kz + 1 };
    let ky = if kx == 2 { 0 } else { kx + 1 };
    out.permutation = Some([kx, ky, kz]);
    // [v.at(kx), v.at(ky), v.at(kz)], as a rotation of the components.
    let mut q = [
        (p[0] - ray.origin).rotate_last(kz),
        (p[1] - ray.origin).rotate_last(kz),
        (p[2] - ray.origin).rotate_last(kz),
    ];
    // Shear so the ray runs along +z.
    let [sx, sy, sz] = shear.s;
    for v in q.iter_mut() {
        v[0] = v[0] + sx * v[2];
        v[1] = v[1] + sy * v[2];
    }
    out.shear = Some([sx, sy, sz]);
    out.sheared = Some(q);
    // 2D edge functions.
    let mut e0 = difference_of_products(q[1][0], q[2][1], q[1][1], q[2][0]);
    let mut e1 = difference_of_products(q[2][0], q[0][1], q[2][1], q[0][0]);
    let mut e2 = difference_of_products(q[0][0], q[1][1], q[0][1], q[1][0]);
    // Exactly zero: recompute in f64 to decide the sign (a no-op refinement in f64 itself).
    if e0 == T::zero() || e1 == T::zero() || e2 == T::zero() {
        let w = |x: T| x.to_f64();
        let dop = |a: [T; 3], b: [T; 3]| T::from_f64(w(a[0]) * w(b[1]) - w(a[1]) * w(b[0]));
        e0 = dop(q[1], q[2]);
        e1 = dop(q[2], q[0]);
        e2 = dop(q[0], q[1]);
    }
    out.edges = Some([e0, e1, e2]);
    let zero = T::zero();
    if (e0 < zero || e1 < zero || e2 < zero) && (e0 > zero || e1 > zero || e2 > zero) {
        out.stopped_at = 8;
        return out;
    }
    let det = e0 + e1 + e2;
    out.det = det;
    if det == zero || !det.is_finite() {
        out.stopped_at = 2;
        return out;
    }
    // The shear's rounding depends on the *unscaled* z (x′ = x + Sx·z with |Sx| ≤ 1): keep it for
    // the error bound before z is rescaled into units of t. (pbrt-v4 uses the scaled z here, which
    // overstates the bound by 1/|Q_z| and rejects valid hits along short directions.)
    let max_z_unscaled = q[0][2].abs().max(q[1][2].abs()).max(q[2][2].abs());
    // Scaled distance, compared against the interval without dividing.
    for v in q.iter_mut() {
        v[2] = v[2] * sz;
    }
    out.z_scaled = Some([q[0][2], q[1][2], q[2][2]]);
    let t_scaled = e0 * q[0][2] + e1 * q[1][2] + e2 * q[2][2];
    out.dt = Some(t_scaled);
    let inv_det = T::one() / det;
    let t = t_scaled * inv_det;
    out.t_star = Some(t);
    let b1 = e1 * inv_det;
    let b2 = e2 * inv_det;
    out.u = Some(b1);
    out.v = Some(b2);
    if !ray.accepts(t) {
        out.stopped_at = 5;
        return out;
    }
    // pbrt-v4's conservative bound: t must exceed its own rounding error, so a ray leaving a
    // triangle never re-hits it at t ≈ 0.
    let max_zt = q[0][2].abs().max(q[1][2].abs()).max(q[2][2].abs());
    let delta_z = gamma::<T>(3) * max_zt;
    let max_xt = q[0][0].abs().max(q[1][0].abs()).max(q[2][0].abs());
    let max_yt = q[0][1].abs().max(q[1][1].abs()).max(q[2][1].abs());
    let delta_x = gamma::<T>(5) * (max_xt + max_z_unscaled);
    let delta_y = gamma::<T>(5) * (max_yt + max_z_unscaled);
    let delta_e =
        T::lit(2.0) * (gamma::<T>(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = e0.abs().max(e1.abs()).max(e2.abs());
    let delta_t = T::lit(3.0)
        * (gamma::<T>(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e)
        * inv_det.abs();
    if t <= delta_t {
        out.stopped_at = 5;
        return out;
    }
    out.stopped_at = 12;
    out.t = Some(t);
    out
}

/// The unnormalized geometric normal E1 × E2 (its direction follows the winding P0 → P1 → P2).
#[inline(always)]
pub fn normal<T: Real>(p: [T::V; 3]) -> T::V {
    (p[1] - p[0]).cross(p[2] - p[0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    // The Ray Tracer Challenge, ch. 15 ("Triangles"): p1 (0,1,0), p2 (−1,0,0), p3 (1,0,0).
    fn tri() -> [Vec3; 3] {
        [
            Vec3::new(0., 1., 0.),
            Vec3::new(-1., 0., 0.),
            Vec3::new(1., 0., 0.),
        ]
    }
    fn ray(o: [f32; 3], d: [f32; 3]) -> Ray<f32> {
        Ray::infinite(Vec3::from(o), Vec3::from(d)).unwrap()
    }

    #[test]
    fn rtc_triangle_vectors_both_methods() {
        for m in [TriangleMethod::MollerTrumbore, TriangleMethod::Watertight] {
            let parallel = intersect(&ray([0., -1., -2.], [0., 1., 0.]), tri(), m);
            assert!(parallel.t.is_none(), "{m:?}");
            for o in [[1., 1., -2.], [-1., 1., -2.], [0., -1., -2.]] {
                assert!(
                    intersect(&ray(o, [0., 0., 1.]), tri(), m).t.is_none(),
                    "{o:?} {m:?}"
                );
            }
            let hit = intersect(&ray([0., 0.5, -2.], [0., 0., 1.]), tri(), m);
            assert_eq!(hit.t, Some(2.0));
            assert_eq!(hit.stopped_at, 12);
            // RTC ch. 15 smooth triangles: ray (−0.2, 0.3, −2) → u = 0.45, v = 0.25.
            let uv = intersect(&ray([-0.2, 0.3, -2.], [0., 0., 1.]), tri(), m);
            assert!((uv.u.unwrap() - 0.45).abs() < 1e-6, "{m:?} {uv:?}");
            assert!((uv.v.unwrap() - 0.25).abs() < 1e-6);
        }
    }

    #[test]
    fn moller_trumbore_stops_where_the_seeds_say() {
        // Hand-computed: S = (0, 0.5, −2), Q = (0,0,1), P0 = (0,1,0), P1 = (−1,0,0), P2 = (1,0,0).
        // E1 = (−1,−1,0), E2 = (1,−1,0), −Q = (0,0,−1), E1×E2 = (0,0,2): D0 = −2.
        // T = (0,−0.5,−2): Dt = T·(E1×E2) = −4 → t* = 2; Du = −Q·(T×E2)=... u* = 0.25, v* = 0.25.
        let t = moller_trumbore(&ray([0., 0.5, -2.], [0., 0., 1.]), tri());
        assert_eq!(t.det, -2.0);
        assert_eq!(t.dt, Some(-4.0));
        assert_eq!(t.t_star, Some(2.0));
        assert_eq!(t.u, Some(0.25));
        assert_eq!(t.v, Some(0.25));
        // Parallel: stops at 2 with only D0.
        let p = moller_trumbore(&ray([0., -1., -2.], [0., 1., 0.]), tri());
        assert_eq!((p.stopped_at, p.dt), (2, None));
        // Behind: the triangle is at z = 0, origin at z = 2 looking +z → t* = −2, stop at 5.
        let b = moller_trumbore(&ray([0., 0.5, 2.], [0., 0., 1.]), tri());
        assert_eq!((b.stopped_at, b.t_star, b.du), (5, Some(-2.0), None));
        // Off the P1–P2 edge below: u* + v* computed... u = 0.75, v = 0.75 → stops at 11.
        let o = moller_trumbore(&ray([0., -0.5, -2.], [0., 0., 1.]), tri());
        assert_eq!(o.stopped_at, 11);
        // Far left: u* = (weight of P1) > 1 → stops at 8.
        let l = moller_trumbore(&ray([-3., 0.5, -2.], [0., 0., 1.]), tri());
        assert_eq!(l.stopped_at, 8);
    }

    #[test]
    fn degenerate_triangles_never_nan() {
        // S15: collinear, repeated and identical vertices.
        let degenerate = [
            [Vec3::ZERO, Vec3::X, Vec3::X * 2.0],
            [Vec3::ZERO, Vec3::ZERO, Vec3::Y],
            [Vec3::ONE; 3],
        ];
        for p in degenerate {
            for m in [TriangleMethod::MollerTrumbore, TriangleMethod::Watertight] {
                let t = intersect(&ray([0.2, 0.1, -1.], [0., 0., 1.]), p, m);
                assert!(t.t.is_none());
            }
        }
    }
}
