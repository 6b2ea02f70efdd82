//! A render in steps: progressive Monte Carlo passes ([`super::passes`]) and, for the browser's
//! page, bands of tiles on its one thread ([`super::bands`]) or tiles gathered from its Web
//! Workers ([`super::workers`]); whatever the steps, the finished image and its figures are
//! [`render`]'s, bit for bit.

use super::bands::{BandPass, BandSize};
use super::cpu::*;
use super::workers::WorkerPass;
use crate::accel::Accelerator;
use crate::trace::{PreparedScene, Tracer};
use glam::Vec3;
use std::sync::Arc;
use std::sync::atomic::Ordering;

/// Renders the scene progressively: passes of 1, 1, 2, 4, … samples per pixel (each doubling
/// the samples so far) up to the scene's spp, each pass adding its samples to the running sum of
/// every pixel in sample order, so that the final image is bit for bit the one [`render`] makes
/// (and the traced pixel's). After each pass `after_pass(samples so far, running sums)` is
/// called (the app shows sum / samples). `opts.live`, when given, counts the tiles of all passes
/// and the samples done. The output is the finished image, its stats summed over the passes.
pub fn render_progressive<A: Accelerator>(
    tracer: &Tracer<'_, A>,
    opts: &RenderOptions,
    mut after_pass: impl FnMut(u32, &RenderOutput),
) -> Result<RenderOutput, String> {
    let mut p = Progressive::new(tracer, opts);
    while let Some(done) = p.next_pass(tracer, &mut after_pass)? {
        let _ = done;
    }
    p.finish()
}

/// What one step of a [`Progressive`] render did ([`Progressive::next_step`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stepped {
    /// Traced a band of the current pass (or gathered the tiles its workers traced so far,
    /// [`Progressive::on_workers`]), which goes on.
    Band,
    /// Finished a pass: every pixel has this many samples now.
    Pass(u32),
}

/// [`render_progressive`] a step at a time, so that a caller that cannot wait for the whole
/// render (the browser's only thread) draws the image between steps. A step is a pass (1, 1,
/// 2, 4, … samples per pixel, on every thread, by [`render`]) or, [`Progressive::in_bands`], a
/// band of tiles of a pass on the calling thread. [`Progressive::whole`] is [`render`] itself
/// in steps: one pass of every sample. Whatever the steps, the finished image and its figures
/// are [`render`]'s, bit for bit.
#[derive(Debug)]
pub struct Progressive {
    opts: RenderOptions,
    spp: u32,
    ends: std::collections::VecDeque<u32>,
    start: u32,
    sums: Option<Arc<Vec<Vec3>>>,
    total: Option<RenderOutput>,
    /// One pass of every sample, its pixels their means: [`render`] without a pass.
    whole: bool,
    /// What a step is, and the pass in progress where a step is less than a pass.
    steps: Steps,
}

/// What one step of a [`Progressive`] render traces.
#[derive(Debug)]
enum Steps {
    /// A pass, by [`render`] on every thread.
    Passes,
    /// A band of tiles of this size on the calling thread ([`Progressive::in_bands`]); the pass
    /// being traced band by band.
    Bands(BandSize, Option<BandPass>),
    /// The tiles that have arrived from the workers tracing the pass
    /// ([`Progressive::on_workers`]); the pass they trace.
    Workers(Arc<PreparedScene>, usize, Option<WorkerPass>),
}

impl Progressive {
    /// A progressive render of `tracer`'s scene with `opts` (its live view told the totals), a
    /// pass a step.
    pub fn new<A: Accelerator>(tracer: &Tracer<'_, A>, opts: &RenderOptions) -> Progressive {
        let spp = tracer.scene.settings.spp.max(1);
        let ends = super::passes::pass_ends(spp).into();
        if let Some(live) = &opts.live {
            // Progress in tile-samples: a pass's tiles count as many times as it has samples.
            live.tiles_total
                .store(tiles(tracer) * spp as usize, Ordering::Relaxed);
            live.samples_total.store(spp, Ordering::Relaxed);
        }
        Progressive::planned(opts, spp, ends, false)
    }

    /// [`render`] of `tracer`'s scene with `opts` as one pass of every sample (for stepping
    /// [`Progressive::in_bands`]; its live view counts tiles as [`render`]'s does).
    pub fn whole<A: Accelerator>(tracer: &Tracer<'_, A>, opts: &RenderOptions) -> Progressive {
        let spp = tracer.scene.settings.spp.max(1);
        if let Some(live) = &opts.live {
            live.tiles_total.store(tiles(tracer), Ordering::Relaxed);
        }
        Progressive::planned(opts, spp, [spp].into(), true)
    }

    /// A render of passes ending at `ends`, nothing traced yet.
    fn planned(
        opts: &RenderOptions,
        spp: u32,
        ends: std::collections::VecDeque<u32>,
        whole: bool,
    ) -> Progressive {
        Progressive {
            opts: RenderOptions {
                pass: None,
                ..opts.clone()
            },
            spp,
            ends,
            start: 0,
            sums: None,
            total: None,
            whole,
            steps: Steps::Passes,
        }
    }

    /// The same render in steps of a band of tiles each, traced on the calling thread (one
    /// thread, `opts.threads` aside, and no terminal progress bar): each step is short, and
    /// the live view shows each tile as it finishes.
    pub fn in_bands(mut self, size: BandSize) -> Progressive {
        self.steps = Steps::Bands(size, None);
        self
    }

