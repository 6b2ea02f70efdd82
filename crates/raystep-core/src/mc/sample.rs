//! Sampling routines: uniform numbers in, a point or direction and its density out.
//!
//! Directions are in a local frame whose z axis is the surface normal (or, for a cone, the axis
//! to the sphere's centre); [`Frame`] takes them to world space. Each routine returns a
//! [`Sampled`] value with the density of having made it, in the measure its documentation names.
//! The formulas follow pbrt-v4 (Pharr, Jakob and Humphreys, *Physically Based Rendering*, 4th ed.,
//! ch. A.5 and 9.6) and Walter et al. 2007 for GGX; docs/SOURCES.md lists them. Sines and cosines
//! are [`crate::portable::math::sin_cos`], so that the GPU computes the same directions bit for bit.

use crate::portable::math::sin_cos;
use glam::Vec3;
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// A sampled value and its density.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sampled<T> {
    /// What was sampled.
    pub value: T,
    /// The density of sampling it, in the routine's measure.
    pub pdf: f32,
}

/// Shirley and Chiu's concentric map of the unit square onto the unit disk: uniform by area
/// (density 1/π), keeping strata compact (less distortion than √u, 2πv).
pub fn concentric_disk(u: [f32; 2]) -> [f32; 2] {
    let (a, b) = (2.0 * u[0] - 1.0, 2.0 * u[1] - 1.0);
    if a == 0.0 && b == 0.0 {
        return [0.0, 0.0];
    }
    let (r, theta) = if a.abs() > b.abs() {
        (a, FRAC_PI_4 * (b / a))
    } else {
        (b, FRAC_PI_2 - FRAC_PI_4 * (a / b))
    };
    let (sin, cos) = sin_cos(theta);
    [r * cos, r * sin]
}

/// A direction in the hemisphere z ≥ 0 with density cos θ / π per steradian (Malley's method:
/// a uniform point on the disk lifted to the hemisphere). The diffuse BSDF's importance sampling.
pub fn cosine_hemisphere(u: [f32; 2]) -> Sampled<Vec3> {
    let [x, y] = concentric_disk(u);
    // z² = 1 − x² − y² = 1 − r² with r = max(|2u₀ − 1|, |2u₁ − 1|) the disk point's radius,
    // written (1 − r)(1 + r): near the rim (grazing directions) 1 − x² − y² keeps none of the
    // digits of the small z², and the pdf z/π was not the density of the direction.
    let r = (2.0 * u[0] - 1.0).abs().max((2.0 * u[1] - 1.0).abs());
    let z = ((1.0 - r) * (1.0 + r)).max(0.0).sqrt();
    Sampled {
        value: Vec3::new(x, y, z),
        pdf: z / PI,
    }
}

/// A direction on the whole sphere, uniform: density 1/(4π) per steradian.
pub fn uniform_sphere(u: [f32; 2]) -> Sampled<Vec3> {
    let z = 1.0 - 2.0 * u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sin_phi, cos_phi) = sin_cos(2.0 * PI * u[1]);
    Sampled {
        value: Vec3::new(r * cos_phi, r * sin_phi, z),
        pdf: 1.0 / (4.0 * PI),
    }
}

/// Barycentric weights (of P1 and P2, as the tracer's u and v) of a point uniform by area on a
/// triangle: s = √u₀, weights (1 − s, s(1 − u₁), s·u₁).
pub fn uniform_triangle(u: [f32; 2]) -> [f32; 2] {
    let s = u[0].sqrt();
    [s * (1.0 - u[1]), s * u[1]]
}

/// The area of triangle `p`, ½|(P1 − P0) × (P2 − P0)|, computed in f64 and rounded: for
/// vertices near ±1e10 (inside the scene loader's bounds) the cross product's squared length
/// passes f32::MAX, so the f32 formula gives infinity where the area (≈ 1e20) is finite.
pub fn triangle_area(p: [Vec3; 3]) -> f32 {
    let [a, b, c] = p.map(|v| v.as_dvec3());
    (0.5 * (b - a).cross(c - a).length()) as f32
}

