//! Eric Haines's Standard Procedural Databases (SPD, 1987): the classic benchmark scenes of ray
//! tracing, generated as raystep scene files.
//!
//! Three of the databases are here, each following its original C program (`balls.c`, `tetra.c`,
//! `mount.c`) in geometry, viewpoint, lights and colours:
//!
//! - [`SpdScene::Balls`], the *sphereflake*: a mirrored sphere with nine spheres of a third its
//!   radius on it, each with nine more, …, over a beige floor, three lights.
//! - [`SpdScene::Tetra`]: the Sierpinski tetrahedron of red triangles, one light.
//! - [`SpdScene::Mount`]: a fractal mountain of triangles (midpoint displacement) with a pyramid of
//!   four spheres (three glass, one mirror) floating in front of it, one light.
//!
//! The originals are z-up, so the scenes keep their coordinates and set the camera's `up` to +z.
//! Their colours were display values for renderers without gamma, so they are converted from sRGB to
//! linear here: raystep encodes its images as sRGB, and the pictures then look like the classic ones.
//! Everything is deterministic: the same scene and size give the same text, byte for byte.

use crate::io::limits;
use crate::scene::MAX_OBJECTS;
use glam::{DQuat, DVec3};
use std::fmt::{self, Write};

/// Which SPD scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SpdScene {
    /// The sphereflake (`balls.c`): size d gives 1 + 9 + … + 9^d spheres and a floor plane.
    Balls,
    /// The Sierpinski tetrahedron (`tetra.c`): size d gives 4^d tetrahedra, 4^(d+1) triangles.
    /// (SPD's own size counts one more: its size d + 1 is this size d.)
    Tetra,
    /// The fractal mountain (`mount.c`): size n gives 2·4^n triangles and 4 spheres.
    Mount,
}

impl SpdScene {
    /// The scene's name, as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            SpdScene::Balls => "balls",
            SpdScene::Tetra => "tetra",
            SpdScene::Mount => "mount",
        }
    }

    /// The largest size [`generate`] accepts (sizes start at 1): the largest whose scene raystep
    /// loads. It is derived from the loader's own limits — at most [`MAX_OBJECTS`] primitives,
    /// a scene file of at most [`limits::SCENE`] bytes and an OBJ file of at most
    /// [`limits::OBJ`] — so that `raystep scene spd` never writes a scene raystep then refuses.
    pub fn max_size(self) -> u32 {
        // Each size has more primitives and bytes than the one before, so the sizes that fit
        // are 1 up to the first that does not.
        (1..)
            .take_while(|&size| self.fits(size))
            .last()
            .unwrap_or(0)
    }

    /// Whether raystep loads this scene at `size`: its primitives within [`MAX_OBJECTS`], and
    /// files no larger than the loader reads. The file sizes are lower bounds (every number
    /// written as one digit), so a size refused here would certainly be refused by the loader;
    /// [`generate`] checks the real sizes of what it wrote as well.
    fn fits(self, size: u32) -> bool {
        let (toml, obj) = min_bytes(self, size);
        count(self, size) <= MAX_OBJECTS as u64 && toml <= limits::SCENE && obj <= limits::OBJ
    }
}

/// A generated scene: the TOML text, and an OBJ file to write beside it when the scene has a mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct SpdOutput {
    /// The scene file's text.
    pub toml: String,
    /// The mesh the scene refers to, as (file name, OBJ text): write it in the scene file's folder
    /// under exactly that name, since the scene's `[[mesh]]` names it relative to itself.
    pub obj: Option<(String, String)>,
    /// Every primitive of the scene once loaded: spheres, planes and triangles.
    pub primitives: usize,
}

