//! Texturing at a hit: the texture coordinates (u, v) of the point ([`tex_coords`]), the
//! texture read there ([`lookup`]), and the colour that results ([`texture_at`]). Every number is
//! computed with operations that round the same everywhere (`+ − × ÷`, `floor`, `sqrt` and the
//! portable [`atan2`]), in the order the GPU's `texture.wgsl` repeats, so a textured pixel has
//! the same bits on both.

use crate::accel::Hit;
use crate::math::Ray;
use crate::portable::math::{atan2, ln};
use crate::record::Step;
use crate::record::texturing::{LodRecord, MipRead, Texel, TexelLookup, UvMapping};
use crate::scene::{Filter, MipLevel, Scene, Shape, Texture, TextureKind, Wrap};
use crate::trace::interaction::Interaction;
use glam::Vec3;

/// π and 1/π, 1/(2π) rounded to f32 (the WGSL writes the same decimals).
const PI: f32 = std::f32::consts::PI;
const FRAC_1_PI: f32 = std::f32::consts::FRAC_1_PI;
const FRAC_1_2PI: f32 = 0.159_154_94;

/// Where a hit's texture coordinates came from, with the numbers they came from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TexCoords {
    /// How they were found.
    pub mapping: UvMapping,
    /// A triangle's barycentrics (b₁, b₂).
    pub barycentric: Option<[f32; 2]>,
    /// A triangle's vertex texture coordinates.
    pub vertex_uvs: Option<[[f32; 2]; 3]>,
    /// A sphere's outward unit direction.
    pub direction: Option<Vec3>,
    /// A plane's two in-plane axes.
    pub axes: Option<[Vec3; 2]>,
    /// (u, v).
    pub uv: [f32; 2],
}

/// Two unit axes in the plane of unit normal `n` (Duff et al., "Building an orthonormal basis,
/// revisited", JCGT 2017): with s = ±1 the sign of n_z and a = −1/(s + n_z), b = n_x·n_y·a,
/// a₁ = (1 + s·n_x²·a, s·b, −s·n_x) and a₂ = (b, s + n_y²·a, −n_y). For the floor's normal
/// (0, 1, 0) they are (1, 0, 0) and (0, 0, −1).
pub fn plane_axes(n: Vec3) -> [Vec3; 2] {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    [
        Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        Vec3::new(b, s + n.y * n.y * a, -n.y),
    ]
}

