//! The WGSL generator: the tracer's shader assembled from the pieces in `crates/raystep-gpu/src/wgsl/`, keeping
//! only what the scene needs (docs/ARCHITECTURE.md, invariant 4).
//!
//! Each piece is a WGSL file named after the stage of a hardware ray-tracing pipeline it plays
//! (ray generation, traversal, intersection, any-hit, closest-hit, miss). Whole pieces are left
//! out when a scene does not need them (no sphere kernel without spheres, no BVH traversal for a
//! brute-force scene, no media stack without glass), and inside pieces `//#if NAME` … `//#else` …
//! `//#endif` lines keep or drop smaller blocks (the shadow-ray loop, the reflection and
//! refraction spawns). The "full" variant switches everything on, the way a single shader for
//! every scene would be written, and is what the generated one is measured against.

use super::exact::{ArithConfig, arith_wgsl};
use crate::accel::Bvh;
use crate::math::gamma;
use crate::scene::{Integrator, OffsetPolicy, Scene};
use crate::shapes::{SphereMethod, TriangleMethod};
use crate::trace::PreparedScene;

/// The deepest BVH the GPU traversal's stack may be sized for (raystep's trees for a million
/// triangles are about 30 levels deep; [`super::GpuTracer::new`] refuses deeper ones).
pub const MAX_BVH_STACK: u32 = 64;

/// What goes into a tracer shader.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShaderConfig {
    /// Sphere intersection code.
    pub spheres: bool,
    /// Plane intersection code (general and axis-aligned).
    pub planes: bool,
    /// Triangle intersection code.
    pub triangles: bool,
    /// Smooth shading: a triangle's vertex normals interpolated at the hit (the scene has
    /// smooth triangles).
    pub smooth: bool,
    /// Hanika's terminator fix on smooth triangles (`[render] terminator = "hanika"`).
    pub hanika: bool,
    /// Textures (`wgsl/texture.wgsl`): some object's material has one.
    pub textures: bool,
    /// BVH traversal.
    pub bvh: bool,
    /// The brute-force loop.
    pub brute: bool,
    /// Instances (`wgsl/traversal_instances.wgsl`): the TLAS walk after the world's objects, each
    /// entered instance's BLAS walked in its object space (the scene has `[[instance]]`s).
    pub instances: bool,
    /// Hardware ray queries instead of `bvh` and `brute` (only on a device with
    /// `EXPERIMENTAL_RAY_QUERY`; the tracer sets it).
    pub ray_query: bool,
    /// Lights: the shadow-ray loop and Phong.
    pub shadows: bool,
    /// Reflection rays.
    pub reflection: bool,
    /// Refraction rays, Snell, Schlick and the media stack.
    pub refraction: bool,
    /// Every feature on, chosen at run time (lights, accelerator).
    pub full: bool,
    /// The scene's ray–sphere method.
    pub sphere_method: SphereMethod,
    /// The scene's ray–triangle method.
    pub triangle_method: TriangleMethod,
    /// The scene's offset policy for spawned rays.
    pub offset: OffsetPolicy,
    /// The recursion limit (sizes the ray stack).
    pub max_depth: u32,
    /// Entries of the BVH traversal stack: the tree's depth + 2. Sized per scene because a
    /// software rasterizer (lavapipe) pays for every entry of a dynamically indexed array.
    /// With instances: the deepest of the world's tree and the prototypes' BLAS.
    pub bvh_stack: u32,
    /// Entries of the TLAS walk's stack: the TLAS's depth + 2 (see [`ShaderConfig::two_level`]).
    pub tlas_stack: u32,
    /// The arithmetic variant (division, square root, fma), decided per device by the probe
    /// ([`super::exact`]); the default (plain operations, emulated fma) until a tracer sets it.
    pub arith: ArithConfig,
    /// The Monte Carlo integrators (the scene's `[render] integrator` is `distribution` or
    /// `path`): each sample is traced by `wgsl/mc_integrator.wgsl` with the CPU's random numbers
    /// ([`super::buffers`] uploads the lights and BSDFs; `path` and `distribution` say which
    /// integrators are compiled in).
    pub monte_carlo: bool,
    /// The path tracer (`wgsl/mc_integrator.wgsl`'s `mc_path`) is compiled in. A generated
    /// shader has only the scene's integrator: a shader compiler inlines the whole integrator
    /// at its call, so the other one doubled what lavapipe compiles. The full shader has both,
    /// chosen at run time.
    pub path: bool,
    /// The distribution tracer (`mc_distribution`) is compiled in (see `path`).
    pub distribution: bool,
    /// The trace shader: one invocation logs every step it takes (`raystep trace --gpu`,
    /// [`super::trace_log`]). The shaders that render have it off.
    pub trace: bool,
}

