//! The trace tree: a recorded [`Trace`] of one sample of one pixel, its rays ([`RayRecord`])
//! holding their [`StepRecord`]s, the closest hits, the objects and acceleration outlines the
//! diagrams draw, and reading and writing traces as JSON ([`TraceError`]). The steps themselves
//! are in [`super::steps`].

use super::steps::{RayKind, Stage, Step, TRACE_VERSION};
use serde::{Deserialize, Serialize};
use std::path::Path;
/// A step with its pipeline stage (the stage is stored so a trace reads without raystep).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepRecord {
    /// The pipeline stage.
    pub stage: Stage,
    /// The step.
    #[serde(flatten)]
    pub step: Step,
}

/// The closest hit of a ray.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HitRecord {
    /// Object id.
    pub object: u32,
    /// Object name.
    pub name: String,
    /// Hit distance.
    #[serde(with = "crate::jsonf")]
    pub t: f32,
    /// Triangle barycentric u, v (weights of P1 and P2).
    #[serde(with = "crate::jsonf")]
    pub uv: Option<[f32; 2]>,
    /// The instance the object was met through (`object` is then a prototype's, in object
    /// space); absent for an object of the world.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instance: Option<u32>,
}

/// One ray of the trace tree.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RayRecord {
    /// Kind.
    pub kind: RayKind,
    /// Recursion depth (primary = 0).
    pub depth: u32,
    /// Origin.
    #[serde(with = "crate::jsonf")]
    pub origin: [f32; 3],
    /// Direction.
    #[serde(with = "crate::jsonf")]
    pub direction: [f32; 3],
    /// Interval start.
    #[serde(with = "crate::jsonf")]
    pub t_min: f32,
    /// Interval end (∞ is stored as null in JSON).
    #[serde(with = "crate::jsonf")]
    pub t_max: Option<f32>,
    /// Steps in order.
    pub steps: Vec<StepRecord>,
    /// The closest hit (for shadow rays: the first blocker found).
    pub hit: Option<HitRecord>,
    /// Child rays, in the order they were traced.
    pub children: Vec<RayRecord>,
    /// The weight the parent multiplies this ray's colour by (1 for primary rays).
    #[serde(with = "crate::jsonf")]
    pub weight: f32,
    /// The colour this ray returns (linear RGB, before the parent's weight).
    #[serde(with = "crate::jsonf")]
    pub color: [f32; 3],
}

/// An object a trace refers to: what diagrams need to draw it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TraceObject {
    /// Object id.
    pub id: u32,
    /// Name.
    pub name: String,
    /// Geometry.
    pub shape: crate::scene::Shape,
    /// Material name.
    pub material: String,
    /// Surface colour (linear RGB).
    pub color: [f32; 3],
    /// Reflectivity.
    pub reflective: f32,
    /// Transparency.
    pub transparency: f32,
    /// Index of refraction.
    pub refractive_index: f32,
    /// Whether it is a prototype's object, whose `shape` lies in its object space (instances
    /// place it in the world): diagrams of world space leave it out.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub prototype: bool,
}

/// One node of the top of a BVH.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OutlineNode {
    /// Node index.
    pub node: u32,
    /// Depth (root = 0).
    pub depth: u32,
    /// Children's node indices (inner nodes), or None for a leaf.
    pub children: Option<[u32; 2]>,
    /// Number of primitives below the node.
    pub primitives: u32,
    /// Box minimum.
    pub min: [f32; 3],
    /// Box maximum.
    pub max: [f32; 3],
}

/// The uniform grid's shape: its box and how many cells it has along each axis (the cells are
/// equal boxes, `(max − min) / cells` wide).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GridOutline {
    /// The grid box's minimum corner.
    #[serde(with = "crate::jsonf")]
    pub min: [f32; 3],
    /// The grid box's maximum corner.
    #[serde(with = "crate::jsonf")]
    pub max: [f32; 3],
    /// Cells along x, y and z.
    pub cells: [u32; 3],
}

/// A whole recorded trace of one sample of one pixel.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Trace {
    /// Format version ([`TRACE_VERSION`]).
    pub version: u32,
    /// The raystep version that wrote it.
    pub raystep: String,
    /// The scene's name.
    pub scene: String,
    /// SHA-256 of the scene file.
    pub scene_hash: String,
    /// Pixel (x, y).
    pub pixel: [u32; 2],
    /// Sample index.
    pub sample: u32,
    /// The settings the trace was made with.
    pub settings: crate::scene::Settings,
    /// The primary ray and everything below it.
    pub root: RayRecord,
    /// The camera (so diagrams can draw the eye and the image plane without the scene).
    pub camera: crate::scene::Camera,
    /// The scene's lights.
    pub lights: Vec<crate::scene::Light>,
    /// Every object the trace tested or hit, with its geometry and material.
    pub objects: Vec<TraceObject>,
    /// The top levels of the BVH, when one was used (for the tree diagram).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bvh: Option<Vec<OutlineNode>>,
    /// The uniform grid's box and cell counts, when the grid was used (for the slice, which draws
    /// the cells its cutting plane crosses).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<GridOutline>,
    /// Under a Monte Carlo integrator: the lights, the BSDFs and every sample of the pixel
    /// summarised (for the hemisphere, area-light and samples diagrams).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub monte_carlo: Option<super::samples::McRecord>,
    /// The sample's final colour (linear RGB), bit-identical to the render's.
    #[serde(with = "crate::jsonf")]
    pub color: [f32; 3],
}

