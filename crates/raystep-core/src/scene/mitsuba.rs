//! Writes a scene in Mitsuba 3's XML format, so an independent renderer can render what raystep's
//! path tracer renders (the tests and `raystep bench --section path` compare the two).
//!
//! What maps: the perspective camera (vertical field of view, a box pixel filter), the path
//! integrator (Mitsuba's `max_depth` is raystep's plus one: Mitsuba counts path segments, raystep
//! bounces; so is its `rr_depth`, so that Russian roulette first gambles on the same vertex of
//! the path (Mitsuba plays when its depth, counted from 0 at the camera ray's hit and raised
//! before the game, is at least `rr_depth`; raystep when its bounce count plus one exceeds its
//! own): Mitsuba's default, 5, would spare every path one vertex more than raystep's default 3.
//! The survival probability still differs: Mitsuba's is capped at 0.95 and scaled by η²),
//! triangles and meshes (as OBJ files of their triangles, face normals, so their
//! winding decides an area light's side as in raystep; a smooth mesh with its vertex normals,
//! which both renderers interpolate), spheres, the four BSDFs (`diffuse`;
//! `mirror` as a `conductor` with no Fresnel and the colour as its reflectance; `glass` as a
//! `dielectric`; `glossy` as a `roughconductor` with GGX, the same α and no Fresnel), emission as
//! an `area` emitter, point lights as `point` emitters and the background as a `constant`
//! environment, and a thin lens as Mitsuba's `thinlens` sensor. Infinite planes have no
//! equivalent here: they are refused (so is a glossy material's roughness texture).
//!
//! Textures on triangles: a checker is Mitsuba's `checkerboard` (its `to_uv` scaled so that its
//! half-unit checks are raystep's squares, and v turned back: Mitsuba's OBJ loader flips texture
//! v), its colours multiplied by the BSDF's albedo or tint; an image (nearest or bilinear, any
//! wrap) is a `bitmap` of an OpenEXR file holding raystep's own linear texels already multiplied
//! by the albedo or tint (Mitsuba has no texture-times-colour), so both read the same numbers.
//! Triangles carry their texture coordinates (`vt`; a triangle without them gets its
//! barycentrics' corners (0, 0), (1, 0), (0, 1)). Refused: a textured sphere (Mitsuba maps a
//! sphere's (u, v) in its own frame) and a trilinear image (Mitsuba 3's bitmap has no mip maps).

use super::{Bsdf, Filter, Scene, Shape, TextureKind, Wrap};
use std::fmt::Write;

/// A scene in Mitsuba's format: the XML and the files it names (file name, contents).
#[derive(Debug, Clone, PartialEq)]
pub struct MitsubaScene {
    /// The scene's XML.
    pub xml: String,
    /// OBJ files the XML refers to, by file name (to be written beside it).
    pub objs: Vec<(String, String)>,
    /// OpenEXR images the XML's textures read, by file name (to be written beside it).
    pub images: Vec<(String, Vec<u8>)>,
}

impl MitsubaScene {
    /// Writes the OBJ files and the images into `dir` (each atomically), not the XML.
    pub fn write_files(&self, dir: &std::path::Path) -> Result<(), String> {
        for (f, text) in &self.objs {
            crate::io::write_atomic(&dir.join(f), text.as_bytes())?;
        }
        for (f, bytes) in &self.images {
            crate::io::write_atomic(&dir.join(f), bytes)?;
        }
        Ok(())
    }
}

