//! What a question's pixel must show (`require` in a sheet): the premises its text states —
//! "the camera ray hits the red wall", "then a second diffuse surface", "it samples the small
//! light" — checked on the pixel's trace, so that a student's variant never asks about something
//! their pixel does not show. The variant generator ([`super::ExerciseSheet::variant`]) draws only
//! pixels whose trace satisfies them, and a sheet whose pixel range holds too few is refused when
//! it is loaded.

use super::Question;
use crate::record::{RayKind, RayRecord, Step, Trace};

/// One vertex of the path a question requires: what the k-th surface the path meets must be
/// (k = 0: the camera ray's hit; then each Monte Carlo bounce's).
#[derive(Debug, Clone, PartialEq)]
pub enum PathVertex {
    /// Any surface (the path must get there).
    Any,
    /// The object of this name (as traces name it).
    Object(String),
    /// An object whose material has this name.
    Material(String),
    /// An object whose Monte Carlo BSDF is of this kind (`diffuse`, `glossy`, `mirror`, `glass`).
    Bsdf(String),
    /// Any object of the instance of this name (`[[instance]] name`).
    Instance(String),
}

impl PathVertex {
    /// Reads `any`, `object:NAME`, `material:NAME`, `bsdf:KIND` or `instance:NAME`.
    pub fn parse(s: &str) -> Result<PathVertex, String> {
        let s = s.trim();
        if s == "any" {
            return Ok(PathVertex::Any);
        }
        let Some((kind, value)) = s.split_once(':') else {
            return Err(format!(
                "\"{s}\": expected \"any\", \"object:NAME\", \"material:NAME\", \"bsdf:KIND\" or \"instance:NAME\""
            ));
        };
        let value = value.trim().to_string();
        match kind.trim() {
            "object" => Ok(PathVertex::Object(value)),
            "instance" => Ok(PathVertex::Instance(value)),
            "material" => Ok(PathVertex::Material(value)),
            "bsdf" if ["diffuse", "glossy", "mirror", "glass"].contains(&value.as_str()) => {
                Ok(PathVertex::Bsdf(value))
            }
            "bsdf" => Err(format!(
                "\"{value}\" is not a BSDF kind: expected diffuse, glossy, mirror or glass"
            )),
            other => Err(format!(
                "\"{other}:\" is not a kind of vertex: expected object:, material:, bsdf: or instance:"
            )),
        }
    }

    /// In words ("the material \"red\"").
    pub fn describe(&self) -> String {
        match self {
            PathVertex::Any => "a surface".into(),
            PathVertex::Object(o) => format!("the object \"{o}\""),
            PathVertex::Material(m) => format!("an object of material \"{m}\""),
            PathVertex::Bsdf(b) => format!("a {b} surface"),
            PathVertex::Instance(i) => format!("the instance \"{i}\""),
        }
    }
}

/// How far from a whole number λ must be for a `mip_level` question to be asked.
pub const MIP_MARGIN: f64 = 0.01;

/// A question's premises (`require = { path = [...], sampled_light = "..." }`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Premise {
    /// The surfaces the path must meet, in order from the camera.
    pub path: Vec<PathVertex>,
    /// The light the question's ray's first light sample must aim at.
    pub sampled_light: Option<String>,
}

/// The next segment of a Monte Carlo path: the bounce ray a ray spawned (not its shadow rays).
fn bounce(r: &RayRecord) -> Option<&RayRecord> {
    r.children.iter().find(|c| {
        matches!(
            c.kind,
            RayKind::Diffuse | RayKind::Glossy | RayKind::Reflection | RayKind::Refraction
        )
    })
}

impl Premise {
    /// Whether `trace` satisfies the premise (and the question's quantity was computed); the
    /// reason when not, in words a sheet's author reads.
    pub fn check(&self, trace: &Trace, q: &Question) -> Result<(), String> {
        let mut ray = Some(&trace.root);
        for (k, want) in self.path.iter().enumerate() {
            let Some(r) = ray else {
                return Err(format!(
                    "the path ends before surface {} ({})",
                    k + 1,
                    want.describe()
                ));
            };
            let Some(hit) = &r.hit else {
                return Err(format!("surface {} ({}) is a miss", k + 1, want.describe()));
            };
            let object = trace.objects.iter().find(|o| o.id == hit.object);
            let ok = match want {
                PathVertex::Any => true,
                PathVertex::Object(o) => hit.name == *o,
                // An instanced hit is named "instance → object".
                PathVertex::Instance(i) => {
                    hit.instance.is_some() && hit.name.split(" → ").next() == Some(i.as_str())
                }
                PathVertex::Material(m) => object.is_some_and(|o| o.material == *m),
                PathVertex::Bsdf(b) => trace
                    .monte_carlo
                    .as_ref()
                    .and_then(|mc| mc.bsdfs.iter().find(|x| x.object == hit.object))
                    .is_some_and(|x| crate::mc::bsdf::name(&x.bsdf) == b),
            };
            if !ok {
                return Err(format!(
                    "surface {} is \"{}\", not {}",
                    k + 1,
                    hit.name,
                    want.describe()
                ));
            }
            ray = bounce(r);
        }
        if let Some(light) = &self.sampled_light {
            let r = super::extract::ray(trace, q.ray);
            let first = r.and_then(|r| {
                r.steps.iter().find_map(|s| match &s.step {
                    Step::LightSample { name, .. } => Some(name.as_str()),
                    _ => None,
                })
            });
            match first {
                Some(n) if n == light => {}
                Some(n) => {
                    return Err(format!(
                        "the first light sample aims at \"{n}\", not \"{light}\""
                    ));
                }
                None => return Err(format!("no light sample aims at \"{light}\"")),
            }
        }
        let answer = super::extract(trace, q);
        if answer == super::Answer::None {
            return Err(format!("the tracer computes no {}", q.quantity.name()));
        }
        // A mip level is ⌊λ⌋: where λ is nearly whole, a careful student's λ and the tracer's
        // f32 one may fall on either side, so such pixels are not asked about.
        if q.quantity == super::Quantity::MipLevel {
            let lambda = super::extract(
                trace,
                &Question {
                    quantity: super::Quantity::MipLambda,
                    ..q.clone()
                },
            );
            if let super::Answer::Number(l) = lambda
                && (l - l.round()).abs() < MIP_MARGIN
            {
                return Err(format!(
                    "λ = {l} is within {MIP_MARGIN} of a whole number: the level it picks is not clear-cut"
                ));
            }
        }
        Ok(())
    }

    /// The premise in words, for messages.
    pub fn describe(&self) -> String {
        let mut parts = vec![];
        if !self.path.is_empty() {
            let p: Vec<String> = self.path.iter().map(PathVertex::describe).collect();
            parts.push(format!("the path meets {}", p.join(", then ")));
        }
        if let Some(l) = &self.sampled_light {
            parts.push(format!("its first light sample aims at \"{l}\""));
        }
        if parts.is_empty() {
            "the quantity is computed".into()
        } else {
            parts.join(" and ")
        }
    }
}
