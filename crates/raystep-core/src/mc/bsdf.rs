//! The BSDFs of the Monte Carlo integrators ([`crate::scene::Bsdf`]): their value, their density
//! and their sampling. Every direction is a world-space unit vector pointing away from the surface;
//! `n` is the unit normal on the side the light leaves towards the viewer (`wo · n > 0`), as the
//! tracer's [`crate::trace::interaction::Interaction`] gives it.
//!
//! Formulas: Lambert; the perfect mirror; the smooth dielectric with the exact (unpolarized)
//! Fresnel equations and radiance scaled by 1/η² on refraction (pbrt-v4 §9.5); GGX microfacet
//! reflection with Smith's separable shadowing (Walter et al. 2007), tinted by the material's
//! colour as its (constant) Fresnel term.

use super::sample::{Frame, cosine_hemisphere, ggx_d, ggx_normal, sin2_between};
use crate::scene::Bsdf;
use glam::Vec3;
use std::f32::consts::PI;

/// The side of the surface a sampled direction leaves on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Lobe {
    /// Back to the viewer's side.
    Reflection,
    /// Through the surface.
    Transmission,
}

impl Lobe {
    /// The lobe's name in traces.
    pub fn name(self) -> &'static str {
        match self {
            Lobe::Reflection => "reflection",
            Lobe::Transmission => "transmission",
        }
    }
}

/// A direction sampled from a BSDF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BsdfSample {
    /// The direction the next ray takes.
    pub wi: Vec3,
    /// The BSDF's value f(wo, wi) (for a delta BSDF: the weight, f · cos / pdf).
    pub value: Vec3,
    /// The density per steradian; None for a delta (mirror, glass).
    pub pdf: Option<f32>,
    /// |wi · n|.
    pub cos: f32,
    /// f · cos / pdf: what the next ray's radiance is multiplied by.
    pub weight: Vec3,
    /// Which side it leaves on.
    pub lobe: Lobe,
}

/// The exact Fresnel reflectance of unpolarized light at a smooth dielectric: `cos_i` ≥ 0 on the
/// incident side, `eta` = n_transmitted / n_incident. Returns (reflectance, cos θₜ), cos θₜ None
/// under total internal reflection.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> (f32, Option<f32>) {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return (1.0, None);
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    (
        0.5 * (parallel * parallel + perpendicular * perpendicular),
        Some(cos_t),
    )
}

/// A smooth dielectric's two lobes at once: (the Fresnel reflectance F, the mirror reflection,
/// the refraction unless the light is totally internally reflected). Each lobe's weight is its
/// value given that it was chosen (1 for the reflection, 1/η² for the refraction's radiance
/// scaling): sampling picks the reflection with probability F, so its estimate is unbiased; the
/// distribution tracer follows both and weights them by F and 1 − F. `inside`: the light leaves
/// towards the inside of the object (`wo` comes from inside), so the far side is air.
pub fn glass_lobes(
    ior: f32,
    wo: Vec3,
    n: Vec3,
    inside: bool,
) -> (f32, BsdfSample, Option<BsdfSample>) {
    let cos_o = wo.dot(n);
    let eta = if inside { 1.0 / ior } else { ior };
    let (f, cos_t) = fresnel_dielectric(cos_o, eta);
    let reflection = BsdfSample {
        wi: mirror(wo, n),
        value: Vec3::ONE,
        pdf: None,
        cos: cos_o,
        weight: Vec3::ONE,
        lobe: Lobe::Reflection,
    };
    let transmission = cos_t.map(|cos_t| {
        let w = Vec3::splat(1.0 / (eta * eta));
        BsdfSample {
            wi: (-wo / eta + (cos_o / eta - cos_t) * n).normalize(),
            value: w,
            pdf: None,
            cos: cos_t,
            weight: w,
            lobe: Lobe::Transmission,
        }
    });
    (f, reflection, transmission)
}

/// Smith's masking term for GGX: G₁(v) = 2 / (1 + √(1 + α² tan²θ_v)).
fn smith_g1(alpha: f32, cos: f32) -> f32 {
    if cos <= 0.0 {
        return 0.0;
    }
    let cos2 = cos * cos;
    let tan2 = ((1.0 - cos2) / cos2).max(0.0);
    2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt())
}

/// The mirror direction of `wo` about `n`: 2(wo·n)n − wo.
pub fn mirror(wo: Vec3, n: Vec3) -> Vec3 {
    2.0 * wo.dot(n) * n - wo
}

/// The BSDF's name in scene files and traces.
pub fn name(b: &Bsdf) -> &'static str {
    match b {
        Bsdf::Diffuse { .. } => "diffuse",
        Bsdf::Mirror { .. } => "mirror",
        Bsdf::Glass { .. } => "glass",
        Bsdf::Glossy { .. } => "glossy",
    }
}

/// Whether the BSDF scatters into single directions only (no density: light sampling cannot
/// reach it).
pub fn is_delta(b: &Bsdf) -> bool {
    matches!(b, Bsdf::Mirror { .. } | Bsdf::Glass { .. })
}

