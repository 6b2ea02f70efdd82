//! raystep-core's integration tests, one test binary: scenes and their errors, the kernels'
//! properties, the accelerators, the Monte Carlo samplers, the CPU render. Nothing here links
//! the diagrams, the GPU or the app.

// A seeded generator, shared with the workspace's other tests.
#[path = "../../../../tests/it/common/rng.rs"]
mod rng;
// The f64 arithmetic of the exercise-sheet tests (a camera ray, Möller–Trumbore).
#[path = "../../../../tests/it/common/exact.rs"]
#[allow(dead_code)]
mod exact;
mod common {
    pub(crate) use super::{exact, rng};
}

mod bvh;
mod formula;
mod gltf;
mod instances;
mod mipmap;
mod properties;
mod render_bands;
mod render_common;
mod render_workers;
mod roughness;
mod rtc_world;
mod samplers;
mod scene_edit;
mod scene_errors;
mod scenes;
mod smooth;
mod spd;
mod stiff;
mod textures;
