//! # raystep-core — the ray tracer, its records and their words
//!
//! The layer everything else in raystep stands on, with no GUI and no GPU: scenes, shapes,
//! accelerators, the tracer and its integrators (Whitted, distribution, path), the Monte Carlo
//! samplers, the CPU render, the recorded trace and the words and formulas that explain it. It
//! builds for `wasm32-unknown-unknown` as it is, and a course can use it as a library:
//!
//! ```
//! use raystep_core::PreparedScene;
//!
//! let prepared = PreparedScene::new(raystep_core::scene::default_scene());
//! let trace = prepared.record(160, 120, 0);
//! print!("{}", raystep_core::explain::describe::tree(&trace));
//! ```
//!
//! Load a [`Scene`], prepare it once ([`PreparedScene`]: the scene and its accelerator), then
//! render it ([`render::render`]) or record one pixel ([`PreparedScene::record`]) — both run the
//! one [`Tracer`], which reports to an observer ([`record::Silent`], [`record::Counter`],
//! [`record::Recorder`]). A recorded [`record::Trace`] is plain data that [`explain`] puts into
//! words and formulas; the crates above draw it (raystep-diagram), trace it on the GPU
//! (raystep-gpu), grade and teach with it (raystep-course) and show it (raystep-app).
//!
//! # The modules, lowest first
//!
//! - [`platform`]: the seam to the machine — threads, clocks, files, the browser's downloads —
//!   so that everything above also runs in a web page; [`io`]: bounded reading and atomic
//!   writing of files; [`text`]: line and column of an offset, CSV; `jsonf`: JSON numbers
//!   written to round-trip.
//! - [`math`]: rays (validated where they are made), the [`math::Real`] precision abstraction the
//!   kernels are generic over (f32 for the renderer, f64 for the calculator and the lab), γₙ.
//! - [`shapes`]: one kernel per primitive (sphere, plane, triangle, box), each returning a record
//!   of every intermediate it computed.
//! - [`scene`]: the TOML scene format, OBJ meshes, validation with located errors, the camera's
//!   rays, and the scene's [`scene::Features`]; [`assets`]: the scenes, lessons and sheets built
//!   into the binary.
//! - [`record`]: the trace records, the observer, and the shared vocabulary (one number
//!   formatter, one wording per outcome).
//! - [`accel`]: finding the closest hit — the course notes' naive loop, the BVH and the grid,
//!   observed.
//! - [`mc`]: the Monte Carlo samplers — random numbers hashed from (pixel, sample, dimension,
//!   seed), lights, BSDFs and their densities.
//! - [`trace`]: where a ray meets a surface and where its children start, Phong/Snell/Schlick
//!   shading, the [`Tracer`] with its Whitted, distribution and path integrators, and
//!   [`PreparedScene`].
//! - [`render`]: the full parallel render and image output.
//! - [`explain`]: the records put into words, the math panel's formulas, trace diff.
// A few places opt in, with their reasons: the BVH's calls of its AVX2 + FMA build and its AVX
// box and triangle tests after checking the CPU.
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod accel;
pub mod assets;
pub mod explain;
pub mod io;
pub mod jsonf;
pub mod math;
pub mod mc;
pub mod platform;
pub mod portable;
pub mod record;
pub mod render;
pub mod scene;
pub mod shapes;
pub mod text;
pub mod trace;

pub use scene::Scene;
pub use trace::{PreparedScene, Tracer};
