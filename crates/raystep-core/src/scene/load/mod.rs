//! Loading and validating a scene: TOML syntax errors with file:line:column, semantic errors that
//! name the object and field (with the field's line and column), OBJ meshes through `tobj`.
//!
//! This file finds positions in the text and builds the scene's objects; `values.rs` checks one
//! field's value (`Loc`), `view.rs` reads `[camera]` and `[render]`, `textures.rs` the
//! `[[texture]]` tables.

use super::limits::*;
use super::model::*;
use super::obj::{MeshShading, load_obj};
use super::*;
use std::collections::HashMap;
use std::ops::Range;
use std::path::Path;
use toml::Spanned;

mod gltf;
mod instances;
mod textures;
mod values;
mod view;

use values::Loc;

/// A file that could not be read (a scene, an OBJ, an exercise sheet): where and why, printed
/// as `file:line:column: field: message`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}", self.render())]
pub struct LocatedError {
    /// The file.
    pub file: String,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// 1-based column, when known.
    pub column: Option<usize>,
    /// The object and field, e.g. `sphere "ball" → radius` or `question "disc" → quantity`.
    pub field: Option<String>,
    /// What is wrong.
    pub message: String,
}

/// A scene that could not be loaded.
pub type SceneError = LocatedError;

impl LocatedError {
    fn render(&self) -> String {
        let mut s = self.file.clone();
        if let (Some(l), Some(c)) = (self.line, self.column) {
            s += &format!(":{l}:{c}");
        }
        s += ": ";
        if let Some(f) = &self.field {
            s += &format!("{f}: ");
        }
        s + &self.message
    }
}

/// Loads a scene file (and the OBJ files it names, relative to it).
pub fn load_file(path: &Path) -> Result<Scene, SceneError> {
    let file = path.display().to_string();
    if is_gltf(path) {
        return load_gltf(path);
    }
    let text = crate::io::read_text(path, crate::io::limits::SCENE, "scene file").map_err(|e| {
        SceneError {
            file: file.clone(),
            line: None,
            column: None,
            field: None,
            message: format!("cannot read the scene file: {e}"),
        }
    })?;
    let mut scene = load_str(&text, &file, path.parent())?;
    scene.path = Some(path.to_path_buf());
    Ok(scene)
}

/// Whether a path names a glTF file (`.gltf`, `.glb`), which [`load_file`] opens as a scene.
pub fn is_gltf(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// A glTF file opened as a scene: the scene of [`gltf::opening_text`] (the file included
/// whole, its camera or a framed view, its lights or a headlight, the path tracer), named after
/// the file, its hash the file's.
fn load_gltf(path: &Path) -> Result<Scene, SceneError> {
    let file = path.display().to_string();
    let name = path
        .file_name()
        .map_or(file.clone(), |n| n.to_string_lossy().into_owned());
    let text = gltf::opening_text(&name);
    let ctx = Ctx {
        text: &text,
        file: &file,
        gltf_open: true,
    };
    let parsed: SceneFile = toml::from_str(&text).map_err(|e| SceneError {
        file: file.clone(),
        line: None,
        column: None,
        field: None,
        message: format!("cannot open the glTF file: {e}"),
    })?;
    let mut scene = ctx.build(parsed, path.parent())?;
    scene.path = Some(path.to_path_buf());
    Ok(scene)
}

/// Loads a scene from TOML text. `file` names it in errors; `base` is where OBJ paths start from.
pub fn load_str(text: &str, file: &str, base: Option<&Path>) -> Result<Scene, SceneError> {
    let ctx = Ctx {
        text,
        file,
        gltf_open: false,
    };
    let parsed: SceneFile = toml::from_str(text).map_err(|e| {
        let (line, column) = e.span().map(|s| ctx.line_col(s.start)).unzip();
        // Name the table and key the error sits in (serde reports only the position).
        let field = e.span().and_then(|s| match ctx.describe_position(s.start) {
            (Some(table), Some(key)) => Some(format!("{table} → {key}")),
            (Some(table), None) => Some(table),
            (None, Some(key)) => Some(key),
            (None, None) => None,
        });
        SceneError {
            file: file.into(),
            line,
            column,
            field,
            message: crate::text::shorten_numbers(e.message().trim()),
        }
    })?;
    ctx.build(parsed, base)
}

struct Ctx<'a> {
    text: &'a str,
    file: &'a str,
    /// Whether the text is a glTF file's opening scene ([`gltf::opening_text`]).
    gltf_open: bool,
}

