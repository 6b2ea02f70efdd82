//! The heatmap of accelerator visits per pixel (BVH nodes, bounding spheres tested, grid cells
//! entered), with a legend strip
//! underneath: a title with the mean and the maximum, and the colour bar with its scale. The
//! legend's text is drawn by the diagrams' one text renderer ([`super::Canvas`]).

use super::canvas::{Anchor, Canvas, Theme};
use crate::record::number::{Style, fmt64};
use crate::render::RenderOutput;
use crate::render::image::HeatScale;
use image::{Rgb, RgbImage};

/// The heatmap of `out`'s per-pixel visit counts, or None when the render did not count them.
/// `what` names what was visited: "BVH nodes", "bounding spheres", "grid cells".
pub fn heatmap(out: &RenderOutput, what: &str) -> Option<RgbImage> {
    let visits = out.node_visits.as_ref()?;
    let scale = HeatScale::of(visits);
    let (w, h) = (out.width, out.height);
    let size = (w as f32 / 40.0).clamp(11.0, 22.0);
    let legend_h = (size * 3.2) as u32;
    let mut img = RgbImage::from_pixel(w, h + legend_h, Rgb([255, 255, 255]));
    for (i, &v) in visits.iter().enumerate() {
        let (x, y) = (i as u32 % w.max(1), i as u32 / w.max(1));
        if y < h {
            img.put_pixel(x, y, Rgb(scale.color(v)));
        }
    }
    let legend = legend(&scale, what, w, legend_h, size);
    for (x, y, p) in legend.enumerate_pixels() {
        img.put_pixel(x, h + y, Rgb([p[0], p[1], p[2]]));
    }
    Some(img)
}

/// The legend strip, `width` × `height` pixels.
fn legend(scale: &HeatScale, what: &str, width: u32, height: u32, size: f32) -> image::RgbaImage {
    let mut c = Canvas::new(width, height, Theme::LIGHT);
    let ink = Theme::LIGHT.ink;
    let pad = size * 0.5;
    let title = format!(
        "{what} visited per pixel (mean {}, max {})",
        fmt64(scale.mean, Style::Decimals(1)),
        scale.max
    );
    let title = c.elide(&title, size, width as f32 - 2.0 * pad);
    c.text(pad, pad * 0.4, size, &title, ink, Anchor::TopLeft);
    let bar_y = size * 1.6;
    let bar_h = size * 0.7;
    let lo = "0";
    let hi = if scale.max > scale.top {
        format!("≥{} (p99)", scale.top)
    } else {
        format!("{}", scale.top)
    };
    let x0 = pad + c.text_width(lo, size) + pad;
    let x1 = (width as f32 - pad - c.text_width(&hi, size) - pad).max(x0 + 2.0);
    // One rectangle per pixel column of the bar.
    let columns = (x1 - x0).ceil() as u32;
    for i in 0..columns {
        let [r, g, b] = scale.color_at(i as f32 / columns.max(1) as f32);
        c.rect(x0 + i as f32, bar_y, 1.0, bar_h, [r, g, b, 255]);
    }
    let ty = bar_y + bar_h * 0.5;
    c.text(pad, ty, size, lo, ink, Anchor::MiddleLeft);
    c.text(x1 + pad, ty, size, &hi, ink, Anchor::MiddleLeft);
    c.to_rgba_image()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Counts 0 … 99 over a 10×10 image: the top colour is the 99th percentile (98 here, by
    /// nearest rank on 0-based indices), the legend sits under the image, and a pixel's colour is
    /// the scale's colour of its count.
    #[test]
    fn heatmap_pixels_follow_the_scale_and_the_legend_sits_below() {
        let out = RenderOutput {
            width: 10,
            height: 10,
            pixels: vec![],
            node_visits: Some((0..100).collect()),
            stats: Default::default(),
        };
        let img = heatmap(&out, "BVH nodes").unwrap();
        assert_eq!(img.width(), 10);
        assert!(img.height() > 10);
        let scale = HeatScale::of(&(0..100).collect::<Vec<u32>>());
        assert_eq!((scale.top, scale.max), (98, 99));
        assert_eq!(scale.mean, 49.5);
        assert_eq!(img.get_pixel(3, 2).0, scale.color(23));
        assert_eq!(img.get_pixel(9, 9).0, scale.color_at(1.0));
    }
}
