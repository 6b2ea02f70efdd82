//! What a scene uses — the facts that decide what raystep builds, compiles and shows.

use super::{Material, Object, Shape};
use serde::{Deserialize, Serialize};

/// The scene's features (docs/ARCHITECTURE.md, invariant 4: leave out what a scene does not need).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct Features {
    /// Number of spheres.
    pub spheres: usize,
    /// Number of planes (general and axis-aligned).
    pub planes: usize,
    /// Number of triangles (loose and from meshes).
    pub triangles: usize,
    /// Number of smooth-shaded triangles (with vertex normals).
    #[serde(default)]
    pub smooth: usize,
    /// Number of objects whose material has a texture.
    #[serde(default)]
    pub textured: usize,
    /// Number of meshes.
    pub meshes: usize,
    /// Number of point lights.
    pub lights: usize,
    /// Whether any object's material reflects.
    pub reflective: bool,
    /// Whether any object's material transmits (refraction code is needed).
    pub transparent: bool,
    /// Total primitive count.
    pub primitives: usize,
    /// Primitives whose material emits: the Monte Carlo integrators' area lights.
    #[serde(default)]
    pub emitters: usize,
    /// Instances (`[[instance]]`): placed copies of prototypes, traced by the two-level BVH.
    #[serde(default)]
    pub instances: usize,
}

impl Features {
    /// Computes the features of a set of objects with their materials.
    pub fn compute(
        objects: &[Object],
        materials: &[Material],
        lights: usize,
        meshes: usize,
    ) -> Self {
        let mut f = Features {
            lights,
            meshes,
            primitives: objects.len(),
            ..Default::default()
        };
        let mut used = vec![false; materials.len()];
        for o in objects {
            match o.shape {
                Shape::Sphere { .. } => f.spheres += 1,
                Shape::Plane { .. } | Shape::AxisPlane { .. } => f.planes += 1,
                Shape::Triangle { .. } => f.triangles += 1,
            }
            f.smooth += usize::from(o.normals != super::NO_NORMALS);
            used[o.material as usize] = true;
            let m = &materials[o.material as usize];
            f.textured += usize::from(m.texture.is_some() || m.roughness_texture.is_some());
            f.emitters += usize::from(materials[o.material as usize].emission.max_element() > 0.0);
        }
        for (m, _) in materials.iter().zip(&used).filter(|(_, u)| **u) {
            f.reflective |= m.reflective > 0.0;
            f.transparent |= m.transparency > 0.0;
        }
        f
    }

    /// The primitive kinds present, in a fixed order.
    pub fn kinds(&self) -> Vec<&'static str> {
        let mut k = vec![];
        if self.spheres > 0 {
            k.push("sphere");
        }
        if self.planes > 0 {
            k.push("plane");
        }
        if self.triangles > 0 {
            k.push("triangle");
        }
        k
    }
}
