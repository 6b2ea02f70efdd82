//! # raystep — ray tracing, one pixel at a time
//!
//! raystep traces a single pixel and keeps every step of the work — the ray, each intersection
//! test with its numbers, the closest-hit bookkeeping, the shadow, reflection and refraction
//! branches — while a full parallel render runs the very same code without recording anything.
//!
//! # Using raystep as a library
//!
//! Load a [`Scene`], prepare it once ([`PreparedScene`]: the scene and its accelerator), then
//! render it ([`render::render`]) or record one pixel ([`PreparedScene::record`]) — both run the
//! one [`Tracer`], which reports to an observer ([`record::Silent`], [`record::Counter`],
//! [`record::Recorder`]). A recorded [`record::Trace`] is plain data that [`explain`] puts into
//! words and formulas and [`diagram`] draws; [`lesson`] checks answers against it and
//! [`stability`] measures its numbers against exact ones. Each of those items carries a runnable
//! example.
//!
//! ```
//! use raystep::PreparedScene;
//!
//! let prepared = PreparedScene::new(raystep::scene::default_scene());
//! let trace = prepared.record(160, 120, 0);
//! print!("{}", raystep::explain::describe::tree(&trace));
//! ```
//!
//! # The modules, in the order data flows through them
//!
//! - [`math`]: rays (validated where they are made), the [`math::Real`] precision abstraction the
//!   kernels are generic over (f32 for the renderer, f64 for the calculator and the lab), γₙ.
//! - [`scene`]: the TOML scene format, OBJ meshes, validation with located errors, the camera's
//!   rays, and the scene's [`scene::Features`].
//! - [`shapes`]: one kernel per primitive (sphere, plane, triangle, box), each returning a record
//!   of every intermediate it computed.
//! - [`record`]: the trace records, the observer, and the shared vocabulary (one number
//!   formatter, one wording per outcome) — below everything that produces or reads records.
//! - [`accel`]: finding the closest hit — the course notes' naive loop and the BVH, observed.
//! - [`trace`]: deterministic sampling, where a ray meets a surface and where its children
//!   start, Phong/Snell/Schlick shading, the one recursive Whitted tracer, and [`PreparedScene`].
//! - [`render`]: the full parallel render and image output.
//! - [`mc`]: the Monte Carlo core — random numbers hashed from (pixel, sample, dimension, seed)
//!   and the sampling routines with their densities (the integrators that use them are to come).
//! - [`explain`] and [`diagram`]: the readers of records — words, the math panel, trace diff,
//!   `raystep intersect`'s text; the 2D diagrams.
//! - [`gpu`]: the same scene traced on the GPU (wgpu, WGSL generated per scene), compared with
//!   the CPU render.
//! - [`view3d`]: the 3D view of a scene and a trace's rays, drawn with wgpu into a texture.
//! - [`lesson`]: lessons and exercise sheets whose answers are computed by the tracer.
//! - [`student`]: checking a student's own tracer — its printed trace lined up with raystep's,
//!   the program run with limits, sheets, class runs and Gradescope's `results.json`.
//! - [`stability`]: the numerical stability lab — every method in f32 and f64 on the stiff cases
//!   S1–S25 against exact rational references, cost per test, and image error against run time.
//! - [`app`]: the eframe app; [`cli`]: the `raystep` command line; [`fuzzing`]: the entry points
//!   the fuzzers and the property tests feed hostile input; [`io`]: bounded reading and atomic
//!   writing of files; [`text`]: line and column of an offset, CSV reading and writing (shared by
//!   the readers of hand-written files); `variant`: the seeded per-student draws the exercise
//!   sheets and the tracer grading sheets share.
// A few places opt in, with their reasons: gpu::tracer's request for wgpu's experimental ray
// queries, the BVH's calls of its AVX2 + FMA build and its AVX box and triangle tests after
// checking the CPU, and the command line's restoring of SIGPIPE's default action.
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod accel;
pub mod app;
pub(crate) mod assets;
#[cfg(not(target_arch = "wasm32"))]
pub(crate) mod bench;
#[cfg(not(target_arch = "wasm32"))]
pub mod cli;
pub mod diagram;
pub mod explain;
#[cfg(not(target_arch = "wasm32"))]
pub mod fuzzing;
pub mod gpu;
pub mod io;
pub(crate) mod jsonf;
pub mod lesson;
pub mod math;
pub mod mc;
pub mod platform;
pub mod record;
pub mod render;
pub mod scene;
pub mod shapes;
pub mod stability;
#[cfg(not(target_arch = "wasm32"))]
pub mod student;
pub mod text;
pub mod trace;
pub(crate) mod variant;
pub mod view3d;

pub use scene::Scene;
pub use trace::{PreparedScene, Tracer};
