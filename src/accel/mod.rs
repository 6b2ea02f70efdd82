//! Finding the closest hit (and, for shadow rays, any hit), observed.
//!
//! [`test_object`] is the one place a primitive is tested: it runs the scene's chosen kernel and
//! hands the full test record to the observer. [`BruteForce`] is the seeds' naive loop — "for
//! each ray, for each primitive" — behind the [`Accelerator`] trait that the BVH also implements.

mod brute;

pub use brute::BruteForce;

use crate::math::Ray;
use crate::scene::{Scene, Shape};
use crate::shapes::{plane, sphere, triangle};
use crate::trace::{Observer, Step};

/// A hit: which object, where along the ray, and a triangle's barycentrics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Object id.
    pub object: u32,
    /// Distance along the ray.
    pub t: f32,
    /// Barycentric u (weight of P1) for triangles, 0 otherwise.
    pub u: f32,
    /// Barycentric v (weight of P2) for triangles, 0 otherwise.
    pub v: f32,
}

/// Something that finds hits along a ray.
pub trait Accelerator: Sync {
    /// The closest hit in (t_min, t_max), reporting every test to `obs`.
    fn closest<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit>;
    /// Any hit in (t_min, t_max) — the first found (shadow rays need no more).
    fn any<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit>;
    /// A short name for reports.
    fn name(&self) -> &'static str;
}

/// Tests object `id` with the scene's chosen method and reports the test to `obs`.
#[inline(always)]
pub fn test_object<O: Observer>(scene: &Scene, id: u32, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
    let s = &scene.settings;
    match scene.objects[id as usize].shape {
        Shape::Sphere { center, radius } => {
            let test = sphere::intersect(ray, center, radius, s.sphere_method);
            obs.prim_test(|| Step::Sphere { object: id, name: scene.object_name(id), test });
            test.t.map(|t| Hit { object: id, t, u: 0.0, v: 0.0 })
        }
        Shape::Plane { normal, offset } => {
            let test = plane::general(ray, normal, offset);
            obs.prim_test(|| Step::Plane { object: id, name: scene.object_name(id), test });
            test.t.map(|t| Hit { object: id, t, u: 0.0, v: 0.0 })
        }
        Shape::AxisPlane { axis, offset } => {
            let test = plane::axis(ray, axis, offset);
            obs.prim_test(|| Step::Plane { object: id, name: scene.object_name(id), test });
            test.t.map(|t| Hit { object: id, t, u: 0.0, v: 0.0 })
        }
        Shape::Triangle { p } => {
            let test = triangle::intersect(ray, p, s.triangle_method);
            obs.prim_test(|| Step::Triangle {
                object: id,
                name: scene.object_name(id),
                vertices: p.map(|v| v.to_array()),
                test,
            });
            match test.t {
                Some(t) => Some(Hit { object: id, t, u: test.u.unwrap_or(0.0), v: test.v.unwrap_or(0.0) }),
                None => None,
            }
        }
    }
}

/// Records that `hit` became the closest so far.
#[inline(always)]
pub fn accept<O: Observer>(scene: &Scene, hit: &Hit, previous: f32, obs: &mut O) {
    obs.step(|| Step::Accept { object: hit.object, name: scene.object_name(hit.object), t: hit.t, previous });
}
