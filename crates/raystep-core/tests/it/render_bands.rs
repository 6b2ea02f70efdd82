//! A render in bands of tiles (`Progressive::in_bands`, the browser's way: each step a few tiles
//! on the page's thread) ends on `render`'s image and figures bit for bit, shows its tiles on the
//! live view as they finish, counts its progress right and stops between bands when cancelled.
//! The expected values come from `render` (every tile at once, on every core).

use super::render_common::{assert_live_shows, assert_same, bits, counted, shipped};
use raystep_core::PreparedScene;
use raystep_core::render::{
    BandSize, CANCELLED, LiveRender, Progressive, RenderOptions, Stepped, render,
};
use raystep_core::scene::Integrator;
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::Duration;

/// The render's tile size (16 × 16 pixels), as the docs of `raystep_core::render::cpu` give it.
const TILE: u32 = 16;

/// How many pixels of the live view have been shown (opaque).
fn shown(live: &LiveRender) -> usize {
    live.pixels
        .lock()
        .unwrap()
        .iter()
        .filter(|p| p[3] == 255)
        .count()
}

/// Pixels in the first `k` tiles of a `width` × `height` image in tile order (tile rows top to
/// bottom, left to right; the right and bottom tiles cut by the image's edge).
fn pixels_of_tiles(width: u32, height: u32, k: usize) -> usize {
    let across = width.div_ceil(TILE) as usize;
    (0..k)
        .map(|i| {
            let (tx, ty) = ((i % across) as u32, (i / across) as u32);
            let w = (width - tx * TILE).min(TILE);
            let h = (height - ty * TILE).min(TILE);
            (w * h) as usize
        })
        .sum()
}

/// A Whitted render with antialiasing (4 samples per pixel), 37 × 21 so that the right column
/// and the bottom row of tiles are cut (3 × 2 tiles), stepped 4 tiles a band: two bands (the
/// second of the last 2 tiles), each shown on the live view as it finishes and counted in its
/// progress, and the image, visits and counts of `render`.
#[test]
fn a_whitted_render_in_bands_is_render_s_image() {
    let mut s = shipped("mirror-glass.toml", 37, 21);
    s.settings.spp = 4;
    assert_eq!(s.settings.integrator, Integrator::Whitted);
    let prepared = PreparedScene::new(s);
    let tracer = prepared.tracer();
    let want = render(&tracer, &counted(None)).unwrap();
    // Antialiased: not every pixel's samples agree (else this would test one sample).
    let mut one = prepared.scene().clone();
    one.settings.spp = 1;
    let single = render(&PreparedScene::new(one).tracer(), &counted(None)).unwrap();
    assert_ne!(bits(&single), bits(&want));

    let live = Arc::new(LiveRender::new(37, 21));
    let mut p =
        Progressive::whole(&tracer, &counted(Some(live.clone()))).in_bands(BandSize::Tiles(4));
    assert_eq!(live.tiles_total.load(Ordering::Relaxed), 6);
    assert_eq!(shown(&live), 0);
    let mut passes = vec![];
    let first = p.next_step(&tracer, |done, _| passes.push(done)).unwrap();
    assert_eq!(first, Some(Stepped::Band));
    assert_eq!(live.tiles_done.load(Ordering::Relaxed), 4);
    assert_eq!(shown(&live), pixels_of_tiles(37, 21, 4));
    let second = p.next_step(&tracer, |done, _| passes.push(done)).unwrap();
    assert_eq!(second, Some(Stepped::Pass(4)));
    assert_eq!(
        p.next_step(&tracer, |_, _| panic!("no pass is left"))
            .unwrap(),
        None
    );
    assert_eq!(passes, [4]);
    assert_eq!(live.tiles_done.load(Ordering::Relaxed), 6);
    assert_eq!(live.progress(), 1.0);
    // A render in one pass says nothing of samples (the app's "k of N samples" is for passes).
    assert_eq!(live.samples_total.load(Ordering::Relaxed), 0);
    let got = p.finish().unwrap();
    assert_same(&got, &want);
    // The live view ends on the finished image, in sRGB.
    assert_live_shows(&live, &want);
}