impl<'a> Ctx<'a> {
    fn line_col(&self, pos: usize) -> (usize, usize) {
        crate::text::line_col(self.text, pos)
    }

    /// The byte offset of `field = …` inside an object's span.
    fn find_field(&self, span: Range<usize>, field: &str) -> Option<usize> {
        if field.is_empty() {
            return None;
        }
        // A `[[table]]`'s span covers only its header: its body runs to the next header.
        let end = self.next_header(span.end);
        let span = span.start..end;
        let body = self.text.get(span.clone())?;
        let mut offset = 0;
        for line in body.split_inclusive('\n') {
            let trimmed = line.trim_start();
            let quoted = format!("\"{field}\"");
            if let Some(rest) = trimmed
                .strip_prefix(field)
                .or_else(|| trimmed.strip_prefix(quoted.as_str()))
                && rest.trim_start().starts_with('=')
            {
                return Some(span.start + offset + (line.len() - trimmed.len()));
            }
            offset += line.len();
        }
        None
    }

    /// The byte offset where the table header after `pos` starts (or the end of the text).
    fn next_header(&self, pos: usize) -> usize {
        let pos = self.text.floor_char_boundary(pos);
        let mut offset = pos;
        for line in self.text[pos..].split_inclusive('\n') {
            if offset > pos && is_header(line) {
                return offset;
            }
            offset += line.len();
        }
        self.text.len()
    }

    /// For a position inside a table: the table's description (`sphere "ball"`, `camera`) and the
    /// key written at the start of the position's line, if any. The position's own line counts:
    /// an error reported at a table's header (a required field missing) belongs to that table,
    /// not the one before it, and one on the name inside a header (`[[spheres]]`, an unknown
    /// table) is described by the header itself.
    fn describe_position(&self, pos: usize) -> (Option<String>, Option<String>) {
        let pos = self.text.floor_char_boundary(pos);
        let line_start = self.text[..pos].rfind('\n').map_or(0, |i| i + 1);
        let line_end = self.text[pos..]
            .find('\n')
            .map_or(self.text.len(), |i| pos + i);
        let this_line = &self.text[line_start..line_end];
        if is_header(this_line) {
            let lead = this_line.len() - this_line.trim_start().len();
            let brackets = if this_line.trim_start().starts_with("[[") {
                2
            } else {
                1
            };
            if pos >= line_start + lead + brackets {
                let h = this_line.split('#').next().unwrap_or("").trim();
                return (Some(h.to_string()), None);
            }
        }
        let upto = &self.text[..line_end];
        let mut header = None;
        let mut header_at = 0;
        let mut offset = 0;
        for line in upto.split_inclusive('\n') {
            if is_header(line) {
                header = Some(line.split('#').next().unwrap_or("").trim().to_string());
                header_at = offset;
            }
            offset += line.len();
        }
        let key = this_line
            .split_once('=')
            .map(|(k, _)| k.trim().trim_matches('"').to_string())
            .filter(|k| !k.is_empty() && !is_header(this_line));
        let Some(h) = header else { return (None, key) };
        let kind = h.trim_matches(|c| c == '[' || c == ']').trim().to_string();
        if !h.starts_with("[[") {
            return (Some(kind), key);
        }
        // Which entry of that kind, and its name if the body gives one.
        let index = self.text[..header_at]
            .lines()
            .filter(|l| is_header(l) && l.split('#').next().unwrap_or("").trim() == h)
            .count();
        let body_end = self.next_header(header_at + 1);
        let name = self.text[header_at..body_end].lines().find_map(|l| {
            let (k, v) = l.split_once('=')?;
            (k.trim() == "name").then(|| v.trim().trim_matches('"').to_string())
        });
        (
            Some(format!(
                "{kind} \"{}\"",
                name.unwrap_or_else(|| format!("{kind} {index}"))
            )),
            key,
        )
    }

