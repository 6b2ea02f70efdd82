//! The stages a course checks, one after another, and the words and scope every stage shares:
//! which rays a stage looks at and how feedback names a ray. Both the comparison (`compare`) and
//! the check that the student printed what a stage judges (`coverage`) read them.

use super::format::Pixel;
use serde::{Deserialize, Serialize};

/// What a course checks, one stage after another (each includes the ones before).
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Hash,
    Serialize,
    Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum Stage {
    /// The primary ray: origin and direction.
    Camera,
    /// Ray–sphere tests: a, b, c, the discriminant, t.
    Sphere,
    /// Ray–plane and ray–triangle tests.
    PlaneTriangle,
    /// The closest hit: object, t, point, normal.
    ClosestHit,
    /// What the surface gives shading (lessons 17–19): the shading normal, the texture
    /// coordinates, the texel read and the texture's colour. Graded only where raystep's trace
    /// has them (a smooth-shaded or textured hit).
    Surface,
    /// Shadows: each light blocked or not (and the shadow rays' tests).
    Shadows,
    /// Reflection and refraction rays (and their tests and hits).
    Secondary,
    /// The pixel's colour.
    Color,
    /// A path tracer's random numbers: raystep's hash, dimension for dimension (format v2).
    Random,
    /// Each sample's path: the camera ray, every ray's hit, the path's length.
    Path,
    /// The BSDF's samples: direction (in the right hemisphere) and pdf.
    BsdfSample,
    /// Next-event estimation: the light, the point, its pdf per steradian, blocked or not.
    LightSample,
    /// Each bounce: the BSDF's value, the cosine, the throughput, Russian roulette.
    Bounce,
    /// MIS weights of light samples and of emission found by BSDF samples.
    Mis,
    /// Each sample's value and the pixel's.
    Estimate,
}

impl Stage {
    /// A path tracer's stages (format version 2), in order.
    pub const PATH: [Stage; 7] = [
        Stage::Random,
        Stage::Path,
        Stage::BsdfSample,
        Stage::LightSample,
        Stage::Bounce,
        Stage::Mis,
        Stage::Estimate,
    ];

    /// Whether this is one of a path tracer's stages.
    pub fn is_path(self) -> bool {
        self >= Stage::Random
    }

    /// The stages a pixel is graded on up to `upto`: a Whitted scene's up to `upto`; a
    /// path-traced scene's up to `upto`, or all of them when `upto` is a Whitted stage (the
    /// default, `color`, among them).
    pub fn graded(upto: Stage, path: bool) -> Vec<Stage> {
        if path {
            Stage::PATH
                .iter()
                .copied()
                .filter(|s| !upto.is_path() || *s <= upto)
                .collect()
        } else {
            Stage::ALL.iter().copied().filter(|s| *s <= upto).collect()
        }
    }

    /// Whitted's stages (format version 1), in order.
    pub const ALL: [Stage; 8] = [
        Stage::Camera,
        Stage::Sphere,
        Stage::PlaneTriangle,
        Stage::ClosestHit,
        Stage::Surface,
        Stage::Shadows,
        Stage::Secondary,
        Stage::Color,
    ];

    /// The stage's name as the command line and sheets spell it.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Camera => "camera",
            Stage::Sphere => "sphere",
            Stage::PlaneTriangle => "plane-triangle",
            Stage::ClosestHit => "closest-hit",
            Stage::Surface => "surface",
            Stage::Shadows => "shadows",
            Stage::Secondary => "secondary",
            Stage::Color => "color",
            Stage::Random => "random",
            Stage::Path => "path",
            Stage::BsdfSample => "bsdf-sample",
            Stage::LightSample => "light-sample",
            Stage::Bounce => "bounce",
            Stage::Mis => "mis",
            Stage::Estimate => "estimate",
        }
    }
}

/// Which rays a stage looks at: the primary always, shadow rays from `Shadows`, reflection and
/// refraction rays from `Secondary`.
pub(crate) fn in_scope(kind: &str, upto: Stage) -> bool {
    match kind {
        "primary" => true,
        "shadow" => upto >= Stage::Shadows,
        _ => upto >= Stage::Secondary,
    }
}

/// How feedback names raystep's ray `i`.
pub fn ray_name(e: &Pixel, i: usize) -> String {
    let Some(r) = e.rays.get(i) else {
        return format!("ray {i}");
    };
    let what = match (r.kind.as_str(), &r.light) {
        ("primary", _) => "the primary ray".to_string(),
        ("shadow", Some(l)) => format!("the shadow ray towards light \"{l}\""),
        (k, _) => format!("the {k} ray"),
    };
    format!("ray {i} ({what}, depth {})", r.depth)
}
