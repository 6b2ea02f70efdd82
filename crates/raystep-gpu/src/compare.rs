//! CPU against GPU: the error figures and the difference image, both computed on the 8-bit
//! sRGB values each side's linear colour encodes to (with the same [`srgb8_rgb`]), i.e. what a
//! PNG of either render would hold.

use crate::render::image::srgb8_rgb;
use glam::Vec3;
use image::{Rgb, RgbImage};

/// How far two renders of the same scene are apart.
#[derive(Debug, Clone)]
pub struct Difference {
    /// Root mean square of the per-channel differences, as a fraction of full scale (1/255 is
    /// one 8-bit step).
    pub rmse: f64,
    /// The largest per-channel difference, in 8-bit steps (0–255).
    pub max_error: u8,
    /// Pixels where any channel differs.
    pub differing_pixels: usize,
    /// Pixels compared.
    pub pixels: usize,
    /// Where the differences are: equal pixels in dim grey (the CPU image's luminance at a
    /// quarter brightness, for orientation), differing pixels in colour from dark red (one step)
    /// to yellow (16 steps or more).
    pub image: RgbImage,
}

impl Difference {
    /// A one-line summary: "RMSE 0.12/255, max error 3/255, 17 of 19200 pixels differ".
    pub fn summary(&self) -> String {
        format!(
            "RMSE {:.3}/255, max error {}/255, {} of {} pixels differ ({:.3}%)",
            self.rmse * 255.0,
            self.max_error,
            self.differing_pixels,
            self.pixels,
            100.0 * self.differing_pixels as f64 / self.pixels.max(1) as f64
        )
    }
}

/// Compares two linear images of `width` × `height` (row-major from the top-left). Returns an
/// error message when the sizes disagree.
pub fn difference(
    width: u32,
    height: u32,
    cpu: &[Vec3],
    gpu: &[Vec3],
) -> Result<Difference, String> {
    let n = (width * height) as usize;
    if cpu.len() != n || gpu.len() != n {
        return Err(format!(
            "cannot compare images of {} and {} pixels at {width}×{height}",
            cpu.len(),
            gpu.len()
        ));
    }
    let enc = srgb8_rgb;
    let mut sum_sq = 0.0f64;
    let mut max_error = 0u8;
    let mut differing = 0;
    let mut image = RgbImage::new(width, height);
    for (i, (a, b)) in cpu.iter().zip(gpu).enumerate() {
        let (a, b) = (enc(*a), enc(*b));
        let mut worst = 0u8;
        for c in 0..3 {
            let e = a[c].abs_diff(b[c]);
            worst = worst.max(e);
            sum_sq += (e as f64 / 255.0).powi(2);
        }
        max_error = max_error.max(worst);
        let (x, y) = (i as u32 % width, i as u32 / width);
        let px = if worst == 0 {
            let lum = (0.2126 * a[0] as f32 + 0.7152 * a[1] as f32 + 0.0722 * a[2] as f32) / 4.0;
            Rgb([lum as u8; 3])
        } else {
            differing += 1;
            let c = colorous::INFERNO.eval_continuous(0.35 + 0.65 * (worst.min(16) as f64 / 16.0));
            Rgb([c.r, c.g, c.b])
        };
        image.put_pixel(x, y, px);
    }
    Ok(Difference {
        rmse: (sum_sq / (3 * n.max(1)) as f64).sqrt(),
        max_error,
        differing_pixels: differing,
        pixels: n,
        image,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_by_hand() {
        // Two pixels; the second differs by one 8-bit step in red (linear 1.0 → 255 vs 0.5 → 188
        // would be far more; pick values that encode to 255 and 254: linear 1.0 and 0.9922).
        let cpu = [Vec3::ZERO, Vec3::ONE];
        let gpu = [Vec3::ZERO, Vec3::new(0.9922, 1.0, 1.0)];
        assert_eq!(crate::render::image::srgb8(0.9922), 254);
        let d = difference(2, 1, &cpu, &gpu).unwrap();
        assert_eq!((d.max_error, d.differing_pixels, d.pixels), (1, 1, 2));
        // One channel of six off by 1/255: RMSE = √(1/6)/255.
        assert!((d.rmse * 255.0 - (1.0f64 / 6.0).sqrt()).abs() < 1e-9);
        assert!(difference(3, 1, &cpu, &gpu).is_err());
    }
}
