//! Where a ray meets a surface: the hit point each shape computes from its own parametrization,
//! with its rounding-error bound (pbrt-v4 §6.8), the normal facing the ray, and where a spawned
//! ray starts ([`spawn_origin`], by the scene's offset policy). The Whitted tracer, the stability
//! lab and the benchmarks all spawn rays through this one file.

use crate::accel::Hit;
use crate::math::{Ray, gamma};
use crate::scene::{OffsetPolicy, Scene, Shape, Terminator};
use glam::Vec3;

/// Where a ray met a surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interaction {
    /// The hit point (re-projected onto the surface where the shape allows).
    pub point: Vec3,
    /// Unit normal facing the incoming ray.
    pub normal: Vec3,
    /// Unit vector from the point back towards the ray origin.
    pub eye: Vec3,
    /// Whether the ray hit the back (inside) of the surface.
    pub inside: bool,
    /// Per-axis bound on the point's rounding error.
    pub error: Vec3,
    /// Unit shading normal, on the same side as `normal`: a smooth triangle's vertex normals
    /// interpolated at the hit ([`interpolate_normal`]), else `normal` itself. Lighting,
    /// reflection, refraction and the BSDFs use it; which side a ray is on and where a spawned
    /// ray starts use `normal`.
    pub shading_normal: Vec3,
    /// Where rays leaving on the side of `shading_normal` start from before the offset: `point`,
    /// or on a smooth triangle under `terminator = "hanika"` the point lifted by [`lift_point`].
    pub lifted: Vec3,
    /// The rounding-error bound of `lifted` (`error`, plus half an ulp of its own sum where it
    /// was lifted).
    pub lifted_error: Vec3,
    /// The colour of the material's texture at the hit ([`crate::trace::texture`]), which
    /// multiplies the material's colour (and a Monte Carlo BSDF's albedo or tint); `None` for
    /// an untextured material. Set by the tracer's `surface`, which records the lookup.
    pub texel: Option<Vec3>,
    /// A glossy BSDF's roughness at the hit from the material's roughness texture
    /// ([`crate::scene::Material::roughness_at`]); `None` without one (or under Whitted).
    pub roughness: Option<f32>,
    /// The path length from the eye to the point, over every bounce: the previous hit's plus
    /// t·|Q| (a ray cone's width here is the camera's spread times it). Set by the tracer's
    /// `surface` in a scene with textures (0 in one without: nothing reads it there).
    pub distance: f32,
    /// The point in the object's own space: `point`, except on an instance, where it is the
    /// point before M carried it to the world (a texture sticks to the object by it).
    pub object_point: Vec3,
    /// The normal (facing the ray) in the object's own space: `normal`, except on an instance.
    pub object_normal: Vec3,
}

/// Computes the interaction at `hit`. Each shape computes the point from its own parametrization
/// where that is more accurate than S + tQ, with the error bound of pbrt-v4 (§6.8):
/// sphere — re-projected onto the sphere, bound γ₅|P − G| + γ₂|P|; triangle — from barycentrics,
/// bound γ₇ Σ|bᵢPᵢ|; axis-aligned plane — the coordinate snapped exactly (zero error on that axis);
/// general plane — re-projected, bound γ₇(|P| + |P·n||n| + |c||n|).
///
/// On an instance ([`Hit::instance`]) the interaction is computed in the prototype's object
/// space, with the ray carried there by M⁻¹ as the traversal carried it, then taken back by
/// [`to_world`].
#[inline(always)]
pub fn interact(scene: &Scene, hit: &Hit, ray: &Ray<f32>) -> Interaction {
    match scene.instance_of(hit) {
        None => interact_local(scene, hit, ray),
        Some(inst) => to_world(
            inst,
            &interact_local(scene, hit, &inst.to_object.ray(ray)),
            ray,
        ),
    }
}