/// Linear RGB texels as a 32-bit float OpenEXR file's bytes.
fn exr_bytes(width: u32, height: u32, texels: &[glam::Vec3]) -> Result<Vec<u8>, String> {
    let data: Vec<f32> = texels.iter().flat_map(|p| p.to_array()).collect();
    let img = image::Rgb32FImage::from_raw(width, height, data)
        .ok_or_else(|| format!("a texture is not {width}×{height}"))?;
    let mut bytes = std::io::Cursor::new(vec![]);
    image::DynamicImage::ImageRgb32F(img)
        .write_to(&mut bytes, image::ImageFormat::OpenExr)
        .map_err(|e| format!("cannot encode OpenEXR: {e}"))?;
    Ok(bytes.into_inner())
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
        "  <integrator type=\"path\"><integer name=\"max_depth\" value=\"{}\"/><integer name=\"rr_depth\" value=\"{}\"/></integrator>",
        s.max_depth + 1,
        s.rr_depth + 1
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
    let mut images = vec![];
    // A roughness texture squares each read (α = (roughness × green)²): Mitsuba's `alpha`
    // texture would need α itself per texel; refused rather than exported without it.
    if let Some(m) = scene.materials.iter().find(|m| m.reads_roughness()) {
        return Err(format!(
            "material \"{}\": a roughness texture does not map (Mitsuba's alpha texture is α itself, raystep's is roughness × green, squared)",
            m.name
        ));
    }
    for (i, m) in scene.materials.iter().enumerate() {
        // The albedo or tint: a colour, or the material's texture times it.
        let mut colour = |name: &str, c: glam::Vec3| -> Result<String, String> {
            let Some(t) = m.texture.and_then(|t| scene.textures.get(t as usize)) else {
                return Ok(format!("<rgb name=\"{name}\" value=\"{}\"/>", v(c)));
            };
            match &t.kind {
                TextureKind::Checker { squares, colors } => Ok(format!(
                    "<texture type=\"checkerboard\" name=\"{name}\"><rgb name=\"color0\" value=\"{}\"/><rgb name=\"color1\" value=\"{}\"/><transform name=\"to_uv\"><scale x=\"{:e}\" y=\"{:e}\"/><translate y=\"{:e}\"/></transform></texture>",
                    v(c * colors[0]),
                    v(c * colors[1]),
                    f64::from(squares[0]) / 2.0,
                    -f64::from(squares[1]) / 2.0,
                    f64::from(squares[1]) / 2.0
                )),
                TextureKind::Image {
                    filter: Filter::Trilinear,
                    ..
                } => Err(format!(
                    "texture \"{}\": Mitsuba 3's bitmap has no mip maps (use filter = \"bilinear\")",
                    t.name
                )),
                TextureKind::Image {
                    width,
                    height,
                    texels,
                    filter,
                    wrap,
                    ..
                } => {
                    let file = format!("{prefix}-t{i}-{name}.exr");
                    let scaled: Vec<glam::Vec3> = texels[..(*width as usize) * (*height as usize)]
                        .iter()
                        .map(|&x| x * c)
                        .collect();
                    images.push((file.clone(), exr_bytes(*width, *height, &scaled)?));
                    Ok(format!(
                        "<texture type=\"bitmap\" name=\"{name}\"><string name=\"filename\" value=\"{file}\"/><string name=\"filter_type\" value=\"{}\"/><string name=\"wrap_mode\" value=\"{}\"/><boolean name=\"raw\" value=\"true\"/></texture>",
                        if *filter == Filter::Nearest {
                            "nearest"
                        } else {
                            "bilinear"
                        },
                        match wrap {
                            Wrap::Repeat => "repeat",
                            Wrap::Clamp => "clamp",
                            Wrap::Mirror => "mirror",
                        }
                    ))
                }
            }
        };
        let body = match m.bsdf() {
            Bsdf::Diffuse { albedo } => format!(
                "<bsdf type=\"diffuse\">{}</bsdf>",
                colour("reflectance", albedo)?
            ),
            Bsdf::Mirror { tint } => format!(
                "<bsdf type=\"conductor\"><string name=\"material\" value=\"none\"/>{}</bsdf>",
                colour("specular_reflectance", tint)?
            ),
            Bsdf::Glass { ior } => format!(
                "<bsdf type=\"dielectric\"><float name=\"int_ior\" value=\"{ior:e}\"/><float name=\"ext_ior\" value=\"1\"/></bsdf>"
            ),
            Bsdf::Glossy { tint, alpha } => format!(
                "<bsdf type=\"roughconductor\"><string name=\"material\" value=\"none\"/><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"{alpha:e}\"/>{}</bsdf>",
                colour("specular_reflectance", tint)?
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
    let is_prototype = |gi: usize| scene.prototypes.iter().any(|p| p.group as usize == gi);
    for (gi, g) in scene.groups.iter().enumerate() {
        let objects = &scene.objects[g.first as usize..(g.first + g.count) as usize];
        let Some(first) = objects.first() else {
            continue;
        };
        let m = first.material as usize;
        let e = emitter(scene.materials[m].emission);
        // A prototype is written once, as Mitsuba's `shapegroup`, which its instances place.
        let shapes_start = x.len();
        match first.shape {
            Shape::Sphere { center, radius } => {
                if scene.materials[m].texture.is_some() {
                    return Err(format!(
                        "sphere \"{}\": a textured sphere does not map (Mitsuba's sphere has (u, v) of its own)",
                        g.name
                    ));
                }
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
                // Texture coordinates where the material has a texture: the triangle's own, or
                // its barycentrics' corners.
                let textured = scene.materials[m].texture.is_some();
                if textured {
                    for o in objects {
                        let t = if o.uvs == super::NO_UVS {
                            [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
                        } else {
                            scene.vertex_uvs[o.uvs as usize]
                        };
                        for q in t {
                            let _ = writeln!(obj, "vt {:e} {:e}", q[0], q[1]);
                        }
                    }
                }
                // A smooth mesh's vertex normals (`vn`; a triangle of it without them gets its
                // face normal at each corner), which Mitsuba interpolates as raystep does.
                let smooth = objects.iter().any(|o| o.normals != super::NO_NORMALS);
                if smooth {
                    for o in objects {
                        let face = match o.shape {
                            Shape::Triangle { p } => (p[1] - p[0]).cross(p[2] - p[0]),
                            _ => glam::Vec3::ZERO,
                        };
                        let n = scene
                            .vertex_normals
                            .get(o.normals as usize)
                            .copied()
                            .unwrap_or([face.normalize_or_zero(); 3]);
                        for q in n {
                            let _ = writeln!(obj, "vn {:e} {:e} {:e}", q.x, q.y, q.z);
                        }
                    }
                }
                for k in 0..objects.len() {
                    let (a, b, c) = (3 * k + 1, 3 * k + 2, 3 * k + 3);
                    let _ = match (textured, smooth) {
                        (true, true) => writeln!(obj, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}"),
                        (false, true) => writeln!(obj, "f {a}//{a} {b}//{b} {c}//{c}"),
                        (true, false) => writeln!(obj, "f {a}/{a} {b}/{b} {c}/{c}"),
                        (false, false) => writeln!(obj, "f {a} {b} {c}"),
                    };
                }
                let name = format!("{prefix}-g{gi}.obj");
                let _ = writeln!(
                    x,
                    "  <shape type=\"obj\"><string name=\"filename\" value=\"{name}\"/><boolean name=\"face_normals\" value=\"{}\"/><ref id=\"m{m}\"/>{e}</shape>",
                    !smooth
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
        if is_prototype(gi) {
            let shape = x.split_off(shapes_start);
            let _ = writeln!(
                x,
                "  <shape type=\"shapegroup\" id=\"g{gi}\">\n  {}  </shape>",
                shape.trim_start()
            );
        }
    }
    for inst in &scene.instances {
        let m = inst.to_world.0;
        let _ = writeln!(
            x,
            "  <shape type=\"instance\"><ref id=\"g{}\"/><transform name=\"to_world\"><matrix value=\"{:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} 0 0 0 1\"/></transform></shape>",
            inst.group,
            m[0][0],
            m[0][1],
            m[0][2],
            m[0][3],
            m[1][0],
            m[1][1],
            m[1][2],
            m[1][3],
            m[2][0],
            m[2][1],
            m[2][2],
            m[2][3],
        );
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
    Ok(MitsubaScene {
        xml: x,
        objs,
        images,
    })
}