/// Generates `scene` at size `size`. A mesh is written to the OBJ text of [`SpdOutput::obj`], whose
/// file name (`tetra-6.obj`, `mount-9.obj`, …) is the one the TOML's `[[mesh]]` refers to.
///
/// Sizes run from 1 to [`SpdScene::max_size`], the largest whose scene raystep loads; any other
/// size is an error that names the largest and says which limit the next one passes.
pub fn generate(scene: SpdScene, size: u32) -> Result<SpdOutput, String> {
    let max = scene.max_size();
    if !(1..=max).contains(&size) {
        return Err(format!(
            "SPD {} size must be between 1 and {max}, got {size}{}",
            scene.name(),
            if size > max {
                format!(
                    " (the largest size raystep loads is {max}: size {} would {})",
                    max + 1,
                    past_limit(scene, max + 1)
                )
            } else {
                String::new()
            }
        ));
    }
    let out = match scene {
        SpdScene::Balls => balls(size),
        SpdScene::Tetra => tetra(size),
        SpdScene::Mount => mount(size),
    };
    // The bounds of `fits` are lower bounds: check what was really written against the limits
    // the loader applies, so no scene it would refuse is ever written.
    let too_large = |what: &str, len: usize, limit: u64| {
        (len as u64 > limit).then(|| {
            format!(
                "SPD {} size {size} would write a {what} of {len} bytes, more than the {} raystep \
                 reads",
                scene.name(),
                limits::describe(limit)
            )
        })
    };
    let obj_len = out.obj.as_ref().map_or(0, |(_, t)| t.len());
    if let Some(e) = too_large("scene file", out.toml.len(), limits::SCENE)
        .or_else(|| too_large("mesh (OBJ file)", obj_len, limits::OBJ))
    {
        return Err(e);
    }
    Ok(out)
}

/// How many primitives `scene` has at `size`, as the loader counts them (a mesh's triangles
/// each, the spheres and the floor plane).
fn count(scene: SpdScene, size: u32) -> u64 {
    let pow = |b: u64, e: u32| b.checked_pow(e).unwrap_or(u64::MAX);
    match scene {
        SpdScene::Balls => spheres_in_flake(size).saturating_add(1),
        SpdScene::Tetra => pow(4, size.saturating_add(1)),
        SpdScene::Mount => pow(4, size).saturating_mul(2).saturating_add(4),
    }
}

/// 1 + 9 + … + 9^size: the sphereflake's spheres.
fn spheres_in_flake(size: u32) -> u64 {
    (0..=size).fold(0u64, |n, k| {
        n.saturating_add(9u64.checked_pow(k).unwrap_or(u64::MAX))
    })
}

/// Lower bounds on the bytes of the scene file and of the OBJ file at `size`: the lines each
/// primitive needs with every number one character long (the shortest [`F`] writes). The
/// mountain writes its vertex and face lines in the same form as [`obj_vertex`] and [`obj_face`].
fn min_bytes(scene: SpdScene, size: u32) -> (u64, u64) {
    let line = |write: &dyn Fn(&mut String)| {
        let mut s = String::new();
        write(&mut s);
        s.len() as u64
    };
    let vertex = line(&|s| obj_vertex(s, DVec3::ZERO));
    let face = line(&|s| obj_face(s, 1, 1, 1));
    match scene {
        SpdScene::Balls => {
            let sphere = line(&|s| flake_sphere(s, DVec3::ZERO, 0.0));
            (spheres_in_flake(size).saturating_mul(sphere), 0)
        }
        // Four corners a tetrahedron, four faces.
        SpdScene::Tetra => (0, count(scene, size).saturating_mul(vertex + face)),
        SpdScene::Mount => {
            let side = 1u64.checked_shl(size).unwrap_or(u64::MAX).saturating_add(1);
            let triangles = count(scene, size).saturating_sub(4);
            (
                0,
                side.saturating_mul(side)
                    .saturating_mul(vertex)
                    .saturating_add(triangles.saturating_mul(face)),
            )
        }
    }
}

/// Which of the loader's limits `scene` at `size` passes, in words (for the error message).
fn past_limit(scene: SpdScene, size: u32) -> String {
    let n = count(scene, size);
    let (toml, obj) = min_bytes(scene, size);
    if n > MAX_OBJECTS as u64 {
        format!("make {n} primitives, more than the limit of {MAX_OBJECTS} in a scene")
    } else if toml > limits::SCENE {
        format!(
            "write a scene file of more than {toml} bytes, past the limit of {} for scene files",
            limits::describe(limits::SCENE)
        )
    } else {
        format!(
            "write an OBJ file of more than {obj} bytes, past the limit of {} for OBJ files",
            limits::describe(limits::OBJ)
        )
    }
}

