//! Helpers shared by the integration tests: the diagram tests' goldens ([`golden`]), the GPU tests'
//! one lock and context ([`gpu`]), the scenes the grader tests write ([`scenes`]), a seeded
//! generator ([`rng`]), hostile input ([`hostile`]) and the app's test harness ([`app_harness`]).
#![allow(dead_code)]

pub mod app_harness;
pub mod golden;
pub mod gpu;
pub mod hostile;
pub mod rng;
pub mod scenes;

pub use golden::assert_golden;
