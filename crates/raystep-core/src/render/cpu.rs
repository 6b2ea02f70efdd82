//! The full parallel render: 16×16 tiles shared among threads, each pixel traced by the same
//! [`Tracer::trace_pixel`] the stepped pixel uses. Every pixel depends only on (scene, pixel,
//! sample), so the image is identical whatever the thread count.

use super::pool::{await_helpers, bands, drain, linger, render_pool};
use crate::accel::Accelerator;
use crate::math::Ray;
use crate::platform::{Duration, Instant};
use crate::record::{Counter, Observer, Silent};
use crate::record::{HitRecord, NodeVisit, RayKind, Step};
use crate::trace::Tracer;
use crossbeam_deque::{Stealer, Worker};
use glam::Vec3;
use std::mem::MaybeUninit;
use std::sync::Arc;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicUsize, Ordering};

pub(super) const TILE: u32 = 16;
/// Pixels in a whole tile.
const TILE_PIXELS: usize = (TILE * TILE) as usize;

/// How to render.
#[derive(Debug, Clone, Default)]
pub struct RenderOptions {
    /// Worker threads (None: all cores).
    pub threads: Option<usize>,
    /// Show a progress bar on stderr (only when stderr is a terminal).
    pub progress: bool,
    /// Count rays and tests, and accelerator visits per pixel (for the stats and the heatmap).
    pub count: bool,
    /// Where a watching UI sees the image build up, and can cancel it.
    pub live: Option<Arc<LiveRender>>,
    /// One pass of a progressive render ([`render_progressive`]): only these samples of each
    /// pixel, added in order onto the running sums given; the output's pixels are then the
    /// new running sums, not means. None: every sample, the output the pixels' means.
    pub pass: Option<Pass>,
}

/// A pass of a progressive render: samples `samples.start..samples.end` of every pixel, added
/// to `sums` (None: from zero).
#[derive(Debug, Clone, Default)]
pub struct Pass {
    /// The samples this pass traces.
    pub samples: std::ops::Range<u32>,
    /// The running sums the previous passes left, one per pixel.
    pub sums: Option<Arc<Vec<Vec3>>>,
}

/// A render in progress, shared with whoever watches it (the app): finished tiles appear in
/// `pixels` as they complete, and setting `cancel` stops the render at the next tile.
#[derive(Debug)]
pub struct LiveRender {
    /// Set to stop the render; [`render`] then returns an error saying it was cancelled.
    pub cancel: AtomicBool,
    /// Tiles finished so far (in a progressive render, tiles × the samples they traced).
    pub tiles_done: AtomicUsize,
    /// Tiles in all (in a progressive render, tiles × spp).
    pub tiles_total: AtomicUsize,
    /// sRGB RGBA8, row-major from the top-left; tiles not yet traced are transparent.
    pub pixels: Mutex<Vec<[u8; 4]>>,
    /// A progressive render's samples per pixel finished so far (every pixel has this many).
    pub samples_done: AtomicU32,
    /// A progressive render's samples per pixel in all (0 for a render in one pass).
    pub samples_total: AtomicU32,
}

impl LiveRender {
    /// A fresh, empty live image of the given size.
    pub fn new(width: u32, height: u32) -> Self {
        LiveRender {
            cancel: AtomicBool::new(false),
            tiles_done: AtomicUsize::new(0),
            tiles_total: AtomicUsize::new(0),
            pixels: Mutex::new(vec![[0; 4]; (width * height) as usize]),
            samples_done: AtomicU32::new(0),
            samples_total: AtomicU32::new(0),
        }
    }

    /// The fraction of tiles done, in [0, 1].
    pub fn progress(&self) -> f32 {
        let total = self.tiles_total.load(Ordering::Relaxed);
        if total == 0 {
            0.0
        } else {
            self.tiles_done.load(Ordering::Relaxed) as f32 / total as f32
        }
    }
}

/// The error [`render`] returns when its [`LiveRender`] was cancelled.
pub const CANCELLED: &str = "the render was cancelled";

