//! Ray–sphere intersection: the course notes' quadratic (docs/SOURCES.md), and the stable form of
//! Ray Tracing Gems ch. 7.

use crate::math::{Ray, Real, Vector, to_array};
use serde::{Deserialize, Serialize};

/// How the quadratic is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum SphereMethod {
    /// The course notes' formula: a = d·d, b = 2 f·d, c = f·f − r², Δ = b² − 4ac, t = (−b ± √Δ)/2a.
    /// Loses the radius for far spheres (c cancels) and the near root of huge spheres (−b ± √Δ cancels).
    Textbook,
    /// Ray Tracing Gems ch. 7 (Haines, Günther, Akenine-Möller 2019): Δ′ from a vector difference,
    /// roots from q = b′ + sign(b′)·√(aΔ′) so that neither root subtracts nearly equal numbers.
    /// The renderer's default: docs/NUMERICS.md S1/S3 show the textbook form misclassifying far spheres
    /// and picking wrong near roots in f32, while this form stays within a few ulps.
    // Why the default (the stability lab, `raystep stability`, full suite, f32, exact
    // references): S1 (unit sphere 1e2…1e4 away) — textbook misclassifies 5128 of 16 000 rays
    // outside the rounding band (32%), stable 0, with t within 15 ulps (p99 2.6); S3 (huge
    // sphere, origin just above) — near-root error p99 4.3e6 ulps textbook against 3.9e5
    // stable (the rest is the rounding of O − G itself); no misclassification of stable on any
    // sphere case. The cost is a few ns per test more (13–25 ns against 12–16 ns).
    #[default]
    Stable,
}

/// The three cases of the discriminant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SphereCase {
    /// Δ < 0: the ray's line passes the sphere by.
    Miss,
    /// Δ = 0: the line touches the sphere in one point.
    Tangent,
    /// Δ > 0: the line enters and exits the sphere.
    EnterExit,
}

/// Which root was taken, and why.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RootChoice {
    /// No real roots.
    NoRoots,
    /// The smaller root lies in (t_min, t_max): the near side of the sphere.
    NearRoot,
    /// The smaller root is at or behind t_min (the origin is inside or on the sphere): the larger root.
    FarRoot,
    /// Both roots are at or behind t_min: the sphere is behind the ray.
    Behind,
    /// The nearest usable root is at or beyond t_max (something closer was already hit).
    BeyondTMax,
}

/// Every intermediate of one ray–sphere test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(bound(
    serialize = "T: crate::jsonf::JsonFloat",
    deserialize = "T: crate::jsonf::JsonFloat"
))]
pub struct SphereTest<T> {
    /// The method used.
    pub method: SphereMethod,
    /// a = d·d.
    #[serde(with = "crate::jsonf")]
    pub a: T,
    /// b = 2 f·d with f = S − G (reported in the course notes' form for both methods).
    #[serde(with = "crate::jsonf")]
    pub b: T,
    /// c = f·f − r².
    #[serde(with = "crate::jsonf")]
    pub c: T,
    /// The course notes' discriminant b² − 4ac (for `stable`, 4a·Δ′, the same quantity computed robustly).
    #[serde(with = "crate::jsonf")]
    pub discriminant: T,
    /// `stable` only: Δ′ = r² − ‖f − (f·d / a)·d‖², the squared distance margin of the ray's line.
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub delta_prime: Option<T>,
    /// `stable` only: q = b′ + sign(b′)·√(a·Δ′) with b′ = −f·d.
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub q: Option<T>,
    /// f = S − G, from the sphere's centre to the ray's origin, as the kernel computed it.
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub f: Option<[T; 3]>,
    /// Stable: b′ = −f·Q.
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub b_half: Option<T>,
    /// Stable: l = f + (b′/a)·Q, from the centre to the ray's line at right angles.
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub l: Option<[T; 3]>,
    /// Textbook: √Δ (None for a miss).
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub sqrt_discriminant: Option<T>,
    /// The two roots as computed, before they are put in order: textbook (−b − √Δ)/2a and
    /// (−b + √Δ)/2a, stable c/q and q/a (None for a miss).
    #[serde(
        with = "crate::jsonf",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub computed_roots: Option<[T; 2]>,
    /// The two roots in ascending order (equal when tangent), or none.
    #[serde(with = "crate::jsonf")]
    pub roots: Option<[T; 2]>,
    /// Which case of the discriminant this is.
    pub case: SphereCase,
    /// Which root was taken and why.
    pub choice: RootChoice,
    /// The hit distance, if a root lies in (t_min, t_max).
    #[serde(with = "crate::jsonf")]
    pub t: Option<T>,
    /// Whether the origin is inside the sphere (c < 0).
    pub inside: bool,
}

impl<T: Real> SphereTest<T> {
    /// The hit distance, if any.
    #[inline(always)]
    pub fn hit(&self) -> Option<T> {
        self.t
    }
}

