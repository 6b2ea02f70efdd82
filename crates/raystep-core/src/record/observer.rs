//! The observer passed into the tracer: [`Silent`] for rendering (every hook is an empty inline
//! function, so recording compiles away), [`Counter`] for render statistics, and [`Recorder`],
//! which builds the step trace tree.
//!
//! Steps are handed over as closures: a silent observer never calls them, so the record (and
//! every `String` in it) is never built on the render path.

use super::steps::{NodeVisit, RayKind, Stage, Step};
use super::trace::{HitRecord, RayRecord, StepRecord};
use crate::math::Ray;
use glam::Vec3;

/// What the tracer reports as it works.
pub trait Observer {
    /// Whether this observer keeps anything (lets callers skip work that only feeds records).
    const RECORDS: bool;
    /// A ray starts (its steps follow until [`Observer::end_ray`]).
    #[inline(always)]
    fn begin_ray(&mut self, _kind: RayKind, _depth: u32, _ray: &Ray<f32>, _weight: f32) {}
    /// A primitive intersection test ran.
    #[inline(always)]
    fn prim_test(&mut self, _step: impl FnOnce() -> Step) {}
    /// `n` primitive tests ran, one after the other, the `i`-th recorded by `step(i)` (a
    /// leaf's triangles tested four at a time, all missed): [`Observer::prim_test`] for each,
    /// unless the observer only counts them.
    #[inline(always)]
    fn prim_tests(&mut self, n: usize, mut step: impl FnMut(usize) -> Step) {
        for i in 0..n {
            self.prim_test(|| step(i));
        }
    }
    /// A BVH node was visited.
    #[inline(always)]
    fn node_visit(&mut self, _visit: impl FnOnce() -> NodeVisit) {}
    /// A step of an accelerator other than the BVH (a bounding sphere tested, a grid cell
    /// entered): counted as a node visit, recorded as a step.
    #[inline(always)]
    fn accel_visit(&mut self, _step: impl FnOnce() -> Step) {}
    /// Any other step.
    #[inline(always)]
    fn step(&mut self, _step: impl FnOnce() -> Step) {}
    /// The current ray ends with this hit and colour.
    #[inline(always)]
    fn end_ray(&mut self, _hit: impl FnOnce() -> Option<HitRecord>, _color: Vec3) {}
}

/// Keeps nothing: the render path.
#[derive(Debug, Default, Clone, Copy)]
pub struct Silent;

impl Observer for Silent {
    const RECORDS: bool = false;
}

/// Counts rays by kind and tests, for render statistics; records nothing else.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct Counter {
    /// Primary rays.
    pub primary: u64,
    /// Shadow rays.
    pub shadow: u64,
    /// Reflection rays.
    pub reflection: u64,
    /// Refraction rays.
    pub refraction: u64,
    /// Monte Carlo bounces off diffuse and glossy surfaces.
    pub scattered: u64,
    /// Primitive intersection tests.
    pub prim_tests: u64,
    /// Accelerator visits: BVH nodes (box tests), bounding spheres tested, grid cells entered.
    pub node_visits: u64,
}

impl Counter {
    /// All rays.
    pub fn rays(&self) -> u64 {
        self.primary + self.shadow + self.reflection + self.refraction + self.scattered
    }
    /// Adds another counter's figures.
    pub fn merge(&mut self, o: &Counter) {
        self.primary += o.primary;
        self.shadow += o.shadow;
        self.reflection += o.reflection;
        self.refraction += o.refraction;
        self.scattered += o.scattered;
        self.prim_tests += o.prim_tests;
        self.node_visits += o.node_visits;
    }
}

impl Observer for Counter {
    const RECORDS: bool = false;
    #[inline(always)]
    fn begin_ray(&mut self, kind: RayKind, _: u32, _: &Ray<f32>, _: f32) {
        match kind {
            RayKind::Primary => self.primary += 1,
            RayKind::Shadow => self.shadow += 1,
            RayKind::Reflection => self.reflection += 1,
            RayKind::Refraction => self.refraction += 1,
            RayKind::Diffuse | RayKind::Glossy => self.scattered += 1,
        }
    }
    #[inline(always)]
    fn prim_test(&mut self, _: impl FnOnce() -> Step) {
        self.prim_tests += 1;
    }
    #[inline(always)]
    fn prim_tests(&mut self, n: usize, _: impl FnMut(usize) -> Step) {
        self.prim_tests += n as u64;
    }
    #[inline(always)]
    fn node_visit(&mut self, _: impl FnOnce() -> NodeVisit) {
        self.node_visits += 1;
    }
    #[inline(always)]
    fn accel_visit(&mut self, _: impl FnOnce() -> Step) {
        self.node_visits += 1;
    }
}