/// The two coordinates an axis-aligned plane's texture reads, in order: (y, z) for x = c,
/// (x, z) for y = c, (x, y) for z = c.
pub fn axis_plane_coords(axis: usize) -> (usize, usize) {
    match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// The unit axes along [`axis_plane_coords`]'s two coordinates.
pub fn axis_plane_axes(axis: usize) -> [Vec3; 2] {
    let (i, j) = axis_plane_coords(axis);
    let mut a = [Vec3::ZERO; 2];
    a[0][i] = 1.0;
    a[1][j] = 1.0;
    a
}

/// A plane's texture axes ([`axis_plane_axes`], [`plane_axes`]); none for another shape.
pub fn texture_axes(shape: &Shape) -> Option<[Vec3; 2]> {
    match *shape {
        Shape::AxisPlane { axis, .. } => Some(axis_plane_axes(axis)),
        Shape::Plane { normal, .. } => Some(plane_axes(normal)),
        _ => None,
    }
}

/// The texture coordinates of the hit (book/tracer.md, *Textures*):
/// - a triangle with vertex texture coordinates: (1 − b₁ − b₂)·t₀ + b₁·t₁ + b₂·t₂;
/// - a triangle without: the barycentrics (b₁, b₂) themselves;
/// - a sphere: longitude and latitude of the outward direction d, u = (atan2(−d_z, d_x) + π)/2π
///   and v = atan2(√(d_x² + d_z²), −d_y)/π (v = 0 at the bottom, 1 at the top);
/// - an axis-aligned plane: the point's two other coordinates in order ((y, z), (x, z) or
///   (x, y)); a general plane: the point along [`plane_axes`].
#[inline(always)]
pub fn tex_coords(scene: &Scene, hit: &Hit, it: &Interaction) -> TexCoords {
    let mut c = TexCoords {
        mapping: UvMapping::Barycentric,
        barycentric: None,
        vertex_uvs: None,
        direction: None,
        axes: None,
        uv: [0.0; 2],
    };
    let shape = &scene.objects[hit.object as usize].shape;
    match *shape {
        Shape::Triangle { .. } => {
            c.barycentric = Some([hit.u, hit.v]);
            c.uv = [hit.u, hit.v];
            if let Some(t) = scene.vertex_uvs_of(hit.object) {
                let b0 = 1.0 - hit.u - hit.v;
                c.mapping = UvMapping::VertexUvs;
                c.vertex_uvs = Some(*t);
                c.uv = [
                    t[0][0] * b0 + t[1][0] * hit.u + t[2][0] * hit.v,
                    t[0][1] * b0 + t[1][1] * hit.u + t[2][1] * hit.v,
                ];
            }
        }
        Shape::Sphere { .. } => {
            let d = if it.inside {
                -it.object_normal
            } else {
                it.object_normal
            };
            c.mapping = UvMapping::Sphere;
            c.direction = Some(d);
            c.uv = [
                (atan2(-d.z, d.x) + PI) * FRAC_1_2PI,
                atan2((d.x * d.x + d.z * d.z).sqrt(), -d.y) * FRAC_1_PI,
            ];
        }
        Shape::AxisPlane { axis, .. } => {
            let (i, j) = axis_plane_coords(axis);
            c.mapping = UvMapping::Plane;
            c.axes = texture_axes(shape);
            c.uv = [it.object_point[i], it.object_point[j]];
        }
        Shape::Plane { .. } => {
            let a = texture_axes(shape).unwrap_or([Vec3::X, Vec3::Z]);
            c.mapping = UvMapping::Plane;
            c.axes = Some(a);
            c.uv = [it.object_point.dot(a[0]), it.object_point.dot(a[1])];
        }
    }
    c
}

/// A coordinate in [0, 1] by the wrap mode: repeat keeps t − ⌊t⌋; clamp holds t to [0, 1];
/// mirror folds t − 2⌊t/2⌋ (in [0, 2)) back at 1.
#[inline(always)]
fn wrap_coord(wrap: Wrap, t: f32) -> f32 {
    match wrap {
        Wrap::Repeat => t - t.floor(),
        Wrap::Clamp => t.clamp(0.0, 1.0),
        Wrap::Mirror => {
            let m = t - 2.0 * (t * 0.5).floor();
            if m > 1.0 { 2.0 - m } else { m }
        }
    }
}

/// A texel column or row, `i` in −1 … n, into 0 … n − 1: repeat wraps to the other edge; clamp
/// and mirror keep the edge texel.
#[inline(always)]
fn wrap_index(wrap: Wrap, i: f32, n: u32) -> u32 {
    let last = n - 1;
    if i < 0.0 {
        if wrap == Wrap::Repeat { last } else { 0 }
    } else if i as u32 > last {
        if wrap == Wrap::Repeat { 0 } else { last }
    } else {
        i as u32
    }
}

/// One texel a lookup read.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TexelRead {
    /// The mip level it is in (0: the image itself).
    pub level: u32,
    /// Column and row in its level.
    pub at: [u32; 2],
    /// Its colour.
    pub color: Vec3,
    /// Its weight within its level (bilinear's, or 1).
    pub weight: f32,
}

const NO_TEXEL: TexelRead = TexelRead {
    level: 0,
    at: [0; 2],
    color: Vec3::ZERO,
    weight: 0.0,
};

/// The ray cone at a hit (Akenine-Möller et al., "Texture level of detail strategies for
/// real-time ray tracing", *Ray Tracing Gems*, ch. 20): a cone around the ray whose half-width
/// grows by the camera's pixel spread angle γ per unit of distance travelled, so at the hit its
/// width is W = γ·d for the path length d from the eye.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cone {
    /// γ: the angle one pixel subtends at the eye (`CameraRays::spread`).
    pub spread: f32,
    /// d: the path length from the eye to the hit, over every bounce.
    pub distance: f32,
}