/// An object-space interaction carried to the world by instance `inst`: points (the hit and
/// the lifted point) by M with their error bounds carried too (as pbrt-v4 transforms a `Point3fi`), normals by the
/// inverse transpose M⁻ᵀ and renormalised, the eye direction from the world ray.
#[inline(always)]
pub fn to_world(inst: &crate::scene::Instance, it: &Interaction, ray: &Ray<f32>) -> Interaction {
    let m = &inst.to_world;
    let normal = |n: Vec3| {
        let w = inst.to_object.transpose_vector(n);
        let len = w.length();
        if len.is_normal() { w / len } else { n }
    };
    let point = m.point(it.point);
    let error = m.point_error(it.point, it.error);
    let (lifted, lifted_error) = if it.lifted == it.point {
        (point, error)
    } else {
        (
            m.point(it.lifted),
            m.point_error(it.lifted, it.lifted_error),
        )
    };
    Interaction {
        point,
        normal: normal(it.normal),
        eye: -ray.dir / ray.dir.length(),
        inside: it.inside,
        error,
        shading_normal: normal(it.shading_normal),
        lifted,
        lifted_error,
        texel: it.texel,
        roughness: it.roughness,
        distance: it.distance,
        object_point: it.point,
        object_normal: it.normal,
    }
}

/// [`interact`] in the hit object's own space (the world's, for an object not instanced).
#[inline(always)]
fn interact_local(scene: &Scene, hit: &Hit, ray: &Ray<f32>) -> Interaction {
    let shape = &scene.objects[hit.object as usize].shape;
    let mut it = interact_shape(shape, hit, ray);
    if let Some(n) = scene.vertex_normals_of(hit.object) {
        let (normal, side) = blend_normals(n, hit.u, hit.v, it.normal);
        it.shading_normal = normal;
        if scene.settings.terminator == Terminator::Hanika
            && side != 0.0
            && let Shape::Triangle { p } = shape
        {
            let lifted = lift_point(p, n, hit.u, hit.v, it.point, side);
            if lifted != it.point {
                it.lifted = lifted;
                it.lifted_error = it.error + gamma::<f32>(1) * lifted.abs();
            }
        }
    }
    it
}

/// [`interpolate_normal`], and the sign that turned the blend to `facing` (1 or −1; 0 where the
/// normals cancelled and `facing` was used).
#[inline(always)]
fn blend_normals(n: &[Vec3; 3], u: f32, v: f32, facing: Vec3) -> (Vec3, f32) {
    let b0 = 1.0 - u - v;
    let s = n[0] * b0 + n[1] * u + n[2] * v;
    let len = s.length();
    if !len.is_normal() {
        return (facing, 0.0);
    }
    let unit = s / len;
    if unit.dot(facing) < 0.0 {
        (-unit, -1.0)
    } else {
        (unit, 1.0)
    }
}

/// Hanika's shading-point shift for the shadow terminator ("Hacking the shadow terminator", Ray
/// Tracing Gems II, ch. 4). Each vertex Pᵢ with its normal nᵢ (times `side`, so that it faces
/// the ray) defines a tangent plane of the curved surface the normals describe. Where the point
/// lies below a vertex's plane, dᵢ = (P − Pᵢ)·nᵢ < 0, it is raised onto it, P − dᵢ·nᵢ; where it
/// lies above, it stays. The three raised points are blended with the barycentrics:
/// P′ = P − (min(d₀, 0)·n₀·b₀ + min(d₁, 0)·n₁·u + min(d₂, 0)·n₂·v). On a convex patch P′ lies
/// above the flat triangle, towards the smooth surface, and a shadow ray from it clears the
/// neighbouring facets; on a flat or concave patch every dᵢ ≥ 0 and P′ = P exactly.
#[inline(always)]
pub fn lift_point(p: &[Vec3; 3], n: &[Vec3; 3], u: f32, v: f32, point: Vec3, side: f32) -> Vec3 {
    let b0 = 1.0 - u - v;
    let raise = |i: usize| {
        let ni = n[i] * side;
        ni * (point - p[i]).dot(ni).min(0.0)
    };
    point - (raise(0) * b0 + raise(1) * u + raise(2) * v)
}

