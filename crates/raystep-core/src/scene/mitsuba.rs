//! Writes a scene in Mitsuba 3's XML format, so an independent renderer can render what raystep's
//! path tracer renders (the tests and `raystep bench --section path` compare the two).
//!
//! What maps: the perspective camera (vertical field of view, a box pixel filter), the path
//! integrator (Mitsuba's `max_depth` is raystep's plus one: Mitsuba counts path segments, raystep
//! bounces), triangles and meshes (as OBJ files of their triangles, face normals, so their
//! winding decides an area light's side as in raystep), spheres, the four BSDFs (`diffuse`;
//! `mirror` as a `conductor` with no Fresnel and the colour as its reflectance; `glass` as a
//! `dielectric`; `glossy` as a `roughconductor` with GGX, the same α and no Fresnel), emission as
//! an `area` emitter, point lights as `point` emitters and the background as a `constant`
//! environment, and a thin lens as Mitsuba's `thinlens` sensor. Infinite planes have no
//! equivalent here: they are refused.

use super::{Bsdf, Scene, Shape};
use std::fmt::Write;

/// A scene in Mitsuba's format: the XML and the OBJ files it names (file name, contents).
#[derive(Debug, Clone, PartialEq)]
pub struct MitsubaScene {
    /// The scene's XML.
    pub xml: String,
    /// OBJ files the XML refers to, by file name (to be written beside it).
    pub objs: Vec<(String, String)>,
}

fn v(a: glam::Vec3) -> String {
    format!("{:e},{:e},{:e}", a.x, a.y, a.z)
}

/// The scene in Mitsuba's format, rendered at `spp` samples per pixel; its OBJ files are named
/// `{prefix}-g{N}.obj` (N: the object's index), so that they do not clobber other files beside
/// the XML. Errors name what does not map.
pub fn to_mitsuba(scene: &Scene, spp: u32, prefix: &str) -> Result<MitsubaScene, String> {
    let c = &scene.camera;
    // A thin lens is Mitsuba's `thinlens` sensor: the same radius, and the plane in focus at the
    // same distance along the view direction.
    let sensor = if c.aperture > 0.0 {
        format!(
            "thinlens\"><float name=\"aperture_radius\" value=\"{:e}\"/><float name=\"focus_distance\" value=\"{:e}\"/",
            c.aperture, c.focus_distance
        )
    } else {
        "perspective\"".into()
    };
    let s = &scene.settings;
    let mut x = String::new();
    let _ = writeln!(x, "<scene version=\"3.0.0\">");
    let _ = writeln!(
        x,
        "  <integrator type=\"path\"><integer name=\"max_depth\" value=\"{}\"/></integrator>",
        s.max_depth + 1
    );
    let _ = writeln!(
        x,
        "  <sensor type=\"{sensor}>\n    <float name=\"fov\" value=\"{:e}\"/><string name=\"fov_axis\" value=\"y\"/>\n    <transform name=\"to_world\"><lookat origin=\"{}\" target=\"{}\" up=\"{}\"/></transform>\n    <sampler type=\"independent\"><integer name=\"sample_count\" value=\"{spp}\"/></sampler>\n    <film type=\"hdrfilm\"><integer name=\"width\" value=\"{}\"/><integer name=\"height\" value=\"{}\"/><rfilter type=\"box\"/><string name=\"pixel_format\" value=\"rgb\"/></film>\n  </sensor>",
        c.fov,
        v(c.from),
        v(c.at),
        v(c.up),
        c.width,
        c.height
    );
    for (i, m) in scene.materials.iter().enumerate() {
        let body = match m.bsdf() {
            Bsdf::Diffuse { albedo } => format!(
                "<bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"{}\"/></bsdf>",
                v(albedo)
            ),
            Bsdf::Mirror { tint } => format!(
                "<bsdf type=\"conductor\"><string name=\"material\" value=\"none\"/><rgb name=\"specular_reflectance\" value=\"{}\"/></bsdf>",
                v(tint)
            ),
            Bsdf::Glass { ior } => format!(
                "<bsdf type=\"dielectric\"><float name=\"int_ior\" value=\"{ior:e}\"/><float name=\"ext_ior\" value=\"1\"/></bsdf>"
            ),
            Bsdf::Glossy { tint, alpha } => format!(
                "<bsdf type=\"roughconductor\"><string name=\"material\" value=\"none\"/><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"{alpha:e}\"/><rgb name=\"specular_reflectance\" value=\"{}\"/></bsdf>",
                v(tint)
            ),
        };
        // Mitsuba's `ref` needs an id on the BSDF: number them.
        let _ = writeln!(
            x,
            "  {}",
            body.replacen("<bsdf ", &format!("<bsdf id=\"m{i}\" "), 1)
        );
    }
    let emitter = |e: glam::Vec3| {
        if e.max_element() > 0.0 {
            format!(
                "<emitter type=\"area\"><rgb name=\"radiance\" value=\"{}\"/></emitter>",
                v(e)
            )
        } else {
            String::new()
        }
    };
    let mut objs = vec![];
    for (gi, g) in scene.groups.iter().enumerate() {
        let objects = &scene.objects[g.first as usize..(g.first + g.count) as usize];
        let Some(first) = objects.first() else {
            continue;
        };
        let m = first.material as usize;
        let e = emitter(scene.materials[m].emission);
        match first.shape {
            Shape::Sphere { center, radius } => {
                let _ = writeln!(
                    x,
                    "  <shape type=\"sphere\"><point name=\"center\" value=\"{}\"/><float name=\"radius\" value=\"{radius:e}\"/><ref id=\"m{m}\"/>{e}</shape>",
                    v(center)
                );
            }
            Shape::Triangle { .. } => {
                let mut obj = String::new();
                for o in objects {
                    if let Shape::Triangle { p } = o.shape {
                        for q in p {
                            let _ = writeln!(obj, "v {:e} {:e} {:e}", q.x, q.y, q.z);
                        }
                    }
                }
                for k in 0..objects.len() {
                    let _ = writeln!(obj, "f {} {} {}", 3 * k + 1, 3 * k + 2, 3 * k + 3);
                }
                let name = format!("{prefix}-g{gi}.obj");
                let _ = writeln!(
                    x,
                    "  <shape type=\"obj\"><string name=\"filename\" value=\"{name}\"/><boolean name=\"face_normals\" value=\"true\"/><ref id=\"m{m}\"/>{e}</shape>"
                );
                objs.push((name, obj));
            }
            Shape::Plane { .. } | Shape::AxisPlane { .. } => {
                return Err(format!(
                    "plane \"{}\": an infinite plane has no Mitsuba equivalent (use triangles)",
                    g.name
                ));
            }
        }
    }
    for l in &scene.lights {
        let _ = writeln!(
            x,
            "  <emitter type=\"point\"><point name=\"position\" value=\"{}\"/><rgb name=\"intensity\" value=\"{}\"/></emitter>",
            v(l.position),
            v(l.color)
        );
    }
    if s.background.max_element() > 0.0 {
        let _ = writeln!(
            x,
            "  <emitter type=\"constant\"><rgb name=\"radiance\" value=\"{}\"/></emitter>",
            v(s.background)
        );
    }
    let _ = writeln!(x, "</scene>");
    Ok(MitsubaScene { xml: x, objs })
}