/// Figures a teacher wants after a render.
#[derive(Debug, Clone, Default)]
pub struct RenderStats {
    /// Time spent tracing (excludes loading and building).
    pub trace: Duration,
    /// Rays and tests (zero unless `count` was set).
    pub counts: Counter,
    /// Threads used.
    pub threads: usize,
    /// Rays (of any kind) whose origin or direction has a NaN or infinite component (zero unless
    /// `count` was set). A validated scene should give none.
    pub nan_rays: u64,
    /// Pixels with a NaN channel (always counted).
    pub nan_pixels: u64,
    /// Samples with a NaN or infinite channel, left out of their pixel (always counted).
    pub bad_samples: u64,
    /// The first such sample in image order: (pixel, sample index), for `raystep trace`.
    pub first_bad_sample: Option<([u32; 2], u32)>,
}

/// The counting observer of a render: [`Counter`]'s figures, and the rays that are not finite.
#[derive(Debug, Default, Clone, Copy)]
struct StatsObserver {
    counts: Counter,
    nan_rays: u64,
}

impl Observer for StatsObserver {
    const RECORDS: bool = false;
    #[inline(always)]
    fn begin_ray(&mut self, kind: RayKind, depth: u32, ray: &Ray<f32>, weight: f32) {
        if !(ray.origin.is_finite() && ray.dir.is_finite()) {
            self.nan_rays += 1;
        }
        self.counts.begin_ray(kind, depth, ray, weight);
    }
    #[inline(always)]
    fn prim_test(&mut self, step: impl FnOnce() -> Step) {
        self.counts.prim_test(step);
    }
    #[inline(always)]
    fn prim_tests(&mut self, n: usize, step: impl FnMut(usize) -> Step) {
        self.counts.prim_tests(n, step);
    }
    #[inline(always)]
    fn node_visit(&mut self, visit: impl FnOnce() -> NodeVisit) {
        self.counts.node_visit(visit);
    }
    #[inline(always)]
    fn accel_visit(&mut self, step: impl FnOnce() -> Step) {
        self.counts.accel_visit(step);
    }
    #[inline(always)]
    fn step(&mut self, step: impl FnOnce() -> Step) {
        self.counts.step(step);
    }
    #[inline(always)]
    fn end_ray(&mut self, hit: impl FnOnce() -> Option<HitRecord>, color: Vec3) {
        self.counts.end_ray(hit, color);
    }
}

impl RenderStats {
    /// Millions of rays (all kinds) per second of tracing.
    pub fn mrays_per_s(&self) -> f64 {
        self.counts.rays() as f64 / self.trace.as_secs_f64().max(1e-9) / 1e6
    }
}

/// A rendered image in linear RGB, with per-pixel accelerator visits when counted.
#[derive(Debug, Clone)]
pub struct RenderOutput {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Linear RGB, row-major from the top-left.
    pub pixels: Vec<Vec3>,
    /// Accelerator visits per pixel (BVH nodes, bounding spheres, grid cells; all rays of the
    /// pixel), when counted.
    pub node_visits: Option<Vec<u32>>,
    /// Statistics.
    pub stats: RenderStats,
}

/// A tile and its rows of the image (not yet written, `S` = `MaybeUninit<Vec3>`, in [`render`];
/// or written over, `S` = `Vec3`, in a render in bands) and, when counted, of the visit counts
/// (see [`tile_rows`]).
pub(super) type TileWork<'a, S> = (Tile, Vec<&'a mut [S]>, Option<Vec<&'a mut [u32]>>);

/// A place a traced pixel goes: a slot of [`render`]'s unfilled image, or a pixel of an image
/// traced in bands.
pub(super) trait Slot {
    /// Stores the pixel's value.
    fn put(&mut self, c: Vec3);
}

impl Slot for MaybeUninit<Vec3> {
    #[inline(always)]
    fn put(&mut self, c: Vec3) {
        self.write(c);
    }
}

impl Slot for Vec3 {
    #[inline(always)]
    fn put(&mut self, c: Vec3) {
        *self = c;
    }
}

/// What a tile's tracing leaves beside its pixels.
#[derive(Default)]
pub(super) struct TileDone {
    /// Its counts (when counted).
    stats: StatsObserver,
    /// Its pixels with a NaN channel.
    nan_pixels: u64,
    /// Its samples that were not finite, and the first (pixel, sample).
    bad_samples: u64,
    first_bad_sample: Option<([u32; 2], u32)>,
    /// How many pixels of the image it wrote (all of its own unless the render was cancelled).
    written: usize,
}

