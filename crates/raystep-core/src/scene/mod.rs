//! The scene as data: the validated [`Scene`] every other module reads, its [`Features`], and the
//! loader ([`load_file`], [`load_str`]) that turns a TOML file (plus OBJ meshes) into it or into a located
//! [`SceneError`].

pub mod camera;
pub mod edit;
mod features;
mod gltf;
pub mod instance;
mod limits;
mod load;
pub mod mitsuba;
mod model;
mod obj;
pub mod spd;
pub mod texture;

pub use crate::shapes::Shape;
pub use features::Features;
pub use gltf::{GltfError, MAX_GLTF_BYTES};
pub use instance::{Affine, Instance, NO_INSTANCE, Prototype};
pub use limits::{MAX_COORD, MAX_MAGNITUDE, MAX_OBJECTS, MAX_VERTEX};
pub use load::{LocatedError, SceneError, is_gltf, load_file, load_str};
pub use model::SceneFile;
pub use texture::{Filter, MipLevel, Texture, TextureKind, Wrap, mip_levels};

use crate::shapes::{SphereMethod, TriangleMethod};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The built-in default scene (three spheres on a plane, one light): what `raystep` opens with no
/// scene given. It is `scenes/three-spheres.toml`, compiled into the binary.
pub const DEFAULT_SCENE: &str = include_str!("../../../../scenes/three-spheres.toml");
/// The file name reported for the built-in scene.
pub const DEFAULT_SCENE_NAME: &str = "three-spheres.toml (built in)";

/// Loads the built-in default scene.
pub fn default_scene() -> Scene {
    load_str(DEFAULT_SCENE, DEFAULT_SCENE_NAME, None).expect("the built-in scene is valid")
}

/// The pinhole camera, in the convention of *Ray Tracing in One Weekend* (book/scenes.md, "The scene format").
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Camera {
    /// Eye position.
    pub from: Vec3,
    /// Point looked at.
    pub at: Vec3,
    /// Up hint.
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub fov: f32,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The thin lens's radius (`[camera] aperture`, scene units): 0 is a pinhole. Read by the
    /// Monte Carlo integrators only; the Whitted tracer (and the GPU) is always a pinhole.
    #[serde(default)]
    pub aperture: f32,
    /// The distance from the eye, along the view direction, of the plane in focus
    /// (`[camera] focus_distance`; by default the distance from `from` to `at`).
    #[serde(default)]
    pub focus_distance: f32,
}

/// How spawned rays (shadow, reflection, refraction) leave a surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum OffsetPolicy {
    /// Start exactly at the computed hit point: shows shadow acne.
    None,
    /// The Ray Tracer Challenge's `over_point`: move `epsilon` along the normal. Fails at large
    /// scales (acne) and skips surfaces closer than `epsilon` (docs/NUMERICS.md S7, S19).
    Fixed,
    /// pbrt-v4 `OffsetRayOrigin`: move by the hit point's rounding-error bound along the normal,
    /// then one float further. Scale-independent; the default.
    // Why the default (`raystep stability`, full suite, through the renderer's own `interact`
    // and `spawn_origin`): reflected rays from spheres, planes and triangles at scales
    // 1e-3…1e6 (S19) hit their own surface 2271 times in 16 000 with no offset, 530 with the
    // fixed ε = 1e-4 (at large scales), 0 with this offset; rays leaving a sphere towards a
    // second one 4e-5 away (S7) skip it 4000 times in 4000 with the fixed ε, never with this
    // offset. scenes/acne.toml shows the acne.
    #[default]
    Robust,
}

/// Which structure finds the closest hit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum AccelChoice {
    /// Brute force for small scenes, the BVH for larger ones.
    #[default]
    Auto,
    /// The lecture notes' naive loop over every primitive.
    None,
    /// A bounding volume hierarchy.
    Bvh,
    /// A hierarchy of bounding spheres (over the BVH's tree).
    Spheres,
    /// A uniform grid walked by 3D-DDA.
    Grid,
}

/// How much time the BVH build spends on the tree's quality: obvhs's presets, named after
/// Embree's build qualities. A better tree costs fewer node visits per ray and takes longer to
/// build (`raystep bench SCENE --section build` prints both, with the tree's SAH cost).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum BvhQuality {
    /// obvhs's `very_fast_build`: PLOC with the smallest search radius and little reinsertion.
    Low,
    /// obvhs's `medium_build`, every node offered for reinsertion up to 2¹⁸ primitives: the
    /// default.
    #[default]
    Medium,
    /// obvhs's `slow_build` (a wider PLOC search, 128-bit Morton codes), every node offered for
    /// reinsertion up to 2¹⁸ primitives.
    High,
}

