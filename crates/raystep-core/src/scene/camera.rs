//! Primary rays: the inverse mapping from a pixel to a ray (the camera convention in book/scenes.md, "The scene format").

use super::Camera;
use crate::math::{Ray, normalize};
use glam::Vec3;

/// The camera's basis, computed once per scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraRays {
    /// Eye position.
    pub origin: Vec3,
    /// Right.
    pub u: Vec3,
    /// Up.
    pub v: Vec3,
    /// Backwards (from `at` to `from`).
    pub w: Vec3,
    /// tan(fov/2)·width/height.
    pub half_width: f32,
    /// tan(fov/2).
    pub half_height: f32,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// γ = atan(2·tan(fov/2) / height), the angle one pixel subtends at the eye: a ray cone's
    /// spread (*Ray Tracing Gems*, ch. 20, eq. 20.30), computed in f64 and rounded once.
    pub spread: f32,
}

impl CameraRays {
    /// The basis of *Ray Tracing in One Weekend*: w = normalize(from − at), u = normalize(up × w),
    /// v = w × u. The scene loader has already rejected `from = at` and `up ∥ w`.
    pub fn new(c: &Camera) -> Self {
        let w = normalize(c.from - c.at);
        let u = normalize(c.up.cross(w));
        let v = w.cross(u);
        let half_height = (c.fov.to_radians() * 0.5).tan();
        CameraRays {
            origin: c.from,
            u,
            v,
            w,
            half_width: half_height * c.width as f32 / c.height as f32,
            half_height,
            width: c.width,
            height: c.height,
            spread: (2.0 * f64::from(half_height) / f64::from(c.height)).atan() as f32,
        }
    }

    /// Screen coordinates (sx, sy) ∈ [−1, 1]² of the point `offset` inside pixel (x, y):
    /// sx = 2(x + ox)/width − 1, sy = 1 − 2(y + oy)/height (y counts from the top).
    #[inline(always)]
    pub fn screen(&self, x: u32, y: u32, offset: [f32; 2]) -> [f32; 2] {
        [
            2.0 * (x as f32 + offset[0]) / self.width as f32 - 1.0,
            1.0 - 2.0 * (y as f32 + offset[1]) / self.height as f32,
        ]
    }

    /// The primary ray through `offset` inside pixel (x, y): direction
    /// normalize(sx·half_width·u + sy·half_height·v − w).
    #[inline(always)]
    pub fn ray(&self, x: u32, y: u32, offset: [f32; 2]) -> (Ray<f32>, [f32; 2]) {
        let s = self.screen(x, y, offset);
        let d = normalize(
            self.u * (s[0] * self.half_width) + self.v * (s[1] * self.half_height) - self.w,
        );
        // The direction is a unit vector built from a validated camera: never zero or NaN.
        (
            Ray {
                origin: self.origin,
                dir: d,
                t_min: 0.0,
                t_max: f32::INFINITY,
            },
            s,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(width: u32, height: u32, fov: f32) -> CameraRays {
        CameraRays::new(&Camera {
            from: Vec3::ZERO,
            at: Vec3::new(0.0, 0.0, -1.0),
            up: Vec3::Y,
            fov,
            width,
            height,
            aperture: 0.0,
            focus_distance: 1.0,
        })
    }

    // The Ray Tracer Challenge, ch. 7 ("Making a Scene"): a 201×101 canvas with a horizontal
    // field of view of π/2. Its half-height is 101/201; our fov is vertical, so the same camera is
    // fov = 2·atan(101/201). RTC's view transform mirrors x relative to the RTIOW basis (its camera
    // looks down −z with +x to the left of the image), so its x components change sign here.
    #[test]
    fn rtc_camera_vectors() {
        let fov = 2.0 * (101.0f32 / 201.0).atan().to_degrees();
        let c = cam(201, 101, fov);
        assert!((c.half_width - 1.0).abs() < 1e-6);
        let (centre, _) = c.ray(100, 50, [0.5, 0.5]);
        assert_eq!(centre.origin, Vec3::ZERO);
        assert!((centre.dir - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        let (corner, _) = c.ray(0, 0, [0.5, 0.5]);
        let rtc = Vec3::new(0.66519, 0.33259, -0.66851);
        assert!(
            (corner.dir - Vec3::new(-rtc.x, rtc.y, rtc.z)).length() < 1e-5,
            "{:?}",
            corner.dir
        );
    }

    #[test]
    fn pixel_centre_convention() {
        // Pixel (0, 0) of a 2×2 image: sx = 2·0.5/2 − 1 = −0.5, sy = 1 − 2·0.5/2 = 0.5.
        assert_eq!(cam(2, 2, 90.0).screen(0, 0, [0.5, 0.5]), [-0.5, 0.5]);
        assert_eq!(cam(2, 2, 90.0).screen(1, 1, [0.5, 0.5]), [0.5, -0.5]);
    }
}
