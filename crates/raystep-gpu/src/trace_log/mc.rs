//! The Monte Carlo records of the GPU's step trace (`crates/raystep-gpu/src/wgsl/mc_trace_log.wgsl`): the lens,
//! emission, light-sample, BSDF-sample and Russian-roulette steps of `crates/raystep-core/src/trace/` (`distribution.rs`, `path.rs`, `monte_carlo.rs`), and
//! the summaries of the pixel's samples that make the trace's [`McRecord`]. Every number is the
//! GPU's; names, the lights' shapes and the objects' BSDFs come from the scene.

use super::{NO_OBJECT, Payload};
use crate::mc::bsdf::Lobe;
use crate::mc::lights::Lights;
use crate::record::samples::{LightPointSample, McRecord, PixelSample};
use crate::record::{Draw, RayRecord, Step, TraceObject};
use crate::scene::Scene;

/// What the Monte Carlo records need of the scene: its lights as the integrators number them.
pub(super) struct McScene {
    lights: Lights,
}

impl McScene {
    pub(super) fn new(scene: &Scene) -> McScene {
        McScene {
            lights: Lights::new(scene),
        }
    }

    fn light_name(&self, index: u32) -> String {
        self.lights
            .lights
            .get(index as usize)
            .map_or_else(|| format!("light {index}"), |l| l.name.clone())
    }
}

fn draws(p: &mut Payload) -> Result<Vec<Draw>, String> {
    let n = p.u()? as usize;
    let d = [p.u()?, p.u()?, p.u()?];
    let v = p.v()?;
    if n > 3 {
        return Err(format!(
            "a step drew {n} numbers, more than raystep's steps draw"
        ));
    }
    Ok((0..n)
        .map(|i| Draw {
            dimension: d[i],
            value: v[i],
        })
        .collect())
}

/// The lens step.
pub(super) fn lens(p: &mut Payload) -> Result<Step, String> {
    let (d0, d1) = (p.u()?, p.u()?);
    let (u0, u1) = (p.f()?, p.f()?);
    Ok(Step::Lens {
        random: vec![
            Draw {
                dimension: d0,
                value: u0,
            },
            Draw {
                dimension: d1,
                value: u1,
            },
        ],
        lens_point: p.v()?,
        focus_point: p.v()?,
        pdf: p.f()?,
        direction: p.v()?,
    })
}

/// The emission found at a hit.
pub(super) fn emitted(scene: &Scene, p: &mut Payload) -> Result<Step, String> {
    let object = p.u()?;
    Ok(Step::Emitted {
        object,
        name: scene.object_name(object),
        radiance: p.v()?,
        light_pdf: p.f()?,
        bsdf_pdf: p.f()?,
        mis_weight: p.f()?,
        contribution: p.v()?,
    })
}

/// A light sample (its shadow ray is a child ray of the trace).
pub(super) fn light_sample(mc: &McScene, scene: &Scene, p: &mut Payload) -> Result<Step, String> {
    let light = p.u()?;
    let random = draws(p)?;
    let (point, direction) = (p.v()?, p.v()?);
    let (distance, select_pdf, pdf) = (p.f()?, p.f()?, p.f()?);
    let (radiance, bsdf) = (p.v()?, p.v()?);
    let (cos, bsdf_pdf, mis_weight) = (p.f()?, p.f()?, p.f()?);
    let blocked = p.b()?;
    let by = p.u()?;
    Ok(Step::LightSample {
        light,
        name: mc.light_name(light),
        random,
        point,
        direction,
        distance,
        select_pdf,
        pdf,
        radiance,
        bsdf,
        cos,
        bsdf_pdf,
        mis_weight,
        blocked,
        blocker: (by != NO_OBJECT).then(|| scene.object_name(by)),
        contribution: p.v()?,
    })
}

/// A direction sampled from a BSDF.
pub(super) fn bsdf_sample(p: &mut Payload) -> Result<Step, String> {
    let bsdf = match p.u()? {
        0 => "diffuse",
        1 => "mirror",
        2 => "glass",
        3 => "glossy",
        k => return Err(format!("BSDF kind {k} is not one raystep has")),
    };
    let lobe = if p.u()? == 1 {
        Lobe::Transmission
    } else {
        Lobe::Reflection
    };
    let random = draws(p)?;
    let direction = p.v()?;
    let has_pdf = p.b()?;
    let pdf = p.f()?;
    Ok(Step::BsdfSample {
        bsdf: bsdf.into(),
        lobe: lobe.name().into(),
        random,
        direction,
        pdf: has_pdf.then_some(pdf),
        value: p.v()?,
        cos: p.f()?,
        weight: p.v()?,
        throughput: p.v()?,
    })
}

/// Russian roulette.
pub(super) fn roulette(p: &mut Payload) -> Result<Step, String> {
    Ok(Step::RussianRoulette {
        random: Draw {
            dimension: p.u()?,
            value: p.f()?,
        },
        probability: p.f()?,
        survived: p.b()?,
        throughput: p.v()?,
    })
}

/// The summaries of the pixel's samples as the log gives them: each sample's camera-ray records,
/// then its sample record.
#[derive(Default)]
pub(super) struct Summaries {
    samples: Vec<PixelSample>,
    hit: Option<([f32; 3], [f32; 3])>,
    lights: Vec<LightPointSample>,
    bounce: Option<[f32; 3]>,
}

impl Summaries {
    /// A record of the camera ray of the sample being summarised (what the CPU's summary keeps
    /// of it: the first surface, the light samples, the first BSDF direction).
    pub(super) fn step(&mut self, step: Step) {
        match step {
            Step::Surface { point, normal, .. } if self.hit.is_none() => {
                self.hit = Some((point, normal));
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

    /// The sample record: the sample's index, value and the object its camera ray hit.
    pub(super) fn finish(&mut self, p: &mut Payload) -> Result<(), String> {
        let sample = p.u()?;
        let color = p.v()?;
        let object = p.u()?;
        let hit = self.hit.take();
        self.samples.push(PixelSample {
            sample,
            color,
            hit: hit.map(|h| h.0),
            normal: hit.map(|h| h.1),
            object: (object != NO_OBJECT).then_some(object),
            light_samples: std::mem::take(&mut self.lights),
            bounce: self.bounce.take(),
        });
        Ok(())
    }

    /// Samples summarised.
    pub(super) fn len(&self) -> usize {
        self.samples.len()
    }
}

/// The trace's Monte Carlo record from the GPU's summaries, as the CPU's `mc_record` makes it:
/// the lights any light sample aimed at, the objects' BSDFs.
pub(super) fn record(
    mc: &McScene,
    scene: &Scene,
    root: &RayRecord,
    objects: &[TraceObject],
    summaries: Summaries,
) -> McRecord {
    crate::trace::pixel_samples::assemble(&mc.lights, scene, root, objects, summaries.samples)
}