/// Render and tracing settings (the scene's `[render]` table, possibly overridden on the command line).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    /// Recursion limit for reflection and refraction (the primary ray has depth 0).
    pub max_depth: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Colour of rays that hit nothing (linear RGB).
    pub background: Vec3,
    /// The ray–sphere method.
    pub sphere_method: SphereMethod,
    /// The ray–triangle method.
    pub triangle_method: TriangleMethod,
    /// The ray-origin offset policy for spawned rays.
    pub offset: OffsetPolicy,
    /// The distance used by `offset = "fixed"`.
    pub epsilon: f32,
    /// Acceleration structure.
    pub accel: AccelChoice,
    /// Build quality of the BVH (and of the sphere tree, which is built over the BVH's tree).
    #[serde(default)]
    pub bvh_quality: BvhQuality,
    /// Seed mixed into every sample's jitter (renders with different seeds are independent).
    pub seed: u32,
    /// Which light transport the tracer computes (`[render] integrator`).
    #[serde(default)]
    pub integrator: Integrator,
    /// The path tracer's Russian roulette starts after this many bounces (`[render] rr_depth`).
    #[serde(default = "default_rr_depth")]
    pub rr_depth: u32,
    /// Which estimators the path tracer combines for direct light (`[render] strategy`).
    #[serde(default)]
    pub strategy: Strategy,
    /// How the Monte Carlo integrators' 2D samples are spread over a pixel's samples
    /// (`[render] sampler`).
    #[serde(default)]
    pub sampler: SamplerKind,
    /// Where rays leave a smooth-shaded triangle (`[render] terminator`): the shadow
    /// terminator's fix, or none.
    #[serde(default)]
    pub terminator: Terminator,
}

/// Where rays leave a smooth-shaded triangle on the side the ray came from (`[render]
/// terminator`). Shadow rays from the flat triangle of a coarse mesh are blocked by the
/// neighbouring facets where the smooth normal still faces the light: a jagged terminator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Terminator {
    /// From the hit point on the flat triangle: the jagged terminator shows.
    #[default]
    None,
    /// Hanika's shift ("Hacking the shadow terminator", Ray Tracing Gems II, ch. 4): from the
    /// point lifted towards the curved surface the vertex normals describe
    /// ([`crate::trace::interaction::lift_point`]).
    Hanika,
}

fn default_rr_depth() -> u32 {
    3
}

/// The light transport a scene is rendered with (`[render] integrator`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Integrator {
    /// Whitted 1980: point lights with Phong, perfect mirror and refraction rays (the default).
    #[default]
    Whitted,
    /// Cook, Porter and Carpenter 1984, distribution ray tracing: Whitted's recursion with area
    /// lights sampled (soft shadows), glossy reflection sampled about the mirror direction and a
    /// thin-lens camera.
    Distribution,
    /// Kajiya 1986, unidirectional path tracing with next-event estimation, BSDF sampling, multiple
    /// importance sampling (Veach's power heuristic, β = 2) and Russian roulette.
    Path,
}

impl Integrator {
    /// Whether it is one of the Monte Carlo integrators (distribution or path tracing): it samples
    /// lights and BSDFs with random numbers, records a pixel's samples, and reads a material as a
    /// BSDF ([`Material::bsdf`]); Whitted does none of these.
    pub fn is_monte_carlo(self) -> bool {
        match self {
            Integrator::Whitted => false,
            Integrator::Distribution | Integrator::Path => true,
        }
    }
}

/// How the Monte Carlo integrators draw their 2D samples (a point on a light or on the lens, a
/// BSDF direction) over a pixel's samples (`[render] sampler`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum SamplerKind {
    /// Every pair independent and uniform (the default).
    #[default]
    Independent,
    /// Stratified: the pixel's samples share a grid, one sample per cell, jittered inside it
    /// (see [`crate::trace::monte_carlo::stratified_pair`]).
    Stratified,
}

