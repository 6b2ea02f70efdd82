//! The 3D view's own camera: an orbit around the scene, or the scene's camera itself ("look
//! through the camera"), with the projection both the GPU pass and the tests use.

use crate::scene::Camera;
use glam::{Mat4, Quat, Vec3, Vec4};

/// An orbit about the scene's camera's up vector, in degrees and relative distances: where the
/// 3D view looks from ([`ViewCamera::orbit`]) and how the app's GPU view moves the scene's camera
/// ([`Orbit::move_camera`]). The one orbit type of raystep: angles are degrees everywhere (the
/// command line's `--orbit` too) and become radians only inside the camera arithmetic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// Degrees around the scene camera's up vector; 0 = from behind the scene camera.
    pub yaw: f32,
    /// Degrees up: above the horizontal plane through the target (−89 … 89) for the 3D view,
    /// about the scene camera's right vector for [`Orbit::move_camera`].
    pub pitch: f32,
    /// The eye's distance from the target as a multiple of the distance that fits the whole
    /// scene (objects, lights, camera) in view: 1 fits it, 0.5 is twice as close.
    pub distance: f32,
    /// Shift of the target from the scene's centre, in world units (pan).
    pub pan: [f32; 3],
}

impl Default for Orbit {
    /// The 3D view's starting point: 35° round, 25° up, a little closer than fits the scene.
    fn default() -> Self {
        Orbit {
            yaw: 35.0,
            pitch: 25.0,
            distance: 0.8,
            pan: [0.0; 3],
        }
    }
}

impl Orbit {
    /// No turn, the reference distance, no pan: [`Orbit::move_camera`] leaves the scene's camera
    /// as it is (the GPU view's starting point).
    pub const IDENTITY: Orbit = Orbit {
        yaw: 0.0,
        pitch: 0.0,
        distance: 1.0,
        pan: [0.0; 3],
    };

    /// The scene camera `c` turned about its look-at point (the GPU view's camera): `yaw` degrees
    /// about its up vector, then `pitch` degrees about its right vector, the eye's distance to
    /// the look-at point times `distance`; same look-at point, up vector and field of view. `pan`
    /// is not used. [`Orbit::IDENTITY`] returns `c` unchanged.
    pub fn move_camera(&self, c: &Camera) -> Camera {
        if *self == Orbit::IDENTITY {
            return c.clone();
        }
        let offset = c.from - c.at;
        let up = c.up.normalize_or(Vec3::Y);
        let right = offset.cross(up).normalize_or(Vec3::X);
        let q = Quat::from_axis_angle(up, self.yaw.to_radians())
            * Quat::from_axis_angle(right, self.pitch.to_radians());
        Camera {
            from: c.at + q * offset * self.distance,
            ..c.clone()
        }
    }

    /// The orbit with its pitch kept off the poles and its distance positive and finite (what a
    /// drag or a scroll may push it to).
    pub fn sanitized(self) -> Orbit {
        let finite = |v: f32, d: f32| if v.is_finite() { v } else { d };
        Orbit {
            yaw: finite(self.yaw, 0.0).rem_euclid(360.0),
            pitch: finite(self.pitch, 0.0).clamp(-89.0, 89.0),
            distance: finite(self.distance, 1.0).clamp(0.02, 50.0),
            pan: self.pan.map(|p| finite(p, 0.0)),
        }
    }
}

/// A sphere around everything the view shows: the finite objects, the lights, the camera and
/// its image plane.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Bounds {
    /// The centre.
    pub center: Vec3,
    /// The radius (never zero).
    pub radius: f32,
}

/// A perspective view: eye, target, up, vertical field of view and aspect ratio.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewCamera {
    /// Where the eye is.
    pub eye: Vec3,
    /// The point looked at.
    pub target: Vec3,
    /// The up direction (need not be orthogonal to the view direction).
    pub up: Vec3,
    /// The vertical field of view, in degrees.
    pub fov_y: f32,
    /// Width / height of the picture.
    pub aspect: f32,
    /// Near clipping distance.
    pub near: f32,
    /// Far clipping distance.
    pub far: f32,
}

