//! raystep-diagram's integration tests, one test binary: the diagrams of recorded traces
//! against their golden images (tests/golden at the repository's root) and the accelerators'
//! trees drawn.

// Shared with the workspace's other tests: the goldens and a seeded generator.
#[path = "../../../../tests/it/common/golden.rs"]
mod golden;
#[path = "../../../../tests/it/common/rng.rs"]
mod rng;
mod common {
    pub(crate) use super::golden::assert_golden;
    pub(crate) use super::rng;
}

mod accelerators;
mod diagram_quadratic_barycentric;
mod diagram_slice;
mod diagram_texture;
mod diagram_two_level;