// ---------------------------------------------------------------------------------------------
// Writing numbers and common tables

/// A number as the renderer will read it: the shortest text that parses back to the same f32
/// (the loader narrows every number to f32), with no `-0`.
struct F(f64);

impl fmt::Display for F {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0 as f32;
        if v == 0.0 {
            f.write_str("0")
        } else {
            write!(f, "{v}")
        }
    }
}

/// A point or colour as a TOML array.
struct V(DVec3);

impl fmt::Display for V {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{}, {}, {}]", F(self.0.x), F(self.0.y), F(self.0.z))
    }
}

/// The sRGB display value `c` as linear intensity, to four decimals (see the module docs).
fn linear(c: [f64; 3]) -> DVec3 {
    let l = |c: f64| {
        let v = if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        };
        (v * 1e4).round() / 1e4
    };
    DVec3::new(l(c[0]), l(c[1]), l(c[2]))
}

/// SPD's background, "UNC sky blue".
const SKY_BLUE: [f64; 3] = [0.078, 0.361, 0.753];

/// The title, camera and render tables every SPD scene starts with: the originals' 45° square view.
fn header(s: &mut String, title: &str, from: DVec3, at: DVec3, up: DVec3) {
    // Writing to a String cannot fail.
    let _ = write!(
        s,
        "# {title}\n\
         # Eric Haines's Standard Procedural Databases, generated by `raystep scene spd`.\n\
         # z is up, as in the original.\n\
         title = \"{title}\"\n\n\
         [camera]\nfrom = {}\nat = {}\nup = {}\nfov = 45\nwidth = 512\nheight = 512\n\n\
         [render]\nbackground = {}\nmax_depth = 5\n",
        V(from),
        V(at),
        V(up),
        V(linear(SKY_BLUE)),
    );
}

fn light(s: &mut String, position: DVec3, intensity: f64) {
    let _ = write!(
        s,
        "\n[[light]]\nposition = {}\ncolor = {}\n",
        V(position),
        V(DVec3::splat(intensity))
    );
}

/// A `[[material]]`. SPD gives colours in display values (converted to linear here) and its
/// coefficients much like The Ray Tracer Challenge's: diffuse, specular highlight, shininess, the
/// mirror reflectance, the transmittance and the index of refraction.
struct Mat {
    name: &'static str,
    color: [f64; 3],
    ambient: f64,
    diffuse: f64,
    specular: f64,
    shininess: f64,
    reflective: f64,
    transparency: f64,
    refractive_index: f64,
}

impl Mat {
    fn write(&self, s: &mut String) {
        let _ = write!(
            s,
            "\n[[material]]\nname = \"{}\"\ncolor = {}\nambient = {}\ndiffuse = {}\nspecular = {}\n\
             shininess = {}\nreflective = {}\ntransparency = {}\nrefractive_index = {}\n",
            self.name,
            V(linear(self.color)),
            F(self.ambient),
            F(self.diffuse),
            F(self.specular),
            F(self.shininess),
            F(self.reflective),
            F(self.transparency),
            F(self.refractive_index),
        );
    }
}

// ---------------------------------------------------------------------------------------------
// balls.c: the sphereflake

/// The nine directions, relative to a sphere's "up" axis +z, at which its children sit: the 12
/// vertex directions of a cuboctahedron, less the three of the lower hemisphere. Seen along the
/// cube diagonal (1, 1, 1), a cuboctahedron's vertices form three rings: 3 above, 6 on the equator
/// and 3 below. Take the three (±1, ±1, 0)/√2-style directions that lie one above and two on the
/// equator, turn the diagonal onto +z, and copy them at 0°, 120° and 240° about z.
fn flake_directions() -> [DVec3; 9] {
    let trio = [
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(1.0, 0.0, -1.0),
        DVec3::new(0.0, 1.0, -1.0),
    ];
    let to_z = DQuat::from_rotation_arc(DVec3::ONE.normalize(), DVec3::Z);
    let mut dirs = [DVec3::ZERO; 9];
    for set in 0..3 {
        let turn = DQuat::from_rotation_z(set as f64 * std::f64::consts::TAU / 3.0);
        for (k, t) in trio.iter().enumerate() {
            dirs[set * 3 + k] = (turn * to_z * t.normalize()).normalize();
        }
    }
    dirs
}

