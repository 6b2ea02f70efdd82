//! Phong lighting, reflection, Snell's law and Schlick's approximation, as in The Ray Tracer
//! Challenge (chapters 6 and 11).

use crate::portable::math::pow;
use crate::scene::Material;
use glam::Vec3;

/// The three Phong terms from one light, with the dot products that produced them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhongTerms {
    /// material colour × light colour × ambient.
    pub ambient: Vec3,
    /// material colour × light colour × diffuse × (l·n), or zero.
    pub diffuse: Vec3,
    /// light colour × specular × (r·e)^shininess, or zero.
    pub specular: Vec3,
    /// l·n.
    pub l_dot_n: f32,
    /// r·e.
    pub r_dot_e: f32,
    /// The unit light vector l = (L − P)/|L − P|.
    pub light_dir: Vec3,
    /// The reflected light vector r = reflect(−l, n).
    pub reflected: Vec3,
}

impl PhongTerms {
    /// ambient + diffuse + specular.
    #[inline(always)]
    pub fn sum(&self) -> Vec3 {
        self.ambient + self.diffuse + self.specular
    }
}

/// Phong lighting at `point` (RTC's `lighting`): `eye` and `normal` are unit vectors, `normal`
/// faces the eye; `color` is the surface's colour (the material's, times its texture's at the
/// point). In shadow only the ambient term remains.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn phong(
    m: &Material,
    color: Vec3,
    light_pos: Vec3,
    light_color: Vec3,
    point: Vec3,
    eye: Vec3,
    normal: Vec3,
    in_shadow: bool,
) -> PhongTerms {
    let effective = color * light_color;
    let to_light = light_pos - point;
    let lightv = to_light / to_light.length();
    let ambient = effective * m.ambient;
    let l_dot_n = lightv.dot(normal);
    let reflectv = reflect(-lightv, normal);
    let r_dot_e = reflectv.dot(eye);
    let (mut diffuse, mut specular) = (Vec3::ZERO, Vec3::ZERO);
    if !in_shadow && l_dot_n >= 0.0 {
        diffuse = effective * (m.diffuse * l_dot_n);
        if r_dot_e > 0.0 {
            specular = light_color * (m.specular * pow(r_dot_e, m.shininess));
        }
    }
    PhongTerms {
        ambient,
        diffuse,
        specular,
        l_dot_n,
        r_dot_e,
        light_dir: lightv,
        reflected: reflectv,
    }
}

/// Mirror reflection of `v` about the unit normal `n`: v − 2(v·n)n.
#[inline(always)]
pub fn reflect(v: Vec3, n: Vec3) -> Vec3 {
    reflect_recorded(v, n).1
}

/// [`reflect`] with its intermediate: (v·n, the reflected vector).
#[inline(always)]
pub fn reflect_recorded(v: Vec3, n: Vec3) -> (f32, Vec3) {
    let dn = v.dot(n);
    (dn, v - n * (2.0 * dn))
}

/// Snell's law for the unit eye vector `eye` (pointing away from the surface) and unit normal `n`
/// on the eye's side, going from index n1 into n2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Refraction {
    /// cos θᵢ = eye·n.
    pub cos_i: f32,
    /// sin² θₜ = (n1/n2)²(1 − cos² θᵢ).
    pub sin2_t: f32,
    /// The refracted direction, or None under total internal reflection (sin² θₜ > 1).
    pub direction: Option<Vec3>,
    /// η = n1/n2.
    pub eta: f32,
    /// cos θₜ = √(1 − sin² θₜ), or None under total internal reflection.
    pub cos_t: Option<f32>,
}

/// Refracts (RTC ch. 11): direction = n·(η cos θᵢ − cos θₜ) − eye·η with η = n1/n2.
#[inline(always)]
pub fn refract(eye: Vec3, n: Vec3, n1: f32, n2: f32) -> Refraction {
    let ratio = n1 / n2;
    let cos_i = eye.dot(n);
    let sin2_t = ratio * ratio * (1.0 - cos_i * cos_i);
    if sin2_t > 1.0 {
        return Refraction {
            cos_i,
            sin2_t,
            direction: None,
            eta: ratio,
            cos_t: None,
        };
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let d = n * (ratio * cos_i - cos_t) - eye * ratio;
    Refraction {
        cos_i,
        sin2_t,
        direction: Some(d),
        eta: ratio,
        cos_t: Some(cos_t),
    }
}

/// Schlick's approximation of the Fresnel reflectance (RTC ch. 11), 1 under total internal
/// reflection.
#[inline(always)]
pub fn schlick(cos_i: f32, n1: f32, n2: f32) -> f32 {
    schlick_recorded(cos_i, n1, n2).reflectance
}

/// Schlick's approximation with its intermediates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Schlick {
    /// R0 = ((n1 − n2)/(n1 + n2))², or None under total internal reflection.
    pub r0: Option<f32>,
    /// The cosine used: cos θᵢ, or cos θₜ when n1 > n2; None under total internal reflection.
    pub cos: Option<f32>,
    /// The reflectance R(θ) (1 under total internal reflection).
    pub reflectance: f32,
}