    /// The same render with its tiles traced by `workers` worker threads
    /// ([`crate::platform::spawn_worker`]: the browser page's Web Workers) while each step on
    /// the calling thread only takes in the tiles that have arrived, waiting for none (a step
    /// with none to take in says so, [`crate::platform::step_waits`]). `prepared` is the scene
    /// the workers trace: the one of the tracer given to each step. The live view shows each
    /// tile as it arrives; the finished image is [`render`]'s, bit for bit.
    pub fn on_workers(mut self, prepared: Arc<PreparedScene>, workers: usize) -> Progressive {
        self.steps = Steps::Workers(prepared, workers.max(1), None);
        self
    }

    /// Traces the next step (a pass, or a band of one [`Progressive::in_bands`]) and, when it
    /// ends a pass, calls `after_pass` with the samples per pixel done and the pass's output;
    /// `None` once every pass is done. `tracer` must be the one given to [`Progressive::new`]
    /// (or one of the same prepared scene).
    pub fn next_step<A: Accelerator>(
        &mut self,
        tracer: &Tracer<'_, A>,
        after_pass: impl FnMut(u32, &RenderOutput),
    ) -> Result<Option<Stepped>, String> {
        let Some(&end) = self.ends.front() else {
            return Ok(None);
        };
        let pass = (!self.whole).then(|| Pass {
            samples: self.start..end,
            sums: self.sums.clone(),
        });
        let (width, height) = (tracer.camera.width, tracer.camera.height);
        let count = self.opts.count;
        let out = match &mut self.steps {
            Steps::Passes => render(
                tracer,
                &RenderOptions {
                    pass,
                    ..self.opts.clone()
                },
            )?,
            Steps::Bands(size, current) => {
                let band = current.get_or_insert_with(|| BandPass::new(width, height, pass, count));
                if !band.next_band(tracer, &self.opts, *size)? {
                    return Ok(Some(Stepped::Band));
                }
                current
                    .take()
                    .ok_or("internal error: a band with no pass")?
                    .output()?
            }
            Steps::Workers(prepared, workers, gathering) => {
                let traced = gathering
                    .get_or_insert_with(|| WorkerPass::new(width, height, pass, count, *workers));
                if !traced.gather(prepared, &self.opts)? {
                    return Ok(Some(Stepped::Band));
                }
                gathering
                    .take()
                    .ok_or("internal error: a gathered pass with no pass")?
                    .output()?
            }
        };
        self.ends.pop_front();
        self.end_pass(end, out, after_pass);
        Ok(Some(Stepped::Pass(end)))
    }

    /// Traces the rest of the next pass (all of it but in bands) and calls `after_pass` with the
    /// samples per pixel done and the pass's output; `None` once every pass is done. `tracer`
    /// must be the one given to [`Progressive::new`] (or one of the same prepared scene).
    pub fn next_pass<A: Accelerator>(
        &mut self,
        tracer: &Tracer<'_, A>,
        mut after_pass: impl FnMut(u32, &RenderOutput),
    ) -> Result<Option<u32>, String> {
        loop {
            match self.next_step(tracer, &mut after_pass)? {
                Some(Stepped::Band) => {}
                Some(Stepped::Pass(end)) => return Ok(Some(end)),
                None => return Ok(None),
            }
        }
    }

    /// Takes in a finished pass's output: its figures added to the render's, its pixels the
    /// running sums (or, [`Progressive::whole`], the means).
    fn end_pass(
        &mut self,
        end: u32,
        out: RenderOutput,
        mut after_pass: impl FnMut(u32, &RenderOutput),
    ) {
        if let Some(live) = &self.opts.live
            && !self.whole
        {
            live.samples_done.store(end, Ordering::Relaxed);
        }
        after_pass(end, &out);
        self.total = Some(match self.total.take() {
            None => RenderOutput {
                width: out.width,
                height: out.height,
                pixels: vec![],
                node_visits: out.node_visits.clone(),
                stats: out.stats.clone(),
            },
            Some(mut t) => {
                t.stats.trace += out.stats.trace;
                t.stats.counts.merge(&out.stats.counts);
                t.stats.nan_rays += out.stats.nan_rays;
                t.stats.bad_samples += out.stats.bad_samples;
                t.stats.first_bad_sample = t.stats.first_bad_sample.or(out.stats.first_bad_sample);
                if let (Some(a), Some(b)) = (t.node_visits.as_mut(), out.node_visits.as_ref()) {
                    for (a, b) in a.iter_mut().zip(b) {
                        *a += b;
                    }
                }
                t
            }
        });
        self.sums = Some(Arc::new(out.pixels));
        self.start = end;
    }

    /// The finished render: the mean of every pass's samples.
    pub fn finish(self) -> Result<RenderOutput, String> {
        let mut out = self
            .total
            .ok_or("internal error: a progressive render with no pass")?;
        let sums = self
            .sums
            .ok_or("internal error: a progressive render with no pass")?;
        out.pixels = if self.whole {
            // One pass without a pass: its pixels are the means already.
            Arc::unwrap_or_clone(sums)
        } else {
            // The mean exactly as Tracer::trace_pixel divides it.
            sums.iter().map(|s| *s / self.spp as f32).collect()
        };
        out.stats.nan_pixels = out.pixels.iter().filter(|p| p.is_nan()).count() as u64;
        Ok(out)
    }
}