/// A sphere, then (while `depth` lasts) its nine children of a third the radius, touching it, each
/// with its "up" pointing away from the parent — balls.c's `output_object`.
fn flake(
    out: &mut Vec<(DVec3, f64)>,
    dirs: &[DVec3; 9],
    center: DVec3,
    radius: f64,
    up: DVec3,
    depth: u32,
) {
    out.push((center, radius));
    if depth == 0 {
        return;
    }
    let turn = DQuat::from_rotation_arc(DVec3::Z, up);
    let child_radius = radius / 3.0;
    for d in dirs {
        let dir = (turn * *d).normalize();
        flake(
            out,
            dirs,
            center + dir * (radius + child_radius),
            child_radius,
            dir,
            depth - 1,
        );
    }
}

/// One sphere of the flake, as the scene file lists it.
fn flake_sphere(s: &mut String, center: DVec3, radius: f64) {
    let _ = write!(
        s,
        "\n[[sphere]]\ncenter = {}\nradius = {}\nmaterial = \"flake\"\n",
        V(center),
        F(radius)
    );
}

/// An OBJ vertex line.
fn obj_vertex(s: &mut String, p: DVec3) {
    let _ = writeln!(s, "v {} {} {}", F(p.x), F(p.y), F(p.z));
}

/// An OBJ face line (vertices counted from 1).
fn obj_face(s: &mut String, a: usize, b: usize, c: usize) {
    let _ = writeln!(s, "f {a} {b} {c}");
}

fn balls(size: u32) -> SpdOutput {
    let mut spheres = Vec::with_capacity(spheres_in_flake(size) as usize);
    // The whole flake fits in a sphere of radius 1: the first sphere has radius 1/2, and each
    // generation adds 2/3 of the previous one's reach (1/2 · (1 + 2/3 + 4/9 + …) → 1).
    flake(
        &mut spheres,
        &flake_directions(),
        DVec3::ZERO,
        0.5,
        DVec3::Z,
        size,
    );

    let mut s = String::with_capacity(1024 + spheres.len() * 80);
    let title = format!(
        "SPD balls (sphereflake), size {size}: {} spheres",
        spheres.len()
    );
    header(
        &mut s,
        &title,
        DVec3::new(2.1, 1.3, 1.7),
        DVec3::ZERO,
        DVec3::Z,
    );
    // balls.c scales its three lights to 1/√3 each, so that together they make 1.
    let each = 1.0 / 3f64.sqrt();
    for p in [
        DVec3::new(4.0, 3.0, 2.0),
        DVec3::new(1.0, -4.0, 4.0),
        DVec3::new(-3.0, 1.0, 5.0),
    ] {
        light(&mut s, p, each);
    }
    Mat {
        name: "floor",
        color: [1.0, 0.75, 0.33],
        ambient: 0.2,
        diffuse: 0.8,
        specular: 0.0,
        shininess: 200.0,
        reflective: 0.0,
        transparency: 0.0,
        refractive_index: 1.0,
    }
    .write(&mut s);
    // "Mirrored": half diffuse, half mirror, with a broad highlight (balls.c: Kd 0.5, Ks 0.5, a
    // highlight falling to half at 37° — Phong exponent about 13). A little ambient keeps the
    // shadowed undersides from going black (the original has none).
    Mat {
        name: "flake",
        color: [1.0, 0.9, 0.7],
        ambient: 0.05,
        diffuse: 0.5,
        specular: 0.5,
        shininess: 13.0,
        reflective: 0.5,
        transparency: 0.0,
        refractive_index: 1.0,
    }
    .write(&mut s);
    // balls.c's floor is a 24 × 24 square at z = -1/2, touching the first sphere; from this
    // viewpoint its edges are far outside the picture, so an infinite plane shows the same.
    s += "\n[[plane]]\nname = \"floor\"\naxis = \"z\"\noffset = -0.5\nmaterial = \"floor\"\n";
    for (c, r) in &spheres {
        flake_sphere(&mut s, *c, *r);
    }
    SpdOutput {
        toml: s,
        obj: None,
        primitives: spheres.len() + 1,
    }
}