/// A point uniform by area on the triangle `p`: density 1/area per unit area (the area from
/// [`triangle_area`]). None for a degenerate triangle (no area).
pub fn triangle_point(p: [Vec3; 3], u: [f32; 2]) -> Option<Sampled<Vec3>> {
    let area = triangle_area(p);
    if area.is_nan() || area <= 0.0 || !area.is_finite() {
        return None;
    }
    let [b1, b2] = uniform_triangle(u);
    Some(Sampled {
        value: p[0] * (1.0 - b1 - b2) + p[1] * b1 + p[2] * b2,
        pdf: 1.0 / area,
    })
}

/// 1 − cos θ_max of the cone a sphere of `radius` subtends from `distance` away, and cos θ_max:
/// with sin²θ_max = r²/d², cos θ_max = √(1 − sin²θ_max), and 1 − cos θ_max written as
/// sin²θ_max / (1 + cos θ_max) (since (1 − cos)(1 + cos) = sin²). The textbook 1 − cos θ_max
/// subtracts two nearly equal numbers for a small or distant lamp and keeps only the digits
/// they differ in: 9.2e-5 off for lesson 13's lamp, 0.57 % for Veach's 0.03 lamp (the stability
/// lab's cone cases compare the two forms). Shared by the sampler and [`super::lights`]'s pdf,
/// so that the density printed is the density the sample was drawn with.
pub fn cone_one_minus_cos(distance: f32, radius: f32) -> (f32, f32) {
    let q = radius / distance;
    let sin2_max = q * q;
    let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
    (sin2_max / (1.0 + cos_max), cos_max)
}

/// A direction, in the frame whose z axis points from the shading point to a sphere's centre,
/// uniform in the cone the sphere subtends: density 1/(2π(1 − cos θ_max)) per steradian, with
/// 1 − cos θ_max from [`cone_one_minus_cos`]. cos θ = 1 − u₀(1 − cos θ_max), and sin θ from
/// sin²θ = x(2 − x) with x = u₀(1 − cos θ_max) (again without 1 − cos²θ's cancellation). None
/// when the point is on or inside the sphere (sample its area instead). `distance`: from the
/// point to the centre.
#[inline]
pub fn sphere_cone(distance: f32, radius: f32, u: [f32; 2]) -> Option<Sampled<Vec3>> {
    // Written so that NaN inputs give None too.
    let outside = distance > radius && radius > 0.0;
    if !outside {
        return None;
    }
    let (one_minus_cos_max, _) = cone_one_minus_cos(distance, radius);
    let x = u[0] * one_minus_cos_max;
    let cos = 1.0 - x;
    let sin = (x * (2.0 - x)).max(0.0).sqrt();
    let (sin_phi, cos_phi) = sin_cos(2.0 * PI * u[1]);
    let solid_angle = 2.0 * PI * one_minus_cos_max;
    if solid_angle.is_nan() || solid_angle <= 0.0 {
        return None;
    }
    Some(Sampled {
        value: Vec3::new(sin * cos_phi, sin * sin_phi, cos),
        pdf: 1.0 / solid_angle,
    })
}

/// GGX's normal distribution D(h) for a microfacet normal at angle θ_h to the surface normal,
/// roughness α (Walter et al. 2007): α² / (π(α² cos²θ_h + sin²θ_h)²); 0 below the surface.
/// Given cos θ_h and sin²θ_h: the textbook denominator (α² − 1)cos²θ_h + 1 is the same number,
/// but near a mirror (θ_h and α small) it subtracts nearly equal numbers and loses the digits
/// D depends on (6.7 % of the pdf at roughness 0.05).
pub fn ggx_d(alpha: f32, cos_h: f32, sin2_h: f32) -> f32 {
    if cos_h <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = a2 * (cos_h * cos_h) + sin2_h;
    a2 / (PI * t * t)
}

/// sin²θ between two unit vectors, as |a × b|²: accurate for small angles, where 1 − (a·b)²
/// keeps no digits.
pub fn sin2_between(a: Vec3, b: Vec3) -> f32 {
    a.cross(b).length_squared()
}

