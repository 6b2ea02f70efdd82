//! Reading a question's quantity out of a recorded trace.

use super::{Answer, Quantity, Question, RaySel};
use crate::record::texturing::TexelLookup;
use crate::record::{RayKind, RayRecord, Step, Trace};

fn v3(a: [f32; 3]) -> Answer {
    Answer::Vector(a.map(f64::from))
}

fn num(x: Option<f32>) -> Answer {
    x.map_or(Answer::None, |x| Answer::Number(x as f64))
}

/// The ray of the trace a question is about (the first of its kind).
pub(super) fn ray(trace: &Trace, sel: RaySel) -> Option<&RayRecord> {
    let kind = match sel {
        RaySel::Primary => return Some(&trace.root),
        RaySel::Shadow => RayKind::Shadow,
        RaySel::Reflection => RayKind::Reflection,
        RaySel::Refraction => RayKind::Refraction,
        RaySel::Diffuse => RayKind::Diffuse,
        RaySel::Glossy => RayKind::Glossy,
    };
    trace.rays().into_iter().find(|r| r.kind == kind)
}

/// A ray in an instance's object space: origin S′, direction Q′, and M⁻¹ (3 × 4, rows).
pub(super) type ObjectRay = ([f32; 3], [f32; 3], [[f32; 4]; 3]);

/// The ray `r` carried into the object space of the instance its closest hit lies on: the
/// origin S′, the direction Q′ and M⁻¹ from that instance's (last) `Instance` step.
pub(super) fn instance_step(r: &RayRecord) -> Option<ObjectRay> {
    let i = r.hit.as_ref()?.instance?;
    r.steps.iter().rev().find_map(|s| match &s.step {
        Step::Instance {
            instance,
            origin,
            direction,
            to_object,
            ..
        } if *instance == i => Some((*origin, *direction, *to_object)),
        _ => None,
    })
}