/// [`schlick`] with its intermediates.
#[inline(always)]
pub fn schlick_recorded(cos_i: f32, n1: f32, n2: f32) -> Schlick {
    let mut cos = cos_i;
    if n1 > n2 {
        let ratio = n1 / n2;
        let sin2_t = ratio * ratio * (1.0 - cos * cos);
        if sin2_t > 1.0 {
            return Schlick {
                r0: None,
                cos: None,
                reflectance: 1.0,
            };
        }
        cos = (1.0 - sin2_t).sqrt();
    }
    let r0 = ((n1 - n2) / (n1 + n2)).powi(2);
    Schlick {
        r0: Some(r0),
        cos: Some(cos),
        reflectance: r0 + (1.0 - r0) * (1.0 - cos).powi(5),
    }
}

/// The critical angle asin(n2/n1) in degrees, when n1 > n2.
pub fn critical_angle_deg(n1: f32, n2: f32) -> Option<f32> {
    (n1 > n2).then(|| (n2 / n1).asin().to_degrees())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn approx(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() < 1e-4
    }

    // The Ray Tracer Challenge, ch. 6 ("Light and Shading"): default material, point at origin.
    #[test]
    fn rtc_lighting_vectors() {
        let m = Material::default();
        let n = Vec3::new(0., 0., -1.);
        let s2 = 2f32.sqrt() / 2.0;
        let white = Vec3::ONE;
        let cases = [
            (
                Vec3::new(0., 0., -1.),
                Vec3::new(0., 0., -10.),
                Vec3::splat(1.9),
            ),
            (
                Vec3::new(0., s2, -s2),
                Vec3::new(0., 0., -10.),
                Vec3::splat(1.0),
            ),
            (
                Vec3::new(0., 0., -1.),
                Vec3::new(0., 10., -10.),
                Vec3::splat(0.7364),
            ),
            (
                Vec3::new(0., -s2, -s2),
                Vec3::new(0., 10., -10.),
                Vec3::splat(1.6364),
            ),
            (
                Vec3::new(0., 0., -1.),
                Vec3::new(0., 0., 10.),
                Vec3::splat(0.1),
            ),
        ];
        for (eye, light, expect) in cases {
            let got = phong(&m, m.color, light, white, Vec3::ZERO, eye, n, false).sum();
            assert!(approx(got, expect), "{got:?} vs {expect:?}");
        }
        // In shadow: ambient only.
        let shadowed = phong(
            &m,
            m.color,
            Vec3::new(0., 0., -10.),
            white,
            Vec3::ZERO,
            Vec3::new(0., 0., -1.),
            n,
            true,
        );
        assert!(approx(shadowed.sum(), Vec3::splat(0.1)));
    }

    #[test]
    fn rtc_reflect_vectors() {
        assert_eq!(
            reflect(Vec3::new(1., -1., 0.), Vec3::Y),
            Vec3::new(1., 1., 0.)
        );
        let s2 = 2f32.sqrt() / 2.0;
        assert!(approx(
            reflect(Vec3::new(0., -1., 0.), Vec3::new(s2, s2, 0.)),
            Vec3::X
        ));
    }

    #[test]
    fn rtc_schlick_vectors() {
        // RTC ch. 11: glass sphere (n = 1.5). Under TIR from inside at ray (0,0,√2/2) dir (0,1,0):
        // the eye vector makes cos θᵢ = √2/2 with the (inside) normal: Schlick = 1.
        let s2 = 2f32.sqrt() / 2.0;
        assert_eq!(schlick(s2, 1.5, 1.0), 1.0);
        // Perpendicular viewing: r0 = ((1 − 1.5)/(2.5))² = 0.04.
        assert!((schlick(1.0, 1.0, 1.5) - 0.04).abs() < 1e-5);
        // Small angle, n2 > n1: ray (0, 0.99, −2) → hit at y = 0.99 on the unit sphere,
        // normal (0, 0.99, −√(1 − 0.99²)), eye (0,0,−1): cos θᵢ = √(1 − 0.9801) = 0.141067.
        let cos = (1.0f32 - 0.99 * 0.99).sqrt();
        assert!((schlick(cos, 1.0, 1.5) - 0.48873).abs() < 1e-4);
    }

    #[test]
    fn refraction_total_internal_reflection() {
        let s2 = 2f32.sqrt() / 2.0;
        let r = refract(Vec3::new(0., s2, s2), Vec3::new(0., 0., 1.), 1.5, 1.0);
        assert!(r.direction.is_none());
        assert!(r.sin2_t > 1.0);
        // Straight through: no bending.
        let straight = refract(Vec3::new(0., 0., 1.), Vec3::new(0., 0., 1.), 1.0, 1.5);
        assert!(approx(straight.direction.unwrap(), Vec3::new(0., 0., -1.)));
        assert!((critical_angle_deg(1.5, 1.0).unwrap() - 41.8103).abs() < 1e-3);
    }
}