impl ViewCamera {
    /// The scene's own camera, matched exactly: a point on the primary ray through the centre
    /// of pixel (x, y) projects to (x + ½, y + ½) in a picture of the camera's size (raystep's
    /// convention: direction = sx·half_width·u + sy·half_height·v − w, half_height =
    /// tan(fov/2), y counted from the top).
    pub fn look_through(c: &Camera, bounds: &Bounds) -> ViewCamera {
        let reach = (c.from - bounds.center).length() + bounds.radius * 2.0;
        ViewCamera {
            eye: c.from,
            target: c.at,
            up: c.up,
            fov_y: c.fov,
            aspect: c.width as f32 / c.height.max(1) as f32,
            near: (reach * 2e-3).max(1e-4),
            far: reach.max(1e-3) * 2.0,
        }
    }

    /// An orbit around the scene: yaw and pitch about the scene camera's up vector, starting
    /// from behind the scene camera, at a distance that fits `bounds` in a view of `aspect`.
    pub fn orbit(c: &Camera, bounds: &Bounds, orbit: &Orbit, aspect: f32) -> ViewCamera {
        let o = orbit.sanitized();
        let up = c.up.normalize_or(Vec3::Y);
        let back = (c.from - c.at).normalize_or(Vec3::Z);
        let mut horizontal = back - up * back.dot(up);
        if horizontal.length_squared() < 1e-8 {
            horizontal = up.any_orthonormal_vector();
        }
        let fwd = horizontal.normalize();
        let side = up.cross(fwd);
        let (yaw, pitch) = (o.yaw.to_radians(), o.pitch.to_radians());
        let dir = (fwd * yaw.cos() + side * yaw.sin()) * pitch.cos() + up * pitch.sin();
        let fov_y = 40.0_f32;
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        // The distance at which the bounding sphere fills the narrower of the two angles.
        let tan_half = (fov_y.to_radians() * 0.5).tan();
        let half = tan_half.atan().min((tan_half * aspect).atan());
        let fit = bounds.radius / half.sin().max(1e-3) * 1.05;
        let distance = fit * o.distance;
        let target = bounds.center + Vec3::from(o.pan);
        ViewCamera {
            eye: target + dir * distance,
            target,
            up,
            fov_y,
            aspect,
            near: (distance - bounds.radius * 3.0)
                .max(distance * 1e-3)
                .max(1e-4),
            far: distance + bounds.radius * 4.0,
        }
    }

    /// World → clip space (wgpu's depth range 0…1).
    pub fn view_proj(&self) -> Mat4 {
        self.projection() * self.view_from(self.eye)
    }

    /// View → clip space.
    fn projection(&self) -> Mat4 {
        glam::camera::rh::proj::directx::perspective(
            self.fov_y.to_radians(),
            self.aspect,
            self.near,
            self.far,
        )
    }

    /// World → view space with the eye at `eye` (the origin, for points given relative to it).
    fn view_from(&self, eye: Vec3) -> Mat4 {
        glam::camera::rh::view::look_to_mat4(
            eye,
            (self.target - self.eye).normalize(),
            self.up.normalize_or(Vec3::Y),
        )
    }