/// Which shader a [`super::GpuTracer`] runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum ShaderVariant {
    /// Generated for the scene's features.
    #[default]
    Generated,
    /// Every feature compiled in.
    Full,
}

impl ShaderConfig {
    /// The shader a prepared scene needs (its BVH, when it uses one, sets the stack depth).
    pub fn for_scene(prepared: &PreparedScene) -> ShaderConfig {
        let c = ShaderConfig::for_scene_with(prepared.scene(), prepared.bvh());
        match prepared.accel() {
            crate::accel::SceneAccel::TwoLevel(t) => c.two_level(t),
            _ => c,
        }
    }

    /// This config with the stacks sized for a two-level structure's trees: the TLAS's, and the
    /// BVH walk's for the deepest BLAS (or the world's tree, if deeper).
    pub fn two_level(self, t: &crate::accel::TwoLevel) -> ShaderConfig {
        let blas = t
            .blas
            .iter()
            .map(|b| b.max_depth as u32 + 2)
            .max()
            .unwrap_or(2);
        ShaderConfig {
            bvh_stack: self.bvh_stack.max(blas),
            tlas_stack: tree_depth(&t.tlas.nodes) + 2,
            ..self
        }
    }

    /// The shader a scene needs, given the BVH already built for it (None: brute force).
    pub fn for_scene_with(scene: &Scene, tree: Option<&Bvh>) -> ShaderConfig {
        let f = &scene.features;
        let bvh = tree.is_some();
        let s = &scene.settings;
        let monte_carlo = s.integrator.is_monte_carlo();
        ShaderConfig {
            spheres: f.spheres > 0,
            planes: f.planes > 0,
            triangles: f.triangles > 0,
            smooth: f.smooth > 0,
            hanika: f.smooth > 0 && s.terminator == crate::scene::Terminator::Hanika,
            textures: f.textured > 0,
            bvh,
            brute: !bvh,
            instances: !scene.instances.is_empty(),
            ray_query: false,
            // The Monte Carlo integrators cast shadow rays to area lights too.
            shadows: f.lights > 0 || monte_carlo,
            reflection: f.reflective,
            refraction: f.transparent,
            full: false,
            sphere_method: s.sphere_method,
            triangle_method: s.triangle_method,
            offset: s.offset,
            max_depth: s.max_depth,
            bvh_stack: tree.map_or(2, |t| t.max_depth as u32 + 2),
            tlas_stack: 2,
            arith: ArithConfig::default(),
            monte_carlo,
            path: s.integrator == Integrator::Path,
            distribution: s.integrator == Integrator::Distribution,
            trace: false,
        }
    }

    /// Every feature on (the scene's methods and recursion limit are kept: they are settings,
    /// not features).
    pub fn full(prepared: &PreparedScene) -> ShaderConfig {
        ShaderConfig::for_scene(prepared).all_on()
    }

    /// This config with every feature switched on (the traversal stays as chosen when it is
    /// hardware ray queries).
    pub fn all_on(self) -> ShaderConfig {
        ShaderConfig {
            spheres: true,
            planes: true,
            triangles: true,
            smooth: true,
            textures: true,
            bvh: !self.ray_query,
            brute: !self.ray_query,
            instances: true,
            shadows: true,
            reflection: true,
            refraction: true,
            full: true,
            path: true,
            distribution: true,
            ..self
        }
    }

