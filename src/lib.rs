//! # raystep — ray tracing, one pixel at a time
//!
//! The `raystep` package is the top of the workspace: the command line ([`cli`]), the
//! benchmarks behind `raystep bench`, and the entry points the fuzzers feed hostile input
//! ([`fuzzing`]). Everything it runs lives in the crates below it, which it re-exports under the
//! module names they had when raystep was one crate, so `raystep::scene`, `raystep::diagram` and
//! `raystep::app` name the same things as before. From the bottom up (docs/ARCHITECTURE.md):
//!
//! - **raystep-core** (no GUI, no GPU): [`platform`], [`io`], [`text`], [`math`], [`shapes`],
//!   [`scene`], [`record`], [`accel`], [`mc`], [`trace`], [`render`], [`explain`].
//! - **raystep-diagram**: [`diagram`], the 2D diagrams (tiny-skia).
//! - **raystep-course**: [`lesson`], [`student`], [`stability`].
//! - **raystep-gpu**: [`gpu`] and [`view3d`] (wgpu, naga, the WGSL).
//! - **raystep-app**: [`app`] (eframe).
//!
//! ```
//! use raystep::PreparedScene;
//!
//! let prepared = PreparedScene::new(raystep::scene::default_scene());
//! let trace = prepared.record(160, 120, 0);
//! print!("{}", raystep::explain::describe::tree(&trace));
//! ```
// The command line restores SIGPIPE's default action (its one opt-in, with its reason there).
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub use raystep_app as app;
pub use raystep_core::{
    PreparedScene, Scene, Tracer, accel, explain, io, math, mc, platform, portable, record, render,
    scene, shapes, text, trace,
};
#[cfg(not(target_arch = "wasm32"))]
pub use raystep_course::student;
pub use raystep_course::{lesson, stability};
pub use raystep_diagram as diagram;
pub use raystep_gpu as gpu;
pub use raystep_gpu::view3d;
// Used by the command line and the benchmarks by the names they had in the one crate.
use raystep_core::assets;

#[cfg(not(target_arch = "wasm32"))]
pub(crate) mod bench;
#[cfg(not(target_arch = "wasm32"))]
pub mod cli;
#[cfg(not(target_arch = "wasm32"))]
pub mod fuzzing;
