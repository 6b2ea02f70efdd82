//! # raystep-course — what a course does with the tracer
//!
//! Above the tracer (raystep-core) and the diagrams (raystep-diagram), below the app and the
//! command line:
//!
//! - [`lesson`]: lessons and exercise sheets whose answers are computed by the tracer, drawn
//!   per student, checked against the sheet's premises, and marked.
//! - [`student`]: checking a student's own tracer — its printed trace lined up with raystep's,
//!   the program run with limits, tracer sheets, class runs and Gradescope's `results.json`
//!   (native only: it runs programs).
//! - [`stability`]: the numerical stability lab — every method in f32 and f64 on the stiff cases
//!   against exact rational references, cost per test, and image error against run time.
//! - `variant`: the seeded per-student draws the exercise sheets and the tracer grading sheets
//!   share.
#![deny(unsafe_code)]
#![warn(missing_docs)]

// The layers below, by the names the modules use for them.
use raystep_core::{
    accel, assets, io, math, mc, platform, record, render, scene, shapes, text, trace,
};
// Only the student tools (native) hash as the GPU does.
#[cfg(not(target_arch = "wasm32"))]
use raystep_core::portable;
use raystep_diagram as diagram;

pub mod lesson;
pub mod stability;
#[cfg(not(target_arch = "wasm32"))]
pub mod student;
pub(crate) mod variant;
