//! The Monte Carlo formulas under test, each in a textbook and a stable form, generic over the
//! precision (f32 or f64). The textbook forms are the lab's own code, written as courses teach
//! them; docs/NUMERICS.md derives the stable ones.

use super::McMethod;
use crate::math::Real;

fn lit<T: Real>(x: f64) -> T {
    T::from_f64(x)
}

fn pi<T: Real>() -> T {
    lit(std::f64::consts::PI)
}

/// S26: a sphere light of radius `r` seen from distance `d`, sampled uniformly in its cone with
/// the uniform number `u`: [1 − cos θmax, the pdf 1/(2π(1 − cos θmax)), the sampled cos θ,
/// its sin θ].
///
/// - Textbook: cos θmax = √(1 − s), s = r²/d², then 1 − cos θmax (cancels for a small cone);
///   cos θ = 1 − u(1 − cos θmax); sin θ = √(1 − cos²θ) (cancels again).
/// - Stable: 1 − cos θmax = s/(1 + √(1 − s)); with x = u(1 − cos θmax), cos θ = 1 − x and
///   sin²θ = x(2 − x).
#[inline(always)]
pub fn cone<T: Real>(m: McMethod, d: T, r: T, u: T) -> [T; 4] {
    let one = T::one();
    let s = (r / d) * (r / d);
    let one_minus_cos_max = match m {
        McMethod::Textbook => one - (one - s).max(T::zero()).sqrt(),
        McMethod::Stable => s / (one + (one - s).max(T::zero()).sqrt()),
    };
    let pdf = one / (lit::<T>(2.0) * pi::<T>() * one_minus_cos_max);
    let x = u * one_minus_cos_max;
    let cos = one - x;
    let sin = match m {
        McMethod::Textbook => (one - cos * cos).max(T::zero()).sqrt(),
        McMethod::Stable => (x * (lit::<T>(2.0) - x)).max(T::zero()).sqrt(),
    };
    [one_minus_cos_max, pdf, cos, sin]
}

/// S27: a GGX microfacet normal sampled with roughness α (Walter et al. 2007) from the uniform
/// number `u`, at azimuth (cos φ, sin φ), and the reflection's density seen from `wo`:
/// [sin θh, D(h), the pdf D(h)·cos θh/(4 ωo·h)].
///
/// Both: tan²θh = α²u/(1 − u), cos θh = 1/√(1 + tan²θh).
/// - Textbook: sin θh = √(1 − cos²θh); D = α²/(π((α² − 1)cos²θh + 1)²).
/// - Stable: sin θh = √(tan²θh)·cos θh; D = α²/(π(α²cos²θh + sin²θh)²).
#[inline(always)]
pub fn ggx<T: Real>(m: McMethod, alpha: T, u: T, cphi: T, sphi: T, wo: [T; 3]) -> [T; 3] {
    let one = T::one();
    let a2 = alpha * alpha;
    let tan2 = a2 * u / (one - u);
    let cos = one / (one + tan2).sqrt();
    let (sin, den) = match m {
        McMethod::Textbook => (
            (one - cos * cos).max(T::zero()).sqrt(),
            (a2 - one) * cos * cos + one,
        ),
        McMethod::Stable => {
            let sin = tan2.sqrt() * cos;
            (sin, a2 * cos * cos + sin * sin)
        }
    };
    let d = a2 / (pi::<T>() * den * den);
    let wo_h = wo[0] * (sin * cphi) + wo[1] * (sin * sphi) + wo[2] * cos;
    let pdf = d * cos / (lit::<T>(4.0) * wo_h);
    [sin, d, pdf]
}

/// a·b as the sum `p` and its rounding error `e` (exact, with a fused multiply–add).
fn two_prod<T: Real>(a: T, b: T) -> (T, T) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// a + b as the sum `s` and its rounding error `e` (Knuth's TwoSum, exact).
fn two_sum<T: Real>(a: T, b: T) -> (T, T) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// The plain dot product: three roundings of products, two of sums.
fn dot<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The compensated dot product (Ogita, Rump and Oishi 2005, Dot2): as accurate as the plain one
/// computed in twice the precision, then rounded — a grazing cos θ keeps its digits.
pub fn dot2<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    let (mut p, mut s) = two_prod(a[0], b[0]);
    for i in 1..3 {
        let (h, r) = two_prod(a[i], b[i]);
        let (sum, q) = two_sum(p, h);
        p = sum;
        s = s + (q + r);
    }
    p + s
}