// ---------------------------------------------------------------------------------------------
// tetra.c: the Sierpinski tetrahedron

/// The corners (±1, ±1, ±1) with x·y·z = 1: every other corner of a cube, a regular tetrahedron.
const TETRA_CORNERS: [[f64; 3]; 4] = [
    [-1.0, -1.0, 1.0],
    [-1.0, 1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, 1.0],
];
/// tetra.c's faces, wound counter-clockwise seen from outside.
const TETRA_FACES: [[usize; 3]; 4] = [[0, 1, 2], [3, 2, 1], [2, 3, 0], [1, 0, 3]];

/// Writes the tetrahedron inscribed in the cube of centre `c` and half-side `h`, or (while
/// `depth` lasts) the four of half its size in its corners — tetra.c's `create_tetra`.
fn sierpinski(v: &mut String, f: &mut String, next: &mut usize, c: DVec3, h: f64, depth: u32) {
    if depth == 0 {
        for k in TETRA_CORNERS {
            obj_vertex(v, c + DVec3::from(k) * h);
        }
        for [a, b, d] in TETRA_FACES {
            obj_face(f, *next + a, *next + b, *next + d);
        }
        *next += 4;
    } else {
        for k in TETRA_CORNERS {
            sierpinski(
                v,
                f,
                next,
                c + DVec3::from(k) * (h / 2.0),
                h / 2.0,
                depth - 1,
            );
        }
    }
}

fn tetra(size: u32) -> SpdOutput {
    let tetrahedra = 4usize.pow(size);
    let triangles = tetrahedra * 4;
    // Corners are dyadic fractions (a few bytes each); a face line is up to ~25 bytes.
    let mut v = String::with_capacity(tetrahedra * 4 * 40 + 256);
    let mut f = String::with_capacity(triangles * 26);
    let _ = writeln!(
        v,
        "# SPD tetra, size {size}: {tetrahedra} tetrahedra, {triangles} triangles\no tetra"
    );
    let mut next = 1; // OBJ counts vertices from 1
    sierpinski(&mut v, &mut f, &mut next, DVec3::ZERO, 1.0, size);
    v += &f;
    drop(f);

    let obj_name = format!("tetra-{size}.obj");
    let mut s = String::new();
    let title = format!("SPD tetra (Sierpinski tetrahedron), size {size}: {triangles} triangles");
    // tetra.c's view, which is Kay & Kajiya's (SIGGRAPH '86) in other world coordinates.
    header(
        &mut s,
        &title,
        DVec3::new(1.022846, -3.177154, -2.174512),
        DVec3::new(-0.004103, -0.004103, 0.216539),
        DVec3::new(-0.816497, -0.816497, 0.816497),
    );
    light(&mut s, DVec3::new(2.0, -18.0, -5.0), 1.0);
    // Red, purely diffuse; a little ambient (the original has none) shows the faces in shadow.
    Mat {
        name: "red",
        color: [1.0, 0.2, 0.2],
        ambient: 0.1,
        diffuse: 1.0,
        specular: 0.0,
        shininess: 200.0,
        reflective: 0.0,
        transparency: 0.0,
        refractive_index: 1.0,
    }
    .write(&mut s);
    let _ = write!(
        s,
        "\n[[mesh]]\nname = \"tetra\"\nobj = \"{obj_name}\"\nmaterial = \"red\"\n"
    );
    SpdOutput {
        toml: s,
        obj: Some((obj_name, v)),
        primitives: triangles,
    }
}

// ---------------------------------------------------------------------------------------------
// mount.c: the fractal mountain

