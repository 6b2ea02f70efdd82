//! The stability lab's runs, part of [`super::AppState`]: the quick suite of
//! [`crate::stability`] and the comparison of the path tracer's strategies, each started by a
//! [`LabCmd`] and running in the background until [`super::AppState::tick`] takes its result. The
//! lab window ([`crate::lab`]) only shows them.

use crate::platform::Instant;
use crate::scene::{Integrator, Scene, Strategy};
use crate::stability::converge::{ConvergeOptions, StrategyRun, run_strategies};
use crate::stability::{self, Report};
use std::sync::Arc;
use std::sync::mpsc::Receiver;

/// A finished comparison of strategies, or why it failed.
pub type Comparison = Result<Vec<StrategyRun>, String>;

/// The strategies the lab compares, in the table's order.
pub const ALL_STRATEGIES: [Strategy; 3] = [Strategy::Light, Strategy::Bsdf, Strategy::Mis];

/// What the lab's comparison of strategies renders: the levels up to this spp, with this many
/// seeds (the command line's `--max-spp 16 --seeds 2`).
pub const COMPARE_MAX_SPP: u32 = 16;
/// Seeds per level of the lab's comparison.
pub const COMPARE_SEEDS: u32 = 2;

/// What the lab can be asked to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LabCmd {
    /// Run the quick suite (unless it is running).
    RunSuite,
    /// Compare light sampling, BSDF sampling and MIS on the scene as it is set now (a scene
    /// rendered with the path integrator; unless a comparison is running).
    CompareStrategies,
}

/// The lab's runs and their last results.
pub struct Lab {
    /// What the suite runs (the quick suite, on one worker thread).
    pub options: stability::Options,
    /// The quick suite running in the background, and when it started.
    running: Option<(Receiver<Report>, Instant)>,
    /// The last report.
    pub report: Option<Report>,
    /// The strategy comparison running in the background, when it started, and its scene's name.
    comparing: Option<(Receiver<Comparison>, Instant, String)>,
    /// The last comparison (or why it failed), and the name of the scene it was of.
    pub comparison: Option<(String, Comparison)>,
}

impl Default for Lab {
    fn default() -> Self {
        Lab {
            // One worker: the render and the UI keep the other core.
            options: stability::Options {
                threads: Some(1),
                ..stability::Options::quick()
            },
            running: None,
            report: None,
            comparing: None,
            comparison: None,
        }
    }
}

impl Lab {
    /// Whether the suite or a comparison is running.
    pub fn running(&self) -> bool {
        self.running.is_some() || self.comparing.is_some()
    }

    /// When the running suite started.
    pub fn suite_started(&self) -> Option<Instant> {
        self.running.as_ref().map(|(_, t)| *t)
    }

    /// When the running comparison started.
    pub fn comparison_started(&self) -> Option<Instant> {
        self.comparing.as_ref().map(|(_, t, _)| *t)
    }

    /// Starts the quick suite in the background (unless it is running): a case a step, on a
    /// thread of its own natively, between frames in a web page (which keeps drawing).
    pub(super) fn start_suite(&mut self, repaint: Arc<dyn Fn() + Send + Sync>) {
        if self.running.is_some() {
            return;
        }
        let (tx, rx) = std::sync::mpsc::channel();
        let mut suite = stability::Suite::new(&self.options);
        crate::platform::spawn_steps(move || match suite.step() {
            None => true,
            Some(report) => {
                let _ = tx.send(report);
                repaint();
                false
            }
        });
        self.running = Some((rx, Instant::now()));
    }

    /// Starts comparing the path tracer's strategies on `scene` in the background (unless a
    /// comparison is running or the scene is not path traced).
    pub(super) fn compare(&mut self, scene: Scene, repaint: Arc<dyn Fn() + Send + Sync>) {
        if self.comparing.is_some() || scene.settings.integrator != Integrator::Path {
            return;
        }
        let (tx, rx) = std::sync::mpsc::channel();
        let name = scene.name.clone();
        crate::platform::spawn(move || {
            let opts = ConvergeOptions {
                max_spp: COMPARE_MAX_SPP,
                seeds: COMPARE_SEEDS,
                threads: Some(1),
                ..ConvergeOptions::default()
            };
            let runs = run_strategies(&scene, &opts, &ALL_STRATEGIES, &mut |_| {});
            let _ = tx.send(runs);
            repaint();
        });
        self.comparing = Some((rx, Instant::now(), name));
    }

    /// Takes a finished run (a run that stopped without its result, one that panicked, is over
    /// too: the comparison then says so, the suite keeps its last report).
    pub(super) fn poll(&mut self) {
        use std::sync::mpsc::TryRecvError;
        if let Some((rx, _, name)) = &self.comparing {
            match rx.try_recv() {
                Ok(r) => {
                    self.comparison = Some((name.clone(), r));
                    self.comparing = None;
                }
                Err(TryRecvError::Disconnected) => {
                    let e = "the comparison stopped without a result".to_string();
                    self.comparison = Some((name.clone(), Err(e)));
                    self.comparing = None;
                }
                Err(TryRecvError::Empty) => {}
            }
        }
        if let Some((rx, _)) = &self.running {
            match rx.try_recv() {
                Ok(r) => {
                    self.report = Some(r);
                    self.running = None;
                }
                Err(TryRecvError::Disconnected) => self.running = None,
                Err(TryRecvError::Empty) => {}
            }
        }
    }
}
