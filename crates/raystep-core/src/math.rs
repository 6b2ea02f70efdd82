//! Rays, the float abstraction the kernels are written against, and the float helpers
//! (γₙ error bounds, next-float steps) that the robust formulations need.
//!
//! The kernels in [`crate::shapes`] are generic over [`Real`] so that the *same* code runs in
//! f32 (the renderer's precision) and in f64 (the calculator's `--precision f64` and the
//! stability lab). glam provides the vectors: [`glam::Vec3`] for f32 and [`glam::DVec3`] for f64.

pub use glam::{DVec3, Vec3};
use std::fmt::Debug;
use std::ops::{Add, Mul, Neg, Sub};

/// A 3-vector of some [`Real`] precision (implemented by glam's `Vec3` and `DVec3`).
pub trait Vector<T>:
    Copy
    + Debug
    + PartialEq
    + Add<Output = Self>
    + Sub<Output = Self>
    + Neg<Output = Self>
    + Mul<T, Output = Self>
    + Send
    + Sync
    + 'static
{
    /// Builds a vector from components.
    fn new(x: T, y: T, z: T) -> Self;
    /// The dot product.
    fn dot(self, o: Self) -> T;
    /// The cross product.
    fn cross(self, o: Self) -> Self;
    /// Component `i` (0 = x, 1 = y, 2 = z).
    fn at(self, i: usize) -> T;
    /// The components rotated so that component `k` comes last: k = 0 → (y, z, x), 1 →
    /// (z, x, y), otherwise (x, y, z) — the watertight triangle test's permutation, as moves
    /// of whole components rather than three indexings by a run-time index.
    fn rotate_last(self, k: usize) -> [T; 3];
    /// Component-wise absolute value.
    fn abs(self) -> Self;
    /// Component-wise product.
    fn mul_elem(self, o: Self) -> Self;
    /// Euclidean length.
    fn length(self) -> T;
}

/// A floating-point precision the kernels can run in: `f32` or `f64`.
pub trait Real:
    num_traits::Float
    + Debug
    + Default
    + Send
    + Sync
    + serde::Serialize
    + crate::jsonf::JsonFloat
    + std::fmt::Display
    + 'static
{
    /// The matching glam vector type.
    type V: Vector<Self>;
    /// The unit roundoff u = 2^-p (2⁻²⁴ for f32, 2⁻⁵³ for f64).
    const UNIT_ROUNDOFF: Self;
    /// Name of the precision, as the command line spells it.
    const NAME: &'static str;
    /// Converts from f64 (rounding to nearest).
    fn from_f64(x: f64) -> Self;
    /// Widens to f64 (exact).
    fn to_f64(self) -> f64;
    /// The next representable value towards +∞.
    fn next_up(self) -> Self;
    /// The next representable value towards −∞.
    fn next_down(self) -> Self;
    /// Converts a literal.
    fn lit(x: f64) -> Self {
        Self::from_f64(x)
    }
}

macro_rules! impl_vector {
    ($v:ty, $t:ty) => {
        impl Vector<$t> for $v {
            #[inline(always)]
            fn new(x: $t, y: $t, z: $t) -> Self {
                <$v>::new(x, y, z)
            }
            #[inline(always)]
            fn dot(self, o: Self) -> $t {
                <$v>::dot(self, o)
            }
            #[inline(always)]
            fn cross(self, o: Self) -> Self {
                <$v>::cross(self, o)
            }
            #[inline(always)]
            fn at(self, i: usize) -> $t {
                self[i]
            }
            #[inline(always)]
            fn rotate_last(self, k: usize) -> [$t; 3] {
                match k {
                    0 => [self.y, self.z, self.x],
                    1 => [self.z, self.x, self.y],
                    _ => [self.x, self.y, self.z],
                }
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$v>::abs(self)
            }
            #[inline(always)]
            fn mul_elem(self, o: Self) -> Self {
                self * o
            }
            #[inline(always)]
            fn length(self) -> $t {
                <$v>::length(self)
            }
        }
    };
}
impl_vector!(Vec3, f32);
impl_vector!(DVec3, f64);

impl Real for f32 {
    type V = Vec3;
    const UNIT_ROUNDOFF: f32 = f32::EPSILON * 0.5;
    const NAME: &'static str = "f32";
    #[inline(always)]
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline(always)]
    fn next_up(self) -> Self {
        f32::next_up(self)
    }
    #[inline(always)]
    fn next_down(self) -> Self {
        f32::next_down(self)
    }
}