/// How the level of detail was chosen and which levels were read (a trilinear lookup).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevelOfDetail {
    /// The cone at the hit.
    pub cone: Cone,
    /// W = γ·d, the cone's width at the hit.
    pub width: f32,
    /// |n·d̂|: the cosine between the geometric normal and the unit ray direction.
    pub cos: f32,
    /// Level-0 texels per unit of surface area at the hit (the texture's area over the
    /// surface's, RTG's t_a / p_a; on an instance, over the surface's area in the world).
    pub texels_per_area: f32,
    /// L = W·√(texels per area) / |n·d̂|: the footprint's side in level-0 texels.
    pub footprint: f32,
    /// λ = log₂ L.
    pub lambda: f32,
    /// The levels read (the second only where λ falls between two): ⌊λ⌋ and ⌊λ⌋ + 1, held to the
    /// pyramid.
    pub levels: [u32; 2],
    /// How many levels were read (1 or 2).
    pub count: usize,
    /// The second level's weight, λ − ⌊λ⌋ (the first's is 1 minus it).
    pub fraction: f32,
    /// Each level's address, (u·wₗ, (1 − v)·hₗ).
    pub addresses: [[f32; 2]; 2],
    /// Each level's colour.
    pub colors: [Vec3; 2],
}

/// The texels a lookup read, without allocating (the render reads, a trace records).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lookup {
    /// The colour read.
    pub color: Vec3,
    /// A checker's cell and whether it is odd.
    pub cell: [f32; 2],
    /// Whether the checker's cell is odd.
    pub odd: bool,
    /// (u, v) after the wrap mode.
    pub wrapped: [f32; 2],
    /// (u·width, (1 − v)·height) at the (first) level read.
    pub address: [f32; 2],
    /// The texels read (the first `count`): a trilinear lookup's first level, then its second.
    pub texels: [TexelRead; 8],
    /// How many texels were read (0 for a checker).
    pub count: usize,
    /// A trilinear lookup's level of detail.
    pub lod: Option<LevelOfDetail>,
}

/// 2π², the sphere's texture area factor (its (u, v) square covers 4πr² of surface, and at
/// polar angle θ one unit of u is 2πr·sin θ long, one unit of v πr).
const TWO_PI_SQUARED: f32 = 19.739_208;

/// log₂ e, for log₂ x = ln x · log₂ e.
const LOG2_E: f32 = std::f32::consts::LOG2_E;

/// Level-0 texels per unit of surface area at the hit, for an image of `size`:
/// - a triangle: w·h·|t₁ − t₀ × t₂ − t₀| / |(P₁ − P₀) × (P₂ − P₀)| (twice the uv triangle's area
///   over twice its own; the barycentrics' uv triangle has twice-area 1);
/// - a plane: w·h (its (u, v) are lengths along unit axes);
/// - a sphere: w·h / (2π²·r²·sin θ), sin θ = √(d_x² + d_z²) (+∞ at a pole).
#[inline(always)]
pub fn texels_per_area(shape: &Shape, coords: &TexCoords, size: [u32; 2]) -> f32 {
    let texels = size[0] as f32 * size[1] as f32;
    match *shape {
        Shape::Triangle { p } => {
            let uv_area = coords.vertex_uvs.map_or(1.0, |t| {
                let (a, b) = (
                    [t[1][0] - t[0][0], t[1][1] - t[0][1]],
                    [t[2][0] - t[0][0], t[2][1] - t[0][1]],
                );
                (a[0] * b[1] - a[1] * b[0]).abs()
            });
            let area = (p[1] - p[0]).cross(p[2] - p[0]).length();
            texels * uv_area / area
        }
        Shape::Sphere { radius, .. } => {
            let d = coords.direction.unwrap_or(Vec3::Y);
            let sin = (d.x * d.x + d.z * d.z).sqrt();
            texels / (TWO_PI_SQUARED * (radius * radius) * sin)
        }
        Shape::Plane { .. } | Shape::AxisPlane { .. } => texels,
    }
}

