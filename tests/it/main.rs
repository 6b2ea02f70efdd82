//! raystep's integration tests: one test binary (each file here is a module of it), so that the
//! command line's tests, the app's and the GPU's link the workspace once rather than once a file.
//! Tests that need nothing above raystep-core, raystep-diagram, raystep-course, raystep-gpu or
//! raystep-app live in that crate's own `tests/it`. The GPU tests take one lock
//! (`common::gpu::one_at_a_time`): a software adapter runs one at a time.

mod common;

mod app;
mod app_answers;
mod app_layout;
mod app_scene3d;
mod class_path;
mod cli;
mod diagram_robust;
mod diagram_trees;
mod diff;
mod exercises;
mod fuzz_props;
mod fuzz_student;
mod gpu;
mod gpu_trace;
mod gpu_trace_mc;
mod grader_hardening;
mod grader_isolation;
mod hostile_accel;
mod hostile_cli;
mod hostile_input;
mod lessons;
mod mc_diagrams;
mod monkey;
mod monte_carlo;
mod outputs_safe;
mod render_gpu_limits;
mod sheet_instances;
mod sheet_mipmap;
mod sheet_smooth;
mod sheet_textures;
mod sheets_mc;
mod slice_framing;
mod stability;
mod statistical_mode;
mod student;
mod student_path;
mod student_tracer;
mod trace_input;
mod view3d;
mod walkthrough;