impl Real for f64 {
    type V = DVec3;
    const UNIT_ROUNDOFF: f64 = f64::EPSILON * 0.5;
    const NAME: &'static str = "f64";
    #[inline(always)]
    fn from_f64(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn next_up(self) -> Self {
        f64::next_up(self)
    }
    #[inline(always)]
    fn next_down(self) -> Self {
        f64::next_down(self)
    }
}

/// γₙ = n·u / (1 − n·u): the bound on the relative error of n floating-point operations
/// (Higham; pbrt-v4 §6.8.1). Used for ray-origin offsets and the slab test's t_far enlargement.
#[inline(always)]
pub fn gamma<T: Real>(n: u32) -> T {
    let nu = T::from_f64(n as f64) * T::UNIT_ROUNDOFF;
    nu / (T::one() - nu)
}

/// Converts a glam vector of any precision to an `[f64; 3]` (exact widening).
pub fn to_f64x3<T: Real>(v: T::V) -> [f64; 3] {
    [v.at(0).to_f64(), v.at(1).to_f64(), v.at(2).to_f64()]
}

/// The components of a vector, in its own precision.
pub fn to_array<T: Real>(v: T::V) -> [T; 3] {
    [v.at(0), v.at(1), v.at(2)]
}

/// Builds a vector of precision `T` from f64 components (rounding to nearest).
pub fn vec_from_f64<T: Real>(v: [f64; 3]) -> T::V {
    T::V::new(T::from_f64(v[0]), T::from_f64(v[1]), T::from_f64(v[2]))
}

/// Normalizes an f64 vector without overflow or underflow (scaling by its largest component
/// first); None for the zero vector or a non-finite one.
pub fn unit_f64(v: [f64; 3]) -> Option<[f64; 3]> {
    let m = v.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    if m == 0.0 || !m.is_finite() {
        return None;
    }
    let s = [v[0] / m, v[1] / m, v[2] / m];
    let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    Some([s[0] / len, s[1] / len, s[2] / len])
}

/// Why a ray could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RayError {
    /// The origin has a NaN or infinite component.
    #[error("ray origin {0:?} is not finite")]
    NonFiniteOrigin([f64; 3]),
    /// The direction has a NaN or infinite component.
    #[error("ray direction {0:?} is not finite")]
    NonFiniteDirection([f64; 3]),
    /// The direction is the zero vector (or so small that d·d underflows to zero).
    #[error("ray direction {0:?} is zero (or so small that d·d underflows)")]
    ZeroDirection([f64; 3]),
    /// The direction is so large that d·d overflows.
    #[error("ray direction {0:?} is too large (d·d overflows): scale it down")]
    HugeDirection([f64; 3]),
    /// t_min is NaN or negative, or t_max < t_min.
    #[error("bad ray interval [{0}, {1}]")]
    BadInterval(f64, f64),
}

/// A ray p(t) = S + t·Q with t in (t_min, t_max) — the notation of Bailey's notes
/// (docs/SOURCES.md): S the start, Q the direction.
///
/// A `Ray` can only be built through [`Ray::new`], which rejects non-finite or zero directions:
/// NaN rays "hit" every slab test (docs/NUMERICS.md, S25), so they must never reach a kernel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray<T: Real> {
    /// The ray's origin S.
    pub origin: T::V,
    /// The ray's direction Q (not necessarily unit length).
    pub dir: T::V,
    /// Hits at t ≤ t_min are ignored.
    pub t_min: T,
    /// Hits at t ≥ t_max are ignored.
    pub t_max: T,
}

impl<T: Real> Ray<T> {
    /// Makes a ray, rejecting non-finite origins, non-finite or zero directions, and bad intervals.
    #[inline]
    pub fn new(origin: T::V, dir: T::V, t_min: T, t_max: T) -> Result<Self, RayError> {
        let fin = |v: T::V| (0..3).all(|i| v.at(i).is_finite());
        let dd = dir.dot(dir);
        // The comparisons are false for NaN: a NaN bound fails here.
        let ok = fin(origin)
            && fin(dir)
            && dd != T::zero()
            && dd.is_finite()
            && t_min >= T::zero()
            && t_max >= t_min;
        if !ok {
            return Err(Self::rejection(origin, dir, t_min, t_max));
        }
        Ok(Ray {
            origin,
            dir,
            t_min,
            t_max,
        })
    }