/// Why a trace file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum TraceError {
    /// The file could not be read.
    #[error("{file}: cannot read: {source}")]
    Io {
        /// The file.
        file: String,
        /// The cause.
        source: std::io::Error,
    },
    /// Not JSON, or not a trace.
    #[error("{file}:{line}:{column}: not a raystep trace: {message}")]
    Corrupt {
        /// The file.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What serde said.
        message: String,
    },
    /// A field out of range: an index that points nowhere, an enum stored as a number that has
    /// no such value, a BVH that is not a tree, a trace larger than raystep writes.
    #[error("{file}: field `{field}`: {message}")]
    Invalid {
        /// The file.
        file: String,
        /// The field's JSON path.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// A trace of a version this raystep does not read.
    #[error(
        "{file}: field `version`: trace format version {found} is not supported (this raystep reads version {TRACE_VERSION})"
    )]
    Version {
        /// The file.
        file: String,
        /// The version found.
        found: u64,
    },
}

impl Trace {
    /// Serializes to pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("traces serialize")
    }

    /// Parses a trace, checking the version before the rest so that a future format gets a
    /// version error rather than a confusing field error, and every field the readers index with
    /// or rely on after it (see [`crate::record::validate`]).
    pub fn from_json(text: &str, file: &str) -> Result<Trace, TraceError> {
        let corrupt = |e: serde_json::Error| TraceError::Corrupt {
            file: file.into(),
            // serde_json counts an empty input as column 0; our positions are 1-based.
            line: e.line().max(1),
            column: e.column().max(1),
            message: e.to_string(),
        };
        // Nesting measured first (without recursion), then parsed without serde_json's limit of
        // 128 levels, which a trace of a ray 60 bounces deep passes.
        let nesting = super::nesting::depth(text, super::nesting::MAX_NESTING);
        if nesting > super::nesting::MAX_NESTING {
            return Err(TraceError::Corrupt {
                file: file.into(),
                line: 1,
                column: 1,
                message: format!(
                    "nested more than {} levels deep: a trace raystep writes nests at most {} (a ray of depth 64)",
                    super::nesting::MAX_NESTING,
                    super::nesting::MAX_NESTING
                ),
            });
        }
        let value: serde_json::Value = super::nesting::parse(text).map_err(corrupt)?;
        match value.get("version").and_then(|v| v.as_u64()) {
            Some(v) if v == TRACE_VERSION as u64 => {}
            Some(found) => {
                return Err(TraceError::Version {
                    file: file.into(),
                    found,
                });
            }
            None => {
                return Err(TraceError::Corrupt {
                    file: file.into(),
                    line: 1,
                    column: 1,
                    message: "missing numeric field `version`".into(),
                });
            }
        }
        let trace: Trace = super::nesting::parse(text).map_err(corrupt)?;
        super::validate::validate(&trace).map_err(|e| TraceError::Invalid {
            file: file.into(),
            field: e.field,
            message: e.message,
        })?;
        Ok(trace)
    }

    /// Where the recording was cut (the step limit was reached): the timeline index of the
    /// [`Step::Truncated`] step, if any.
    pub fn truncated_at(&self) -> Option<usize> {
        self.timeline()
            .iter()
            .position(|(_, s)| matches!(s.step, Step::Truncated { .. }))
    }

    /// Reads a trace file.
    pub fn load(path: &Path) -> Result<Trace, TraceError> {
        let file = path.display().to_string();
        let text = crate::io::read_text(path, crate::io::limits::TRACE, "trace file").map_err(
            |source| TraceError::Io {
                file: file.clone(),
                source,
            },
        )?;
        Self::from_json(&text, &file)
    }

    /// Every ray in depth-first order (the order they were traced).
    pub fn rays(&self) -> Vec<&RayRecord> {
        fn walk<'a>(r: &'a RayRecord, out: &mut Vec<&'a RayRecord>) {
            out.push(r);
            for c in &r.children {
                walk(c, out);
            }
        }
        let mut out = vec![];
        walk(&self.root, &mut out);
        out
    }

    /// Every step in the order it happened, with the ray it belongs to (a timeline): a child
    /// ray's steps appear where its parent spawned it.
    pub fn timeline(&self) -> Vec<(&RayRecord, &StepRecord)> {
        fn walk<'a>(r: &'a RayRecord, out: &mut Vec<(&'a RayRecord, &'a StepRecord)>) {
            for s in &r.steps {
                out.push((r, s));
                if let Step::Spawn { child } = s.step
                    && let Some(c) = r.children.get(child as usize)
                {
                    walk(c, out);
                }
            }
        }
        let mut out = vec![];
        walk(&self.root, &mut out);
        out
    }
}
