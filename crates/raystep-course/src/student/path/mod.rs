//! Version 2 of the student trace format: a path tracer's samples, one record per event
//! (documented in `lessons/starter/README.md`, "The student trace format, version 2").
//!
//! A version 2 output starts with `{"type":"format","version":2}`, then a `pixel`, then for
//! every sample of the pixel a `path` record (its index) followed by its vertices: a `ray`
//! starts one (the camera ray, then each bounce's ray), and the records after it belong to it —
//! its `hit`, the `emission` found there, its `light-sample`s (next-event estimation), the
//! BSDF's `sample` (random numbers, direction, pdf), the `bounce` (BSDF value, cosine,
//! throughput) and the `roulette`; the path ends with its `value`. Random numbers are written
//! with their dimension (`{"dimension":16,"value":0.53}`), so the checker can compare them
//! with raystep's hash, [`crate::portable::random::uniform`], bit for bit.
//!
//! [`expected`] is raystep's own path tracer's samples of a pixel in this model, with the
//! timeline step of each record (for the `--step` links); [`write`] prints a model in the
//! format (`raystep trace --format student` on a path-traced scene); [`parse`] reads a
//! student's output.

use crate::record::observer::Recorder;
use crate::record::{RayKind, RayRecord, Step};
use crate::trace::PreparedScene;
use serde::{Deserialize, Serialize};

mod text;
pub use text::{FormatError, parse, write};

/// The version of the format with path records.
pub const PATH_VERSION: u32 = 2;

/// The most samples of a pixel the checker compares one by one (the pixel's first ones).
pub const MAX_CHECKED_SAMPLES: u32 = 16;

/// Below this |cos θ| at the light, a light sample's density is rounding noise (it grows as
/// 1 / cos θ): [`LightSample::grazing`].
pub const GRAZING: f64 = 0.02;

/// The deepest vertex compared (the camera ray's hit is depth 0): past the first bounce,
/// float32 rounding — amplified by every curved mirror — has moved raystep's path too far from
/// an exact tracer's for its numbers to be compared (a sample's value is compared when its path
/// ends by the second bounce).
pub const MAX_CHECKED_DEPTH: u32 = 1;

/// One random number and its dimension.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Draw {
    /// The dimension ([`crate::trace::monte_carlo::dimension`]).
    pub dimension: u32,
    /// The number, in [0, 1).
    pub value: f64,
}

/// One line of a version 2 output. Keys the format does not define are ignored; every key but
/// `type` may be left out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case")]
pub enum Record {
    /// `{"type":"format","version":2}`.
    Format {
        /// 2.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        version: Option<u32>,
    },
    /// Starts the pixel.
    Pixel {
        /// x.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        x: Option<u32>,
        /// y.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        y: Option<u32>,
    },
    /// Starts sample `sample` of the pixel.
    Path {
        /// The sample's index (0 … spp − 1).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        sample: Option<u32>,
    },
    /// Starts a vertex of the path: the camera ray (depth 0) or a bounce's ray.
    Ray {
        /// 0 for the camera ray, one more per bounce.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        depth: Option<u32>,
        /// Origin.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        origin: Option<[f64; 3]>,
        /// Direction (any length).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        direction: Option<[f64; 3]>,
    },
    /// The ray's closest hit (`object` null: the ray escaped).
    Hit {
        /// The object's name, or null.
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        object: Option<Option<String>>,
        /// The point.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        point: Option<[f64; 3]>,
        /// The unit normal, facing the ray.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        normal: Option<[f64; 3]>,
    },
    /// The hit surface emits, and the path counts it with weight `mis_weight`.
    Emission {
        /// Le.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        radiance: Option<[f64; 3]>,
        /// The weight it is counted with (1 from the camera; MIS against light sampling after
        /// a BSDF sample).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        mis_weight: Option<f64>,
        /// The density light sampling from the previous hit has for this point, per steradian.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        light_pdf: Option<f64>,
        /// The density of the BSDF sample that found it.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        bsdf_pdf: Option<f64>,
    },
    /// Next-event estimation: a light picked, a point on it, a shadow ray.
    LightSample {
        /// The light's name.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        light: Option<String>,
        /// The numbers drawn (the pick, then the point).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        random: Option<Vec<Draw>>,
        /// The point on the light.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        point: Option<[f64; 3]>,
        /// Its density per steradian, the pick included.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pdf: Option<f64>,
        /// The BSDF's density of the same direction.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        bsdf_pdf: Option<f64>,
        /// Its MIS weight.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        mis_weight: Option<f64>,
        /// Whether the shadow ray was blocked.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        blocked: Option<bool>,
        /// What it adds to the sample: throughput · f · Le · cos · w / pdf.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        contribution: Option<[f64; 3]>,
    },
    /// The BSDF samples the next direction.
    Sample {
        /// The numbers drawn.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        random: Option<Vec<Draw>>,
        /// The direction.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        direction: Option<[f64; 3]>,
        /// Its density per steradian (null for a mirror or glass: a delta).
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        pdf: Option<Option<f64>>,
    },
    /// The bounce: the BSDF's value, the cosine and the throughput after it.
    Bounce {
        /// f (a delta BSDF: leave it out).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        bsdf: Option<[f64; 3]>,
        /// |cos θ| of the direction with the normal.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        cos: Option<f64>,
        /// The throughput after this bounce (before roulette).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        throughput: Option<[f64; 3]>,
    },
    /// Russian roulette.
    Roulette {
        /// The number drawn.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        random: Option<Draw>,
        /// q, the probability of going on.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        probability: Option<f64>,
        /// Went on?
        #[serde(default, skip_serializing_if = "Option::is_none")]
        survived: Option<bool>,
        /// The throughput after it.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        throughput: Option<[f64; 3]>,
    },
    /// The sample's value: what it adds to the pixel.
    Value {
        /// r, g, b.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rgb: Option<[f64; 3]>,
    },
    /// The pixel: the mean of its samples.
    Color {
        /// r, g, b.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rgb: Option<[f64; 3]>,
    },
}