/// A glossy BSDF's half vector h of `wo` and `wi`, cos θ_h about `n` and GGX's D(h); None where
/// h is undefined (wi = −wo). [`eval`], [`pdf`] and [`eval_pdf`] share it (and the two helpers
/// below), so the three compute the same bits.
#[inline(always)]
fn glossy_half(alpha: f32, wo: Vec3, wi: Vec3, n: Vec3) -> Option<(Vec3, f32, f32)> {
    let h = (wo + wi).normalize_or_zero();
    if h == Vec3::ZERO {
        return None;
    }
    let cos_h = h.dot(n);
    Some((h, cos_h, ggx_d(alpha, cos_h, sin2_between(h, n))))
}

/// The glossy BSDF's value: tint · D G / (4 cos θ_o cos θ_i), G Smith's two masking terms.
#[inline(always)]
fn glossy_value(tint: Vec3, alpha: f32, d: f32, cos_o: f32, cos_i: f32) -> Vec3 {
    let g = smith_g1(alpha, cos_o) * smith_g1(alpha, cos_i);
    tint * (d * g / (4.0 * cos_o * cos_i))
}

/// The glossy BSDF's density of `wi`: D(h) cos θ_h / (4 wo·h), 0 when h faces away from `wo`.
#[inline(always)]
fn glossy_density(wo: Vec3, h: Vec3, cos_h: f32, d: f32) -> f32 {
    let wo_h = wo.dot(h);
    if wo_h <= 0.0 {
        0.0
    } else {
        d * cos_h / (4.0 * wo_h)
    }
}

/// f(wo, wi): 0 for a delta BSDF (its value is not a function) and below the surface.
pub fn eval(b: &Bsdf, wo: Vec3, wi: Vec3, n: Vec3) -> Vec3 {
    let (cos_o, cos_i) = (wo.dot(n), wi.dot(n));
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return Vec3::ZERO;
    }
    match *b {
        Bsdf::Diffuse { albedo } => albedo / PI,
        Bsdf::Glossy { tint, alpha } => glossy_half(alpha, wo, wi, n)
            .map_or(Vec3::ZERO, |(_, _, d)| {
                glossy_value(tint, alpha, d, cos_o, cos_i)
            }),
        Bsdf::Mirror { .. } | Bsdf::Glass { .. } => Vec3::ZERO,
    }
}

/// The density, per steradian, of [`sample`] choosing `wi` (0 for a delta BSDF).
pub fn pdf(b: &Bsdf, wo: Vec3, wi: Vec3, n: Vec3) -> f32 {
    let (cos_o, cos_i) = (wo.dot(n), wi.dot(n));
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return 0.0;
    }
    match *b {
        Bsdf::Diffuse { .. } => cos_i / PI,
        Bsdf::Glossy { alpha, .. } => glossy_half(alpha, wo, wi, n)
            .map_or(0.0, |(h, cos_h, d)| glossy_density(wo, h, cos_h, d)),
        Bsdf::Mirror { .. } | Bsdf::Glass { .. } => 0.0,
    }
}

/// [`eval`] and [`pdf`] together, bit for bit: `(eval(b, wo, wi, n), pdf(b, wo, wi, n))`. The
/// path tracer needs both at every light sample and every glossy BSDF sample; a glossy BSDF's
/// half vector and GGX density D(h) (a square root and two divisions) are then computed once.
#[inline]
pub fn eval_pdf(b: &Bsdf, wo: Vec3, wi: Vec3, n: Vec3) -> (Vec3, f32) {
    let (cos_o, cos_i) = (wo.dot(n), wi.dot(n));
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return (Vec3::ZERO, 0.0);
    }
    match *b {
        Bsdf::Diffuse { albedo } => (albedo / PI, cos_i / PI),
        Bsdf::Glossy { tint, alpha } => {
            glossy_half(alpha, wo, wi, n).map_or((Vec3::ZERO, 0.0), |(h, cos_h, d)| {
                (
                    glossy_value(tint, alpha, d, cos_o, cos_i),
                    glossy_density(wo, h, cos_h, d),
                )
            })
        }
        Bsdf::Mirror { .. } | Bsdf::Glass { .. } => (Vec3::ZERO, 0.0),
    }
}

