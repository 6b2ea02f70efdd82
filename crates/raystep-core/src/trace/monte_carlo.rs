//! What the two Monte Carlo integrators share, on the same [`Tracer`] and [`Observer`] as
//! Whitted's (the render passes a silent observer, the stepped pixel a recorder, and both compute
//! the same numbers): the camera's sample with its thin lens, the random numbers and their
//! dimensions, emission with its MIS weight, a light sample, a BSDF sample. The integrators
//! themselves are `distribution.rs` and `path.rs` beside this file:
//!
//! - **Distribution ray tracing** (Cook, Porter and Carpenter 1984): at a diffuse surface, every
//!   light is sampled once (soft shadows); a glossy surface sends one reflection ray sampled from
//!   its GGX lobe (and takes point lights directly); mirrors and glass recurse as in Whitted,
//!   glass along both branches weighted by the exact Fresnel reflectance. Emission is added
//!   wherever a ray from the camera, a mirror, glass or a glossy bounce lands on a light.
//! - **Path tracing** (Kajiya 1986): one path per sample. At each hit, next-event estimation
//!   picks one light (by power) and a point on it; the BSDF samples the next direction; emission
//!   found by a BSDF-sampled ray and the light sample are combined by multiple importance
//!   sampling with Veach's power heuristic (β = 2); after `rr_depth` bounces Russian roulette
//!   ends the path with probability 1 − min(1, max channel of the throughput).
//!   `[render] strategy` keeps one estimator of direct light instead of both: `light` (next-event
//!   estimation alone; emission a BSDF-sampled ray finds counts only where light sampling has
//!   no density) or `bsdf` (no next-event estimation; emission counts wherever it is found).
//!
//! `max_depth` bounds the bounces (a path has at most `max_depth` scattering events, so
//! `max_depth + 1` segments; Mitsuba's `max_depth` is this plus one). A ray that escapes returns
//! `background` as radiance: a constant environment.
//!
//! Random numbers come from [`uniform`]`(pixel, sample, dimension, seed)`; the dimensions are
//! laid out by [`dimension`]: the lens takes 2 and 3, and bounce `b` the block from
//! 16 + 1024·b, slot by slot ([`slot`]).

use super::interaction::{Interaction, spawn_origin};
use super::sampling::{ONE_BELOW, sample_offset};
use super::tracer::{SHADOW_EPSILON, Tracer};
use crate::accel::{Accelerator, Hit};
use crate::math::Ray;
use crate::mc::bsdf::{self, Lobe};
use crate::mc::lights::LightShape;
use crate::portable::random::{sample_key, uniform, uniform_keyed};
use crate::record::observer::Observer;
use crate::record::{Draw, RayKind, Step};
use crate::scene::{Bsdf, Integrator, SamplerKind, Strategy};
use glam::Vec3;

/// The lens's two dimensions start here.
pub const LENS_DIMENSION: u32 = 2;

/// The slots of a bounce's block of dimensions.
pub mod slot {
    /// The path tracer picks a light.
    pub const LIGHT_PICK: u32 = 0;
    /// Then a point on it (two dimensions).
    pub const LIGHT_POINT: u32 = 1;
    /// Glass picks its lobe.
    pub const LOBE: u32 = 3;
    /// The BSDF's direction (two dimensions).
    pub const BSDF: u32 = 4;
    /// Russian roulette.
    pub const ROULETTE: u32 = 6;
    /// The distribution tracer's light group g takes 3 from here: 8 + 3g (a member, a point).
    pub const GROUP: u32 = 8;
    /// Every slot with the name the GPU's shaders give it (raystep-gpu's `interface`).
    pub const ALL: &[(&str, u32)] = &[
        ("SLOT_LIGHT_PICK", LIGHT_PICK),
        ("SLOT_LIGHT_POINT", LIGHT_POINT),
        ("SLOT_LOBE", LOBE),
        ("SLOT_BSDF", BSDF),
        ("SLOT_ROULETTE", ROULETTE),
        ("SLOT_GROUP", GROUP),
    ];
}

