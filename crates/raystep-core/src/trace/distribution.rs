//! Distribution ray tracing (Cook, Porter and Carpenter 1984): Whitted's recursion with area
//! lights sampled (every light group once at a diffuse surface: soft shadows), a glossy surface's
//! reflection sampled from its GGX lobe, mirrors and glass recursing along both branches weighted
//! by the exact Fresnel reflectance, and a thin-lens camera. The machinery it shares with the
//! path tracer is in `monte_carlo.rs`.

use super::interaction::Interaction;
use super::monte_carlo::{Previous, Sampler, dimension, slot};
use super::tracer::{Tracer, WEIGHT_CUTOFF};
use crate::accel::{Accelerator, Hit};
use crate::mc::bsdf;
use crate::mc::lights::LightShape;
use crate::record::observer::Observer;
use crate::record::{Draw, Step};
use crate::scene::Bsdf;
use glam::Vec3;

impl<A: Accelerator> Tracer<'_, A> {
    /// The distribution tracer follows one sampled direction: its step, then the ray unless its
    /// share of the pixel is below Whitted's cut-off ([`WEIGHT_CUTOFF`]: glass's two branches at
    /// every level would otherwise double the work per bounce), and the radiance it brings back
    /// times its weight.
    #[allow(clippy::too_many_arguments)]
    fn follow<O: Observer>(
        &self,
        sampler: &Sampler,
        it: &Interaction,
        b: &Bsdf,
        bs: bsdf::BsdfSample,
        random: &[Draw],
        depth: u32,
        throughput: Vec3,
        obs: &mut O,
    ) -> Vec3 {
        let next = throughput * bs.weight;
        let Some((kind, ray)) = self.bsdf_step(it, b, &bs, random, next, obs) else {
            return Vec3::ZERO;
        };
        let contribution = next.max_element();
        if contribution < WEIGHT_CUTOFF {
            obs.step(|| Step::WeightCutoff {
                kind,
                contribution,
                cutoff: WEIGHT_CUTOFF,
            });
            return Vec3::ZERO;
        }
        let prev = Previous {
            bsdf_pdf: None,
            origin: it.point,
            travelled: it.distance,
        };
        let li = self.mc_child(sampler, &ray, kind, depth + 1, bs.weight, next, prev, obs);
        bs.weight * li
    }

    /// The distribution ray tracer at a hit: emission, every light sampled once at a diffuse
    /// surface, one glossy reflection ray, and Whitted's mirror and glass recursion.
    pub(super) fn distribution_at<O: Observer>(
        &self,
        sampler: &Sampler,
        hit: &Hit,
        it: &Interaction,
        depth: u32,
        throughput: Vec3,
        obs: &mut O,
    ) -> Vec3 {
        let s = &self.scene.settings;
        let mut l = self.emitted(hit, it, throughput, None, obs);
        let m = self.scene.material_of(hit.object);
        let b = m.bsdf_textured(it.texel, it.roughness);
        let dim = |slot| dimension(depth, slot);
        // Direct light: every light group once (a diffuse surface); point lights only for glossy
        // (its area lights are found by its reflection ray).
        if !bsdf::is_delta(&b) {
            for g in 0..self.lights.groups.len() {
                let first = self.lights.groups[g].members.first().copied();
                let point = first.is_some_and(|i| {
                    matches!(
                        self.lights.lights[i as usize].shape,
                        LightShape::Point { .. }
                    )
                });
                if matches!(b, Bsdf::Glossy { .. }) && !point {
                    continue;
                }
                let base = slot::GROUP + 3 * g as u32;
                let pick = sampler.draw(dim(base));
                let (u0, u1) = sampler.draw_pair(dim(base + 1));
                let Some((index, p)) = self.lights.pick_in_group(g, pick.value) else {
                    continue;
                };
                let drawn = [pick, u0, u1];
                let random = if point { &[][..] } else { &drawn[..] };
                l += self.light_sample(
                    it,
                    &b,
                    index,
                    p,
                    false,
                    random,
                    [u0.value, u1.value],
                    depth,
                    throughput,
                    obs,
                );
            }
        }
        if matches!(b, Bsdf::Diffuse { .. }) {
            return l;
        }
        if depth >= s.max_depth {
            obs.step(|| Step::DepthLimit {
                max_depth: s.max_depth,
            });
            return l;
        }
        match b {
            Bsdf::Glass { ior } => {
                // Both branches, each weighted by its Fresnel share.
                let (fr, mut reflection, transmission) =
                    bsdf::glass_lobes(ior, it.eye, it.shading_normal, it.inside);
                reflection.weight *= fr;
                l += self.follow(sampler, it, &b, reflection, &[], depth, throughput, obs);
                if let Some(mut t) = transmission {
                    t.weight *= 1.0 - fr;
                    l += self.follow(sampler, it, &b, t, &[], depth, throughput, obs);
                }
            }
            _ => {
                let (u0, u1) = sampler.draw_pair(dim(slot::BSDF));
                let drawn = [u0, u1];
                let random = if matches!(b, Bsdf::Glossy { .. }) {
                    &drawn[..]
                } else {
                    &[][..]
                };
                if let Some(bs) = bsdf::sample(
                    &b,
                    it.eye,
                    it.shading_normal,
                    it.inside,
                    0.0,
                    [u0.value, u1.value],
                ) {
                    l += self.follow(sampler, it, &b, bs, random, depth, throughput, obs);
                }
            }
        }
        l
    }
}