/// The level of detail a ray cone picks (RTG ch. 20, eq. 20.21 with the texture's own area
/// ratio): L = W·√(texels per area) / |n·d̂| level-0 texels across, λ = log₂ L (the portable
/// `ln` times log₂ e), held to [0, last level]; the levels ⌊λ⌋ and ⌊λ⌋ + 1 are read and blended
/// by λ − ⌊λ⌋. A NaN λ (a degenerate triangle) reads level 0.
///
/// `stretch`: on an instance, how many times larger the surface is in the world than in the
/// prototype's object space here ([`crate::scene::Affine::area_scale`]; None elsewhere). The
/// cone's width is a world length, so the density is per unit of world area: the prototype's
/// divided by the stretch (a gem scaled by 0.3 packs its texels into 0.09 of the area).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn level_of_detail(
    shape: &Shape,
    coords: &TexCoords,
    it: &Interaction,
    ray: &Ray<f32>,
    cone: Cone,
    size: [u32; 2],
    n_levels: u32,
    stretch: Option<f32>,
) -> LevelOfDetail {
    let width = cone.spread * cone.distance;
    let d = ray.dir / ray.dir.length();
    let cos = it.normal.dot(d).abs();
    let object = texels_per_area(shape, coords, size);
    let ratio = stretch.map_or(object, |s| object / s);
    let footprint = width * ratio.sqrt() / cos;
    let lambda = ln(footprint) * LOG2_E;
    let last = (n_levels - 1) as f32;
    let held = if lambda > 0.0 { lambda.min(last) } else { 0.0 };
    let l0 = held.floor();
    let fraction = held - l0;
    let l0 = l0 as u32;
    LevelOfDetail {
        cone,
        width,
        cos,
        texels_per_area: ratio,
        footprint,
        lambda,
        levels: [l0, (l0 + 1).min(n_levels - 1)],
        count: if fraction > 0.0 { 2 } else { 1 },
        fraction,
        addresses: [[0.0; 2]; 2],
        colors: [Vec3::ZERO; 2],
    }
}

/// Reads one level of an image, nearest or bilinear, at the wrapped (u, v); writes its texels
/// into `out` from `first` and returns (address, colour, texels read).
#[inline(always)]
// The image's texels and levels are taken once per lookup: a texel fetch is then one index.
#[allow(clippy::too_many_arguments)]
fn read_level(
    texels: &[Vec3],
    levels: &[MipLevel],
    level: u32,
    bilinear: bool,
    wrap: Wrap,
    uv: [f32; 2],
    out: &mut [TexelRead; 8],
    first: usize,
) -> ([f32; 2], Vec3, usize) {
    let Some(&l) = levels.get(level as usize) else {
        return ([0.0; 2], Vec3::ZERO, 0);
    };
    // Indices come from `wrap_index`, inside the level; black past it, as `Texture::texel_at`.
    let fetch = |x: u32, y: u32| {
        texels
            .get(l.offset + (y * l.width + x) as usize)
            .copied()
            .unwrap_or(Vec3::ZERO)
    };
    let (w, h) = (l.width as f32, l.height as f32);
    let x = uv[0] * w;
    let y = (1.0 - uv[1]) * h;
    if !bilinear {
        let at = [
            wrap_index(wrap, x.floor(), l.width),
            wrap_index(wrap, y.floor(), l.height),
        ];
        let c = fetch(at[0], at[1]);
        out[first] = TexelRead {
            level,
            at,
            color: c,
            weight: 1.0,
        };
        return ([x, y], c, 1);
    }
    let (xs, ys) = (x - 0.5, y - 0.5);
    let (x0, y0) = (xs.floor(), ys.floor());
    let (fx, fy) = (xs - x0, ys - y0);
    let cols = [
        wrap_index(wrap, x0, l.width),
        wrap_index(wrap, x0 + 1.0, l.width),
    ];
    let rows = [
        wrap_index(wrap, y0, l.height),
        wrap_index(wrap, y0 + 1.0, l.height),
    ];
    let weights = [
        (1.0 - fx) * (1.0 - fy),
        fx * (1.0 - fy),
        (1.0 - fx) * fy,
        fx * fy,
    ];
    let mut sum = Vec3::ZERO;
    for (k, weight) in weights.into_iter().enumerate() {
        let at = [cols[k & 1], rows[k >> 1]];
        let c = fetch(at[0], at[1]);
        out[first + k] = TexelRead {
            level,
            at,
            color: c,
            weight,
        };
        sum += c * weight;
    }
    ([x, y], sum, 4)
}

