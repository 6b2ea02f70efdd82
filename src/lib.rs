//! # raystep — ray tracing, one pixel at a time
//!
//! raystep traces a single pixel and keeps every step of the work — the ray, each intersection
//! test with its numbers, the closest-hit bookkeeping, the shadow, reflection and refraction
//! branches — while a full parallel render runs the very same code without recording anything.
//!
//! The modules, in the order data flows through them:
//!
//! - [`math`]: rays (validated where they are made), the [`math::Real`] precision abstraction the
//!   kernels are generic over (f32 for the renderer, f64 for the calculator and the lab), γₙ.
//! - [`scene`]: the TOML scene format, OBJ meshes, validation with located errors, and the
//!   scene's [`scene::Features`].
//! - [`shapes`]: one kernel per primitive (sphere, plane, triangle, box), each returning a record
//!   of every intermediate it computed.
//! - [`accel`]: finding the closest hit — the seeds' naive loop, observed.
//! - [`trace`]: the camera, the observer ([`trace::Silent`] and [`trace::Recorder`]), the step
//!   trace records, Phong/Snell/Schlick shading and the one recursive Whitted tracer.
//! - [`render`]: the full parallel render and image output; [`diagram`]: the 2D diagrams drawn
//!   from a trace.
//! - [`gpu`]: the same scene traced on the GPU (wgpu, WGSL generated per scene), compared with
//!   the CPU render.
//! - [`app`]: the eframe app — the render, the stepping, the math and the diagrams side by side.
//! - [`stability`]: the numerical stability lab — every method in f32 and f64 on the stiff cases
//!   S1–S25 against exact rational references, cost per test, and image error against run time.
//! - [`lesson`]: exercise sheets whose answers are computed by the tracer, per-student variants.
//! - [`cli`]: the `raystep` command line.
//! - [`fuzzing`]: the entry points the fuzzers and the property tests feed hostile input.
// One function opts in, with its reason: gpu::tracer's request for wgpu's experimental ray queries.
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod accel;
pub mod app;
pub mod assets;
pub mod bench;
pub mod cli;
pub mod diagram;
pub mod explain;
pub mod fuzzing;
pub mod gpu;
pub mod io;
pub mod jsonf;
pub mod lesson;
pub mod math;
pub mod record;
pub mod render;
pub mod scene;
pub mod shapes;
pub mod stability;
pub mod trace;

pub use scene::Scene;
pub use trace::{PreparedScene, Tracer};
