//! Textures (`[[texture]]` in a scene file): a procedural checker, or an image (PNG or JPEG)
//! decoded from sRGB to linear once, when the scene loads. A material names one with
//! `texture = "name"`; the colour looked up at the hit multiplies the material's colour wherever
//! it is used (book/tracer.md, *Textures*). The lookup itself is in [`crate::trace::texture`].

use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::Arc;

/// The most texels all of a scene's images may hold together (2048 × 2048): 48 MiB of linear
/// RGB on the CPU, 64 MiB on the GPU (four texels in each 64-byte record of its objects buffer,
/// well under WebGPU's 128 MiB guaranteed for one storage buffer). A trilinear image's mip
/// pyramid adds at most a third to its own (85 MiB on the GPU at most) and is not counted here.
pub const MAX_TEXELS: u64 = 2048 * 2048;

/// The largest image file a texture may name.
pub const MAX_IMAGE_BYTES: u64 = 64 << 20;

/// How an image is read between texel centres (`filter`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Filter {
    /// The texel the point falls in.
    Nearest,
    /// The four texels around the point, weighted by how near their centres are.
    #[default]
    Bilinear,
    /// Mip-mapped: bilinear in the two levels of the image's pyramid whose texels are nearest
    /// the size of the ray cone's footprint, blended by where its level of detail falls between
    /// them (`trace::texture`, book/tracer.md, *Mip-mapping and ray cones*).
    Trilinear,
}

/// What texture coordinates outside [0, 1] read (`wrap`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Wrap {
    /// The image tiles: only the fraction of u and v counts.
    #[default]
    Repeat,
    /// u and v are held to [0, 1]: the edge texels stretch outwards.
    Clamp,
    /// Every other tile is flipped, so neighbouring tiles meet edge to edge.
    Mirror,
}

impl Filter {
    /// The name a scene file gives it (`nearest`, `bilinear`).
    pub fn name(self) -> &'static str {
        match self {
            Filter::Nearest => "nearest",
            Filter::Bilinear => "bilinear",
            Filter::Trilinear => "trilinear",
        }
    }
}

impl Wrap {
    /// The name a scene file gives it (`repeat`, `clamp`, `mirror`).
    pub fn name(self) -> &'static str {
        match self {
            Wrap::Repeat => "repeat",
            Wrap::Clamp => "clamp",
            Wrap::Mirror => "mirror",
        }
    }
}

/// What a texture is.
#[derive(Debug, Clone, PartialEq)]
pub enum TextureKind {
    /// A checkerboard of `squares[0]` × `squares[1]` squares per unit of u and v: the square
    /// (i, j) = (⌊u·squares₀⌋, ⌊v·squares₁⌋) has `colors[(i + j) mod 2]`.
    Checker {
        /// Squares per unit of u and of v.
        squares: [u32; 2],
        /// The colours of the even and the odd squares (linear RGB).
        colors: [Vec3; 2],
    },
    /// An image, row 0 at the top (v = 1), in linear RGB.
    Image {
        /// The file as the scene names it.
        file: String,
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
        /// Row-major texels, decoded from sRGB (the alpha channel is ignored): level 0 (the
        /// image), then the mip pyramid's smaller levels where the filter is trilinear
        /// ([`mip_levels`]).
        texels: Arc<Vec<Vec3>>,
        /// The levels in `texels`: the image alone, or its whole pyramid down to 1 × 1.
        levels: Arc<Vec<MipLevel>>,
        /// How it is read between texel centres.
        filter: Filter,
        /// What coordinates outside [0, 1] read.
        wrap: Wrap,
    },
}

/// One level of an image's mip pyramid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MipLevel {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Where its first texel is in the image's texels.
    pub offset: usize,
}