/// The tiles' figures added up, in any order: a render's (or a pass's) [`RenderStats`] but for
/// the time and the threads.
#[derive(Debug, Default, Clone)]
pub(super) struct Tally {
    counts: Counter,
    nan_rays: u64,
    nan_pixels: u64,
    bad_samples: u64,
    first_bad_sample: Option<([u32; 2], u32)>,
    /// Pixels written so far.
    pub(super) written: usize,
}

impl Tally {
    /// Adds a finished tile.
    pub(super) fn add(&mut self, r: &TileDone) {
        self.bad_samples += r.bad_samples;
        // The first in image order (row, then column), whichever tile found it.
        if let Some(b) = r.first_bad_sample
            && self
                .first_bad_sample
                .is_none_or(|f| (b.0[1], b.0[0]) < (f.0[1], f.0[0]))
        {
            self.first_bad_sample = Some(b);
        }
        self.counts.merge(&r.stats.counts);
        self.nan_rays += r.stats.nan_rays;
        self.nan_pixels += r.nan_pixels;
        self.written += r.written;
    }

    /// The statistics of a render that traced these tiles in `trace` on `threads` threads.
    pub(super) fn stats(self, trace: Duration, threads: usize) -> RenderStats {
        RenderStats {
            trace,
            counts: self.counts,
            threads,
            nan_rays: self.nan_rays,
            nan_pixels: self.nan_pixels,
            bad_samples: self.bad_samples,
            first_bad_sample: self.first_bad_sample,
        }
    }
}

/// The image of one pass traced piece by piece (in bands on the calling thread, or gathered
/// from workers): its pixels and visit counts as the tiles fill them, and their figures.
#[derive(Debug)]
pub(super) struct PassImage {
    /// The samples traced and the running sums they add to (None: every sample, the pixels
    /// their means, as [`render`] without a pass).
    pub(super) pass: Option<Pass>,
    pub(super) width: u32,
    pub(super) height: u32,
    /// The pass's image (zero where no tile is in yet).
    pub(super) pixels: Vec<Vec3>,
    /// The pass's accelerator visits per pixel, when counted.
    pub(super) node_visits: Option<Vec<u32>>,
    /// The figures of the tiles in so far.
    pub(super) tally: Tally,
}

impl PassImage {
    /// A `width` × `height` image, no tile in yet.
    pub(super) fn new(width: u32, height: u32, pass: Option<Pass>, count: bool) -> PassImage {
        let n = width as usize * height as usize;
        PassImage {
            pass,
            width,
            height,
            pixels: vec![Vec3::ZERO; n],
            node_visits: count.then(|| vec![0; n]),
            tally: Tally::default(),
        }
    }

    /// The finished pass, as [`render`] returns it, traced in `trace` on `threads` threads;
    /// an internal error naming `by` (who wrote the pixels) if some pixel was never written.
    pub(super) fn output(
        self,
        by: &str,
        trace: Duration,
        threads: usize,
    ) -> Result<RenderOutput, String> {
        let n = self.pixels.len();
        if self.tally.written != n {
            return Err(format!(
                "internal error: {by} wrote {} of the image's {n} pixels",
                self.tally.written
            ));
        }
        Ok(RenderOutput {
            width: self.width,
            height: self.height,
            pixels: self.pixels,
            node_visits: self.node_visits,
            stats: self.tally.stats(trace, threads),
        })
    }
}

/// A tile's top-left pixel (its size is `TILE`, less at the right and bottom edges).
pub(super) struct Tile {
    pub(super) x0: u32,
    pub(super) y0: u32,
}

/// What every tile of one render (or of one pass traced in bands) shares: how to trace a tile
/// ([`TileJob::trace`]).
pub(super) struct TileJob<'r, 't, A: Accelerator> {
    /// The tracer of the scene.
    pub(super) tracer: &'r Tracer<'t, A>,
    /// The pass, in a progressive render.
    pub(super) pass: Option<&'r Pass>,
    /// The image's width.
    pub(super) width: u32,
    /// Whether rays, tests and visits are counted.
    pub(super) count: bool,
    /// Where finished tiles are shown and counted, and the cancel flag.
    pub(super) live: Option<&'r LiveRender>,
    /// The terminal's progress bar.
    pub(super) bar: Option<&'r crate::platform::TerminalProgress>,
}