fn present<'de, D, T>(d: D) -> Result<Option<Option<T>>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Deserialize<'de>,
{
    Option::<T>::deserialize(d).map(Some)
}

/// The record types of version 2 (others are skipped).
pub const KNOWN_TYPES: [&str; 13] = [
    "format",
    "pixel",
    "path",
    "ray",
    "hit",
    "emission",
    "light-sample",
    "sample",
    "bounce",
    "roulette",
    "value",
    "color",
    "shadow",
];

/// A vertex's hit.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PathHit {
    /// The object's name.
    pub object: Option<String>,
    /// The point.
    pub point: Option<[f64; 3]>,
    /// The normal.
    pub normal: Option<[f64; 3]>,
}

/// Emission counted at a hit.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Emission {
    /// Le.
    pub radiance: Option<[f64; 3]>,
    /// Its weight.
    pub mis_weight: Option<f64>,
    /// Light sampling's density of this point.
    pub light_pdf: Option<f64>,
    /// The BSDF sample's density.
    pub bsdf_pdf: Option<f64>,
    /// The student's line, or raystep's timeline step.
    pub at: usize,
}

/// A light sample.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LightSample {
    /// The light's name.
    pub light: Option<String>,
    /// Its numbers.
    pub random: Vec<Draw>,
    /// The point.
    pub point: Option<[f64; 3]>,
    /// Density per steradian, pick included.
    pub pdf: Option<f64>,
    /// The BSDF's density of the direction.
    pub bsdf_pdf: Option<f64>,
    /// MIS weight.
    pub mis_weight: Option<f64>,
    /// Blocked?
    pub blocked: Option<bool>,
    /// Contribution.
    pub contribution: Option<[f64; 3]>,
    /// raystep's only: the same density per unit area of the light (pick included), the value a
    /// tracer that forgets to convert prints.
    pub area_pdf: Option<f64>,
    /// raystep's only: the light is seen edge-on from the point (|cos θ_light| below
    /// [`GRAZING`]), where the density d² / (A |cos θ_light|) is decided by rounding: its pdf
    /// and weight are not compared.
    pub grazing: bool,
    /// The student's line, or raystep's timeline step.
    pub at: usize,
}

/// The BSDF's sample.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BsdfSample {
    /// Its numbers.
    pub random: Vec<Draw>,
    /// The direction.
    pub direction: Option<[f64; 3]>,
    /// pdf: None = not given; Some(None) = a delta.
    pub pdf: Option<Option<f64>>,
    /// The student's line, or raystep's timeline step.
    pub at: usize,
}

/// A bounce's numbers.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Bounce {
    /// f.
    pub bsdf: Option<[f64; 3]>,
    /// cos.
    pub cos: Option<f64>,
    /// Throughput after it.
    pub throughput: Option<[f64; 3]>,
    /// The student's line, or raystep's timeline step.
    pub at: usize,
}

/// Russian roulette.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Roulette {
    /// The number.
    pub random: Option<Draw>,
    /// q.
    pub probability: Option<f64>,
    /// Went on?
    pub survived: Option<bool>,
    /// Throughput after it.
    pub throughput: Option<[f64; 3]>,
    /// The student's line, or raystep's timeline step.
    pub at: usize,
}

