//! Sampling routines: uniform numbers in, a point or direction and its density out.
//!
//! Directions are in a local frame whose z axis is the surface normal (or, for a cone, the axis
//! to the sphere's centre); [`Frame`] takes them to world space. Each routine returns a
//! [`Sampled`] value with the density of having made it, in the measure its documentation names.
//! The formulas follow pbrt-v4 (Pharr, Jakob and Humphreys, *Physically Based Rendering*, 4th ed.,
//! ch. A.5 and 9.6) and Walter et al. 2007 for GGX; docs/SOURCES.md lists them. Sines and cosines
//! are [`super::portable::sin_cos`], so that the GPU computes the same directions bit for bit.

use super::portable::sin_cos;
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
    let z = (1.0 - x * x - y * y).max(0.0).sqrt();
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

/// A point uniform by area on the triangle `p`: density 1/area per unit area. None for a
/// degenerate triangle (no area).
pub fn triangle_point(p: [Vec3; 3], u: [f32; 2]) -> Option<Sampled<Vec3>> {
    let area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
    if area.is_nan() || area <= 0.0 || !area.is_finite() {
        return None;
    }
    let [b1, b2] = uniform_triangle(u);
    Some(Sampled {
        value: p[0] * (1.0 - b1 - b2) + p[1] * b1 + p[2] * b2,
        pdf: 1.0 / area,
    })
}

/// A direction, in the frame whose z axis points from the shading point to a sphere's centre,
/// uniform in the cone the sphere subtends: cos θ_max = √(1 − r²/d²), density 1/(2π(1 − cos θ_max))
/// per steradian. None when the point is on or inside the sphere (sample its area instead).
/// `distance`: from the point to the centre.
pub fn sphere_cone(distance: f32, radius: f32, u: [f32; 2]) -> Option<Sampled<Vec3>> {
    // Written so that NaN inputs give None too.
    let outside = distance > radius && radius > 0.0;
    if !outside {
        return None;
    }
    let sin2_max = (radius / distance) * (radius / distance);
    let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
    let cos = 1.0 - u[0] * (1.0 - cos_max);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let (sin_phi, cos_phi) = sin_cos(2.0 * PI * u[1]);
    let solid_angle = 2.0 * PI * (1.0 - cos_max);
    if solid_angle.is_nan() || solid_angle <= 0.0 {
        return None;
    }
    Some(Sampled {
        value: Vec3::new(sin * cos_phi, sin * sin_phi, cos),
        pdf: 1.0 / solid_angle,
    })
}

/// GGX's normal distribution D(h) for a microfacet normal at cos θ_h to the surface normal,
/// roughness α (Walter et al. 2007): α² / (π((α² − 1)cos²θ_h + 1)²); 0 below the surface.
pub fn ggx_d(alpha: f32, cos_h: f32) -> f32 {
    if cos_h <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = (a2 - 1.0) * cos_h * cos_h + 1.0;
    a2 / (PI * t * t)
}

/// A microfacet normal h distributed as D(h) cos θ_h (Walter et al. 2007, eq. 35–36):
/// tan²θ_h = α²u₀/(1 − u₀), φ = 2πu₁; density D(h) cos θ_h per steradian of h. `alpha` > 0.
pub fn ggx_normal(alpha: f32, u: [f32; 2]) -> Sampled<Vec3> {
    let tan2 = alpha * alpha * u[0] / (1.0 - u[0]).max(f32::MIN_POSITIVE);
    let cos = 1.0 / (1.0 + tan2).sqrt();
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let (sin_phi, cos_phi) = sin_cos(2.0 * PI * u[1]);
    Sampled {
        value: Vec3::new(sin * cos_phi, sin * sin_phi, cos),
        pdf: ggx_d(alpha, cos) * cos,
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