/// A microfacet normal h distributed as D(h) cos θ_h (Walter et al. 2007, eq. 35–36):
/// tan²θ_h = α²u₀/(1 − u₀), φ = 2πu₁, cos θ_h = 1/√(1 + tan²θ_h) and sin θ_h = √tan²θ_h · cos θ_h
/// (not √(1 − cos²θ_h), which loses the small angles of a near-mirror: 6.905e-4 for 8.071e-4 at
/// roughness 0.05); density D(h) cos θ_h per steradian of h. `alpha` > 0.
pub fn ggx_normal(alpha: f32, u: [f32; 2]) -> Sampled<Vec3> {
    let tan2 = alpha * alpha * u[0] / (1.0 - u[0]).max(f32::MIN_POSITIVE);
    let cos = 1.0 / (1.0 + tan2).sqrt();
    let sin = tan2.sqrt() * cos;
    let (sin_phi, cos_phi) = sin_cos(2.0 * PI * u[1]);
    Sampled {
        value: Vec3::new(sin * cos_phi, sin * sin_phi, cos),
        pdf: ggx_d(alpha, cos, sin * sin) * cos,
    }
}

/// A point on a thin lens of radius `radius` (the aperture's half-width), uniform by area
/// (the concentric map): density 1/(πr²) per unit area. None for a pinhole (radius 0).
pub fn thin_lens(radius: f32, u: [f32; 2]) -> Option<Sampled<[f32; 2]>> {
    if radius.is_nan() || radius <= 0.0 || !radius.is_finite() {
        return None;
    }
    let [x, y] = concentric_disk(u);
    Some(Sampled {
        value: [radius * x, radius * y],
        pdf: 1.0 / (PI * radius * radius),
    })
}

/// An orthonormal frame around a unit vector `n` (Duff et al. 2017, "Building an Orthonormal
/// Basis, Revisited"): takes local directions (z along `n`) to world space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// The local x axis.
    pub s: Vec3,
    /// The local y axis.
    pub t: Vec3,
    /// The local z axis.
    pub n: Vec3,
}

impl Frame {
    /// The frame of unit vector `n`.
    pub fn new(n: Vec3) -> Frame {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        Frame {
            s: Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
            t: Vec3::new(b, sign + n.y * n.y * a, -n.y),
            n,
        }
    }

    /// A local direction in world space.
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }

    /// A world direction in the local frame.
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_concentric_map_keeps_the_corners_and_the_centre() {
        assert_eq!(concentric_disk([0.5, 0.5]), [0.0, 0.0]);
        // (1, 0.5) → a = 1, b = 0: radius 1 at angle 0.
        let [x, y] = concentric_disk([1.0, 0.5]);
        assert!((x - 1.0).abs() < 1e-6 && y.abs() < 1e-6);
        // A corner of the square goes to the circle at 45°.
        let [x, y] = concentric_disk([1.0, 1.0]);
        assert!((x - FRAC_PI_4.cos()).abs() < 1e-6 && (y - FRAC_PI_4.sin()).abs() < 1e-6);
    }

    #[test]
    fn a_frame_is_orthonormal_and_round_trips() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(0.3, -0.4, 0.866).normalize(),
            Vec3::new(-0.1, 0.2, -0.97).normalize(),
        ] {
            let f = Frame::new(n);
            for (a, b) in [(f.s, f.t), (f.t, f.n), (f.s, f.n)] {
                assert!(a.dot(b).abs() < 1e-6);
            }
            for v in [f.s, f.t, f.n] {
                assert!((v.length() - 1.0).abs() < 1e-6);
            }
            let v = Vec3::new(0.2, -0.5, 0.7);
            assert!((f.to_local(f.to_world(v)) - v).length() < 1e-6);
            assert!((f.to_world(Vec3::Z) - n).length() < 1e-6);
        }
    }

    #[test]
    fn degenerate_inputs_give_none() {
        assert!(triangle_point([Vec3::ZERO; 3], [0.5, 0.5]).is_none());
        assert!(sphere_cone(1.0, 2.0, [0.5, 0.5]).is_none());
        assert!(sphere_cone(2.0, 0.0, [0.5, 0.5]).is_none());
        assert!(thin_lens(0.0, [0.5, 0.5]).is_none());
        assert!(thin_lens(f32::NAN, [0.5, 0.5]).is_none());
    }
}
