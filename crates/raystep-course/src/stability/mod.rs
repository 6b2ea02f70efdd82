//! The numerical stability lab: every intersection method in both precisions, run on
//! the stiff cases S1–S25 of docs/NUMERICS.md, each answer measured against an *exact* reference, and
//! each method's cost measured on the same inputs; and the Monte Carlo sampling numerics (a sphere
//! light's cone, near-mirror GGX, grazing directions, huge and tiny emitting triangles) in a
//! textbook and a stable formulation, on the stiff cases S26–S29 ([`mc`]).
//!
//! One call does it all: [`run`] takes [`Options`] and returns a [`Report`] — plain data the
//! command line prints as Markdown and CSV ([`report`]) and draws as error-vs-time plots
//! ([`plot`]), and the app can show as it likes:
//!
//! ```
//! use raystep_course::stability::{Method, Options, Precision, run};
//! // A small run: every stiff case, few rays (the command line's `--quick` uses 200).
//! let report = run(&Options { rays: 8, min_timing_s: 0.0, ..Options::quick() });
//! let s1 = report.row("S1", Method::SphereTextbook, Precision::F32).expect("S1 ran");
//! assert!(s1.rays > 0);
//! for row in &report.rows {
//!     println!("{} {} {}: {} misclassified", row.case, row.method.name(), row.precision.name(), row.misclassified);
//! }
//! for p in &report.points {
//!     println!("{:?} {}: {:.1} ns, p99 {:.1} ulps", p.primitive, p.label(), p.ns_per_test, p.p99_ulps);
//! }
//! ```
//!
//! The image-level half of the lab — error of a whole render against run time — is [`converge`].
//!
//! Modules: [`exact`] (rational references and the rounding bands), [`cases`] (the S1–S29
//! generators), [`mc`] (the Monte Carlo formulations and their references), [`report`] (Markdown
//! and CSV), [`plot`] (log–log PNG plots), [`converge`].

pub mod cases;
pub mod converge;
pub mod exact;
pub mod mc;
mod measure;
pub mod pixel;
pub mod plot;
pub mod report;
mod stats;

use crate::platform::Instant;
use serde::Serialize;

/// The four primitives of the lab, plus the spawned-ray offsets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Primitive {
    /// Spheres: textbook and stable quadratics.
    Sphere,
    /// Triangles: Möller–Trumbore and watertight.
    Triangle,
    /// Planes: general and axis-aligned.
    Plane,
    /// Axis-aligned boxes: plain and robust slab tests.
    Box,
    /// Rays spawned from a hit point (shadow, reflection, refraction): the offset policies.
    Spawn,
}

impl Primitive {
    /// Every primitive, in report order.
    pub const ALL: [Primitive; 5] = [
        Primitive::Sphere,
        Primitive::Triangle,
        Primitive::Plane,
        Primitive::Box,
        Primitive::Spawn,
    ];
    /// The name used in tables, CSV and file names.
    pub fn name(self) -> &'static str {
        match self {
            Primitive::Sphere => "sphere",
            Primitive::Triangle => "triangle",
            Primitive::Plane => "plane",
            Primitive::Box => "box",
            Primitive::Spawn => "spawn",
        }
    }
}

/// A method under test: one intersection formulation, or one ray-origin offset policy.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// [`crate::shapes::sphere::textbook`].
    SphereTextbook,
    /// [`crate::shapes::sphere::stable`].
    SphereStable,
    /// [`crate::shapes::triangle::moller_trumbore`].
    MollerTrumbore,
    /// [`crate::shapes::triangle::watertight`].
    Watertight,
    /// [`crate::shapes::plane::general`].
    PlaneGeneral,
    /// [`crate::shapes::plane::axis`].
    PlaneAxis,
    /// [`crate::shapes::aabb::slab_plain`].
    SlabPlain,
    /// [`crate::shapes::aabb::slab_robust`].
    SlabRobust,
    /// Spawned rays start at the hit point ([`crate::scene::OffsetPolicy::None`]).
    OffsetNone,
    /// Spawned rays start ε = 1e-4 along the normal ([`crate::scene::OffsetPolicy::Fixed`]).
    OffsetFixed,
    /// Spawned rays start at the error-bound offset ([`crate::scene::OffsetPolicy::Robust`]).
    OffsetErrorBound,
}

