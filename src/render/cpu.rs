//! The full parallel render: rayon over 16×16 tiles, each pixel traced by the same
//! [`Tracer::trace_pixel`] the stepped pixel uses. Every pixel depends only on (scene, pixel,
//! sample), so the image is identical whatever the thread count.

use crate::accel::Accelerator;
use crate::math::Ray;
use crate::record::{Counter, Observer, Silent};
use crate::record::{HitRecord, NodeVisit, RayKind, Step};
use crate::trace::Tracer;
use glam::Vec3;
use rayon::prelude::*;
use std::io::IsTerminal;
use std::sync::Arc;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

const TILE: u32 = 16;

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
}

/// A render in progress, shared with whoever watches it (the app): finished tiles appear in
/// `pixels` as they complete, and setting `cancel` stops the render at the next tile.
#[derive(Debug)]
pub struct LiveRender {
    /// Set to stop the render; [`render`] then returns an error saying it was cancelled.
    pub cancel: AtomicBool,
    /// Tiles finished so far.
    pub tiles_done: AtomicUsize,
    /// Tiles in all.
    pub tiles_total: AtomicUsize,
    /// sRGB RGBA8, row-major from the top-left; tiles not yet traced are transparent.
    pub pixels: Mutex<Vec<[u8; 4]>>,
}

impl LiveRender {
    /// A fresh, empty live image of the given size.
    pub fn new(width: u32, height: u32) -> Self {
        LiveRender {
            cancel: AtomicBool::new(false),
            tiles_done: AtomicUsize::new(0),
            tiles_total: AtomicUsize::new(0),
            pixels: Mutex::new(vec![[0; 4]; (width * height) as usize]),
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

struct Tile {
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
}

/// Renders the tracer's scene.
pub fn render<A: Accelerator>(
    tracer: &Tracer<'_, A>,
    opts: &RenderOptions,
) -> Result<RenderOutput, String> {
    let (width, height) = (tracer.camera.width, tracer.camera.height);
    let mut tiles = vec![];
    for y0 in (0..height).step_by(TILE as usize) {
        for x0 in (0..width).step_by(TILE as usize) {
            tiles.push(Tile {
                x0,
                y0,
                w: TILE.min(width - x0),
                h: TILE.min(height - y0),
            });
        }
    }
    // One thread: the calling thread, no pool to start. Otherwise a pool of the render's own, so
    // that a render in the background never holds up work the app gives rayon's global pool
    // (the BVH build, for one).
    let pool = match opts.threads {
        Some(1) => None,
        n => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n.unwrap_or(0))
                .build()
                .map_err(|e| format!("cannot start the worker threads: {e}"))?,
        ),
    };
    let threads = pool.as_ref().map_or(1, |p| p.current_num_threads());
    let bar = if opts.progress && std::io::stderr().is_terminal() && tiles.len() > 64 {
        let b = indicatif::ProgressBar::new(tiles.len() as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} tracing [{bar:40}] {percent}% {elapsed} (eta {eta})",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        Some(b)
    } else {
        None
    };
    if let Some(live) = &opts.live {
        live.tiles_total.store(tiles.len(), Ordering::Relaxed);
    }
    let start = Instant::now();
    let count = opts.count;
    let live = opts.live.as_deref();
    let cancelled = || live.is_some_and(|l| l.cancel.load(Ordering::Relaxed));
    let per_tile = |t: &Tile| {
        if cancelled() {
            return (vec![], vec![], StatsObserver::default());
        }
        let mut px = Vec::with_capacity((t.w * t.h) as usize);
        let mut visits = vec![];
        let mut counter = StatsObserver::default();
        for y in t.y0..t.y0 + t.h {
            for x in t.x0..t.x0 + t.w {
                if count {
                    let before = counter.counts.node_visits;
                    px.push(tracer.trace_pixel(x, y, &mut counter));
                    visits.push((counter.counts.node_visits - before) as u32);
                } else {
                    px.push(tracer.trace_pixel(x, y, &mut Silent));
                }
            }
        }
        if let Some(b) = &bar {
            b.inc(1);
        }
        if let Some(l) = live {
            publish_tile(l, t, width, &px);
        }
        (px, visits, counter)
    };
    let results: Vec<(Vec<Vec3>, Vec<u32>, StatsObserver)> = match &pool {
        None => tiles.iter().map(per_tile).collect(),
        Some(p) => p.install(|| tiles.par_iter().map(per_tile).collect()),
    };
    let trace = start.elapsed();
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    if cancelled() {
        return Err(CANCELLED.into());
    }
    let mut pixels = vec![Vec3::ZERO; (width * height) as usize];
    let mut node_visits = count.then(|| vec![0u32; (width * height) as usize]);
    let mut counts = Counter::default();
    let (mut nan_rays, mut nan_pixels) = (0, 0);
    // Row by row: a tile's rows are contiguous in its results and in the image, so whole rows are
    // copied (this loop runs on one thread; it used to divide per pixel to find its place).
    for (t, (px, visits, c)) in tiles.iter().zip(results) {
        counts.merge(&c.counts);
        nan_rays += c.nan_rays;
        nan_pixels += px.iter().filter(|p| p.is_nan()).count() as u64;
        let w = t.w as usize;
        for (dy, row) in px.chunks(w.max(1)).enumerate() {
            let start = ((t.y0 as usize + dy) * width as usize) + t.x0 as usize;
            if let Some(dst) = pixels.get_mut(start..start + row.len()) {
                dst.copy_from_slice(row);
            }
            if let (Some(nv), Some(src)) =
                (&mut node_visits, visits.get(dy * w..dy * w + row.len()))
                && let Some(dst) = nv.get_mut(start..start + row.len())
            {
                dst.copy_from_slice(src);
            }
        }
    }
    Ok(RenderOutput {
        width,
        height,
        pixels,
        node_visits,
        stats: RenderStats {
            trace,
            counts,
            threads,
            nan_rays,
            nan_pixels,
        },
    })
}

/// Copies a finished tile into the live image (sRGB, opaque).
fn publish_tile(live: &LiveRender, t: &Tile, width: u32, px: &[Vec3]) {
    // A poisoned lock only means a watcher panicked while reading; the pixels are still valid.
    let mut pixels = live.pixels.lock().unwrap_or_else(|e| e.into_inner());
    for (k, p) in px.iter().enumerate() {
        let (dx, dy) = (k as u32 % t.w, k as u32 / t.w);
        let i = ((t.y0 + dy) * width + t.x0 + dx) as usize;
        if let Some(slot) = pixels.get_mut(i) {
            *slot = [
                super::image::srgb8(p.x),
                super::image::srgb8(p.y),
                super::image::srgb8(p.z),
                255,
            ];
        }
    }
    drop(pixels);
    live.tiles_done.fetch_add(1, Ordering::Relaxed);
}

/// Traces one pixel with a counting observer (for tests and the app's pixel readout).
pub fn count_pixel<A: Accelerator>(tracer: &Tracer<'_, A>, x: u32, y: u32) -> (Vec3, Counter) {
    let mut c = Counter::default();
    let color = tracer.trace_pixel(x, y, &mut c);
    (color, c)
}
