//! The 3D scene view: the scene in space — its objects, lights, the camera with its image plane
//! and pixel grid — and the rays of a recorded trace drawn where the tracer sent them, up to the
//! step being shown. Every ray drawn is a ray the renderer traced: the rays come from the
//! [`Trace`], never from a second tracer.
//!
//! - [`camera`]: the view's camera (an orbit around the scene, or the scene's own camera
//!   matched exactly) and its projection;
//! - [`geometry`]: what is drawn, as plain data (a pure function of the scene, the trace and the
//!   options; the tests check it without a GPU);
//! - [`gpu`]: drawing it with wgpu into a texture (the app shows it; `raystep view` saves it).
//!
//! ```
//! use raystep_gpu::view3d::{geometry, camera::{Orbit, ViewCamera}};
//! let prepared = raystep_core::PreparedScene::new(raystep_core::scene::default_scene());
//! let trace = prepared.record(160, 120, 0);
//! let options = geometry::Options { step: Some(5), ..Default::default() };
//! let g = geometry::build(prepared.scene(), Some(&trace), &[], &options);
//! assert!(!g.rays.is_empty());
//! let cam = ViewCamera::orbit(&prepared.scene().camera, &g.bounds, &Orbit::default(), 4.0 / 3.0);
//! assert!(cam.project(g.rays[0].origin, 640.0, 480.0).is_some());
//! ```

pub mod camera;
pub mod geometry;
pub mod gpu;

use crate::record::Trace;
use crate::scene::Camera;
use crate::trace::PreparedScene;
use camera::{Bounds, Orbit, ViewCamera};
use geometry::Options;

/// The pixels of an `n`×`n` grid spread evenly over the image (cell centres), for the fan of
/// primary rays; `n` is capped at 32.
pub fn fan_pixels(camera: &Camera, n: u32) -> Vec<[u32; 2]> {
    let n = n.clamp(1, 32);
    let (w, h) = (camera.width.max(1), camera.height.max(1));
    let mut out = vec![];
    for j in 0..n {
        for i in 0..n {
            let x = ((2 * i + 1) as u64 * w as u64 / (2 * n) as u64) as u32;
            let y = ((2 * j + 1) as u64 * h as u64 / (2 * n) as u64) as u32;
            let p = [x.min(w - 1), y.min(h - 1)];
            if !out.contains(&p) {
                out.push(p);
            }
        }
    }
    out
}

/// Records the traces of the fan's pixels (`n`×`n`, sample 0).
pub fn fan_traces(prepared: &PreparedScene, n: u32) -> Vec<Trace> {
    fan_pixels(&prepared.scene().camera, n)
        .into_iter()
        .map(|[x, y]| prepared.record(x, y, 0))
        .collect()
}

/// Where the view looks from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Viewpoint {
    /// An orbit around the scene.
    Orbit(Orbit),
    /// Through the scene's camera (the view matches the render).
    Camera,
}

impl Default for Viewpoint {
    fn default() -> Self {
        Viewpoint::Orbit(Orbit::default())
    }
}

impl Viewpoint {
    /// The view camera for a picture of `aspect` (width / height). Looking through the camera
    /// keeps the camera's own aspect: draw it at the image's proportions to match the render.
    pub fn camera(&self, scene_camera: &Camera, bounds: &Bounds, aspect: f32) -> ViewCamera {
        match self {
            Viewpoint::Orbit(o) => ViewCamera::orbit(scene_camera, bounds, o, aspect),
            Viewpoint::Camera => ViewCamera::look_through(scene_camera, bounds),
        }
    }
}

/// A whole 3D view, drawn headless into an RGB image (for `raystep view`, slides and tests).
/// A picture larger than [`gpu::TILE_SIDE`] a side is drawn and read back tile by tile, so
/// the GPU never holds more than one tile's multisampled picture; `renderer.last_frame` is then
/// the tiles' drawing time together.
pub fn render_image(
    renderer: &mut gpu::Renderer,
    prepared: &PreparedScene,
    trace: Option<&Trace>,
    fan: &[Trace],
    options: &Options,
    viewpoint: Viewpoint,
    size: [u32; 2],
) -> Result<image::RgbImage, crate::GpuError> {
    render_image_in_tiles(
        renderer,
        prepared,
        trace,
        fan,
        options,
        viewpoint,
        size,
        gpu::TILE_SIDE,
    )
}

/// [`render_image`] drawn in tiles of at most `tile` pixels a side (at least 1).
#[allow(clippy::too_many_arguments)]
pub fn render_image_in_tiles(
    renderer: &mut gpu::Renderer,
    prepared: &PreparedScene,
    trace: Option<&Trace>,
    fan: &[Trace],
    options: &Options,
    viewpoint: Viewpoint,
    size: [u32; 2],
    tile: u32,
) -> Result<image::RgbImage, crate::GpuError> {
    let scene = prepared.scene();
    let cam = viewpoint.camera(
        &scene.camera,
        &geometry::bounds(scene),
        size[0] as f32 / size[1].max(1) as f32,
    );
    let options = Options {
        eye: Some(cam.eye.to_array()),
        camera: options.camera && viewpoint != Viewpoint::Camera,
        ..options.clone()
    };
    let g = geometry::build(scene, trace, fan, &options);
    let bg = options.theme.background.map(|v| f32::from(v) / 255.0);
    let tile = tile.max(1);
    let mut out = image::RgbImage::new(size[0], size[1]);
    let mut drawing = std::time::Duration::ZERO;
    for y0 in (0..size[1]).step_by(tile as usize) {
        for x0 in (0..size[0]).step_by(tile as usize) {
            let (w, h) = (tile.min(size[0] - x0), tile.min(size[1] - y0));
            renderer.draw_region(&g, &cam, size, [x0, y0, w, h], bg)?;
            drawing += renderer.last_frame;
            let part = renderer.read()?;
            for (x, y, p) in part.enumerate_pixels() {
                out.put_pixel(x0 + x, y0 + y, image::Rgb([p[0], p[1], p[2]]));
            }
        }
    }
    renderer.last_frame = drawing;
    Ok(out)
}