/// Intersects `ray` with the sphere of centre `center` and radius `radius` by `method`.
#[inline(always)]
pub fn intersect<T: Real>(
    ray: &Ray<T>,
    center: T::V,
    radius: T,
    method: SphereMethod,
) -> SphereTest<T> {
    match method {
        SphereMethod::Textbook => textbook(ray, center, radius),
        SphereMethod::Stable => stable(ray, center, radius),
    }
}

/// The course notes' quadratic, exactly as taught.
#[inline(always)]
pub fn textbook<T: Real>(ray: &Ray<T>, center: T::V, radius: T) -> SphereTest<T> {
    let two = T::lit(2.0);
    let f = ray.origin - center;
    let a = ray.dir.dot(ray.dir);
    let b = two * f.dot(ray.dir);
    let c = f.dot(f) - radius * radius;
    let disc = b * b - T::lit(4.0) * a * c;
    let mut test = SphereTest {
        method: SphereMethod::Textbook,
        a,
        b,
        c,
        discriminant: disc,
        delta_prime: None,
        q: None,
        f: Some(to_array::<T>(f)),
        b_half: None,
        l: None,
        sqrt_discriminant: None,
        computed_roots: None,
        roots: None,
        case: SphereCase::Miss,
        choice: RootChoice::NoRoots,
        t: None,
        inside: c < T::zero(),
    };
    // A NaN discriminant (only possible from overflow to ∞ − ∞) is a miss.
    if disc.is_nan() || disc < T::zero() {
        return test;
    }
    let sq = disc.sqrt();
    let t0 = (-b - sq) / (two * a);
    let t1 = (-b + sq) / (two * a);
    test.sqrt_discriminant = Some(sq);
    test.computed_roots = Some([t0, t1]);
    finish(&mut test, ray, t0, t1);
    test
}

/// Ray Tracing Gems ch. 7, eq. 7.5–7.7 (see docs/NUMERICS.md).
#[inline(always)]
pub fn stable<T: Real>(ray: &Ray<T>, center: T::V, radius: T) -> SphereTest<T> {
    let f = ray.origin - center;
    let d = ray.dir;
    let a = d.dot(d);
    let fd = f.dot(d);
    let b_half = -fd; // b′
    let c = f.dot(f) - radius * radius;
    // ‖f − (f·d/a)·d‖²: the squared distance from the centre to the ray's line, from a vector
    // difference, so it keeps r² even when ‖f‖ ≫ r (where c above has already lost it).
    let l = f + d * (b_half / a);
    let delta_prime = radius * radius - l.dot(l);
    let disc = T::lit(4.0) * a * delta_prime;
    let mut test = SphereTest {
        method: SphereMethod::Stable,
        a,
        b: T::lit(2.0) * fd,
        c,
        discriminant: disc,
        delta_prime: Some(delta_prime),
        q: None,
        f: Some(to_array::<T>(f)),
        b_half: Some(b_half),
        l: Some(to_array::<T>(l)),
        sqrt_discriminant: None,
        computed_roots: None,
        roots: None,
        case: SphereCase::Miss,
        choice: RootChoice::NoRoots,
        t: None,
        inside: c < T::zero(),
    };
    if delta_prime.is_nan() || delta_prime < T::zero() {
        return test;
    }
    let sign = if b_half >= T::zero() {
        T::one()
    } else {
        -T::one()
    };
    let q = b_half + sign * (a * delta_prime).sqrt();
    test.q = Some(q);
    let (t0, t1) = if q == T::zero() {
        // b′ = 0 and Δ′ = 0: a tangent ray whose origin is the tangent point. c/q would be 0/0;
        // the single root is t = 0 (the closest point of the line is the origin itself).
        (T::zero(), T::zero())
    } else {
        (c / q, q / a)
    };
    test.computed_roots = Some([t0, t1]);
    finish(&mut test, ray, t0, t1);
    test
}

/// Orders the roots, classifies the case and chooses the root (shared by both methods).
#[inline(always)]
fn finish<T: Real>(test: &mut SphereTest<T>, ray: &Ray<T>, t0: T, t1: T) {
    let (lo, hi) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    test.roots = Some([lo, hi]);
    test.case = if test.discriminant == T::zero() {
        SphereCase::Tangent
    } else {
        SphereCase::EnterExit
    };
    if lo > ray.t_min {
        if lo < ray.t_max {
            test.choice = RootChoice::NearRoot;
            test.t = Some(lo);
        } else {
            test.choice = RootChoice::BeyondTMax;
        }
    } else if hi > ray.t_min {
        if hi < ray.t_max {
            test.choice = RootChoice::FarRoot;
            test.t = Some(hi);
        } else {
            test.choice = RootChoice::BeyondTMax;
        }
    } else {
        test.choice = RootChoice::Behind;
    }
}

