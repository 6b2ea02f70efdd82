//! What a texture lookup records: how the hit's texture coordinates were found
//! ([`UvMapping`]) and how the texture was read at them ([`TexelLookup`]). The `Texture` step
//! ([`super::Step::Texture`]) holds both; `trace::texture` computes them.

use crate::scene::{Filter, Wrap};
use serde::{Deserialize, Serialize};

/// How a hit's texture coordinates (u, v) were found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum UvMapping {
    /// A triangle's vertex texture coordinates blended with the hit's barycentrics:
    /// (1 − b₁ − b₂)·t₀ + b₁·t₁ + b₂·t₂.
    VertexUvs,
    /// A triangle without vertex texture coordinates: (u, v) are the hit's barycentrics.
    Barycentric,
    /// A sphere's longitude and latitude: from the outward unit direction d,
    /// u = (atan2(−d_z, d_x) + π) / 2π and v = atan2(√(d_x² + d_z²), −d_y) / π.
    Sphere,
    /// A plane's own coordinates: the point's components along two axes in the plane.
    Plane,
}

impl UvMapping {
    /// The mapping's name in words.
    pub fn name(self) -> &'static str {
        match self {
            UvMapping::VertexUvs => "the vertices' texture coordinates",
            UvMapping::Barycentric => "the barycentric coordinates",
            UvMapping::Sphere => "the sphere's longitude and latitude",
            UvMapping::Plane => "the plane's coordinates",
        }
    }
}

fn is_zero(x: &u32) -> bool {
    *x == 0
}

/// One texel read by an image lookup.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Texel {
    /// The mip level it is in (0, the image itself, unless the lookup is trilinear).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub level: u32,
    /// Column and row (row 0 at the top of the image).
    pub at: [u32; 2],
    /// Its linear colour.
    #[serde(with = "crate::jsonf")]
    pub color: [f32; 3],
    /// Its weight within its level (1 for the nearest texel; a level's bilinear weights sum to
    /// 1).
    #[serde(with = "crate::jsonf")]
    pub weight: f32,
}

/// A roughness texture's read (the `Texture` step of a glossy BSDF's `roughness_texture`): the
/// roughness there is the material's times the texel's green channel.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RoughnessRead {
    /// The material's `roughness`.
    #[serde(with = "crate::jsonf")]
    pub material: f32,
    /// The roughness at the hit: `material` × the texel's green channel (α = roughness², or a
    /// mirror below the glossy BSDF's least roughness).
    #[serde(with = "crate::jsonf")]
    pub roughness: f32,
}

/// How a texture was read at (u, v).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum TexelLookup {
    /// A checker: the square (i, j) = (⌊u·squares₀⌋, ⌊v·squares₁⌋), odd when i + j is.
    Checker {
        /// Squares per unit of u and of v.
        squares: [u32; 2],
        /// ⌊u·squares₀⌋ and ⌊v·squares₁⌋ (as floats: a plane's coordinates may be large).
        #[serde(with = "crate::jsonf")]
        cell: [f32; 2],
        /// Whether i + j is odd (the square takes the second colour).
        odd: bool,
        /// The even and the odd squares' colours.
        #[serde(with = "crate::jsonf")]
        colors: [[f32; 3]; 2],
    },
    /// An image.
    Image {
        /// Width and height in texels.
        size: [u32; 2],
        /// Nearest or bilinear.
        filter: Filter,
        /// Repeat, clamp or mirror.
        wrap: Wrap,
        /// (u, v) after the wrap mode, in [0, 1].
        #[serde(with = "crate::jsonf")]
        wrapped: [f32; 2],
        /// The point in texel units, x = u·width and y = (1 − v)·height (row 0 at the top),
        /// at the level read (the first level a trilinear lookup read); texel (i, j)'s centre
        /// is at (i + ½, j + ½).
        #[serde(with = "crate::jsonf")]
        address: [f32; 2],
        /// The texels read: one (nearest), or four with their bilinear weights, in the order
        /// (x₀, y₀), (x₀ + 1, y₀), (x₀, y₀ + 1), (x₀ + 1, y₀ + 1); a trilinear lookup's four
        /// in its first level, then four in its second.
        texels: Vec<Texel>,
        /// A trilinear lookup's level of detail from the ray cone.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        lod: Option<LodRecord>,
    },
}

/// How a trilinear lookup chose its mip levels from the ray cone (Akenine-Möller et al., *Ray
/// Tracing Gems*, ch. 20).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LodRecord {
    /// γ, the angle one pixel subtends at the eye (radians).
    #[serde(with = "crate::jsonf")]
    pub spread: f32,
    /// d, the path length from the eye to the hit.
    #[serde(with = "crate::jsonf")]
    pub distance: f32,
    /// W = γ·d, the cone's width at the hit.
    #[serde(with = "crate::jsonf")]
    pub width: f32,
    /// |n·d̂|, the geometric normal against the unit ray direction.
    #[serde(with = "crate::jsonf")]
    pub cos: f32,
    /// Level-0 texels per unit of surface area at the hit (of world area: on an instance, the
    /// prototype's density divided by how much M stretches the area there).
    #[serde(with = "crate::jsonf")]
    pub texels_per_area: f32,
    /// L = W·√(texels per area) / |n·d̂|, the footprint's side in level-0 texels.
    #[serde(with = "crate::jsonf")]
    pub footprint: f32,
    /// λ = log₂ L.
    #[serde(with = "crate::jsonf")]
    pub lambda: f32,
    /// The level(s) read: ⌊λ⌋ held to the pyramid, then ⌊λ⌋ + 1 where λ has a fraction.
    pub levels: Vec<MipRead>,
}

/// One mip level a trilinear lookup read.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MipRead {
    /// The level (0 is the image; each halves the one below).
    pub level: u32,
    /// Its width and height in texels.
    pub size: [u32; 2],
    /// The point in its texels, (u·wₗ, (1 − v)·hₗ).
    #[serde(with = "crate::jsonf")]
    pub address: [f32; 2],
    /// Its weight in the result: 1 − (λ − ⌊λ⌋) for the first, λ − ⌊λ⌋ for the second.
    #[serde(with = "crate::jsonf")]
    pub weight: f32,
    /// Its bilinear colour.
    #[serde(with = "crate::jsonf")]
    pub color: [f32; 3],
}
