//! A pass of a render traced by worker threads while the calling thread only gathers the
//! finished tiles, never waiting for them: [`super::Progressive::on_workers`]. This is how the
//! browser's page renders on every core: the page's own thread may not block (a wait there
//! stops the page, and WebAssembly's `memory.atomic.wait` traps on it), so it cannot share a
//! render's tiles as [`super::render`] does, in a scope it waits on. Instead each worker
//! ([`crate::platform::spawn_worker`]: a Web Worker in the page, rayon's pool natively) takes
//! the next tile from a shared counter, traces it into a buffer of its own with the very tile
//! function [`super::render`] uses, and sends it; each step of the calling thread copies the
//! tiles that have arrived into the pass's image and shows them on the live view. The workers
//! touch nothing the page's thread locks (the live view is written by the page's thread alone),
//! so the page never waits on them either. After the last tile the pass's output is the one
//! [`super::render`] makes, bit for bit: every pixel depends only on (scene, pixel, sample).

use super::CANCELLED;
use super::cpu::{
    Pass, PassImage, RenderOptions, RenderOutput, TILE, Tile, TileDone, TileJob, tile_grid,
};
use crate::platform::{Duration, Instant};
use crate::trace::PreparedScene;
use glam::Vec3;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, Sender, TryRecvError, channel};

/// One traced tile, as a worker sends it.
struct TracedTile {
    /// The tile's index in the image's tile order.
    index: usize,
    /// Its pixels, row by row (the tile's width a row).
    pixels: Vec<Vec3>,
    /// Its accelerator visits per pixel, when counted.
    visits: Option<Vec<u32>>,
    /// Its figures.
    done: TileDone,
}

/// One pass of a render traced by workers ([`WorkerPass::gather`]), into an image of its own.
#[derive(Debug)]
pub(super) struct WorkerPass {
    /// The pass's image and the figures of the tiles that have arrived.
    image: PassImage,
    /// The tiles that have arrived.
    arrived: usize,
    /// The tiles as the workers send them, once they have been started.
    tiles: Option<Receiver<TracedTile>>,
    /// When the workers were started.
    start: Option<Instant>,
    /// How many workers trace the pass.
    workers: usize,
}

impl WorkerPass {
    /// A pass over a `width` × `height` image for `workers` workers, nothing traced yet.
    pub(super) fn new(
        width: u32,
        height: u32,
        pass: Option<Pass>,
        count: bool,
        workers: usize,
    ) -> WorkerPass {
        WorkerPass {
            image: PassImage::new(width, height, pass, count),
            arrived: 0,
            tiles: None,
            start: None,
            workers: workers.max(1),
        }
    }

    /// The image's tiles across and in all.
    fn grid(&self) -> (usize, usize) {
        tile_grid(self.image.width, self.image.height)
    }

    /// Starts the workers on the pass's tiles (the first call), then takes in the tiles
    /// that have arrived since the last call, without waiting for any, and says whether the
    /// pass is done. The tiles are shown and counted on `opts.live` as they arrive; a render
    /// cancelled there returns [`CANCELLED`] (and the workers stop at their next tile).
    pub(super) fn gather(
        &mut self,
        prepared: &Arc<PreparedScene>,
        opts: &RenderOptions,
    ) -> Result<bool, String> {
        let cancelled = || {
            opts.live
                .as_ref()
                .is_some_and(|l| l.cancel.load(Ordering::Relaxed))
        };
        if cancelled() {
            return Err(CANCELLED.into());
        }
        let tiles = match &self.tiles {
            Some(t) => t,
            None => {
                self.start = Some(Instant::now());
                self.tiles.insert(self.start_workers(prepared, opts))
            }
        };
        let mut arrived = vec![];
        loop {
            match tiles.try_recv() {
                Ok(t) => arrived.push(t),
                Err(TryRecvError::Empty) => break,
                // Every worker has finished and every tile is in, or a worker died.
                Err(TryRecvError::Disconnected) => {
                    if self.arrived + arrived.len() < self.grid().1 && !cancelled() {
                        return Err("internal error: a render's workers stopped early".into());
                    }
                    break;
                }
            }
        }
        if arrived.is_empty() && self.arrived < self.grid().1 {
            crate::platform::step_waits();
        }
        for t in arrived {
            self.take_in(t, opts);
        }
        if cancelled() {
            return Err(CANCELLED.into());
        }
        Ok(self.arrived >= self.grid().1)
    }