/// One vertex of a path: a ray and what happened where it landed.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Vertex {
    /// 0 for the camera ray.
    pub depth: u32,
    /// Origin.
    pub origin: Option<[f64; 3]>,
    /// Direction.
    pub direction: Option<[f64; 3]>,
    /// None: no record; Some(None): escaped.
    pub hit: Option<Option<PathHit>>,
    /// Emission counted here.
    pub emission: Option<Emission>,
    /// Light samples.
    pub lights: Vec<LightSample>,
    /// The BSDF's sample.
    pub sample: Option<BsdfSample>,
    /// The bounce.
    pub bounce: Option<Bounce>,
    /// Roulette.
    pub roulette: Option<Roulette>,
    /// The student's line, or raystep's timeline step.
    pub at: usize,
}

/// One sample of the pixel.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PathSample {
    /// Its index.
    pub sample: u32,
    /// Its vertices.
    pub vertices: Vec<Vertex>,
    /// Its value.
    pub value: Option<[f64; 3]>,
    /// The student's line, or raystep's timeline step (0).
    pub at: usize,
}

/// A pixel's samples.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PathPixel {
    /// x, y.
    pub at: Option<[u32; 2]>,
    /// The samples, in the order printed.
    pub samples: Vec<PathSample>,
    /// The pixel's value (the mean), if printed.
    pub color: Option<[f64; 3]>,
}

/// raystep's samples of a pixel, with what the checker needs around them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PathExpected {
    /// The samples (the first min(spp, [`MAX_CHECKED_SAMPLES`])); `color` is the pixel's
    /// rendered value over all its spp samples.
    pub pixel: PathPixel,
    /// The scene's seed (the random numbers' last input).
    pub seed: u32,
    /// The scene's samples per pixel.
    pub spp: u32,
    /// `sampler = "stratified"`: the numbers used are not the hash's.
    pub stratified: bool,
    /// `[render] strategy`.
    pub strategy: crate::scene::Strategy,
    /// The names of every object (for "no such object").
    pub names: Vec<String>,
    /// The scene's background: the radiance a ray that escapes brings back (a sample's value
    /// counts it times the throughput that reaches it).
    pub background: [f64; 3],
}

/// An f32 as the f64 with the same shortest decimal form.
fn f(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(x as f64)
}
fn v64(a: [f32; 3]) -> [f64; 3] {
    a.map(f)
}
fn draws(d: &[crate::record::Draw]) -> Vec<Draw> {
    d.iter()
        .map(|d| Draw {
            dimension: d.dimension,
            value: d.value as f64,
        })
        .collect()
}

/// Whether grade-tracer can check `scene` sample by sample: it is path traced.
pub fn applies(scene: &crate::scene::Scene) -> bool {
    scene.settings.integrator == crate::scene::Integrator::Path
}

/// raystep's path tracer's samples of pixel (x, y) in the version 2 model: samples 0 … n − 1,
/// n = min(spp, [`MAX_CHECKED_SAMPLES`]), each traced again with a recorder (the very numbers
/// the render draws), and the pixel's rendered value.
pub fn expected(prepared: &PreparedScene, x: u32, y: u32) -> PathExpected {
    let scene = prepared.scene();
    let s = &scene.settings;
    let tracer = prepared.tracer();
    let n = s.spp.min(MAX_CHECKED_SAMPLES);
    let mut samples = vec![];
    for k in 0..n {
        let mut rec = Recorder::new();
        let value = tracer.trace_sample(x, y, k, &mut rec);
        let Some(root) = rec.finish() else { continue };
        samples.push(sample_of(&root, k, value.to_array(), &tracer.lights));
    }
    let (color, _, _) = tracer.trace_pixel_checked(x, y, &mut crate::record::observer::Silent);
    PathExpected {
        pixel: PathPixel {
            at: Some([x, y]),
            samples,
            color: Some(v64(color.to_array())),
        },
        seed: s.seed,
        spp: s.spp,
        stratified: s.sampler == crate::scene::SamplerKind::Stratified,
        strategy: s.strategy,
        names: (0..scene.objects.len() as u32)
            .map(|i| scene.object_name(i))
            .collect(),
        background: v64(s.background.to_array()),
    }
}

