//! The background render: prepare the scene for the current settings (a settings copy, the
//! acceleration structure), then render it tile by tile into a [`LiveRender`] the UI shows as
//! it builds up. The UI thread never waits on it; a new job cancels the previous one.

use crate::platform::{Duration, Instant};
use crate::render::{
    BandSize, CANCELLED, LiveRender, Progressive, RenderOptions, RenderOutput, Stepped, render,
};
use crate::scene::{Scene, Settings};
use crate::trace::PreparedScene;
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::sync::mpsc::{Receiver, TryRecvError, channel};

/// What the job reports.
#[derive(Debug)]
pub enum JobEvent {
    /// The scene is prepared: pixels can be traced now, while the render goes on.
    Prepared(Arc<PreparedScene>),
    /// The render finished (or failed).
    Done(Result<Arc<RenderOutput>, String>),
}

/// Waits until `until`, or until the render is cancelled (checked every 20 ms, so that a new
/// render never waits on an old one's pause).
/// In the browser the render runs within a frame: there is nothing to hold it for.
fn hold(live: &LiveRender, until: Instant) {
    if crate::platform::IN_BROWSER {
        return;
    }
    while !live.cancel.load(Ordering::Relaxed) {
        let now = Instant::now();
        if now >= until {
            return;
        }
        crate::platform::sleep((until - now).min(Duration::from_millis(20)));
    }
}

/// How long a step of a render in the browser traces at most (and one tile more): a band of
/// tiles, between which the page draws. The page runs steps for 30 ms a frame
/// (`crate::app`), so a frame holds a few bands.
const BAND: BandSize = BandSize::Time(Duration::from_millis(8));

/// Where a render job is.
enum Stage {
    /// The scene is to be prepared.
    Prepare,
    /// Rendering the prepared scene: in one go, or a render in steps' next step (a pass of a
    /// progressive render; in the browser, a band of tiles).
    Render(Arc<PreparedScene>, Option<Box<Progressive>>),
    /// Finished (or given up).
    Done,
}

/// A render running on background threads.
#[derive(Debug)]
pub struct RenderJob {
    /// The image as it builds up.
    pub live: Arc<LiveRender>,
    /// When the job started.
    pub started: Instant,
    /// How long each pass of a progressive render stays on screen at least ("watch it
    /// converge"); `None` renders as fast as it can.
    pub pace: Option<Duration>,
    events: Receiver<JobEvent>,
}

