//! Texturing at a hit: the texture coordinates (u, v) of the point ([`tex_coords`]), the
//! texture read there ([`lookup`]), and the colour that results ([`texture_at`]). Every number is
//! computed with operations that round the same everywhere (`+ − × ÷`, `floor`, `sqrt` and the
//! portable [`atan2`]), in the order the GPU's `texture.wgsl` repeats, so a textured pixel has
//! the same bits on both.

use crate::accel::Hit;
use crate::portable::math::atan2;
use crate::record::Step;
use crate::record::texturing::{Texel, TexelLookup, UvMapping};
use crate::scene::{Filter, Scene, Shape, Texture, TextureKind, Wrap};
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

/// The texture coordinates of the hit (README.md, *Textures*):
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
            let d = if it.inside { -it.normal } else { it.normal };
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
            c.uv = [it.point[i], it.point[j]];
        }
        Shape::Plane { .. } => {
            let a = texture_axes(shape).unwrap_or([Vec3::X, Vec3::Z]);
            c.mapping = UvMapping::Plane;
            c.axes = Some(a);
            c.uv = [it.point.dot(a[0]), it.point.dot(a[1])];
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
    /// (u·width, (1 − v)·height).
    pub address: [f32; 2],
    /// The texels read (the first `count`).
    pub texels: [([u32; 2], Vec3, f32); 4],
    /// How many texels were read (0 for a checker).
    pub count: usize,
}

/// Reads `tex` at `uv`. A checker: the colour of square (⌊u·s₀⌋, ⌊v·s₁⌋), odd when
/// i + j − 2⌊(i + j)/2⌋ ≠ 0. An image: (u, v) wrapped, the address x = u·w, y = (1 − v)·h; nearest
/// reads texel (⌊x⌋, ⌊y⌋); bilinear reads the four texels whose centres surround the point,
/// x₀ = ⌊x − ½⌋, f = (x − ½) − x₀ (likewise y), with weights (1 − f_x)(1 − f_y), f_x(1 − f_y),
/// (1 − f_x)f_y, f_x·f_y, summed in that order.
#[inline(always)]
pub fn lookup(tex: &Texture, uv: [f32; 2]) -> Lookup {
    let mut out = Lookup {
        color: Vec3::ZERO,
        cell: [0.0; 2],
        odd: false,
        wrapped: uv,
        address: [0.0; 2],
        texels: [([0; 2], Vec3::ZERO, 0.0); 4],
        count: 0,
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
            width,
            height,
            filter,
            wrap,
            ..
        } => {
            let (w, h) = (*width as f32, *height as f32);
            let u = wrap_coord(*wrap, uv[0]);
            let v = wrap_coord(*wrap, uv[1]);
            let x = u * w;
            let y = (1.0 - v) * h;
            out.wrapped = [u, v];
            out.address = [x, y];
            match filter {
                Filter::Nearest => {
                    let at = [
                        wrap_index(*wrap, x.floor(), *width),
                        wrap_index(*wrap, y.floor(), *height),
                    ];
                    let c = tex.texel(at[0], at[1]);
                    out.texels[0] = (at, c, 1.0);
                    out.count = 1;
                    out.color = c;
                }
                Filter::Bilinear => {
                    let (xs, ys) = (x - 0.5, y - 0.5);
                    let (x0, y0) = (xs.floor(), ys.floor());
                    let (fx, fy) = (xs - x0, ys - y0);
                    let cols = [
                        wrap_index(*wrap, x0, *width),
                        wrap_index(*wrap, x0 + 1.0, *width),
                    ];
                    let rows = [
                        wrap_index(*wrap, y0, *height),
                        wrap_index(*wrap, y0 + 1.0, *height),
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
                        let c = tex.texel(at[0], at[1]);
                        out.texels[k] = (at, c, weight);
                        sum += c * weight;
                    }
                    out.count = 4;
                    out.color = sum;
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
    /// The material's colour × the texture's colour.
    pub color: Vec3,
}

/// Texturing at a hit ([`tex_coords`], [`lookup`]), or `None` where the material has no texture.
#[inline(always)]
pub fn texture_at(scene: &Scene, hit: &Hit, it: &Interaction) -> Option<Texturing> {
    let m = scene.material_of(hit.object);
    let index = m.texture?;
    let tex = &scene.textures[index as usize];
    let coords = tex_coords(scene, hit, it);
    let lookup = lookup(tex, coords.uv);
    Some(Texturing {
        texture: index,
        coords,
        lookup,
        color: m.color * lookup.color,
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
                ..
            } => TexelLookup::Image {
                size: [*width, *height],
                filter: *filter,
                wrap: *wrap,
                wrapped: l.wrapped,
                address: l.address,
                texels: l.texels[..l.count]
                    .iter()
                    .map(|(at, c, w)| Texel {
                        at: *at,
                        color: c.to_array(),
                        weight: *w,
                    })
                    .collect(),
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
        }
    }
}