/// Bounce 0's block of dimensions starts here (below it: the camera's, the lens's).
pub const FIRST_BOUNCE_DIMENSION: u32 = 16;
/// Each bounce's block of dimensions is this long.
pub const DIMENSIONS_PER_BOUNCE: u32 = 1024;

/// The dimension of `slot` at bounce `depth` (the camera's hit is bounce 0):
/// [`FIRST_BOUNCE_DIMENSION`] + [`DIMENSIONS_PER_BOUNCE`]·depth + slot.
pub fn dimension(depth: u32, slot: u32) -> u32 {
    FIRST_BOUNCE_DIMENSION
        .wrapping_add(depth.wrapping_mul(DIMENSIONS_PER_BOUNCE))
        .wrapping_add(slot)
}

/// Veach's power heuristic (β = 2) for `a` against `b`: a² / (a² + b²).
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 <= 0.0 || !(a2 + b2).is_finite() {
        return if a > 0.0 { 1.0 } else { 0.0 };
    }
    a2 / (a2 + b2)
}

/// The sample being traced: where its random numbers come from.
#[derive(Clone, Copy)]
pub(super) struct Sampler {
    pub(super) pixel: [u32; 2],
    pub(super) sample: u32,
    pub(super) seed: u32,
    /// The pixel's samples (the strata's count).
    pub(super) spp: u32,
    /// `sampler = "stratified"`.
    pub(super) stratified: bool,
    /// The sample's [`sample_key`]: each draw hashes its dimension into it (the numbers are
    /// [`uniform`]'s).
    pub(super) key: u32,
}

impl Sampler {
    /// The sampler of sample `sample` of `pixel`.
    pub(super) fn new(pixel: [u32; 2], sample: u32, seed: u32, spp: u32, stratified: bool) -> Self {
        Sampler {
            pixel,
            sample,
            seed,
            spp,
            stratified,
            key: sample_key(pixel, sample, seed),
        }
    }

    #[inline]
    pub(super) fn draw(&self, dimension: u32) -> Draw {
        Draw {
            dimension,
            value: uniform_keyed(self.key, dimension),
        }
    }

    /// A pair of numbers for a 2D sample (a point on a light or the lens, a BSDF direction):
    /// two independent uniforms, or under `sampler = "stratified"` the pair placed in its own
    /// cell of a grid over the pixel's samples ([`stratified_pair`]).
    #[inline]
    pub(super) fn draw_pair(&self, dimension: u32) -> (Draw, Draw) {
        let (a, b) = (self.draw(dimension), self.draw(dimension + 1));
        if !self.stratified {
            return (a, b);
        }
        let [u, v] = stratified_pair(
            self.pixel,
            self.sample,
            self.spp,
            dimension,
            self.seed,
            [a.value, b.value],
        );
        (
            Draw {
                dimension,
                value: u,
            },
            Draw {
                dimension: dimension + 1,
                value: v,
            },
        )
    }
}

/// Stratified 2D samples: the pixel's `spp` samples share the grid of `spp` equal cells that
/// the pixel jitter uses ([`super::sampling::grid_point`]); sample k takes cell π(k), where π(k) = (a·k + b) mod spp is a permutation hashed from the pixel, the dimension and
/// the seed (a coprime to spp), so that a sample's cell on the light is not tied to its cell in
/// the pixel; `jitter` (two uniforms) places the pair inside its cell.
pub fn stratified_pair(
    pixel: [u32; 2],
    sample: u32,
    spp: u32,
    dimension: u32,
    seed: u32,
    jitter: [f32; 2],
) -> [f32; 2] {
    if spp <= 1 {
        return jitter;
    }
    // The permutation's multiplier and offset, from the same hash as every other number.
    let h = |salt: u32| {
        let u = uniform(pixel, u32::MAX - salt, dimension, seed);
        (u * spp as f32) as u32 % spp
    };
    let mut a = h(0).max(1);
    while gcd(a, spp) != 1 {
        a = a % spp + 1;
    }
    let cell = (u64::from(a) * u64::from(sample % spp) + u64::from(h(1))) % u64::from(spp);
    let [u, v] = super::sampling::grid_point(cell as u32, spp, jitter);
    [u.min(ONE_BELOW), v.min(ONE_BELOW)]
}