impl RenderJob {
    /// Starts preparing and rendering `base` with `settings`. `repaint` is called whenever
    /// there is something new to show. With a `pace`, a progressive (Monte Carlo) render holds
    /// each pass's image on screen that long at least before the next pass starts, so that a
    /// class can watch 1, 2, 4, … samples per pixel come in (the image is the same).
    pub fn start(
        base: Arc<Scene>,
        settings: Settings,
        previous: Option<Arc<PreparedScene>>,
        pace: Option<Duration>,
        repaint: impl Fn() + Send + Sync + 'static,
    ) -> RenderJob {
        let live = Arc::new(LiveRender::new(base.camera.width, base.camera.height));
        let (tx, events) = channel();
        let job_live = Arc::clone(&live);
        let repaint = Arc::new(repaint);
        let mut previous = previous;
        let mut stage = Stage::Prepare;
        let mut ticker = None;
        let mut shown_at = Instant::now();
        let spp = settings.spp;
        let held = Arc::clone(&job_live);
        let pass_repaint = Arc::clone(&repaint);
        let mut after_pass = move |done: u32| {
            pass_repaint();
            // Held after every pass but the last (the finished image needs no wait).
            if let Some(pace) = pace
                && done < spp
            {
                hold(&held, shown_at + pace);
                shown_at = Instant::now();
            }
        };
        let opts = RenderOptions {
            threads: None,
            progress: false,
            count: true,
            live: Some(Arc::clone(&job_live)),
            pass: None,
        };
        // Steps: prepare; then the render, a step per pass of a Monte Carlo render (1, 2, 4, …
        // samples per pixel, the image shown after each; the finished image is the same).
        // Natively they follow each other on the job's thread, a Whitted render in one step on
        // every core. In the browser a frame is drawn between steps, and the render's steps are
        // bands of tiles of about `BAND` each (Whitted or Monte Carlo), so that no step holds the
        // page for a whole pass of the image; where the page has Web Workers, they trace the
        // tiles and each step only takes in those that have arrived.
        crate::platform::spawn_steps(move || {
            let finished = match std::mem::replace(&mut stage, Stage::Done) {
                Stage::Done => return false,
                Stage::Prepare => {
                    let prepared = Arc::new(PreparedScene::with_settings(
                        &base,
                        &settings,
                        previous.as_deref(),
                    ));
                    previous = None;
                    // A closed channel means the app dropped this job: nobody is watching.
                    if tx.send(JobEvent::Prepared(Arc::clone(&prepared))).is_err() {
                        return false;
                    }
                    repaint();
                    let watcher = Arc::clone(&job_live);
                    let tiles_repaint = Arc::clone(&repaint);
                    // Repaint the UI a few times a second while the tiles come in.
                    ticker = crate::platform::spawn_ticker(
                        Duration::from_millis(100),
                        move || watcher.progress() < 1.0 && !watcher.cancel.load(Ordering::Relaxed),
                        move || tiles_repaint(),
                    );
                    let tracer = prepared.tracer();
                    let passes = settings.integrator.is_monte_carlo() && settings.spp > 1;
                    let progressive = if crate::platform::IN_BROWSER {
                        let steps = if passes {
                            Progressive::new(&tracer, &opts)
                        } else {
                            Progressive::whole(&tracer, &opts)
                        };
                        // The page's Web Workers trace, the page gathers their tiles; a page
                        // without workers traces bands itself.
                        Some(Box::new(match crate::platform::workers() {
                            0 => steps.in_bands(BAND),
                            n => steps.on_workers(Arc::clone(&prepared), n),
                        }))
                    } else {
                        passes.then(|| Box::new(Progressive::new(&tracer, &opts)))
                    };
                    stage = Stage::Render(prepared, progressive);
                    return true;
                }
                Stage::Render(_, _) if job_live.cancel.load(Ordering::Relaxed) => {
                    Err(CANCELLED.to_string())
                }
                Stage::Render(prepared, None) => render(&prepared.tracer(), &opts),
                Stage::Render(prepared, Some(mut p)) => {
                    let step = p.next_step(&prepared.tracer(), |done, _| after_pass(done));
                    match step {
                        Ok(Some(Stepped::Band)) => {
                            // The page draws the tiles so far before the next band.
                            repaint();
                            stage = Stage::Render(prepared, Some(p));
                            return true;
                        }
                        Ok(Some(Stepped::Pass(_))) => {
                            stage = Stage::Render(prepared, Some(p));
                            return true;
                        }
                        Ok(None) => p.finish(),
                        Err(e) => Err(e),
                    }
                }
            };
            job_live.cancel.store(true, Ordering::Relaxed);
            if let Some(t) = ticker.take() {
                t.join();
            }
            let _ = tx.send(JobEvent::Done(finished.map(Arc::new)));
            repaint();
            false
        });
        RenderJob {
            live,
            started: Instant::now(),
            pace,
            events,
        }
    }

    /// The next event, if one has arrived.
    pub fn poll(&self) -> Option<JobEvent> {
        match self.events.try_recv() {
            Ok(e) => Some(e),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(JobEvent::Done(Err(
                "the render stopped unexpectedly".into(),
            ))),
        }
    }

    /// Stops the render at its next tile.
    pub fn cancel(&self) {
        self.live.cancel.store(true, Ordering::Relaxed);
    }
}

impl Drop for RenderJob {
    fn drop(&mut self) {
        self.cancel();
    }
}

/// Whether a render error is only the cancellation of a replaced job.
pub fn is_cancelled(e: &str) -> bool {
    e == CANCELLED
}