    /// This config tracing with hardware ray queries instead of the WGSL traversal.
    pub fn with_ray_query(self) -> ShaderConfig {
        ShaderConfig {
            ray_query: true,
            bvh: false,
            brute: false,
            ..self
        }
    }

    /// The config of a variant, given the scene's BVH (None: brute force).
    pub fn variant(scene: &Scene, tree: Option<&Bvh>, variant: ShaderVariant) -> ShaderConfig {
        let c = ShaderConfig::for_scene_with(scene, tree);
        match variant {
            ShaderVariant::Generated => c,
            ShaderVariant::Full => c.all_on(),
        }
    }

    fn flag(&self, name: &str) -> Option<bool> {
        Some(match name {
            "SPHERES" => self.spheres,
            "PLANES" => self.planes,
            "TRIANGLES" => self.triangles,
            "SMOOTH" => self.smooth,
            "HANIKA" => self.hanika,
            "TEXTURES" => self.textures,
            "BVH" => self.bvh,
            "BRUTE" => self.brute,
            "INSTANCES" => self.instances,
            "TLAS_WALK" => self.instances && !self.ray_query,
            "SHADOWS" => self.shadows,
            "REFLECTION" => self.reflection,
            "REFRACTION" => self.refraction,
            "FULL" => self.full,
            "RAY_QUERY" => self.ray_query,
            "TRACE" => self.trace,
            "MC" => self.monte_carlo,
            "PATH" => self.path,
            "DISTRIBUTION" => self.distribution,
            _ => return None,
        })
    }

    /// Whether spawned rays exist (and so the offset policy's code).
    fn spawns(&self) -> bool {
        self.shadows || self.reflection || self.refraction
    }
}

/// The pieces, by file.
pub(crate) mod pieces {
    pub const COMMON: &str = include_str!("wgsl/common.wgsl");
    pub const TRACE_LOG: &str = include_str!("wgsl/trace_log.wgsl");
    pub const MEDIA: &str = include_str!("wgsl/media.wgsl");
    pub const SPHERE_ROOT: &str = include_str!("wgsl/sphere_root.wgsl");
    pub const SPHERE_STABLE: &str = include_str!("wgsl/sphere_stable.wgsl");
    pub const SPHERE_TEXTBOOK: &str = include_str!("wgsl/sphere_textbook.wgsl");
    pub const PLANE: &str = include_str!("wgsl/plane.wgsl");
    pub const TRIANGLE_MT: &str = include_str!("wgsl/triangle_mt.wgsl");
    pub const TRIANGLE_WATERTIGHT: &str = include_str!("wgsl/triangle_watertight.wgsl");
    pub const ANY_HIT: &str = include_str!("wgsl/any_hit.wgsl");
    pub const TRAVERSAL_BRUTE: &str = include_str!("wgsl/traversal_brute.wgsl");
    pub const TRAVERSAL_PLANES: &str = include_str!("wgsl/traversal_planes.wgsl");
    pub const TRAVERSAL_BVH: &str = include_str!("wgsl/traversal_bvh.wgsl");
    pub const TRAVERSAL_RAY_QUERY: &str = include_str!("wgsl/traversal_ray_query.wgsl");
    pub const TRAVERSAL_INSTANCES: &str = include_str!("wgsl/traversal_instances.wgsl");
    pub const MISS: &str = include_str!("wgsl/miss.wgsl");
    pub const INTERACTION: &str = include_str!("wgsl/interaction.wgsl");
    pub const OFFSET_NONE: &str = include_str!("wgsl/offset_none.wgsl");
    pub const OFFSET_FIXED: &str = include_str!("wgsl/offset_fixed.wgsl");
    pub const OFFSET_ROBUST: &str = include_str!("wgsl/offset_robust.wgsl");
    pub const TEXTURE: &str = include_str!("wgsl/texture.wgsl");
    pub const ATAN: &str = raystep_core::portable::ATAN_WGSL;
    pub const CLOSEST_HIT: &str = include_str!("wgsl/closest_hit.wgsl");
    pub const RAYGEN: &str = include_str!("wgsl/raygen.wgsl");
    pub const DISPLAY: &str = include_str!("wgsl/display.wgsl");
    pub const PORTABLE: &str = raystep_core::portable::MATH_WGSL;
    pub const RANDOM: &str = raystep_core::portable::RANDOM_WGSL;
    pub const MC_SAMPLE: &str = include_str!("wgsl/mc_sample.wgsl");
    pub const MC_INTEGRATOR: &str = include_str!("wgsl/mc_integrator.wgsl");
    pub const MC_TRACE_LOG: &str = include_str!("wgsl/mc_trace_log.wgsl");