    /// Why [`Ray::new`] refused: the first of its checks that fails. Kept out of line so that
    /// the tracer's hot path carries only the checks (a path tracer makes a ray or two a bounce).
    #[cold]
    #[inline(never)]
    fn rejection(origin: T::V, dir: T::V, t_min: T, t_max: T) -> RayError {
        let fin = |v: T::V| (0..3).all(|i| v.at(i).is_finite());
        if !fin(origin) {
            return RayError::NonFiniteOrigin(to_f64x3::<T>(origin));
        }
        if !fin(dir) {
            return RayError::NonFiniteDirection(to_f64x3::<T>(dir));
        }
        let dd = dir.dot(dir);
        if dd == T::zero() {
            return RayError::ZeroDirection(to_f64x3::<T>(dir));
        }
        if !dd.is_finite() {
            return RayError::HugeDirection(to_f64x3::<T>(dir));
        }
        RayError::BadInterval(t_min.to_f64(), t_max.to_f64())
    }

    /// A ray over (0, ∞).
    pub fn infinite(origin: T::V, dir: T::V) -> Result<Self, RayError> {
        Self::new(origin, dir, T::zero(), T::infinity())
    }

    /// The point S + t·Q.
    #[inline(always)]
    pub fn at(&self, t: T) -> T::V {
        self.origin + self.dir * t
    }

    /// Whether t lies strictly inside (t_min, t_max).
    #[inline(always)]
    pub fn accepts(&self, t: T) -> bool {
        t > self.t_min && t < self.t_max
    }
}

/// Normalizes a vector (f32 renderer helper); the caller guarantees it is non-zero.
#[inline(always)]
pub fn normalize(v: Vec3) -> Vec3 {
    v / v.length()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_rays() {
        let o = Vec3::ZERO;
        assert!(matches!(
            Ray::<f32>::infinite(o, Vec3::ZERO),
            Err(RayError::ZeroDirection(_))
        ));
        assert!(Ray::<f32>::infinite(o, Vec3::new(f32::NAN, 0.0, 1.0)).is_err());
        assert!(Ray::<f32>::infinite(Vec3::new(0.0, f32::INFINITY, 0.0), Vec3::Z).is_err());
        // 1e-30² underflows to zero in f32: rejected rather than producing 0/0 later.
        assert!(Ray::<f32>::infinite(o, Vec3::new(1e-30, 0.0, 0.0)).is_err());
        assert!(Ray::<f32>::new(o, Vec3::Z, 1.0, 0.5).is_err());
        assert!(Ray::<f32>::infinite(o, Vec3::Z).is_ok());
        // Each refusal names its reason, the first failing check in this order.
        let inf = f32::INFINITY;
        let why = |r: Result<Ray<f32>, RayError>| match r {
            Err(RayError::NonFiniteOrigin(_)) => "origin",
            Err(RayError::NonFiniteDirection(_)) => "direction",
            Err(RayError::ZeroDirection(_)) => "zero",
            Err(RayError::HugeDirection(_)) => "huge",
            Err(RayError::BadInterval(..)) => "interval",
            Ok(_) => "ok",
        };
        let nan = f32::NAN;
        assert_eq!(
            why(Ray::new(Vec3::splat(nan), Vec3::ZERO, -1.0, nan)),
            "origin"
        );
        assert_eq!(
            why(Ray::new(o, Vec3::new(0.0, inf, 0.0), nan, 0.0)),
            "direction"
        );
        assert_eq!(why(Ray::new(o, Vec3::ZERO, nan, 0.0)), "zero");
        // 1e20² overflows f32.
        assert_eq!(
            why(Ray::new(o, Vec3::new(1e20, 0.0, 0.0), 0.0, 1.0)),
            "huge"
        );
        for (t_min, t_max) in [(nan, 1.0), (0.0, nan), (-1.0, 1.0), (2.0, 1.0)] {
            assert_eq!(why(Ray::new(o, Vec3::Z, t_min, t_max)), "interval");
        }
        for (t_min, t_max) in [(0.0, 0.0), (0.0, inf), (1.0, 1.0), (-0.0, 1.0)] {
            assert_eq!(why(Ray::new(o, Vec3::Z, t_min, t_max)), "ok");
        }
    }

    #[test]
    fn gamma_matches_definition() {
        // γ₃ in f32: 3u/(1−3u) with u = 2⁻²⁴, ≈ 1.788e-7 (so 1 + 2γ₃ ≈ 1.000000358, docs/NUMERICS.md).
        let g: f32 = gamma(3);
        let u = 2f64.powi(-24);
        assert!((g as f64 - 3.0 * u / (1.0 - 3.0 * u)).abs() < 1e-12);
        assert!(((1.0 + 2.0 * g as f64) - 1.000000358).abs() < 1e-9);
    }
}