/// mount.c's fractal dimension, between 2 (smooth) and 3 (rough).
const FRACTAL_DIMENSION: f64 = 2.2;
/// Changes the mountain, as mount.c's `MOUNTAIN_NO` does.
const MOUNTAIN_NO: u64 = 21;
/// Grid coordinates are hashed at this resolution, whatever the size (see [`gauss`]).
const CANONICAL_LEVEL: u32 = 16;

/// A standard-normal-like number for the grid point (x, y) of the 2^16 grid: a pure function of
/// the point, so an edge's midpoint is displaced the same in both squares that share the edge (no
/// cracks), and — because the point is named on a fixed fine grid rather than the size's own —
/// mountains of different sizes share their large features: a larger size only adds detail.
///
/// mount.c uses a table of Gaussian numbers indexed by a (famously faulty) hash. Here a 64-bit
/// mix (SplitMix64's finalizer) gives four 16-bit uniforms whose sum, centred and scaled
/// (Irwin–Hall), has mean 0 and variance 1. Only integer arithmetic and exactly rounded float
/// additions and products: the same on every run and every machine.
fn gauss(x: u64, y: u64) -> f64 {
    let mut z = (x | (y << 32)) ^ MOUNTAIN_NO.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    let sum: f64 = (0..4)
        .map(|k| ((z >> (16 * k)) & 0xffff) as f64 / 65535.0)
        .sum();
    (sum - 2.0) * 3f64.sqrt()
}

/// The heights of the (2^size + 1)² grid points over the square [-1, 1]², corners at 0: mount.c's
/// `grow_mountain` (Carpenter's midpoint displacement), level by level instead of square by square.
/// At each level a square of half-side `half` gets its edge midpoints (the mean of the edge's ends)
/// and its centre (the mean of its corners, displaced √2 as much) raised by a random amount
/// proportional to the half-side.
fn mountain_heights(size: u32) -> Vec<f64> {
    let n = 1usize << size;
    let row = n + 1;
    let mut z = vec![0.0f64; row * row];
    let ratio = 2.0 / (2f64.ln() / (FRACTAL_DIMENSION - 1.0)).exp();
    let roughness = (ratio * ratio - 1.0).sqrt();
    let shift = CANONICAL_LEVEL - size;
    let g = |x: usize, y: usize| gauss((x as u64) << shift, (y as u64) << shift);
    let mut width = n;
    while width > 1 {
        let half = width / 2;
        let rise = half as f64 * 2.0 / n as f64 * roughness;
        for y0 in (0..n).step_by(width) {
            for x0 in (0..n).step_by(width) {
                let (x1, y1, xm, ym) = (x0 + width, y0 + width, x0 + half, y0 + half);
                let (ll, lr, ur, ul) = (
                    z[y0 * row + x0],
                    z[y0 * row + x1],
                    z[y1 * row + x1],
                    z[y1 * row + x0],
                );
                // Each edge midpoint is written by both squares sharing the edge, with the same value.
                z[y0 * row + xm] = (ll + lr) / 2.0 + rise * g(xm, y0);
                z[ym * row + x1] = (lr + ur) / 2.0 + rise * g(x1, ym);
                z[y1 * row + xm] = (ur + ul) / 2.0 + rise * g(xm, y1);
                z[ym * row + x0] = (ul + ll) / 2.0 + rise * g(x0, ym);
                z[ym * row + xm] =
                    (ll + lr + ur + ul) / 4.0 + std::f64::consts::SQRT_2 * rise * g(xm, ym);
            }
        }
        width = half;
    }
    z
}

/// mount.c's pyramid of four touching spheres of radius `r` around `center`: one on top, three
/// below at the tetrahedral angle, 120° apart.
fn sphere_pyramid(center: DVec3, r: f64) -> [DVec3; 4] {
    let top = DVec3::new(0.0, 0.0, r * 1.5f64.sqrt());
    let tilt = DQuat::from_axis_angle(
        DVec3::new(1.0, 1.0, 0.0).normalize(),
        (-1.0f64 / 3.0).acos(),
    );
    let low = tilt * top;
    let mut out = [center + top; 4];
    for (i, o) in out.iter_mut().skip(1).enumerate() {
        *o = center + DQuat::from_rotation_z(i as f64 * std::f64::consts::TAU / 3.0) * low;
    }
    out
}

