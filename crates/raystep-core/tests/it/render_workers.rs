//! A render whose tiles worker threads trace while the calling thread only gathers them
//! (`Progressive::on_workers`, the browser page's way where it has Web Workers: the page's own
//! thread may not wait) ends on `render`'s image and figures bit for bit, shows every tile on the
//! live view, counts its progress, says how many threads traced it and stops when cancelled.
//! The expected values come from `render` (every tile at once, on the calling thread and its
//! pool, waiting for them). Natively the workers are rayon's global pool.

use super::render_common::{assert_live_shows, assert_same, bits, counted, shipped};
use raystep_core::PreparedScene;
use raystep_core::render::{CANCELLED, LiveRender, Progressive, RenderOptions, Stepped, render};
use raystep_core::scene::Integrator;
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

/// Steps `p` to its end as the page does, a frame at a time (here: a yield between steps that
/// took in nothing new); the steps that ended passes, and the passes `after_pass` saw.
fn step_to_the_end(
    p: &mut Progressive,
    prepared: &PreparedScene,
) -> Result<(Vec<u32>, Vec<u32>), String> {
    let tracer = prepared.tracer();
    let deadline = Instant::now() + Duration::from_secs(120);
    let (mut ends, mut passes) = (vec![], vec![]);
    while let Some(step) = p.next_step(&tracer, |done, _| passes.push(done))? {
        match step {
            Stepped::Band => std::thread::yield_now(),
            Stepped::Pass(k) => ends.push(k),
        }
        assert!(Instant::now() < deadline, "the workers never finished");
    }
    Ok((ends, passes))
}

/// A Whitted render with antialiasing (4 samples per pixel), 37 × 21 so that the right column
/// and the bottom row of tiles are cut (3 × 2 tiles), on 3 workers: the image, visits and counts
/// of `render`; every tile shown on the live view (it ends on the image in sRGB), counted in the
/// progress; 3 threads in its figures.
#[test]
fn a_whitted_render_on_workers_is_render_s_image() {
    let mut s = shipped("mirror-glass.toml", 37, 21);
    s.settings.spp = 4;
    assert_eq!(s.settings.integrator, Integrator::Whitted);
    let prepared = Arc::new(PreparedScene::new(s));
    let tracer = prepared.tracer();
    let want = render(&tracer, &counted(None)).unwrap();

    let live = Arc::new(LiveRender::new(37, 21));
    let mut p = Progressive::whole(&tracer, &counted(Some(live.clone())))
        .on_workers(Arc::clone(&prepared), 3);
    assert_eq!(live.tiles_total.load(Ordering::Relaxed), 6);
    let (ends, passes) = step_to_the_end(&mut p, &prepared).unwrap();
    assert_eq!((ends, passes), (vec![4], vec![4]));
    assert_eq!(live.tiles_done.load(Ordering::Relaxed), 6);
    let got = p.finish().unwrap();
    assert_same(&got, &want);
    assert_eq!(got.stats.threads, 3);
    assert_live_shows(&live, &want);
}

/// A Monte Carlo render (the Cornell box with its area light, path traced, 5 samples per pixel,
/// 37 × 21) on 2 workers: passes ending at 1, 2, 4 and 5 samples, the live view's samples and
/// tile-samples (6 tiles × 5) counted in full, and `render`'s image, visits and counts.
#[test]
fn a_monte_carlo_render_on_workers_is_render_s_image() {
    let mut s = shipped("cornell-area.toml", 37, 21);
    s.settings.spp = 5;
    s.settings.seed = 3;
    assert_eq!(s.settings.integrator, Integrator::Path);
    let prepared = Arc::new(PreparedScene::new(s));
    let tracer = prepared.tracer();
    let want = render(&tracer, &counted(None)).unwrap();

    let live = Arc::new(LiveRender::new(37, 21));
    let mut p =
        Progressive::new(&tracer, &counted(Some(live.clone()))).on_workers(prepared.clone(), 2);
    let (ends, passes) = step_to_the_end(&mut p, &prepared).unwrap();
    assert_eq!(ends, [1, 2, 4, 5]);
    assert_eq!(passes, [1, 2, 4, 5]);
    assert_eq!(live.tiles_done.load(Ordering::Relaxed), 6 * 5);
    assert_eq!(live.samples_done.load(Ordering::Relaxed), 5);
    assert_eq!(live.progress(), 1.0);
    assert_same(&p.finish().unwrap(), &want);
}

