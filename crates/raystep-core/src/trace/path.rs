//! Path tracing (Kajiya 1986): one path per sample. At each hit next-event estimation picks one
//! light by power and a point on it, the BSDF samples the next direction, and emission found by
//! a BSDF-sampled ray is weighted against the light sample by multiple importance sampling
//! (Veach's power heuristic, β = 2); after `rr_depth` bounces Russian roulette may end the path.
//! `[render] strategy` keeps one estimator of direct light instead of both. The machinery it
//! shares with the distribution tracer (random numbers, light and BSDF samples, emission) is in
//! `monte_carlo.rs`.

use super::interaction::Interaction;
use super::monte_carlo::{Previous, Sampler, arr, dimension, slot};
use super::tracer::Tracer;
use crate::accel::{Accelerator, Hit};
use crate::mc::bsdf;
use crate::record::Step;
use crate::record::observer::Observer;
use crate::scene::{Bsdf, Strategy};
use glam::Vec3;

impl<A: Accelerator> Tracer<'_, A> {
    /// The path tracer at a hit: emission (MIS), next-event estimation (MIS), a BSDF sample,
    /// Russian roulette, and the rest of the path.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn path_at<O: Observer>(
        &self,
        sampler: &Sampler,
        hit: &Hit,
        it: &Interaction,
        depth: u32,
        throughput: Vec3,
        prev: Previous,
        obs: &mut O,
    ) -> Vec3 {
        let s = &self.scene.settings;
        let mut l = self.emitted(hit, it, throughput, Some(prev), obs);
        if depth >= s.max_depth {
            obs.step(|| Step::DepthLimit {
                max_depth: s.max_depth,
            });
            return l;
        }
        let m = self.scene.material_of(hit.object);
        let b = m.bsdf_textured(it.texel, it.roughness);
        let dim = |slot| dimension(depth, slot);
        // Next-event estimation (not under BSDF sampling alone).
        if !bsdf::is_delta(&b) && !self.lights.is_empty() && s.strategy != Strategy::Bsdf {
            let pick = sampler.draw(dim(slot::LIGHT_PICK));
            if let Some((index, select_pdf)) = self.lights.pick(pick.value) {
                let (u0, u1) = sampler.draw_pair(dim(slot::LIGHT_POINT));
                l += self.light_sample(
                    it,
                    &b,
                    index,
                    select_pdf,
                    true,
                    &[pick, u0, u1],
                    [u0.value, u1.value],
                    depth,
                    throughput,
                    obs,
                );
            }
        }
        // The next direction.
        let lobe = sampler.draw(dim(slot::LOBE));
        let (u0, u1) = sampler.draw_pair(dim(slot::BSDF));
        let Some(bs) = bsdf::sample(
            &b,
            it.eye,
            it.shading_normal,
            it.inside,
            lobe.value,
            [u0.value, u1.value],
        ) else {
            return l;
        };
        let mut weight = bs.weight;
        let mut next = throughput * weight;
        // The numbers the BSDF used: glass its lobe's, a mirror none (it is deterministic).
        let drawn = [lobe, u0, u1];
        let random = match b {
            Bsdf::Glass { .. } => &drawn[..],
            Bsdf::Mirror { .. } => &drawn[..0],
            _ => &drawn[1..],
        };
        let Some((kind, ray)) = self.bsdf_step(it, &b, &bs, random, next, obs) else {
            return l;
        };
        // Russian roulette.
        if depth + 1 > s.rr_depth {
            let u = sampler.draw(dim(slot::ROULETTE));
            let q = next.max_element().min(1.0);
            let survived = u.value < q;
            if survived {
                weight /= q;
                next /= q;
            }
            obs.step(|| Step::RussianRoulette {
                random: u,
                probability: q,
                survived,
                throughput: arr(next),
            });
            if !survived {
                return l;
            }
        }
        let prev = Previous {
            bsdf_pdf: bs.pdf,
            origin: it.point,
            travelled: it.distance,
        };
        let li = self.mc_child(sampler, &ray, kind, depth + 1, weight, next, prev, obs);
        l + weight * li
    }
}