    /// The view's right, up and backward unit vectors (u, v, w), as the scene camera's are made.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let w = (self.eye - self.target).normalize_or(Vec3::Z);
        let u = self.up.cross(w).normalize_or(Vec3::X);
        (u, w.cross(u), w)
    }

    /// Where `p` lands in a `width`×`height` picture, in pixels from the top-left (pixel (x, y)
    /// covers [x, x+1)×[y, y+1)); None when it is behind the eye.
    pub fn project(&self, p: Vec3, width: f32, height: f32) -> Option<[f32; 2]> {
        // Relative to the eye: with the eye far from the origin, the view matrix's translation
        // (−R·eye) and R·p cancel in f32 and move a point near the eye by a good part of a pixel
        // (acne.toml's camera, 26 000 units out: a third of a pixel).
        let q = p - self.eye;
        let c = self.projection() * self.view_from(Vec3::ZERO) * Vec4::new(q.x, q.y, q.z, 1.0);
        if c.w <= 0.0 {
            return None;
        }
        let (x, y) = (c.x / c.w, c.y / c.w);
        Some([(x + 1.0) * 0.5 * width, (1.0 - y) * 0.5 * height])
    }

    /// The ray from the eye through point `at` (pixels from the top-left) of a `width`×`height`
    /// picture: origin and unit direction (for picking objects with the mouse).
    pub fn ray_through(&self, at: [f32; 2], width: f32, height: f32) -> (Vec3, Vec3) {
        let (u, v, w) = self.basis();
        let hh = (self.fov_y.to_radians() * 0.5).tan();
        let hw = hh * self.aspect;
        let sx = 2.0 * at[0] / width.max(1.0) - 1.0;
        let sy = 1.0 - 2.0 * at[1] / height.max(1.0);
        let d = (u * (sx * hw) + v * (sy * hh) - w).normalize_or(-w);
        (self.eye, d)
    }

    /// The world length that covers one pixel at `p` in a picture `height` pixels tall (to size
    /// markers and handles so they look the same on screen at any distance).
    pub fn world_per_pixel(&self, p: Vec3, height: f32) -> f32 {
        let forward = (self.target - self.eye).normalize_or(Vec3::NEG_Z);
        let depth = (p - self.eye).dot(forward).max(self.near);
        2.0 * depth * (self.fov_y.to_radians() * 0.5).tan() / height.max(1.0)
    }
}

#[cfg(test)]
mod orbit_tests {
    use super::*;

    fn camera(from: Vec3) -> Camera {
        Camera {
            from,
            at: Vec3::ZERO,
            up: Vec3::Y,
            fov: 60.0,
            width: 320,
            height: 240,
            aperture: 0.0,
            focus_distance: 1.0,
        }
    }

    /// The GPU view's orbit, as it was in radians (app::gpu_view before the one orbit type):
    /// the same cameras from the same turns given in degrees.
    fn old_apply(yaw: f32, pitch: f32, distance: f32, c: &Camera) -> Camera {
        let offset = c.from - c.at;
        let up = c.up.normalize_or(Vec3::Y);
        let right = offset.cross(up).normalize_or(Vec3::X);
        let q = Quat::from_axis_angle(up, yaw) * Quat::from_axis_angle(right, pitch);
        Camera {
            from: c.at + q * offset * distance,
            ..c.clone()
        }
    }

    #[test]
    fn moving_the_camera_turns_it_in_degrees() {
        let c = camera(Vec3::new(0.0, 0.0, 5.0));
        assert_eq!(Orbit::IDENTITY.move_camera(&c), c);
        // A quarter turn about up (Y) takes the eye from +Z to +X; a quarter turn up, to +Y.
        let turned = |yaw, pitch| Orbit {
            yaw,
            pitch,
            ..Orbit::IDENTITY
        };
        let e = turned(90.0, 0.0).move_camera(&c).from;
        assert!((e - Vec3::new(5.0, 0.0, 0.0)).length() < 1e-5, "{e}");
        let e = turned(0.0, 90.0).move_camera(&c).from;
        assert!((e - Vec3::new(0.0, 5.0, 0.0)).length() < 1e-5, "{e}");
        let c = camera(Vec3::new(1.0, 2.0, -4.0));
        for (yaw, pitch, distance) in [(-0.4f32, 0.3f32, 1.0f32), (1.2, -1.4, 0.5), (3.0, 1.4, 2.0)]
        {
            let new = Orbit {
                yaw: yaw.to_degrees(),
                pitch: pitch.to_degrees(),
                distance,
                pan: [0.0; 3],
            }
            .move_camera(&c);
            let old = old_apply(yaw, pitch, distance, &c);
            assert!(
                (new.from - old.from).length() < 1e-5,
                "{} vs {}",
                new.from,
                old.from
            );
            assert_eq!((new.at, new.up, new.fov), (old.at, old.up, old.fov));
        }
    }
}
