//! The one recursive Whitted tracer. The render, the stepped pixel, the exercises and the CPU side
//! of the GPU comparison all call [`Tracer::trace_sample`]; only the observer differs.

use super::interaction::{Interaction, interact, spawn_origin};
use super::media::Media;
use super::sampling::sample_offset;
use super::shading::{critical_angle_deg, phong, reflect_recorded, refract, schlick_recorded};
use crate::accel::{Accelerator, Hit};
use crate::math::Ray;
use crate::record::observer::{Observer, Recorder};
use crate::record::{HitRecord, RayKind, RayRecord, Step, TRACE_VERSION, Trace, TraceObject};
use crate::scene::camera::CameraRays;
use crate::scene::{Integrator, Scene, Shape};
use glam::Vec3;

/// pbrt-v4's `ShadowEpsilon`: shadow rays stop at 1 − 1e-4 of the segment to the light.
pub const SHADOW_EPSILON: f32 = 1e-4;
/// How many levels of the BVH a trace carries for the tree diagram.
pub(crate) const BVH_OUTLINE_DEPTH: u32 = 6;
/// The ray-tree weight cut-off: a reflection or refraction ray whose contribution to the pixel
/// (the product of the weights from the camera down to it: reflectivity or transparency, times
/// Schlick's reflectance where both blend) is below 1/512 is not spawned, and its colour counts
/// as black. Below half an 8-bit step of a white image it cannot be seen, and it bounds the work
/// of a sample: the contributions of the rays at one depth sum to at most 1, so at most 512 rays
/// per depth are traced however deep the recursion may go. The GPU tracer applies the same rule.
pub const WEIGHT_CUTOFF: f32 = 1.0 / 512.0;
/// The tracer: a scene, its accelerator and its camera.
///
/// The same tracer renders and records: what changes is the [`Observer`] passed in.
///
/// ```
/// use raystep::PreparedScene;
/// use raystep::record::{Counter, Recorder, Silent, Step};
///
/// let prepared = PreparedScene::new(raystep::scene::default_scene());
/// let tracer = prepared.tracer();
/// // The render's path: nothing kept.
/// let silent = tracer.trace_sample(160, 120, 0, &mut Silent);
/// // Statistics: rays and intersection tests counted.
/// let mut counter = Counter::default();
/// let counted = tracer.trace_sample(160, 120, 0, &mut counter);
/// assert!(counter.rays() >= 1);
/// // The stepped pixel: every step kept.
/// let mut recorder = Recorder::new();
/// let recorded = tracer.trace_sample(160, 120, 0, &mut recorder);
/// assert_eq!(silent, counted);
/// assert_eq!(silent, recorded);
/// let primary = recorder.finish().expect("the primary ray ended");
/// assert!(primary.steps.iter().any(|s| matches!(s.step, Step::Sphere { .. })));
/// ```
pub struct Tracer<'s, A: Accelerator> {
    /// The scene.
    pub scene: &'s Scene,
    /// Finds hits.
    pub accel: &'s A,
    /// Primary rays.
    pub camera: CameraRays,
    /// Which optional stages are compiled into the tracing loop: (shadow rays, reflection,
    /// refraction). Set from the scene's features, so an opaque scene runs a tracer with no
    /// refraction code at all (docs/ARCHITECTURE.md, invariant 4).
    pub stages: (bool, bool, bool),
    /// The lights the Monte Carlo integrators sample (empty under Whitted).
    pub lights: crate::mc::lights::Lights,
}

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

impl<'s, A: Accelerator> Tracer<'s, A> {
    /// A tracer over `scene` using `accel`.
    pub fn new(scene: &'s Scene, accel: &'s A) -> Self {
        let f = &scene.features;
        Tracer {
            scene,
            accel,
            camera: CameraRays::new(&scene.camera),
            stages: (f.lights > 0, f.reflective, f.transparent),
            lights: if scene.settings.integrator == Integrator::Whitted {
                crate::mc::lights::Lights::default()
            } else {
                crate::mc::lights::Lights::new(scene)
            },
        }
    }

    /// Turns the per-scene specialization off (every stage compiled in and checked at run time),
    /// for the benchmark that shows what specialization saves. Results are identical.
    pub fn unspecialized(mut self) -> Self {
        self.stages = (true, true, true);
        self
    }