/// Builds an image's mip pyramid (level 0 is the image itself): each level halves the one below,
/// rounded down and at least 1 (as OpenGL's `glGenerateMipmap`), and each of its texels is the
/// mean of the 2 × 2 texels below it (2 × 1 or 1 × 2 once a side is 1), computed in f64 and
/// rounded once. Where a side is odd its last row or column has no texel above it and is left
/// out of the level above. Returns the levels and every level's texels, one after another.
pub fn mip_levels(width: u32, height: u32, texels: Vec<Vec3>) -> (Vec<MipLevel>, Vec<Vec3>) {
    let mut levels = vec![MipLevel {
        width,
        height,
        offset: 0,
    }];
    let mut all = texels;
    let (mut w, mut h) = (width, height);
    while w > 1 || h > 1 {
        let below = *levels.last().expect("level 0 is there");
        let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
        let (sx, sy) = (u32::from(w > 1) + 1, u32::from(h > 1) + 1);
        let offset = all.len();
        for j in 0..nh {
            for i in 0..nw {
                let mut sum = [0.0f64; 3];
                for b in 0..sy {
                    for a in 0..sx {
                        let t = all[below.offset + ((j * sy + b) * w + i * sx + a) as usize];
                        for (s, c) in sum.iter_mut().zip(t.to_array()) {
                            *s += f64::from(c);
                        }
                    }
                }
                let n = f64::from(sx * sy);
                all.push(Vec3::from(sum.map(|s| (s / n) as f32)));
            }
        }
        levels.push(MipLevel {
            width: nw,
            height: nh,
            offset,
        });
        (w, h) = (nw, nh);
    }
    (levels, all)
}

impl TextureKind {
    /// An image texture from its decoded texels, with its mip pyramid built when the filter is
    /// trilinear.
    pub fn image(
        file: String,
        width: u32,
        height: u32,
        texels: Vec<Vec3>,
        filter: Filter,
        wrap: Wrap,
    ) -> TextureKind {
        let (levels, texels) = if filter == Filter::Trilinear {
            mip_levels(width, height, texels)
        } else {
            let level = MipLevel {
                width,
                height,
                offset: 0,
            };
            (vec![level], texels)
        };
        TextureKind::Image {
            file,
            width,
            height,
            texels: Arc::new(texels),
            levels: Arc::new(levels),
            filter,
            wrap,
        }
    }
}

/// A texture of the scene, named so materials can refer to it.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    /// The name materials give in `texture = "…"`.
    pub name: String,
    /// What it is.
    pub kind: TextureKind,
}

impl Texture {
    /// The texel at column `x`, row `y` of an image (row 0 at the top); black for a checker or
    /// outside the image.
    pub fn texel(&self, x: u32, y: u32) -> Vec3 {
        self.texel_at(0, x, y)
    }

    /// The texel at column `x`, row `y` of mip level `level` (0 is the image); black for a
    /// checker, a level the image does not have, or outside the level.
    pub fn texel_at(&self, level: u32, x: u32, y: u32) -> Vec3 {
        match &self.kind {
            TextureKind::Image { texels, levels, .. } => match levels.get(level as usize) {
                Some(l) if x < l.width && y < l.height => {
                    texels[l.offset + (y * l.width + x) as usize]
                }
                _ => Vec3::ZERO,
            },
            TextureKind::Checker { .. } => Vec3::ZERO,
        }
    }

    /// An image's mip levels (level 0 alone unless its filter is trilinear); none for a checker.
    pub fn levels(&self) -> &[MipLevel] {
        match &self.kind {
            TextureKind::Image { levels, .. } => levels,
            TextureKind::Checker { .. } => &[],
        }
    }
}

/// sRGB's transfer function undone (IEC 61966-2-1): an 8- or 16-bit channel value `c` in
/// [0, 1] to linear light, computed in f64 and rounded once to f32.
pub fn srgb_to_linear(c: f64) -> f32 {
    let l = if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    };
    l as f32
}

/// Decodes an image file's bytes (PNG or JPEG) into linear texels, row 0 at the top. 8-bit and
/// 16-bit channels are both decoded through [`srgb_to_linear`] (each 8-bit value exactly once,
/// through a table). `budget`: how many texels the scene may still take ([`MAX_TEXELS`]).
pub fn decode_image(
    bytes: &[u8],
    path: &Path,
    budget: u64,
) -> Result<(u32, u32, Vec<Vec3>), String> {
    decode_image_as(bytes, path, budget, true)
}