/// How the path tracer estimates the light arriving from emitters (`[render] strategy`): the
/// three estimators of Veach's comparison, all unbiased, with different noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Strategy {
    /// Both, combined by multiple importance sampling with the power heuristic (the default).
    #[default]
    Mis,
    /// Light sampling alone: next-event estimation at every hit; an emitter that a BSDF-sampled
    /// ray finds (and light sampling could have sampled) is not counted.
    Light,
    /// BSDF sampling alone: no next-event estimation; emitters count where the path finds them.
    Bsdf,
}

/// A material's scattering model for the Monte Carlo integrators (`[[material]] bsdf`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum BsdfKind {
    /// Lambert: albedo `color`.
    Diffuse,
    /// Perfect mirror reflection times `color`.
    Mirror,
    /// A smooth dielectric with `refractive_index`, exact Fresnel.
    Glass,
    /// A GGX microfacet reflector tinted by `color`, α = `roughness`².
    Glossy,
}

/// A material's BSDF as the Monte Carlo integrators use it (see [`Material::bsdf`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Bsdf {
    /// Lambert with this albedo.
    Diffuse {
        /// Albedo ρ (f = ρ/π).
        albedo: Vec3,
    },
    /// A perfect mirror with this reflectance.
    Mirror {
        /// Reflectance.
        tint: Vec3,
    },
    /// A smooth dielectric.
    Glass {
        /// Index of refraction (inside over outside).
        ior: f32,
    },
    /// GGX microfacet reflection.
    Glossy {
        /// Reflectance (the Fresnel term, constant).
        tint: Vec3,
        /// GGX α = roughness².
        alpha: f32,
    },
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            max_depth: 5,
            spp: 1,
            background: Vec3::ZERO,
            sphere_method: SphereMethod::default(),
            triangle_method: TriangleMethod::default(),
            offset: OffsetPolicy::default(),
            epsilon: 1e-4,
            accel: AccelChoice::default(),
            bvh_quality: BvhQuality::default(),
            seed: 0,
            integrator: Integrator::Whitted,
            rr_depth: 3,
            strategy: Strategy::Mis,
            sampler: SamplerKind::Independent,
            terminator: Terminator::None,
        }
    }
}

/// A point light.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Light {
    /// Name (`light 0` … when the file gives none).
    pub name: String,
    /// Position.
    pub position: Vec3,
    /// Intensity (linear RGB).
    pub color: Vec3,
}

/// A Phong material, with the defaults of The Ray Tracer Challenge.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Name objects refer to it by.
    pub name: String,
    /// Surface colour (linear RGB).
    pub color: Vec3,
    /// Ambient coefficient.
    pub ambient: f32,
    /// Diffuse coefficient.
    pub diffuse: f32,
    /// Specular coefficient.
    pub specular: f32,
    /// Phong exponent.
    pub shininess: f32,
    /// Mirror reflectance in [0, 1].
    pub reflective: f32,
    /// Transmittance in [0, 1].
    pub transparency: f32,
    /// Index of refraction.
    pub refractive_index: f32,
    /// Emitted radiance (linear RGB): an object with a non-zero emission is an area light.
    #[serde(default)]
    pub emission: Vec3,
    /// The BSDF the Monte Carlo integrators use; `None` maps the Phong fields ([`Material::bsdf`]).
    #[serde(default)]
    pub bsdf: Option<BsdfKind>,
    /// A glossy BSDF's roughness in [0, 1].
    #[serde(default)]
    pub roughness: f32,
    /// Index into [`Scene::textures`] of the texture whose colour multiplies `color` (and the
    /// Monte Carlo BSDF's albedo or tint) at each hit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<u32>,
    /// Index into [`Scene::textures`] of the texture whose green channel multiplies a glossy
    /// BSDF's `roughness` at each hit, under the Monte Carlo integrators (`[[material]]
    /// roughness_texture`; green, as glTF's metallic-roughness textures keep it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roughness_texture: Option<u32>,
}

/// Below this roughness a glossy BSDF is a mirror (GGX's α = roughness² would be a delta).
pub const MIN_ROUGHNESS: f32 = 0.03;

