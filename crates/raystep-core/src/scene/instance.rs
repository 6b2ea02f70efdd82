//! Instances: a mesh, triangle or sphere defined once in its own object space and placed in the
//! world by a matrix, any number of times (`[[instance]]`). The two-level acceleration structure
//! of the ray-tracing APIs traces them: a bottom-level BVH (BLAS) per prototype, built once, and a
//! top-level BVH (TLAS) over the instances' world boxes ([`crate::accel::TwoLevel`]).
//!
//! A ray meets an instance in the instance's object space: its origin and direction are carried
//! there by the inverse matrix M⁻¹ (the direction is not renormalised, so the same t names the
//! same point in both spaces); the hit comes back with the point carried by M and the normal by
//! the inverse transpose M⁻ᵀ. The matrices are 3 × 4, rows, as Vulkan's `VkTransformMatrixKHR`
//! holds them; each product is written out in one order (x, then y, then z, then the
//! translation), so the math panel can repeat it exactly.

use crate::math::{Ray, gamma};
use glam::{DMat4, DVec3, Vec3};
use serde::{Deserialize, Serialize};

/// A 3 × 4 affine matrix, by rows: x′ = m₀₀x + m₀₁y + m₀₂z + m₀₃, and so on (the layout of
/// Vulkan's `VkTransformMatrixKHR`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Affine(pub [[f32; 4]; 3]);

impl Affine {
    /// The identity.
    pub const IDENTITY: Affine = Affine([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ]);

    /// The top three rows of an f64 matrix, each entry rounded to the nearest f32.
    pub fn from_dmat4(m: &DMat4) -> Affine {
        let r = |i: usize| {
            let row = m.row(i);
            [row.x as f32, row.y as f32, row.z as f32, row.w as f32]
        };
        Affine([r(0), r(1), r(2)])
    }

    /// The matrix in f64 (each entry exact).
    pub fn to_dmat4(&self) -> DMat4 {
        let r = |i: usize| self.0[i].map(f64::from);
        DMat4::from_cols_array_2d(&[r(0), r(1), r(2), [0.0, 0.0, 0.0, 1.0]]).transpose()
    }

    /// A point: M·p, each row ((m₀x + m₁y) + m₂z) + m₃.
    #[inline(always)]
    pub fn point(&self, p: Vec3) -> Vec3 {
        let r = |m: &[f32; 4]| m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3];
        Vec3::new(r(&self.0[0]), r(&self.0[1]), r(&self.0[2]))
    }

    /// A direction: the linear part alone, each row (m₀x + m₁y) + m₂z.
    #[inline(always)]
    pub fn vector(&self, v: Vec3) -> Vec3 {
        let r = |m: &[f32; 4]| m[0] * v.x + m[1] * v.y + m[2] * v.z;
        Vec3::new(r(&self.0[0]), r(&self.0[1]), r(&self.0[2]))
    }

    /// A normal by this matrix's transpose (of the linear part): with `self` = M⁻¹ this is
    /// M⁻ᵀ·n, the transform that keeps a normal perpendicular to the carried surface. Not
    /// renormalised.
    #[inline(always)]
    pub fn transpose_vector(&self, n: Vec3) -> Vec3 {
        let m = &self.0;
        let c = |j: usize| m[0][j] * n.x + m[1][j] * n.y + m[2][j] * n.z;
        Vec3::new(c(0), c(1), c(2))
    }

    /// With `self` = M⁻¹ and `n` a unit normal in object space: how many times larger a small
    /// patch of the surface there is in the world than in object space, |det M|·|M⁻ᵀn|
    /// (Nanson's formula), computed from M⁻¹ as |M⁻ᵀn| / |det M⁻¹| with
    /// det M⁻¹ = r₀·(r₁ × r₂) over its rows (glam's cross and dot, term for term). A ray cone
    /// divides a prototype's texel density by it to pick a mipmap level on a scaled instance.
    #[inline(always)]
    pub fn area_scale(&self, n: Vec3) -> f32 {
        let row = |i: usize| Vec3::new(self.0[i][0], self.0[i][1], self.0[i][2]);
        let det = row(0).dot(row(1).cross(row(2)));
        self.transpose_vector(n).length() / det.abs()
    }

    /// The rounding-error bound of [`Affine::point`] applied to a point `p` that itself carries
    /// the per-axis bound `error` (pbrt-v4's transformation of a `Point3fi`, in its "Managing Rounding Error"): (γ₃ + 1)·|M|·e +
    /// γ₃·(|m₀x| + |m₁y| + |m₂z| + |m₃|) per row.
    #[inline(always)]
    pub fn point_error(&self, p: Vec3, error: Vec3) -> Vec3 {
        let g3 = gamma::<f32>(3);
        let r = |m: &[f32; 4]| {
            let carried = m[0].abs() * error.x + m[1].abs() * error.y + m[2].abs() * error.z;
            let own = (m[0] * p.x).abs() + (m[1] * p.y).abs() + (m[2] * p.z).abs() + m[3].abs();
            (g3 + 1.0) * carried + g3 * own
        };
        Vec3::new(r(&self.0[0]), r(&self.0[1]), r(&self.0[2]))
    }

    /// A ray carried by this matrix: origin as a point, direction as a vector (not
    /// renormalised, so t means the same point before and after), t_min and t_max unchanged.
    #[inline(always)]
    pub fn ray(&self, r: &Ray<f32>) -> Ray<f32> {
        Ray {
            origin: self.point(r.origin),
            dir: self.vector(r.dir),
            t_min: r.t_min,
            t_max: r.t_max,
        }
    }
}