/// A Monte Carlo render (the Cornell box with its area light, path traced, 5 samples per pixel,
/// 37 × 21) stepped one tile a band: passes of 1, 1, 2 and 1 samples, 6 bands each; the samples
/// done and the tile-samples done count up as the app's "k of N samples" line and progress bar
/// read them, and the finished image, visits and counts are `render`'s.
#[test]
fn a_monte_carlo_render_in_bands_is_render_s_image() {
    let mut s = shipped("cornell-area.toml", 37, 21);
    s.settings.spp = 5;
    s.settings.seed = 3;
    assert_eq!(s.settings.integrator, Integrator::Path);
    let prepared = PreparedScene::new(s);
    let tracer = prepared.tracer();
    let want = render(&tracer, &counted(None)).unwrap();

    let live = Arc::new(LiveRender::new(37, 21));
    let mut p =
        Progressive::new(&tracer, &counted(Some(live.clone()))).in_bands(BandSize::Tiles(1));
    assert_eq!(live.tiles_total.load(Ordering::Relaxed), 6 * 5);
    assert_eq!(live.samples_total.load(Ordering::Relaxed), 5);
    let (mut steps, mut passes) = (vec![], vec![]);
    // The passes' samples: 1, 1, 2, 1 (ending at 1, 2, 4, 5).
    let samples = [1, 1, 2, 1];
    let mut tile_samples = 0;
    while let Some(step) = p.next_step(&tracer, |done, _| passes.push(done)).unwrap() {
        steps.push(step);
        // The pass this band belongs to: the passes finished before it.
        let k = passes.len() - usize::from(matches!(step, Stepped::Pass(_)));
        // Each band's tile counts once per sample of its pass.
        tile_samples += samples[k];
        assert_eq!(live.tiles_done.load(Ordering::Relaxed), tile_samples);
        assert_eq!(
            live.samples_done.load(Ordering::Relaxed),
            passes.last().copied().unwrap_or(0)
        );
    }
    let band = Stepped::Band;
    let pass = |k| [band, band, band, band, band, Stepped::Pass(k)];
    assert_eq!(steps, [pass(1), pass(2), pass(4), pass(5)].concat());
    assert_eq!(passes, [1, 2, 4, 5]);
    assert_eq!(live.progress(), 1.0);
    assert_same(&p.finish().unwrap(), &want);
}

/// Visits counted per pixel (the heatmap) on a scene with a BVH of 120 spheres: a band render
/// gives `render`'s counts, pixel by pixel, whatever the band size: one tile, a prime number of
/// tiles that ends bands mid-row, a band of no time at all (one tile each) and one of an hour
/// (the whole image).
#[test]
fn node_visits_in_bands_are_render_s() {
    let s = shipped("teapot-stadium.toml", 45, 35);
    let prepared = PreparedScene::new(s);
    let tracer = prepared.tracer();
    let want = render(&tracer, &counted(None)).unwrap();
    let visits = want.node_visits.as_ref().unwrap();
    assert!(visits.iter().filter(|&&v| v > 0).count() > visits.len() / 2);
    let tiles = 3 * 3;
    for (size, bands) in [
        (BandSize::Tiles(1), tiles),
        (BandSize::Tiles(5), 2),
        (BandSize::Time(Duration::ZERO), tiles),
        (BandSize::Time(Duration::from_secs(3600)), 1),
    ] {
        let mut p = Progressive::whole(&tracer, &counted(None)).in_bands(size);
        let mut steps = 0;
        while p.next_step(&tracer, |_, _| {}).unwrap().is_some() {
            steps += 1;
        }
        assert_eq!(steps, bands, "{size:?}");
        assert_same(&p.finish().unwrap(), &want);
    }
}

/// Uncounted, the same: no visits, and the pixels of `render`; `next_pass` finishes a pass in
/// bands as `next_step` would.
#[test]
fn an_uncounted_render_in_bands_is_render_s_too() {
    let mut s = shipped("soft-shadows.toml", 33, 17);
    s.settings.spp = 3;
    let prepared = PreparedScene::new(s);
    let tracer = prepared.tracer();
    let want = render(&tracer, &RenderOptions::default()).unwrap();
    assert_eq!(want.node_visits, None);
    let mut p = Progressive::new(&tracer, &RenderOptions::default()).in_bands(BandSize::Tiles(2));
    let mut passes = vec![];
    while let Some(done) = p.next_pass(&tracer, |done, _| passes.push(done)).unwrap() {
        assert_eq!(passes.last(), Some(&done));
    }
    assert_eq!(passes, [1, 2, 3]);
    assert_same(&p.finish().unwrap(), &want);
}

/// Cancelled after its second band, a render in bands returns the cancellation at its next step
/// and traces no more tiles; so does one cancelled before its first band.
#[test]
fn a_cancelled_render_in_bands_stops_between_bands() {
    let mut s = shipped("cornell-area.toml", 40, 40);
    s.settings.spp = 4;
    let prepared = PreparedScene::new(s);
    let tracer = prepared.tracer();
    let live = Arc::new(LiveRender::new(40, 40));
    let mut p =
        Progressive::new(&tracer, &counted(Some(live.clone()))).in_bands(BandSize::Tiles(2));
    for _ in 0..2 {
        assert_eq!(
            p.next_step(&tracer, |_, _| {}).unwrap(),
            Some(Stepped::Band)
        );
    }
    assert_eq!(live.tiles_done.load(Ordering::Relaxed), 4);
    live.cancel.store(true, Ordering::Relaxed);
    assert_eq!(p.next_step(&tracer, |_, _| {}), Err(CANCELLED.to_string()));
    assert_eq!(live.tiles_done.load(Ordering::Relaxed), 4);
    assert_eq!(shown(&live), pixels_of_tiles(40, 40, 4));

    let live = Arc::new(LiveRender::new(40, 40));
    live.cancel.store(true, Ordering::Relaxed);
    let mut p =
        Progressive::whole(&tracer, &counted(Some(live.clone()))).in_bands(BandSize::Tiles(2));
    assert_eq!(p.next_step(&tracer, |_, _| {}), Err(CANCELLED.to_string()));
    assert_eq!(live.tiles_done.load(Ordering::Relaxed), 0);
}
