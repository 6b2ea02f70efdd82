//! Loading and validating a scene: TOML syntax errors with file:line:column, semantic errors that
//! name the object and field (with the field's line and column), OBJ meshes through `tobj`.

use super::limits::*;
use super::model::*;
use super::obj::{MeshShading, load_obj};
use super::*;
use sha2::{Digest, Sha256};
use std::collections::HashMap;
use std::ops::Range;
use std::path::Path;
use toml::Spanned;

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

/// Loads a scene from TOML text. `file` names it in errors; `base` is where OBJ paths start from.
pub fn load_str(text: &str, file: &str, base: Option<&Path>) -> Result<Scene, SceneError> {
    let ctx = Ctx { text, file };
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
}

/// Where an object sits in the file, for locating its fields.
struct Loc<'a> {
    what: String,
    span: Option<Range<usize>>,
    ctx: &'a Ctx<'a>,
}

impl Loc<'_> {
    fn err(&self, field: &str, message: impl Into<String>) -> SceneError {
        let (line, column) = match &self.span {
            Some(span) => {
                let pos = self
                    .ctx
                    .find_field(span.clone(), field)
                    .unwrap_or(span.start);
                let (l, c) = self.ctx.line_col(pos);
                (Some(l), Some(c))
            }
            None => (None, None),
        };
        SceneError {
            file: self.ctx.file.into(),
            line,
            column,
            field: Some(if field.is_empty() {
                self.what.clone()
            } else {
                format!("{} → {field}", self.what)
            }),
            message: message.into(),
        }
    }

    fn num(&self, field: &str, x: f64) -> Result<f32, SceneError> {
        if !x.is_finite() {
            return Err(self.err(field, format!("must be a finite number, got {x}")));
        }
        if x.abs() > MAX_MAGNITUDE {
            return Err(self.err(
                field,
                format!("{x:e} is too large: scene numbers lie within ±{MAX_MAGNITUDE:e}, where single-precision (f32) tracing stays finite"),
            ));
        }
        Ok(x as f32)
    }

    fn nonneg(&self, field: &str, x: f64) -> Result<f32, SceneError> {
        let v = self.num(field, x)?;
        if v < 0.0 {
            return Err(self.err(field, format!("must not be negative, got {x}")));
        }
        Ok(v)
    }

    fn unit(&self, field: &str, x: f64) -> Result<f32, SceneError> {
        let v = self.nonneg(field, x)?;
        if v > 1.0 {
            return Err(self.err(field, format!("must lie in [0, 1], got {x}")));
        }
        Ok(v)
    }

    fn vec3(&self, field: &str, a: [f64; 3]) -> Result<Vec3, SceneError> {
        if a.iter().any(|c| !c.is_finite()) {
            return Err(self.err(field, format!("must be three finite numbers, got {a:?}")));
        }
        if a.iter().any(|c| c.abs() > MAX_MAGNITUDE) {
            return Err(self.err(
                field,
                format!("{a:?} has a component too large: scene numbers lie within ±{MAX_MAGNITUDE:e}, where single-precision (f32) tracing stays finite"),
            ));
        }
        Ok(Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32))
    }

    /// A triangle's vertex: within ±[`MAX_VERTEX`].
    fn vertex(&self, field: &str, a: [f64; 3]) -> Result<Vec3, SceneError> {
        let v = self.vec3(field, a)?;
        if a.iter().any(|c| c.abs() > MAX_VERTEX) {
            return Err(self.err(field, vertex_too_large(&format!("{a:?}"))));
        }
        Ok(v)
    }

    /// A position or length of a sphere, plane, light or camera: within ±[`MAX_COORD`].
    fn coord(&self, field: &str, x: f64) -> Result<f32, SceneError> {
        if x.is_finite() && x.abs() > MAX_COORD {
            return Err(self.err(
                field,
                format!("{x:e} is too large: positions and radii lie within ±{MAX_COORD:e}, where their squares stay finite in single precision (f32)"),
            ));
        }
        if x.is_finite() {
            return Ok(x as f32);
        }
        self.num(field, x)
    }

    /// A point of a sphere, plane, light or camera: within ±[`MAX_COORD`].
    fn coord3(&self, field: &str, a: [f64; 3]) -> Result<Vec3, SceneError> {
        if a.iter().all(|c| c.is_finite()) {
            if a.iter().any(|c| c.abs() > MAX_COORD) {
                return Err(self.err(
                    field,
                    format!("{a:?} has a component too large: positions lie within ±{MAX_COORD:e}, where their squares stay finite in single precision (f32)"),
                ));
            }
            return Ok(Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32));
        }
        self.vec3(field, a)
    }

    fn color(&self, field: &str, a: [f64; 3]) -> Result<Vec3, SceneError> {
        let v = self.vec3(field, a)?;
        if v.min_element() < 0.0 {
            return Err(self.err(
                field,
                format!("colour components must not be negative, got {a:?}"),
            ));
        }
        Ok(v)
    }

    /// A colour that is a reflectance: each component in [0, 1].
    fn unit_color(&self, field: &str, a: [f64; 3]) -> Result<Vec3, SceneError> {
        let v = self.color(field, a)?;
        if v.max_element() > 1.0 {
            return Err(self.err(
                field,
                format!(
                    "a texture's colours are reflectances: each component lies in [0, 1], got {a:?}"
                ),
            ));
        }
        Ok(v)
    }

    fn choice<T: clap::ValueEnum>(&self, field: &str, s: &str) -> Result<T, SceneError> {
        T::from_str(s, true).map_err(|_| {
            let names: Vec<String> = T::value_variants()
                .iter()
                .filter_map(|v| {
                    v.to_possible_value()
                        .map(|p| format!("\"{}\"", p.get_name()))
                })
                .collect();
            self.err(
                field,
                format!(
                    "unknown value \"{s}\"; expected one of {}",
                    names.join(", ")
                ),
            )
        })
    }
}