    /// Traces sample `sample` of pixel (x, y) and returns its linear colour.
    #[inline]
    pub fn trace_sample<O: Observer>(&self, x: u32, y: u32, sample: u32, obs: &mut O) -> Vec3 {
        if self.scene.settings.integrator != Integrator::Whitted {
            return self.mc_sample(x, y, sample, obs);
        }
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
        let (color, hit) = self.shade_ray::<O, L, R, T>(&ray, 0, 1.0, Media::default(), obs);
        obs.end_ray(|| self.hit_record(hit), color);
        color
    }

    /// The pixel's colour: the mean of its `spp` samples. A sample with a NaN or infinite
    /// channel counts as black (see [`Tracer::trace_pixel_checked`]).
    #[inline]
    pub fn trace_pixel<O: Observer>(&self, x: u32, y: u32, obs: &mut O) -> Vec3 {
        self.trace_pixel_checked(x, y, obs).0
    }

    /// The pixel's colour, the number of its samples that were not finite (a NaN or an infinite
    /// channel: left out of the sum, so they never reach the image) and the first such sample's
    /// index.
    #[inline]
    pub fn trace_pixel_checked<O: Observer>(
        &self,
        x: u32,
        y: u32,
        obs: &mut O,
    ) -> (Vec3, u32, Option<u32>) {
        let spp = self.scene.settings.spp;
        let (sum, bad, first) = self.accumulate_samples(x, y, 0..spp, Vec3::ZERO, obs);
        (sum / spp as f32, bad, first)
    }

    /// Adds samples `samples` of pixel (x, y), in order, onto `sum`: the new sum, the number of
    /// samples left out for not being finite, and the first of them. The pixel's colour is the
    /// sum over all its samples divided by spp; a progressive render adds them pass by pass in
    /// this very order, so it reaches the same bits.
    #[inline]
    pub fn accumulate_samples<O: Observer>(
        &self,
        x: u32,
        y: u32,
        samples: std::ops::Range<u32>,
        mut sum: Vec3,
        obs: &mut O,
    ) -> (Vec3, u32, Option<u32>) {
        let (mut bad, mut first) = (0, None);
        for k in samples {
            let c = self.trace_sample(x, y, k, obs);
            if c.is_finite() {
                sum += c;
            } else {
                bad += 1;
                first.get_or_insert(k);
            }
        }
        (sum, bad, first)
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
        self.trace_child::<O, L, R, T>(ray, RayKind::Primary, 0, 1.0, 1.0, Media::default(), obs)
    }

    /// Records the full step trace of one sample of one pixel.
    pub fn record(&self, x: u32, y: u32, sample: u32) -> Trace {
        let mut rec = Recorder::new();
        let color = self.trace_sample(x, y, sample, &mut rec);
        let root = rec.finish().expect("the primary ray ends");
        let objects = referenced_objects(self.scene, &root);
        let monte_carlo = (self.scene.settings.integrator != Integrator::Whitted)
            .then(|| self.mc_record(x, y, &root, &objects));
        Trace {
            version: TRACE_VERSION,
            raystep: env!("CARGO_PKG_VERSION").into(),
            scene: self.scene.name.clone(),
            scene_hash: self.scene.source_hash.clone(),
            pixel: [x, y],
            sample,
            settings: self.scene.settings.clone(),
            root,
            camera: self.scene.camera.clone(),
            lights: self.scene.lights.clone(),
            objects,
            bvh: self.accel.outline(BVH_OUTLINE_DEPTH),
            grid: self.accel.grid_outline(),
            monte_carlo,
            color: color.to_array(),
        }
    }

    pub(crate) fn hit_record(&self, hit: Option<Hit>) -> Option<HitRecord> {
        hit.map(|h| {
            let tri = matches!(
                self.scene.objects[h.object as usize].shape,
                Shape::Triangle { .. }
            );
            HitRecord {
                object: h.object,
                name: self.scene.object_name(h.object),
                t: h.t,
                uv: tri.then_some([h.u, h.v]),
            }
        })
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
        media: Media,
        obs: &mut O,
    ) -> Vec3 {
        obs.begin_ray(kind, depth, ray, weight);
        let (color, hit) = self.shade_ray::<O, L, R, T>(ray, depth, throughput, media, obs);
        obs.end_ray(|| self.hit_record(hit), color);
        color
    }