impl<A: Accelerator> TileJob<'_, '_, A> {
    /// Whether the watching UI cancelled the render.
    pub(super) fn cancelled(&self) -> bool {
        self.live.is_some_and(|l| l.cancel.load(Ordering::Relaxed))
    }

    /// Traces one tile into its rows (and visit counts), shows it on the live image and counts
    /// it there; nothing once the render is cancelled.
    #[inline(always)]
    pub(super) fn trace<S: Slot>(&self, (t, mut rows, mut visit_rows): TileWork<S>) -> TileDone {
        let (tracer, pass, width, live) = (self.tracer, self.pass, self.width, self.live);
        let mut counter = StatsObserver::default();
        let (mut nan_pixels, mut written) = (0u64, 0usize);
        let (mut bad_samples, mut first_bad_sample) = (0u64, None);
        if self.cancelled() {
            return TileDone::default();
        }
        // What a pixel's value is divided by to show it: its samples so far in a pass.
        let shown_scale = pass.map_or(1.0, |p| 1.0 / p.samples.end.max(1) as f32);
        // The tile's pixels in sRGB, for a watching UI.
        let mut shown = Vec::with_capacity(if live.is_some() { TILE_PIXELS } else { 0 });
        for (dy, row) in rows.iter_mut().enumerate() {
            let y = t.y0 + dy as u32;
            let mut visits = visit_rows
                .as_mut()
                .and_then(|v| v.get_mut(dy))
                .map(|r| r.iter_mut());
            for (dx, slot) in row.iter_mut().enumerate() {
                let x = t.x0 + dx as u32;
                let (color, bad, first) = if self.count {
                    let before = counter.counts.node_visits;
                    let checked = trace_pixel(tracer, pass, width, x, y, &mut counter);
                    if let Some(slot) = visits.as_mut().and_then(|v| v.next()) {
                        *slot = (counter.counts.node_visits - before) as u32;
                    }
                    checked
                } else {
                    trace_pixel(tracer, pass, width, x, y, &mut Silent)
                };
                if bad > 0 {
                    bad_samples += u64::from(bad);
                    if let Some(k) = first {
                        first_bad_sample.get_or_insert(([x, y], k));
                    }
                }
                slot.put(color);
                written += 1;
                nan_pixels += u64::from(color.is_nan());
                if live.is_some() {
                    shown.push(srgba(color * shown_scale));
                }
            }
        }
        if let Some(b) = self.bar {
            b.inc(1);
        }
        if let Some(l) = live {
            let tile_width = rows.first().map_or(1, |r| r.len());
            let weight = pass.map_or(1, |p| p.samples.len());
            publish_tile(l, &t, width, tile_width, &shown, weight);
        }
        TileDone {
            stats: counter,
            nan_pixels,
            bad_samples,
            first_bad_sample,
            written,
        }
    }
}

/// One pixel of a render: all its samples' mean, or in a pass of a progressive render its
/// running sum with the pass's samples added ([`Pass`]).
#[inline(always)]
fn trace_pixel<A: Accelerator, O: Observer>(
    tracer: &Tracer<'_, A>,
    pass: Option<&Pass>,
    width: u32,
    x: u32,
    y: u32,
    obs: &mut O,
) -> (Vec3, u32, Option<u32>) {
    match pass {
        None => tracer.trace_pixel_checked(x, y, obs),
        Some(p) => {
            let start = p.sums.as_ref().map_or(Vec3::ZERO, |s| {
                s.get(y as usize * width as usize + x as usize)
                    .copied()
                    .unwrap_or(Vec3::ZERO)
            });
            tracer.accumulate_samples(x, y, p.samples.clone(), start, obs)
        }
    }
}

/// The tiles of `tracer`'s image.
pub(super) fn tiles<A: Accelerator>(tracer: &Tracer<'_, A>) -> usize {
    tile_grid(tracer.camera.width, tracer.camera.height).1
}

/// A `width` × `height` image's tiles across (at least one) and in all.
pub(super) fn tile_grid(width: u32, height: u32) -> (usize, usize) {
    let across = width.div_ceil(TILE).max(1) as usize;
    (across, across * height.div_ceil(TILE) as usize)
}