/// Visits counted per pixel (the heatmap) on a scene with a BVH of 120 spheres, on 1, 2 and 7
/// workers (more workers than the machine's cores, and 9 tiles): `render`'s counts, pixel by
/// pixel; uncounted, `render`'s pixels and no visits.
#[test]
fn node_visits_on_workers_are_render_s() {
    let prepared = Arc::new(PreparedScene::new(shipped("teapot-stadium.toml", 45, 35)));
    let tracer = prepared.tracer();
    let want = render(&tracer, &counted(None)).unwrap();
    let visits = want.node_visits.as_ref().unwrap();
    assert!(visits.iter().filter(|&&v| v > 0).count() > visits.len() / 2);
    for workers in [1, 2, 7] {
        let mut p =
            Progressive::whole(&tracer, &counted(None)).on_workers(prepared.clone(), workers);
        step_to_the_end(&mut p, &prepared).unwrap();
        assert_same(&p.finish().unwrap(), &want);
    }
    let plain = render(&tracer, &RenderOptions::default()).unwrap();
    let mut p =
        Progressive::new(&tracer, &RenderOptions::default()).on_workers(prepared.clone(), 2);
    step_to_the_end(&mut p, &prepared).unwrap();
    let got = p.finish().unwrap();
    assert_eq!(got.node_visits, None);
    assert!(bits(&got) == bits(&plain));
}

/// Cancelled while its workers trace, a render on workers returns the cancellation at its next
/// step and shows no tile after it; so does one cancelled before its first step (which then
/// starts no worker: nothing is ever shown).
#[test]
fn a_cancelled_render_on_workers_stops() {
    let mut s = shipped("cornell-area.toml", 64, 64);
    s.settings.spp = 16;
    let prepared = Arc::new(PreparedScene::new(s));
    let tracer = prepared.tracer();
    let live = Arc::new(LiveRender::new(64, 64));
    let mut p =
        Progressive::new(&tracer, &counted(Some(live.clone()))).on_workers(prepared.clone(), 2);
    assert_eq!(
        p.next_step(&tracer, |_, _| {}).unwrap(),
        Some(Stepped::Band)
    );
    live.cancel.store(true, Ordering::Relaxed);
    let done = live.tiles_done.load(Ordering::Relaxed);
    assert_eq!(p.next_step(&tracer, |_, _| {}), Err(CANCELLED.to_string()));
    std::thread::sleep(Duration::from_millis(50));
    assert_eq!(live.tiles_done.load(Ordering::Relaxed), done);
    assert!(
        done < 16 * 16,
        "the render finished before it was cancelled"
    );

    let live = Arc::new(LiveRender::new(64, 64));
    live.cancel.store(true, Ordering::Relaxed);
    let mut p =
        Progressive::whole(&tracer, &counted(Some(live.clone()))).on_workers(prepared.clone(), 2);
    assert_eq!(p.next_step(&tracer, |_, _| {}), Err(CANCELLED.to_string()));
    std::thread::sleep(Duration::from_millis(20));
    assert_eq!(live.tiles_done.load(Ordering::Relaxed), 0);
}

/// An image with no pixels (0 wide or 0 tall, as an edited camera can ask) ends at once on
/// workers, with `render`'s empty image, and panics nowhere.
#[test]
fn an_empty_image_on_workers_is_render_s() {
    for (w, h) in [(0, 5), (5, 0), (0, 0), (0, 40)] {
        let prepared = Arc::new(PreparedScene::new(shipped("mirror-glass.toml", w, h)));
        let tracer = prepared.tracer();
        let want = render(&tracer, &counted(None)).unwrap();
        let mut p = Progressive::whole(&tracer, &counted(None)).on_workers(prepared.clone(), 2);
        step_to_the_end(&mut p, &prepared).unwrap();
        let got = p.finish().unwrap();
        assert!(got.pixels.is_empty(), "{w} x {h}");
        assert_same(&got, &want);
    }
}
