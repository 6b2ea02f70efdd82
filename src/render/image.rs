//! Image output: sRGB encoding, atomic PNG writing, and the BVH-visit heatmap with its legend.

use super::RenderOutput;
use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use glam::Vec3;
use image::{ImageEncoder, Rgb, RgbImage};
use std::path::Path;

/// The sRGB transfer function of a clamped linear value, to 8 bits.
#[inline]
pub fn srgb8(c: f32) -> u8 {
    // NaN never reaches an image: it maps to 0 (and the tracer never produces one).
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
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

/// The font labels are drawn with (Hack, shipped inside the `epaint_default_fonts` crate).
pub fn label_font() -> FontRef<'static> {
    FontRef::try_from_slice(epaint_default_fonts::HACK_REGULAR).expect("the bundled font parses")
}

/// Draws `text` with its top-left corner at (x, y), `size` pixels high, blending `color` over the
/// image by glyph coverage.
pub fn draw_text(img: &mut RgbImage, x: f32, y: f32, size: f32, text: &str, color: [u8; 3]) {
    let font = label_font();
    let scaled = font.as_scaled(PxScale::from(size));
    let mut caret = x;
    let baseline = y + scaled.ascent();
    for ch in text.chars() {
        let id = scaled.glyph_id(ch);
        let glyph = id.with_scale_and_position(PxScale::from(size), point(caret, baseline));
        caret += scaled.h_advance(id);
        if let Some(outline) = font.outline_glyph(glyph) {
            let b = outline.px_bounds();
            outline.draw(|gx, gy, cov| {
                let px = b.min.x as i32 + gx as i32;
                let py = b.min.y as i32 + gy as i32;
                if px >= 0 && py >= 0 && (px as u32) < img.width() && (py as u32) < img.height() {
                    let p = img.get_pixel_mut(px as u32, py as u32);
                    for (ch, &target) in p.0.iter_mut().zip(&color) {
                        *ch = (*ch as f32 * (1.0 - cov) + target as f32 * cov).round() as u8;
                    }
                }
            });
        }
    }
}

/// The width in pixels of `text` at `size`.
pub fn text_width(size: f32, text: &str) -> f32 {
    let font = label_font();
    let scaled = font.as_scaled(PxScale::from(size));
    text.chars()
        .map(|c| scaled.h_advance(scaled.glyph_id(c)))
        .sum()
}

/// The heatmap of BVH node visits per pixel (viridis, 0 = dark purple, the 99th percentile and
/// above = yellow), with a legend strip underneath: the colour bar, its scale, the mean and max.
pub fn heatmap(out: &RenderOutput) -> Option<RgbImage> {
    let visits = out.node_visits.as_ref()?;
    // The colour scale tops out at the 99th percentile so a few very busy pixels do not flatten
    // everything else; pixels above it show in the top colour.
    let mut sorted = visits.clone();
    sorted.sort_unstable();
    let true_max = sorted.last().copied().unwrap_or(0);
    let max = sorted
        .get(sorted.len().saturating_sub(1) * 99 / 100)
        .copied()
        .unwrap_or(0)
        .max(1);
    let mean = visits.iter().map(|&v| v as f64).sum::<f64>() / visits.len().max(1) as f64;
    let (w, h) = (out.width, out.height);
    let size = (w as f32 / 40.0).clamp(11.0, 22.0);
    let legend = (size * 3.2) as u32;
    let mut img = RgbImage::from_pixel(w, h + legend, Rgb([255, 255, 255]));
    let map = |v: f32| {
        let c = colorous::VIRIDIS.eval_continuous(v.clamp(0.0, 1.0) as f64);
        Rgb([c.r, c.g, c.b])
    };
    for y in 0..h {
        for x in 0..w {
            img.put_pixel(x, y, map(visits[(y * w + x) as usize] as f32 / max as f32));
        }
    }
    // Legend: title, then a bar from 0 to max with end labels.
    let pad = size * 0.5;
    let title = format!("BVH node visits per pixel (mean {mean:.1}, max {true_max})");
    draw_text(&mut img, pad, h as f32 + pad * 0.4, size, &title, [0, 0, 0]);
    let bar_y0 = h + (size * 1.6) as u32;
    let bar_h = (size * 0.7) as u32;
    let lo_label = "0";
    let hi_label = if true_max > max {
        format!("≥{max} (p99)")
    } else {
        format!("{max}")
    };
    let bx0 = (pad + text_width(size, lo_label) + pad) as u32;
    let bx1 = (w as f32 - pad - text_width(size, &hi_label) - pad).max(bx0 as f32 + 2.0) as u32;
    for x in bx0..bx1.min(w) {
        let c = map((x - bx0) as f32 / (bx1 - bx0).max(1) as f32);
        for y in bar_y0..(bar_y0 + bar_h).min(h + legend) {
            img.put_pixel(x, y, c);
        }
    }
    let ty = bar_y0 as f32 + bar_h as f32 * 0.5 - size * 0.6;
    draw_text(&mut img, pad, ty, size, lo_label, [0, 0, 0]);
    draw_text(&mut img, bx1 as f32 + pad, ty, size, &hi_label, [0, 0, 0]);
    Some(img)
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
