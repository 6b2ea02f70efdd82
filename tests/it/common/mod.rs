//! Helpers shared by the integration tests: the diagram tests' goldens ([`golden`]), the GPU tests'
//! one lock and context ([`gpu`]), the scenes the grader tests write ([`scenes`]), a seeded
//! generator ([`rng`]), hostile input ([`hostile`]), the app's test harness ([`app_harness`])
//! a class graded through `raystep grade` ([`grades`]), a careful student's f64 arithmetic
//! ([`exact`]) and the shell blocks of the documentation ([`shell_blocks`]).
#![allow(dead_code)]

pub mod app_harness;
pub mod exact;
pub mod golden;
pub mod gpu;
pub mod grades;
pub mod hostile;
pub mod rng;
pub mod scenes;
pub mod shell_blocks;

pub use golden::assert_golden;
