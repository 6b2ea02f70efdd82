//! The record of a trace, and the shared vocabulary every reader uses.
//!
//! This layer sits below [`crate::accel`] and [`crate::trace`], which produce records, and
//! below [`crate::explain`], [`crate::diagram`], the app and the command line, which read them:
//!
//! - [`trace`]: the step trace — [`Trace`] and its rays ([`RayRecord`]), saved and loaded as
//!   versioned JSON;
//! - [`steps`]: the [`Step`]s a ray takes, each holding the record a kernel returned with every
//!   intermediate it computed;
//! - [`observer`]: what the tracer reports to as it works — [`Silent`] (the render: every hook
//!   compiles away), [`Counter`] (statistics) and [`Recorder`] (builds the [`Trace`]);
//! - [`validate`]: the checks a loaded trace passes before anything reads it;
//! - [`texturing`]: what a texture lookup records (the `Texture` step's mapping and texels);
//! - [`samples`]: what a Monte Carlo trace keeps beyond its one sample: the pixel's samples
//!   summarised, the lights they aimed at, the BSDFs;
//! - [`words`]: one name per ray kind and one wording per kernel outcome;
//! - [`number`]: one number formatter with named styles, used by the math panel, the diagrams,
//!   the command line, the lessons and the exercise feedback;
//! - [`tolerance`]: one [`Tolerance`] type for "equal enough", with its three rules named (trace
//!   diff, tracer grading, exercise answers).
//!
//! A trace is plain data: walk its rays and steps, save it as JSON and load it back (checked on
//! the way in), explain any step in words:
//!
//! ```
//! use raystep_core::PreparedScene;
//! use raystep_core::explain::describe::describe;
//! use raystep_core::record::{Step, Trace};
//!
//! let trace = PreparedScene::new(raystep_core::scene::default_scene()).record(160, 120, 0);
//! let (ray, first_test) = trace
//!     .timeline()
//!     .into_iter()
//!     .find(|(_, s)| matches!(s.step, Step::Sphere { .. }))
//!     .expect("the primary ray tests a sphere");
//! assert_eq!(ray.kind.name(), "primary");
//! assert!(describe(&first_test.step, ray.kind).contains("Δ = b² − 4ac"));
//!
//! let again = Trace::from_json(&trace.to_json(), "pixel.json").unwrap();
//! assert_eq!(again.color, trace.color);
//! ```

pub mod nesting;
pub mod number;
pub mod observer;
pub mod samples;
pub mod steps;
pub mod texturing;
pub mod tolerance;
pub mod trace;
pub mod validate;
pub mod words;

pub use observer::{Counter, MAX_TRACE_STEPS, Observer, Recorder, Silent};
pub use steps::{Draw, NodeAction, NodeVisit, RayKind, Stage, Step, TRACE_VERSION};
pub use tolerance::Tolerance;
pub use trace::{
    GridOutline, HitRecord, OutlineNode, RayRecord, StepRecord, Trace, TraceError, TraceObject,
};
