//! Whitted's integrator (1980): at each hit Phong's local model with a shadow ray per point
//! light, then a mirror ray and a refraction ray weighted by the material's reflectivity and
//! transparency (blended by Schlick's reflectance where both are present), recursing up to
//! `max_depth` or until a ray's weight falls below [`WEIGHT_CUTOFF`]. The stages a scene does not
//! use (shadows, reflection, refraction) are compiled out of its tracing loop.
//!
//! [`WEIGHT_CUTOFF`]: super::tracer::WEIGHT_CUTOFF

use super::interaction::spawn_origin;
use super::media::Media;
use super::sampling::sample_offset;
use super::shading::{critical_angle_deg, phong, reflect_recorded, refract, schlick_recorded};
use super::tracer::{SHADOW_EPSILON, Tracer, WEIGHT_CUTOFF};
use crate::accel::{Accelerator, Hit};
use crate::math::Ray;
use crate::record::observer::Observer;
use crate::record::{RayKind, Step};
use glam::Vec3;

/// Calls `$self.$f::<O, L, R, T>($args)` with the const flags matching `$self.stages`.
macro_rules! specialized {
    ($self:ident . $f:ident ::<$o:ty>($($arg:expr),*)) => {
        match $self.stages {
            (false, false, false) => $self.$f::<$o, false, false, false>($($arg),*),
            (false, false, true) => $self.$f::<$o, false, false, true>($($arg),*),
            (false, true, false) => $self.$f::<$o, false, true, false>($($arg),*),
            (false, true, true) => $self.$f::<$o, false, true, true>($($arg),*),
            (true, false, false) => $self.$f::<$o, true, false, false>($($arg),*),
            (true, false, true) => $self.$f::<$o, true, false, true>($($arg),*),
            (true, true, false) => $self.$f::<$o, true, true, false>($($arg),*),
            (true, true, true) => $self.$f::<$o, true, true, true>($($arg),*),
        }
    };
}

