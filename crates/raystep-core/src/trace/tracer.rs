//! The [`Tracer`]: a scene, its accelerator and its camera, and the one entry point every user
//! calls, [`Tracer::trace_sample`], which hands the sample to the scene's integrator — Whitted
//! (`whitted.rs`), distribution or path (`distribution.rs`, `path.rs`, on the Monte Carlo
//! machinery of `monte_carlo.rs`). The render, the stepped pixel, the exercises and the CPU side
//! of the GPU comparison all call it; only the observer differs. What every integrator shares is
//! here too: the closest hit with its `Miss` or `Color` step, the surface interaction, the
//! recorded trace.

use super::interaction::{Interaction, interact, spawn_origin};
use crate::accel::{Accelerator, Hit};
use crate::math::Ray;
use crate::record::observer::{Observer, Recorder};
use crate::record::{HitRecord, RayRecord, Step, TRACE_VERSION, Trace, TraceObject};
use crate::scene::camera::CameraRays;
use crate::scene::{Integrator, Scene, Shape};
use glam::Vec3;

/// pbrt-v4's `ShadowEpsilon`: shadow rays stop at 1 − 1e-4 of the segment to the light.
pub const SHADOW_EPSILON: f32 = 1e-4;
/// How many levels of the BVH a trace carries for the tree diagram.
pub const BVH_OUTLINE_DEPTH: u32 = 6;
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
/// use raystep_core::PreparedScene;
/// use raystep_core::record::{Counter, Recorder, Silent, Step};
///
/// let prepared = PreparedScene::new(raystep_core::scene::default_scene());
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

impl<'s, A: Accelerator> Tracer<'s, A> {
    /// A tracer over `scene` using `accel`.
    pub fn new(scene: &'s Scene, accel: &'s A) -> Self {
        let f = &scene.features;
        Tracer {
            scene,
            accel,
            camera: CameraRays::new(&scene.camera),
            stages: (f.lights > 0, f.reflective, f.transparent),
            lights: if scene.settings.integrator.is_monte_carlo() {
                crate::mc::lights::Lights::new(scene)
            } else {
                crate::mc::lights::Lights::default()
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
        match self.scene.settings.integrator {
            Integrator::Whitted => self.whitted_sample(x, y, sample, obs),
            Integrator::Distribution | Integrator::Path => self.mc_sample(x, y, sample, obs),
        }
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

    /// Records the full step trace of one sample of one pixel.
    pub fn record(&self, x: u32, y: u32, sample: u32) -> Trace {
        let mut rec = Recorder::new();
        let color = self.trace_sample(x, y, sample, &mut rec);
        let root = rec.finish().expect("the primary ray ends");
        let objects = referenced_objects(self.scene, &root);
        let monte_carlo = self
            .scene
            .settings
            .integrator
            .is_monte_carlo()
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
                name: self.scene.hit_name(&h),
                t: h.t,
                uv: tri.then_some([h.u, h.v]),
                instance: (h.instance != crate::scene::NO_INSTANCE).then_some(h.instance),
            }
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

    /// The surface interaction at a hit, and its `Surface` step. `travelled`: the path length
    /// from the eye to the ray's origin (0 for a primary ray).
    #[inline(always)]
    pub(crate) fn surface<O: Observer>(
        &self,
        hit: &Hit,
        ray: &Ray<f32>,
        travelled: f32,
        obs: &mut O,
    ) -> Interaction {
        let s = &self.scene.settings;
        let mut it = interact(self.scene, hit, ray);
        // The path's length so far, for a ray cone (only a textured scene reads it).
        if self.scene.features.textured > 0 {
            it.distance = travelled + hit.t * ray.dir.length();
        }
        if let Some(inst) = self.scene.instance_of(hit) {
            obs.step(|| {
                let wrong = inst.to_world.vector(it.object_normal);
                Step::InstanceHit {
                    instance: hit.instance,
                    name: inst.name.clone(),
                    to_world: inst.to_world.0,
                    to_object: inst.to_object.0,
                    point: it.object_point.to_array(),
                    normal: it.object_normal.to_array(),
                    world_point: it.point.to_array(),
                    world_normal: it.normal.to_array(),
                    wrong_normal: (wrong / wrong.length()).to_array(),
                }
            });
        }
        obs.step(|| Step::Surface {
            point: it.point.to_array(),
            normal: it.normal.to_array(),
            inside: it.inside,
            error_bound: it.error.to_array(),
            over_point: spawn_origin(s.offset, s.epsilon, &it, it.normal).to_array(),
        });
        if let Some(n) = self.scene.vertex_normals_of(hit.object) {
            // On an instance, the blend of the vertex normals in object space, as the
            // interaction computed it before M⁻ᵀ carried it out.
            let (shading, geometric) = if hit.instance == crate::scene::NO_INSTANCE {
                (it.shading_normal, it.normal)
            } else {
                let g = it.object_normal;
                (
                    super::interaction::interpolate_normal(n, hit.u, hit.v, g),
                    g,
                )
            };
            obs.step(|| Step::ShadingNormal {
                vertex_normals: n.map(|v| v.to_array()),
                u: hit.u,
                v: hit.v,
                normal: shading.to_array(),
                angle_deg: super::interaction::angle_deg(shading, geometric),
                lifted: (s.terminator == crate::scene::Terminator::Hanika)
                    .then(|| it.lifted.to_array()),
            });
        }
        let cone = super::texture::Cone {
            spread: self.camera.spread,
            distance: it.distance,
        };
        if let Some(t) = super::texture::texture_at(self.scene, hit, &it, ray, cone) {
            obs.step(|| t.step(self.scene));
            it.texel = Some(t.lookup.color);
        }
        // A glossy BSDF's roughness texture, read where a Monte Carlo integrator samples it.
        let m = self.scene.material_of(hit.object);
        if s.integrator.is_monte_carlo()
            && m.reads_roughness()
            && let Some(index) = m.roughness_texture
            && let Some(mut t) =
                super::texture::read_texture(self.scene, hit, &it, ray, cone, index)
        {
            let roughness = m.roughness_at(t.lookup.color);
            // Its `Texture` step carries the roughness, in place of a surface colour.
            t.color = glam::Vec3::splat(roughness);
            t.roughness = Some(crate::record::texturing::RoughnessRead {
                material: m.roughness,
                roughness,
            });
            obs.step(|| t.step(self.scene));
            it.roughness = Some(roughness);
        }
        it
    }
}

/// The geometry and material of every object the trace's steps mention, in id order.
pub fn referenced_objects(scene: &Scene, root: &RayRecord) -> Vec<TraceObject> {
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
                prototype: id >= scene.world_objects,
            }
        })
        .collect()
}