/// The question's quantity in `trace` ([`Answer::None`] where the tracer never computed it).
pub fn extract(trace: &Trace, q: &Question) -> Answer {
    let Some(r) = ray(trace, q.ray) else {
        return Answer::None;
    };
    let steps = || r.steps.iter().map(|s| &s.step);
    let object = q.object.as_deref();
    // The last test against the object (a ray tests each object at most once; last to be safe).
    let sphere = || {
        steps()
            .filter_map(|s| match s {
                Step::Sphere { name, test, .. } if Some(name.as_str()) == object => Some(test),
                _ => None,
            })
            .next_back()
    };
    let triangle = || {
        let target = match object {
            Some(o) => Some(o.to_string()),
            None => r.hit.as_ref().map(|h| h.name.clone()),
        }?;
        steps()
            .filter_map(|s| match s {
                Step::Triangle { name, test, .. } if *name == target => Some(test),
                _ => None,
            })
            .next_back()
    };
    let surface = || {
        steps().find_map(|s| match s {
            Step::Surface { point, normal, .. } => Some((*point, *normal)),
            _ => None,
        })
    };
    match q.quantity {
        Quantity::Discriminant => num(sphere().map(|t| t.discriminant)),
        Quantity::NearRoot => num(sphere().and_then(|t| t.roots).map(|r| r[0])),
        Quantity::FarRoot => num(sphere().and_then(|t| t.roots).map(|r| r[1])),
        Quantity::ClosestT => num(r.hit.as_ref().map(|h| h.t)),
        Quantity::HitObject => r
            .hit
            .as_ref()
            .map_or(Answer::None, |h| Answer::Name(h.name.clone())),
        Quantity::HitPoint => surface().map_or(Answer::None, |(p, _)| v3(p)),
        Quantity::Normal => surface().map_or(Answer::None, |(_, n)| v3(n)),
        Quantity::ShadingNormal => steps()
            .find_map(|s| match s {
                Step::ShadingNormal { normal, .. } => Some(v3(*normal)),
                _ => None,
            })
            .unwrap_or(Answer::None),
        Quantity::TextureU | Quantity::TextureV | Quantity::TexelColumn | Quantity::TexelRow => {
            steps()
                .find_map(|s| match s {
                    Step::Texture {
                        uv,
                        lookup,
                        roughness: None,
                        ..
                    } => Some(match q.quantity {
                        Quantity::TextureU => Answer::Number(f64::from(uv[0])),
                        Quantity::TextureV => Answer::Number(f64::from(uv[1])),
                        _ => {
                            let k = usize::from(q.quantity == Quantity::TexelRow);
                            match lookup {
                                TexelLookup::Checker { cell, .. } => {
                                    Answer::Number(f64::from(cell[k]))
                                }
                                TexelLookup::Image { texels, .. } => texels
                                    .first()
                                    .map_or(Answer::None, |t| Answer::Number(f64::from(t.at[k]))),
                            }
                        }
                    }),
                    _ => None,
                })
                .unwrap_or(Answer::None)
        }
        Quantity::TextureColor => steps()
            .find_map(|s| match s {
                Step::Texture {
                    texel,
                    roughness: None,
                    ..
                } => Some(v3(*texel)),
                _ => None,
            })
            .unwrap_or(Answer::None),
        Quantity::ConeWidth | Quantity::MipLambda | Quantity::MipLevel => steps()
            .find_map(|s| match s {
                Step::Texture {
                    lookup: TexelLookup::Image { lod: Some(l), .. },
                    roughness: None,
                    ..
                } => Some(match q.quantity {
                    Quantity::ConeWidth => Answer::Number(f64::from(l.width)),
                    Quantity::MipLambda => Answer::Number(f64::from(l.lambda)),
                    _ => l
                        .levels
                        .first()
                        .map_or(Answer::None, |m| Answer::Number(f64::from(m.level))),
                }),
                _ => None,
            })
            .unwrap_or(Answer::None),
        Quantity::ObjectOrigin | Quantity::ObjectDirection => {
            instance_step(r).map_or(Answer::None, |(origin, direction, _)| {
                v3(if q.quantity == Quantity::ObjectOrigin {
                    origin
                } else {
                    direction
                })
            })
        }
        Quantity::TriangleU => num(triangle().and_then(|t| t.u)),
        Quantity::TriangleV => num(triangle().and_then(|t| t.v)),
        Quantity::BvhNodesVisited => {
            if trace.bvh.is_none() {
                return Answer::None;
            }
            Answer::Number(steps().filter(|s| matches!(s, Step::Node(_))).count() as f64)
        }
        Quantity::ShadowBlocked => steps()
            .find_map(|s| match s {
                Step::Light { light, blocked, .. } if *light == q.light => {
                    Some(Answer::YesNo(*blocked))
                }
                _ => None,
            })
            .unwrap_or(Answer::None),
        Quantity::ReflectedDirection => steps()
            .find_map(|s| match s {
                Step::Reflect { direction, .. } => Some(v3(*direction)),
                _ => None,
            })
            .unwrap_or(Answer::None),
        Quantity::RefractedDirection => steps()
            .find_map(|s| match s {
                Step::Refract { direction, .. } => Some(direction.map_or(Answer::None, v3)),
                _ => None,
            })
            .unwrap_or(Answer::None),
        Quantity::TotalInternalReflection => steps()
            .find_map(|s| match s {
                Step::Refract {
                    total_internal_reflection,
                    ..
                } => Some(Answer::YesNo(*total_internal_reflection)),
                _ => None,
            })
            .unwrap_or(Answer::None),
        Quantity::Color => v3(r.color),
        Quantity::BsdfPdf => steps()
            .find_map(|s| match s {
                Step::BsdfSample { pdf, .. } => Some(num(*pdf)),
                _ => None,
            })
            .unwrap_or(Answer::None),
        Quantity::SampleDirection => steps()
            .find_map(|s| match s {
                Step::BsdfSample { direction, .. } => Some(v3(*direction)),
                _ => None,
            })
            .unwrap_or(Answer::None),
        Quantity::Throughput => steps()
            .find_map(|s| match s {
                Step::BsdfSample { throughput, .. } => Some(v3(*throughput)),
                _ => None,
            })
            .unwrap_or(Answer::None),
        Quantity::LightPdf | Quantity::MisWeight | Quantity::LightContribution => steps()
            .find_map(|s| match s {
                Step::LightSample {
                    pdf,
                    mis_weight,
                    contribution,
                    ..
                } => Some(match q.quantity {
                    Quantity::LightPdf => num(Some(*pdf)),
                    Quantity::MisWeight => num(Some(*mis_weight)),
                    _ => v3(*contribution),
                }),
                _ => None,
            })
            .unwrap_or(Answer::None),
        Quantity::RouletteProbability => steps()
            .find_map(|s| match s {
                Step::RussianRoulette { probability, .. } => Some(num(Some(*probability))),
                _ => None,
            })
            .unwrap_or(Answer::None),
    }
}