/// Smooth shading: the vertex normals blended by the hit's barycentrics,
/// s = (1 − u − v)·n₀ + u·n₁ + v·n₂, then s / |s|, turned to the side of `facing` (the
/// geometric normal facing the ray) if it points away from it, so that a mesh whose winding
/// disagrees with its normals still shades its visible side. Where the three cancel (|s| is
/// zero or subnormal: normals that point opposite ways) the geometric normal `facing` is used.
/// The GPU's `interpolate_normal` is the same arithmetic in the same order.
#[inline(always)]
pub fn interpolate_normal(n: &[Vec3; 3], u: f32, v: f32, facing: Vec3) -> Vec3 {
    blend_normals(n, u, v, facing).0
}

/// [`interact`] for one shape, without a scene: the stability lab spawns rays from bare shapes
/// through this very code, so what it measures is what the renderer does.
#[inline(always)]
pub fn interact_shape(shape: &Shape, hit: &Hit, ray: &Ray<f32>) -> Interaction {
    let raw = ray.at(hit.t);
    let (point, outward, error) = match *shape {
        Shape::Sphere { center, radius } => {
            let rel = raw - center;
            let len = rel.length();
            let rel = if len > 0.0 { rel * (radius / len) } else { rel };
            let p = center + rel;
            (
                p,
                rel / radius,
                gamma::<f32>(5) * rel.abs() + gamma::<f32>(2) * p.abs(),
            )
        }
        Shape::Plane { normal, offset } => {
            let p = raw - normal * (raw.dot(normal) - offset);
            let e = gamma::<f32>(7)
                * (p.abs() + normal.abs() * (p.abs().dot(normal.abs()) + offset.abs()));
            (p, normal, e)
        }
        Shape::AxisPlane { axis, offset } => {
            let mut p = raw;
            p[axis] = offset;
            let mut n = Vec3::ZERO;
            n[axis] = 1.0;
            let mut e = gamma::<f32>(3) * p.abs();
            e[axis] = 0.0;
            (p, n, e)
        }
        Shape::Triangle { p } => {
            let b0 = 1.0 - hit.u - hit.v;
            let point = p[0] * b0 + p[1] * hit.u + p[2] * hit.v;
            let e =
                gamma::<f32>(7) * ((p[0] * b0).abs() + (p[1] * hit.u).abs() + (p[2] * hit.v).abs());
            (point, unit_normal(p[1] - p[0], p[2] - p[0]), e)
        }
    };
    let eye = -ray.dir / ray.dir.length();
    let inside = outward.dot(eye) < 0.0;
    Interaction {
        point,
        normal: if inside { -outward } else { outward },
        eye,
        inside,
        error,
        shading_normal: if inside { -outward } else { outward },
        lifted: point,
        lifted_error: error,
        texel: None,
        roughness: None,
        distance: 0.0,
        object_point: point,
        object_normal: if inside { -outward } else { outward },
    }
}

/// The angle between two unit vectors in degrees, computed in f64 as atan2(|a × b|, a · b)
/// (accurate at small angles, where acos(a · b) is not): the `ShadingNormal` step's angle,
/// recorded for the reader (nothing is computed from it), on the CPU and from a GPU trace alike.
pub fn angle_deg(a: Vec3, b: Vec3) -> f32 {
    let (a, b) = (a.as_dvec3(), b.as_dvec3());
    a.cross(b).length().atan2(a.dot(b)).to_degrees() as f32
}

/// The unit normal E1 × E2 / |E1 × E2| of a triangle's edges. For a triangle of vertices near
/// ±1e10 (inside the scene loader's bounds) |E1 × E2|² passes f32::MAX and the quotient is 0 or
/// NaN (and for a tiny one it underflows); then the edges are first scaled by the power of two that brings their largest component
/// to [1, 2) — exact, so the direction is the one E1 × E2 has. Every other triangle takes the
/// first branch, bit for bit as before (and as the GPU's `unit_normal`).
pub fn unit_normal(e1: Vec3, e2: Vec3) -> Vec3 {
    let n = e1.cross(e2);
    let len = n.length();
    if len.is_normal() {
        return n / len;
    }
    let m = e1.abs().max(e2.abs()).max_element();
    let exponent = ((m.to_bits() >> 23) & 0xff) as i32 - 127;
    if !(-126..=127).contains(&exponent) {
        return n / len;
    }
    let k = f32::from_bits(((127 - exponent) as u32) << 23);
    let n = (e1 * k).cross(e2 * k);
    n / n.length()
}

