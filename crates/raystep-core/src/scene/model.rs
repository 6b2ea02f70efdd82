//! The scene file's TOML schema (a public contract: extend, don't rename). Every field has a
//! default; unknown fields are errors, so a typo is reported rather than silently ignored.

use serde::Deserialize;
use toml::Spanned;

/// The whole scene file, as parsed (before validation).
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// A display name for the scene.
    pub title: Option<String>,
    /// `[camera]`.
    #[serde(default)]
    pub camera: Option<Spanned<CameraDef>>,
    /// `[render]`.
    #[serde(default)]
    pub render: Option<Spanned<RenderDef>>,
    /// `[[light]]`.
    #[serde(default)]
    pub light: Vec<Spanned<LightDef>>,
    /// `[[material]]`.
    #[serde(default)]
    pub material: Vec<Spanned<MaterialDef>>,
    /// `[[sphere]]`.
    #[serde(default)]
    pub sphere: Vec<Spanned<SphereDef>>,
    /// `[[plane]]`.
    #[serde(default)]
    pub plane: Vec<Spanned<PlaneDef>>,
    /// `[[triangle]]`.
    #[serde(default)]
    pub triangle: Vec<Spanned<TriangleDef>>,
    /// `[[mesh]]`.
    #[serde(default)]
    pub mesh: Vec<Spanned<MeshDef>>,
    /// `[[texture]]`.
    #[serde(default)]
    pub texture: Vec<Spanned<TextureDef>>,
    /// `[[gltf]]`.
    #[serde(default)]
    pub gltf: Vec<Spanned<GltfDef>>,
    /// `[[instance]]`.
    #[serde(default)]
    pub instance: Vec<Spanned<InstanceDef>>,
}

/// `[camera]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[allow(missing_docs)]
pub struct CameraDef {
    #[serde(deserialize_with = "exact::vec3")]
    pub from: [f64; 3],
    #[serde(deserialize_with = "exact::vec3")]
    pub at: [f64; 3],
    #[serde(deserialize_with = "exact::vec3")]
    pub up: [f64; 3],
    pub fov: f64,
    pub width: i64,
    pub height: i64,
    pub aperture: f64,
    pub focus_distance: Option<f64>,
}

impl Default for CameraDef {
    fn default() -> Self {
        CameraDef {
            from: [0., 0., -5.],
            at: [0.; 3],
            up: [0., 1., 0.],
            fov: 60.0,
            width: 320,
            height: 240,
            aperture: 0.0,
            focus_distance: None,
        }
    }
}

/// `[render]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[allow(missing_docs)]
pub struct RenderDef {
    pub max_depth: i64,
    pub spp: i64,
    #[serde(deserialize_with = "exact::vec3")]
    pub background: [f64; 3],
    pub sphere_method: String,
    pub triangle_method: String,
    pub offset: String,
    pub epsilon: f64,
    pub accel: String,
    pub bvh_quality: String,
    pub seed: i64,
    pub integrator: String,
    pub rr_depth: i64,
    pub strategy: String,
    pub sampler: String,
    pub terminator: String,
}

impl Default for RenderDef {
    fn default() -> Self {
        RenderDef {
            max_depth: 5,
            spp: 1,
            background: [0.; 3],
            sphere_method: "stable".into(),
            triangle_method: "watertight".into(),
            offset: "robust".into(),
            epsilon: 1e-4,
            accel: "auto".into(),
            bvh_quality: "medium".into(),
            seed: 0,
            integrator: "whitted".into(),
            rr_depth: 3,
            strategy: "mis".into(),
            sampler: "independent".into(),
            terminator: "none".into(),
        }
    }
}

/// `[[light]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[allow(missing_docs)]
pub struct LightDef {
    pub name: Option<String>,
    #[serde(deserialize_with = "exact::vec3")]
    pub position: [f64; 3],
    #[serde(deserialize_with = "exact::vec3")]
    pub color: [f64; 3],
}

impl Default for LightDef {
    fn default() -> Self {
        LightDef {
            name: None,
            position: [-10., 10., -10.],
            color: [1.; 3],
        }
    }
}

/// `[[material]]` (defaults as in The Ray Tracer Challenge).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[allow(missing_docs)]
pub struct MaterialDef {
    pub name: Option<String>,
    #[serde(deserialize_with = "exact::vec3")]
    pub color: [f64; 3],
    pub ambient: f64,
    pub diffuse: f64,
    pub specular: f64,
    pub shininess: f64,
    pub reflective: f64,
    pub transparency: f64,
    pub refractive_index: f64,
    #[serde(deserialize_with = "exact::vec3")]
    pub emission: [f64; 3],
    pub bsdf: Option<String>,
    pub roughness: f64,
    /// The name of a `[[texture]]` whose colour multiplies `color` at each hit.
    pub texture: Option<String>,
    /// The name of a `[[texture]]` whose green channel multiplies a glossy BSDF's `roughness`
    /// at each hit (glTF's metallic-roughness convention).
    pub roughness_texture: Option<String>,
}