/// Reads `tex` at `uv`. A checker: the colour of square (⌊u·s₀⌋, ⌊v·s₁⌋), odd when
/// i + j − 2⌊(i + j)/2⌋ ≠ 0. An image: (u, v) wrapped, the address x = u·w, y = (1 − v)·h; nearest
/// reads texel (⌊x⌋, ⌊y⌋); bilinear reads the four texels whose centres surround the point,
/// x₀ = ⌊x − ½⌋, f = (x − ½) − x₀ (likewise y), with weights (1 − f_x)(1 − f_y), f_x(1 − f_y),
/// (1 − f_x)f_y, f_x·f_y, summed in that order. Trilinear: bilinear in each level `lod` names,
/// at that level's size, then c₀·(1 − f) + c₁·f.
#[inline(always)]
pub fn lookup(tex: &Texture, uv: [f32; 2], lod: Option<LevelOfDetail>) -> Lookup {
    let mut out = Lookup {
        color: Vec3::ZERO,
        cell: [0.0; 2],
        odd: false,
        wrapped: uv,
        address: [0.0; 2],
        texels: [NO_TEXEL; 8],
        count: 0,
        lod: None,
    };
    match &tex.kind {
        TextureKind::Checker { squares, colors } => {
            let i = (uv[0] * squares[0] as f32).floor();
            let j = (uv[1] * squares[1] as f32).floor();
            let s = i + j;
            out.cell = [i, j];
            out.odd = s - 2.0 * (s * 0.5).floor() != 0.0;
            out.color = colors[usize::from(out.odd)];
        }
        TextureKind::Image {
            filter,
            wrap,
            texels,
            levels,
            ..
        } => {
            let u = wrap_coord(*wrap, uv[0]);
            let v = wrap_coord(*wrap, uv[1]);
            out.wrapped = [u, v];
            let bilinear = *filter != Filter::Nearest;
            match (*filter, lod) {
                (Filter::Trilinear, Some(mut lod)) => {
                    let mut count = 0;
                    for k in 0..lod.count {
                        let (address, c, n) = read_level(
                            texels,
                            levels,
                            lod.levels[k],
                            true,
                            *wrap,
                            [u, v],
                            &mut out.texels,
                            count,
                        );
                        lod.addresses[k] = address;
                        lod.colors[k] = c;
                        count += n;
                    }
                    out.count = count;
                    out.address = lod.addresses[0];
                    out.color = if lod.count == 2 {
                        lod.colors[0] * (1.0 - lod.fraction) + lod.colors[1] * lod.fraction
                    } else {
                        lod.colors[0]
                    };
                    out.lod = Some(lod);
                }
                _ => {
                    let (address, c, n) = read_level(
                        texels,
                        levels,
                        0,
                        bilinear,
                        *wrap,
                        [u, v],
                        &mut out.texels,
                        0,
                    );
                    out.address = address;
                    out.color = c;
                    out.count = n;
                }
            }
        }
    }
    out
}

/// The texture of the hit object's material at the hit, if it has one: its coordinates, the
/// lookup, and the surface colour (the material's colour × the texture's).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Texturing {
    /// The texture's index in [`Scene::textures`].
    pub texture: u32,
    /// Where (u, v) came from.
    pub coords: TexCoords,
    /// What was read.
    pub lookup: Lookup,
    /// The material's colour × the texture's colour (a roughness texture's read: the roughness,
    /// in all three).
    pub color: Vec3,
    /// Set where this is a glossy BSDF's roughness texture.
    pub roughness: Option<crate::record::texturing::RoughnessRead>,
}

