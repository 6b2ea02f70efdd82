//! What the tests of a render in steps share (`render_bands`, `render_workers`): a shipped scene at
//! a small size, counted render options, and the comparison of two finished renders.

use raystep_core::render::{LiveRender, RenderOptions, RenderOutput};
use raystep_core::scene::{Scene, load_file};
use std::path::PathBuf;
use std::sync::Arc;

/// A shipped scene (`scenes/NAME`) at `width` × `height`.
pub(crate) fn shipped(name: &str, width: u32, height: u32) -> Scene {
    let path = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("scenes")
        .join(name);
    let mut s = load_file(&path).unwrap();
    (s.camera.width, s.camera.height) = (width, height);
    s
}

/// Options that count rays, tests and visits, with `live` as the live view.
pub(crate) fn counted(live: Option<Arc<LiveRender>>) -> RenderOptions {
    RenderOptions {
        count: true,
        live,
        ..Default::default()
    }
}

/// The pixels as bits (NaN equal to itself).
pub(crate) fn bits(out: &RenderOutput) -> Vec<[u32; 3]> {
    out.pixels
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

/// Everything the app shows of a finished render is the same.
pub(crate) fn assert_same(got: &RenderOutput, want: &RenderOutput) {
    assert_eq!((got.width, got.height), (want.width, want.height));
    assert!(bits(got) == bits(want), "the pixels differ");
    assert_eq!(got.node_visits, want.node_visits);
    assert_eq!(got.stats.counts, want.stats.counts);
    assert_eq!(got.stats.nan_rays, want.stats.nan_rays);
    assert_eq!(got.stats.nan_pixels, want.stats.nan_pixels);
    assert_eq!(got.stats.bad_samples, want.stats.bad_samples);
    assert_eq!(got.stats.first_bad_sample, want.stats.first_bad_sample);
}

/// The live view ends on the finished image `want`, in sRGB, every pixel shown (opaque).
pub(crate) fn assert_live_shows(live: &LiveRender, want: &RenderOutput) {
    let srgb: Vec<[u8; 4]> = want
        .pixels
        .iter()
        .map(|c| {
            let [r, g, b] = raystep_core::render::image::srgb8_rgb(*c);
            [r, g, b, 255]
        })
        .collect();
    assert_eq!(*live.pixels.lock().unwrap(), srgb);
}
