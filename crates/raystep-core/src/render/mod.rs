//! Rendering the whole image: the parallel CPU renderer, and image output (sRGB PNG, heatmaps).
//!
//! ```
//! use raystep_core::PreparedScene;
//! use raystep_core::render::{RenderOptions, image, render};
//!
//! let mut scene = raystep_core::scene::default_scene();
//! (scene.camera.width, scene.camera.height) = (32, 24);
//! let prepared = PreparedScene::new(scene);
//! let out = render(&prepared.tracer(), &RenderOptions::default()).unwrap();
//! assert_eq!(out.pixels.len(), 32 * 24);
//! // Bit for bit what the recorded pixel says (one sample per pixel).
//! assert_eq!(out.pixels[12 * 32 + 16].to_array(), prepared.record(16, 12, 0).color);
//! let png = image::to_rgb8(out.width, out.height, &out.pixels, false);
//! assert_eq!(png.dimensions(), (32, 24));
//! ```

pub mod bands;
pub mod cpu;
pub mod image;
pub mod passes;
mod pool;
pub mod progressive;
mod workers;

pub use bands::BandSize;
pub use cpu::{CANCELLED, LiveRender, Pass, RenderOptions, RenderOutput, RenderStats, render};
pub use progressive::{Progressive, Stepped, render_progressive};