/// The timeline index of the step that shows the question's quantity — where a student who got
/// it wrong should look: the sphere test for a discriminant or root, the triangle test for u and
/// v, the surface step for the hit point and normal, the last BVH node for the count of nodes,
/// the light's step for a shadow, the reflect or refract step, the colour step. `None` when the
/// trace has no such step (the ray was never spawned).
pub fn explaining_step(trace: &Trace, q: &Question) -> Option<usize> {
    let r = ray(trace, q.ray)?;
    let object = q.object.as_deref();
    let hit_name = r.hit.as_ref().map(|h| h.name.as_str());
    let is = |s: &Step| match q.quantity {
        Quantity::Discriminant | Quantity::NearRoot | Quantity::FarRoot => {
            matches!(s, Step::Sphere { name, .. } if Some(name.as_str()) == object)
        }
        Quantity::TriangleU | Quantity::TriangleV => {
            matches!(s, Step::Triangle { name, .. } if Some(name.as_str()) == object.or(hit_name))
        }
        Quantity::ClosestT | Quantity::HitObject | Quantity::HitPoint | Quantity::Normal => {
            matches!(s, Step::Surface { .. })
        }
        Quantity::ShadingNormal => matches!(s, Step::ShadingNormal { .. }),
        Quantity::TextureU
        | Quantity::TextureV
        | Quantity::TexelColumn
        | Quantity::TexelRow
        | Quantity::TextureColor
        | Quantity::ConeWidth
        | Quantity::MipLambda
        | Quantity::MipLevel => matches!(s, Step::Texture { .. }),
        Quantity::BvhNodesVisited => matches!(s, Step::Node(_)),
        Quantity::ShadowBlocked => matches!(s, Step::Light { light, .. } if *light == q.light),
        Quantity::ReflectedDirection => matches!(s, Step::Reflect { .. }),
        Quantity::RefractedDirection | Quantity::TotalInternalReflection => {
            matches!(s, Step::Refract { .. })
        }
        Quantity::Color => false,
        Quantity::BsdfPdf | Quantity::SampleDirection | Quantity::Throughput => {
            matches!(s, Step::BsdfSample { .. })
        }
        Quantity::LightPdf | Quantity::MisWeight | Quantity::LightContribution => {
            matches!(s, Step::LightSample { .. })
        }
        Quantity::RouletteProbability => matches!(s, Step::RussianRoulette { .. }),
        Quantity::ObjectOrigin | Quantity::ObjectDirection => matches!(
            s,
            Step::Instance { instance, .. }
                if Some(*instance) == r.hit.as_ref().and_then(|h| h.instance)
        ),
    };
    // The last matching step (a ray tests each object once; the last node is where the count
    // ends); the ray's last step when nothing matches (its colour, or where it missed).
    // The Monte Carlo quantities are the first sample of their kind (as `extract` reads them).
    let first = matches!(
        q.quantity,
        Quantity::BsdfPdf
            | Quantity::SampleDirection
            | Quantity::Throughput
            | Quantity::LightPdf
            | Quantity::MisWeight
            | Quantity::LightContribution
            | Quantity::RouletteProbability
    );
    let found = if first {
        r.steps.iter().find(|s| is(&s.step))
    } else {
        r.steps.iter().rev().find(|s| is(&s.step))
    };
    let target = found.or_else(|| r.steps.last())?;
    trace
        .timeline()
        .iter()
        .position(|(_, s)| std::ptr::eq(*s, target))
}