impl<A: Accelerator> Tracer<'_, A> {
    /// Traces sample `sample` of pixel (x, y) with Whitted's integrator, its stages specialized
    /// to the scene's ([`Tracer::stages`]).
    #[inline(always)]
    pub(crate) fn whitted_sample<O: Observer>(
        &self,
        x: u32,
        y: u32,
        sample: u32,
        obs: &mut O,
    ) -> Vec3 {
        specialized!(self.sample_spec::<O>(x, y, sample, obs))
    }

    fn sample_spec<O: Observer, const L: bool, const R: bool, const T: bool>(
        &self,
        x: u32,
        y: u32,
        sample: u32,
        obs: &mut O,
    ) -> Vec3 {
        let s = &self.scene.settings;
        let offset = sample_offset(x, y, sample, s.spp, s.seed);
        let (ray, screen) = self.camera.ray(x, y, offset);
        obs.begin_ray(RayKind::Primary, 0, &ray, 1.0);
        obs.step(|| Step::Camera {
            pixel: [x, y],
            sample,
            offset,
            screen,
            direction: ray.dir.to_array(),
        });
        let (color, hit) = self.shade_ray::<O, L, R, T>(&ray, 0, 1.0, 0.0, Media::default(), obs);
        obs.end_ray(|| self.hit_record(hit), color);
        color
    }

    /// Traces an arbitrary ray as a primary ray (depth 0, in air) and returns its colour.
    /// Used by tests with The Ray Tracer Challenge's rays, and by the exercises.
    pub fn trace_ray<O: Observer>(&self, ray: &Ray<f32>, obs: &mut O) -> Vec3 {
        specialized!(self.primary_spec::<O>(ray, obs))
    }

    fn primary_spec<O: Observer, const L: bool, const R: bool, const T: bool>(
        &self,
        ray: &Ray<f32>,
        obs: &mut O,
    ) -> Vec3 {
        self.trace_child::<O, L, R, T>(
            ray,
            RayKind::Primary,
            0,
            1.0,
            1.0,
            0.0,
            Media::default(),
            obs,
        )
    }

    /// Traces a secondary ray as a child of the current one.
    // The recursion's state (depth, weights, media) is passed by value, one argument each, so
    // every level has its own copy.
    #[allow(clippy::too_many_arguments)]
    fn trace_child<O: Observer, const L: bool, const R: bool, const T: bool>(
        &self,
        ray: &Ray<f32>,
        kind: RayKind,
        depth: u32,
        weight: f32,
        throughput: f32,
        travelled: f32,
        media: Media,
        obs: &mut O,
    ) -> Vec3 {
        obs.begin_ray(kind, depth, ray, weight);
        let (color, hit) =
            self.shade_ray::<O, L, R, T>(ray, depth, throughput, travelled, media, obs);
        obs.end_ray(|| self.hit_record(hit), color);
        color
    }

    /// Finds the closest hit and shades it (the body of a colour ray). `throughput`: what the
    /// ray's colour is multiplied by on its way to the pixel; `travelled`: the path length from
    /// the eye to the ray's origin (a ray cone's distance).
    fn shade_ray<O: Observer, const L: bool, const R: bool, const T: bool>(
        &self,
        ray: &Ray<f32>,
        depth: u32,
        throughput: f32,
        travelled: f32,
        media: Media,
        obs: &mut O,
    ) -> (Vec3, Option<Hit>) {
        self.closest_then(ray, obs, |hit, obs| {
            self.shade::<O, L, R, T>(hit, ray, depth, throughput, travelled, media, obs)
        })
    }

    /// Shades a hit. `L`, `R`, `T`: whether shadow rays, reflection and refraction are compiled in.
    #[allow(clippy::too_many_arguments)]
    fn shade<O: Observer, const L: bool, const R: bool, const T: bool>(
        &self,
        hit: &Hit,
        ray: &Ray<f32>,
        depth: u32,
        throughput: f32,
        travelled: f32,
        media: Media,
        obs: &mut O,
    ) -> Vec3 {
        let scene = self.scene;
        let s = &scene.settings;
        let m = scene.material_of(hit.object);
        let it = self.surface(hit, ray, travelled, obs);
        let color = it.texel.map_or(m.color, |t| m.color * t);

        // Direct light: Phong from each light, ambient only where a shadow ray is blocked.
        let mut surface = Vec3::ZERO;
        if !L || scene.lights.is_empty() {
            // No lights: show the ambient colour rather than black (a scene with no lights still
            // shows its shapes).
            surface = color * m.ambient;
        }
        for (li, light) in scene
            .lights
            .iter()
            .enumerate()
            .take(if L { usize::MAX } else { 0 })
        {
            let to_light = light.position - it.point;
            // A light behind the surface contributes only ambient, shadowed or not: no shadow ray.
            let facing = to_light.dot(it.shading_normal) > 0.0;
            let mut blocker = None;
            if facing {
                obs.step(|| Step::ShadowRay {
                    light: li as u32,
                    name: light.name.clone(),
                    distance: to_light.length(),
                });
                let o = spawn_origin(s.offset, s.epsilon, &it, to_light);
                if let Ok(shadow) = Ray::new(o, light.position - o, 0.0, 1.0 - SHADOW_EPSILON) {
                    obs.begin_ray(RayKind::Shadow, depth + 1, &shadow, 0.0);
                    blocker = self.accel.any(scene, &shadow, obs);
                    obs.end_ray(|| self.hit_record(blocker), Vec3::ZERO);
                }
            }
            let terms = phong(
                m,
                color,
                light.position,
                light.color,
                it.point,
                it.eye,
                it.shading_normal,
                blocker.is_some(),
            );
            obs.step(|| Step::Light {
                light: li as u32,
                name: light.name.clone(),
                blocked: blocker.is_some(),
                blocker: blocker.map(|b| scene.object_name(b.object)),
                l_dot_n: terms.l_dot_n,
                r_dot_e: terms.r_dot_e,
                ambient: terms.ambient.to_array(),
                diffuse: terms.diffuse.to_array(),
                specular: terms.specular.to_array(),
                light_dir: Some(terms.light_dir.to_array()),
                reflected: Some(terms.reflected.to_array()),
                eye: Some(it.eye.to_array()),
                total: Some(terms.sum().to_array()),
            });
            surface += terms.sum();
        }

        let can_recurse = depth < s.max_depth;
        // Snell and Schlick come first: the reflection's share of the pixel depends on the
        // reflectance (their steps are recorded where they were, after the reflection).
        let transparent = T && m.transparency > 0.0;
        let blend = transparent && R && m.reflective > 0.0;
        let snell = transparent.then(|| {
            let (n1, n2) = media.indices(hit.object, m.refractive_index);
            (n1, n2, refract(it.eye, it.shading_normal, n1, n2))
        });
        let fresnel = match snell {
            Some((n1, n2, refr)) if blend => Some(schlick_recorded(refr.cos_i, n1, n2)),
            _ => None,
        };
        let reflectance = fresnel.map_or(1.0, |f| f.reflectance);
        // Each child's share of the pixel, as the GPU tracer computes it (same operations, same
        // order, so both cut the same rays).
        let cut = |kind: RayKind, share: f32, obs: &mut O| -> bool {
            let contribution = throughput * share;
            let below = contribution < WEIGHT_CUTOFF;
            if below {
                obs.step(|| Step::WeightCutoff {
                    kind,
                    contribution,
                    cutoff: WEIGHT_CUTOFF,
                });
            }
            below
        };
        // Reflection.
        let mut reflected = Vec3::ZERO;
        if R && m.reflective > 0.0 {
            if can_recurse {
                let (d_dot_n, dir) = reflect_recorded(ray.dir, it.shading_normal);
                obs.step(|| Step::Reflect {
                    reflective: m.reflective,
                    direction: dir.to_array(),
                    d_dot_n: Some(d_dot_n),
                });
                let share = if blend {
                    m.reflective * reflectance
                } else {
                    m.reflective
                };
                if !cut(RayKind::Reflection, share, obs) {
                    let o = spawn_origin(s.offset, s.epsilon, &it, dir);
                    // dir is a reflection of a valid direction: finite and non-zero.
                    let r = Ray {
                        origin: o,
                        dir,
                        t_min: 0.0,
                        t_max: f32::INFINITY,
                    };
                    reflected = self.trace_child::<O, L, R, T>(
                        &r,
                        RayKind::Reflection,
                        depth + 1,
                        m.reflective,
                        throughput * share,
                        it.distance,
                        media,
                        obs,
                    ) * m.reflective;
                }
            } else {
                obs.step(|| Step::DepthLimit {
                    max_depth: s.max_depth,
                });
            }
        }
        // Refraction.
        if let Some((n1, n2, refr)) = snell {
            let mut refracted = Vec3::ZERO;
            if can_recurse {
                obs.step(|| Step::Refract {
                    n1,
                    n2,
                    cos_i: refr.cos_i,
                    sin2_t: refr.sin2_t,
                    critical_angle_deg: critical_angle_deg(n1, n2),
                    total_internal_reflection: refr.direction.is_none(),
                    direction: refr.direction.map(|d| d.to_array()),
                    eta: Some(refr.eta),
                    eye: Some(it.eye.to_array()),
                    cos_t: refr.cos_t,
                });
                let share = if blend {
                    m.transparency * (1.0 - reflectance)
                } else {
                    m.transparency
                };
                if let Some(dir) = refr.direction
                    && let Ok(r) = Ray::new(
                        spawn_origin(s.offset, s.epsilon, &it, dir),
                        dir,
                        0.0,
                        f32::INFINITY,
                    )
                    && !cut(RayKind::Refraction, share, obs)
                {
                    let inner = media.crossed(hit.object, m.refractive_index);
                    refracted = self.trace_child::<O, L, R, T>(
                        &r,
                        RayKind::Refraction,
                        depth + 1,
                        m.transparency,
                        throughput * share,
                        it.distance,
                        inner,
                        obs,
                    ) * m.transparency;
                }
            } else if m.reflective == 0.0 {
                obs.step(|| Step::DepthLimit {
                    max_depth: s.max_depth,
                });
            }
            if blend {
                obs.step(|| Step::Schlick {
                    reflectance,
                    r0: fresnel.and_then(|f| f.r0),
                    cos: fresnel.and_then(|f| f.cos),
                });
                return surface + reflected * reflectance + refracted * (1.0 - reflectance);
            }
            return surface + reflected + refracted;
        }
        surface + reflected
    }
}