    /// Finds the closest hit and shades it (the body of a colour ray). `throughput`: what the
    /// ray's colour is multiplied by on its way to the pixel.
    fn shade_ray<O: Observer, const L: bool, const R: bool, const T: bool>(
        &self,
        ray: &Ray<f32>,
        depth: u32,
        throughput: f32,
        media: Media,
        obs: &mut O,
    ) -> (Vec3, Option<Hit>) {
        self.closest_then(ray, obs, |hit, obs| {
            self.shade::<O, L, R, T>(hit, ray, depth, throughput, media, obs)
        })
    }

    /// The body of a colour ray for every integrator: finds the closest hit; a miss returns the
    /// background (its `Miss` step), a hit what `shade` computes; then the ray's `Color` step.
    #[inline(always)]
    pub(crate) fn closest_then<O: Observer>(
        &self,
        ray: &Ray<f32>,
        obs: &mut O,
        shade: impl FnOnce(&Hit, &mut O) -> Vec3,
    ) -> (Vec3, Option<Hit>) {
        let Some(hit) = self.accel.closest(self.scene, ray, obs) else {
            let bg = self.scene.settings.background;
            obs.step(|| Step::Miss {
                background: bg.to_array(),
            });
            obs.step(|| Step::Color {
                color: bg.to_array(),
            });
            return (bg, None);
        };
        let color = shade(&hit, obs);
        obs.step(|| Step::Color {
            color: color.to_array(),
        });
        (color, Some(hit))
    }

    /// The surface interaction at a hit, and its `Surface` step.
    #[inline(always)]
    pub(crate) fn surface<O: Observer>(
        &self,
        hit: &Hit,
        ray: &Ray<f32>,
        obs: &mut O,
    ) -> Interaction {
        let s = &self.scene.settings;
        let it = interact(self.scene, hit, ray);
        obs.step(|| Step::Surface {
            point: it.point.to_array(),
            normal: it.normal.to_array(),
            inside: it.inside,
            error_bound: it.error.to_array(),
            over_point: spawn_origin(s.offset, s.epsilon, &it, it.normal).to_array(),
        });
        it
    }

    /// Shades a hit. `L`, `R`, `T`: whether shadow rays, reflection and refraction are compiled in.
    fn shade<O: Observer, const L: bool, const R: bool, const T: bool>(
        &self,
        hit: &Hit,
        ray: &Ray<f32>,
        depth: u32,
        throughput: f32,
        media: Media,
        obs: &mut O,
    ) -> Vec3 {
        let scene = self.scene;
        let s = &scene.settings;
        let m = scene.material_of(hit.object);
        let it = self.surface(hit, ray, obs);

        // Direct light: Phong from each light, ambient only where a shadow ray is blocked.
        let mut surface = Vec3::ZERO;
        if !L || scene.lights.is_empty() {
            // No lights: show the ambient colour rather than black (a scene with no lights still
            // shows its shapes).
            surface = m.color * m.ambient;
        }
        for (li, light) in scene
            .lights
            .iter()
            .enumerate()
            .take(if L { usize::MAX } else { 0 })
        {
            let to_light = light.position - it.point;
            // A light behind the surface contributes only ambient, shadowed or not: no shadow ray.
            let facing = to_light.dot(it.normal) > 0.0;
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
                light.position,
                light.color,
                it.point,
                it.eye,
                it.normal,
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
            (n1, n2, refract(it.eye, it.normal, n1, n2))
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
                let (d_dot_n, dir) = reflect_recorded(ray.dir, it.normal);
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

/// The geometry and material of every object the trace's steps mention, in id order.
pub(crate) fn referenced_objects(scene: &Scene, root: &RayRecord) -> Vec<TraceObject> {
    let mut ids = std::collections::BTreeSet::new();
    fn walk(r: &RayRecord, ids: &mut std::collections::BTreeSet<u32>) {
        for s in &r.steps {
            match &s.step {
                Step::Sphere { object, .. }
                | Step::Plane { object, .. }
                | Step::Triangle { object, .. } => {
                    ids.insert(*object);
                }
                _ => {}
            }
        }
        if let Some(h) = &r.hit {
            ids.insert(h.object);
        }
        for c in &r.children {
            walk(c, ids);
        }
    }
    walk(root, &mut ids);
    ids.into_iter()
        .map(|id| {
            let m = scene.material_of(id);
            TraceObject {
                id,
                name: scene.object_name(id),
                shape: scene.objects[id as usize].shape,
                material: m.name.clone(),
                color: m.color.to_array(),
                reflective: m.reflective,
                transparency: m.transparency,
                refractive_index: m.refractive_index,
            }
        })
        .collect()
}
