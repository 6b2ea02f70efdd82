//! Building a Monte Carlo trace's [`McRecord`]: every sample of the pixel traced again (the
//! same numbers the render draws) through a small observer that keeps what the diagrams need of
//! each — its value, its first hit, the light points sampled there, the direction it bounced to.

use crate::accel::Accelerator;
use crate::math::Ray;
use crate::record::observer::Observer;
use crate::record::samples::{
    LightPointSample, MAX_PIXEL_SAMPLES, McRecord, ObjectBsdf, PixelSample, TraceLight,
};
use crate::record::{HitRecord, RayKind, RayRecord, Step, TraceObject};
use crate::trace::tracer::Tracer;
use glam::Vec3;
use std::collections::BTreeSet;

/// Keeps the steps of the camera ray (its first hit) and nothing below it.
#[derive(Default)]
struct SampleLog {
    /// Rays begun and not ended (the camera ray is 1).
    open: usize,
    hit: Option<[f32; 3]>,
    normal: Option<[f32; 3]>,
    object: Option<u32>,
    lights: Vec<LightPointSample>,
    bounce: Option<[f32; 3]>,
}

impl Observer for SampleLog {
    const RECORDS: bool = true;
    fn begin_ray(&mut self, _: RayKind, _: u32, _: &Ray<f32>, _: f32) {
        self.open += 1;
    }
    fn step(&mut self, step: impl FnOnce() -> Step) {
        if self.open != 1 {
            return;
        }
        match step() {
            Step::Surface { point, normal, .. } if self.hit.is_none() => {
                self.hit = Some(point);
                self.normal = Some(normal);
            }
            Step::LightSample {
                light,
                point,
                pdf,
                blocked,
                contribution,
                ..
            } => self.lights.push(LightPointSample {
                light,
                point,
                pdf,
                blocked,
                contribution,
            }),
            Step::BsdfSample { direction, .. } if self.bounce.is_none() => {
                self.bounce = Some(direction);
            }
            _ => {}
        }
    }
    fn end_ray(&mut self, hit: impl FnOnce() -> Option<HitRecord>, _: Vec3) {
        if self.open == 1 {
            self.object = hit().map(|h| h.object);
        }
        self.open = self.open.saturating_sub(1);
    }
}

impl<A: Accelerator> Tracer<'_, A> {
    /// The Monte Carlo record of pixel (x, y) for a trace whose rays are `root` and whose
    /// objects are `objects`: its first min(spp, [`MAX_PIXEL_SAMPLES`]) samples traced again
    /// and summarised, the lights any light sample aimed at, the objects' BSDFs.
    pub(crate) fn mc_record(
        &self,
        x: u32,
        y: u32,
        root: &RayRecord,
        objects: &[TraceObject],
    ) -> McRecord {
        let kept = self.scene.settings.spp.min(MAX_PIXEL_SAMPLES as u32);
        let samples: Vec<PixelSample> = (0..kept)
            .map(|k| {
                let mut log = SampleLog::default();
                let color = self.trace_sample(x, y, k, &mut log);
                PixelSample {
                    sample: k,
                    color: color.to_array(),
                    hit: log.hit,
                    normal: log.normal,
                    object: log.object,
                    light_samples: log.lights,
                    bounce: log.bounce,
                }
            })
            .collect();
        assemble(&self.lights, self.scene, root, objects, samples)
    }
}

/// A trace's Monte Carlo record around its pixel's `samples` (the CPU's, or the GPU's read back
/// by `gpu::trace_log`): the lights any light sample aimed at — in the traced sample's steps
/// under `root` or in the summaries — and the BSDFs of `objects`.
pub fn assemble(
    lights: &crate::mc::lights::Lights,
    scene: &crate::scene::Scene,
    root: &RayRecord,
    objects: &[TraceObject],
    samples: Vec<PixelSample>,
) -> McRecord {
    let mut used = BTreeSet::new();
    fn walk(r: &RayRecord, used: &mut BTreeSet<u32>) {
        for s in &r.steps {
            if let Step::LightSample { light, .. } = s.step {
                used.insert(light);
            }
        }
        for c in &r.children {
            walk(c, used);
        }
    }
    walk(root, &mut used);
    for s in &samples {
        used.extend(s.light_samples.iter().map(|l| l.light));
    }
    let lights = used
        .into_iter()
        .filter_map(|i| {
            let l = lights.lights.get(i as usize)?;
            Some(TraceLight {
                index: i,
                name: l.name.clone(),
                object: l.object,
                shape: l.shape,
                radiance: l.radiance.to_array(),
            })
        })
        .collect();
    let bsdfs = objects
        .iter()
        .map(|o| ObjectBsdf {
            object: o.id,
            bsdf: scene.material_of(o.id).bsdf(),
        })
        .collect();
    McRecord {
        spp: scene.settings.spp,
        lights,
        bsdfs,
        samples,
    }
}
