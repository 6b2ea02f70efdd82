//! Textures (`[[texture]]` in a scene file): a procedural checker, or an image (PNG or JPEG)
//! decoded from sRGB to linear once, when the scene loads. A material names one with
//! `texture = "name"`; the colour looked up at the hit multiplies the material's colour wherever
//! it is used (README.md, *Textures*). The lookup itself is in [`crate::trace::texture`].

use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::Arc;

/// The most texels all of a scene's images may hold together (2048 × 2048): 48 MiB of linear
/// RGB on the CPU, 64 MiB on the GPU (four texels in each 64-byte record of its objects buffer,
/// well under WebGPU's 128 MiB guaranteed for one storage buffer).
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
        /// Row-major texels, decoded from sRGB (the alpha channel is ignored).
        texels: Arc<Vec<Vec3>>,
        /// How it is read between texel centres.
        filter: Filter,
        /// What coordinates outside [0, 1] read.
        wrap: Wrap,
    },
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
        match &self.kind {
            TextureKind::Image {
                width,
                height,
                texels,
                ..
            } if x < *width && y < *height => texels[(y * width + x) as usize],
            _ => Vec3::ZERO,
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
            .map(|p| Vec3::from(p.0.map(|c| srgb_to_linear(f64::from(c) / 65535.0))))
            .collect()
    } else {
        let table: Vec<f32> = (0..=255u8)
            .map(|c| srgb_to_linear(f64::from(c) / 255.0))
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
}
