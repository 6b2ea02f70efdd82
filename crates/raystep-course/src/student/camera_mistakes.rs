//! Naming a student's camera mistake: the primary ray each common mistake would give, built in
//! the camera's own frame (u right, v up, w backwards: lesson 1) and compared with the student's
//! direction. Judged in that frame, a flipped image is recognised whatever way the camera looks
//! (a tilted camera's flipped ray is not the raystep ray with world y negated).

use crate::scene::Camera;

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    if l > 0.0 { a.map(|x| x / l) } else { a }
}
fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = sub(a, b);
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// One way of building the primary ray, right or wrong.
#[derive(Clone, Copy)]
struct Build {
    /// Screen x and y multiplied by these (−1: flipped).
    flip: [f64; 2],
    /// The point inside the pixel (0.5, 0.5 = its centre).
    offset: [f64; 2],
    /// half_width = half_height (the aspect ratio left out).
    square: bool,
    /// half_height = tan(fov) instead of tan(fov / 2).
    whole_fov: bool,
    /// The angle's degrees taken as radians.
    degrees: bool,
    /// The scene's `up` used as the camera's v.
    raw_up: bool,
}

/// The unit direction `b` builds for pixel (x, y).
fn direction(c: &Camera, x: u32, y: u32, b: Build) -> [f64; 3] {
    let v3 = |v: glam::Vec3| [v.x as f64, v.y as f64, v.z as f64];
    let (from, at, up) = (v3(c.from), v3(c.at), v3(c.up));
    let w = unit(sub(from, at));
    let u = unit(cross(up, w));
    let v = if b.raw_up { up } else { cross(w, u) };
    let angle = if b.degrees {
        c.fov as f64
    } else {
        (c.fov as f64).to_radians()
    };
    let hh = if b.whole_fov {
        angle.tan()
    } else {
        (angle / 2.0).tan()
    };
    let hw = if b.square {
        hh
    } else {
        hh * c.width as f64 / c.height as f64
    };
    let sx = b.flip[0] * (2.0 * (x as f64 + b.offset[0]) / c.width as f64 - 1.0);
    let sy = b.flip[1] * (1.0 - 2.0 * (y as f64 + b.offset[1]) / c.height as f64);
    unit([0, 1, 2].map(|k| sx * hw * u[k] + sy * hh * v[k] - w[k]))
}

/// The mistake whose primary ray is `yours` (a unit direction) for pixel (x, y) sampled at
/// `offset`, as feedback names it; None when it is none of the common ones.
pub fn camera_hint(
    c: &Camera,
    [x, y]: [u32; 2],
    offset: [f32; 2],
    yours: [f64; 3],
) -> Option<&'static str> {
    let right = Build {
        flip: [1.0, 1.0],
        offset: offset.map(|o| o as f64),
        square: false,
        whole_fov: false,
        degrees: false,
        raw_up: false,
    };
    let mistakes: [(Build, &str); 8] = [
        (
            Build {
                flip: [1.0, -1.0],
                ..right
            },
            " — y is flipped: pixel rows count down from the top, the camera's up counts up (sy = 1 − 2(y + 0.5)/height)",
        ),
        (
            Build {
                flip: [-1.0, 1.0],
                ..right
            },
            " — x is flipped: check the sign of the camera's right vector (u = up × w, w pointing backwards)",
        ),
        (
            Build {
                flip: [-1.0, -1.0],
                ..right
            },
            " — x and y are both flipped: the image is upside down (rows count down from the top, u = up × w)",
        ),
        (
            Build {
                offset: [0.0, 0.0],
                ..right
            },
            " — the ray goes through the pixel's corner: aim at its centre (x + 0.5, y + 0.5)",
        ),
        (
            Build {
                square: true,
                ..right
            },
            " — the aspect ratio is missing: half_width = half_height · width / height",
        ),
        (
            Build {
                whole_fov: true,
                ..right
            },
            " — the field of view is the whole angle: half_height = tan(fov / 2)",
        ),
        (
            Build {
                degrees: true,
                ..right
            },
            " — fov is in degrees: convert it to radians before tan()",
        ),
        (
            Build {
                raw_up: true,
                ..right
            },
            " — the camera's v must be w × u, not the scene's `up` (they differ when the camera looks up or down)",
        ),
    ];
    let close = |b: Build| dist(direction(c, x, y, b), yours) < 1e-3;
    mistakes
        .iter()
        .find(|(b, _)| close(*b) && !close(right))
        .map(|(_, hint)| *hint)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A camera looking down at the scene, like three-spheres': a y-flipped ray is recognised
    /// although its world y is not raystep's negated.
    #[test]
    fn a_flipped_image_is_named_on_a_tilted_camera() {
        let c = Camera {
            from: glam::Vec3::new(0.0, 1.5, -5.0),
            at: glam::Vec3::new(0.0, 1.0, 0.0),
            up: glam::Vec3::Y,
            fov: 60.0,
            width: 320,
            height: 240,
            aperture: 0.0,
            focus_distance: 1.0,
        };
        let flipped = direction(
            &c,
            40,
            30,
            Build {
                flip: [1.0, -1.0],
                offset: [0.5, 0.5],
                square: false,
                whole_fov: false,
                degrees: false,
                raw_up: false,
            },
        );
        let right = direction(
            &c,
            40,
            30,
            Build {
                flip: [1.0, 1.0],
                offset: [0.5, 0.5],
                square: false,
                whole_fov: false,
                degrees: false,
                raw_up: false,
            },
        );
        // World y is not simply negated (the old test would not see it) ...
        assert!(
            (flipped[1] + right[1]).abs() > 1e-2,
            "{flipped:?} {right:?}"
        );
        // ... but the camera frame names it.
        let hint = camera_hint(&c, [40, 30], [0.5, 0.5], flipped).unwrap();
        assert!(hint.contains("y is flipped"), "{hint}");
        assert_eq!(camera_hint(&c, [40, 30], [0.5, 0.5], right), None);
    }
}