/// Texturing at a hit ([`tex_coords`], [`level_of_detail`] for a trilinear image, [`lookup`]),
/// or `None` where the material has no texture.
#[inline(always)]
pub fn texture_at(
    scene: &Scene,
    hit: &Hit,
    it: &Interaction,
    ray: &Ray<f32>,
    cone: Cone,
) -> Option<Texturing> {
    read_texture(
        scene,
        hit,
        it,
        ray,
        cone,
        scene.material_of(hit.object).texture?,
    )
}

/// Reads texture `index` at `hit` (as [`texture_at`] reads the material's colour texture; a
/// roughness texture is read this way). Its `color` is the material's colour × the texel.
pub fn read_texture(
    scene: &Scene,
    hit: &Hit,
    it: &Interaction,
    ray: &Ray<f32>,
    cone: Cone,
    index: u32,
) -> Option<Texturing> {
    let m = scene.material_of(hit.object);
    let tex = scene.textures.get(index as usize)?;
    let coords = tex_coords(scene, hit, it);
    let lod = match &tex.kind {
        TextureKind::Image {
            filter: Filter::Trilinear,
            width,
            height,
            levels,
            ..
        } => Some(level_of_detail(
            &scene.objects[hit.object as usize].shape,
            &coords,
            it,
            ray,
            cone,
            [*width, *height],
            levels.len() as u32,
            scene
                .instance_of(hit)
                .map(|i| i.to_object.area_scale(it.object_normal)),
        )),
        _ => None,
    };
    let lookup = lookup(tex, coords.uv, lod);
    Some(Texturing {
        texture: index,
        coords,
        lookup,
        color: m.color * lookup.color,
        roughness: None,
    })
}

impl Texturing {
    /// The `Texture` step that records it.
    pub fn step(&self, scene: &Scene) -> Step {
        let tex = &scene.textures[self.texture as usize];
        let l = &self.lookup;
        let lookup = match &tex.kind {
            TextureKind::Checker { squares, colors } => TexelLookup::Checker {
                squares: *squares,
                cell: l.cell,
                odd: l.odd,
                colors: colors.map(|c| c.to_array()),
            },
            TextureKind::Image {
                width,
                height,
                filter,
                wrap,
                levels,
                ..
            } => TexelLookup::Image {
                size: [*width, *height],
                filter: *filter,
                wrap: *wrap,
                wrapped: l.wrapped,
                address: l.address,
                texels: l.texels[..l.count]
                    .iter()
                    .map(|t| Texel {
                        level: t.level,
                        at: t.at,
                        color: t.color.to_array(),
                        weight: t.weight,
                    })
                    .collect(),
                lod: l.lod.map(|d| LodRecord {
                    spread: d.cone.spread,
                    distance: d.cone.distance,
                    width: d.width,
                    cos: d.cos,
                    texels_per_area: d.texels_per_area,
                    footprint: d.footprint,
                    lambda: d.lambda,
                    levels: (0..d.count)
                        .map(|k| {
                            let level = d.levels[k];
                            let size = levels
                                .get(level as usize)
                                .map_or([0; 2], |m| [m.width, m.height]);
                            MipRead {
                                level,
                                size,
                                address: d.addresses[k],
                                weight: if k == 0 { 1.0 - d.fraction } else { d.fraction },
                                color: d.colors[k].to_array(),
                            }
                        })
                        .collect(),
                }),
            },
        };
        let c = &self.coords;
        Step::Texture {
            texture: tex.name.clone(),
            mapping: c.mapping,
            barycentric: c.barycentric,
            vertex_uvs: c.vertex_uvs,
            direction: c.direction.map(|v| v.to_array()),
            axes: c.axes.map(|a| a.map(|v| v.to_array())),
            uv: c.uv,
            lookup,
            texel: l.color.to_array(),
            color: self.color.to_array(),
            roughness: self.roughness,
        }
    }
}
