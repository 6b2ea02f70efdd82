//! The classic mistakes of the Monte Carlo and instance questions, each with the answer it gives for a
//! student's pixel: a wrong answer that matches one is named in the feedback and in the grades
//! file, and a question that lists one (`mistakes = [...]`) draws only pixels where that mistake's
//! answer is at least [`MIN_APART`] from the right one, so that the question tells them apart.
//! They are the mistakes `raystep grade-tracer` names in a student's own path tracer (a pdf
//! missing its cosine or π, a light's pdf left per unit area, a missing light-pick probability,
//! the balance heuristic for the power heuristic, no MIS at all), in the same words.

use super::{Answer, AnswerKind, Quantity, Question};
use crate::record::{Step, Tolerance, Trace};

/// The expected answer and the mistakes' answers for one pixel.
pub type Key = (Answer, Vec<(Mistake, Answer)>);

/// How far apart, relatively, a listed mistake's answer and the right answer must be at every
/// variant's pixel (5 %).
pub const MIN_APART: f64 = 0.05;

/// A classic mistake.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mistake {
    /// The MIS weight of the balance heuristic p_l / (p_l + p_b) for the power heuristic's.
    BalanceHeuristic,
    /// No MIS: a weight of 1.
    NoMis,
    /// A cosine-weighted direction's density without its cosine: 1/π.
    PdfNoCosine,
    /// A cosine-weighted direction's density without π: cos θ.
    PdfNoPi,
    /// GGX: the half vector's density D(h) cos θ_h, without the Jacobian 1 / (4 ωo·h).
    HalfVectorPdf,
    /// A light point's density per unit area (pick / A) instead of per steradian.
    AreaPdf,
    /// A light's density without the probability of having picked that light.
    NoPick,
    /// A light sample's estimate without the cosine at the surface.
    NoCosine,
    /// A light sample's estimate without its MIS weight.
    NoMisWeight,
    /// A light sample counted although its shadow ray is blocked.
    IgnoredShadow,
    /// An instance's normal carried by the matrix M instead of its inverse transpose M⁻ᵀ.
    NormalByMatrix,
    /// The ray's origin carried into object space by M⁻¹'s linear part alone (no translation).
    OriginNotTranslated,
    /// The ray's direction carried into object space as a point (translated by M⁻¹'s
    /// translation).
    DirectionTranslated,
}

/// Every mistake, for lookups.
pub const ALL: [Mistake; 13] = [
    Mistake::BalanceHeuristic,
    Mistake::NoMis,
    Mistake::PdfNoCosine,
    Mistake::PdfNoPi,
    Mistake::HalfVectorPdf,
    Mistake::AreaPdf,
    Mistake::NoPick,
    Mistake::NoCosine,
    Mistake::NoMisWeight,
    Mistake::IgnoredShadow,
    Mistake::NormalByMatrix,
    Mistake::OriginNotTranslated,
    Mistake::DirectionTranslated,
];

