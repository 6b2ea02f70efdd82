//! The selected pixel's trace as the app steps through it: the timeline indexed for the panels.

use crate::diagram::{self, DiagramKind};
use crate::record::{RayRecord, StepRecord, Trace};
use std::sync::Arc;
use std::time::Duration;

/// The trace being stepped through, with the indexes the panels need.
#[derive(Debug, Clone)]
pub struct Stepping {
    /// The trace.
    pub trace: Arc<Trace>,
    /// For each timeline step: (index of its ray in [`Trace::rays`], index in that ray's steps).
    pub index: Vec<(usize, usize)>,
    /// The depth of each ray (in [`Trace::rays`] order).
    pub ray_depth: Vec<u32>,
    /// The diagram kinds this trace has.
    pub kinds: Vec<DiagramKind>,
    /// How long recording it took (zero for a loaded trace).
    pub record_time: Duration,
}

impl Stepping {
    /// Indexes a trace.
    pub fn new(trace: Trace, record_time: Duration) -> Stepping {
        let rays = trace.rays();
        let ray_depth = rays.iter().map(|r| r.depth).collect();
        let index = trace
            .timeline()
            .iter()
            .map(|(r, s)| {
                let ri = rays
                    .iter()
                    .position(|x| std::ptr::eq(*x, *r))
                    .expect("a timeline ray is one of the trace's rays");
                let si = r
                    .steps
                    .iter()
                    .position(|x| std::ptr::eq(x, *s))
                    .expect("a timeline step is one of its ray's steps");
                (ri, si)
            })
            .collect();
        let kinds = diagram::available(&trace);
        Stepping {
            trace: Arc::new(trace),
            index,
            ray_depth,
            kinds,
            record_time,
        }
    }

    /// Number of steps.
    pub fn len(&self) -> usize {
        self.index.len()
    }

    /// Whether the trace has no steps.
    pub fn is_empty(&self) -> bool {
        self.index.is_empty()
    }

    /// The ray and step at timeline position `k`.
    pub fn at(&self, k: usize) -> Option<(&RayRecord, &StepRecord)> {
        let (ri, si) = *self.index.get(k)?;
        let ray = *self.trace.rays().get(ri)?;
        Some((ray, ray.steps.get(si)?))
    }
}
