//! The lights the Monte Carlo integrators sample: every primitive whose material emits (a sphere,
//! a triangle, each triangle of a mesh) and every point light.
//!
//! - A **triangle** is sampled uniformly by area (density 1/A per unit area, converted to solid
//!   angle: d² / (A |cos θ_light|)). It emits on the side its vertices wind counter-clockwise
//!   around (its normal (P1 − P0) × (P2 − P0)), as Mitsuba's area lights do.
//! - A **sphere** seen from outside is sampled uniformly in the cone it subtends (density
//!   1/(2π(1 − cos θ_max)) per steradian); it emits outwards, so from inside it gives nothing.
//! - A **point light** is a delta: its `color` is read as radiant intensity, and the radiance it
//!   delivers falls off as intensity / distance².
//!
//! The path tracer picks one light per bounce with probability proportional to its power
//! (mean of RGB × π × area for an area light, mean of RGB × 4π for a point light); the
//! distribution ray tracer samples every light group once (an object: one sphere, one triangle,
//! one mesh, picking a mesh's triangle by area).

use super::sample::{Frame, cone_one_minus_cos, sphere_cone, triangle_area, uniform_triangle};
use crate::scene::{Scene, Shape};
use glam::Vec3;
use std::f32::consts::PI;

pub use crate::record::samples::LightShape;

/// One light the integrators sample.
#[derive(Debug, Clone, PartialEq)]
pub struct McLight {
    /// The object's name (a mesh's triangles share it) or the point light's.
    pub name: String,
    /// The object id, for an emitting primitive.
    pub object: Option<u32>,
    /// Its shape.
    pub shape: LightShape,
    /// Emitted radiance (area lights) or intensity (point lights).
    pub radiance: Vec3,
    /// Its power, for picking it (see the module's documentation).
    pub power: f32,
}

/// A group of lights that the distribution ray tracer samples once: one scene object.
#[derive(Debug, Clone, PartialEq)]
pub struct LightGroup {
    /// The indices of its lights.
    pub members: Vec<u32>,
    /// The running sum of their areas (their pick probabilities are area / total).
    pub cdf: Vec<f32>,
}

/// Every light of a scene, for sampling.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Lights {
    /// The lights: emitting primitives in object order, then the point lights.
    pub lights: Vec<McLight>,
    /// The running sum of their powers.
    cdf: Vec<f32>,
    /// Which light each object is (u32::MAX: none).
    by_object: Vec<u32>,
    /// The groups (one per emitting object, one per point light).
    pub groups: Vec<LightGroup>,
}

/// A point sampled on a light, seen from a shading point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightPoint {
    /// The point.
    pub point: Vec3,
    /// Unit direction from the shading point to it.
    pub wi: Vec3,
    /// Distance to it.
    pub distance: f32,
    /// Density per steradian of the direction, given the light (0 for a point light).
    pub pdf: f32,
    /// Radiance arriving along `wi` (0 from an area light's back).
    pub radiance: Vec3,
}

fn mean(v: Vec3) -> f32 {
    (v.x + v.y + v.z) / 3.0
}