impl Material {
    /// The BSDF of the Monte Carlo integrators. With `bsdf` given: as named (`glossy` with
    /// roughness below [`MIN_ROUGHNESS`] is a mirror). Without it, from the Phong fields:
    /// transparency > 0 is glass; reflective ≥ 0.5 a mirror of reflectance `reflective`;
    /// otherwise Lambert with albedo `color × diffuse` (each channel at most 1).
    pub fn bsdf(&self) -> Bsdf {
        let albedo = (self.color * self.diffuse).min(Vec3::ONE);
        match self.bsdf {
            Some(BsdfKind::Diffuse) => Bsdf::Diffuse {
                albedo: self.color.min(Vec3::ONE),
            },
            Some(BsdfKind::Mirror) => Bsdf::Mirror { tint: self.color },
            Some(BsdfKind::Glass) => Bsdf::Glass {
                ior: self.refractive_index,
            },
            Some(BsdfKind::Glossy) if self.roughness < MIN_ROUGHNESS => {
                Bsdf::Mirror { tint: self.color }
            }
            Some(BsdfKind::Glossy) => Bsdf::Glossy {
                tint: self.color,
                alpha: self.roughness * self.roughness,
            },
            None if self.transparency > 0.0 => Bsdf::Glass {
                ior: self.refractive_index,
            },
            None if self.reflective >= 0.5 => Bsdf::Mirror {
                tint: Vec3::splat(self.reflective),
            },
            None => Bsdf::Diffuse { albedo },
        }
    }
}

impl Material {
    /// [`Material::bsdf`] with the texture's colour at the hit (`None`: untextured) multiplying
    /// a diffuse BSDF's albedo and a mirror's or glossy BSDF's tint; glass is not tinted.
    ///
    /// `roughness`: the roughness at the hit from a roughness texture (`roughness` × its green
    /// channel, [`Material::roughness_at`]); a glossy BSDF takes α = roughness², or is a mirror
    /// where it is below [`MIN_ROUGHNESS`].
    #[inline(always)]
    pub fn bsdf_textured(&self, texel: Option<Vec3>, roughness: Option<f32>) -> Bsdf {
        let mut b = self.bsdf();
        if let (Some(r), Bsdf::Glossy { tint, .. }) = (roughness, b) {
            b = if r < MIN_ROUGHNESS {
                Bsdf::Mirror { tint }
            } else {
                Bsdf::Glossy { tint, alpha: r * r }
            };
        }
        let Some(t) = texel else { return b };
        match b {
            Bsdf::Diffuse { albedo } => Bsdf::Diffuse { albedo: albedo * t },
            Bsdf::Mirror { tint } => Bsdf::Mirror { tint: tint * t },
            Bsdf::Glossy { tint, alpha } => Bsdf::Glossy {
                tint: tint * t,
                alpha,
            },
            glass => glass,
        }
    }
}

impl Material {
    /// Whether the material reads a roughness texture at a hit: it has one and its BSDF is
    /// glossy (`bsdf = "glossy"` with `roughness` ≥ [`MIN_ROUGHNESS`]).
    pub fn reads_roughness(&self) -> bool {
        self.roughness_texture.is_some() && matches!(self.bsdf(), Bsdf::Glossy { .. })
    }

    /// The roughness at a hit whose roughness texture reads `texel`: `roughness` × its green
    /// channel.
    #[inline(always)]
    pub fn roughness_at(&self, texel: Vec3) -> f32 {
        self.roughness * texel.y
    }
}

impl Default for Material {
    fn default() -> Self {
        Material {
            name: "default".into(),
            color: Vec3::ONE,
            ambient: 0.1,
            diffuse: 0.9,
            specular: 0.9,
            shininess: 200.0,
            reflective: 0.0,
            transparency: 0.0,
            refractive_index: 1.0,
            emission: Vec3::ZERO,
            bsdf: None,
            roughness: 0.5,
            texture: None,
            roughness_texture: None,
        }
    }
}

/// One primitive of the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Object {
    /// Geometry.
    pub shape: Shape,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Index into [`Scene::groups`] (a named sphere, plane or triangle, or a whole mesh).
    pub group: u32,
    /// Index into [`Scene::vertex_normals`] of a smooth-shaded triangle's three vertex normals,
    /// or [`NO_NORMALS`] (the geometric normal shades it).
    pub normals: u32,
    /// Index into [`Scene::vertex_uvs`] of a triangle's three texture coordinates, or
    /// [`NO_UVS`] (a texture reads the hit's barycentric u, v, or a sphere's or plane's own).
    pub uvs: u32,
}

