//! Image output: sRGB encoding, atomic PNG writing, and the colour scale of visit heatmaps (drawn
//! with their legend by [`crate::diagram::heatmap`]).

use glam::Vec3;
use image::{ImageEncoder, Rgb, RgbImage};
use std::path::Path;

/// The sRGB transfer function of a linear value clamped to [0, 1] (NaN maps to 0): the one
/// encoding of images, the app's view and the 3D view's colours.
#[inline]
pub fn srgb(c: f32) -> f32 {
    // NaN never reaches an image: it maps to 0 (and the tracer never produces one).
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The sRGB transfer function of a clamped linear value, to 8 bits.
#[inline]
pub fn srgb8(c: f32) -> u8 {
    (srgb(c) * 255.0 + 0.5) as u8
}

/// A linear colour's three channels through [`srgb8`].
#[inline]
pub fn srgb8_rgb(p: Vec3) -> [u8; 3] {
    [srgb8(p.x), srgb8(p.y), srgb8(p.z)]
}

/// A linear value clamped and quantized to 8 bits without encoding (`--linear`).
#[inline]
pub fn linear8(c: f32) -> u8 {
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    (c * 255.0 + 0.5) as u8
}

/// Converts linear RGB pixels to an 8-bit image, sRGB-encoded unless `linear`.
pub fn to_rgb8(width: u32, height: u32, pixels: &[Vec3], linear: bool) -> RgbImage {
    let f = if linear { linear8 } else { srgb8 };
    RgbImage::from_fn(width, height, |x, y| {
        let p = pixels[(y * width + x) as usize];
        Rgb([f(p.x), f(p.y), f(p.z)])
    })
}

/// Encodes an image as PNG and writes it atomically. The path must end in `.png`.
pub fn write_png(path: &Path, img: &RgbImage) -> Result<(), String> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if ext.as_deref() != Some("png") {
        return Err(format!(
            "{}: the output must be a .png file",
            path.display()
        ));
    }
    let mut bytes = vec![];
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(
            img.as_raw(),
            img.width(),
            img.height(),
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| format!("{}: cannot encode PNG: {e}", path.display()))?;
    crate::io::write_atomic(path, &bytes)
}

/// Whether a path names an OpenEXR file (`.exr`, any case).
pub fn is_exr(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

/// Writes linear RGB as a 32-bit float OpenEXR file, atomically (the image crate's encoder): the
/// render's own numbers, for comparison outside raystep.
pub fn write_exr(path: &Path, width: u32, height: u32, pixels: &[Vec3]) -> Result<(), String> {
    let data: Vec<f32> = pixels.iter().flat_map(|p| p.to_array()).collect();
    let img = image::Rgb32FImage::from_raw(width, height, data)
        .ok_or_else(|| format!("{}: the image is not {width}×{height}", path.display()))?;
    let mut bytes = std::io::Cursor::new(vec![]);
    image::DynamicImage::ImageRgb32F(img)
        .write_to(&mut bytes, image::ImageFormat::OpenExr)
        .map_err(|e| format!("{}: cannot encode OpenEXR: {e}", path.display()))?;
    crate::io::write_atomic(path, bytes.get_ref())
}

/// Reads an OpenEXR file's RGB channels as linear floats: (width, height, pixels).
pub fn read_exr(path: &Path) -> Result<(u32, u32, Vec<Vec3>), String> {
    let img = image::open(path)
        .map_err(|e| format!("{}: cannot read OpenEXR: {e}", path.display()))?
        .into_rgb32f();
    let (w, h) = img.dimensions();
    let px = img
        .pixels()
        .map(|p| Vec3::new(p.0[0], p.0[1], p.0[2]))
        .collect();
    Ok((w, h, px))
}

/// The colour scale of a visit-count heatmap: it tops out at the 99th percentile so a few very
/// busy pixels do not flatten everything else (pixels above it show in the top colour).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeatScale {
    /// The count shown in the top colour: the 99th percentile, at least 1.
    pub top: u32,
    /// The largest count.
    pub max: u32,
    /// The mean count per pixel.
    pub mean: f64,
}

impl HeatScale {
    /// The scale of these per-pixel counts.
    pub fn of(visits: &[u32]) -> HeatScale {
        let mut sorted = visits.to_vec();
        sorted.sort_unstable();
        let max = sorted.last().copied().unwrap_or(0);
        let top = sorted
            .get(sorted.len().saturating_sub(1) * 99 / 100)
            .copied()
            .unwrap_or(0)
            .max(1);
        let mean = visits.iter().map(|&v| v as f64).sum::<f64>() / visits.len().max(1) as f64;
        HeatScale { top, max, mean }
    }

    /// The colour of a count (viridis: 0 dark purple, `top` and above yellow).
    pub fn color(&self, v: u32) -> [u8; 3] {
        self.color_at(v as f32 / self.top as f32)
    }

    /// The colour at a fraction of the scale (clamped to 0 … 1).
    pub fn color_at(&self, f: f32) -> [u8; 3] {
        let f = if f.is_nan() { 0.0 } else { f.clamp(0.0, 1.0) };
        let c = colorous::VIRIDIS.eval_continuous(f as f64);
        [c.r, c.g, c.b]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_reference_points() {
        // sRGB (IEC 61966-2-1): 0 → 0, 1 → 255, 0.5 linear → 0.7354 → 188, 0.0031308 → 0.04045 → 10.
        assert_eq!(srgb8(0.0), 0);
        assert_eq!(srgb8(1.0), 255);
        assert_eq!(srgb8(0.5), 188);
        assert_eq!(srgb8(0.003_130_8), 10);
        assert_eq!(srgb8(f32::NAN), 0);
        assert_eq!(srgb8(7.0), 255);
        assert_eq!(linear8(0.5), 128);
    }
}