impl Lights {
    /// The lights of `scene`.
    pub fn new(scene: &Scene) -> Lights {
        let mut lights = vec![];
        let mut by_object = vec![u32::MAX; scene.objects.len()];
        let mut groups: Vec<LightGroup> = vec![];
        let mut group_of_scene_group: Vec<Option<usize>> = vec![None; scene.groups.len()];
        for (id, o) in scene.objects.iter().enumerate() {
            let m = &scene.materials[o.material as usize];
            if m.emission.max_element() <= 0.0 {
                continue;
            }
            let shape = match o.shape {
                Shape::Triangle { p } => {
                    // Area and normal in f64 (see `triangle_area`): the f32 cross product of a
                    // triangle near ±1e10 overflows, and such a lamp left the light list.
                    let area = triangle_area(p);
                    if !(area > 0.0 && area.is_finite()) {
                        continue;
                    }
                    let [a, b, c] = p.map(|v| v.as_dvec3());
                    LightShape::Triangle {
                        p,
                        normal: (b - a).cross(c - a).normalize().as_vec3(),
                        area,
                    }
                }
                Shape::Sphere { center, radius } => LightShape::Sphere { center, radius },
                // An infinite plane cannot be sampled by area: it emits when hit, unsampled.
                Shape::Plane { .. } | Shape::AxisPlane { .. } => continue,
            };
            let area = match shape {
                LightShape::Triangle { area, .. } => area,
                LightShape::Sphere { radius, .. } => 4.0 * PI * radius * radius,
                LightShape::Point { .. } => 0.0,
            };
            let index = lights.len() as u32;
            by_object[id] = index;
            let g = o.group as usize;
            let gi = match group_of_scene_group.get(g).copied().flatten() {
                Some(gi) => gi,
                None => {
                    groups.push(LightGroup {
                        members: vec![],
                        cdf: vec![],
                    });
                    if let Some(slot) = group_of_scene_group.get_mut(g) {
                        *slot = Some(groups.len() - 1);
                    }
                    groups.len() - 1
                }
            };
            let group = &mut groups[gi];
            let total = group.cdf.last().copied().unwrap_or(0.0);
            group.members.push(index);
            group.cdf.push(total + area);
            lights.push(McLight {
                name: scene.object_name(id as u32),
                object: Some(id as u32),
                shape,
                radiance: m.emission,
                power: mean(m.emission) * PI * area,
            });
        }
        for l in &scene.lights {
            let index = lights.len() as u32;
            groups.push(LightGroup {
                members: vec![index],
                cdf: vec![1.0],
            });
            lights.push(McLight {
                name: l.name.clone(),
                object: None,
                shape: LightShape::Point {
                    position: l.position,
                },
                radiance: l.color,
                power: mean(l.color) * 4.0 * PI,
            });
        }
        let mut cdf = Vec::with_capacity(lights.len());
        let mut total = 0.0f32;
        for l in &lights {
            total += l.power;
            cdf.push(total);
        }
        Lights {
            lights,
            cdf,
            by_object,
            groups,
        }
    }

    /// Whether there is no light to sample (or none with any power).
    pub fn is_empty(&self) -> bool {
        self.cdf.last().is_none_or(|t| *t <= 0.0)
    }

    /// Picks a light in proportion to its power with the uniform number `u`: (index, probability).
    pub fn pick(&self, u: f32) -> Option<(u32, f32)> {
        pick_cdf(&self.cdf, u)
    }

    /// The probability that [`Lights::pick`] picks light `index`.
    pub fn pick_pdf(&self, index: u32) -> f32 {
        let Some(total) = self.cdf.last().copied().filter(|t| *t > 0.0) else {
            return 0.0;
        };
        self.lights
            .get(index as usize)
            .map_or(0.0, |l| l.power / total)
    }

    /// The light an object is, if it emits.
    pub fn of_object(&self, object: u32) -> Option<u32> {
        self.by_object
            .get(object as usize)
            .copied()
            .filter(|i| *i != u32::MAX)
    }