/// [`Object::normals`] of an object shaded with its geometric normal.
pub const NO_NORMALS: u32 = u32::MAX;
/// [`Object::uvs`] of an object without vertex texture coordinates.
pub const NO_UVS: u32 = u32::MAX;

/// A named entry of the scene file: one sphere, plane or triangle, or one mesh's triangles.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Group {
    /// Name given in the file, or `sphere 0`, `mesh 1`, … .
    pub name: String,
    /// The first object of the group.
    pub first: u32,
    /// How many objects it holds (1 except for meshes).
    pub count: u32,
}

/// A camera a glTF file names: where it stands and looks, and its vertical field of view.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedCamera {
    /// The camera's name in the file (else its node's, else `camera i`).
    pub name: String,
    /// Eye position.
    pub from: Vec3,
    /// A point it looks at.
    pub at: Vec3,
    /// Its up direction.
    pub up: Vec3,
    /// Vertical field of view, degrees.
    pub fov: f32,
}

/// A validated scene: everything the tracer needs, nothing unchecked.
///
/// Load one from TOML with [`load_file`] or [`load_str`]; a bad scene is an error naming the
/// file, line, column and field, never a panic:
///
/// ```
/// use raystep_core::scene::load_str;
///
/// let text = r#"
/// [camera]
/// from = [0, 0, -5]
/// width = 64
/// height = 48
/// [[sphere]]
/// name = "ball"
/// radius = 1
/// "#;
/// let scene = load_str(text, "ball.toml", None).unwrap();
/// assert_eq!(scene.objects.len(), 1);
/// assert_eq!((scene.camera.width, scene.camera.height), (64, 48));
///
/// let bad = load_str("[[sphere]]\nradius = -1\n", "bad.toml", None).unwrap_err();
/// assert_eq!((bad.file.as_str(), bad.line), ("bad.toml", Some(2)));
/// assert_eq!(bad.field.as_deref(), Some("sphere \"sphere 0\" → radius"));
/// ```
#[derive(Debug, Clone)]
pub struct Scene {
    /// Display name (the file's `title`, else its file name).
    pub name: String,
    /// The file it came from, if any.
    pub path: Option<PathBuf>,
    /// SHA-256 of the scene file's text (hex), so a saved trace can name the scene it came from.
    pub source_hash: String,
    /// The camera.
    pub camera: Camera,
    /// Render settings.
    pub settings: Settings,
    /// Point lights.
    pub lights: Vec<Light>,
    /// Materials (objects refer to them by index).
    pub materials: Vec<Material>,
    /// Every primitive, meshes expanded to triangles.
    pub objects: Vec<Object>,
    /// Named groups of objects.
    pub groups: Vec<Group>,
    /// The unit vertex normals n₀, n₁, n₂ of each smooth-shaded triangle (OBJ `vn`, a mesh's
    /// `shading = "smooth"`, or a triangle's `normals`), indexed by [`Object::normals`].
    pub vertex_normals: Vec<[Vec3; 3]>,
    /// The texture coordinates t₀, t₁, t₂ of each triangle that has them (OBJ `vt`, a
    /// triangle's `uvs`), indexed by [`Object::uvs`].
    pub vertex_uvs: Vec<[[f32; 2]; 3]>,
    /// The textures (`[[texture]]`), indexed by [`Material::texture`].
    pub textures: Vec<Texture>,
    /// What the scene uses.
    pub features: Features,
    /// The cameras of the scene's glTF files, by the files' own names (for `--camera NAME`,
    /// [`Scene::use_camera`]).
    pub cameras: Vec<NamedCamera>,
    /// What loading left out or added, one line each (a glTF file's unread features, a
    /// framed view or a headlight): printed by the commands, shown by the app.
    pub warnings: Vec<String>,
    /// The placed copies of prototypes (`[[instance]]`), traced through the two-level BVH
    /// ([`crate::accel::TwoLevel`]).
    pub instances: Vec<Instance>,
    /// The groups that instances place, each with its object-space box (one BLAS each).
    pub prototypes: Vec<Prototype>,
    /// How many of [`Scene::objects`] lie in the world: the first `world_objects`. The
    /// prototypes' objects follow, in their own object space, reached only through instances.
    pub world_objects: u32,
}