    /// Every piece with its file's name.
    #[cfg(test)]
    pub const ALL: &[(&str, &str)] = &[
        ("common.wgsl", COMMON),
        ("trace_log.wgsl", TRACE_LOG),
        ("media.wgsl", MEDIA),
        ("sphere_root.wgsl", SPHERE_ROOT),
        ("sphere_stable.wgsl", SPHERE_STABLE),
        ("sphere_textbook.wgsl", SPHERE_TEXTBOOK),
        ("plane.wgsl", PLANE),
        ("triangle_mt.wgsl", TRIANGLE_MT),
        ("triangle_watertight.wgsl", TRIANGLE_WATERTIGHT),
        ("any_hit.wgsl", ANY_HIT),
        ("traversal_brute.wgsl", TRAVERSAL_BRUTE),
        ("traversal_planes.wgsl", TRAVERSAL_PLANES),
        ("traversal_bvh.wgsl", TRAVERSAL_BVH),
        ("traversal_ray_query.wgsl", TRAVERSAL_RAY_QUERY),
        ("traversal_instances.wgsl", TRAVERSAL_INSTANCES),
        ("miss.wgsl", MISS),
        ("interaction.wgsl", INTERACTION),
        ("offset_none.wgsl", OFFSET_NONE),
        ("offset_fixed.wgsl", OFFSET_FIXED),
        ("offset_robust.wgsl", OFFSET_ROBUST),
        ("texture.wgsl", TEXTURE),
        ("portable/atan.wgsl", ATAN),
        ("closest_hit.wgsl", CLOSEST_HIT),
        ("raygen.wgsl", RAYGEN),
        ("display.wgsl", DISPLAY),
        ("portable/math.wgsl", PORTABLE),
        ("portable/random.wgsl", RANDOM),
        ("mc_sample.wgsl", MC_SAMPLE),
        ("mc_integrator.wgsl", MC_INTEGRATOR),
        ("mc_trace_log.wgsl", MC_TRACE_LOG),
    ];
}

/// The small shader that encodes the linear image as sRGB into the app's `Rgba8Unorm` texture.
pub const DISPLAY_WGSL: &str = pieces::DISPLAY;

/// The portable `sin`/`cos`/`exp`/`ln` in WGSL (`p_sin_cos`, `p_exp`, `p_ln`): the twin of
/// [`crate::portable::math`], the same f32 steps, so the exact compute path returns its bits.
pub const PORTABLE_WGSL: &str = pieces::PORTABLE;

/// The Monte Carlo sampling routines in WGSL (`crates/raystep-gpu/src/wgsl/mc_sample.wgsl`, after
/// [`RANDOM_WGSL`], [`PORTABLE_WGSL`] and [`crate::exact::arith_wgsl`]): the twins of
/// [`crate::mc::sample`], [`crate::portable::random::uniform`], the stratified pairs and the power
/// heuristic of [`crate::trace::monte_carlo`], and the exact Fresnel reflectance, step for step.
pub const MC_SAMPLE_WGSL: &str = pieces::MC_SAMPLE;

/// `pcg_hash`, `unit_float` and `mc_uniform` (crates/raystep-core/src/portable/random.rs `uniform`) in WGSL.
pub const RANDOM_WGSL: &str = pieces::RANDOM;

/// The tracer shader generated for a scene's features.
pub fn generated_wgsl(prepared: &PreparedScene) -> String {
    wgsl(&ShaderConfig::for_scene(prepared))
}

