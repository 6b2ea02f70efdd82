//! The `[[gltf]]` tables (and a glTF file opened as a scene): each file read
//! ([`crate::scene::gltf`]), its materials, textures and lights added to the scene's, its camera
//! taken where asked.

use super::*;
use crate::scene::gltf::{GltfError, GltfInstance, Imported, Part, import};
use glam::{DMat4, DQuat, DVec3};

/// One `[[gltf]]` read: its primitives, and where its materials start in the scene's.
pub(super) struct Placed {
    pub(super) parts: Vec<Part>,
    /// The nodes' instances of the prototypes among `parts`.
    pub(super) instances: Vec<GltfInstance>,
    pub(super) material_base: u32,
    /// SHA-256 of the file's bytes.
    pub(super) source_hash: String,
}

/// The parts of a scene [`Ctx::gltf_files`] adds to.
pub(super) struct Adding<'s> {
    pub(super) materials: &'s mut Vec<Material>,
    pub(super) textures: &'s mut Vec<Texture>,
    pub(super) lights: &'s mut Vec<Light>,
    pub(super) camera: &'s mut Camera,
    pub(super) warnings: &'s mut Vec<String>,
    pub(super) cameras: &'s mut Vec<NamedCamera>,
}

impl Ctx<'_> {
    /// Every `[[gltf]]` table, in file order: the file read and placed, its materials, textures
    /// and lights appended. When the scene is a glTF file opened directly
    /// ([`super::load_file`]), a file without a camera is framed from the front and one without
    /// lights gets a headlight (both said in a warning).
    pub(super) fn gltf_files(
        &self,
        f: &SceneFile,
        base: Option<&Path>,
        add: Adding,
    ) -> Result<Vec<Placed>, SceneError> {
        let mut out = vec![];
        for (i, g) in f.gltf.iter().enumerate() {
            let d = g.get_ref();
            let name = d.name.clone().unwrap_or_else(|| format!("gltf {i}"));
            let loc = self.loc(format!("gltf \"{name}\""), g);
            let translate = loc.vec3("translate", d.translate)?.as_dvec3();
            let rotate = loc.vec3("rotate", d.rotate)?.as_dvec3();
            let scale = loc.num("scale", d.scale)?;
            if scale <= 0.0 {
                return Err(loc.err("scale", format!("must be positive, got {}", d.scale)));
            }
            let r = rotate.to_array().map(f64::to_radians);
            let place = DMat4::from_scale_rotation_translation(
                DVec3::splat(d.scale),
                DQuat::from_rotation_z(r[2])
                    * DQuat::from_rotation_y(r[1])
                    * DQuat::from_rotation_x(r[0]),
                translate,
            );
            let path = base.map_or_else(|| Path::new(&d.file).to_path_buf(), |b| b.join(&d.file));
            let used: u64 = add
                .textures
                .iter()
                .map(|t| {
                    t.levels()
                        .first()
                        .map_or(0, |l| u64::from(l.width) * u64::from(l.height))
                })
                .sum();
            let budget = texture::MAX_TEXELS.saturating_sub(used);
            // A `material` that emits light is every part's: then no part may be instanced.
            let share = !d.material.as_ref().is_some_and(|m| {
                add.materials
                    .iter()
                    .any(|x| &x.name == m && x.emission.max_element() > 0.0)
            });
            let imported = import(&path, &name, place, budget, share)
                .map_err(|e| self.gltf_error(&loc, &path, e))?;
            let Imported {
                parts,
                instances,
                materials,
                textures,
                lights,
                cameras,
                warnings,
                bounds,
                source_hash,
            } = imported;
            add.warnings.extend(
                warnings
                    .into_iter()
                    .map(|w| format!("{}: {w}", path.display())),
            );
            let material_base = add.materials.len() as u32;
            let texture_base = add.textures.len() as u32;
            for mut m in materials {
                if add.materials.iter().any(|x| x.name == m.name) {
                    return Err(loc.err("name", format!("a material named \"{}\" is already defined: give the [[gltf]] another `name`", m.name)));
                }
                m.texture = m.texture.map(|t| t + texture_base);
                m.roughness_texture = m.roughness_texture.map(|t| t + texture_base);
                add.materials.push(m);
            }
            for t in textures {
                if add.textures.iter().any(|x| x.name == t.name) {
                    return Err(loc.err("name", format!("a texture named \"{}\" is already defined: give the [[gltf]] another `name`", t.name)));
                }
                add.textures.push(t);
            }
            if d.lights {
                for l in lights {
                    if add.lights.iter().any(|x| x.name == l.name) {
                        return Err(loc.err("name", format!("a light named \"{}\" is already defined: give the [[gltf]] another `name`", l.name)));
                    }
                    add.lights.push(l);
                }
            }
            let chosen = match &d.camera {
                None | Some(GltfCameraDef::First(false)) => None,
                Some(GltfCameraDef::First(true)) => Some(cameras.first().ok_or_else(|| {
                    loc.err(
                        "camera",
                        format!("{} has no perspective camera", path.display()),
                    )
                })?),
                Some(GltfCameraDef::Named(n)) => {
                    Some(cameras.iter().find(|c| &c.name == n).ok_or_else(|| {
                        let known: Vec<String> =
                            cameras.iter().map(|c| format!("\"{}\"", c.name)).collect();
                        loc.err(
                            "camera",
                            format!(
                                "{} has no camera named \"{n}\" ({})",
                                path.display(),
                                if known.is_empty() {
                                    "it has none".to_string()
                                } else {
                                    format!("known: {}", known.join(", "))
                                }
                            ),
                        )
                    })?)
                }
            };
            for c in &cameras {
                // The first of a name is the one `--camera` finds; a usable one only.
                if c.usable() && !add.cameras.iter().any(|x| x.name == c.name) {
                    add.cameras.push(NamedCamera {
                        name: c.name.clone(),
                        from: c.from.as_vec3(),
                        at: c.at.as_vec3(),
                        up: c.up.as_vec3(),
                        fov: c.fov as f32,
                    });
                }
            }
            let opened = self.gltf_open && i == 0;
            if let Some(c) = chosen.or(if opened { cameras.first() } else { None }) {
                if !c.usable() {
                    return Err(loc.err(
                        "camera",
                        format!("{}: camera \"{}\" cannot be used (field of view {}°, or its up is along its view)", path.display(), c.name, c.fov),
                    ));
                }
                add.camera.from = c.from.as_vec3();
                add.camera.at = c.at.as_vec3();
                add.camera.up = c.up.as_vec3();
                add.camera.fov = c.fov as f32;
                if let Some(a) = c.aspect
                    && (f.camera.is_none() || opened)
                    && a.is_finite()
                    && a > 0.0
                {
                    let h = i64::from(add.camera.height);
                    let most = view::MAX_DIMENSION.min(view::MAX_PIXELS / h);
                    add.camera.width = ((h as f64 * a).round() as i64).clamp(1, most) as u32;
                }
            } else if opened && let Some((lo, hi)) = bounds {
                // Framed: the box's bounding sphere fills a 45° view from the front (glTF's +z)
                // and 20° above.
                let centre = (lo + hi) / 2.0;
                let radius = ((hi - lo).length() / 2.0).max(1e-3);
                let distance = radius / 22.5f64.to_radians().sin() * 1.1;
                let (sin, cos) = 20f64.to_radians().sin_cos();
                add.camera.from = (centre + DVec3::new(0.0, sin, cos) * distance).as_vec3();
                add.camera.at = centre.as_vec3();
                add.camera.up = Vec3::Y;
                add.camera.fov = 45.0;
                add.warnings.push(format!(
                    "{}: the file has no perspective camera: the view is framed from the front (+z), 20° above",
                    path.display()
                ));
            }
            if opened
                && add.lights.is_empty()
                && !add.materials.iter().any(|m| m.emission.max_element() > 0.0)
            {
                // The path tracer's point light is an intensity: d² gives the model about the
                // irradiance of a unit light at unit distance.
                let at = bounds.map_or(add.camera.at.as_dvec3(), |(lo, hi)| (lo + hi) / 2.0);
                let d2 = (add.camera.from.as_dvec3() - at).length_squared().max(1e-6);
                add.lights.push(Light {
                    name: "headlight".into(),
                    position: add.camera.from,
                    color: Vec3::splat(d2 as f32),
                });
                add.warnings.push(format!(
                    "{}: the file has no lights and nothing emits: a headlight is added at the camera",
                    path.display()
                ));
            }
            out.push(Placed {
                parts,
                instances,
                material_base,
                source_hash,
            });
        }
        Ok(out)
    }

    /// A glTF file's problem as a scene error: the glTF file, the JSON path as the field, and
    /// (for a `[[gltf]]` table) where the scene includes it.
    fn gltf_error(&self, loc: &Loc, path: &Path, e: GltfError) -> SceneError {
        let mut message = e.message;
        if !self.gltf_open {
            let l = loc.err("file", "");
            message += &format!(
                " (included by {}:{}:{})",
                l.file,
                l.line.unwrap_or(0),
                l.column.unwrap_or(0)
            );
        }
        SceneError {
            file: path.display().to_string(),
            line: e.line_col.map(|(l, _)| l),
            column: e.line_col.map(|(_, c)| c),
            field: e.json_path,
            message,
        }
    }
}

/// The text of the scene a glTF file opened directly becomes: the file included whole, its
/// camera used (or the view framed), rendered by the path tracer at 16 samples a pixel.
pub(super) fn opening_text(file_name: &str) -> String {
    let stem = Path::new(file_name)
        .file_stem()
        .map_or("model".to_string(), |s| s.to_string_lossy().into_owned());
    format!(
        "title = {title}\n\n[camera]\nwidth = 480\nheight = 360\n\n[render]\nintegrator = \"path\"\nspp = 16\n\n[[gltf]]\nname = {name}\nfile = {file}\n",
        title = toml_string(file_name),
        name = toml_string(&stem),
        file = toml_string(file_name),
    )
}

fn toml_string(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}