impl Method {
    /// Every method, in report order.
    pub const ALL: [Method; 11] = [
        Method::SphereTextbook,
        Method::SphereStable,
        Method::MollerTrumbore,
        Method::Watertight,
        Method::PlaneGeneral,
        Method::PlaneAxis,
        Method::SlabPlain,
        Method::SlabRobust,
        Method::OffsetNone,
        Method::OffsetFixed,
        Method::OffsetErrorBound,
    ];
    /// The primitive the method belongs to.
    pub fn primitive(self) -> Primitive {
        match self {
            Method::SphereTextbook | Method::SphereStable => Primitive::Sphere,
            Method::MollerTrumbore | Method::Watertight => Primitive::Triangle,
            Method::PlaneGeneral | Method::PlaneAxis => Primitive::Plane,
            Method::SlabPlain | Method::SlabRobust => Primitive::Box,
            _ => Primitive::Spawn,
        }
    }
    /// The name used in tables and CSV (the command line's spelling where there is one).
    pub fn name(self) -> &'static str {
        match self {
            Method::SphereTextbook => "textbook",
            Method::SphereStable => "stable",
            Method::MollerTrumbore => "moller-trumbore",
            Method::Watertight => "watertight",
            Method::PlaneGeneral => "general",
            Method::PlaneAxis => "axis",
            Method::SlabPlain => "slab-plain",
            Method::SlabRobust => "slab-robust",
            Method::OffsetNone => "offset-none",
            Method::OffsetFixed => "offset-fixed",
            Method::OffsetErrorBound => "offset-error-bound",
        }
    }
}

/// The floating-point precision a kernel ran in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Precision {
    /// f32, the renderer's precision.
    F32,
    /// f64.
    F64,
}

impl Precision {
    /// "f32" or "f64".
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }
    /// The unit roundoff u = 2⁻²⁴ or 2⁻⁵³.
    pub fn unit_roundoff(self) -> f64 {
        match self {
            Precision::F32 => f32::EPSILON as f64 * 0.5,
            Precision::F64 => f64::EPSILON * 0.5,
        }
    }
}

/// What to run.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Rays per case and scale (the cases multiply this by their number of scales).
    pub rays: usize,
    /// Fewer scales per case (the first, a middle and the last): the CI suite.
    pub quick: bool,
    /// Seed of the case generators (the same seed gives the same rays).
    pub seed: u64,
    /// Minimum wall time spent timing each row (the cost column), in seconds.
    pub min_timing_s: f64,
    /// Worker threads for the exact references (None: all cores).
    pub threads: Option<usize>,
}

impl Options {
    /// The CI suite behind `raystep stability --quick`: every case, fewer scales and rays.
    pub fn quick() -> Options {
        Options {
            rays: 200,
            quick: true,
            seed: 1,
            min_timing_s: 2e-4,
            threads: None,
        }
    }
    /// The full suite behind `raystep stability`.
    pub fn full() -> Options {
        Options {
            rays: 4000,
            quick: false,
            seed: 1,
            min_timing_s: 5e-3,
            threads: None,
        }
    }
}

/// One method × precision × case: how often it was wrong, by how much, and what it cost.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Row {
    /// The case id, "S1" … "S25".
    pub case: &'static str,
    /// What the case is, in a few words.
    pub title: &'static str,
    /// The primitive.
    pub primitive: Primitive,
    /// The method.
    pub method: Method,
    /// The precision.
    pub precision: Precision,
    /// Rays tested.
    pub rays: usize,
    /// Rays the exact reference says hit.
    pub exact_hits: usize,
    /// Rays in the rounding band (either answer is accepted; see [`exact`]).
    pub in_band: usize,
    /// Rays outside the band where the method disagrees with the reference: hit vs miss, or the
    /// wrong root of a sphere. For spawn rows: a second surface the spawned ray should reach but
    /// skips. For S25: an invalid ray accepted.
    pub misclassified: usize,
    /// Leak-test rays (aimed exactly at a shared edge or vertex) in this row.
    pub leak_rays: usize,
    /// Leak-test rays that hit none of the triangles sharing the edge or vertex.
    pub leaks: usize,
    /// Spawned rays that hit the surface they start on.
    pub self_hits: usize,
    /// Results with a NaN or infinite t, u or v reported as a hit.
    pub nonfinite: usize,
    /// Hits compared with the reference for the error columns.
    pub compared: usize,
    /// Largest |t − t_exact| in ulps of t_exact (in this row's precision).
    pub t_max_ulps: f64,
    /// 99th percentile of the same.
    pub t_p99_ulps: f64,
    /// Largest |t − t_exact| / |t_exact|.
    pub t_max_rel: f64,
    /// 99th percentile of the same.
    pub t_p99_rel: f64,
    /// Triangles: largest |u − u_exact| and |v − v_exact| in units of u (ulps of 1).
    pub uv_max_ulps: Option<f64>,
    /// Triangles: 99th percentile of the same.
    pub uv_p99_ulps: Option<f64>,
    /// Cost: nanoseconds per test on this row's inputs.
    pub ns_per_test: f64,
}