/// The tracer shader with every feature compiled in.
pub fn full_wgsl(prepared: &PreparedScene) -> String {
    wgsl(&ShaderConfig::full(prepared))
}

/// Assembles the shader for `config`.
pub fn wgsl(config: &ShaderConfig) -> String {
    let mut out = String::new();
    if config.ray_query {
        // An enable directive must come before every declaration.
        out += "enable wgpu_ray_query;\n\n";
    }
    let on = |b: bool| if b { "yes" } else { "no" };
    out += &format!(
        "// raystep GPU tracer, {} shader.\n// spheres: {}, planes: {}, triangles: {}, accelerator: {}, \
         shadows: {}, reflection: {}, refraction: {}, textures: {}, monte carlo: {}\n// sphere method: {:?}, triangle method: {:?}, offset: {:?}\n\n",
        if config.full {
            "full (every feature)"
        } else {
            "generated"
        },
        on(config.spheres),
        on(config.planes),
        on(config.triangles),
        match (config.ray_query, config.bvh, config.brute) {
            (true, _, _) => "hardware ray queries",
            (_, true, true) => "BVH or brute force (chosen at run time)",
            (_, true, false) => "BVH",
            _ => "brute force",
        },
        on(config.shadows),
        on(config.reflection),
        on(config.refraction),
        on(config.textures),
        on(config.monte_carlo),
        config.sphere_method,
        config.triangle_method,
        config.offset,
    );
    // Constants computed exactly as the CPU computes them, written in Rust's shortest
    // round-trip form.
    let constants: [(&str, f32); 8] = [
        ("GAMMA1", gamma::<f32>(1)),
        ("GAMMA2", gamma::<f32>(2)),
        ("GAMMA3", gamma::<f32>(3)),
        ("GAMMA5", gamma::<f32>(5)),
        ("GAMMA7", gamma::<f32>(7)),
        ("BOX_ENLARGE", 1.0 + 2.0 * gamma::<f32>(3)),
        ("SHADOW_T_MAX", 1.0 - crate::trace::tracer::SHADOW_EPSILON),
        ("WEIGHT_CUTOFF", crate::trace::tracer::WEIGHT_CUTOFF),
    ];
    for (name, v) in constants {
        out += &format!("const {name}: f32 = {v:?};\n");
    }
    out += &format!(
        "const RAY_STACK: u32 = {}u;\nconst BVH_STACK: u32 = {}u;\nconst TLAS_STACK: u32 = {}u;\n\n",
        config.max_depth + 2,
        config.bvh_stack.clamp(2, MAX_BVH_STACK),
        config.tlas_stack.clamp(2, MAX_BVH_STACK)
    );
    out += &crate::interface::wgsl();
    out += &arith_wgsl(config.arith);
    let mut add = |piece: &str| {
        out += &preprocess(piece, config);
        out.push('\n');
    };
    add(pieces::COMMON);
    if config.trace {
        add(pieces::TRACE_LOG);
    }
    if config.refraction {
        add(pieces::MEDIA);
    }
    if config.spheres {
        add(pieces::SPHERE_ROOT);
        add(match config.sphere_method {
            SphereMethod::Stable => pieces::SPHERE_STABLE,
            SphereMethod::Textbook => pieces::SPHERE_TEXTBOOK,
        });
    }
    if config.planes {
        add(pieces::PLANE);
    }
    if config.triangles {
        add(match config.triangle_method {
            TriangleMethod::Watertight => pieces::TRIANGLE_WATERTIGHT,
            TriangleMethod::MollerTrumbore => pieces::TRIANGLE_MT,
        });
    }
    add(&intersection_dispatch(config));
    add(pieces::ANY_HIT);
    if config.brute {
        add(pieces::TRAVERSAL_BRUTE);
    }
    // The compute path walks each instance's BLAS with the BVH walk, whatever the world's
    // accelerator.
    let blas_walk = config.instances && !config.ray_query;
    if config.bvh || config.ray_query || blas_walk {
        add(pieces::TRAVERSAL_PLANES);
    }
    if config.bvh || blas_walk {
        add(pieces::TRAVERSAL_BVH);
    }
    if config.instances {
        add(pieces::TRAVERSAL_INSTANCES);
    }
    if config.ray_query {
        add(pieces::TRAVERSAL_RAY_QUERY);
    }
    add(&traversal_dispatch(config));
    add(pieces::MISS);
    add(pieces::INTERACTION);
    if config.spawns() || config.trace {
        add(match config.offset {
            OffsetPolicy::None => pieces::OFFSET_NONE,
            OffsetPolicy::Fixed => pieces::OFFSET_FIXED,
            OffsetPolicy::Robust => pieces::OFFSET_ROBUST,
        });
    }
    // The portable ln: a trilinear texture's level of detail, and the Monte Carlo sampling.
    if config.textures || config.monte_carlo {
        add(pieces::PORTABLE);
    }
    if config.textures {
        add(pieces::ATAN);
        add(pieces::TEXTURE);
    }
    add(pieces::CLOSEST_HIT);
    add(pieces::RANDOM);
    if config.monte_carlo {
        add(pieces::MC_SAMPLE);
        add(pieces::MC_INTEGRATOR);
        if config.trace {
            add(pieces::MC_TRACE_LOG);
        }
    }
    add(pieces::RAYGEN);
    out
}