    /// Samples a point on light `index` as seen from `p` with the uniform numbers `u`.
    #[inline(always)]
    pub fn sample(&self, index: u32, p: Vec3, u: [f32; 2]) -> Option<LightPoint> {
        let l = self.lights.get(index as usize)?;
        match l.shape {
            LightShape::Triangle { p: v, normal, area } => {
                // The point of sample::triangle_point, with the light's own area (computed in
                // f64 once: see `Lights::new`).
                let [b1, b2] = uniform_triangle(u);
                let q = v[0] * (1.0 - b1 - b2) + v[1] * b1 + v[2] * b2;
                let d = q - p;
                let distance = d.length();
                if distance.is_nan() || distance <= 0.0 {
                    return None;
                }
                let wi = d / distance;
                let cos_l = -wi.dot(normal);
                let (pdf, radiance) = if cos_l > 0.0 {
                    (distance * distance / (area * cos_l), l.radiance)
                } else {
                    (0.0, Vec3::ZERO)
                };
                Some(LightPoint {
                    point: q,
                    wi,
                    distance,
                    pdf,
                    radiance,
                })
            }
            LightShape::Sphere { center, radius } => {
                let to_center = center - p;
                let dc = to_center.length();
                let s = sphere_cone(dc, radius, u)?;
                let axis = to_center / dc;
                let wi = Frame::new(axis).to_world(s.value).normalize();
                // Where the sampled direction meets the sphere first: the near root of
                // |p + t wi − c|² = r², with the discriminant clamped at the cone's edge.
                let b = wi.dot(to_center);
                let disc = (radius * radius - (dc * dc - b * b)).max(0.0);
                let distance = b - disc.sqrt();
                if distance.is_nan() || distance <= 0.0 {
                    return None;
                }
                Some(LightPoint {
                    point: p + wi * distance,
                    wi,
                    distance,
                    pdf: s.pdf,
                    radiance: l.radiance,
                })
            }
            LightShape::Point { position } => {
                let d = position - p;
                let distance = d.length();
                if distance.is_nan() || distance <= 0.0 {
                    return None;
                }
                Some(LightPoint {
                    point: position,
                    wi: d / distance,
                    distance,
                    pdf: 0.0,
                    radiance: l.radiance / (distance * distance),
                })
            }
        }
    }

    /// The density per steradian with which [`Lights::sample`] of light `index` from `p` makes the
    /// point `q` (on the light), given the light.
    pub fn pdf(&self, index: u32, p: Vec3, q: Vec3) -> f32 {
        let Some(l) = self.lights.get(index as usize) else {
            return 0.0;
        };
        match l.shape {
            LightShape::Triangle { normal, area, .. } => {
                let d = q - p;
                let d2 = d.length_squared();
                let cos_l = (-d.normalize_or_zero().dot(normal)).abs();
                if cos_l <= 0.0 {
                    return 0.0;
                }
                d2 / (area * cos_l)
            }
            LightShape::Sphere { center, radius } => {
                let dc = (center - p).length();
                if dc <= radius {
                    return 0.0;
                }
                let (one_minus_cos_max, _) = cone_one_minus_cos(dc, radius);
                1.0 / (2.0 * PI * one_minus_cos_max)
            }
            LightShape::Point { .. } => 0.0,
        }
    }

    /// Picks a member of group `g` in proportion to its area: (light index, probability).
    pub fn pick_in_group(&self, g: usize, u: f32) -> Option<(u32, f32)> {
        let group = self.groups.get(g)?;
        let (k, p) = pick_cdf(&group.cdf, u)?;
        Some((*group.members.get(k as usize)?, p))
    }
}

/// Picks an index from a running sum with a uniform number in [0, 1): (index, probability).
fn pick_cdf(cdf: &[f32], u: f32) -> Option<(u32, f32)> {
    let total = *cdf.last()?;
    if total.is_nan() || total <= 0.0 {
        return None;
    }
    let target = u * total;
    let i = cdf.partition_point(|c| *c <= target).min(cdf.len() - 1);
    let before = if i == 0 { 0.0 } else { cdf[i - 1] };
    let p = (cdf[i] - before) / total;
    (p > 0.0).then_some((i as u32, p))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn picking_follows_the_running_sum() {
        let cdf = [1.0, 1.0, 4.0];
        assert_eq!(pick_cdf(&cdf, 0.0), Some((0, 0.25)));
        // Index 1 has zero weight: never picked.
        assert_eq!(pick_cdf(&cdf, 0.25), Some((2, 0.75)));
        assert_eq!(pick_cdf(&cdf, 0.999), Some((2, 0.75)));
        assert_eq!(pick_cdf(&[], 0.5), None);
        assert_eq!(pick_cdf(&[0.0], 0.5), None);
    }
}