/// Samples a direction: `u_lobe` picks glass's lobe (reflection with the Fresnel reflectance's
/// probability), `u` makes the direction. `inside`: the ray arrived from inside the object (glass
/// then leaves into air). None when the sample leaves below the surface (a glossy normal that
/// reflects under the horizon): the path ends there.
#[inline(always)]
pub fn sample(
    b: &Bsdf,
    wo: Vec3,
    n: Vec3,
    inside: bool,
    u_lobe: f32,
    u: [f32; 2],
) -> Option<BsdfSample> {
    let cos_o = wo.dot(n);
    if cos_o <= 0.0 {
        return None;
    }
    match *b {
        Bsdf::Diffuse { albedo } => {
            let s = cosine_hemisphere(u);
            let wi = Frame::new(n).to_world(s.value).normalize();
            let cos = wi.dot(n);
            if cos <= 0.0 || s.pdf <= 0.0 {
                return None;
            }
            let f = albedo / PI;
            Some(BsdfSample {
                wi,
                value: f,
                pdf: Some(s.pdf),
                cos,
                weight: f * cos / s.pdf,
                lobe: Lobe::Reflection,
            })
        }
        Bsdf::Glossy { alpha, .. } => {
            let frame = Frame::new(n);
            let h = frame.to_world(ggx_normal(alpha, u).value).normalize();
            let wi = mirror(wo, h);
            let cos = wi.dot(n);
            if cos <= 0.0 {
                return None;
            }
            let (f, p) = eval_pdf(b, wo, wi, n);
            if p <= 0.0 || !p.is_finite() {
                return None;
            }
            Some(BsdfSample {
                wi,
                value: f,
                pdf: Some(p),
                cos,
                weight: f * cos / p,
                lobe: Lobe::Reflection,
            })
        }
        Bsdf::Mirror { tint } => Some(BsdfSample {
            wi: mirror(wo, n),
            value: tint,
            pdf: None,
            cos: cos_o,
            weight: tint,
            lobe: Lobe::Reflection,
        }),
        Bsdf::Glass { ior } => {
            let (f, reflection, transmission) = glass_lobes(ior, wo, n, inside);
            match transmission {
                Some(t) if u_lobe >= f => Some(t),
                _ => Some(reflection),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_matches_published_values() {
        // Glass n = 1.5 at normal incidence: ((1.5 − 1)/(1.5 + 1))² = 0.04.
        assert!((fresnel_dielectric(1.0, 1.5).0 - 0.04).abs() < 1e-6);
        // Brewster's angle, atan(1.5) = 56.31°: the parallel part vanishes, so R = R_s / 2 with
        // R_s = ((cos i − 1.5 cos t)/(cos i + 1.5 cos t))² = 0.1479 (Hecht, Optics, fig. 4.49).
        let cos_b = 1.5f32.atan().cos();
        assert!((fresnel_dielectric(cos_b, 1.5).0 - 0.1479 / 2.0).abs() < 1e-3);
        // From inside at 60° (beyond the critical angle 41.8°): total internal reflection.
        assert_eq!(fresnel_dielectric(0.5, 1.0 / 1.5), (1.0, None));
    }

    #[test]
    fn refraction_obeys_snell() {
        let n = Vec3::Z;
        let wo = Vec3::new(0.6, 0.0, 0.8);
        // u_lobe = 0.99: beyond the 4–5 % reflectance, so the transmitted lobe.
        let s = sample(&Bsdf::Glass { ior: 1.5 }, wo, n, false, 0.99, [0.5, 0.5]).unwrap();
        assert_eq!(s.lobe, Lobe::Transmission);
        // sin θₜ = sin θᵢ / 1.5 = 0.4, on the far side, away from wo's tangent direction.
        assert!((s.wi.x + 0.4).abs() < 1e-6 && s.wi.z < 0.0, "{:?}", s.wi);
        assert!((s.weight.x - 1.0 / 2.25).abs() < 1e-6);
    }

    #[test]
    fn eval_pdf_is_eval_and_pdf_bit_for_bit() {
        // Directions on both sides of the surface, grazing ones, the mirror pair (wo + wi = 0
        // never, but h = n exactly) and a half vector below the surface, for every BSDF.
        let bsdfs = [
            Bsdf::Diffuse {
                albedo: Vec3::new(0.7, 0.5, 0.3),
            },
            Bsdf::Glossy {
                tint: Vec3::new(0.9, 0.8, 0.35),
                alpha: 0.0025,
            },
            Bsdf::Glossy {
                tint: Vec3::splat(0.35),
                alpha: 0.25,
            },
            Bsdf::Mirror { tint: Vec3::ONE },
            Bsdf::Glass { ior: 1.5 },
        ];
        let n = Vec3::new(0.0, 0.6, 0.8);
        let mut state = 12345u32;
        let mut next = || {
            state = crate::portable::random::pcg_hash(state);
            crate::portable::random::unit_float(state) * 2.0 - 1.0
        };
        let mut dirs = vec![n, Vec3::new(0.0, 0.8, -0.6), Vec3::new(0.0, -0.6, -0.8)];
        dirs.push(mirror(Vec3::new(0.0, 0.8, -0.6), n));
        for _ in 0..400 {
            let v = Vec3::new(next(), next(), next());
            if v.length_squared() > 1e-6 {
                dirs.push(v.normalize());
            }
        }
        let mut both = 0;
        for b in &bsdfs {
            for &wo in &dirs {
                for &wi in &dirs {
                    let (f, p) = eval_pdf(b, wo, wi, n);
                    let (ef, ep) = (eval(b, wo, wi, n), pdf(b, wo, wi, n));
                    assert_eq!(
                        (f.to_array().map(f32::to_bits), p.to_bits()),
                        (ef.to_array().map(f32::to_bits), ep.to_bits()),
                        "{b:?} {wo} {wi}"
                    );
                    both += usize::from(p > 0.0 && f.max_element() > 0.0);
                }
            }
        }
        // The comparison covered pairs where both are non-zero, not only the early returns.
        assert!(both > 10_000, "{both}");
    }
}
