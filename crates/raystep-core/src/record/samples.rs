//! What a Monte Carlo trace keeps beyond its one sample ([`McRecord`]): the lights its light
//! samples aimed at, the BSDF of each object it names, and a summary of every sample of the
//! pixel — its value, where it first hit, the points it sampled on lights there (blocked or
//! not) and the direction it bounced to. The diagrams of the hemisphere, the area light and the
//! pixel's samples draw from it, so a saved trace draws the same as a live one.
//!
//! A Whitted trace has none (its JSON is as before).

use crate::scene::Bsdf;
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// The most samples of its pixel a trace summarises (a pixel with more keeps its first ones;
/// [`McRecord::spp`] says how many it has).
pub const MAX_PIXEL_SAMPLES: usize = 1024;

/// The shape of a light (the Monte Carlo samplers' lights, `mc::lights`, and a trace's).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum LightShape {
    /// An emitting triangle.
    Triangle {
        /// Vertices.
        p: [Vec3; 3],
        /// Unit normal (the emitting side).
        normal: Vec3,
        /// Area.
        area: f32,
    },
    /// An emitting sphere.
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f32,
    },
    /// A point light.
    Point {
        /// Position.
        position: Vec3,
    },
}

/// The Monte Carlo part of a trace.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct McRecord {
    /// The pixel's samples per pixel (the summaries below are the first
    /// min(spp, [`MAX_PIXEL_SAMPLES`]) of them).
    pub spp: u32,
    /// Every light a light sample of the trace or of the summaries aimed at.
    pub lights: Vec<TraceLight>,
    /// The BSDF of each object of the trace ([`crate::record::Trace::objects`]).
    pub bsdfs: Vec<ObjectBsdf>,
    /// One summary per sample of the pixel, in sample order.
    pub samples: Vec<PixelSample>,
}

/// A light the Monte Carlo integrators sample.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TraceLight {
    /// Its index in the integrators' list of lights (a step's `light`).
    pub index: u32,
    /// The object's name (a mesh's triangles share it) or the point light's.
    pub name: String,
    /// The emitting object, if it is one.
    pub object: Option<u32>,
    /// Its shape.
    pub shape: LightShape,
    /// Emitted radiance (area lights) or intensity (point lights).
    #[serde(with = "crate::jsonf")]
    pub radiance: [f32; 3],
}

/// The BSDF an object's material gives the Monte Carlo integrators.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectBsdf {
    /// Object id.
    pub object: u32,
    /// Its BSDF.
    pub bsdf: Bsdf,
}

/// One sample of the pixel, summarised.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PixelSample {
    /// Sample index.
    pub sample: u32,
    /// What it adds to the pixel (linear RGB; the pixel is the mean of the finite ones).
    #[serde(with = "crate::jsonf")]
    pub color: [f32; 3],
    /// Where its camera ray first hit (None: it escaped).
    #[serde(with = "crate::jsonf")]
    pub hit: Option<[f32; 3]>,
    /// The unit normal there, facing the camera ray.
    #[serde(with = "crate::jsonf")]
    pub normal: Option<[f32; 3]>,
    /// The object it hit.
    pub object: Option<u32>,
    /// The points it sampled on lights at that first hit.
    pub light_samples: Vec<LightPointSample>,
    /// The direction its BSDF sampled there (the second ray of its path).
    #[serde(with = "crate::jsonf")]
    pub bounce: Option<[f32; 3]>,
}

/// A point sampled on a light at a sample's first hit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LightPointSample {
    /// The light's index (see [`TraceLight::index`]).
    pub light: u32,
    /// The point.
    #[serde(with = "crate::jsonf")]
    pub point: [f32; 3],
    /// Its density per steradian, the light's pick included (0 for a point light).
    #[serde(with = "crate::jsonf")]
    pub pdf: f32,
    /// Whether the shadow ray to it was blocked.
    pub blocked: bool,
    /// What it added to the pixel.
    #[serde(with = "crate::jsonf")]
    pub contribution: [f32; 3],
}

impl McRecord {
    /// The light with this index, if the trace keeps it.
    pub fn light(&self, index: u32) -> Option<&TraceLight> {
        self.lights.iter().find(|l| l.index == index)
    }

    /// The BSDF of this object, if the trace keeps it.
    pub fn bsdf_of(&self, object: u32) -> Option<&Bsdf> {
        self.bsdfs
            .iter()
            .find(|b| b.object == object)
            .map(|b| &b.bsdf)
    }

    /// The mean of the finite sample values kept, as the render divides: the sum of the finite
    /// ones, in sample order, over the number kept. With every sample kept (spp ≤
    /// [`MAX_PIXEL_SAMPLES`]) it is the rendered pixel, bit for bit.
    pub fn mean(&self) -> [f32; 3] {
        let mut sum = glam::Vec3::ZERO;
        for s in &self.samples {
            let c = glam::Vec3::from(s.color);
            if c.is_finite() {
                sum += c;
            }
        }
        (sum / self.samples.len().max(1) as f32).to_array()
    }
}

/// Rec. 709 luminance of a linear RGB value: what the samples diagram plots.
pub fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}
