//! The CPU–GPU interface, defined once: every number the WGSL and the Rust must agree on — the
//! trace log's record tags and header, the ray kinds, the Monte Carlo buffer's header words and
//! record sizes, the BSDF, light, integrator and strategy codes, the random numbers' dimension
//! layout and slots, and the limits both sides size their arrays by. [`wgsl`] writes them as WGSL
//! `const`s at the top of every generated shader, so no `.wgsl` piece spells one out; the Rust
//! that writes the buffers and reads the log uses the same items. A unit test parses every
//! shader variant with naga (no GPU needed), so a piece that uses a name no longer generated
//! fails to build its shader there.

use crate::trace::monte_carlo;

/// Defines a module of named `u32` codes and the list of them ([`wgsl`] writes each as
/// `const {prefix}{NAME}: u32`).
macro_rules! codes {
    ($(#[$doc:meta])* pub mod $m:ident ($prefix:literal) { $($(#[$d:meta])* $name:ident = $v:expr),* $(,)? }) => {
        $(#[$doc])*
        pub mod $m {
            $($(#[$d])* pub const $name: u32 = $v;)*
            /// Every code with its WGSL name.
            pub const ALL: &[(&str, u32)] = &[$((concat!($prefix, stringify!($name)), $v)),*];
        }
    };
}

codes! {
    /// The trace log's record tags: a record's header word is `tag << 16 | payload words`
    /// (`wgsl/trace_log.wgsl` writes them, `trace_log.rs` reads them).
    pub mod tag ("EV_") {
        /// A ray begins.
        RAY = 1,
        /// The camera's sample.
        CAMERA = 2,
        /// A BVH node visited.
        NODE = 3,
        /// An intersection test.
        TEST = 4,
        /// A test's hit accepted as the closest so far.
        ACCEPT = 5,
        /// Nothing hit.
        MISS = 6,
        /// The surface interaction.
        SURFACE = 7,
        /// A shadow ray.
        SHADOW_RAY = 8,
        /// A light's Phong terms.
        LIGHT = 9,
        /// The mirror direction.
        REFLECT = 10,
        /// Snell's law.
        REFRACT = 11,
        /// Schlick's reflectance.
        SCHLICK = 12,
        /// The recursion's depth limit reached.
        DEPTH_LIMIT = 13,
        /// A ray below the weight cut-off.
        CUTOFF = 14,
        /// A child ray's origin.
        SPAWN = 15,
        /// A ray's colour.
        COLOR = 16,
        /// A ray ends.
        END = 17,
        /// The pixel's colour.
        PIXEL = 18,
        /// A hardware ray query's traversal.
        HARDWARE = 19,
        /// The thin lens.
        LENS = 20,
        /// Emission found by a ray.
        EMITTED = 21,
        /// A light sample.
        LIGHT_SAMPLE = 22,
        /// A BSDF sample.
        BSDF_SAMPLE = 23,
        /// Russian roulette.
        ROULETTE = 24,
        /// A pixel sample's summary.
        SAMPLE = 25,
        /// Smooth shading's interpolated normal.
        SHADING_NORMAL = 26,
        /// A texture read at the hit.
        TEXTURE = 27,
        /// A trilinear texture's level of detail and second mip level (before its `TEXTURE`).
        TEXTURE_LOD = 28,
        /// The roughness a glossy BSDF's roughness texture gives (before that texture's
        /// `TEXTURE`).
        ROUGHNESS = 29,
        /// A node of the top-level BVH (over the instances).
        TLAS_NODE = 30,
        /// The ray carried into an instance's object space.
        INSTANCE = 31,
        /// A hit on an instance carried back to the world.
        INSTANCE_HIT = 32,
    }
}

codes! {
    /// A texture's kind, filter and wrap mode, and how a hit's texture coordinates were found
    /// (`scene::TextureKind`, `scene::Filter`, `scene::Wrap`, `record::texturing::UvMapping`).
    pub mod texture ("") {
        /// A checker.
        TEX_CHECKER = 0,
        /// An image.
        TEX_IMAGE = 1,
        /// The nearest texel.
        FILTER_NEAREST = 0,
        /// Bilinear.
        FILTER_BILINEAR = 1,
        /// Trilinear (mip-mapped, the level from the ray cone).
        FILTER_TRILINEAR = 2,
        /// Repeat.
        WRAP_REPEAT = 0,
        /// Clamp.
        WRAP_CLAMP = 1,
        /// Mirror.
        WRAP_MIRROR = 2,
        /// A triangle's vertex texture coordinates.
        UV_VERTEX_UVS = 0,
        /// A triangle's barycentrics.
        UV_BARYCENTRIC = 1,
        /// A sphere's longitude and latitude.
        UV_SPHERE = 2,
        /// A plane's coordinates.
        UV_PLANE = 3,
    }
}

codes! {
    /// A ray's kind in the trace log (`record::RayKind`).
    pub mod ray_kind ("KIND_") {
        /// From the camera.
        PRIMARY = 0,
        /// Towards a light.
        SHADOW = 1,
        /// Whitted's mirror ray.
        REFLECTION = 2,
        /// Whitted's refraction ray.
        REFRACTION = 3,
        /// A Monte Carlo bounce off a diffuse or delta BSDF.
        DIFFUSE = 4,
        /// A Monte Carlo bounce off a glossy BSDF.
        GLOSSY = 5,
    }
}

codes! {
    /// The Monte Carlo buffer's header, word by word (`buffers::mc_data` writes it; the WGSL reads
    /// `mc[MC_H_…]`).
    pub mod mc_header ("MC_H_") {
        /// The integrator ([`super::integrator`]).
        INTEGRATOR = 0,
        /// The direct-light strategy ([`super::strategy`]).
        STRATEGY = 1,
        /// 1 for stratified 2D samples.
        STRATIFIED = 2,
        /// Russian roulette's first bounce.
        RR_DEPTH = 3,
        /// The number of lights.
        N_LIGHTS = 4,
        /// The number of light groups.
        N_GROUPS = 5,
        /// Where the materials start.
        OFF_MATERIALS = 6,
        /// Where the lights start.
        OFF_LIGHTS = 7,
        /// Where the lights' running sum of powers starts.
        OFF_CDF = 8,
        /// Where each object's light index starts.
        OFF_BY_OBJECT = 9,
        /// Where the groups' (offset, count) pairs start.
        OFF_GROUPS = 10,
        /// Where the groups' members start.
        OFF_MEMBERS = 11,
        /// Where the groups' running sums of areas start.
        OFF_GROUP_CDF = 12,
        /// The lens's aperture (f32 bits).
        APERTURE = 13,
        /// The focus distance (f32 bits).
        FOCUS_DISTANCE = 14,
        /// The glossy BSDF's least roughness, `scene::MIN_ROUGHNESS` (f32 bits): a roughness
        /// texture's read below it makes a mirror.
        MIN_ROUGHNESS = 15,
        /// Words in the header.
        WORDS = 16,
        /// Words per material: kind, colour, parameter, emission, roughness.
        MATERIAL_WORDS = 9,
        /// Words per light.
        LIGHT_WORDS = 20,
    }
}

codes! {
    /// A material's Monte Carlo BSDF (`scene::Bsdf`).
    pub mod bsdf ("BSDF_") {
        /// Lambert.
        DIFFUSE = 0,
        /// A perfect mirror.
        MIRROR = 1,
        /// A smooth dielectric.
        GLASS = 2,
        /// GGX.
        GLOSSY = 3,
    }
}

codes! {
    /// A light's shape (`record::samples::LightShape`).
    pub mod light ("LIGHT_") {
        /// An emitting triangle.
        TRIANGLE = 0,
        /// An emitting sphere.
        SPHERE = 1,
        /// A point light.
        POINT = 2,
    }
}

codes! {
    /// The integrator (`scene::Integrator`).
    pub mod integrator ("MC_INTEGRATOR_") {
        /// Whitted.
        WHITTED = 0,
        /// Distribution ray tracing.
        DISTRIBUTION = 1,
        /// Path tracing.
        PATH = 2,
    }
}

codes! {
    /// The direct-light strategy (`scene::Strategy`).
    pub mod strategy ("STRATEGY_") {
        /// Multiple importance sampling.
        MIS = 0,
        /// Light sampling alone.
        LIGHT = 1,
        /// BSDF sampling alone.
        BSDF = 2,
    }
}

/// Words of the trace log before its first record: the words written, the ran-out flag, two
/// spare.
pub const LOG_HEADER: u32 = 4;
/// No trace-log record is longer than this (the longest, a texture lookup, has 47 words).
pub const LOG_RECORD_MAX: u32 = 64;
/// "No object" wherever an object index is stored.
pub const NO_OBJECT: u32 = u32::MAX;
/// A material's `texture` (or `roughness_texture`) word when it has none.
pub const NO_TEXTURE: u32 = u32::MAX;

/// The shared `u32` constants besides the code lists: (WGSL name, value).
fn scalars() -> Vec<(&'static str, u32)> {
    vec![
        ("LOG_HEADER", LOG_HEADER),
        ("LOG_RECORD_MAX", LOG_RECORD_MAX),
        ("NO_OBJECT", NO_OBJECT),
        ("NO_INSTANCE", crate::scene::NO_INSTANCE),
        ("NO_NORMALS", crate::scene::NO_NORMALS),
        ("NO_UVS", crate::scene::NO_UVS),
        ("NO_TEXTURE", NO_TEXTURE),
        (
            "MAX_PIXEL_SAMPLES",
            crate::record::samples::MAX_PIXEL_SAMPLES as u32,
        ),
        ("MAX_MEDIA", crate::trace::media::MAX_MEDIA as u32),
        ("LENS_DIMENSION", monte_carlo::LENS_DIMENSION),
        (
            "DIMENSION_FIRST_BOUNCE",
            monte_carlo::FIRST_BOUNCE_DIMENSION,
        ),
        ("DIMENSIONS_PER_BOUNCE", monte_carlo::DIMENSIONS_PER_BOUNCE),
    ]
}

/// Every shared constant as a WGSL `const`, one a line: what each generated shader starts with.
pub fn wgsl() -> String {
    let mut out = String::from(
        "// ---- the CPU-GPU interface (crates/raystep-gpu/src/interface.rs, generated) ----\n",
    );
    let lists = [
        tag::ALL,
        ray_kind::ALL,
        mc_header::ALL,
        bsdf::ALL,
        light::ALL,
        integrator::ALL,
        strategy::ALL,
        texture::ALL,
        monte_carlo::slot::ALL,
    ];
    for (name, v) in lists
        .iter()
        .flat_map(|l| l.iter())
        .copied()
        .chain(scalars())
    {
        out += &format!("const {name}: u32 = {v}u;\n");
    }
    out.push('\n');
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shader::{self, ShaderConfig};

    #[test]
    fn every_name_is_defined_once_and_no_piece_defines_one_itself() {
        let text = wgsl();
        let names: Vec<&str> = text
            .lines()
            .filter_map(|l| l.strip_prefix("const "))
            .map(|l| l.split(':').next().unwrap())
            .collect();
        let mut sorted = names.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), names.len(), "a name twice: {names:?}");
        for (piece, source) in shader::pieces::ALL {
            for name in &names {
                assert!(
                    !source.contains(&format!("const {name}:"))
                        && !source.contains(&format!("var<private> {name}:")),
                    "{piece} defines {name}, which interface.rs generates"
                );
            }
        }
    }

    #[test]
    fn every_shader_variant_parses_and_validates_with_naga() {
        let prepared = crate::trace::PreparedScene::new(crate::scene::default_scene());
        let base = ShaderConfig::for_scene(&prepared);
        let mut checked = 0;
        // Every combination of the features a scene switches on (instances too), then the Monte Carlo, trace,
        // ray-query, terminator-fix and texture shaders with every feature (smooth shading included).
        for bits in 0u32..256 {
            let b = |k: u32| bits & (1 << k) != 0;
            let c = ShaderConfig {
                instances: b(7),
                spheres: b(0),
                planes: b(1),
                triangles: b(2),
                shadows: b(3),
                reflection: b(4),
                refraction: b(5),
                bvh: b(6),
                brute: !b(6),
                full: false,
                ..base
            };
            let wgsl = shader::wgsl(&c);
            shader::validate(&wgsl).unwrap_or_else(|e| panic!("{c:?}:\n{e}"));
            checked += 1;
        }
        let full = ShaderConfig::full(&prepared);
        for bits in 0u32..32 {
            let b = |k: u32| bits & (1 << k) != 0;
            let mut c = ShaderConfig {
                monte_carlo: b(0),
                trace: b(1),
                hanika: b(3),
                textures: b(4),
                ..full
            };
            if b(2) {
                c = c.with_ray_query();
            }
            let wgsl = shader::wgsl(&c);
            assert!(wgsl.contains("const EV_SAMPLE: u32 = 25u;"));
            shader::validate(&wgsl).unwrap_or_else(|e| panic!("{c:?}:\n{e}"));
            checked += 1;
        }
        // A generated Monte Carlo shader has one integrator: each alone, rendering and tracing.
        for (path, distribution) in [(true, false), (false, true)] {
            for trace in [false, true] {
                let c = ShaderConfig {
                    monte_carlo: true,
                    path,
                    distribution,
                    trace,
                    ..full
                };
                let wgsl = shader::wgsl(&c);
                assert!(!wgsl.contains("mc_integrator() == MC_INTEGRATOR_PATH"));
                shader::validate(&wgsl).unwrap_or_else(|e| panic!("{c:?}:\n{e}"));
                checked += 1;
            }
        }
        assert_eq!(checked, 292);
    }
}