const MAX_DIMENSION: i64 = 16384;
const MAX_PIXELS: i64 = 40_000_000;

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
        let camera = self.camera(f.camera.as_ref())?;
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

        let textures = self.textures(&f, base)?;
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
                texture: match &d.texture {
                    None => None,
                    Some(n) => Some(textures.iter().position(|t| &t.name == n).ok_or_else(|| {
                        let known: Vec<String> =
                            textures.iter().map(|t| format!("\"{}\"", t.name)).collect();
                        let known = if known.is_empty() {
                            "no textures are defined: add a [[texture]]".to_string()
                        } else {
                            format!("known: {}", known.join(", "))
                        };
                        loc.err("texture", format!("unknown texture \"{n}\" ({known})"))
                    })? as u32),
                },
            });
        }
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
         -> Result<(), SceneError> {
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
            Ok(())
        };

        // Objects are processed in file order (whatever their kind), so ids follow the file and a
        // duplicate name is reported where it repeats.
        enum Def<'d> {
            Sphere(&'d Spanned<SphereDef>),
            Plane(&'d Spanned<PlaneDef>),
            Triangle(&'d Spanned<TriangleDef>),
            Mesh(&'d Spanned<MeshDef>),
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
            }
        }
        let features = Features::compute(&objects, &materials, lights.len(), f.mesh.len());
        let name = f.title.clone().unwrap_or_else(|| {
            Path::new(self.file)
                .file_name()
                .map_or(self.file.to_string(), |n| n.to_string_lossy().into_owned())
        });
        let hash = Sha256::digest(self.text.as_bytes());
        Ok(Scene {
            name,
            path: None,
            source_hash: hash.iter().map(|b| format!("{b:02x}")).collect(),
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
        })
    }

    /// The `[[texture]]` tables, in file order: a checker's squares and colours, or an image
    /// read (relative to the scene file) and decoded to linear texels.
    fn textures(&self, f: &SceneFile, base: Option<&Path>) -> Result<Vec<Texture>, SceneError> {
        let mut out: Vec<Texture> = vec![];
        let mut budget = texture::MAX_TEXELS;
        for (i, t) in f.texture.iter().enumerate() {
            let d = t.get_ref();
            let name = d.name.clone().unwrap_or_else(|| format!("texture {i}"));
            let loc = self.loc(format!("texture \"{name}\""), t);
            if out.iter().any(|x| x.name == name) {
                return Err(loc.err(
                    "name",
                    format!("a texture named \"{name}\" is already defined"),
                ));
            }
            let kind = match (&d.checker, &d.image) {
                (Some(_), Some(_)) => {
                    return Err(loc.err(
                        "image",
                        "give either `checker` (a checkerboard) or `image` (a file), not both",
                    ));
                }
                (None, None) => {
                    return Err(loc.err(
                        "",
                        "a texture needs `checker = [squares across u, squares across v]` or `image = \"file.png\"`",
                    ));
                }
                (Some(squares), None) => {
                    for (field, given) in [("filter", &d.filter), ("wrap", &d.wrap)] {
                        if given.is_some() {
                            return Err(loc.err(
                                field,
                                format!("`{field}` applies to images; a checker is computed exactly at each point"),
                            ));
                        }
                    }
                    if squares.iter().any(|&s| s == 0 || s > 1_000_000) {
                        return Err(loc.err(
                            "checker",
                            format!(
                                "squares across u and v must lie in 1 … 1000000, got {squares:?}"
                            ),
                        ));
                    }
                    let colors = d.colors.unwrap_or([[0.9; 3], [0.15; 3]]);
                    TextureKind::Checker {
                        squares: *squares,
                        colors: [
                            loc.unit_color("colors", colors[0])?,
                            loc.unit_color("colors", colors[1])?,
                        ],
                    }
                }
                (None, Some(file)) => {
                    if d.colors.is_some() {
                        return Err(
                            loc.err("colors", "`colors` go with `checker`; an image has its own")
                        );
                    }
                    let path = base.map_or_else(|| Path::new(file).to_path_buf(), |b| b.join(file));
                    let bytes =
                        crate::io::read_input(&path, texture::MAX_IMAGE_BYTES, "image file")
                            .map_err(|e| {
                                loc.err(
                                    "image",
                                    if e.kind() == std::io::ErrorKind::NotFound {
                                        format!("image file {} does not exist", path.display())
                                    } else {
                                        format!("cannot read image file {}: {e}", path.display())
                                    },
                                )
                            })?;
                    let (width, height, texels) = texture::decode_image(&bytes, &path, budget)
                        .map_err(|m| loc.err("image", m))?;
                    budget -= u64::from(width) * u64::from(height);
                    TextureKind::Image {
                        file: file.clone(),
                        width,
                        height,
                        texels: std::sync::Arc::new(texels),
                        filter: d
                            .filter
                            .as_deref()
                            .map(|x| loc.choice("filter", x))
                            .transpose()?
                            .unwrap_or_default(),
                        wrap: d
                            .wrap
                            .as_deref()
                            .map(|x| loc.choice("wrap", x))
                            .transpose()?
                            .unwrap_or_default(),
                    }
                }
            };
            out.push(Texture { name, kind });
        }
        Ok(out)
    }

    fn camera(&self, c: Option<&Spanned<CameraDef>>) -> Result<Camera, SceneError> {
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

    fn settings(&self, r: Option<&Spanned<RenderDef>>) -> Result<Settings, SceneError> {
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