/// One placed copy of a prototype: a group of [`crate::scene::Scene::objects`] (a mesh, a
/// triangle or a sphere, in object space) and the matrices between its space and the world's.
#[derive(Debug, Clone, PartialEq)]
pub struct Instance {
    /// The name given in the file, or `instance i`.
    pub name: String,
    /// The prototype: index into [`crate::scene::Scene::groups`].
    pub group: u32,
    /// Index into [`crate::scene::Scene::prototypes`] (the BLAS it is traced with).
    pub prototype: u32,
    /// M: object space to world space.
    pub to_world: Affine,
    /// M⁻¹: world space to object space (inverted in f64 from the f64 matrix, then rounded).
    pub to_object: Affine,
    /// The world-space box of the placed prototype: its object box's eight corners carried by M
    /// in f64, rounded outwards.
    pub min: Vec3,
    /// See `min`.
    pub max: Vec3,
}

impl Instance {
    /// A prototype's shape carried to the world, for drawing: a triangle's vertices by M; a
    /// sphere's centre by M and its radius by M's largest axis scale (under a non-uniform scale
    /// the sphere that holds the ellipsoid the tracer sees: a bound; the 3D view draws the
    /// ellipsoid itself from M, [`crate::scene::Scene::placed_by`]); a plane unchanged
    /// (a prototype is never a plane).
    pub fn place(&self, shape: &crate::scene::Shape) -> crate::scene::Shape {
        use crate::scene::Shape;
        let m = &self.to_world;
        match *shape {
            Shape::Triangle { p } => Shape::Triangle {
                p: p.map(|v| m.point(v)),
            },
            Shape::Sphere { center, radius } => {
                let axis = |k: usize| {
                    m.vector(Vec3::from_array({
                        let mut a = [0.0; 3];
                        a[k] = 1.0;
                        a
                    }))
                    .length()
                };
                Shape::Sphere {
                    center: m.point(center),
                    radius: radius * axis(0).max(axis(1)).max(axis(2)),
                }
            }
            other => other,
        }
    }
}

/// [`crate::accel::Hit::instance`] of a hit on an object that is not instanced.
pub const NO_INSTANCE: u32 = u32::MAX;

/// A prototype: a group that instances place, with its object-space box.
#[derive(Debug, Clone, PartialEq)]
pub struct Prototype {
    /// Index into [`crate::scene::Scene::groups`].
    pub group: u32,
    /// The object-space box of its primitives.
    pub min: Vec3,
    /// See `min`.
    pub max: Vec3,
}

/// The world box of an object box [`min`, `max`] placed by `m` (f64), rounded outwards to f32
/// and widened by γ₄ of its magnitude (the slack of carrying rays in f32).
pub fn world_box(m: &DMat4, min: Vec3, max: Vec3) -> (Vec3, Vec3) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for k in 0..8 {
        let c = DVec3::new(
            if k & 1 == 0 { min.x } else { max.x } as f64,
            if k & 2 == 0 { min.y } else { max.y } as f64,
            if k & 4 == 0 { min.z } else { max.z } as f64,
        );
        let w = m.transform_point3(c);
        lo = lo.min(w);
        hi = hi.max(w);
    }
    let slack = lo.abs().max(hi.abs()) * f64::from(gamma::<f32>(4));
    let down = |x: f64| {
        let f = x as f32;
        if f as f64 > x { f.next_down() } else { f }
    };
    let up = |x: f64| {
        let f = x as f32;
        if (f as f64) < x { f.next_up() } else { f }
    };
    let lo = lo - slack;
    let hi = hi + slack;
    (
        Vec3::new(down(lo.x), down(lo.y), down(lo.z)),
        Vec3::new(up(hi.x), up(hi.y), up(hi.z)),
    )
}
