//! A pass of a render traced a band of tiles at a time, so that a caller on a thread it must
//! give back often (the browser's only thread, between frames) never holds it for a whole
//! image: [`super::Progressive::in_bands`]. Each band traces the next tiles in the image's tile
//! order (tile rows top to bottom, tiles left to right) on the calling thread, with the very
//! tile function [`super::render`] shares among its threads, into the pass's image; after the
//! last band the pass's output is the one [`super::render`] makes, bit for bit.

use super::CANCELLED;
use super::cpu::{
    Pass, PassImage, RenderOptions, RenderOutput, TILE, TileJob, tile_grid, tile_rows,
};
use crate::accel::Accelerator;
use crate::platform::{Duration, Instant};
use crate::trace::Tracer;

/// How much of the image one band traces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BandSize {
    /// This many tiles (at least one).
    Tiles(usize),
    /// Tiles until this long has passed (at least one tile): a band ends at most one tile's
    /// time past it, however the tiles' cost varies over the image.
    Time(Duration),
}

/// One pass of a render traced band by band ([`BandPass::next_band`]), into an image of its own.
#[derive(Debug)]
pub(super) struct BandPass {
    /// The pass's image and the figures of its tiles.
    image: PassImage,
    /// Tiles traced so far: the next band starts at this one, in the image's tile order.
    next: usize,
    /// Time spent tracing, over the bands.
    trace: Duration,
}

impl BandPass {
    /// A pass over a `width` × `height` image, nothing traced yet.
    pub(super) fn new(width: u32, height: u32, pass: Option<Pass>, count: bool) -> BandPass {
        BandPass {
            image: PassImage::new(width, height, pass, count),
            next: 0,
            trace: Duration::ZERO,
        }
    }

    /// Traces the next band of `size` and says whether the pass is done. `opts.count` and
    /// `opts.live` are heeded as [`super::render`] heeds them (the tiles are shown and counted
    /// on the live image as they finish); its threads, progress bar and pass are not (one
    /// thread; the pass is the one given to [`BandPass::new`]). A render cancelled before or
    /// during the band returns [`CANCELLED`].
    pub(super) fn next_band<A: Accelerator>(
        &mut self,
        tracer: &Tracer<'_, A>,
        opts: &RenderOptions,
        size: BandSize,
    ) -> Result<bool, String> {
        let job = TileJob {
            tracer,
            pass: self.image.pass.as_ref(),
            width: self.image.width,
            count: opts.count,
            live: opts.live.as_deref(),
            bar: None,
        };
        if job.cancelled() {
            return Err(CANCELLED.into());
        }
        let (across, tiles) = tile_grid(self.image.width, self.image.height);
        let (width, height) = (self.image.width as usize, self.image.height);
        let start = Instant::now();
        let mut traced = 0;
        let band_done = |traced: usize| match size {
            BandSize::Tiles(n) => traced >= n.max(1),
            BandSize::Time(d) => start.elapsed() >= d,
        };
        'rows: while self.next < tiles {
            // The tile row of the next tile, and the first tile of it left to trace.
            let (row, first) = (self.next / across, self.next % across);
            let y0 = row as u32 * TILE;
            let rows = y0 as usize * width..(y0 + TILE).min(height) as usize * width;
            let Some(pixels) = self.image.pixels.get_mut(rows.clone()) else {
                return Err("internal error: a band past the image's last row".into());
            };
            let mut visits = match self.image.node_visits.as_deref_mut() {
                None => None,
                Some(v) => Some(
                    tile_rows(
                        v.get_mut(rows)
                            .ok_or("internal error: a band past the image's last row")?,
                        self.image.width,
                    )
                    .into_iter()
                    .map(|(_, rows)| rows),
                ),
            };
            let row_tiles = tile_rows(pixels, self.image.width)
                .into_iter()
                .map(|(t, rows)| (t, rows, visits.as_mut().and_then(|v| v.next())));
            for (mut t, rows, visit_rows) in row_tiles.skip(first) {
                // `tile_rows` saw the tile row alone: its y0 is 0.
                t.y0 += y0;
                let done = job.trace((t, rows, visit_rows));
                self.image.tally.add(&done);
                self.next += 1;
                traced += 1;
                if band_done(traced) {
                    break 'rows;
                }
            }
        }
        self.trace += start.elapsed();
        if job.cancelled() {
            return Err(CANCELLED.into());
        }
        Ok(self.next >= tiles)
    }

    /// The finished pass, as [`super::render`] returns it (one thread).
    pub(super) fn output(self) -> Result<RenderOutput, String> {
        self.image.output("the bands", self.trace, 1)
    }
}