fn mount(size: u32) -> SpdOutput {
    let n = 1usize << size;
    let row = n + 1;
    let z = mountain_heights(size);
    let triangles = 2 * n * n;

    let mut obj = String::with_capacity(row * row * 32 + triangles * 28 + 256);
    let _ = writeln!(
        obj,
        "# SPD mount, size {size}: {row}x{row} heights, {triangles} triangles\no mountain"
    );
    let coord: Vec<String> = (0..row)
        .map(|i| F(-1.0 + 2.0 * i as f64 / n as f64).to_string())
        .collect();
    for y in 0..row {
        for x in 0..row {
            let _ = writeln!(obj, "v {} {} {}", coord[x], coord[y], F(z[y * row + x]));
        }
    }
    // Each grid square as mount.c splits it: (ll, lr, ur) and (ur, ul, ll), counter-clockwise
    // from above. OBJ counts vertices from 1.
    for y in 0..n {
        for x in 0..n {
            let ll = y * row + x + 1;
            let (lr, ul) = (ll + 1, ll + row);
            let ur = ul + 1;
            let _ = write!(obj, "f {ll} {lr} {ur}\nf {ur} {ul} {ll}\n");
        }
    }

    let obj_name = format!("mount-{size}.obj");
    let mut s = String::new();
    let title =
        format!("SPD mount (fractal mountain), size {size}: {triangles} triangles, 4 spheres");
    header(
        &mut s,
        &title,
        DVec3::new(-1.6, 1.6, 1.7),
        DVec3::ZERO,
        DVec3::Z,
    );
    light(&mut s, DVec3::new(-100.0, -100.0, 100.0), 1.0);
    // Grey-brown rock, purely diffuse; a little ambient (the original has none) for the shadows.
    Mat {
        name: "rock",
        color: [0.5, 0.45, 0.35],
        ambient: 0.1,
        diffuse: 1.0,
        specular: 0.0,
        shininess: 200.0,
        reflective: 0.0,
        transparency: 0.0,
        refractive_index: 1.0,
    }
    .write(&mut s);
    // mount.c's "crystal": clear glass (Kd 0.1, Ks 0.1, T 0.9, index 1.5) with a tight highlight
    // (half at 6.7°: Phong exponent about 400).
    Mat {
        name: "glass",
        color: [1.0, 1.0, 1.0],
        ambient: 0.0,
        diffuse: 0.1,
        specular: 0.4,
        shininess: 400.0,
        reflective: 0.1,
        transparency: 0.9,
        refractive_index: 1.5,
    }
    .write(&mut s);
    // The front right sphere is a mirror here (all four are glass in mount.c): both effects in
    // one view, the mirror showing its glass neighbours.
    Mat {
        name: "mirror",
        color: [1.0, 1.0, 1.0],
        ambient: 0.0,
        diffuse: 0.1,
        specular: 0.4,
        shininess: 400.0,
        reflective: 0.9,
        transparency: 0.0,
        refractive_index: 1.0,
    }
    .write(&mut s);
    let _ = write!(
        s,
        "\n[[mesh]]\nname = \"mountain\"\nobj = \"{obj_name}\"\nmaterial = \"rock\"\n"
    );
    // "In front of the mountain": between the eye and the peak, as in mount.c. Seen from the
    // camera, the pyramid's three lower spheres are at the back, left and right.
    let centers = sphere_pyramid(DVec3::new(-0.8, 0.8, 1.0), 0.17);
    let names = [
        ("ball top", "glass"),
        ("ball back", "glass"),
        ("ball left", "glass"),
        ("ball right", "mirror"),
    ];
    for (c, (name, mat)) in centers.iter().zip(names) {
        let _ = write!(
            s,
            "\n[[sphere]]\nname = \"{name}\"\ncenter = {}\nradius = 0.17\nmaterial = \"{mat}\"\n",
            V(*c)
        );
    }
    SpdOutput {
        toml: s,
        obj: Some((obj_name, obj)),
        primitives: triangles + centers.len(),
    }
}