/// S28: grazing directions. `w` is a unit direction nearly perpendicular to the unit normal `n`;
/// `d` is the offset from a shading point to a point on an emitting triangle of area `area`
/// whose normal is `n`, seen nearly edge-on; `u` makes a cosine-weighted direction near the
/// horizon: [the cosine-hemisphere pdf (w·n)/π, the light's pdf per steradian
/// |d|²/(area · cos θl), the sampled direction's cos θ].
///
/// - Textbook: cos θ = w·n; cos θl = −(d/|d|)·n; the sampled cos θ = √(1 − x² − y²) from the
///   concentric disk's point (x, y).
/// - Stable: the same dot products compensated ([`dot2`]); cos θl = −(d·n)/|d|; the sampled
///   cos θ = √((1 − r)(1 + r)) from the disk point's radius r = max(|2u₀ − 1|, |2u₁ − 1|).
#[inline(always)]
pub fn grazing<T: Real>(
    m: McMethod,
    w: [T; 3],
    n: [T; 3],
    d: [T; 3],
    area: T,
    u: [T; 2],
) -> [T; 3] {
    let dist = dot(d, d).sqrt();
    let one = T::one();
    let (a, b) = (lit::<T>(2.0) * u[0] - one, lit::<T>(2.0) * u[1] - one);
    let (cos, cos_l, z) = match m {
        McMethod::Textbook => {
            let wi = [d[0] / dist, d[1] / dist, d[2] / dist];
            // Shirley and Chiu's concentric map, as sample::concentric_disk.
            let quarter = pi::<T>() / lit::<T>(4.0);
            let (r, theta) = if a.abs() > b.abs() {
                (a, quarter * (b / a))
            } else {
                (b, lit::<T>(2.0) * quarter - quarter * (a / b))
            };
            let (x, y) = (r * theta.cos(), r * theta.sin());
            let z = (one - x * x - y * y).max(T::zero()).sqrt();
            (dot(w, n), -dot(wi, n), z)
        }
        McMethod::Stable => {
            let r = a.abs().max(b.abs());
            let z = ((one - r) * (one + r)).max(T::zero()).sqrt();
            (dot2(w, n), -dot2(d, n) / dist, z)
        }
    };
    [cos / pi::<T>(), dist * dist / (area * cos_l), z]
}

/// The stable rows in f32 through raystep's own kernels where their signatures allow
/// ([`crate::mc::sample`]): the same outputs as the generic kernels, from the f64 inputs (exact in
/// f32). S26: `cone_one_minus_cos` and `sphere_cone` (azimuth 0: the direction is
/// (sin θ, 0, cos θ)); S27: `ggx_normal` (azimuth 0) for sin θh and cos θh, `ggx_d` for D, ωo·h
/// as the generic kernel forms it; S28's sampled cos θ: `cosine_hemisphere`, the two pdfs the
/// lab's (raystep's `bsdf::pdf` and `Lights::pdf` take cos θ as a plain dot product); S29:
/// `triangle_area`.
pub mod raystep {
    use crate::mc::sample::{
        cone_one_minus_cos, cosine_hemisphere, ggx_d, ggx_normal, sphere_cone, triangle_area,
    };
    use glam::Vec3;

    /// S26: [1 − cos θmax, pdf, cos θ, sin θ] (NaN where `sphere_cone` gives nothing).
    pub fn cone(d: f32, r: f32, u: f32) -> [f32; 4] {
        let (x, _) = cone_one_minus_cos(d, r);
        match sphere_cone(d, r, [u, 0.0]) {
            Some(s) => [x, s.pdf, s.value.z, s.value.x],
            None => [x, f32::NAN, f32::NAN, f32::NAN],
        }
    }

    /// S27: [sin θh, D(h), D(h)·cos θh/(4 ωo·h)].
    pub fn ggx(alpha: f32, u: f32, cphi: f32, sphi: f32, wo: [f32; 3]) -> [f32; 3] {
        let h = ggx_normal(alpha, [u, 0.0]).value;
        let (sin, cos) = (h.x, h.z);
        let d = ggx_d(alpha, cos, sin * sin);
        let wo_h = wo[0] * (sin * cphi) + wo[1] * (sin * sphi) + wo[2] * cos;
        [sin, d, d * cos / (4.0 * wo_h)]
    }

    /// S28's sampled cos θ.
    pub fn cosine_z(u: [f32; 2]) -> f32 {
        cosine_hemisphere(u).value.z
    }

    /// S29.
    pub fn area(p: [[f32; 3]; 3]) -> f32 {
        triangle_area(p.map(Vec3::from))
    }
}

/// S29: the area ½|(P1 − P0) × (P2 − P0)| of an emitting triangle.
///
/// - Textbook: in the precision itself (in f32 the squared length overflows for vertices near
///   ±1e10, and underflows for edges below about 1e-10).
/// - Stable: the same computed in f64 and rounded to the precision.
#[inline(always)]
pub fn area<T: Real>(m: McMethod, p: [[T; 3]; 3]) -> T {
    fn half_cross<F: Real>(p: [[F; 3]; 3]) -> F {
        let e1 = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
        let e2 = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
        let c = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        F::from_f64(0.5) * dot(c, c).sqrt()
    }
    match m {
        McMethod::Textbook => half_cross(p),
        McMethod::Stable => T::from_f64(half_cross(p.map(|v| v.map(|x| x.to_f64())))),
    }
}
