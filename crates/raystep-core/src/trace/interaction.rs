//! Where a ray meets a surface: the hit point each shape computes from its own parametrization,
//! with its rounding-error bound (pbrt-v4 §6.8), the normal facing the ray, and where a spawned
//! ray starts ([`spawn_origin`], by the scene's offset policy). The Whitted tracer, the stability
//! lab and the benchmarks all spawn rays through this one file.

use crate::accel::Hit;
use crate::math::{Ray, gamma};
use crate::scene::{OffsetPolicy, Scene, Shape};
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
}

/// Computes the interaction at `hit`. Each shape computes the point from its own parametrization
/// where that is more accurate than S + tQ, with the error bound of pbrt-v4 (§6.8):
/// sphere — re-projected onto the sphere, bound γ₅|P − G| + γ₂|P|; triangle — from barycentrics,
/// bound γ₇ Σ|bᵢPᵢ|; axis-aligned plane — the coordinate snapped exactly (zero error on that axis);
/// general plane — re-projected, bound γ₇(|P| + |P·n||n| + |c||n|).
#[inline(always)]
pub fn interact(scene: &Scene, hit: &Hit, ray: &Ray<f32>) -> Interaction {
    interact_shape(&scene.objects[hit.object as usize].shape, hit, ray)
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
    }
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

/// The origin and t_min of a ray leaving `it` in direction `w`, by the scene's offset policy.
#[inline(always)]
pub fn spawn_origin(policy: OffsetPolicy, epsilon: f32, it: &Interaction, w: Vec3) -> Vec3 {
    let side = if w.dot(it.normal) >= 0.0 { 1.0 } else { -1.0 };
    match policy {
        OffsetPolicy::None => it.point,
        // RTC's over_point / under_point.
        OffsetPolicy::Fixed => it.point + it.normal * (epsilon * side),
        OffsetPolicy::Robust => {
            // pbrt-v4 OffsetRayOrigin: move |n|·error along n to the side w leaves on, then round
            // each moved coordinate one float further away so the offset survives the addition.
            let n = it.normal * side;
            let d = n.abs().dot(it.error);
            let mut o = it.point + n * d;
            for i in 0..3 {
                if n[i] > 0.0 {
                    o[i] = o[i].next_up();
                } else if n[i] < 0.0 {
                    o[i] = o[i].next_down();
                }
            }
            o
        }
    }
}