impl Default for MaterialDef {
    fn default() -> Self {
        MaterialDef {
            name: None,
            color: [1.; 3],
            ambient: 0.1,
            diffuse: 0.9,
            specular: 0.9,
            shininess: 200.0,
            reflective: 0.0,
            transparency: 0.0,
            refractive_index: 1.0,
            emission: [0.0; 3],
            bsdf: None,
            roughness: 0.5,
            texture: None,
            roughness_texture: None,
        }
    }
}

/// `[[sphere]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[allow(missing_docs)]
pub struct SphereDef {
    pub name: Option<String>,
    #[serde(deserialize_with = "exact::vec3")]
    pub center: [f64; 3],
    pub radius: f64,
    pub material: Option<String>,
}

impl Default for SphereDef {
    fn default() -> Self {
        SphereDef {
            name: None,
            center: [0.; 3],
            radius: 1.0,
            material: None,
        }
    }
}

/// `[[plane]]`: `point` + `normal`, or `axis` + `offset`.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
#[allow(missing_docs)]
pub struct PlaneDef {
    pub name: Option<String>,
    #[serde(deserialize_with = "exact::opt_vec3")]
    pub point: Option<[f64; 3]>,
    #[serde(deserialize_with = "exact::opt_vec3")]
    pub normal: Option<[f64; 3]>,
    pub axis: Option<String>,
    pub offset: Option<f64>,
    pub material: Option<String>,
}

/// `[[triangle]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct TriangleDef {
    pub name: Option<String>,
    #[serde(deserialize_with = "exact::triangle")]
    pub vertices: [[f64; 3]; 3],
    /// Vertex normals n₀, n₁, n₂ (any length but zero): the triangle is smooth-shaded.
    #[serde(default, deserialize_with = "exact::opt_triangle")]
    pub normals: Option<[[f64; 3]; 3]>,
    /// Texture coordinates t₀, t₁, t₂ of the three vertices (without them a texture reads the
    /// hit's barycentric u, v).
    #[serde(default, deserialize_with = "exact::opt_uvs")]
    pub uvs: Option<[[f64; 2]; 3]>,
    pub material: Option<String>,
}

/// `[[mesh]]`: an OBJ file, relative to the scene file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct MeshDef {
    pub name: Option<String>,
    pub obj: String,
    #[serde(default, deserialize_with = "exact::vec3")]
    pub translate: [f64; 3],
    #[serde(default = "one")]
    pub scale: f64,
    pub material: Option<String>,
    /// `"flat"` (the geometric normal) or `"smooth"` (vertex normals: the file's `vn`, else the
    /// area-weighted average of the faces around each vertex). Default: smooth where the file
    /// gives every face its `vn`, flat otherwise.
    pub shading: Option<String>,
}

/// `[[gltf]]`: a glTF 2.0 file (`.gltf` or `.glb`, relative to the scene file), placed by `scale`,
/// then `rotate` (degrees about x, then y, then z), then `translate`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct GltfDef {
    pub name: Option<String>,
    pub file: String,
    #[serde(default, deserialize_with = "exact::vec3")]
    pub translate: [f64; 3],
    #[serde(default, deserialize_with = "exact::vec3")]
    pub rotate: [f64; 3],
    #[serde(default = "one")]
    pub scale: f64,
    /// A raystep material every primitive takes instead of the file's.
    pub material: Option<String>,
    /// `true`: the scene's camera is the file's first perspective camera; `"name"`: the one of
    /// that name (its aspect ratio sets the width for the scene's height).
    pub camera: Option<GltfCameraDef>,
    /// Whether the file's `KHR_lights_punctual` point lights join the scene (default true).
    #[serde(default = "yes")]
    pub lights: bool,
}

/// `[[gltf]] camera`: `true`/`false`, or a camera's name.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
#[allow(missing_docs)]
pub enum GltfCameraDef {
    First(bool),
    Named(String),
}

fn yes() -> bool {
    true
}

/// `[[texture]]`: a checker (`checker`, `colors`) or an image (`image`, `filter`, `wrap`).
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
#[allow(missing_docs)]
pub struct TextureDef {
    pub name: Option<String>,
    /// Squares per unit of u and of v.
    pub checker: Option<[u32; 2]>,
    /// The even and the odd squares' colours (default white and a dark grey).
    #[serde(deserialize_with = "exact::opt_colors")]
    pub colors: Option<[[f64; 3]; 2]>,
    /// A PNG or JPEG file, relative to the scene file.
    pub image: Option<String>,
    /// `"nearest"` or `"bilinear"` (images only; default bilinear).
    pub filter: Option<String>,
    /// `"repeat"`, `"clamp"` or `"mirror"` (images only; default repeat).
    pub wrap: Option<String>,
}