/// Renders the tracer's scene.
pub fn render<A: Accelerator>(
    tracer: &Tracer<'_, A>,
    opts: &RenderOptions,
) -> Result<RenderOutput, String> {
    let (width, height) = (tracer.camera.width, tracer.camera.height);
    let n = (width as usize) * (height as usize);
    // Each tile writes straight into its own rows of the image (and of the visit counts): no
    // copy afterwards. That copy ran on one thread and took a seventh of a two-thread render
    // of a 512×512 scene. The image is not filled with zeros first: the calling thread's zeros
    // were in its core's cache, and each line a helper then wrote had to be fetched from there
    // (two-thread renders of the 64×64 far sphere: 1.72× one thread's speed with the zeros,
    // 1.82× without; the helper's share of the tracing took 174 µs instead of 190).
    let mut pixels: Vec<Vec3> = Vec::with_capacity(n);
    let mut node_visits = opts.count.then(|| vec![0u32; n]);
    let mut visit_rows = node_visits
        .as_deref_mut()
        .map(|v| tile_rows(v, width).into_iter().map(|(_, rows)| rows));
    let slots = pixels.spare_capacity_mut().get_mut(..n).unwrap_or_default();
    let work: Vec<TileWork<MaybeUninit<Vec3>>> = tile_rows(slots, width)
        .into_iter()
        .map(|(t, rows)| (t, rows, visit_rows.as_mut().and_then(|v| v.next())))
        .collect();
    // The calling thread traces tiles too; the other `threads - 1` are helpers from a pool of
    // the renders' own, so that a render in the background never holds up work the app gives
    // rayon's global pool (the BVH build, for one). One thread: no pool at all.
    // In the browser there is one thread, whatever was asked.
    let threads = match opts.threads {
        Some(n) if n > 0 && !crate::platform::IN_BROWSER => n,
        _ => crate::platform::threads(),
    };
    let pool = (threads > 1)
        .then(|| render_pool(threads - 1))
        .transpose()?;
    let bar = (opts.progress && work.len() > 64)
        .then(|| crate::platform::TerminalProgress::new(work.len() as u64, "tracing"))
        .flatten();
    // A progressive render counts the tiles of all its passes itself.
    if let Some(live) = &opts.live
        && opts.pass.is_none()
    {
        live.tiles_total.store(work.len(), Ordering::Relaxed);
    }
    let start = Instant::now();
    let job = TileJob {
        tracer,
        pass: opts.pass.as_ref(),
        width,
        count: opts.count,
        live: opts.live.as_deref(),
        bar: bar.as_ref(),
    };
    let per_tile = |work: TileWork<MaybeUninit<Vec3>>| job.trace(work);
    // Each thread starts on its own band of the image (the calling thread on the first) and,
    // when its band is done, takes tiles from the far end of the band with the most left, one
    // at a time, so no thread idles while a tile is left. Two things this replaced cost time:
    // - rayon's parallel iterator over all the tiles, which splits only a few times unless a
    //   piece is stolen (one thread idle for the last 20 ms of a 64 ms render of SPD mount 3),
    //   and whose `install` puts the calling thread to sleep until a worker wakes: on the 64×64
    //   far sphere, a 0.33 ms render, the first tile started 2 to 60 µs after the render did;
    // - one shared counter handing out the tiles in image order: the threads then trace
    //   neighbouring tiles at the same time, and mount 3 took 56–59 ms on two threads (nine
    //   runs of ten) instead of about 51–56 (most likely their rows meeting in the same cache
    //   lines of the image).
    // crossbeam's work-stealing deques (rayon's own) hold the bands.
    let results: Vec<TileDone> = {
        // No more bands than tiles: a thread with no band of its own would only steal.
        let tiles = work.len();
        let bands = bands(work, threads.min(tiles));
        let thieves: Vec<Stealer<TileWork<MaybeUninit<Vec3>>>> =
            bands.iter().map(Worker::stealer).collect();
        let (per_tile, thieves) = (&per_tile, &thieves[..]);
        let mut bands = bands.into_iter();
        let first = bands.next();
        let drain_first = || {
            first
                .map(|own| drain(own, thieves, per_tile))
                .unwrap_or_default()
        };
        match &pool {
            None => drain_first(),
            Some(p) => {
                let helped = Mutex::new(vec![]);
                let running = AtomicUsize::new(bands.len());
                let mut done = vec![];
                p.in_place_scope(|s| {
                    for own in bands {
                        let (helped, running) = (&helped, &running);
                        s.spawn(move |_| {
                            let theirs = drain(own, thieves, per_tile);
                            helped
                                .lock()
                                .unwrap_or_else(|e| e.into_inner())
                                .extend(theirs);
                            running.fetch_sub(1, Ordering::Release);
                        });
                    }
                    done = drain_first();
                    await_helpers(&running);
                });
                linger(p, threads - 1);
                done.extend(helped.into_inner().unwrap_or_else(|e| e.into_inner()));
                done
            }
        }
    };
    let trace = start.elapsed();
    let cancelled = job.cancelled();
    if let Some(b) = bar {
        b.finish();
    }
    if cancelled {
        return Err(CANCELLED.into());
    }
    let mut tally = Tally::default();
    results.iter().for_each(|r| tally.add(r));
    let written = tally.written;
    if written != n {
        return Err(format!(
            "internal error: the tiles wrote {written} of the image's {n} pixels"
        ));
    }
    // SAFETY: the tiles' rows are disjoint pieces of the first `n` elements of `pixels`' spare
    // capacity (`tile_rows` cuts them with `chunks_mut`, and they are `&mut` borrows, so no two
    // overlap), and each element of a row is written once, counted in `written`; `n` writes to
    // `n` different elements of those `n` leave every one of them initialized.
    #[allow(unsafe_code)]
    unsafe {
        pixels.set_len(n);
    }
    Ok(RenderOutput {
        width,
        height,
        pixels,
        node_visits,
        stats: tally.stats(trace, threads),
    })
}

