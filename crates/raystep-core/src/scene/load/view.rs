//! `[camera]` and `[render]`: the camera, the image's size within its limits, and the render
//! settings.

use super::*;

pub(super) const MAX_DIMENSION: i64 = 16384;
pub(super) const MAX_PIXELS: i64 = 40_000_000;

impl Ctx<'_> {
    pub(super) fn camera(&self, c: Option<&Spanned<CameraDef>>) -> Result<Camera, SceneError> {
        let default = CameraDef::default();
        let (loc, d) = match c {
            Some(c) => (self.loc("camera".into(), c), c.get_ref()),
            None => (
                Loc {
                    what: "camera".into(),
                    span: None,
                    ctx: self,
                },
                &default,
            ),
        };
        let from = loc.coord3("from", d.from)?;
        let at = loc.coord3("at", d.at)?;
        let up = loc.coord3("up", d.up)?;
        let fov = loc.num("fov", d.fov)?;
        if !(fov > 0.0 && fov < 180.0) {
            return Err(loc.err(
                "fov",
                format!("must lie strictly between 0 and 180 degrees, got {}", d.fov),
            ));
        }
        for (field, v) in [("width", d.width), ("height", d.height)] {
            if !(1..=MAX_DIMENSION).contains(&v) {
                return Err(loc.err(
                    field,
                    format!("must be between 1 and {MAX_DIMENSION} pixels, got {v}"),
                ));
            }
        }
        if d.width * d.height > MAX_PIXELS {
            return Err(loc.err(
                "width",
                format!(
                    "{}×{} is {} pixels, more than the limit of {MAX_PIXELS}",
                    d.width,
                    d.height,
                    d.width * d.height
                ),
            ));
        }
        let view = (from - at).as_dvec3();
        if view.length() == 0.0 {
            return Err(loc.err(
                "at",
                "`from` and `at` are the same point: the camera looks nowhere",
            ));
        }
        let w = view.normalize();
        if up.as_dvec3().length() == 0.0 || up.as_dvec3().normalize().cross(w).length() < 1e-6 {
            return Err(loc.err("up", format!("{:?} is parallel to the view direction (or zero): the camera's roll is undefined", d.up)));
        }
        let aperture = loc.num("aperture", d.aperture)?;
        if aperture < 0.0 {
            return Err(loc.err(
                "aperture",
                format!("must not be negative (0 is a pinhole), got {}", d.aperture),
            ));
        }
        let focus_distance = match d.focus_distance {
            Some(f) => {
                let f32v = loc.coord("focus_distance", f)?;
                if f32v <= 0.0 {
                    return Err(loc.err("focus_distance", format!("must be positive, got {f}")));
                }
                f32v
            }
            None => (from - at).length(),
        };
        let camera = Camera {
            from,
            at,
            up,
            fov,
            width: d.width as u32,
            height: d.height as u32,
            aperture,
            focus_distance,
        };
        // The checks above are in f64; the tracer builds its basis in f32, where a tiny
        // `from − at` or `up × w` underflows to zero and turns every ray into NaN. Build the
        // basis exactly as the tracer does and check it, and the rays through the corners.
        let rays = crate::scene::camera::CameraRays::new(&camera);
        let unit = |v: Vec3| v.is_finite() && (v.length() - 1.0).abs() < 1e-3;
        if !unit(rays.w) {
            return Err(loc.err(
                "at",
                format!(
                    "`from` {:?} and `at` {:?} are too close together for single precision: the view direction is not defined",
                    d.from, d.at
                ),
            ));
        }
        if !unit(rays.u) || !unit(rays.v) {
            return Err(loc.err(
                "up",
                format!("{:?} is too short (or too close to the view direction) for single precision: the camera's roll is undefined", d.up),
            ));
        }
        let (w, h) = (camera.width, camera.height);
        for (x, y) in [
            (0, 0),
            (w - 1, 0),
            (0, h - 1),
            (w - 1, h - 1),
            (w / 2, h / 2),
        ] {
            let (ray, _) = rays.ray(x, y, [0.5, 0.5]);
            if !ray.dir.is_finite() || !ray.origin.is_finite() {
                return Err(loc.err(
                    "fov",
                    format!("the ray through pixel ({x}, {y}) is not finite: the field of view {} cannot be traced", d.fov),
                ));
            }
        }
        Ok(camera)
    }

    pub(super) fn settings(&self, r: Option<&Spanned<RenderDef>>) -> Result<Settings, SceneError> {
        let default = RenderDef::default();
        let (loc, d) = match r {
            Some(r) => (self.loc("render".into(), r), r.get_ref()),
            None => (
                Loc {
                    what: "render".into(),
                    span: None,
                    ctx: self,
                },
                &default,
            ),
        };
        if !(0..=64).contains(&d.max_depth) {
            return Err(loc.err(
                "max_depth",
                format!("must be between 0 and 64, got {}", d.max_depth),
            ));
        }
        if !(1..=65536).contains(&d.spp) {
            return Err(loc.err("spp", format!("must be between 1 and 65536, got {}", d.spp)));
        }
        let epsilon = loc.num("epsilon", d.epsilon)?;
        if epsilon <= 0.0 {
            return Err(loc.err("epsilon", format!("must be positive, got {}", d.epsilon)));
        }
        if !(0..=u32::MAX as i64).contains(&d.seed) {
            return Err(loc.err(
                "seed",
                format!("must be between 0 and {}, got {}", u32::MAX, d.seed),
            ));
        }
        if !(0..=64).contains(&d.rr_depth) {
            return Err(loc.err(
                "rr_depth",
                format!("must be between 0 and 64, got {}", d.rr_depth),
            ));
        }
        let rr_depth = d.rr_depth;
        let integrator: Integrator = loc.choice("integrator", &d.integrator)?;
        let strategy: Strategy = loc.choice("strategy", &d.strategy)?;
        if strategy != Strategy::Mis && integrator != Integrator::Path {
            return Err(loc.err(
                "strategy",
                format!(
                    "\"{}\" applies to the path integrator (set integrator = \"path\"); the other integrators have no strategy to choose",
                    d.strategy
                ),
            ));
        }
        Ok(Settings {
            max_depth: d.max_depth as u32,
            spp: d.spp as u32,
            background: loc.color("background", d.background)?,
            sphere_method: loc.choice("sphere_method", &d.sphere_method)?,
            triangle_method: loc.choice("triangle_method", &d.triangle_method)?,
            offset: loc.choice("offset", &d.offset)?,
            epsilon,
            accel: loc.choice("accel", &d.accel)?,
            bvh_quality: loc.choice("bvh_quality", &d.bvh_quality)?,
            seed: d.seed as u32,
            integrator,
            rr_depth: rr_depth as u32,
            strategy,
            sampler: loc.choice("sampler", &d.sampler)?,
            terminator: loc.choice("terminator", &d.terminator)?,
        })
    }
}