    fn loc<T>(&'a self, what: String, s: &Spanned<T>) -> Loc<'a> {
        Loc {
            what,
            span: Some(s.span()),
            ctx: self,
        }
    }

    fn build(&self, f: SceneFile, base: Option<&Path>) -> Result<Scene, SceneError> {
        let mut camera = self.camera(f.camera.as_ref())?;
        let settings = self.settings(f.render.as_ref())?;

        let mut lights: Vec<Light> = vec![];
        for (i, l) in f.light.iter().enumerate() {
            let d = l.get_ref();
            let name = d.name.clone().unwrap_or_else(|| format!("light {i}"));
            let loc = self.loc(format!("light \"{name}\""), l);
            // Traces, sheets and the app refer to lights by name: two with one name are ambiguous.
            if lights.iter().any(|x| x.name == name) {
                return Err(loc.err(
                    "name",
                    format!("a light named \"{name}\" is already defined"),
                ));
            }
            lights.push(Light {
                name,
                position: loc.coord3("position", d.position)?,
                color: loc.color("color", d.color)?,
            });
        }

        let mut textures = self.textures(&f, base)?;
        let mut materials = vec![];
        let mut by_name: HashMap<String, u32> = HashMap::new();
        for (i, m) in f.material.iter().enumerate() {
            let d = m.get_ref();
            let name = d.name.clone().unwrap_or_else(|| format!("material {i}"));
            let loc = self.loc(format!("material \"{name}\""), m);
            if by_name.contains_key(&name) {
                return Err(loc.err(
                    "name",
                    format!("a material named \"{name}\" is already defined"),
                ));
            }
            let shininess = loc.num("shininess", d.shininess)?;
            if shininess <= 0.0 {
                return Err(loc.err(
                    "shininess",
                    format!("must be positive, got {}", d.shininess),
                ));
            }
            let refractive_index = loc.num("refractive_index", d.refractive_index)?;
            if refractive_index <= 0.0 {
                return Err(loc.err(
                    "refractive_index",
                    format!("must be positive, got {}", d.refractive_index),
                ));
            }
            // A texture named by `field`, as its index.
            let texture_named =
                |field: &str, n: &Option<String>| -> Result<Option<u32>, SceneError> {
                    let Some(n) = n else { return Ok(None) };
                    textures
                        .iter()
                        .position(|t| &t.name == n)
                        .map(|i| Some(i as u32))
                        .ok_or_else(|| {
                            let known: Vec<String> =
                                textures.iter().map(|t| format!("\"{}\"", t.name)).collect();
                            let known = if known.is_empty() {
                                "no textures are defined: add a [[texture]]".to_string()
                            } else {
                                format!("known: {}", known.join(", "))
                            };
                            loc.err(field, format!("unknown texture \"{n}\" ({known})"))
                        })
                };
            by_name.insert(name.clone(), materials.len() as u32);
            materials.push(Material {
                name,
                color: loc.color("color", d.color)?,
                ambient: loc.nonneg("ambient", d.ambient)?,
                diffuse: loc.nonneg("diffuse", d.diffuse)?,
                specular: loc.nonneg("specular", d.specular)?,
                shininess,
                reflective: loc.unit("reflective", d.reflective)?,
                transparency: loc.unit("transparency", d.transparency)?,
                refractive_index,
                emission: loc.color("emission", d.emission)?,
                bsdf: d
                    .bsdf
                    .as_deref()
                    .map(|b| loc.choice("bsdf", b))
                    .transpose()?,
                roughness: loc.unit("roughness", d.roughness)?,
                texture: texture_named("texture", &d.texture)?,
                roughness_texture: texture_named("roughness_texture", &d.roughness_texture)?,
            });
        }
        let mut warnings = vec![];
        let mut cameras = vec![];
        let placed = self.gltf_files(
            &f,
            base,
            gltf::Adding {
                materials: &mut materials,
                textures: &mut textures,
                lights: &mut lights,
                camera: &mut camera,
                warnings: &mut warnings,
                cameras: &mut cameras,
            },
        )?;
        let gltf_parts: usize = placed.iter().map(|p| p.parts.len()).sum();
        // A glTF file opened alone is named by its bytes, not by the text that includes it.
        let opened_hash = placed
            .first()
            .filter(|_| self.gltf_open)
            .map(|p| p.source_hash.clone());
        let mut placed = placed.into_iter();
        // The glTF files' nodes that place a shared mesh, as instances (after every table).
        let mut gltf_instances: Vec<instances::Placement> = vec![];
        let mut default_material = None;
        let mut material = |loc: &Loc, name: &Option<String>| -> Result<u32, SceneError> {
            match name {
                Some(n) => by_name.get(n).copied().ok_or_else(|| {
                    let mut known: Vec<&String> = by_name.keys().collect();
                    known.sort();
                    let known = if known.is_empty() {
                        "no materials are defined".to_string()
                    } else {
                        format!(
                            "known: {}",
                            known
                                .iter()
                                .map(|k| format!("\"{k}\""))
                                .collect::<Vec<_>>()
                                .join(", ")
                        )
                    };
                    loc.err("material", format!("unknown material \"{n}\" ({known})"))
                }),
                None => Ok(*default_material.get_or_insert_with(|| {
                    materials.push(Material::default());
                    materials.len() as u32 - 1
                })),
            }
        };

        let mut objects: Vec<Object> = vec![];
        let mut groups: Vec<Group> = vec![];
        let mut vertex_normals: Vec<[Vec3; 3]> = vec![];
        let mut vertex_uvs: Vec<[[f32; 2]; 3]> = vec![];
        let mut names: HashMap<String, usize> = HashMap::new();
        // `normals`, `uvs`: empty, or one entry per shape (a smooth triangle's vertex normals, a
        // triangle's texture coordinates).
        let mut add_group = |loc: &Loc,
                             name: String,
                             shapes: Vec<Shape>,
                             normals: Vec<Option<[Vec3; 3]>>,
                             uvs: Vec<Option<[[f32; 2]; 3]>>,
                             mat: u32|
         -> Result<u32, SceneError> {
            // Keep the byte offset; the line is counted only when a duplicate is reported (counting
            // lines for every object made loading quadratic in the file's size).
            if let Some(first) = names.get(&name) {
                let line = self.line_col(*first).0;
                return Err(loc.err(
                    "name",
                    format!("an object defined at line {line} is already named \"{name}\""),
                ));
            }
            if objects.len() + shapes.len() > MAX_OBJECTS {
                return Err(loc.err(
                        if loc.what.starts_with("mesh") { "obj" } else { "" },
                        format!(
                            "the scene would hold {} objects, more than the limit of {MAX_OBJECTS} (a mesh counts one per triangle)",
                            objects.len() + shapes.len()
                        ),
                    ));
            }
            names.insert(name.clone(), loc.span.as_ref().map_or(0, |s| s.start));
            let g = groups.len() as u32;
            groups.push(Group {
                name,
                first: objects.len() as u32,
                count: shapes.len() as u32,
            });
            let mut normals = normals.into_iter();
            let mut uvs = uvs.into_iter();
            for shape in shapes {
                let t = match uvs.next().flatten() {
                    Some(t) => {
                        vertex_uvs.push(t);
                        vertex_uvs.len() as u32 - 1
                    }
                    None => NO_UVS,
                };
                let n = match normals.next().flatten() {
                    Some(n) => {
                        vertex_normals.push(n);
                        vertex_normals.len() as u32 - 1
                    }
                    None => NO_NORMALS,
                };
                objects.push(Object {
                    shape,
                    material: mat,
                    group: g,
                    normals: n,
                    uvs: t,
                });
            }
            Ok(g)
        };

        // Objects are processed in file order (whatever their kind), so ids follow the file and a
        // duplicate name is reported where it repeats.
        enum Def<'d> {
            Sphere(&'d Spanned<SphereDef>),
            Plane(&'d Spanned<PlaneDef>),
            Triangle(&'d Spanned<TriangleDef>),
            Mesh(&'d Spanned<MeshDef>),
            Gltf(&'d Spanned<GltfDef>),
        }
        let mut defs: Vec<(usize, usize, Def)> = vec![];
        defs.extend(
            f.sphere
                .iter()
                .enumerate()
                .map(|(i, d)| (d.span().start, i, Def::Sphere(d))),
        );
        defs.extend(
            f.plane
                .iter()
                .enumerate()
                .map(|(i, d)| (d.span().start, i, Def::Plane(d))),
        );
        defs.extend(
            f.triangle
                .iter()
                .enumerate()
                .map(|(i, d)| (d.span().start, i, Def::Triangle(d))),
        );
        defs.extend(
            f.mesh
                .iter()
                .enumerate()
                .map(|(i, d)| (d.span().start, i, Def::Mesh(d))),
        );
        defs.extend(
            f.gltf
                .iter()
                .enumerate()
                .map(|(i, d)| (d.span().start, i, Def::Gltf(d))),
        );
        defs.sort_by_key(|(start, _, _)| *start);
        for (_, i, def) in defs {
            match def {
                Def::Sphere(s) => {
                    let d = s.get_ref();
                    let name = d.name.clone().unwrap_or_else(|| format!("sphere {i}"));
                    let loc = self.loc(format!("sphere \"{name}\""), s);
                    let center = loc.coord3("center", d.center)?;
                    let radius = loc.coord("radius", d.radius)?;
                    if radius <= 0.0 {
                        return Err(
                            loc.err("radius", format!("must be positive, got {}", d.radius))
                        );
                    }
                    let m = material(&loc, &d.material)?;
                    add_group(
                        &loc,
                        name,
                        vec![Shape::Sphere { center, radius }],
                        vec![],
                        vec![],
                        m,
                    )?;
                }
                Def::Plane(p) => {
                    let d = p.get_ref();
                    let name = d.name.clone().unwrap_or_else(|| format!("plane {i}"));
                    let loc = self.loc(format!("plane \"{name}\""), p);
                    let shape = if let Some(axis) = &d.axis {
                        if d.point.is_some() || d.normal.is_some() {
                            return Err(loc.err("axis", "give either `point` and `normal`, or `axis` and `offset`, not both"));
                        }
                        let axis = match axis.as_str() {
                            "x" => 0,
                            "y" => 1,
                            "z" => 2,
                            other => {
                                return Err(loc.err(
                                    "axis",
                                    format!("must be \"x\", \"y\" or \"z\", got \"{other}\""),
                                ));
                            }
                        };
                        Shape::AxisPlane {
                            axis,
                            offset: loc.coord("offset", d.offset.unwrap_or(0.0))?,
                        }
                    } else {
                        if d.offset.is_some() {
                            return Err(loc.err("offset", "`offset` goes with `axis`; a general plane takes `point` and `normal`"));
                        }
                        let point = loc.coord3("point", d.point.unwrap_or([0.0; 3]))?;
                        let n = d.normal.unwrap_or([0.0, 1.0, 0.0]);
                        loc.vec3("normal", n)?;
                        let Some(unit) = crate::math::unit_f64(n) else {
                            return Err(
                                loc.err("normal", format!("must be a non-zero vector, got {n:?}"))
                            );
                        };
                        let normal = Vec3::new(unit[0] as f32, unit[1] as f32, unit[2] as f32);
                        let offset = loc.coord("point", point.as_dvec3().dot(normal.as_dvec3()))?;
                        Shape::Plane { normal, offset }
                    };
                    let m = material(&loc, &d.material)?;
                    add_group(&loc, name, vec![shape], vec![], vec![], m)?;
                }
                Def::Triangle(t) => {
                    let d = t.get_ref();
                    let name = d.name.clone().unwrap_or_else(|| format!("triangle {i}"));
                    let loc = self.loc(format!("triangle \"{name}\""), t);
                    let p = [
                        loc.vertex("vertices", d.vertices[0])?,
                        loc.vertex("vertices", d.vertices[1])?,
                        loc.vertex("vertices", d.vertices[2])?,
                    ];
                    let normals = match d.normals {
                        Some(ns) => {
                            let mut out = [Vec3::ZERO; 3];
                            for (k, (n, o)) in ns.iter().zip(out.iter_mut()).enumerate() {
                                loc.vec3("normals", *n)?;
                                let Some(u) = crate::math::unit_f64(*n) else {
                                    return Err(loc.err(
                                        "normals",
                                        format!(
                                            "normal {} must be a non-zero vector, got {n:?}",
                                            k + 1
                                        ),
                                    ));
                                };
                                *o = Vec3::new(u[0] as f32, u[1] as f32, u[2] as f32);
                            }
                            vec![Some(out)]
                        }
                        None => vec![],
                    };
                    let uvs = match d.uvs {
                        Some(ts) => {
                            let mut out = [[0.0f32; 2]; 3];
                            for (t, o) in ts.iter().zip(out.iter_mut()) {
                                *o = [loc.num("uvs", t[0])?, loc.num("uvs", t[1])?];
                            }
                            vec![Some(out)]
                        }
                        None => vec![],
                    };
                    let m = material(&loc, &d.material)?;
                    add_group(&loc, name, vec![Shape::Triangle { p }], normals, uvs, m)?;
                }
                Def::Mesh(mesh) => {
                    let d = mesh.get_ref();
                    let name = d.name.clone().unwrap_or_else(|| format!("mesh {i}"));
                    let loc = self.loc(format!("mesh \"{name}\""), mesh);
                    let translate = loc.vec3("translate", d.translate)?;
                    let scale = loc.num("scale", d.scale)?;
                    if scale <= 0.0 {
                        return Err(loc.err("scale", format!("must be positive, got {}", d.scale)));
                    }
                    let path =
                        base.map_or_else(|| Path::new(&d.obj).to_path_buf(), |b| b.join(&d.obj));
                    let shading = match d.shading.as_deref() {
                        None => MeshShading::Auto,
                        Some("flat") => MeshShading::Flat,
                        Some("smooth") => MeshShading::Smooth,
                        Some(other) => {
                            return Err(loc.err(
                                "shading",
                                format!("must be \"flat\" or \"smooth\", got \"{other}\""),
                            ));
                        }
                    };
                    let (tris, normals, uvs) = load_obj(&path, translate, scale, shading)
                        .map_err(|m| loc.err("obj", m))?;
                    let m = material(&loc, &d.material)?;
                    add_group(&loc, name, tris, normals, uvs, m)?;
                }
                Def::Gltf(g) => {
                    let d = g.get_ref();
                    let name = d.name.clone().unwrap_or_else(|| format!("gltf {i}"));
                    let loc = self.loc(format!("gltf \"{name}\""), g);
                    // `gltf_files` read the tables in file order, as this loop meets them.
                    let Some(p) = placed.next() else { break };
                    let instead = d
                        .material
                        .is_some()
                        .then(|| material(&loc, &d.material))
                        .transpose()?;
                    // The group each part becomes (the prototypes' for the instances below).
                    let mut group_of = vec![];
                    for part in p.parts {
                        let m = instead.unwrap_or(p.material_base + part.material as u32);
                        group_of.push(add_group(
                            &loc,
                            part.name,
                            part.triangles,
                            part.normals,
                            part.uvs,
                            m,
                        )?);
                    }
                    for inst in p.instances {
                        if let Some(&group) = group_of.get(inst.part) {
                            gltf_instances.push(instances::Placement {
                                name: inst.name,
                                group,
                                matrix: inst.matrix,
                                what: loc.what.clone(),
                                span: loc.span.clone(),
                            });
                        }
                    }
                }
            }
        }
        let placed = self.instances(&f, gltf_instances, &mut objects, &mut groups, &materials)?;
        let meshes = f.mesh.len() + gltf_parts;
        let mut features = Features::compute(&objects, &materials, lights.len(), meshes);
        features.instances = placed.instances.len();
        let name = f.title.clone().unwrap_or_else(|| {
            Path::new(self.file)
                .file_name()
                .map_or(self.file.to_string(), |n| n.to_string_lossy().into_owned())
        });
        Ok(Scene {
            name,
            path: None,
            source_hash: opened_hash
                .unwrap_or_else(|| crate::text::sha256_hex(self.text.as_bytes())),
            camera,
            settings,
            lights,
            materials,
            objects,
            groups,
            vertex_normals,
            vertex_uvs,
            textures,
            features,
            cameras,
            warnings,
            instances: placed.instances,
            prototypes: placed.prototypes,
            world_objects: placed.world_objects,
        })
    }
}

/// Whether a line is a TOML table header (`[camera]`, `[[sphere]]`), not an array row.
fn is_header(line: &str) -> bool {
    let t = line.split('#').next().unwrap_or("").trim();
    let inner = t
        .strip_prefix("[[")
        .and_then(|r| r.strip_suffix("]]"))
        .or_else(|| t.strip_prefix('[').and_then(|r| r.strip_suffix(']')));
    inner.is_some_and(|i| {
        !i.is_empty()
            && i.chars()
                .all(|c| c.is_ascii_alphanumeric() || "_-. ".contains(c))
    })
}