impl Mistake {
    /// The name sheets use (`mistakes = ["balance-heuristic"]`) and the grades file prints.
    pub fn id(self) -> &'static str {
        match self {
            Mistake::BalanceHeuristic => "balance-heuristic",
            Mistake::NoMis => "no-mis",
            Mistake::PdfNoCosine => "pdf-no-cosine",
            Mistake::PdfNoPi => "pdf-no-pi",
            Mistake::HalfVectorPdf => "half-vector-pdf",
            Mistake::AreaPdf => "area-pdf",
            Mistake::NoPick => "no-pick",
            Mistake::NoCosine => "no-cosine",
            Mistake::NoMisWeight => "no-mis-weight",
            Mistake::IgnoredShadow => "ignored-shadow",
            Mistake::NormalByMatrix => "normal-by-matrix",
            Mistake::OriginNotTranslated => "origin-not-translated",
            Mistake::DirectionTranslated => "direction-translated",
        }
    }

    /// The mistake of a name.
    pub fn from_id(id: &str) -> Option<Mistake> {
        ALL.into_iter().find(|m| m.id() == id)
    }

    /// What the student did, in words (the feedback's and the grades file's).
    pub fn describe(self) -> &'static str {
        match self {
            Mistake::BalanceHeuristic => {
                "that is the balance heuristic p_light / (p_light + p_bsdf); the power heuristic squares both densities"
            }
            Mistake::NoMis => {
                "that is weight 1 (no MIS); the power heuristic weighs the light sample by p_light² / (p_light² + p_bsdf²)"
            }
            Mistake::PdfNoCosine => {
                "that is 1/π, the density without its cosine: cosine-weighted sampling has density cos θ / π"
            }
            Mistake::PdfNoPi => "that is cos θ without the 1/π: the density is cos θ / π",
            Mistake::HalfVectorPdf => {
                "that is the half vector's density D(h) cos θh; the reflected direction's is that over 4 (ωo · h)"
            }
            Mistake::AreaPdf => {
                "that density is per unit area of the light (pick / area); convert it to solid angle: · d² / |cos θ_light|"
            }
            Mistake::NoPick => {
                "that density leaves out the probability of having picked this light"
            }
            Mistake::NoCosine => "that leaves out the cosine at the surface, cos θ",
            Mistake::NoMisWeight => "that leaves out the light sample's MIS weight",
            Mistake::IgnoredShadow => {
                "that counts the light although the shadow ray to it is blocked"
            }
            Mistake::NormalByMatrix => {
                "that is the normal carried by M itself; a normal goes by the inverse transpose M⁻ᵀ (then normalise)"
            }
            Mistake::OriginNotTranslated => {
                "that leaves out the translation: the origin is a point, so M⁻¹ moves it too"
            }
            Mistake::DirectionTranslated => {
                "that translates the direction: a direction is a difference of points, so only M⁻¹'s linear part applies"
            }
        }
    }

    /// The quantities the mistake can be made in.
    pub fn applies_to(self, q: Quantity) -> bool {
        match self {
            Mistake::BalanceHeuristic | Mistake::NoMis => q == Quantity::MisWeight,
            Mistake::PdfNoCosine | Mistake::PdfNoPi | Mistake::HalfVectorPdf => {
                q == Quantity::BsdfPdf
            }
            Mistake::AreaPdf | Mistake::NoPick => q == Quantity::LightPdf,
            Mistake::NoCosine | Mistake::NoMisWeight | Mistake::IgnoredShadow => {
                q == Quantity::LightContribution
            }
            Mistake::NormalByMatrix => q == Quantity::Normal,
            Mistake::OriginNotTranslated => q == Quantity::ObjectOrigin,
            Mistake::DirectionTranslated => q == Quantity::ObjectDirection,
        }
    }

    /// The answer the mistake gives for the question's pixel (computed in f64 from the numbers
    /// the trace records); None where it does not apply there (the balance heuristic where the
    /// light's density is 0, a cosine-pdf mistake at a glossy surface, …).
    pub fn answer(self, trace: &Trace, q: &Question) -> Option<Answer> {
        if !self.applies_to(q.quantity) {
            return None;
        }
        let r = super::extract::ray(trace, q.ray)?;
        let steps = || r.steps.iter().map(|s| &s.step);
        let light = || steps().find(|s| matches!(s, Step::LightSample { .. }));
        let f = f64::from;
        let v = |a: [f32; 3]| a.map(f64::from);
        // M⁻¹ (3 × 4, rows) applied in f64 to `p`, with or without its translation.
        let apply = |m: &[[f32; 4]; 3], p: [f64; 3], translate: bool| {
            [0, 1, 2].map(|i| {
                let row = m[i].map(f64::from);
                row[0] * p[0] + row[1] * p[1] + row[2] * p[2] + if translate { row[3] } else { 0.0 }
            })
        };
        match self {
            Mistake::OriginNotTranslated | Mistake::DirectionTranslated => {
                let (_, _, inv) = super::extract::instance_step(r)?;
                Some(Answer::Vector(if self == Mistake::OriginNotTranslated {
                    apply(&inv, v(r.origin), false)
                } else {
                    apply(&inv, v(r.direction), true)
                }))
            }
            Mistake::NormalByMatrix => {
                let (to_world, normal) = steps().find_map(|s| match s {
                    Step::InstanceHit {
                        to_world, normal, ..
                    } => Some((*to_world, *normal)),
                    _ => None,
                })?;
                let w = apply(&to_world, v(normal), false);
                let len = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
                (len > 0.0).then(|| Answer::Vector(w.map(|c| c / len)))
            }
            Mistake::BalanceHeuristic | Mistake::NoMis => {
                let Some(Step::LightSample { pdf, bsdf_pdf, .. }) = light() else {
                    return None;
                };
                let (p, b) = (f(*pdf), f(*bsdf_pdf));
                if p <= 0.0 {
                    return None;
                }
                Some(Answer::Number(if self == Mistake::NoMis {
                    1.0
                } else {
                    p / (p + b)
                }))
            }
            Mistake::PdfNoCosine | Mistake::PdfNoPi | Mistake::HalfVectorPdf => {
                let (bsdf, direction, pdf) = steps().find_map(|s| match s {
                    Step::BsdfSample {
                        bsdf,
                        direction,
                        pdf,
                        ..
                    } => Some((bsdf.as_str(), *direction, *pdf)),
                    _ => None,
                })?;
                let pdf = f(pdf?);
                match (self, bsdf) {
                    (Mistake::PdfNoCosine, "diffuse") => {
                        Some(Answer::Number(1.0 / std::f64::consts::PI))
                    }
                    (Mistake::PdfNoPi, "diffuse") => {
                        Some(Answer::Number(pdf * std::f64::consts::PI))
                    }
                    (Mistake::HalfVectorPdf, "glossy") => {
                        let wo = v(r.direction).map(|c| -c);
                        let wi = v(direction);
                        let h = [wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]];
                        let len = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
                        let wo_h = (wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2]) / len;
                        Some(Answer::Number(pdf * 4.0 * wo_h))
                    }
                    _ => None,
                }
            }
            Mistake::AreaPdf | Mistake::NoPick => {
                let Some(Step::LightSample {
                    light, select_pdf, ..
                }) = light()
                else {
                    return None;
                };
                let select = f(*select_pdf);
                let pdf = match super::extract::extract(trace, q) {
                    Answer::Number(x) => x,
                    _ => return None,
                };
                if self == Mistake::NoPick {
                    return (select < 1.0 && select > 0.0).then(|| Answer::Number(pdf / select));
                }
                let area = trace
                    .monte_carlo
                    .as_ref()?
                    .lights
                    .iter()
                    .find(|l| l.index == *light)
                    .and_then(|l| match l.shape {
                        crate::mc::lights::LightShape::Triangle { area, .. } => Some(f(area)),
                        _ => None,
                    })?;
                Some(Answer::Number(select / area))
            }
            Mistake::NoCosine | Mistake::NoMisWeight | Mistake::IgnoredShadow => {
                let Some(Step::LightSample {
                    pdf,
                    radiance,
                    bsdf,
                    cos,
                    mis_weight,
                    blocked,
                    ..
                }) = light()
                else {
                    return None;
                };
                let (pdf, cos, w) = (f(*pdf), f(*cos), f(*mis_weight));
                if pdf <= 0.0 || (self == Mistake::IgnoredShadow) != *blocked {
                    return None;
                }
                let (l, b) = (v(*radiance), v(*bsdf));
                let k = match self {
                    Mistake::NoCosine if !*blocked => w / pdf,
                    Mistake::NoMisWeight if !*blocked && w < 1.0 => cos / pdf,
                    Mistake::IgnoredShadow => cos * w / pdf,
                    _ => return None,
                };
                Some(Answer::Vector([0, 1, 2].map(|i| b[i] * l[i] * k)))
            }
        }
    }
}