fn gcd(mut a: u32, mut b: u32) -> u32 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// How the ray being shaded was made: for MIS weights on the emission it finds.
#[derive(Clone, Copy)]
pub(super) struct Previous {
    /// The BSDF's density of the ray's direction (None: the camera or a delta BSDF).
    pub(super) bsdf_pdf: Option<f32>,
    /// Where the ray left from.
    pub(super) origin: Vec3,
    /// The path length from the eye to `origin` (a ray cone's distance, `trace::texture`).
    pub(super) travelled: f32,
}

pub(super) fn arr(v: Vec3) -> [f32; 3] {
    v.to_array()
}

impl<A: Accelerator> Tracer<'_, A> {
    /// Traces sample `sample` of pixel (x, y) with the scene's Monte Carlo integrator.
    pub(crate) fn mc_sample<O: Observer>(&self, x: u32, y: u32, sample: u32, obs: &mut O) -> Vec3 {
        let s = &self.scene.settings;
        let sampler = Sampler::new(
            [x, y],
            sample,
            s.seed,
            s.spp,
            s.sampler == SamplerKind::Stratified,
        );
        let offset = sample_offset(x, y, sample, s.spp, s.seed);
        let (mut ray, screen) = self.camera.ray(x, y, offset);
        let cam = &self.scene.camera;
        let lens = (cam.aperture > 0.0).then(|| {
            let (u0, u1) = sampler.draw_pair(LENS_DIMENSION);
            let u = [u0, u1];
            let disk = crate::mc::sample::thin_lens(cam.aperture, [u[0].value, u[1].value]);
            (u, disk)
        });
        let mut lens_step = None;
        if let Some((u, Some(disk))) = lens {
            // The plane in focus is perpendicular to the view direction, `focus_distance` away.
            let along = ray.dir.dot(-self.camera.w);
            if along > 0.0 {
                let focus = ray.origin + ray.dir * (cam.focus_distance / along);
                let origin =
                    ray.origin + self.camera.u * disk.value[0] + self.camera.v * disk.value[1];
                let dir = (focus - origin).normalize_or_zero();
                if dir != Vec3::ZERO && dir.is_finite() {
                    ray = Ray {
                        origin,
                        dir,
                        t_min: 0.0,
                        t_max: f32::INFINITY,
                    };
                    lens_step = Some((u, origin, focus, disk.pdf, dir));
                }
            }
        }
        obs.begin_ray(RayKind::Primary, 0, &ray, 1.0);
        obs.step(|| Step::Camera {
            pixel: [x, y],
            sample,
            offset,
            screen,
            direction: arr(ray.dir),
        });
        if let Some((u, origin, focus, pdf, dir)) = lens_step {
            obs.step(|| Step::Lens {
                random: u.to_vec(),
                lens_point: arr(origin),
                focus_point: arr(focus),
                pdf,
                direction: arr(dir),
            });
        }
        let prev = Previous {
            bsdf_pdf: None,
            origin: ray.origin,
            travelled: 0.0,
        };
        let (color, hit) = self.mc_shade_ray(&sampler, &ray, 0, Vec3::ONE, prev, obs);
        obs.end_ray(|| self.hit_record(hit), color);
        color
    }

    /// Traces a child ray (its steps bracketed as a ray of the trace).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn mc_child<O: Observer>(
        &self,
        sampler: &Sampler,
        ray: &Ray<f32>,
        kind: RayKind,
        depth: u32,
        weight: Vec3,
        throughput: Vec3,
        prev: Previous,
        obs: &mut O,
    ) -> Vec3 {
        let mean = (weight.x + weight.y + weight.z) / 3.0;
        obs.begin_ray(kind, depth, ray, mean);
        let (color, hit) = self.mc_shade_ray(sampler, ray, depth, throughput, prev, obs);
        obs.end_ray(|| self.hit_record(hit), color);
        color
    }

    /// The radiance arriving along `ray`. `throughput`: what it is multiplied by on its way to
    /// the pixel (recorded with the contributions).
    pub(super) fn mc_shade_ray<O: Observer>(
        &self,
        sampler: &Sampler,
        ray: &Ray<f32>,
        depth: u32,
        throughput: Vec3,
        prev: Previous,
        obs: &mut O,
    ) -> (Vec3, Option<Hit>) {
        self.closest_then(ray, obs, |hit, obs| {
            let it = self.surface(hit, ray, prev.travelled, obs);
            match self.scene.settings.integrator {
                Integrator::Path => self.path_at(sampler, hit, &it, depth, throughput, prev, obs),
                Integrator::Distribution => {
                    self.distribution_at(sampler, hit, &it, depth, throughput, obs)
                }
                Integrator::Whitted => unreachable!("Tracer::trace_sample sends Whitted elsewhere"),
            }
        })
    }

    /// Emission at the hit, with its MIS weight against light sampling from the previous hit.
    pub(super) fn emitted<O: Observer>(
        &self,
        hit: &Hit,
        it: &Interaction,
        throughput: Vec3,
        prev: Option<Previous>,
        obs: &mut O,
    ) -> Vec3 {
        let m = self.scene.material_of(hit.object);
        if m.emission.max_element() <= 0.0 || it.inside {
            return Vec3::ZERO;
        }
        let le = m.emission;
        let (light_pdf, bsdf_pdf, w) = match prev.and_then(|p| p.bsdf_pdf.map(|b| (p.origin, b))) {
            Some((origin, bsdf_pdf)) => {
                let light_pdf = self.lights.of_object(hit.object).map_or(0.0, |i| {
                    self.lights.pick_pdf(i) * self.lights.pdf(i, origin, it.point)
                });
                let w = match self.scene.settings.strategy {
                    Strategy::Mis => power_heuristic(bsdf_pdf, light_pdf),
                    // Light sampling alone counts what it can sample; the rest (an emitting
                    // plane) only BSDF sampling finds.
                    Strategy::Light if light_pdf > 0.0 => 0.0,
                    Strategy::Light | Strategy::Bsdf => 1.0,
                };
                (light_pdf, bsdf_pdf, w)
            }
            None => (0.0, 0.0, 1.0),
        };
        let contribution = throughput * le * w;
        obs.step(|| Step::Emitted {
            object: hit.object,
            name: self.scene.object_name(hit.object),
            radiance: arr(le),
            light_pdf,
            bsdf_pdf,
            mis_weight: w,
            contribution: arr(contribution),
        });
        le * w
    }

    /// Samples light `index` from the hit (a shadow ray and its step): the estimate of the
    /// reflected radiance, f · L · cos · w / (pick · pdf), before the throughput.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn light_sample<O: Observer>(
        &self,
        it: &Interaction,
        b: &Bsdf,
        index: u32,
        select_pdf: f32,
        mis: bool,
        random: &[Draw],
        u: [f32; 2],
        depth: u32,
        throughput: Vec3,
        obs: &mut O,
    ) -> Vec3 {
        let Some(lp) = self.lights.sample(index, it.point, u) else {
            return Vec3::ZERO;
        };
        let light = &self.lights.lights[index as usize];
        let delta = matches!(light.shape, LightShape::Point { .. });
        let (f, bsdf_pdf) = bsdf::eval_pdf(b, it.eye, lp.wi, it.shading_normal);
        let cos = lp.wi.dot(it.shading_normal).max(0.0);
        let pdf = select_pdf * lp.pdf;
        let useful = lp.radiance.max_element() > 0.0 && f.max_element() > 0.0 && cos > 0.0;
        let mut blocker = None;
        if useful {
            let s = &self.scene.settings;
            let o = spawn_origin(s.offset, s.epsilon, it, lp.wi);
            if let Ok(shadow) = Ray::new(o, lp.point - o, 0.0, 1.0 - SHADOW_EPSILON) {
                obs.begin_ray(RayKind::Shadow, depth + 1, &shadow, 0.0);
                blocker = self.accel.any(self.scene, &shadow, obs);
                obs.end_ray(|| self.hit_record(blocker), Vec3::ZERO);
            }
        }
        let w = if delta || !mis || self.scene.settings.strategy != Strategy::Mis {
            1.0
        } else {
            power_heuristic(pdf, bsdf_pdf)
        };
        let estimate = if useful && blocker.is_none() {
            let density = if delta { select_pdf } else { pdf };
            if density > 0.0 {
                f * lp.radiance * (cos * w / density)
            } else {
                Vec3::ZERO
            }
        } else {
            Vec3::ZERO
        };
        obs.step(|| Step::LightSample {
            light: index,
            name: light.name.clone(),
            random: random.to_vec(),
            point: arr(lp.point),
            direction: arr(lp.wi),
            distance: lp.distance,
            select_pdf,
            pdf,
            radiance: arr(lp.radiance),
            bsdf: arr(f),
            cos,
            bsdf_pdf,
            mis_weight: w,
            blocked: blocker.is_some(),
            blocker: blocker.map(|h| self.scene.object_name(h.object)),
            contribution: arr(throughput * estimate),
        });
        estimate
    }

    /// Records a BSDF sample and returns the next ray's kind and ray.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn bsdf_step<O: Observer>(
        &self,
        it: &Interaction,
        b: &Bsdf,
        s: &bsdf::BsdfSample,
        random: &[Draw],
        throughput: Vec3,
        obs: &mut O,
    ) -> Option<(RayKind, Ray<f32>)> {
        obs.step(|| Step::BsdfSample {
            bsdf: bsdf::name(b).into(),
            lobe: s.lobe.name().into(),
            random: random.to_vec(),
            direction: arr(s.wi),
            pdf: s.pdf,
            value: arr(s.value),
            cos: s.cos,
            weight: arr(s.weight),
            throughput: arr(throughput),
        });
        let kind = match (b, s.lobe) {
            (_, Lobe::Transmission) => RayKind::Refraction,
            (Bsdf::Diffuse { .. }, _) => RayKind::Diffuse,
            (Bsdf::Glossy { .. }, _) => RayKind::Glossy,
            _ => RayKind::Reflection,
        };
        let st = &self.scene.settings;
        let o = spawn_origin(st.offset, st.epsilon, it, s.wi);
        Ray::new(o, s.wi, 0.0, f32::INFINITY)
            .ok()
            .map(|r| (kind, r))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_power_heuristic_by_hand() {
        assert_eq!(power_heuristic(1.0, 1.0), 0.5);
        assert_eq!(power_heuristic(3.0, 1.0), 0.9);
        assert_eq!(power_heuristic(0.0, 2.0), 0.0);
        assert_eq!(power_heuristic(2.0, 0.0), 1.0);
    }

    #[test]
    fn bounces_take_disjoint_blocks_of_dimensions() {
        assert_eq!(dimension(0, slot::LIGHT_PICK), 16);
        assert_eq!(dimension(1, slot::LIGHT_PICK), 16 + 1024);
        assert!(dimension(0, slot::GROUP + 3 * 300) < dimension(1, 0));
        assert!(LENS_DIMENSION + 1 < dimension(0, 0));
    }
}
