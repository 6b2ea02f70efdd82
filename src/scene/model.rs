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
}

/// `[camera]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[allow(missing_docs)]
pub struct CameraDef {
    pub from: [f64; 3],
    pub at: [f64; 3],
    pub up: [f64; 3],
    pub fov: f64,
    pub width: i64,
    pub height: i64,
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
    pub background: [f64; 3],
    pub sphere_method: String,
    pub triangle_method: String,
    pub offset: String,
    pub epsilon: f64,
    pub accel: String,
    pub seed: i64,
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
            seed: 0,
        }
    }
}

/// `[[light]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[allow(missing_docs)]
pub struct LightDef {
    pub name: Option<String>,
    pub position: [f64; 3],
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
    pub color: [f64; 3],
    pub ambient: f64,
    pub diffuse: f64,
    pub specular: f64,
    pub shininess: f64,
    pub reflective: f64,
    pub transparency: f64,
    pub refractive_index: f64,
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
        }
    }
}

/// `[[sphere]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[allow(missing_docs)]
pub struct SphereDef {
    pub name: Option<String>,
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
    pub point: Option<[f64; 3]>,
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
    pub vertices: [[f64; 3]; 3],
    pub material: Option<String>,
}

/// `[[mesh]]`: an OBJ file, relative to the scene file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct MeshDef {
    pub name: Option<String>,
    pub obj: String,
    #[serde(default)]
    pub translate: [f64; 3],
    #[serde(default = "one")]
    pub scale: f64,
    pub material: Option<String>,
}

fn one() -> f64 {
    1.0
}