/// One recorded sample as a path: the chain of non-shadow rays from the camera, each step's
/// timeline index kept (as `raystep trace --sample k` numbers them).
fn sample_of(
    root: &RayRecord,
    k: u32,
    value: [f32; 3],
    lights: &crate::mc::lights::Lights,
) -> PathSample {
    let mut out = PathSample {
        sample: k,
        value: Some(v64(value)),
        ..Default::default()
    };
    let mut step = 0usize;
    let mut ray = Some(root);
    while let Some(r) = ray.take() {
        let mut v = Vertex {
            depth: r.depth,
            origin: Some(v64(r.origin)),
            direction: Some(v64(r.direction)),
            at: step,
            ..Default::default()
        };
        let mut point_normal = None;
        let mut next = None;
        for st in &r.steps {
            let here = step;
            step += 1;
            match &st.step {
                Step::Surface { point, normal, .. } if point_normal.is_none() => {
                    point_normal = Some((v64(*point), v64(*normal)));
                }
                Step::Emitted {
                    radiance,
                    light_pdf,
                    bsdf_pdf,
                    mis_weight,
                    ..
                } => {
                    v.emission = Some(Emission {
                        radiance: Some(v64(*radiance)),
                        mis_weight: Some(f(*mis_weight)),
                        light_pdf: Some(f(*light_pdf)),
                        bsdf_pdf: Some(f(*bsdf_pdf)),
                        at: here,
                    })
                }
                Step::LightSample {
                    light,
                    name,
                    random,
                    point,
                    direction,
                    distance,
                    pdf,
                    bsdf_pdf,
                    mis_weight,
                    blocked,
                    contribution,
                    ..
                } => {
                    let cos_l = light_normal(lights, *light, *point).map(|n| {
                        (n[0] * direction[0] + n[1] * direction[1] + n[2] * direction[2]).abs()
                            as f64
                    });
                    let area_pdf =
                        cos_l.map(|c| *pdf as f64 * c / (*distance as f64 * *distance as f64));
                    v.lights.push(LightSample {
                        light: Some(name.clone()),
                        random: draws(random),
                        point: Some(v64(*point)),
                        pdf: Some(f(*pdf)),
                        bsdf_pdf: Some(f(*bsdf_pdf)),
                        mis_weight: Some(f(*mis_weight)),
                        blocked: Some(*blocked),
                        contribution: Some(v64(*contribution)),
                        area_pdf: area_pdf.filter(|p| p.is_finite() && *p > 0.0),
                        grazing: cos_l.is_some_and(|c| c < GRAZING),
                        at: here,
                    })
                }
                Step::BsdfSample {
                    random,
                    direction,
                    pdf,
                    value,
                    cos,
                    throughput,
                    bsdf,
                    ..
                } => {
                    let delta = bsdf == "mirror" || bsdf == "glass";
                    v.sample = Some(BsdfSample {
                        random: draws(random),
                        direction: Some(v64(*direction)),
                        pdf: Some(pdf.map(f)),
                        at: here,
                    });
                    v.bounce = Some(Bounce {
                        bsdf: (!delta).then(|| v64(*value)),
                        cos: Some(f(*cos)),
                        throughput: Some(v64(*throughput)),
                        at: here,
                    });
                }
                Step::RussianRoulette {
                    random,
                    probability,
                    survived,
                    throughput,
                } => {
                    v.roulette = Some(Roulette {
                        random: Some(Draw {
                            dimension: random.dimension,
                            value: random.value as f64,
                        }),
                        probability: Some(f(*probability)),
                        survived: Some(*survived),
                        throughput: Some(v64(*throughput)),
                        at: here,
                    })
                }
                Step::Spawn { child } => {
                    if let Some(c) = r.children.get(*child as usize) {
                        if c.kind == RayKind::Shadow {
                            step += count_steps(c);
                        } else {
                            next = Some(c);
                            // The child's steps follow here in the timeline; a path has
                            // nothing after its child.
                            break;
                        }
                    }
                }
                _ => {}
            }
        }
        v.hit = Some(r.hit.as_ref().map(|h| PathHit {
            object: Some(h.name.clone()),
            point: point_normal.map(|p| p.0),
            normal: point_normal.map(|p| p.1),
        }));
        out.vertices.push(v);
        ray = next;
    }
    out
}

/// The steps of a ray and its descendants, as the timeline counts them.
fn count_steps(r: &RayRecord) -> usize {
    r.steps.len() + r.children.iter().map(count_steps).sum::<usize>()
}

/// The unit normal of light `index` at `point` (None for a point light).
fn light_normal(
    lights: &crate::mc::lights::Lights,
    index: u32,
    point: [f32; 3],
) -> Option<[f32; 3]> {
    use crate::mc::lights::LightShape;
    match lights.lights.get(index as usize)?.shape {
        LightShape::Triangle { normal, .. } => Some(normal.to_array()),
        LightShape::Sphere { center, .. } => Some(
            (glam::Vec3::from(point) - center)
                .normalize_or_zero()
                .to_array(),
        ),
        LightShape::Point { .. } => None,
    }
}