impl Scene {
    /// The readable name of object `id`: the group's name, with `[k]` for a mesh's k-th triangle.
    pub fn object_name(&self, id: u32) -> String {
        let obj = &self.objects[id as usize];
        let g = &self.groups[obj.group as usize];
        if g.count == 1 {
            g.name.clone()
        } else {
            format!("{}[{}]", g.name, id - g.first)
        }
    }
    /// The vertex normals of object `id`, if it is a smooth-shaded triangle.
    #[inline(always)]
    pub fn vertex_normals_of(&self, id: u32) -> Option<&[Vec3; 3]> {
        self.vertex_normals
            .get(self.objects[id as usize].normals as usize)
    }
    /// The texture coordinates of object `id`'s vertices, if it is a triangle that has them.
    #[inline(always)]
    pub fn vertex_uvs_of(&self, id: u32) -> Option<&[[f32; 2]; 3]> {
        self.vertex_uvs.get(self.objects[id as usize].uvs as usize)
    }
    /// The texture of object `id`'s material, if it has one.
    #[inline(always)]
    pub fn texture_of(&self, id: u32) -> Option<&Texture> {
        self.material_of(id)
            .texture
            .and_then(|t| self.textures.get(t as usize))
    }
    /// The material of object `id`.
    #[inline(always)]
    pub fn material_of(&self, id: u32) -> &Material {
        &self.materials[self.objects[id as usize].material as usize]
    }
    /// Looks through the glTF camera called `name` ([`Scene::cameras`]): the camera's position,
    /// aim and field of view change, the image's size does not. An unknown name is an error
    /// listing the known ones.
    pub fn use_camera(&mut self, name: &str) -> Result<(), String> {
        let Some(c) = self.cameras.iter().find(|c| c.name == name) else {
            let known: Vec<String> = self
                .cameras
                .iter()
                .map(|c| format!("\"{}\"", c.name))
                .collect();
            return Err(format!(
                "the scene has no camera named \"{name}\" ({})",
                if known.is_empty() {
                    "it names none: cameras come from its glTF files".to_string()
                } else {
                    format!("known: {}", known.join(", "))
                }
            ));
        };
        self.camera.from = c.from;
        self.camera.at = c.at;
        self.camera.up = c.up;
        self.camera.fov = c.fov;
        Ok(())
    }
    /// The world's own objects (not the prototypes').
    #[inline(always)]
    pub fn world(&self) -> &[Object] {
        self.objects
            .get(..self.world_objects as usize)
            .unwrap_or(&self.objects)
    }
    /// Every object as it stands in the world, for drawing: the world's own objects (with their
    /// ids), then each instance's copies of its prototype's objects (with the prototype
    /// object's id), carried by the instance's matrix ([`Instance::place`]).
    pub fn placed(&self) -> impl Iterator<Item = (u32, Object)> + '_ {
        self.placed_by().map(|(id, _, o)| (id, o))
    }
    /// [`Scene::placed`], with the instance that places each copy (None for the world's own
    /// objects): a view that draws a sphere under a non-uniform scale as the ellipsoid it is
    /// needs the matrix.
    pub fn placed_by(&self) -> impl Iterator<Item = (u32, Option<&Instance>, Object)> + '_ {
        let world = self
            .world()
            .iter()
            .enumerate()
            .map(|(id, o)| (id as u32, None, *o));
        let copies = self.instances.iter().flat_map(move |inst| {
            let g = &self.groups[inst.group as usize];
            (g.first..g.first + g.count).filter_map(move |id| {
                let o = self.objects.get(id as usize)?;
                Some((
                    id,
                    Some(inst),
                    Object {
                        shape: inst.place(&o.shape),
                        ..*o
                    },
                ))
            })
        });
        world.chain(copies)
    }
    /// The instance a hit lies on, if it lies on one.
    #[inline(always)]
    pub fn instance_of(&self, hit: &crate::accel::Hit) -> Option<&Instance> {
        self.instances.get(hit.instance as usize)
    }
    /// The readable name of what a hit lies on: [`Scene::object_name`], after the instance's
    /// name and an arrow for an instanced object (`tree 3 → trunk[12]`).
    pub fn hit_name(&self, hit: &crate::accel::Hit) -> String {
        match self.instance_of(hit) {
            Some(i) => format!("{} → {}", i.name, self.object_name(hit.object)),
            None => self.object_name(hit.object),
        }
    }
    /// Finds the objects of the group called `name`.
    pub fn find_group(&self, name: &str) -> Option<&Group> {
        self.groups.iter().find(|g| g.name == name)
    }
}