/// [`decode_image`], with the channels read as sRGB-encoded colour (`srgb`) or as linear data
/// (`c / 255`: glTF's metallic-roughness textures hold numbers, not colours).
pub fn decode_image_as(
    bytes: &[u8],
    path: &Path,
    budget: u64,
    srgb: bool,
) -> Result<(u32, u32, Vec<Vec3>), String> {
    let decode_channel = |c: f64| if srgb { srgb_to_linear(c) } else { c as f32 };
    let unreadable = |e: &dyn std::fmt::Display| {
        format!(
            "cannot read image {}: {e} (raystep reads PNG and JPEG)",
            path.display()
        )
    };
    let reader = || {
        image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| unreadable(&e))
    };
    // The size from the header first, so that a file claiming a huge image is refused before
    // anything is allocated for it; then the decoder is held to that size's memory.
    let (w, h) = reader()?.into_dimensions().map_err(|e| unreadable(&e))?;
    if w == 0 || h == 0 {
        return Err(format!("image {} is empty ({w} × {h})", path.display()));
    }
    if u64::from(w) * u64::from(h) > budget {
        return Err(format!(
            "image {} is {w} × {h} texels; a scene's images may hold {MAX_TEXELS} texels \
             together (2048 × 2048), and {budget} are left: make it smaller",
            path.display()
        ));
    }
    let mut decode = reader()?;
    let mut limits = image::Limits::default();
    // Up to 16 bytes a texel (RGBA, 32-bit float at most) and room for the decoder's own state.
    limits.max_alloc = Some(u64::from(w) * u64::from(h) * 16 + (16 << 20));
    decode.limits(limits);
    let img = decode.decode().map_err(|e| unreadable(&e))?;
    let texels = if img.color().bytes_per_pixel() / img.color().channel_count().max(1) > 1 {
        img.to_rgb16()
            .pixels()
            .map(|p| Vec3::from(p.0.map(|c| decode_channel(f64::from(c) / 65535.0))))
            .collect()
    } else {
        let table: Vec<f32> = (0..=255u8)
            .map(|c| decode_channel(f64::from(c) / 255.0))
            .collect();
        img.to_rgb8()
            .pixels()
            .map(|p| Vec3::from(p.0.map(|c| table[c as usize])))
            .collect()
    };
    Ok((w, h, texels))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_decoding_matches_the_standards_table() {
        // IEC 61966-2-1's curve at a few 8-bit values, by hand: 0 → 0; 10/255 = 0.0392 is on
        // the linear segment, /12.92 = 0.0030353; 128/255 → 0.2158605; 255 → 1.
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(10.0 / 255.0) - 0.003_035_27).abs() < 1e-8);
        assert!((srgb_to_linear(128.0 / 255.0) - 0.215_860_5).abs() < 1e-6);
        assert_eq!(srgb_to_linear(1.0), 1.0);
    }

    /// A 4 × 2 image's pyramid by hand: level 1 is 2 × 1, each texel the mean of a 2 × 2 block;
    /// level 2 is 1 × 1, the mean of level 1's two texels (2 × 1, the height being 1 already).
    /// A 3 × 3 image drops its last row and column: level 1 is its top-left texel's block.
    #[test]
    fn mip_levels_average_the_texels_below() {
        let t = |r: f32| Vec3::new(r, 0.0, 1.0);
        let image = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0].map(t).to_vec();
        let (levels, all) = mip_levels(4, 2, image);
        let sizes: Vec<_> = levels
            .iter()
            .map(|l| (l.width, l.height, l.offset))
            .collect();
        assert_eq!(sizes, [(4, 2, 0), (2, 1, 8), (1, 1, 10)]);
        // (1 + 2 + 5 + 6)/4 = 3.5, (3 + 4 + 7 + 8)/4 = 5.5, (3.5 + 5.5)/2 = 4.5.
        assert_eq!(&all[8..], &[t(3.5), t(5.5), t(4.5)]);
        let (levels, all) = mip_levels(3, 3, (1..=9).map(|k| t(k as f32)).collect());
        assert_eq!(levels.len(), 2);
        // (1 + 2 + 4 + 5)/4 = 3.
        assert_eq!(all[levels[1].offset], t(3.0));
        let (levels, _) = mip_levels(64, 32, vec![Vec3::ZERO; 64 * 32]);
        assert_eq!(levels.len(), 7, "64 × 32, 32 × 16, … 2 × 1, 1 × 1");
    }
}