/// A linear colour as the live image shows it (sRGB, opaque).
pub(super) fn srgba(p: Vec3) -> [u8; 4] {
    let [r, g, b] = super::image::srgb8_rgb(p);
    [r, g, b, 255]
}

/// Copies a finished tile (`shown`: its pixels, row by row, `tile_width` a row) into the live
/// image.
/// Shows a finished tile and counts it `weight` times towards the progress (a progressive
/// render's tile counts once per sample it traced).
pub(super) fn publish_tile(
    live: &LiveRender,
    t: &Tile,
    width: u32,
    tile_width: usize,
    shown: &[[u8; 4]],
    weight: usize,
) {
    // A poisoned lock only means a watcher panicked while reading; the pixels are still valid.
    let mut pixels = live.pixels.lock().unwrap_or_else(|e| e.into_inner());
    for (dy, row) in shown.chunks(tile_width.max(1)).enumerate() {
        let start = (t.y0 as usize + dy) * width as usize + t.x0 as usize;
        let Some(dst) = pixels.get_mut(start..start + row.len()) else {
            continue;
        };
        dst.copy_from_slice(row);
    }
    drop(pixels);
    live.tiles_done.fetch_add(weight, Ordering::Relaxed);
}

/// The image `buffer` (row-major, `width` wide) cut into tiles: for each tile (bands of `TILE`
/// rows top to bottom, tiles left to right), its top-left pixel and its rows' pieces. Disjoint mutable slices, so the tiles can be traced in parallel straight into
/// the image.
pub(super) fn tile_rows<T>(buffer: &mut [T], width: u32) -> Vec<(Tile, Vec<&mut [T]>)> {
    let (width, tile) = ((width as usize).max(1), TILE as usize);
    let mut out = vec![];
    for (band, y0) in buffer.chunks_mut(width * tile).zip((0..).step_by(tile)) {
        let mut rows: Vec<_> = band.chunks_mut(width).map(|r| r.chunks_mut(tile)).collect();
        for x0 in (0..width).step_by(tile) {
            let t = Tile { x0: x0 as u32, y0 };
            out.push((t, rows.iter_mut().filter_map(|r| r.next()).collect()));
        }
    }
    out
}

/// Traces one pixel with a counting observer (for tests and the app's pixel readout).
pub fn count_pixel<A: Accelerator>(tracer: &Tracer<'_, A>, x: u32, y: u32) -> (Vec3, Counter) {
    let mut c = Counter::default();
    let color = tracer.trace_pixel(x, y, &mut c);
    (color, c)
}

#[cfg(test)]
mod tests;