/// `[[instance]]`: the mesh, triangle or sphere called `of`, placed by `scale` (one number, or
/// one per axis), then `rotate` (degrees about x, then y, then z), then `translate` — or by a
/// `matrix` of 3 or 4 rows of 4 numbers (the fourth row must be 0, 0, 0, 1), not both. An object
/// that an instance names is a prototype: it is drawn only where its instances place it.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct InstanceDef {
    pub name: Option<String>,
    pub of: String,
    #[serde(default, deserialize_with = "exact::opt_vec3")]
    pub translate: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "exact::opt_vec3")]
    pub rotate: Option<[f64; 3]>,
    pub scale: Option<InstanceScale>,
    #[serde(default, deserialize_with = "exact::opt_matrix")]
    pub matrix: Option<[[f64; 4]; 4]>,
}

/// `[[instance]] scale`: one number for every axis, or one per axis.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
#[allow(missing_docs)]
pub enum InstanceScale {
    Uniform(f64),
    PerAxis([f64; 3]),
}

fn one() -> f64 {
    1.0
}

/// Arrays of an exact length. serde's own `[f64; 3]` reads the first three elements and toml
/// does not complain about the rest, so `center = [0, 0, 0, 99]` would load as `[0, 0, 0]`;
/// these read the whole array and reject any other length (toml then reports the array's line
/// and column).
mod exact {
    use serde::de::Error;
    use serde::{Deserialize, Deserializer};

    fn three<E: Error>(v: Vec<f64>, what: &str) -> Result<[f64; 3], E> {
        <[f64; 3]>::try_from(v.as_slice())
            .map_err(|_| E::custom(format!("expected {what}, found {} values", v.len())))
    }

    /// Exactly three numbers.
    pub fn vec3<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 3], D::Error> {
        three(Vec::<f64>::deserialize(d)?, "3 numbers [x, y, z]")
    }

    /// Exactly three numbers, when present.
    pub fn opt_vec3<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f64; 3]>, D::Error> {
        vec3(d).map(Some)
    }

    /// Exactly three points of exactly three numbers, when present.
    pub fn opt_triangle<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<[[f64; 3]; 3]>, D::Error> {
        triangle(d).map(Some)
    }

    /// Exactly three pairs (u, v), when present.
    pub fn opt_uvs<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[[f64; 2]; 3]>, D::Error> {
        let v = Vec::<Vec<f64>>::deserialize(d)?;
        let mut out = [[0.0; 2]; 3];
        if v.len() != 3 {
            return Err(D::Error::custom(format!(
                "expected 3 texture coordinates [[u, v], [u, v], [u, v]], found {} values",
                v.len()
            )));
        }
        for (k, (p, o)) in v.into_iter().zip(out.iter_mut()).enumerate() {
            *o = <[f64; 2]>::try_from(p.as_slice()).map_err(|_| {
                D::Error::custom(format!(
                    "expected 2 numbers [u, v] in vertex {}, found {} values",
                    k + 1,
                    p.len()
                ))
            })?;
        }
        Ok(Some(out))
    }

    /// Exactly two colours of exactly three numbers, when present.
    pub fn opt_colors<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[[f64; 3]; 2]>, D::Error> {
        let v = Vec::<Vec<f64>>::deserialize(d)?;
        if v.len() != 2 {
            return Err(D::Error::custom(format!(
                "expected 2 colours [[r, g, b], [r, g, b]], found {} values",
                v.len()
            )));
        }
        let mut out = [[0.0; 3]; 2];
        for (k, (p, o)) in v.into_iter().zip(out.iter_mut()).enumerate() {
            *o = three(p, &format!("3 numbers [r, g, b] in colour {}", k + 1))?;
        }
        Ok(Some(out))
    }

    /// Three or four rows of exactly four numbers, when present (three rows get 0, 0, 0, 1).
    pub fn opt_matrix<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[[f64; 4]; 4]>, D::Error> {
        let v = Vec::<Vec<f64>>::deserialize(d)?;
        if !(3..=4).contains(&v.len()) {
            return Err(D::Error::custom(format!(
                "expected 3 or 4 rows [[a, b, c, d], …], found {} rows",
                v.len()
            )));
        }
        let mut out = [[0.0, 0.0, 0.0, 1.0]; 4];
        for (k, (p, o)) in v.into_iter().zip(out.iter_mut()).enumerate() {
            *o = <[f64; 4]>::try_from(p.as_slice()).map_err(|_| {
                D::Error::custom(format!(
                    "expected 4 numbers in row {}, found {} values",
                    k + 1,
                    p.len()
                ))
            })?;
        }
        Ok(Some(out))
    }

    /// Exactly three points of exactly three numbers.
    pub fn triangle<'de, D: Deserializer<'de>>(d: D) -> Result<[[f64; 3]; 3], D::Error> {
        let v = Vec::<Vec<f64>>::deserialize(d)?;
        let mut out = [[0.0; 3]; 3];
        if v.len() != 3 {
            return Err(D::Error::custom(format!(
                "expected 3 vertices [[x, y, z], [x, y, z], [x, y, z]], found {} values",
                v.len()
            )));
        }
        for (k, (p, o)) in v.into_iter().zip(out.iter_mut()).enumerate() {
            *o = three(p, &format!("3 numbers [x, y, z] in vertex {}", k + 1))?;
        }
        Ok(out)
    }
}
