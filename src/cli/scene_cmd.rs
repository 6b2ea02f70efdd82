//! `raystep scene …`.

use super::{SettingsArgs, load_scene};
use clap::Subcommand;
use std::fmt::Write;
use std::path::PathBuf;

/// Scene commands.
#[derive(Debug, Subcommand)]
pub enum SceneCmd {
    /// Validate a scene file and print what it contains and what raystep will leave out.
    Check {
        /// The scene file.
        scene: PathBuf,
        /// Print the features as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Generate one of Eric Haines's Standard Procedural Databases scenes: balls (the
    /// sphereflake), tetra (Sierpinski tetrahedron) or mount (fractal mountain). Meshes are
    /// written as an OBJ file beside the scene.
    Spd {
        /// Which scene.
        #[arg(value_enum)]
        name: crate::scene::spd::SpdScene,
        /// Recursion depth / subdivision level (balls 4 = 7,381 spheres; tetra 9 ≈ 1M triangles),
        /// up to the largest size whose scene raystep loads (a larger one is refused, naming it).
        #[arg(long)]
        size: u32,
        /// The scene file to write (.toml).
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Write the scene in Mitsuba 3's XML format (with OBJ files for its triangles, beside it),
    /// for rendering the same scene with an independent renderer.
    Mitsuba {
        /// The scene file.
        scene: PathBuf,
        /// The XML file to write (.xml).
        #[arg(short, long)]
        output: PathBuf,
        /// Settings that override the scene's `[render]` table (--spp sets Mitsuba's
        /// sample count, --max-depth its depth).
        #[command(flatten)]
        settings: SettingsArgs,
    },
}

/// Runs a scene command.
pub fn run(cmd: &SceneCmd) -> Result<(), String> {
    match cmd {
        SceneCmd::Check { scene, json } => check(scene, *json),
        SceneCmd::Spd { name, size, output } => spd(*name, *size, output),
        SceneCmd::Mitsuba {
            scene,
            output,
            settings,
        } => mitsuba(scene, output, settings),
    }
}

fn mitsuba(
    scene: &std::path::Path,
    output: &std::path::Path,
    settings: &SettingsArgs,
) -> Result<(), String> {
    if !output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xml"))
    {
        return Err(format!(
            "{}: the Mitsuba scene must be written to a .xml file",
            output.display()
        ));
    }
    let s = load_scene(Some(&scene.to_path_buf()), settings)?;
    let m = crate::scene::mitsuba::to_mitsuba(
        &s,
        s.settings.spp,
        &output
            .file_stem()
            .map_or("scene".into(), |f| f.to_string_lossy()),
    )
    .map_err(|e| format!("{}: {e}", scene.display()))?;
    let dir = output
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(std::path::Path::new("."));
    m.write_files(dir)?;
    crate::io::write_atomic(output, m.xml.as_bytes())?;
    super::emit(&format!(
        "wrote {} ({} OBJ files and {} images beside it)\n",
        super::full_path(output),
        m.objs.len(),
        m.images.len()
    ))
}

fn spd(
    name: crate::scene::spd::SpdScene,
    size: u32,
    output: &std::path::Path,
) -> Result<(), String> {
    if !output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
    {
        return Err(format!(
            "{}: the scene must be written to a .toml file",
            output.display()
        ));
    }
    let start = std::time::Instant::now();
    let out = crate::scene::spd::generate(name, size)?;
    if let Some((file, text)) = &out.obj {
        let dir = output
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(std::path::Path::new("."));
        crate::io::write_atomic(&dir.join(file), text.as_bytes())?;
    }
    crate::io::write_atomic(output, out.toml.as_bytes())?;
    super::emit(&format!(
        "wrote {} ({} primitives{}) in {:.2} s\n",
        super::full_path(output),
        out.primitives,
        out.obj
            .as_ref()
            .map_or(String::new(), |(f, _)| format!(", mesh {f}")),
        start.elapsed().as_secs_f64()
    ))
}

fn check(path: &PathBuf, json: bool) -> Result<(), String> {
    let scene = load_scene(Some(path), &SettingsArgs::default())?;
    let f = &scene.features;
    let mut o = String::new();
    if json {
        return super::emit(&(serde_json::to_string_pretty(f).expect("features serialize") + "\n"));
    }
    let c = &scene.camera;
    let s = &scene.settings;
    let _ = writeln!(o, "{}: ok — \"{}\"", path.display(), scene.name);
    let _ = writeln!(
        o,
        "  camera     {}×{}, vertical fov {}°, from {:?} looking at {:?}",
        c.width,
        c.height,
        c.fov,
        c.from.to_array(),
        c.at.to_array()
    );
    let mut kinds = vec![];
    for (n, what) in [
        (f.spheres, "sphere"),
        (f.planes, "plane"),
        (f.triangles, "triangle"),
    ] {
        if n > 0 {
            kinds.push(format!("{n} {what}{}", if n == 1 { "" } else { "s" }));
        }
    }
    if f.meshes > 0 {
        kinds.push(format!(
            "from {} mesh{}",
            f.meshes,
            if f.meshes == 1 { "" } else { "es" }
        ));
    }
    let _ = writeln!(o, "  primitives {} ({})", f.primitives, kinds.join(", "));
    if f.instances > 0 {
        let protos: Vec<String> = scene
            .prototypes
            .iter()
            .map(|p| {
                let g = &scene.groups[p.group as usize];
                let n = scene
                    .instances
                    .iter()
                    .filter(|i| i.group == p.group)
                    .count();
                format!("\"{}\" ×{n}", g.name)
            })
            .collect();
        let _ = writeln!(
            o,
            "  instances  {} of {} prototype{} ({}), {} primitives placed in all",
            f.instances,
            scene.prototypes.len(),
            if scene.prototypes.len() == 1 { "" } else { "s" },
            protos.join(", "),
            scene
                .instances
                .iter()
                .map(|i| scene.groups[i.group as usize].count as u64)
                .sum::<u64>()
        );
    }
    let degenerate = scene
        .objects
        .iter()
        .filter(|ob| matches!(ob.shape, crate::scene::Shape::Triangle { p } if (p[1] - p[0]).cross(p[2] - p[0]) == glam::Vec3::ZERO))
        .count();
    if degenerate > 0 {
        let _ = writeln!(
            o,
            "  warning    {degenerate} degenerate triangle{} (zero area) can never be hit",
            if degenerate == 1 { "" } else { "s" }
        );
    }
    let _ = writeln!(
        o,
        "  lights     {} point light{}, {} emitting primitive{} (area lights)",
        f.lights,
        if f.lights == 1 { "" } else { "s" },
        f.emitters,
        if f.emitters == 1 { "" } else { "s" }
    );
    let _ = writeln!(
        o,
        "  materials  {} (reflective: {}, transparent: {})",
        scene.materials.len(),
        if f.reflective { "yes" } else { "no" },
        if f.transparent { "yes" } else { "no" }
    );
    if !scene.textures.is_empty() {
        let each: Vec<String> = scene
            .textures
            .iter()
            .map(|t| match &t.kind {
                crate::scene::TextureKind::Checker { squares, .. } => {
                    format!("\"{}\" checker {}×{}", t.name, squares[0], squares[1])
                }
                crate::scene::TextureKind::Image {
                    width,
                    height,
                    filter,
                    wrap,
                    levels,
                    ..
                } => format!(
                    "\"{}\" image {width}×{height} {}{} {}",
                    t.name,
                    filter.name(),
                    if levels.len() > 1 {
                        format!(" ({} mip levels)", levels.len())
                    } else {
                        String::new()
                    },
                    wrap.name()
                ),
            })
            .collect();
        let _ = writeln!(
            o,
            "  textures   {} ({}); {} textured object{}, {} with vertex texture coordinates",
            scene.textures.len(),
            each.join(", "),
            f.textured,
            if f.textured == 1 { "" } else { "s" },
            scene.vertex_uvs.len()
        );
    }
    let _ = writeln!(
        o,
        "  settings   integrator {}, sphere {}, triangle {}, offset {}, accel {}, BVH quality {}, max depth {}, {} sample{} per pixel",
        if s.integrator == crate::scene::Integrator::Path {
            format!("path ({} strategy)", value_name(&s.strategy))
        } else {
            value_name(&s.integrator)
        },
        value_name(&s.sphere_method),
        value_name(&s.triangle_method),
        value_name(&s.offset),
        value_name(&s.accel),
        value_name(&s.bvh_quality),
        s.max_depth,
        s.spp,
        if s.spp == 1 { "" } else { "s" }
    );
    let mut out = vec![];
    if f.spheres == 0 {
        out.push("sphere tests");
    }
    if f.planes == 0 {
        out.push("plane tests");
    }
    if f.triangles == 0 {
        out.push("triangle tests");
    }
    // Whitted's tracer is specialized to the scene; the Monte Carlo integrators always sample
    // lights and bounce.
    if !s.integrator.is_monte_carlo() {
        if f.lights == 0 {
            out.push("shadow rays");
        }
        if !f.reflective {
            out.push("reflection rays");
        }
        if !f.transparent {
            out.push("refraction");
        }
    }
    if !out.is_empty() {
        let _ = writeln!(o, "  leaves out {}", out.join(", "));
    }
    super::emit(&o)
}

/// The command-line spelling of a setting's value.
pub fn value_name<T: clap::ValueEnum>(v: &T) -> String {
    v.to_possible_value()
        .map_or_else(String::new, |p| p.get_name().to_string())
}