/// `intersection(id, ray)`: the switch over the primitive kinds the shader has. In the trace
/// shader the switch is `kernel(id, ray)`, and `intersection` logs each test with the
/// intermediates its kernel left in `scratch`.
fn intersection_dispatch(c: &ShaderConfig) -> String {
    let mut s = String::from("// ---- intersection: the kernel for the object's kind ----\n\n");
    if c.trace {
        s += "fn intersection(id: u32, r: Ray) -> Cand {\n    scratch_clear();\n    \
              let c = kernel(id, r);\n    log_open();\n    log_u(id);\n    log_u(objects[id].kind);\n    \
              log_f(r.t_min);\n    log_f(r.t_max);\n    log_b(c.hit);\n    log_f(c.t);\n    \
              log_f(c.u);\n    log_f(c.v);\n    for (var i = 0u; i < 32u; i++) {\n        \
              log_f(scratch[i]);\n    }\n    log_close(EV_TEST);\n    return c;\n}\n\n";
    }
    s += if c.trace {
        "fn kernel"
    } else {
        "fn intersection"
    };
    s += "(id: u32, r: Ray) -> Cand {\n    let o = objects[id];\n    switch o.kind {\n";
    if c.spheres {
        s += "        case 0u: { return intersect_sphere(r, o.a.xyz, o.a.w); }\n";
    }
    if c.planes {
        s += "        case 1u: { return intersect_plane(r, o.a.xyz, o.a.w); }\n";
        s += "        case 2u: { return intersect_axis_plane(r, o.axis, o.a.x); }\n";
    }
    if c.triangles {
        s += "        case 3u: { return intersect_triangle(r, o.a.xyz, o.b.xyz, o.c.xyz); }\n";
    }
    s += "        default: { return no_cand(0.0); }\n    }\n}\n";
    s
}

/// `traversal_closest` / `traversal_any`: the accelerator the shader has (both, chosen by a
/// uniform, in the full shader).
fn traversal_dispatch(c: &ShaderConfig) -> String {
    let pick = |kind: &str| match (c.bvh, c.brute) {
        _ if c.ray_query => format!("    return rq_{kind}(r);\n"),
        (true, true) => format!(
            "    if params.use_bvh != 0u {{\n        return bvh_{kind}(r);\n    }}\n    return brute_{kind}(r);\n"
        ),
        (true, false) => format!("    return bvh_{kind}(r);\n"),
        _ => format!("    return brute_{kind}(r);\n"),
    };
    let mut s = String::from(
        "// ---- traversal: finding the closest hit (and any hit, for shadows) ----\n\n",
    );
    // With instances (compute path), the world's accelerator is asked first, then the TLAS;
    // under ray queries the hardware walks both levels in one query.
    let two_level = c.instances && !c.ray_query;
    s += if two_level {
        "fn world_closest(r: Ray) -> Hit {\n"
    } else {
        "fn traversal_closest(r: Ray) -> Hit {\n"
    };
    s += &pick("closest");
    s += "}\n";
    if two_level {
        s += "\nfn traversal_closest(r: Ray) -> Hit {\n    return tlas_closest(world_closest(r), r);\n}\n";
    }
    if c.shadows {
        s += if two_level {
            "\nfn world_any(r: Ray) -> bool {\n"
        } else {
            "\nfn traversal_any(r: Ray) -> bool {\n"
        };
        s += &pick("any");
        s += "}\n";
        if two_level {
            s += "\nfn traversal_any(r: Ray) -> bool {\n    return world_any(r) || tlas_any(r);\n}\n";
        }
    }
    s
}