    /// Starts the workers; the receiving end of the channel they send their tiles on.
    fn start_workers(
        &self,
        prepared: &Arc<PreparedScene>,
        opts: &RenderOptions,
    ) -> Receiver<TracedTile> {
        let (send, receive) = channel();
        let next = Arc::new(AtomicUsize::new(0));
        for _ in 0..self.workers {
            let worker = Worker {
                prepared: Arc::clone(prepared),
                pass: self.image.pass.clone(),
                width: self.image.width,
                height: self.image.height,
                count: opts.count,
                live: opts.live.clone(),
                next: Arc::clone(&next),
                send: send.clone(),
            };
            crate::platform::spawn_worker(move || worker.run());
        }
        receive
    }

    /// Copies an arrived tile into the image, adds its figures and shows it.
    fn take_in(&mut self, t: TracedTile, opts: &RenderOptions) {
        let tile = tile_at(t.index, self.grid().0);
        let tile_width = tile_size(tile.x0, self.image.width);
        let width = self.image.width as usize;
        for (dy, row) in t.pixels.chunks(tile_width.max(1)).enumerate() {
            let start = (tile.y0 as usize + dy) * width + tile.x0 as usize;
            if let Some(dst) = self.image.pixels.get_mut(start..start + row.len()) {
                dst.copy_from_slice(row);
            }
            if let (Some(all), Some(v)) = (self.image.node_visits.as_mut(), t.visits.as_ref())
                && let (Some(dst), Some(src)) = (
                    all.get_mut(start..start + row.len()),
                    v.get(dy * tile_width..dy * tile_width + row.len()),
                )
            {
                dst.copy_from_slice(src);
            }
        }
        self.image.tally.add(&t.done);
        self.arrived += 1;
        if let Some(live) = opts.live.as_deref() {
            let scale = self
                .image
                .pass
                .as_ref()
                .map_or(1.0, |p| 1.0 / p.samples.end.max(1) as f32);
            let shown: Vec<[u8; 4]> = t
                .pixels
                .iter()
                .map(|&c| super::cpu::srgba(c * scale))
                .collect();
            let weight = self.image.pass.as_ref().map_or(1, |p| p.samples.len());
            super::cpu::publish_tile(live, &tile, self.image.width, tile_width, &shown, weight);
        }
    }

    /// The finished pass, as [`super::render`] returns it (the threads: the workers).
    pub(super) fn output(self) -> Result<RenderOutput, String> {
        let trace = self.start.map_or(Duration::ZERO, |st| st.elapsed());
        self.image.output("the workers", trace, self.workers)
    }
}

/// Tile `index`'s top-left pixel, in an image `across` tiles wide.
fn tile_at(index: usize, across: usize) -> Tile {
    Tile {
        x0: (index % across) as u32 * TILE,
        y0: (index / across) as u32 * TILE,
    }
}

/// A tile's extent from `start` in an image `size` long: `TILE`, less at the edge.
fn tile_size(start: u32, size: u32) -> usize {
    TILE.min(size.saturating_sub(start)) as usize
}

/// What a worker needs, all of it its own (it outlives no one's borrow).
struct Worker {
    prepared: Arc<PreparedScene>,
    pass: Option<Pass>,
    width: u32,
    height: u32,
    count: bool,
    live: Option<Arc<super::LiveRender>>,
    /// The next tile to trace, shared by the pass's workers.
    next: Arc<AtomicUsize>,
    send: Sender<TracedTile>,
}

impl Worker {
    /// Traces tiles until none is left, the render is cancelled, or nobody gathers them.
    fn run(self) {
        let tracer = self.prepared.tracer();
        let job = TileJob {
            tracer: &tracer,
            pass: self.pass.as_ref(),
            width: self.width,
            count: self.count,
            // The live view is the gathering thread's: a worker only checks for a cancel.
            live: None,
            bar: None,
        };
        let (across, tiles) = tile_grid(self.width, self.height);
        loop {
            if self
                .live
                .as_ref()
                .is_some_and(|l| l.cancel.load(Ordering::Relaxed))
            {
                return;
            }
            let index = self.next.fetch_add(1, Ordering::Relaxed);
            if index >= tiles {
                return;
            }
            let tile = tile_at(index, across);
            let (w, h) = (
                tile_size(tile.x0, self.width),
                tile_size(tile.y0, self.height),
            );
            let mut pixels = vec![Vec3::ZERO; w * h];
            let mut visits = self.count.then(|| vec![0u32; w * h]);
            let done = job.trace((
                tile,
                pixels.chunks_mut(w.max(1)).collect(),
                visits.as_mut().map(|v| v.chunks_mut(w.max(1)).collect()),
            ));
            let traced = TracedTile {
                index,
                pixels,
                visits,
                done,
            };
            if self.send.send(traced).is_err() {
                // The pass was dropped (a new render): nobody is gathering.
                return;
            }
        }
    }
}