/// The distance between two answers relative to the right one's size (numbers and vectors;
/// None for other kinds).
pub fn relative_distance(right: &Answer, other: &Answer) -> Option<f64> {
    let (a, b): (Vec<f64>, Vec<f64>) = match (right, other) {
        (Answer::Number(a), Answer::Number(b)) => (vec![*a], vec![*b]),
        (Answer::Vector(a), Answer::Vector(b)) => (a.to_vec(), b.to_vec()),
        _ => return None,
    };
    let d = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>();
    let n = a.iter().map(|x| x * x).sum::<f64>();
    Some(if n > 0.0 {
        (d / n).sqrt()
    } else {
        f64::INFINITY
    })
}

/// The mistake a wrong answer `given` (raw text) matches, of those found for its pixel: the
/// answer read as the question's kind is within the question's tolerance of the mistake's.
pub fn matching(
    given: Option<&str>,
    kind: AnswerKind,
    found: &[(Mistake, Answer)],
    tol: Tolerance,
) -> Option<Mistake> {
    found
        .iter()
        .find_map(|(m, a)| super::mark(a, kind, given, tol).right.then_some(*m))
}

/// Names the mistake a wrong answer matches in its mark's note, first ("that is the balance
/// heuristic …  [balance-heuristic]; not within the tolerance …"): what `check`, the app and the
/// grades file tell the student.
pub fn annotate(
    m: &mut super::Mark,
    q: &Question,
    given: Option<&str>,
    found: &[(Mistake, Answer)],
) {
    if m.right || m.unreadable {
        return;
    }
    if let Some(k) = matching(given, q.quantity.kind(), found, q.tolerance) {
        let named = format!("{} [{}]", k.describe(), k.id());
        m.note = Some(match m.note.take() {
            Some(n) => format!("{named}; {n}"),
            None => named,
        });
        m.mistake = Some(k);
    }
}