/// One point of an error-vs-time plot: a method × precision over all cases of its primitive.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CostPoint {
    /// The primitive.
    pub primitive: Primitive,
    /// The method.
    pub method: Method,
    /// The precision.
    pub precision: Precision,
    /// Mean nanoseconds per test over the primitive's cases (each case weighted by its rays).
    pub ns_per_test: f64,
    /// 99th percentile of the t error in ulps, over every compared hit of every case.
    pub p99_ulps: f64,
    /// Largest t error in ulps over every case.
    pub max_ulps: f64,
    /// Total misclassifications outside the band.
    pub misclassified: usize,
    /// Total leaks.
    pub leaks: usize,
    /// Total self-hits.
    pub self_hits: usize,
    /// Total NaN/∞ results.
    pub nonfinite: usize,
}

impl CostPoint {
    /// "method f32" — the point's label on a plot.
    pub fn label(&self) -> String {
        format!("{} {}", self.method.name(), self.precision.name())
    }
}

/// Everything one run of the lab measured.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// One row per method × precision × case, in the order of [`cases::catalogue`].
    pub rows: Vec<Row>,
    /// One point per primitive × method × precision, for the error-vs-time plots.
    pub points: Vec<CostPoint>,
    /// Rays generated (each tested by every applicable method in both precisions).
    pub rays: usize,
    /// The Monte Carlo cases S26–S29: one row per case × quantity × method × precision.
    pub mc: Vec<mc::McRow>,
    /// Monte Carlo samples generated (each evaluated by both methods).
    pub mc_samples: usize,
    /// Wall time of the whole run, in seconds.
    pub seconds: f64,
    /// Whether this was the quick suite.
    pub quick: bool,
}

impl Report {
    /// The rows of one case, method and precision (e.g. for tests and the app's detail view).
    pub fn row(&self, case: &str, method: Method, precision: Precision) -> Option<&Row> {
        self.rows
            .iter()
            .find(|r| r.case == case && r.method == method && r.precision == precision)
    }

    /// The Monte Carlo row of one case, quantity, method and precision.
    pub fn mc_row(
        &self,
        case: &str,
        quantity: &str,
        method: mc::McMethod,
        precision: Precision,
    ) -> Option<&mc::McRow> {
        self.mc.iter().find(|r| {
            r.case == case
                && r.quantity == quantity
                && r.method == method
                && r.precision == precision
        })
    }
}

/// Runs the lab: generates every case, computes the exact references, runs every applicable
/// method in f32 and f64, and times each on the same inputs; then the Monte Carlo cases S26–S29.
/// Never panics on its own inputs.
pub fn run(opts: &Options) -> Report {
    let mut suite = Suite::new(opts);
    loop {
        if let Some(report) = suite.step() {
            return report;
        }
    }
}

/// [`run`] a case at a time, for a caller that cannot wait for the whole suite (the app in a web
/// page draws between cases): [`Suite::step`] until it gives the report, which is [`run`]'s.
pub struct Suite {
    opts: Options,
    start: Instant,
    catalogue: std::vec::IntoIter<cases::Case>,
    mc_catalogue: std::vec::IntoIter<mc::McCase>,
    pool: Option<rayon::ThreadPool>,
    rows: Vec<Row>,
    mc_rows: Vec<mc::McRow>,
    mc_samples: usize,
    samples: measure::Samples,
    rays: usize,
}

impl Suite {
    /// The suite of `opts`, its cases generated, none run yet.
    pub fn new(opts: &Options) -> Suite {
        let start = Instant::now();
        let catalogue = cases::catalogue(opts).into_iter();
        let mc_catalogue = cases::mc_catalogue(opts).into_iter();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(opts.threads.unwrap_or(0))
            .build()
            .ok();
        Suite {
            opts: opts.clone(),
            start,
            catalogue,
            mc_catalogue,
            pool,
            rows: vec![],
            mc_rows: vec![],
            mc_samples: 0,
            samples: measure::Samples::default(),
            rays: 0,
        }
    }

    /// Runs the next case; the report once every case has run.
    pub fn step(&mut self) -> Option<Report> {
        let Some(case) = self.catalogue.next() else {
            if let Some(case) = self.mc_catalogue.next() {
                self.mc_samples += case.len();
                let opts = &self.opts;
                let work = || mc::run_case(&case, opts);
                let mut out = match &self.pool {
                    Some(p) => p.install(work),
                    None => work(),
                };
                self.mc_rows.append(&mut out);
                return None;
            }
            let points = measure::points(&self.rows, &self.samples);
            return Some(Report {
                rows: std::mem::take(&mut self.rows),
                points,
                rays: self.rays,
                mc: std::mem::take(&mut self.mc_rows),
                mc_samples: self.mc_samples,
                seconds: self.start.elapsed().as_secs_f64(),
                quick: self.opts.quick,
            });
        };
        self.rays += case.len();
        let (opts, samples) = (&self.opts, &mut self.samples);
        let mut work = || measure::run_case(&case, opts, samples);
        let mut out = match &self.pool {
            Some(p) => p.install(work),
            None => work(),
        };
        self.rows.append(&mut out);
        None
    }
}