/// The smallest magnitude the robust offset leaves a moved coordinate at: 2⁻¹⁰⁰ ≈ 7.9e-31.
///
/// A point on a surface at a coordinate of exactly 0 (the floor y = 0 of most scenes) has no
/// rounding error there, so pbrt-v4's step to the next float takes it from 0 to 2⁻¹⁴⁹, the
/// smallest subnormal. Every ray from that floor then carried a subnormal in its origin into
/// every box and primitive test, and x86 processors compute with subnormals through a microcode
/// assist of about a hundred cycles an operation (a build that flushed subnormals to zero
/// rendered the path-traced Cornell box in 19 % less time and the soft-shadow scene in 33 %
/// less, the same images). A GPU that flushes subnormals read the 2⁻¹⁴⁹ as 0, starting the ray
/// on the surface itself. Stepping only to the smallest normal float, 2⁻¹²⁶, is not enough:
/// the triangle test multiplies the origin's offset by the shear (a factor below 1) and the
/// error bounds by γ terms, and those products were subnormal again (less than half the gain
/// on the soft-shadow scene). 2⁻¹⁰⁰ keeps such products normal down to factors of 2⁻²⁶, and is
/// far below any length a scene resolves: the triangle test's cubic terms already fall into
/// subnormals for features under 2⁻⁴² ≈ 2.3e-13 (`scene::limits`).
pub const OFFSET_FLOOR: f32 = f32::from_bits(0x0D80_0000);

/// The robust offset's last step kept clear of zero: a coordinate `x` that the step to the
/// next float (towards `sign`) left below [`OFFSET_FLOOR`] in magnitude becomes
/// `sign` · [`OFFSET_FLOOR`], further the same way — on the same side of the surface, by at
/// least the offset pbrt-v4's rule asks for.
#[inline(always)]
fn clear_of_zero(x: f32, sign: f32) -> f32 {
    if x.abs() < OFFSET_FLOOR {
        OFFSET_FLOOR.copysign(sign)
    } else {
        x
    }
}

/// The origin and t_min of a ray leaving `it` in direction `w`, by the scene's offset policy.
#[inline(always)]
pub fn spawn_origin(policy: OffsetPolicy, epsilon: f32, it: &Interaction, w: Vec3) -> Vec3 {
    let side = if w.dot(it.normal) >= 0.0 { 1.0 } else { -1.0 };
    // Rays on the shading normal's side leave from the lifted point (the terminator's fix; the
    // point itself elsewhere, and wherever nothing was lifted). A shadow ray near the terminator
    // may go below the flat triangle's plane (w·n < 0) while its light is above the smooth
    // surface (w·n_s > 0): it leaves from P′, offset to the side w goes.
    let (point, error) = if w.dot(it.shading_normal) >= 0.0 {
        (it.lifted, it.lifted_error)
    } else {
        (it.point, it.error)
    };
    match policy {
        OffsetPolicy::None => point,
        // RTC's over_point / under_point.
        OffsetPolicy::Fixed => point + it.normal * (epsilon * side),
        OffsetPolicy::Robust => {
            // pbrt-v4 OffsetRayOrigin: move |n|·error along n to the side w leaves on, then round
            // each moved coordinate one float further away so the offset survives the addition.
            // A step that ends within ±2⁻¹⁰⁰ of zero goes on to ±2⁻¹⁰⁰ (see `OFFSET_FLOOR`).
            let n = it.normal * side;
            let d = n.abs().dot(error);
            let mut o = point + n * d;
            for i in 0..3 {
                if n[i] > 0.0 {
                    o[i] = clear_of_zero(o[i].next_up(), 1.0);
                } else if n[i] < 0.0 {
                    o[i] = clear_of_zero(o[i].next_down(), -1.0);
                }
            }
            o
        }
    }
}