/// The depth of a tree in raystep's node layout (a leaf alone: 0).
fn tree_depth(nodes: &[crate::accel::bvh::Node]) -> u32 {
    let mut deepest = 0;
    let mut todo = vec![(0usize, 0u32)];
    while let Some((n, d)) = todo.pop() {
        let Some(node) = nodes.get(n) else { continue };
        deepest = deepest.max(d);
        if !node.is_leaf() {
            todo.push((node.first as usize, d + 1));
            todo.push((node.first as usize + 1, d + 1));
        }
    }
    deepest
}

/// Keeps or drops the `//#if NAME` / `//#else` / `//#endif` blocks of a piece.
fn preprocess(src: &str, config: &ShaderConfig) -> String {
    // Each open block: (its condition held, the enclosing blocks all active).
    let mut stack: Vec<(bool, bool)> = vec![];
    let mut out = String::with_capacity(src.len());
    let active = |stack: &[(bool, bool)]| stack.last().is_none_or(|&(c, outer)| c && outer);
    for line in src.lines() {
        let t = line.trim();
        if let Some(name) = t.strip_prefix("//#if ") {
            let cond = config
                .flag(name.trim())
                .unwrap_or_else(|| panic!("unknown shader flag {name} in a WGSL piece"));
            let outer = active(&stack);
            stack.push((cond, outer));
        } else if t == "//#else" {
            if let Some(top) = stack.last_mut() {
                top.0 = !top.0;
            }
        } else if t == "//#endif" {
            stack.pop();
        } else if active(&stack) {
            out += line;
            out.push('\n');
        }
    }
    out
}

/// Parses and validates WGSL with naga (the compiler wgpu itself uses), without any adapter.
/// Ray queries are allowed (a shader that uses them needs a device with the feature anyway).
pub fn validate(wgsl: &str) -> Result<(), String> {
    use wgpu::naga;
    let module = naga::front::wgsl::parse_str(wgsl).map_err(|e| e.emit_to_string(wgsl))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default() | naga::valid::Capabilities::RAY_QUERY,
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string(wgsl))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn preprocessor_nests() {
        let mut c = ShaderConfig::for_scene(&PreparedScene::new(crate::scene::default_scene()));
        c.refraction = false;
        c.reflection = true;
        let src = "a\n//#if REFLECTION\nb\n//#if REFRACTION\nc\n//#else\nd\n//#endif\n//#else\ne\n//#endif\nf\n";
        assert_eq!(preprocess(src, &c), "a\nb\nd\nf\n");
    }
}

#[cfg(test)]
mod trace_shader_tests {
    use super::*;

    /// The trace shader of each shipped Monte Carlo scene (path and distribution, with and
    /// without BVH) is valid WGSL.
    #[test]
    fn monte_carlo_trace_shaders_validate() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        for name in [
            "cornell-area",
            "soft-shadows",
            "depth-of-field",
            "veach-mis",
        ] {
            let scene =
                raystep_core::assets::load_scene(&dir.join(format!("{name}.toml"))).unwrap();
            let mut c = ShaderConfig::for_scene(&PreparedScene::new(scene));
            assert!(c.monte_carlo, "{name}");
            c.trace = true;
            let src = wgsl(&c);
            assert!(src.contains("fn mc_trace_pixel"), "{name}");
            validate(&src).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
    }
}
