//! The whole-image check: a student's rendered PNG against raystep's render of the same scene.

use crate::render::{RenderOptions, image, render};
use crate::trace::PreparedScene;
use ::image::{Rgb, RgbImage};
use std::path::Path;

/// How a student's image compares with raystep's.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageCheck {
    /// Pixels whose largest channel difference exceeds the tolerance.
    pub off: u64,
    /// Pixels in all.
    pub pixels: u64,
    /// The largest channel difference anywhere (0–255).
    pub max_diff: u8,
    /// The difference image: equal pixels a dim grey copy of raystep's, pixels within the
    /// tolerance grey, pixels beyond it red, brighter the larger the difference.
    pub diff: RgbImage,
}

/// raystep's render of the scene as an 8-bit sRGB image (what a student's PNG should hold).
pub fn reference(prepared: &PreparedScene) -> Result<RgbImage, String> {
    let out = render(&prepared.tracer(), &RenderOptions::default())?;
    Ok(image::to_rgb8(out.width, out.height, &out.pixels, false))
}

/// Reads the student's PNG and compares it with `reference`, channel by channel; `tolerance`
/// in levels of 255. A file that is missing, not a PNG, or of another size is an error saying so.
pub fn compare(student: &Path, reference: &RgbImage, tolerance: u8) -> Result<ImageCheck, String> {
    let bytes = std::fs::read(student)
        .map_err(|e| format!("{}: cannot read your image: {e}", student.display()))?;
    let img = ::image::load_from_memory_with_format(&bytes, ::image::ImageFormat::Png)
        .map_err(|e| format!("{}: not a PNG image: {e}", student.display()))?
        .to_rgb8();
    if img.dimensions() != reference.dimensions() {
        return Err(format!(
            "{}: your image is {}×{}, the scene's is {}×{}",
            student.display(),
            img.width(),
            img.height(),
            reference.width(),
            reference.height()
        ));
    }
    let mut off = 0;
    let mut max_diff = 0u8;
    let diff = RgbImage::from_fn(reference.width(), reference.height(), |x, y| {
        let (a, b) = (img.get_pixel(x, y).0, reference.get_pixel(x, y).0);
        let d = (0..3).map(|k| a[k].abs_diff(b[k])).max().unwrap_or(0);
        max_diff = max_diff.max(d);
        let grey = ((b[0] as u32 + b[1] as u32 + b[2] as u32) / 12) as u8;
        if d > tolerance {
            off += 1;
            Rgb([128u8.saturating_add(d / 2), 0, 0])
        } else if d > 0 {
            Rgb([96, 96, 96])
        } else {
            Rgb([grey, grey, grey])
        }
    });
    Ok(ImageCheck {
        off,
        pixels: reference.width() as u64 * reference.height() as u64,
        max_diff,
        diff,
    })
}