pub use super::validate::MAX_TRACE_STEPS;

/// Builds the trace tree, up to a step limit.
#[derive(Debug)]
pub struct Recorder {
    stack: Vec<RayRecord>,
    root: Option<RayRecord>,
    /// Steps kept so far.
    recorded: usize,
    /// The most steps kept.
    limit: usize,
    /// Whether the limit was reached.
    cut: bool,
    /// Rays begun after the cut and not ended yet (not recorded).
    unrecorded: usize,
}

impl Default for Recorder {
    fn default() -> Self {
        Self::with_limit(MAX_TRACE_STEPS)
    }
}

impl Recorder {
    /// A fresh recorder that keeps up to [`MAX_TRACE_STEPS`] steps.
    pub fn new() -> Self {
        Self::default()
    }
    /// A fresh recorder that keeps up to `limit` steps.
    pub fn with_limit(limit: usize) -> Self {
        Recorder {
            stack: vec![],
            root: None,
            recorded: 0,
            limit,
            cut: false,
            unrecorded: 0,
        }
    }
    /// The finished root ray, once the primary ray has ended.
    pub fn finish(self) -> Option<RayRecord> {
        self.root
    }
    /// Whether one more step may be kept; at the limit, records the cut (once) and says no.
    fn room(&mut self) -> bool {
        if self.cut {
            return false;
        }
        if self.recorded < self.limit {
            self.recorded += 1;
            return true;
        }
        self.cut = true;
        if let Some(r) = self.stack.last_mut() {
            let step = Step::Truncated {
                max_steps: u32::try_from(self.limit).unwrap_or(u32::MAX),
            };
            r.steps.push(StepRecord {
                stage: step.stage(),
                step,
            });
        }
        false
    }
    fn push(&mut self, step: Step) {
        if !self.room() {
            return;
        }
        if let Some(r) = self.stack.last_mut() {
            // The colour of a ray that hit nothing comes from the miss shader, not closest-hit.
            let after_miss = matches!(
                r.steps.last(),
                Some(StepRecord {
                    step: Step::Miss { .. },
                    ..
                })
            );
            let stage = match step {
                Step::Color { .. } if after_miss => Stage::Miss,
                _ => step.stage(),
            };
            r.steps.push(StepRecord { stage, step });
        }
    }
}

fn arr(v: Vec3) -> [f32; 3] {
    v.to_array()
}

impl Observer for Recorder {
    const RECORDS: bool = true;
    fn begin_ray(&mut self, kind: RayKind, depth: u32, ray: &Ray<f32>, weight: f32) {
        // The primary ray is always kept (a trace has a root); a child only with room for its
        // spawn step.
        if self.cut || (!self.stack.is_empty() && !self.room()) {
            self.unrecorded += 1;
            return;
        }
        if let Some(parent) = self.stack.last_mut() {
            let child = parent.children.len() as u32;
            parent.steps.push(StepRecord {
                stage: Step::Spawn { child }.stage(),
                step: Step::Spawn { child },
            });
        }
        self.stack.push(RayRecord {
            kind,
            depth,
            origin: arr(ray.origin),
            direction: arr(ray.dir),
            t_min: ray.t_min,
            t_max: ray.t_max.is_finite().then_some(ray.t_max),
            steps: vec![],
            hit: None,
            children: vec![],
            weight,
            color: [0.0; 3],
        });
    }
    fn prim_test(&mut self, step: impl FnOnce() -> Step) {
        if !self.cut {
            self.push(step());
        }
    }
    fn node_visit(&mut self, visit: impl FnOnce() -> NodeVisit) {
        if !self.cut {
            self.push(Step::Node(visit()));
        }
    }
    fn accel_visit(&mut self, step: impl FnOnce() -> Step) {
        if !self.cut {
            self.push(step());
        }
    }
    fn step(&mut self, step: impl FnOnce() -> Step) {
        if !self.cut {
            self.push(step());
        }
    }
    fn end_ray(&mut self, hit: impl FnOnce() -> Option<HitRecord>, color: Vec3) {
        if self.unrecorded > 0 {
            self.unrecorded -= 1;
            return;
        }
        let Some(mut r) = self.stack.pop() else {
            return;
        };
        r.hit = hit();
        r.color = arr(color);
        match self.stack.last_mut() {
            Some(parent) => parent.children.push(r),
            None => self.root = Some(r),
        }
    }
}