/// The outward unit normal (X − G)/r at a point X on the sphere.
#[inline(always)]
pub fn normal<T: Real>(point: T::V, center: T::V, radius: T) -> T::V {
    (point - center) * (T::one() / radius)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn ray(o: [f32; 3], d: [f32; 3]) -> Ray<f32> {
        Ray::infinite(Vec3::from(o), Vec3::from(d)).unwrap()
    }

    // The Ray Tracer Challenge, ch. 5 ("Ray-Sphere Intersections"): unit sphere at the origin.
    #[test]
    fn rtc_sphere_vectors_both_methods() {
        for m in [SphereMethod::Textbook, SphereMethod::Stable] {
            let full = |o, d| {
                // The book reports both roots, including negative ones; ask with t_min = −∞-like.
                let r = Ray::new(Vec3::from(o), Vec3::from(d), 0.0, f32::INFINITY).unwrap();
                intersect(&r, Vec3::ZERO, 1.0, m)
            };
            assert_eq!(full([0., 0., -5.], [0., 0., 1.]).roots, Some([4.0, 6.0]));
            let tangent = full([0., 1., -5.], [0., 0., 1.]);
            assert_eq!(tangent.roots, Some([5.0, 5.0]));
            assert_eq!(tangent.case, SphereCase::Tangent);
            let miss = full([0., 2., -5.], [0., 0., 1.]);
            assert_eq!(miss.case, SphereCase::Miss);
            assert!(miss.discriminant < 0.0);
            assert_eq!(miss.t, None);
            let inside = full([0., 0., 0.], [0., 0., 1.]);
            assert_eq!(inside.roots, Some([-1.0, 1.0]));
            assert_eq!(inside.choice, RootChoice::FarRoot);
            assert_eq!(inside.t, Some(1.0));
            assert!(inside.inside);
            let behind = full([0., 0., 5.], [0., 0., 1.]);
            assert_eq!(behind.roots, Some([-6.0, -4.0]));
            assert_eq!(behind.choice, RootChoice::Behind);
        }
    }

    #[test]
    fn hand_computed_intermediates() {
        // S = (0,0,-5), Q = (0,0,1), unit sphere: f = S, a = 1, b = 2·(−5) = −10, c = 25 − 1 = 24,
        // Δ = 100 − 96 = 4 (stable: Δ′ = 1 − 0 = 1, 4aΔ′ = 4), roots (10 ∓ 2)/2 = 4, 6.
        for m in [SphereMethod::Textbook, SphereMethod::Stable] {
            let t = intersect(&ray([0., 0., -5.], [0., 0., 1.]), Vec3::ZERO, 1.0, m);
            assert_eq!((t.a, t.b, t.c, t.discriminant), (1.0, -10.0, 24.0, 4.0));
            assert_eq!(t.case, SphereCase::EnterExit);
            assert_eq!(t.choice, RootChoice::NearRoot);
            assert_eq!(t.t, Some(4.0));
        }
    }

    #[test]
    fn rtc_normals() {
        let s3 = 3f32.sqrt() / 3.0;
        let n = normal::<f32>(Vec3::splat(s3), Vec3::ZERO, 1.0);
        assert!((n - Vec3::splat(s3)).length() < 1e-6);
        assert_eq!(normal::<f32>(Vec3::X, Vec3::ZERO, 1.0), Vec3::X);
    }

    #[test]
    fn tangent_at_origin_no_nan() {
        // S6: origin at the tangent point, tangent direction: q = 0 → guarded, no NaN.
        let t = stable(&ray([1., 0., 0.], [0., 0., 1.]), Vec3::ZERO, 1.0);
        assert_eq!(t.q, Some(0.0));
        assert_eq!(t.roots, Some([0.0, 0.0]));
        assert_eq!(t.t, None);
    }

    #[test]
    fn far_sphere_textbook_fails_stable_holds() {
        // docs/NUMERICS.md S1: unit sphere at distance 4100 in f32. A ray aimed 0.5 off-centre must hit
        // (exact: the line passes at distance 0.5 < 1). c = 4100² − 1 rounds to 4100² in f32
        // (4100² = 16 810 000 > 2²⁴, ulp 2), so the textbook discriminant sees a sphere of radius 0.
        let r = ray([0.5, 0.0, -4100.0], [0., 0., 1.]);
        let tb = textbook(&r, Vec3::ZERO, 1.0);
        let st = stable(&r, Vec3::ZERO, 1.0);
        assert!(st.t.is_some());
        // exact near root: 4100 − √(1 − 0.25) = 4099.1339746
        assert!((st.t.unwrap() as f64 - (4100.0 - 0.75f64.sqrt())).abs() < 1e-3);
        assert!(tb.t.is_none() || (tb.t.unwrap() as f64 - (4100.0 - 0.75f64.sqrt())).abs() > 1e-3);
    }
}
